// The algebra of cutting (docs/cutting.md; docs/design.md §7, §9; Wang et al. 2007 §5.3): rows and
// columns integrated alone equal blocks of the full assembly; inversion by partitioning
// (eqs. 11-13) equals the direct inverse; the low-rank-updated factorisation solves the grown
// system; and a Green's table updated after a cut step equals the table computed from scratch on
// the cut mesh (base state, every column, the region grown by the new cut-wall elements).
#include <Eigen/LU>
#include <algorithm>
#include <catch2/catch.hpp>
#include <limits>
#include <memory>
#include <random>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/cutting/cut_change.hpp"
#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/snapshot_buffers.hpp"
#include "bemsurg/solvers/low_rank_updated_lu.hpp"
#include "bemsurg/solvers/lu_factors.hpp"
#include "bemsurg/solvers/partitioned_inverse.hpp"
#include "bemsurg/solvers/structured_products.hpp"
#include "support/synthetic_cuts.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;
using bemsurg::testing::SyntheticStep;

namespace {

// Round-off bounds of the form c n eps, the same on any CPU and BLAS. The cut body (the 4 x 4 x 2
// box, nu = 0.45, bottom held) has n = 384 .. 408 unknowns over the steps here. LU with partial
// pivoting does not depend on how the columns are scaled (H's columns are O(1), G's O(1/E)), so
// the forward error of a direct solve follows the condition number of the column-equilibrated
// system, 21.3 .. 22.7 over the steps (7.3e4 .. 8.3e4 unscaled): kCut = 25 x 408 x eps. Two exact
// paths (updated vs from scratch, partitioned vs direct) each carry that much.
using bemsurg_test::kEps;
constexpr double kCut = 25.0 * 408.0 * kEps;  // 2.3e-12

double relative_max(const Eigen::Ref<const Eigen::MatrixXd>& a, const Eigen::Ref<const Eigen::MatrixXd>& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

struct Body {
  std::shared_ptr<const TriangleMesh> mesh;
  Material material{3000.0, 0.45, 1000.0};
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  std::vector<Index> bottom, top;
  BoundaryConditions base;

  explicit Body(TriangleMesh m) : mesh(std::make_shared<const TriangleMesh>(std::move(m))) {
    for (Index e = 0; e < mesh->num_elements(); ++e) {
      if (mesh->normal(e).z() < -0.99) bottom.push_back(e);
      if (mesh->normal(e).z() > 0.99) top.push_back(e);
    }
    base = supported_base_conditions(mesh->num_elements(), bottom);
  }
  GreensTableOptions options(std::vector<Index> region) const {
    GreensTableOptions o;
    o.region = std::move(region);
    o.gravity = gravity;
    return o;
  }
};

/// Table of the mesh computed from scratch with the region and base conditions of `t`.
GreensTable from_scratch(const GreensTable& t, const Body& body) {
  return GreensTable::compute(t.mesh(), body.material, t.base_conditions(), body.options(t.region()));
}

/// Largest relative difference of base state and columns between two tables.
double table_difference(const GreensTable& a, const GreensTable& b) {
  double diff = relative_max(a.columns(), b.columns());
  diff = std::max(diff, relative_max(a.base_displacement(), b.base_displacement()));
  diff = std::max(diff, relative_max(a.base_traction(), b.base_traction()));
  return diff;
}

}  // namespace

TEST_CASE("assemble_rows and assemble_columns equal blocks of the full assembly", "[cut][assembly]") {
  const TriangleMesh mesh = box_mesh(Vec3(0, 0, 0), Vec3(1, 0.8, 0.5), 5, 4, 3);
  const Material material{3000.0, 0.45, 1000.0};
  const InfluenceAssembler assembler(mesh, material);
  const InfluenceMatrices full = assembler.assemble();
  const std::vector<Index> ids = {41, 3, 0, static_cast<Index>(mesh.num_elements() - 1), 17};
  Eigen::MatrixXd rH, rG, cH, cG;
  assembler.assemble_rows(ids, rH, rG);
  assembler.assemble_columns(ids, cH, cG);
  double worst = 0.0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    const Index e = ids[i], j = static_cast<Index>(i);
    worst = std::max(worst, relative_max(rH.middleRows(3 * j, 3), full.H.middleRows(3 * e, 3)));
    worst = std::max(worst, relative_max(rG.middleRows(3 * j, 3), full.G.middleRows(3 * e, 3)));
    worst = std::max(worst, relative_max(cH.middleCols(3 * j, 3), full.H.middleCols(3 * e, 3)));
    worst = std::max(worst, relative_max(cG.middleCols(3 * j, 3), full.G.middleCols(3 * e, 3)));
  }
  // The same pair routine writes every block, whatever the tiling: measured 0 (bit for bit); the
  // bound, about 4.5 eps, admits one rounding.
  CHECK(worst <= 1e-15);
  // Gravity of a subset of columns at every row, summed over a partition, is the full gravity.
  const Eigen::Vector3d g(0, 0, -9.81);
  const Eigen::VectorXd gfull = assembler.gravity_vector(g);
  std::vector<Index> even, odd;
  for (Index e = 0; e < mesh.num_elements(); ++e) (e % 2 ? odd : even).push_back(e);
  Eigen::VectorXd g1 = Eigen::VectorXd::Zero(mesh.num_dofs()), g2 = g1;
  const Eigen::Vector3d b = material.density * g;
  assembler.assemble_block(nullptr, mesh.num_elements(), even.data(), static_cast<Index>(even.size()), nullptr, nullptr, g1.data(), b);
  assembler.assemble_block(nullptr, mesh.num_elements(), odd.data(), static_cast<Index>(odd.size()), nullptr, nullptr, g2.data(), b);
  // Summation order only: each entry is a sum over the 188 elements, regrouped into two partial
  // sums: 188 eps (measured 1.4e-15).
  CHECK(relative_max(g1 + g2, gfull) <= 188.0 * kEps);
  // The same gravity from the H and G pass (a cut step's one pass per block): the rows' share is
  // summed over column ranges (5 rows: 64 ranges), so it agrees with the full vector's rows to the
  // regrouping of 188 terms (measured 4.6e-16); H and G are still the same bits.
  Eigen::MatrixXd rH2, rG2, cH2, cG2;
  Eigen::VectorXd rows_g, even_g, odd_g;
  assembler.assemble_rows(ids, rH2, rG2, &rows_g, g);
  assembler.assemble_columns(even, cH2, cG2, &even_g, g);
  assembler.assemble_columns(odd, cH2, cG2, &odd_g, g);
  CHECK(rH2 == rH);
  CHECK(rG2 == rG);
  REQUIRE(rows_g.size() == 3 * static_cast<Index>(ids.size()));
  double rows_worst = 0.0;
  for (std::size_t i = 0; i < ids.size(); ++i)
    rows_worst = std::max(rows_worst, relative_max(rows_g.segment(3 * static_cast<Index>(i), 3), gfull.segment(3 * ids[i], 3)));
  INFO("rows' gravity from the H and G pass against the full vector: " << rows_worst);
  CHECK(rows_worst <= 188.0 * kEps);
  CHECK(relative_max(even_g, g1) <= 188.0 * kEps);
  CHECK(relative_max(even_g + odd_g, gfull) <= 188.0 * kEps);
  // Without density the gravity outputs are zero, at their sizes.
  const InfluenceAssembler weightless(mesh, Material{3000.0, 0.45, 0.0});
  weightless.assemble_rows(ids, rH2, rG2, &rows_g, g);
  CHECK(rows_g.size() == 3 * static_cast<Index>(ids.size()));
  CHECK(rows_g.isZero(0.0));
  CHECK_THROWS_AS(assembler.assemble_rows({mesh.num_elements()}, rH, rG), InvalidArgumentError);
}

