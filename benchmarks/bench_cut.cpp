// bench_cut: the system and table updates of cutting (docs/cutting.md; Wang et al. 2007 §5.3).
//   1. The paper's Table 1: soft boxes of n = 1080, 1272 and 1584 equations (quick: 384) standing
//      on their base under gravity; a "new cut" (the first step on the uncut body) and an "extended
//      cut" (the next step along the same path), re-solved by GMRES (no restart), BiCGStab and BiCG
//      warm-started from the previous solution (block-Jacobi, tolerance 1e-12), printed beside the
//      paper's figures, with the exact update (system and table) and the reference refactorisation
//      timed in the same run.
//   2. Cut-step latency of the exact update, system plus table (region: the 1,000 free elements
//      nearest the cut, or all when fewer), against n: median over the steps of one cut (opening
//      and five extensions), the refactorisation it replaces (re-assembly, LU, table) and the
//      agreement of the two (largest relative difference of base state and table).
//      Beside it, the step's profile (GreensTableUpdateResult: integration, the step's terms, LU
//      solves, the accumulated rank's work, the new snapshot's first touches, the table's GEMMs)
//      and its arithmetic floor (docs/cutting.md): changed_columns d = 3 (modified + added
//      elements), the rows and columns of A* the step changes (its correction has rank 2d); the
//      step's LU solves (solve_columns right-hand sides, 2 n^2 each) priced at the dgetrs rate on
//      the table's own factors, plus the table's two GEMMs priced at a bare dgemm's rate (n x n
//      times n x d, median of 5), both measured in the same run.
//   3. Narrow gaps: the solution on a cut mesh with default quadrature against a much finer one,
//      as gap width / edge length shrinks (kMinimumGapRatio in cutting/gap_limit.hpp).
//   bench_cut [--quick] [--json PATH] [--csv-dir DIR] [--equations N1,N2,...] [--table1-equations N1,...]
//             [--repeats R] [--no-gap] [--no-table1] [--no-latency] [--fresh-pages]
// JSON: "table1": [{"equations", "scenario", "method", "seconds", "iterations", ...}],
//       "latency": [{"equations", "region_elements", "exact_seconds", "refactor_seconds", "agreement",
//                    "changed_columns", "dgemm_gflops", "arithmetic_floor_seconds", the profile's
//                    "change_seconds", "solve_seconds", "correction_seconds", "snapshot_seconds", ...}],
//       "gap": [{"gap_ratio", "difference_vs_fine_quadrature", ...}].
// --csv-dir DIR: table1.csv, latency.csv (the JSON's fields, one column each) and run.csv.
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/cutting/surface_cutter.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/snapshot_buffers.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bench_support.hpp"

using namespace bemsurg;
using bench::median;
using json = nlohmann::json;

namespace {

constexpr double kCell = 0.01;  // 1 cm cells
// The first response's reach in the latency study: the region elements within 2 cm (two cells) of a
// probe where the step cut: a 1 cm probe and the 1 cm it can travel before the step completes.
constexpr double kReach = 0.02;
// A second probe, this far from where the step cut (3 cm clear of its reach): what a first response
// costs when the tools are away from the cut (docs/cutting.md, "First response").
constexpr double kBeside = 0.05;

struct Body {
  std::shared_ptr<const TriangleMesh> mesh;
  Material material{3000.0, 0.45, 1000.0};
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  BoundaryConditions bc;
  std::vector<char> locked;
  Vec3 from, direction;
  int nx = 0, ny = 0, nz = 0;
};

/// Box of nx x ny x nz cells on its base (u = 0), the cut running along the top face's longer
/// centre line from one cell in from its edge.
Body make_body(int nx, int ny, int nz, const QuadratureOptions& = {}) {
  Body b;
  b.nx = nx;
  b.ny = ny;
  b.nz = nz;
  b.mesh = std::make_shared<const TriangleMesh>(box_mesh(Vec3(0, 0, 0), Vec3(nx * kCell, ny * kCell, nz * kCell), nx, ny, nz));
  b.bc = BoundaryConditions(b.mesh->num_elements());
  b.locked.assign(static_cast<std::size_t>(b.mesh->num_elements()), 0);
  for (Index e = 0; e < b.mesh->num_elements(); ++e)
    if (b.mesh->normal(e).z() < -0.9) {
      b.bc.prescribe_displacement(e, Vec3::Zero());
      b.locked[static_cast<std::size_t>(e)] = 1;
    }
  b.direction = nx >= ny ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  // One cell in from the top face's edge, on its centre line: room for max(nx, ny) - 2 steps.
  const Vec3 centre(0.5 * nx * kCell, 0.5 * ny * kCell, nz * kCell);
  b.from = centre - (0.5 * std::max(nx, ny) - 1.0) * kCell * b.direction;
  return b;
}

/// The free elements nearest the cut's start, at most `limit`.
std::vector<Index> region_near(const Body& b, std::size_t limit) {
  std::vector<Index> free;
  for (Index e = 0; e < b.mesh->num_elements(); ++e)
    if (b.bc.is_free(e)) free.push_back(e);
  std::sort(free.begin(), free.end(),
            [&](Index x, Index y) { return (b.mesh->centroid(x) - b.from).squaredNorm() < (b.mesh->centroid(y) - b.from).squaredNorm(); });
  if (free.size() > limit) free.resize(limit);
  std::sort(free.begin(), free.end());
  return free;
}

std::shared_ptr<const GreensTable> precompute(const Body& b, std::size_t region_limit, const QuadratureOptions& q = {},
                                              bool explicit_inverse = false) {
  GreensTableOptions o;
  o.region = region_near(b, region_limit);
  o.gravity = b.gravity;
  o.quadrature = q;
  o.explicit_inverse = explicit_inverse;
  return std::make_shared<const GreensTable>(GreensTable::compute(b.mesh, b.material, b.bc, o));
}

struct Step {
  std::shared_ptr<const TriangleMesh> mesh;
  MeshDelta delta;
};

/// The cut's steps (topology only): the opening and `extensions` more.
std::vector<Step> cut_steps(const Body& b, int extensions, CutOptions options = {}) {
  SurfaceCutter cutter(b.mesh, b.locked, options);
  std::vector<Step> steps;
  for (int i = 0; i <= extensions; ++i) {
    const CutStep s = cutter.step(b.from, b.direction);
    if (!s.accepted) throw Error("bench_cut: cut step " + std::to_string(i + 1) + " refused: " + s.reason);
    steps.push_back({cutter.mesh(), s.delta});
  }
  return steps;
}

double relative_max(const Eigen::Ref<const Eigen::MatrixXd>& a, const Eigen::Ref<const Eigen::MatrixXd>& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(1e-300, b.cwiseAbs().maxCoeff());
}

double table_difference(const GreensTable& a, const GreensTable& b) {
  return std::max({relative_max(a.columns(), b.columns()), relative_max(a.base_displacement(), b.base_displacement()),
                   relative_max(a.base_traction(), b.base_traction())});
}

/// What a first response must get right (docs/cutting.md, "First response on the rows within
/// reach"): the rows and columns of its region's elements and their base displacement, against the
/// complete table; max difference relative to the complete table's largest entry.
double reach_difference(const GreensTable& first, const GreensTable& complete) {
  double diff = 0.0;
  const double scale = std::max(1e-300, complete.columns().cwiseAbs().maxCoeff());
  const double base_scale = std::max(1e-300, complete.base_displacement().cwiseAbs().maxCoeff());
  for (Index e : first.region()) {
    const Index a = first.region_slot(e), b = complete.region_slot(e);
    for (Index f : first.region())
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j)
          diff = std::max(diff, std::abs(first.columns()(3 * f + i, 3 * a + j) - complete.columns()(3 * f + i, 3 * b + j)) / scale);
        diff = std::max(diff, std::abs(first.base_displacement()(3 * f + i) - complete.base_displacement()(3 * f + i)) / base_scale);
      }
  }
  return diff;
}

