// test_stability_cutting.cpp: the thresholds of the cutting studies (issue 25, docs/stability.md),
// asserted on both sides: (d) the narrowest cut gap, (f) the rank at which cut updates refactorise.
#include <Eigen/LU>
#include <catch2/catch.hpp>
#include <random>

#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/cutting/gap_limit.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "support/studies/cutting_setup.hpp"
#include "support/synthetic_cuts.hpp"

using namespace bemsurg;
using namespace bemsurg::stability;

// The drift an exact cut update may have from a fresh factorisation (docs/stability.md (f)): the
// cut modes' agreement (docs/cutting.md: exact and refactored agree to 1e-14 .. 1e-11), with room.
constexpr double kMaxUpdateDrift = 1e-10;

TEST_CASE("a cut gap just above kMinimumGapRatio is accepted and accurate, just below it is refused naming width, edge and limit",
          "[stability][gap]") {
  const CutBody body = make_cut_body(4, 4, 2);
  SECTION("just above: accepted, and the solution agrees with a refined quadrature to 1e-6 (the limit's criterion)") {
    const auto mesh = cut_mesh(body, 1.05 * kMinimumGapRatio, 2, false);
    REQUIRE(mesh->num_elements() > body.mesh->num_elements());
    const CutSystem s = cut_system(body, *mesh, QuadratureOptions()), f = cut_system(body, *mesh, refined_quadrature());
    const Eigen::VectorXd x = Eigen::PartialPivLU<Eigen::MatrixXd>(s.A).solve(s.b);
    const Eigen::VectorXd xf = Eigen::PartialPivLU<Eigen::MatrixXd>(f.A).solve(f.b);
    CHECK(displacement_difference(x, xf, s.bc) < 1e-6);
  }
  SECTION("just below: refused by the cutter, nothing changed, the message names the width, the edge length and the limit") {
    CutOptions co;
    co.gap_fraction = 0.95 * kMinimumGapRatio;
    SurfaceCutter cutter(body.mesh, body.locked, co);
    const CutStep s = cutter.step(body.from, body.direction);
    CHECK_FALSE(s.accepted);
    CHECK(cutter.mesh() == body.mesh);
    CHECK(cutter.version() == 0);
    CHECK_THAT(s.reason, Catch::Contains("too narrow: width 0.00095") && Catch::Contains("local edge length 0.01") &&
                             Catch::Contains("below 0.1 x the edge length"));
    // The option meant for studies switches the check off; the same step is then accepted.
    co.allow_narrow_gap_for_studies = true;
    SurfaceCutter study(body.mesh, body.locked, co);
    CHECK(study.step(body.from, body.direction).accepted);
  }
}

TEST_CASE("exact cut updates agree with a fresh factorisation up to the refactor rank, and past it bemsurg refactorises",
          "[stability][updates]") {
  const CutBody body = make_cut_body(4, 4, 2);
  auto table = top_face_table(body);
  const Index limit = default_refactor_rank(table->num_dofs());  // refactor_rank 0: the default
  REQUIRE(limit == 96);
  CutSystemOptions so;
  so.background_refactor = false;  // refactorise inside apply(), so the step's result shows it
  CutSystemUpdate system(table, so);
  std::mt19937 rng(7);
  std::vector<Index> candidates = table->region();  // the top face
  // Each random split reshapes 2 elements and adds 2: rank 24 per step (tests/test_cut_algebra.cpp), so
  // steps 1-4 reach rank 96 = the limit (kept) and step 5 passes it (refactorised).
  for (int step = 1; step <= 5; ++step) {
    const testing::SyntheticStep s = testing::random_split(*system.table()->mesh(), candidates, 0.1, rng);
    for (Index e : s.delta.added) candidates.push_back(e);
    const CutStepResult r = system.apply(s.mesh, s.delta, CutUpdateMethod::Exact);
    INFO("step " << step << ", rank " << r.rank);
    CHECK(r.rank == 24 * step);
    CHECK(r.refactor_started == (r.rank > limit));
    CHECK(system.table()->solver()->rank() == (r.rank > limit ? 0 : r.rank));
    if (step < 4) continue;
    // At the limit (step 4: the updated LU) and past it (step 5: the refactorised one), against the
    // independent reference: the cut mesh assembled from scratch and solved by a fresh LU.
    const auto t = system.table();
    const InfluenceAssembler assembler(*t->mesh(), body.material, t->quadrature());
    Eigen::VectorXd g;
    InfluenceMatrices hg = assembler.assemble(body.gravity, g);
    const BoundaryConditions bc = t->base_conditions();
    const Eigen::VectorXd b = build_right_hand_side(hg, bc, g);
    const Eigen::VectorXd x = Eigen::PartialPivLU<Eigen::MatrixXd>(build_system_matrix_in_place(hg, bc)).solve(b);
    CHECK((system.solution() - x).norm() <= kMaxUpdateDrift * x.norm());
    CHECK((t->solver()->solve(b) - x).norm() <= kMaxUpdateDrift * x.norm());
  }
}