TEST_CASE("inversion by partitioning equals the direct inverse of the grown BEM system", "[cut]") {
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 4, 4, 2));
  const SyntheticStep step = bemsurg::testing::split_edge(*body.mesh, body.top[3], 0, Vec3(0, 0, -0.05));
  const InfluenceAssembler assembler(*step.mesh, body.material);
  const InfluenceMatrices hg = assembler.assemble();
  const BoundaryConditions bc = conditions_after_cut(body.base, step.delta);
  const Eigen::MatrixXd A = build_system_matrix(hg, bc);
  const Index n = 3 * step.delta.elements_before, m = A.rows() - n;
  const Eigen::MatrixXd A0inv = A.topLeftCorner(n, n).partialPivLu().inverse();
  const Eigen::MatrixXd grown =
      grow_inverse_by_partitioning(A0inv, A.bottomLeftCorner(m, n), A.topRightCorner(n, m), A.bottomRightCorner(m, m));
  const Eigen::MatrixXd direct = A.partialPivLu().inverse();
  const double err = relative_max(grown, direct);
  INFO("partitioned vs direct inverse: " << err);
  CHECK(err <= kCut);  // measured 5.4e-16 (the issue asks for 1e-10)
  // The residual of an inverse computed through LU: |X A - I| <= c n eps |X| |A| entry by entry
  // (c = 1: n = 390 terms per entry); measured 1.5e-11, large because the columns' norms differ by 1.3e4.
  const double dim = static_cast<double>(A.rows());
  CHECK(relative_max(grown * A, Eigen::MatrixXd::Identity(A.rows(), A.cols())) <=
        dim * kEps * (grown.cwiseAbs() * A.cwiseAbs()).maxCoeff());
}