struct PaperRow {
  int n;
  const char* scenario;
  double gmres, bicgstab, bicg;
  int it_gmres, it_bicgstab, it_bicg;
};
const PaperRow kPaper[] = {
    {1080, "new cut", 0.06250, 0.234375, 0.234375, 3, 8, 12},  {1080, "extended cut", 0.14062, 0.25000, 0.296875, 9, 9, 14},
    {1272, "new cut", 0.09375, 0.453125, 0.578125, 3, 11, 20}, {1272, "extended cut", 0.17188, 0.468750, 0.609375, 7, 11, 21},
    {1584, "new cut", 0.17188, 0.890625, 0.93750, 3, 13, 20},  {1584, "extended cut", 0.21875, 1.140625, 0.93750, 6, 18, 21},
};

void table1(const std::vector<std::array<int, 3>>& sizes, int repeats, json& out) {
  std::printf("\nTable 1 (Wang et al. 2007): seconds (iterations) of one cut step's re-solve; paper: 3.06 GHz, 1 core\n");
  std::printf("%6s %-13s %-9s %11s %6s | %9s %5s | %12s\n", "n", "scenario", "method", "seconds", "iter", "paper s", "iter", "vs refactor");
  const CutUpdateMethod methods[] = {CutUpdateMethod::Gmres, CutUpdateMethod::BiCgStab, CutUpdateMethod::BiCg, CutUpdateMethod::Exact,
                                     CutUpdateMethod::Refactor};
  for (const auto& c : sizes) {
    const Body body = make_body(c[0], c[1], c[2]);
    const Index n = body.mesh->num_dofs();
    const std::vector<Step> steps = cut_steps(body, 1);
    auto table0 = precompute(body, 1000);
    auto table1 = updated_table(*table0, steps[0].mesh, steps[0].delta);
    const std::shared_ptr<const GreensTable> start[2] = {table0, table1};
    const char* names[2] = {"new cut", "extended cut"};
    for (int sc = 0; sc < 2; ++sc) {
      const Step& step = steps[static_cast<std::size_t>(sc)];
      Eigen::VectorXd reference;
      std::vector<json> rows;
      for (int mi = 4; mi >= 0; --mi) {  // refactor first: the reference of the others
        const CutUpdateMethod m = methods[mi];
        std::vector<double> secs, integ;
        int iterations = 0;
        Eigen::VectorXd x;
        for (int r = 0; r < repeats; ++r) {
          CutSystemOptions o;
          o.keep_matrix = m != CutUpdateMethod::Exact && m != CutUpdateMethod::Refactor;
          o.refactor_rank = 1 << 30;
          CutSystemUpdate sys(start[sc], o);
          const CutStepResult rep = sys.apply(step.mesh, step.delta, m);
          const bool krylov = o.keep_matrix;
          secs.push_back(krylov                        ? rep.system_seconds
                         : m == CutUpdateMethod::Exact ? rep.system_seconds + rep.table_seconds
                                                       : rep.total_seconds);
          integ.push_back(rep.integration_seconds);
          iterations = rep.iterations;
          x = sys.solution();
        }
        if (m == CutUpdateMethod::Refactor) reference = x;
        const double agreement = relative_max(x, reference);
        json row = {{"equations", n},
                    {"equations_after", 3 * step.delta.elements_after},
                    {"scenario", names[sc]},
                    {"method", to_string(m)},
                    {"seconds", median(secs)},
                    {"seconds_min", *std::min_element(secs.begin(), secs.end())},
                    {"seconds_max", *std::max_element(secs.begin(), secs.end())},
                    {"repeats", repeats},
                    {"iterations", iterations},
                    {"integration_seconds", median(integ)},
                    {"agreement_vs_refactor", agreement}};
        const PaperRow* paper = nullptr;
        for (const PaperRow& p : kPaper)
          if (p.n == n && std::string(p.scenario) == names[sc]) paper = &p;
        double ps = 0.0;
        int pi = 0;
        if (paper && m == CutUpdateMethod::Gmres) ps = paper->gmres, pi = paper->it_gmres;
        if (paper && m == CutUpdateMethod::BiCgStab) ps = paper->bicgstab, pi = paper->it_bicgstab;
        if (paper && m == CutUpdateMethod::BiCg) ps = paper->bicg, pi = paper->it_bicg;
        if (ps > 0.0) {
          row["paper_seconds"] = ps;
          row["paper_iterations"] = pi;
        }
        rows.push_back(row);
      }
      std::reverse(rows.begin(), rows.end());
      for (const json& row : rows) {
        const double ps = row.value("paper_seconds", 0.0);
        std::printf("%6lld %-13s %-9s %11s %6d | %9s %5s | %12s\n", static_cast<long long>(n), names[sc],
                    row["method"].get<std::string>().c_str(), fixed_text(row["seconds"].get<double>(), 5).c_str(),
                    row["iterations"].get<int>(), ps > 0.0 ? fixed_text(ps, 6).substr(0, 7).c_str() : "-",
                    ps > 0.0 ? std::to_string(row["paper_iterations"].get<int>()).c_str() : "-",
                    scientific_text(row["agreement_vs_refactor"].get<double>(), 1).c_str());
        out.push_back(row);
      }
    }
  }
  std::printf(
      "  Krylov seconds: the iterations only (as the paper); exact: system + table update (integration apart);\n"
      "  refactor: re-assembly, LU and table. Agreement: max |x - x_refactor| / max |x_refactor|.\n");
}

/// Box nearest `equations`: nx = ny = a (>= 8 for the cut's room), nz = b <= a.
std::array<int, 3> block_near(long long equations) {
  std::array<int, 3> best{8, 8, 3};
  long long gap = -1;
  for (int a = 8; a <= 80; ++a)
    for (int b = 3; b <= a; ++b) {  // at least 3 cells deep: the cut must not break through
      const long long n = 12LL * (a * a + 2LL * a * b);
      const long long d = std::llabs(n - equations);
      if (gap < 0 || d < gap) {
        gap = d;
        best = {a, a, b};
      }
    }
  return best;
}

/// One latency size: the cut's steps on the box nearest `N` equations, each timed, and the
/// refactorisation after the last. Its own scope, so that its tables are freed before the next
/// measurement (n = 15,000: 1.8 GB per LU).
json latency_point(int N, bool pooled) {
  const auto c = block_near(N);
  const Body body = make_body(c[0], c[1], c[2]);
  const int extensions = 5;
  const std::vector<Step> steps = cut_steps(body, extensions);
  // Two chains of the same steps: over the explicit inverse (the two-phase steps, whose first
  // response is exact on the rows within reach) and over the LU (the baseline: the step in one call,
  // and the first response exact on whole columns that the LU allows).
  auto t = precompute(body, 1000, {}, true);
  auto t_lu = precompute(body, 1000);
  auto precompute_of = [](const GreensTable& g) {
    const PrecomputeTimings& p = g.timings();
    return p.assembly_seconds + p.factorization_seconds + p.table_seconds + p.inversion_seconds;
  };
  const double precompute_s = precompute_of(*t), precompute_lu_s = precompute_of(*t_lu);
  const double factorization_s = t->timings().factorization_seconds, inversion_s = t->timings().inversion_seconds;
  std::vector<double> exact, integ, sys, tab, first_lu;
  // Where the first response's time goes (GreensTableUpdateResult of CutTableStep::first_response).
  const char* first_keys[] = {"first_integration_seconds", "first_change_seconds",   "first_inverse_gemm_seconds",
                              "first_correction_seconds",  "first_snapshot_seconds", "first_table_seconds"};
  std::vector<std::vector<double>> first_profile(std::size(first_keys));
  double lu_agreement = 0.0;
  // The profile of the system and table phases (GreensTableUpdateResult), one median each.
  const char* profile_keys[] = {"change_seconds", "solve_seconds", "correction_seconds", "snapshot_seconds", "gemm_seconds",
                                "finish_seconds", "solve_columns", "table_gemm_flops",   "snapshot_bytes"};
  std::vector<std::vector<double>> profile(std::size(profile_keys));
  double changed = 0.0;
  Index rank = 0;
  std::shared_ptr<const GreensTable> before_last;
  std::vector<double> first, one_step, reach_count, first_columns, beside, beside_columns;
  double first_agreement = 0.0;
  // The two-phase chain's tables draw their storage from one pool, as CutSystemUpdate's do (docs/cutting.md,
  // "Snapshot storage"); --fresh-pages measures them on fresh memory, as the one-call chain is.
  GreensTableUpdateOptions two_phase_options;
  if (pooled) two_phase_options.buffers = std::make_shared<SnapshotBufferPool>();
  int index = 0;
  for (const Step& s : steps) {
    GreensTableUpdateResult r;
    before_last = t;
    // The step in two phases (CutTableStep, docs/cutting.md "First response"): the first makes exact
    // the columns of the region elements within kReach of a probe where the step cut, the second
    // completes the table. Beside it, from the same table, the step in one call (updated_table, the
    // baseline: the latency before the split). They run in alternating order.
    std::shared_ptr<const GreensTable> one, two, early;
    double first_s = 0.0, two_s = 0.0;
    auto two_phases = [&] {
      const auto t0 = SteadyClock::now();
      CutChange change = integrate_cut_change(*t->mesh(), *s.mesh, s.delta, t->material(), t->quadrature(), t->gravity());
      const CutTableStep cut(t, s.mesh, s.delta, std::move(change), two_phase_options);
      // A probe where the step cut: its first new element (a cut step always adds some; else its first changed one).
      const std::vector<Index> changed = s.delta.changed();
      const Index at = !s.delta.added.empty() ? s.delta.added.front() : !changed.empty() ? changed.front() : 0;
      const Eigen::Vector3d probe = s.mesh->centroid(at);
      const std::vector<Index> reach = elements_within_reach(*s.mesh, cut.region(), {probe}, kReach);
      GreensTableUpdateResult early_report;
      early = cut.first_response(reach, &early_report);
      first_s = seconds_since(t0);
      first_columns.push_back(double(early_report.solve_columns));
      const double parts[] = {early_report.integration_seconds, early_report.change_seconds,   early_report.solve_seconds,
                              early_report.correction_seconds,  early_report.snapshot_seconds, early_report.table_seconds};
      for (std::size_t k = 0; k < first_profile.size(); ++k) first_profile[k].push_back(parts[k]);
      two = cut.complete(&r);
      two_s = seconds_since(t0);
      reach_count.push_back(double(reach.size()));
    };
    auto one_call = [&] {
      const auto t0 = SteadyClock::now();
      one = updated_table(*t_lu, s.mesh, s.delta);
      one_step.push_back(seconds_since(t0));
    };
    // The first response the LU allows (exact columns, every row) for the same probe: the method
    // before the explicit inverse.
    auto lu_first = [&] {
      const auto t0 = SteadyClock::now();
      CutChange change = integrate_cut_change(*t_lu->mesh(), *s.mesh, s.delta, t_lu->material(), t_lu->quadrature(), t_lu->gravity());
      const CutTableStep cut(t_lu, s.mesh, s.delta, std::move(change));
      const std::vector<Index> changed = s.delta.changed();
      const Index at = !s.delta.added.empty() ? s.delta.added.front() : !changed.empty() ? changed.front() : 0;
      cut.first_response(elements_within_reach(*s.mesh, cut.region(), {s.mesh->centroid(at)}, kReach));
      first_lu.push_back(seconds_since(t0));
    };
    // The first response for a probe kBeside from the cut (the region element whose centroid lies
    // nearest that distance from the step's first new element): its reach holds none of the step's
    // fresh columns, which the completion solves (not timed here).
    auto beside_first = [&] {
      const auto t0 = SteadyClock::now();
      CutChange change = integrate_cut_change(*t->mesh(), *s.mesh, s.delta, t->material(), t->quadrature(), t->gravity());
      const CutTableStep cut(t, s.mesh, s.delta, std::move(change), two_phase_options);
      const Eigen::Vector3d at = s.mesh->centroid(!s.delta.added.empty() ? s.delta.added.front() : s.delta.changed().front());
      Index probe = cut.region().front();
      for (Index e : cut.region())
        if (std::abs((s.mesh->centroid(e) - at).norm() - kBeside) < std::abs((s.mesh->centroid(probe) - at).norm() - kBeside)) probe = e;
      GreensTableUpdateResult report;
      cut.first_response(elements_within_reach(*s.mesh, cut.region(), {s.mesh->centroid(probe)}, kReach), &report);
      beside.push_back(seconds_since(t0));
      beside_columns.push_back(double(report.solve_columns));
    };
    if (index++ % 2 == 0) {
      lu_first();
      one_call();
      two_phases();
      beside_first();
    } else {
      beside_first();
      two_phases();
      one_call();
      lu_first();
    }
    first.push_back(first_s);
    first_agreement = std::max(first_agreement, reach_difference(*early, *two));
    lu_agreement = std::max(lu_agreement, table_difference(*two, *one));  // the two chains, step by step
    t_lu = one;
    one.reset();
    early.reset();
    t = two;
    exact.push_back(two_s);
    integ.push_back(r.integration_seconds);
    sys.push_back(r.system_seconds);
    tab.push_back(r.table_seconds);
    const double values[] = {r.change_seconds, r.solve_seconds,         r.correction_seconds, r.snapshot_seconds,      r.gemm_seconds,
                             r.finish_seconds, double(r.solve_columns), r.table_gemm_flops,   double(r.snapshot_bytes)};
    for (std::size_t k = 0; k < profile.size(); ++k) profile[k].push_back(values[k]);
    changed += double(s.delta.modified.size() + s.delta.added.size()) / double(steps.size());
    rank = r.rank;
  }
  // The rate of the LU's triangular solves on this table's own factors (dgetrs, as many right-hand
  // sides as a step's median): what the arithmetic floor prices the solves at.
  const Index n0 = t->solver()->base_size();
  const Index k = std::max<Index>(1, static_cast<Index>(std::lround(median(profile[6]))));
  std::vector<double> solve_s;
  for (int r = 0; r < 6; ++r) {
    Eigen::MatrixXd B = Eigen::MatrixXd::Constant(n0, k, 1e-3);
    const auto ts = SteadyClock::now();
    t->solver()->base()->solve_in_place(B);
    if (r > 0) solve_s.push_back(seconds_since(ts));  // the first touches B's pages and starts threads
  }
  const double dgetrs_gflops = 2.0 * double(n0) * double(n0) * double(k) / std::max(1e-12, median(solve_s)) * 1e-9;
  const auto t0 = SteadyClock::now();
  auto ref = recomputed_table_after(*before_last, steps.back().mesh, steps.back().delta);
  const double refactor_s = seconds_since(t0);
  json profile_row = json::object();
  for (std::size_t i = 0; i < profile.size(); ++i) profile_row[profile_keys[i]] = median(profile[i]);
  profile_row["solve_base_size"] = n0;
  for (std::size_t i = 0; i < first_profile.size(); ++i) profile_row[first_keys[i]] = median(first_profile[i]);
  profile_row["dgetrs_gflops"] = dgetrs_gflops;
  return {{"equations", body.mesh->num_dofs()},
          {"profile", profile_row},
          {"first_response_seconds", median(first)},
          {"first_response_lu_seconds", median(first_lu)},
          {"one_step_seconds", median(one_step)},
          {"reach_elements", median(reach_count)},
          // The first response's LU right-hand sides: U_s's, the base state's and the fresh columns within reach.
          {"first_response_solve_columns", median(first_columns)},
          // The same for a probe kBeside from the cut, whose reach holds none of the fresh columns.
          {"first_response_beside_seconds", median(beside)},
          {"first_response_beside_solve_columns", median(beside_columns)},
          {"beside_metres", kBeside},
          {"reach_metres", kReach},
          {"first_response_agreement", first_agreement},
          {"snapshot_buffers_reused", pooled ? two_phase_options.buffers->counts().reused : 0},
          {"block", {c[0], c[1], c[2]}},
          {"region_elements", before_last->region().size()},
          {"steps", steps.size()},
          {"changed_elements_per_step", changed},
          // d = 3 (|M| + |N|): the rows and columns of A* a step changes (docs/cutting.md).
          {"changed_columns", std::lround(3.0 * changed)},
          {"exact_seconds", median(exact)},
          {"exact_seconds_all", exact},
          {"integration_seconds", median(integ)},
          {"system_seconds", median(sys)},
          {"table_seconds", median(tab)},
          {"refactor_seconds", refactor_s},
          {"precompute_seconds", precompute_s},
          {"precompute_lu_seconds", precompute_lu_s},
          {"factorization_seconds", factorization_s},
          {"inversion_seconds", inversion_s},
          {"lu_agreement", lu_agreement},
          {"solver_bytes", t->solver()->bytes() + t->solver()->base()->bytes()},
          {"solver_lu_bytes", t_lu->solver()->bytes() + t_lu->solver()->base()->bytes()},
          {"agreement", table_difference(*t, *ref)},
          {"final_rank", rank}};
}