TEST_CASE("the low-rank-updated factorisation solves grown and reshaped systems", "[cut]") {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  const Index n0 = 60;
  Eigen::MatrixXd A = Eigen::MatrixXd::NullaryExpr(n0, n0, [&]() { return normal(rng); }) + 10.0 * Eigen::MatrixXd::Identity(n0, n0);
  Eigen::MatrixXd A0 = A;
  LowRankUpdatedLu solver(std::make_shared<const LuFactors>(LuFactors::factor(std::move(A0))));
  double worst = 0.0, worst_ride = 0.0;
  for (int step = 0; step < 6; ++step) {
    const Index n = A.rows(), add = step % 3, n1 = n + add;
    Eigen::MatrixXd A1 = Eigen::MatrixXd::Identity(n1, n1);
    A1.topLeftCorner(n, n) = A;
    // Replace two rows and two columns (a reshaped element) and border the new ones.
    std::vector<Index> D = {static_cast<Index>(rng() % n), static_cast<Index>(rng() % n)};
    if (D[0] == D[1]) D.pop_back();
    for (Index k = n; k < n1; ++k) D.push_back(k);
    Eigen::MatrixXd target = A1;
    for (Index k : D) {
      target.row(k) = Eigen::RowVectorXd::NullaryExpr(n1, [&]() { return normal(rng); });
      target.col(k) = Eigen::VectorXd::NullaryExpr(n1, [&]() { return normal(rng); });
      target(k, k) += 10.0;
    }
    const Index d = static_cast<Index>(D.size());
    Eigen::MatrixXd Us = Eigen::MatrixXd::Zero(n1, 2 * d), Vs = Eigen::MatrixXd::Zero(n1, 2 * d);
    const Eigen::MatrixXd delta = target - A1;
    for (Index j = 0; j < d; ++j) {
      Us(D[static_cast<std::size_t>(j)], j) = 1.0;
      Vs.col(j) = delta.row(D[static_cast<std::size_t>(j)]).transpose();
      Us.col(d + j) = delta.col(D[static_cast<std::size_t>(j)]);
      for (Index q : D) Us(q, d + j) = 0.0;
      Vs(D[static_cast<std::size_t>(j)], d + j) = 1.0;
    }
    // Extra right-hand sides solved with the update's own LU solve (how a cut step's fresh table
    // columns ride along), then finished with the new solver.
    const Eigen::MatrixXd extra = Eigen::MatrixXd::NullaryExpr(n1, 2, [&]() { return normal(rng); });
    Eigen::MatrixXd ride = extra;
    solver = solver.updated(n1, Us, Vs, nullptr, &ride);
    solver.finish_solve(ride);
    worst_ride = std::max(worst_ride, relative_max(ride, target.partialPivLu().solve(extra)));
    A = target;
    const Eigen::MatrixXd B = Eigen::MatrixXd::NullaryExpr(n1, 3, [&]() { return normal(rng); });
    Eigen::MatrixXd X = B;
    solver.solve_in_place(X);
    worst = std::max(worst, relative_max(X, A.partialPivLu().solve(B)));
  }
  INFO("Woodbury vs direct: " << worst << ", right-hand sides riding along with the update: " << worst_ride);
  // Random systems of 60 .. 66 unknowns with condition numbers 10.8 .. 16.7: c n eps with c = 20,
  // n = 66 (2.9e-13).
  CHECK(worst <= 20.0 * 66.0 * kEps);       // measured 6.2e-15
  CHECK(worst_ride <= 20.0 * 66.0 * kEps);  // measured 1.3e-14
  CHECK(solver.rank() > 0);
}

TEST_CASE("a Green's table updated after cut steps equals the table computed from scratch", "[cut][table]") {
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 4, 4, 2));
  auto table = std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, body.base, body.options(body.top)));
  CHECK(table->version() == 0);
  std::mt19937 rng(2026);
  std::vector<Index> candidates = body.top;
  double worst = 0.0;
  for (int step = 0; step < 5; ++step) {
    SyntheticStep s = step == 3
                          ? bemsurg::testing::move_vertex(*table->mesh(), table->mesh()->faces()(candidates[2], 0), Vec3(0.0, 0.0, -0.04))
                          : bemsurg::testing::random_split(*table->mesh(), candidates, 0.1, rng);
    for (Index e : s.delta.added) candidates.push_back(e);
    GreensTableUpdateResult report;
    auto next = updated_table(*table, s.mesh, s.delta, {}, &report);
    CHECK(next->version() == table->version() + 1);
    CHECK(next->num_elements() == s.delta.elements_after);
    for (std::size_t i = 0; i < table->region().size(); ++i) CHECK(next->region()[i] == table->region()[i]);  // slots kept
    const GreensTable reference = from_scratch(*next, body);
    const double diff = table_difference(*next, reference);
    INFO("step " << step << ": updated vs scratch " << diff << ", rank " << report.rank);
    CHECK(diff <= kCut);  // measured 3.9e-15 .. 7.6e-15 (correction ranks 24 .. 120)
    worst = std::max(worst, diff);
    table = next;
  }
  CHECK(table->region().size() > body.top.size());  // the cut walls joined the region
  WARN("updated vs from-scratch table, worst relative difference over 5 steps: " << worst);
}

TEST_CASE("a cut step's first response is exact on the tools' reach and completes to the one-step update", "[cut][table]") {
  // CutTableStep (docs/cutting.md, "First response"): the first response's table covers the region
  // elements within reach of a tool, with their columns equal to the complete table's; the complete
  // table equals updated_table's and the table computed from scratch.
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 4, 4, 2));
  auto table = std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, body.base, body.options(body.top)));
  std::mt19937 rng(39);
  std::vector<Index> candidates = body.top;
  double worst_first = 0.0, worst_complete = 0.0, worst_scratch = 0.0;
  Index deferred = 0;  // fresh columns that the first responses left to the completions
  for (int step = 0; step < 4; ++step) {
    const SyntheticStep s = bemsurg::testing::random_split(*table->mesh(), candidates, 0.1, rng);
    for (Index e : s.delta.added) candidates.push_back(e);
    CutChange change = integrate_cut_change(*table->mesh(), *s.mesh, s.delta, table->material(), table->quadrature(), table->gravity());
    const CutTableStep cut(table, s.mesh, s.delta, std::move(change));
    // A probe where the step cut, or (odd steps) at the region element farthest from it: there the
    // first response leaves the fresh columns of the cut's elements to the completion.
    Vec3 tool = s.mesh->centroid(s.delta.added.front());
    if (step % 2 == 1) {
      Index far = cut.region().front();
      for (Index e : cut.region())
        if ((s.mesh->centroid(e) - tool).norm() > (s.mesh->centroid(far) - tool).norm()) far = e;
      tool = s.mesh->centroid(far);
    }
    const std::vector<Index> reach = elements_within_reach(*s.mesh, cut.region(), {tool}, 0.3);
    REQUIRE(!reach.empty());
    REQUIRE(reach.size() < cut.region().size());
    CHECK_THROWS_AS(cut.first_response({s.mesh->num_elements()}), InvalidArgumentError);
    GreensTableUpdateResult first_report, complete_report;
    const auto first = cut.first_response(reach, &first_report);
    const auto complete = cut.complete(&complete_report);
    GreensTableUpdateResult one_report;
    const auto one_step = updated_table(*table, s.mesh, s.delta, {}, &one_report);
    // The first response solves the fresh columns within its reach only; the completion solves the
    // rest, so that the two phases together take the one call's solves, and a second completion none.
    CHECK(first_report.solve_columns <= complete_report.solve_columns);
    CHECK(complete_report.solve_columns == one_report.solve_columns);
    deferred += complete_report.solve_columns - first_report.solve_columns;
    GreensTableUpdateResult again;
    CHECK(cut.complete(&again) == complete);  // made once
    CHECK(again.solve_columns == complete_report.solve_columns);
    CHECK(cut.first_response(cut.region()) == complete);  // a reach over the whole region asks for the complete table
    CHECK(first->region() == reach);                      // reach lists them in region order, as the first response keeps them
    CHECK(first->version() == table->version() + 1);
    CHECK(complete->version() == table->version() + 1);
    CHECK(first->base_displacement() == complete->base_displacement());  // the same solve
    CHECK(first->base_traction() == complete->base_traction());
    CHECK(first_report.table_seconds >= 0.0);
    CHECK(first_report.snapshot_bytes < complete_report.snapshot_bytes);
    for (Index e : reach) {
      const Index a = first->region_slot(e), b = complete->region_slot(e);
      REQUIRE(a >= 0);
      REQUIRE(b >= 0);
      worst_first = std::max(worst_first, relative_max(first->columns().middleCols(3 * a, 3), complete->columns().middleCols(3 * b, 3)));
      worst_first =
          std::max(worst_first, relative_max(first->reactions().middleCols(3 * a, 3), complete->reactions().middleCols(3 * b, 3)));
    }
    for (Index e = 0; e < s.mesh->num_elements(); ++e)
      if (std::find(reach.begin(), reach.end(), e) == reach.end()) CHECK(first->region_slot(e) < 0);
    worst_complete = std::max(worst_complete, table_difference(*complete, *one_step));
    worst_scratch = std::max(worst_scratch, table_difference(*complete, from_scratch(*complete, body)));
    table = complete;
  }
  CHECK(deferred > 0);
  INFO("first response vs complete: " << worst_first << ", complete vs one step: " << worst_complete << ", vs scratch: " << worst_scratch);
  CHECK(worst_first <= kCut);     // the same arithmetic on a subset of the columns: measured 2.8e-16
  CHECK(worst_complete <= kCut);  // one code path: measured 0 (bit for bit)
  CHECK(worst_scratch <= kCut);   // measured 4.7e-15
  CHECK_THROWS_AS(elements_within_reach(*table->mesh(), table->region(), {Vec3(0, 0, 0)}, -1.0), InvalidArgumentError);
}