/// GFLOP/s of a bare dgemm, an n x n matrix times an n x k one (Eigen's product: OpenBLAS with
/// BEMSURG_HAVE_BLAS), median of `repeats`: the rate the step's flop floor is priced at.
double dgemm_gflops(Index n, Index k, int repeats) {
  const Eigen::MatrixXd a = Eigen::MatrixXd::Constant(n, n, 0.5) + Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Constant(n, k, 0.25);
  Eigen::MatrixXd c(n, k);
  c.noalias() = a * b;  // warm-up: first touches, threads started
  std::vector<double> secs;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = SteadyClock::now();
    c.noalias() = a * b;
    secs.push_back(seconds_since(t0));
  }
  return 2.0 * double(n) * double(n) * double(k) / std::max(1e-12, median(secs)) * 1e-9;
}

void latency(const std::vector<int>& equations, bool pooled, json& out) {
  std::printf("\nCut-step latency, exact update of system + table (region: 1,000 free elements nearest the cut)\n");
  std::printf("%7s %7s %5s %10s %10s %10s %10s %10s %10s %10s %9s %10s %8s %9s %5s %8s %9s\n", "n", "region", "d", "exact s", "first s",
              "first LU s", "beside s", "one call s", "integr. s", "system s", "table s", "refactor s", "agree", "rank", "GF/s", "floor s",
              "ex/floor");
  for (int N : equations) {
    json row = latency_point(N, pooled);
    const Index n = row["equations"].get<Index>(), k = std::max<Index>(1, row["changed_columns"].get<Index>());
    const double rate = dgemm_gflops(n, k, 5);
    // The arithmetic floor (docs/cutting.md, "Where a step's time goes"): the LU solves a step
    // needs (the new dofs' unit columns need none: K^-1 is the identity there) at the measured
    // dgetrs rate, and the table's two products at the dgemm rate. Integration, the accumulated
    // rank's products and first touches are above it.
    json profile = row["profile"];
    row.erase("profile");
    for (auto it = profile.begin(); it != profile.end(); ++it) row[it.key()] = it.value();
    const double nb = row["solve_base_size"].get<double>();
    const double solve_floor = 2.0 * nb * nb * row["solve_columns"].get<double>() / (row["dgetrs_gflops"].get<double>() * 1e9);
    const double gemm_floor = row["table_gemm_flops"].get<double>() / (rate * 1e9);
    const double floor_s = solve_floor + gemm_floor;
    row["dgemm_gflops"] = rate;
    row["solve_floor_seconds"] = solve_floor;
    row["gemm_floor_seconds"] = gemm_floor;
    row["arithmetic_floor_seconds"] = floor_s;
    // The first response's floor over the explicit inverse: V_s^T A0^-1, one GEMM of d x n x n.
    row["first_response_floor_seconds"] = 2.0 * nb * nb * double(k) / (rate * 1e9);
    const double ex = row["exact_seconds"].get<double>();
    std::printf("%7lld %7zu %5lld %10s %10s %10s %10s %10s %10s %10s %9s %10s %8s %9lld %5s %8s %9s\n", static_cast<long long>(n),
                row["region_elements"].get<std::size_t>(), static_cast<long long>(k), fixed_text(ex, 4).c_str(),
                fixed_text(row["first_response_seconds"].get<double>(), 4).c_str(),
                fixed_text(row["first_response_lu_seconds"].get<double>(), 4).c_str(),
                fixed_text(row["first_response_beside_seconds"].get<double>(), 4).c_str(),
                fixed_text(row["one_step_seconds"].get<double>(), 4).c_str(),
                fixed_text(row["integration_seconds"].get<double>(), 4).c_str(), fixed_text(row["system_seconds"].get<double>(), 4).c_str(),
                fixed_text(row["table_seconds"].get<double>(), 4).c_str(), fixed_text(row["refactor_seconds"].get<double>(), 3).c_str(),
                scientific_text(row["agreement"].get<double>(), 1).c_str(), static_cast<long long>(row["final_rank"].get<Index>()),
                fixed_text(rate, 1).c_str(), fixed_text(floor_s, 4).c_str(), fixed_text(ex / floor_s, 1).c_str());
    out.push_back(row);
  }
  std::printf(
      "  exact: request to the complete table in two phases over the explicit inverse; first: to its first\n"
      "  response (exact on the rows and columns of the elements within 2 cm of a probe where the step cut);\n"
      "  first LU: the same probe's first response over the LU (exact columns, every row); beside: the first\n"
      "  response for a probe 5 cm from the cut; one call: the step by updated_table over the LU, the baseline.\n"
      "  targets (medians): first <= 0.020 / 0.050 / 0.100 s at n = 1,620 / 4,704 / 8,976 (issue 39). Agreement: max relative\n"
      "  difference of base state and table from a full refactorisation after the last step. d: changed columns\n"
      "  per step; floor: the step's LU solves at the dgetrs rate measured on its own factors plus the table's\n"
      "  two GEMMs at the dgemm rate (GF/s, n x n times n x d) measured here.\n");
  std::printf("\nWhere the exact step's time goes (medians, seconds)\n");
  std::printf("%7s %9s %9s %9s %6s %10s %9s %9s %9s %9s %9s %9s\n", "n", "integr.", "change", "solves", "rhs", "correction", "snapshot",
              "gemm", "finish", "floor", "dgetrsGF", "snap MB");
  for (const json& row : out)
    std::printf(
        "%7lld %9s %9s %9s %6lld %10s %9s %9s %9s %9s %9s %9s\n", static_cast<long long>(row["equations"].get<Index>()),
        fixed_text(row["integration_seconds"].get<double>(), 4).c_str(), fixed_text(row["change_seconds"].get<double>(), 4).c_str(),
        fixed_text(row["solve_seconds"].get<double>(), 4).c_str(), static_cast<long long>(std::llround(row["solve_columns"].get<double>())),
        fixed_text(row["correction_seconds"].get<double>(), 4).c_str(), fixed_text(row["snapshot_seconds"].get<double>(), 4).c_str(),
        fixed_text(row["gemm_seconds"].get<double>(), 4).c_str(), fixed_text(row["finish_seconds"].get<double>(), 4).c_str(),
        fixed_text(row["arithmetic_floor_seconds"].get<double>(), 4).c_str(), fixed_text(row["dgetrs_gflops"].get<double>(), 1).c_str(),
        fixed_text(row["snapshot_bytes"].get<double>() / 1e6, 0).c_str());
}