TEST_CASE("a snapshot pool hands out the smallest buffer let go of that fits, and frees beyond its size", "[cut][storage]") {
  auto pool = std::make_shared<SnapshotBufferPool>(2, 0.25);
  std::shared_ptr<double> a = pool->acquire(1000);
  const double* a_data = a.get();
  CHECK(pool->counts().allocated == 1);
  a.reset();  // back to the pool, with room for 1250 doubles
  CHECK(pool->counts().held == 1);
  CHECK(pool->counts().held_bytes == 1250.0 * sizeof(double));
  std::shared_ptr<double> b = pool->acquire(1200);  // fits in the slack
  CHECK(b.get() == a_data);
  CHECK(pool->counts().reused == 1);
  CHECK(pool->counts().held == 0);
  std::shared_ptr<double> c = pool->acquire(2000), d = pool->acquire(400), e = pool->acquire(3000);
  CHECK(pool->counts().allocated == 4);
  const double* c_data = c.get();
  b.reset();
  c.reset();
  d.reset();  // a third buffer: the smallest (d's, 500 doubles) is freed
  CHECK(pool->counts().held == 2);
  CHECK(pool->counts().held_bytes == (1250.0 + 2500.0) * sizeof(double));
  std::shared_ptr<double> f = pool->acquire(1300);  // the smallest that fits: c's, not b's (too small)
  CHECK(f.get() == c_data);
  CHECK(pool->counts().reused == 2);
  CHECK(pool->counts().allocated == 4);
  std::weak_ptr<SnapshotBufferPool> gone = pool;
  pool.reset();  // buffers still out outlive their pool and are freed with their last owner (the ASan pass checks)
  CHECK(gone.expired());
  e.reset();
  f.reset();
  std::shared_ptr<double> g = SnapshotBufferPool::fresh(10);
  g.get()[9] = 1.0;
  CHECK(g.get()[9] == 1.0);
}

TEST_CASE("cut steps on a snapshot pool reuse the storage of tables let go of and equal the steps on fresh storage", "[cut][table]") {
  // GreensTableUpdateOptions::buffers (docs/cutting.md, "Snapshot storage"): the tables of a chain of
  // steps take their columns from buffers earlier tables gave back. Each equals the table of the
  // same step on fresh storage (the same arithmetic), and a table still held is never written again.
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 4, 4, 2));
  auto table = std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, body.base, body.options(body.top)));
  GreensTableUpdateOptions pooled;
  // A quarter to spare: on this small body a step's table is ~7 % larger than the last (a real
  // organ's, 1-2 %: the default 1/16), and a buffer comes back two steps after it was taken.
  pooled.buffers = std::make_shared<SnapshotBufferPool>(2, 0.25);
  std::mt19937 rng(56);
  std::vector<Index> candidates = body.top;
  std::shared_ptr<const GreensTable> held;  // one table kept from each step to the next, as the haptic loop keeps its model
  Eigen::MatrixXd held_columns;
  double worst = 0.0;
  for (int step = 0; step < 4; ++step) {
    const SyntheticStep s = bemsurg::testing::random_split(*table->mesh(), candidates, 0.1, rng);
    for (Index e : s.delta.added) candidates.push_back(e);
    CutChange change = integrate_cut_change(*table->mesh(), *s.mesh, s.delta, table->material(), table->quadrature(), table->gravity());
    const CutChange same = change;
    const CutTableStep cut(table, s.mesh, s.delta, std::move(change), pooled);
    const std::vector<Index> reach = elements_within_reach(*s.mesh, cut.region(), {s.mesh->centroid(s.delta.added.front())}, 0.3);
    const auto first = cut.first_response(reach);
    const auto complete = cut.complete();
    const CutTableStep fresh_cut(table, s.mesh, s.delta, same);
    const auto fresh_first = fresh_cut.first_response(reach);
    const auto fresh_complete = updated_table(*table, s.mesh, s.delta, same);
    worst = std::max({worst, table_difference(*first, *fresh_first), table_difference(*complete, *fresh_complete)});
    if (held) CHECK(held->columns() == held_columns);  // its buffer did not go to another table
    held = first;
    held_columns = first->columns();
    table = complete;  // the table before and this step's first response are let go of (held keeps one)
  }
  const SnapshotBufferPool::Counts counts = pooled.buffers->counts();
  INFO("buffers reused " << counts.reused << ", allocated " << counts.allocated << ", pooled vs fresh " << worst);
  CHECK(counts.reused >= 3);           // steps 3 and 4 draw on the tables of steps 1 and 2: measured 3 of 8
  CHECK(worst <= 4.0 * 408.0 * kEps);  // the same sums in the same order: measured 0
  // A copy of a table shares its storage; a rescaled table gets its own, and a table at the same E
  // (gravity switched off, say) shares its columns, which stay as they were.
  const Eigen::MatrixXd before = table->columns();
  const auto stiffer = table->with_young_modulus(2.0 * table->material().young_modulus);
  CHECK(table->columns() == before);
  CHECK(relative_max(stiffer->columns(), 0.5 * before) <= 4.0 * kEps);
  CHECK(stiffer->columns().data() != table->columns().data());
  const auto weightless = table->with_young_modulus(table->material().young_modulus, 0.0);
  CHECK(weightless->columns().data() == table->columns().data());
  CHECK(weightless->columns() == before);
  CHECK(weightless->gravity().isZero(0.0));
  CHECK(relative_max(stiffer->with_young_modulus(table->material().young_modulus)->columns(), before) <= 4.0 * kEps);
}

TEST_CASE("a CutSystemUpdate that reserved its snapshot buffers takes its steps' tables from them", "[cut][storage]") {
  // reserve_snapshot_buffers (what a session does before its clock starts): the first steps find
  // touched storage too, and later ones the storage of the tables let go of.
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 4, 4, 2));
  auto table0 = std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, body.base, body.options(body.top)));
  CutSystemOptions options;
  options.table.buffers = std::make_shared<SnapshotBufferPool>(3, 0.5);  // this small body's tables grow ~7 % a step
  CutSystemUpdate system(table0, options);
  system.reserve_snapshot_buffers();
  CHECK(options.table.buffers->counts().held == 3);
  CHECK(options.table.buffers->counts().held_bytes >= 3.0 * 1.5 * double(table0->columns().size()) * sizeof(double));
  system.reserve_snapshot_buffers();  // already there: nothing more
  CHECK(options.table.buffers->counts().held == 3);
  std::mt19937 rng(3);
  std::vector<Index> candidates = body.top;
  for (int step = 0; step < 4; ++step) {
    const SyntheticStep s = bemsurg::testing::random_split(*system.table()->mesh(), candidates, 0.1, rng);
    for (Index e : s.delta.added) candidates.push_back(e);
    REQUIRE(system.apply(s.mesh, s.delta, CutUpdateMethod::Exact).accepted);
  }
  const SnapshotBufferPool::Counts counts = options.table.buffers->counts();
  CHECK(counts.allocated == 0);
  CHECK(counts.reused == 4);
  CHECK(table_difference(*system.table(), from_scratch(*system.table(), body)) <= kCut);
}

TEST_CASE("products with a step's structure equal the dense products they replace", "[cut][algebra]") {
  // selected_columns_transposed_times multiplies long runs of chosen columns in place and gathers the
  // others into panels; the unit-column products take scaled rows or columns instead of flops. Each
  // against the dense product of the gathered matrices (the same sums, in another order: a few eps).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Index n = 300, cols = 120, width = 5;
  Eigen::MatrixXd A(n, cols), M(n, width);
  for (Index i = 0; i < A.size(); ++i) A.data()[i] = u(rng);
  for (Index i = 0; i < M.size(); ++i) M.data()[i] = u(rng);
  // Runs of 40 and 2, single columns, a descending pair and a repeat, so both paths and every flush run.
  std::vector<Index> chosen;
  for (Index c = 10; c < 50; ++c) chosen.push_back(c);
  for (Index c : {3, 4, 99, 7, 6, 6, 119, 0}) chosen.push_back(c);
  for (Index c = 60; c < 62; ++c) chosen.push_back(c);
  Eigen::MatrixXd gathered(n, static_cast<Index>(chosen.size()));
  for (std::size_t i = 0; i < chosen.size(); ++i) gathered.col(static_cast<Index>(i)) = A.col(chosen[i]);
  const Eigen::MatrixXd expected = gathered.transpose() * M;
  const double bound = 4.0 * n * kEps;
  for (const auto& [panel, run] : std::vector<std::pair<Index, Index>>{{192, 96}, {3, 16}, {1, 1}, {4, 1000}}) {
    Eigen::MatrixXd out = Eigen::MatrixXd::Constant(expected.rows(), expected.cols(), 1e300);
    selected_columns_transposed_times(A, chosen, M, out, panel, run);
    CHECK(relative_max(out, expected) <= bound);
  }
  Eigen::MatrixXd none(0, width);
  selected_columns_transposed_times(A, {}, M, none);  // no columns: nothing to do, no panel

  // Unit columns: zero, one non-zero (scaled), two non-zeros (dense).
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, 4);
  C(17, 1) = -2.5;
  C(3, 2) = 1.0;
  C(250, 2) = 0.5;
  for (Index i = 0; i < n; ++i) C(i, 3) = u(rng);
  CHECK(unit_column_row(C, 0) == -1);
  CHECK(unit_column_row(C, 1) == 17);
  CHECK(unit_column_row(C, 2) == -2);
  CHECK(unit_column_row(C, 3) == -2);
  Eigen::MatrixXd B(40, n);
  for (Index i = 0; i < B.size(); ++i) B.data()[i] = u(rng);
  CHECK(relative_max(times_sparse_columns(B, C), B * C) <= bound);
  CHECK(relative_max(sparse_columns_transposed_times(C, B.transpose()), C.transpose() * B.transpose()) <= bound);
}