void gap_study(bool quick, json& out) {
  std::printf("\nNarrow gaps: solution with default quadrature vs a finer one (far 8, mid 4, order 10, depth 18, polar 20)\n");
  std::printf("%10s %10s %14s %14s\n", "gap/edge", "equations", "u difference", "t difference");
  QuadratureOptions fine;
  fine.far_ratio = 8.0;
  fine.mid_ratio = 4.0;
  fine.mid_order = 10;
  fine.max_depth = 18;
  fine.polar_order = 20;
  fine.polar_max_angle = 0.1;
  const std::vector<double> ratios = quick ? std::vector<double>{0.1} : std::vector<double>{0.0, 0.2, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002};
  const Body body = make_body(quick ? 6 : 8, quick ? 6 : 8, 3);
  for (double ratio : ratios) {
    std::shared_ptr<const TriangleMesh> mesh = body.mesh;
    Index changed = 0;
    MeshDelta delta;
    if (ratio > 0.0) {
      CutOptions co;
      co.gap_fraction = ratio;
      co.allow_narrow_gap_for_studies = true;  // below the library's limit on purpose: this is the study that set it
      co.min_angle_degrees = 0.05;
      const std::vector<Step> steps = cut_steps(body, 1, co);
      mesh = steps.back().mesh;
    }
    BoundaryConditions bc(mesh->num_elements());
    for (Index e = 0; e < body.mesh->num_elements(); ++e)
      if (body.bc.kind(3 * e) == BcKind::Displacement) bc.prescribe_displacement(e, Vec3::Zero());
    Eigen::VectorXd x[2];
    for (int q = 0; q < 2; ++q) {
      const InfluenceAssembler assembler(*mesh, body.material, q == 0 ? QuadratureOptions() : fine);
      Eigen::VectorXd g;
      InfluenceMatrices hg = assembler.assemble(body.gravity, g);
      const Eigen::VectorXd b = build_right_hand_side(hg, bc, g);
      const Eigen::MatrixXd A = build_system_matrix_in_place(hg, bc);
      x[q] = DenseLu(A).solve(b);
    }
    double du = 0, su = 0, dt = 0, st = 0;
    for (Index k = 0; k < x[0].size(); ++k) {
      const bool u = bc.kind(k) == BcKind::Traction;
      (u ? du : dt) = std::max(u ? du : dt, std::abs(x[0](k) - x[1](k)));
      (u ? su : st) = std::max(u ? su : st, std::abs(x[1](k)));
    }
    (void)changed;
    std::printf("%10s %10lld %14s %14s\n", fixed_text(ratio, 3).c_str(), static_cast<long long>(x[0].size()),
                scientific_text(du / su, 2).c_str(), scientific_text(dt / st, 2).c_str());
    out.push_back({{"gap_ratio", ratio},
                   {"equations", x[0].size()},
                   {"difference_vs_fine_quadrature", du / su},
                   {"traction_difference_vs_fine_quadrature", dt / st}});
  }
  std::printf("  gap/edge 0: the uncut body (the quadrature's own error). Differences: max over dofs, relative to the largest.\n");
}