TEST_CASE("over an explicit inverse a cut step's first response is exact on the rows within reach", "[cut][table]") {
  // GreensTableOptions::explicit_inverse (solvers/explicit_inverse.hpp; docs/cutting.md, "First
  // response on the rows within reach"): the first response solves nothing and is exact on the rows
  // and columns of the elements within reach (against the complete table); the complete table, which
  // reuses the first response's V_s^T A0^-1, equals the table computed from scratch after every step.
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 4, 4, 2));
  GreensTableOptions options = body.options(body.top);
  options.explicit_inverse = true;
  auto table = std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, body.base, options));
  REQUIRE(table->solver()->has_rows());
  CHECK(table->timings().inversion_seconds > 0.0);
  std::mt19937 rng(139);
  std::vector<Index> candidates = body.top;
  double worst_rows = 0.0, worst_base = 0.0, worst_scratch = 0.0, stale = 0.0;
  for (int step = 0; step < 5; ++step) {
    const SyntheticStep s =
        step == 3 ? bemsurg::testing::move_vertex(*table->mesh(), table->mesh()->faces()(candidates[2], 0), Vec3(0.0, 0.0, -0.04))
                  : bemsurg::testing::random_split(*table->mesh(), candidates, 0.1, rng);
    for (Index e : s.delta.added) candidates.push_back(e);
    CutChange change = integrate_cut_change(*table->mesh(), *s.mesh, s.delta, table->material(), table->quadrature(), table->gravity());
    const CutTableStep cut(table, s.mesh, s.delta, std::move(change));
    const std::vector<Index> changed = s.delta.changed();
    const Vec3 tool = s.mesh->centroid(changed.front());
    const std::vector<Index> reach = elements_within_reach(*s.mesh, cut.region(), {tool}, 0.3);
    REQUIRE(!reach.empty());
    REQUIRE(reach.size() < cut.region().size());
    GreensTableUpdateResult first_report;
    const auto first = cut.first_response(reach, &first_report);
    CHECK(first->stale_outside_region());
    CHECK(first_report.solve_columns == 0);  // no triangular solve: one GEMM with the inverse
    CHECK(first->region() == reach);
    const auto complete = cut.complete();
    CHECK_FALSE(complete->stale_outside_region());
    REQUIRE(complete->solver()->has_rows());
    const double scale = complete->columns().cwiseAbs().maxCoeff();
    const double base_scale = complete->base_displacement().cwiseAbs().maxCoeff();
    for (Index e : reach)
      for (Index f : reach)
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) {
            const double x = first->columns()(3 * f + b, 3 * first->region_slot(e) + a);
            const double y = complete->columns()(3 * f + b, 3 * complete->region_slot(e) + a);
            worst_rows = std::max(worst_rows, std::abs(x - y) / scale);
          }
    for (Index f : reach)
      for (int b = 0; b < 3; ++b)
        worst_base =
            std::max(worst_base, std::abs(first->base_displacement()(3 * f + b) - complete->base_displacement()(3 * f + b)) / base_scale);
    // Outside the reach the first response is the table before the step: it differs (the test would
    // not see a first response that is the complete table).
    stale = std::max(stale, relative_max(first->base_displacement(), complete->base_displacement()));
    worst_scratch = std::max(worst_scratch, table_difference(*complete, from_scratch(*complete, body)));
    table = complete;
  }
  INFO("rows within reach vs complete: " << worst_rows << ", base state " << worst_base << ", complete vs scratch " << worst_scratch
                                         << ", outside the reach " << stale);
  CHECK(worst_rows <= kCut);
  CHECK(worst_base <= kCut);
  CHECK(worst_scratch <= kCut);
  CHECK(stale > 1e3 * kCut);
  WARN("explicit inverse: rows within reach vs complete " << worst_rows << ", base state " << worst_base << ", complete vs scratch "
                                                          << worst_scratch << ", outside the reach " << stale);
}

TEST_CASE("a table update that reshapes supported elements equals the table computed from scratch", "[cut][table]") {
  // The cutter never reshapes a supported element, but GreensTable::updated takes any delta: the
  // rows of supported dofs hold reactions (kept apart from the columns), and must enter the
  // update like every other row.
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 4, 4, 2));
  const auto table = std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, body.base, body.options(body.top)));
  Index centre = -1;  // the vertex in the middle of the supported bottom face
  for (Index v = 0; v < body.mesh->num_vertices(); ++v)
    if ((body.mesh->vertex(v) - Vec3(0.5, 0.5, 0.0)).norm() < 1e-12) centre = v;
  REQUIRE(centre >= 0);
  const SyntheticStep s = bemsurg::testing::move_vertex(*body.mesh, centre, Vec3(0.06, 0.04, 0.0));  // in the bottom plane
  Index supported_modified = 0;
  for (Index e : s.delta.modified) supported_modified += table->is_free(e) ? 0 : 1;
  REQUIRE(supported_modified >= 4);
  const auto next = updated_table(*table, s.mesh, s.delta);
  const double diff = table_difference(*next, from_scratch(*next, body));
  INFO("updated vs scratch " << diff);
  CHECK(diff <= kCut);  // measured 5.0e-15 (1.1e-3 when T_D took the zero rows instead of the reactions)
  CHECK(relative_max(next->reactions(), from_scratch(*next, body).reactions()) <= kCut);  // measured 1.7e-15
}