/// The 1-minute load average (/proc/loadavg; -1 where unavailable): on a shared 2-core machine a
/// load above 2 makes every wall-clock figure proportionally slower, so the report keeps it.
double load_average() {
  std::ifstream in("/proc/loadavg");
  double l = -1.0;
  in >> l;
  return in ? l : -1.0;
}

/// The boxes of Table 1 by equation count: the paper's three (Wang et al. 2007, Table 1) and the
/// quick run's 384. Empty when `equations` names another count.
std::optional<std::array<int, 3>> table1_block(int equations) {
  switch (equations) {
    case 384: return std::array<int, 3>{4, 4, 2};
    case 1080: return std::array<int, 3>{6, 3, 8};
    case 1272: return std::array<int, 3>{2, 8, 9};
    case 1584: return std::array<int, 3>{6, 6, 8};
    default: return std::nullopt;
  }
}

/// Rows of JSON objects as CSV under `columns` (one column per parameter, then the metrics:
/// docs/benchmarks.md, "The report's data"): numbers as their shortest round-trip text in every
/// locale (number_text.hpp), a missing value as an empty cell.
bool write_csv(const std::string& path, const json& rows, const std::vector<std::string>& columns) {
  std::string text;
  for (std::size_t i = 0; i < columns.size(); ++i) text += (i ? "," : "") + columns[i];
  text += "\n";
  for (const json& r : rows) {
    for (std::size_t i = 0; i < columns.size(); ++i) {
      if (i) text += ",";
      const auto v = r.find(columns[i]);
      if (v == r.end() || v->is_null()) continue;
      if (v->is_string())
        text += v->get<std::string>();
      else if (v->is_number_integer())
        append_integer(text, v->get<long long>());
      else if (v->is_boolean())
        text += v->get<bool>() ? "1" : "0";
      else
        append_number(text, v->get<double>());
    }
    text += "\n";
  }
  std::ofstream out(path);
  use_classic_locale(out);
  out << text;
  if (!out) std::cerr << "bench_cut: cannot write " << path << "\n";
  return static_cast<bool>(out);
}