TEST_CASE("a delta that removes elements or does not fit the meshes is refused", "[cut][table]") {
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 3, 3, 2));
  const GreensTable table = GreensTable::compute(body.mesh, body.material, body.base, body.options(body.top));
  SyntheticStep s = bemsurg::testing::split_edge(*body.mesh, body.top[0], 1);
  MeshDelta removed = s.delta;
  removed.removed = {5};
  CHECK_THROWS_AS(updated_table(table, s.mesh, removed), InvalidArgumentError);
  MeshDelta wrong = s.delta;
  wrong.added = {s.delta.elements_after, s.delta.elements_after + 1};
  CHECK_THROWS_AS(updated_table(table, s.mesh, wrong), InvalidArgumentError);
  CHECK(table.version() == 0);
}

TEST_CASE("exact, iterative and refactored cut updates agree after every step", "[cut][system]") {
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 4, 4, 2));
  auto table0 = std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, body.base, body.options(body.top)));
  CutSystemOptions options;
  options.keep_matrix = true;
  options.refactor_rank = 100000;  // no refactorisation here
  const CutUpdateMethod methods[] = {CutUpdateMethod::Exact, CutUpdateMethod::Gmres, CutUpdateMethod::BiCgStab, CutUpdateMethod::BiCg,
                                     CutUpdateMethod::Refactor};
  std::vector<std::unique_ptr<CutSystemUpdate>> systems;
  for (int i = 0; i < 5; ++i) systems.push_back(std::make_unique<CutSystemUpdate>(table0, options));
  std::mt19937 rng(11);
  std::vector<Index> candidates = body.top;
  double worst_iterative = 0.0, worst_refactor = 0.0;
  for (int step = 0; step < 4; ++step) {
    const SyntheticStep s = bemsurg::testing::random_split(*systems[0]->table()->mesh(), candidates, 0.1, rng);
    for (Index e : s.delta.added) candidates.push_back(e);
    for (int i = 0; i < 5; ++i) {
      const CutStepResult r = systems[static_cast<std::size_t>(i)]->apply(s.mesh, s.delta, methods[i]);
      if (i >= 1 && i <= 3) {
        CHECK(r.iterations > 0);
        // The Krylov re-solve reaches its tolerance (1e-12, the true residual): measured 1.7e-13 ..
        // 9.3e-13 in 26 .. 44 iterations.
        CHECK(r.relative_residual <= 1e-12);
      }
    }
    const Eigen::VectorXd& ref = systems[4]->solution();
    for (int i = 0; i < 4; ++i) {
      const double diff = relative_max(systems[static_cast<std::size_t>(i)]->solution(), ref);
      INFO("step " << step << " " << to_string(methods[i]) << " vs refactor: " << diff);
      // Exact vs refactor: round-off of two direct paths, kCut (measured <= 6.4e-15). Krylov: the
      // error its residual of <= 1e-12 leaves, not round-off: measured <= 7.2e-12, bound 3x.
      CHECK(diff <= (i == 0 ? kCut : 2e-11));
      (i == 0 ? worst_refactor : worst_iterative) = std::max(i == 0 ? worst_refactor : worst_iterative, diff);
    }
    CHECK(table_difference(*systems[0]->table(), *systems[4]->table()) <= kCut);  // measured <= 6.4e-15
  }
  WARN("exact vs refactor " << worst_refactor << ", Krylov vs refactor " << worst_iterative);
}

TEST_CASE("a background refactorisation swaps in an equal table of rank zero", "[cut][system]") {
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 4, 4, 2));
  auto table0 = std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, body.base, body.options(body.top)));
  CutSystemOptions options;
  options.refactor_rank = 30;  // the second step passes it
  CutSystemUpdate system(table0, options);
  std::mt19937 rng(5);
  bool started = false;
  for (int step = 0; step < 2; ++step) {
    const SyntheticStep s = bemsurg::testing::random_split(*system.table()->mesh(), body.top, 0.1, rng);
    started = system.apply(s.mesh, s.delta, CutUpdateMethod::Exact).refactor_started;
  }
  CHECK(started);
  const std::shared_ptr<const GreensTable> before = system.table();  // a snapshot held by a reader stays valid
  system.wait_for_refactor();
  const std::shared_ptr<const GreensTable> after = system.table();
  CHECK(after->solver()->rank() == 0);
  CHECK(after->version() == 2);
  CHECK(table_difference(*after, *before) <= kCut);  // measured 5.4e-15
  // Each random_split step reshapes 2 elements and adds 2: 12 changed dofs, a correction of rank
  // 2 x 12 (their rows and their columns); two steps: 48 (measured 48).
  CHECK(before->solver()->rank() == 48);
}

TEST_CASE("a refused cut step leaves table and solution bit-identical", "[cut][system]") {
  const Body body(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 3, 3, 2));
  auto table0 = std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, body.base, body.options(body.top)));
  CutSystemUpdate system(table0);
  const Eigen::VectorXd x = system.solution();
  SyntheticStep s = bemsurg::testing::split_edge(*body.mesh, body.top[0], 1);
  s.delta.removed = {4};
  CHECK_THROWS_AS(system.apply(s.mesh, s.delta, CutUpdateMethod::Exact), InvalidArgumentError);
  CHECK(system.table() == table0);
  CHECK(system.solution() == x);
}