/// --csv-dir: table1.csv, latency.csv (the box's cells as nx, ny, nz) and run.csv (the run's
/// threads, back end and load), what scripts/report/parts/{table1,cut_latency}.py read.
bool write_csv_dir(const std::string& dir, const json& report) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  json latency_rows = json::array();
  for (json r : report["latency"]) {
    const char* cells[3] = {"nx", "ny", "nz"};
    for (std::size_t i = 0; i < 3; ++i) r[cells[i]] = r["block"][i];
    latency_rows.push_back(r);
  }
  const json run = json::array({report});
  return write_csv(dir + "/table1.csv", report["table1"],
                   {"equations", "scenario", "method", "equations_after", "seconds", "seconds_min", "seconds_max", "repeats", "iterations",
                    "integration_seconds", "agreement_vs_refactor", "paper_seconds", "paper_iterations", "dgemm_gflops"}) &&
         write_csv(dir + "/latency.csv", latency_rows,
                   {"equations",
                    "nx",
                    "ny",
                    "nz",
                    "region_elements",
                    "steps",
                    "changed_elements_per_step",
                    "changed_columns",
                    "exact_seconds",
                    "first_response_seconds",
                    "first_response_lu_seconds",
                    "first_response_floor_seconds",
                    "one_step_seconds",
                    "reach_elements",
                    "first_response_solve_columns",
                    "first_response_beside_seconds",
                    "first_response_beside_solve_columns",
                    "beside_metres",
                    "reach_metres",
                    "first_response_agreement",
                    "snapshot_buffers_reused",
                    "integration_seconds",
                    "system_seconds",
                    "table_seconds",
                    "refactor_seconds",
                    "precompute_seconds",
                    "precompute_lu_seconds",
                    "factorization_seconds",
                    "inversion_seconds",
                    "agreement",
                    "lu_agreement",
                    "solver_bytes",
                    "solver_lu_bytes",
                    "final_rank",
                    "dgemm_gflops",
                    "change_seconds",
                    "solve_seconds",
                    "solve_columns",
                    "correction_seconds",
                    "snapshot_seconds",
                    "gemm_seconds",
                    "finish_seconds",
                    "table_gemm_flops",
                    "snapshot_bytes",
                    "solve_base_size",
                    "dgetrs_gflops",
                    "solve_floor_seconds",
                    "gemm_floor_seconds",
                    "arithmetic_floor_seconds"}) &&
         write_csv(dir + "/run.csv", run,
                   {"mode", "threads", "dense_backend", "repeats", "freed_memory_reused", "load_average_at_start", "load_average_at_end"});
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, no_gap = false, no_table1 = false, no_latency = false, fresh_pages = false;
  int repeats = 3;
  std::string json_path;
  std::string csv_dir;
  std::vector<int> equations, table1_equations;
  cli::OptionParser parser = bench::command_line(
      "bench_cut", "The system and table updates of cutting against the paper's Table 1 (docs/cutting.md).\n", quick, json_path);
  parser.value("--equations", "N1,N2,...", equations, "sizes of the latency study")
      .at_least(1)
      .default_text("1584,4752,9000,12000; --quick: 1000 (the smallest box: 1,344)");
  parser.value("--table1-equations", "N1,...", table1_equations, "sizes of Table 1: 1080, 1272, 1584 (the paper's) or 384")
      .default_text("1080,1272,1584; --quick: 384");
  parser.value("--csv-dir", "DIR", csv_dir, "write table1.csv, latency.csv and run.csv to DIR (the benchmark report's data)");
  parser.value("--repeats", "R", repeats, "timings per figure (median; --quick: 1)").at_least(1);
  parser.flag("--no-gap", no_gap, "leave out the narrow-gap study");
  parser.flag("--no-table1", no_table1, "leave out Table 1");
  parser.flag("--no-latency", no_latency, "leave out the latency study");
  parser.flag("--fresh-pages", fresh_pages,
              "return freed memory to the system and give the two-phase chain no snapshot pool (bemsurg cut reuses both)");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  const bool gap = !no_gap, do_table1 = !no_table1, do_latency = !no_latency, reuse_memory = !fresh_pages;
  // As bemsurg cut and session do: freed table snapshots are reused rather than returned to the
  // system (bemsurg/memory_budget.hpp); --fresh-pages measures without it.
  const bool reused = reuse_memory && reuse_freed_memory();
  if (quick) repeats = 1;
  if (equations.empty()) equations = quick ? std::vector<int>{1000} : std::vector<int>{1584, 4752, 9000, 12000};
  if (table1_equations.empty()) table1_equations = quick ? std::vector<int>{384} : std::vector<int>{1080, 1272, 1584};
  std::vector<std::array<int, 3>> sizes;
  for (int n : table1_equations) {
    const auto block = table1_block(n);
    if (!block) {
      std::cerr << "bench_cut: --table1-equations: " << n << " is not one of 384, 1080, 1272, 1584\n";
      return 2;
    }
    sizes.push_back(*block);
  }
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
#ifdef BEMSURG_HAVE_BLAS
  const char* backend = "OpenBLAS+LAPACKE";
#else
  const char* backend = "Eigen";
#endif
  std::printf("bench_cut (%s): %d OpenMP threads, dense back end %s, %d repeats (median), freed memory %s, load average %s\n",
              quick ? "quick" : "full", threads, backend, repeats, reused ? "reused" : "returned (fresh pages)",
              fixed_text(load_average(), 2).c_str());
  json report = {{"benchmark", "bench_cut"},
                 {"mode", quick ? "quick" : "full"},
                 {"threads", threads},
                 {"dense_backend", backend},
                 {"repeats", repeats},
                 {"freed_memory_reused", reused},
                 {"load_average_at_start", load_average()},
                 {"table1", json::array()},
                 {"latency", json::array()},
                 {"gap", json::array()}};
  try {
    if (do_table1) {
      table1(sizes, repeats, report["table1"]);
      // This machine's dense rate as Table 1 ran (all threads, n x n times n x 100, median of 5):
      // the report prices the paper's seconds by it (issue 37: hardware ratio first, then method).
      const double rate = dgemm_gflops(static_cast<Index>(std::max(table1_equations.back(), 384)), 100, 5);
      for (json& row : report["table1"]) row["dgemm_gflops"] = rate;
    }
    if (do_latency) latency(equations, reuse_memory, report["latency"]);
    if (gap) gap_study(quick, report["gap"]);
  } catch (const std::exception& e) {
    std::cerr << "bench_cut: " << e.what() << "\n";
    bench::write_json_file(json_path, report, "bench_cut");
    return 1;
  }
  report["load_average_at_end"] = load_average();
  std::printf("load average at the end: %s\n", fixed_text(load_average(), 2).c_str());
  if (!bench::write_json_file(json_path, report, "bench_cut")) return 1;
  if (!csv_dir.empty() && !write_csv_dir(csv_dir, report)) return 1;
  return 0;
}
