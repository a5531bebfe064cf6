// bench_krylov: bemsurg's Krylov solvers against Eigen's on the same BEM systems (the
// re-solve after a cut of Wang et al. 2007 §5.3, Table 1: GMRES without restart, BiCGStab, BiCG).
// For each soft block on its base under gravity (A* x = b, eq. 6) it times
//   cold: x0 = 0, every method x preconditioner of ours, Eigen::BiCGSTAB (identity and its default
//         diagonal preconditioner) and Eigen's unsupported GMRES (restart = no restart, and 30);
//   warm: after a local change (one top vertex pushed in, re-assembled: the rows and columns around
//         it change, as after an incremental cut), from the previous solution;
// with iterations, median seconds of repeated solves, the true residual recomputed from x and the
// error against dense LU; ratios are ours / Eigen's for the same method and preconditioner.
//   bench_krylov [--quick] [--json PATH] [--csv PATH] [--tolerance T] [--repeats R] [--equations N1,N2,...]
// --quick: one small system (a few seconds, the CI smoke test). Full: the paper's sizes
// n = 1080, 1272, 1584 (plus the small one). --equations: only the systems of these sizes (any of
// 324, 1080, 1272, 1584; the benchmark report's shorter full run). JSON fields: docs/benchmarks.md "bench_krylov".
#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <unsupported/Eigen/IterativeSolvers>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/solvers/bicg.hpp"
#include "bemsurg/solvers/bicgstab.hpp"
#include "bemsurg/solvers/block_jacobi_preconditioner.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bemsurg/solvers/gmres.hpp"
#include "bemsurg/solvers/near_field_preconditioner.hpp"
#include "bench_support.hpp"

using namespace bemsurg;
using bench::Clock;
using bench::median;
using json = nlohmann::json;

namespace {

struct System {
  std::string name;
  TriangleMesh mesh;
  Eigen::MatrixXd A;
  Eigen::VectorXd b, x_lu;
  double lu_seconds = 0.0, condition = 0.0, assembly_seconds = 0.0;
};

/// Box of nx x ny x nz cells of 1 cm (brain-like: E = 3 kPa, nu = 0.45, rho = 1000) standing on
/// its base (u = 0), gravity, traction-free elsewhere. push > 0 moves the top vertex nearest the
/// centre of the top face down by push x height and re-assembles (a local change, as a cut makes).
System make_system(int nx, int ny, int nz, double push, int lu_repeats) {
  const double h = 0.01;
  const Vec3 lo(0, 0, 0), hi(nx * h, ny * h, nz * h);
  TriangleMesh mesh = box_mesh(lo, hi, nx, ny, nz);
  if (push > 0.0) {
    RowMatrixX3d v = mesh.vertices();
    const Vec3 target(0.5 * hi.x(), 0.5 * hi.y(), hi.z());
    Index best = 0;
    for (Index i = 0; i < v.rows(); ++i)
      if ((v.row(i).transpose() - target).norm() < (v.row(best).transpose() - target).norm()) best = i;
    v(best, 2) -= push * hi.z();
    mesh = TriangleMesh(v, mesh.faces());
  }
  Material material;
  material.young_modulus = 3000.0;
  material.poisson_ratio = 0.45;
  material.density = 1000.0;
  BoundaryConditions bc(mesh.num_elements());
  for (Index e = 0; e < mesh.num_elements(); ++e)
    if (mesh.normal(e).z() < -0.9) bc.prescribe_displacement(e, Vec3::Zero());
  const auto t0 = Clock::now();
  const InfluenceAssembler assembler(mesh, material);
  const InfluenceMatrices hg = assembler.assemble();
  System s;
  s.name = "box " + std::to_string(nx) + "x" + std::to_string(ny) + "x" + std::to_string(nz) + (push > 0 ? " pushed" : "");
  s.A = build_system_matrix(hg, bc);
  s.b = build_right_hand_side(hg, bc, assembler.gravity_vector(Vec3(0, 0, -9.81)));
  s.assembly_seconds = seconds_since(t0);
  s.mesh = std::move(mesh);
  std::vector<double> times;
  DenseLu lu;
  for (int r = 0; r < lu_repeats; ++r) {
    const auto t = Clock::now();
    lu.compute(s.A);
    s.x_lu = lu.solve(s.b);
    times.push_back(seconds_since(t));
  }
  s.lu_seconds = median(times);
  s.condition = 1.0 / lu.rcond();
  return s;
}

struct Result {
  std::string scenario, library, method, preconditioner, status;
  int restart = 0, iterations = 0;
  double median_seconds = 0, min_seconds = 0, max_seconds = 0, setup_seconds = 0, true_residual = 0, error_vs_lu = 0;
  int repeats = 0;
  double ratio_vs_eigen = 0;  // 0 when there is no Eigen counterpart
};

json to_json(const Result& r) {
  return {{"scenario", r.scenario},
          {"library", r.library},
          {"method", r.method},
          {"preconditioner", r.preconditioner},
          {"restart", r.restart},
          {"status", r.status},
          {"iterations", r.iterations},
          {"median_seconds", r.median_seconds},
          {"min_seconds", r.min_seconds},
          {"max_seconds", r.max_seconds},
          {"repeats", r.repeats},
          {"setup_seconds", r.setup_seconds},
          {"true_residual", r.true_residual},
          {"error_vs_lu", r.error_vs_lu},
          {"ratio_vs_eigen", r.ratio_vs_eigen}};
}

struct Options {
  double tolerance = 1e-8;
  int max_iterations = 3000;
  int repeats = 5;
};

/// Times `solve(x)` from x0 `repeats` times; the last x gives residual and error.
template <class Solve>
void time_runs(Result& r, const System& s, const Eigen::VectorXd& x0, int repeats, Solve&& solve) {
  std::vector<double> times;
  Eigen::VectorXd x;
  for (int k = 0; k < repeats; ++k) {
    x = x0;
    const auto t = Clock::now();
    solve(x);
    times.push_back(seconds_since(t));
  }
  r.median_seconds = median(times);
  r.min_seconds = *std::min_element(times.begin(), times.end());
  r.max_seconds = *std::max_element(times.begin(), times.end());
  r.repeats = repeats;
  r.true_residual = (s.b - s.A * x).norm() / s.b.norm();
  r.error_vs_lu = (x - s.x_lu).norm() / s.x_lu.norm();
}

template <template <class, class> class Solver, class Preconditioner>
Result ours(const std::string& scenario, const std::string& method, const std::string& pname, const System& s, const Preconditioner& M,
            double setup, const Eigen::VectorXd& x0, const Options& o, int restart = 0) {
  Result r{scenario, "bemsurg", method, pname, "", restart};
  KrylovOptions ks;
  ks.tolerance = o.tolerance;
  ks.max_iterations = o.max_iterations;
  ks.restart = restart;
  const DenseOperator op(s.A);
  Solver<DenseOperator, Preconditioner> solver(ks);
  solver.compute(op, M);
  time_runs(r, s, x0, o.repeats, [&](Eigen::VectorXd& x) { solver.solve(s.b, x); });
  r.status = to_string(solver.report().status);
  r.iterations = solver.report().iterations;
  r.setup_seconds = setup;
  return r;
}

template <class EigenSolver>
Result eigen(const std::string& scenario, const std::string& method, const std::string& pname, const System& s, EigenSolver& solver,
             const Eigen::VectorXd& x0, const Options& o, int restart = 0) {
  Result r{scenario, "eigen", method, pname, "", restart};
  solver.setTolerance(o.tolerance);
  solver.setMaxIterations(o.max_iterations);
  const auto t = Clock::now();
  solver.compute(s.A);
  r.setup_seconds = seconds_since(t);
  time_runs(r, s, x0, o.repeats, [&](Eigen::VectorXd& x) { x = solver.solveWithGuess(s.b, x); });
  // Eigen says "Success" on its own residual estimate; the status here is re-judged on the true residual.
  const bool ok = solver.info() == Eigen::Success;
  r.status = ok ? (r.true_residual <= o.tolerance ? "converged" : "claimed_converged") : "no_convergence";
  r.iterations = static_cast<int>(solver.iterations());
  return r;
}

/// All methods on system s from x0 (cold: zero; warm: previous solution).
std::vector<Result> run_scenario(const std::string& scenario, const System& s, const Eigen::VectorXd& x0, const Options& o,
                                 json& preconditioner_json) {
  std::vector<Result> out;
  const IdentityPreconditioner none(s.A.rows());
  auto t = Clock::now();
  const BlockJacobiPreconditioner jacobi(s.A);
  const double jacobi_setup = seconds_since(t);
  const NearFieldPreconditioner near(s.A, s.mesh, 2.0);
  const NearFieldStatistics& st = near.statistics();
  preconditioner_json = {{"block_jacobi_build_seconds", jacobi_setup},
                         {"near_field",
                          {{"radius", st.radius},
                           {"element_pairs", st.element_pairs},
                           {"nonzeros", st.nonzeros},
                           {"density", st.density},
                           {"factor_nonzeros", st.factor_nonzeros},
                           {"fill", st.fill},
                           {"selection_seconds", st.selection_seconds},
                           {"factor_seconds", st.factor_seconds},
                           {"build_seconds", st.build_seconds}}}};
  out.push_back(ours<Gmres>(scenario, "gmres", "none", s, none, 0.0, x0, o));
  out.push_back(ours<Gmres>(scenario, "gmres", "block_jacobi", s, jacobi, jacobi_setup, x0, o));
  out.push_back(ours<Gmres>(scenario, "gmres", "near_field", s, near, st.build_seconds, x0, o));
  out.push_back(ours<Gmres>(scenario, "gmres", "none", s, none, 0.0, x0, o, 30));
  out.push_back(ours<BiCgStab>(scenario, "bicgstab", "none", s, none, 0.0, x0, o));
  out.push_back(ours<BiCgStab>(scenario, "bicgstab", "block_jacobi", s, jacobi, jacobi_setup, x0, o));
  out.push_back(ours<BiCgStab>(scenario, "bicgstab", "near_field", s, near, st.build_seconds, x0, o));
  out.push_back(ours<BiCg>(scenario, "bicg", "none", s, none, 0.0, x0, o));
  out.push_back(ours<BiCg>(scenario, "bicg", "block_jacobi", s, jacobi, jacobi_setup, x0, o));
  out.push_back(ours<BiCg>(scenario, "bicg", "near_field", s, near, st.build_seconds, x0, o));
  {
    Eigen::GMRES<Eigen::MatrixXd, Eigen::IdentityPreconditioner> g;
    g.set_restart(static_cast<int>(std::min<Index>(o.max_iterations, s.A.rows())));
    out.push_back(eigen(scenario, "gmres", "none", s, g, x0, o));
    Eigen::GMRES<Eigen::MatrixXd, Eigen::IdentityPreconditioner> g30;
    g30.set_restart(30);
    out.push_back(eigen(scenario, "gmres", "none", s, g30, x0, o, 30));
    Eigen::BiCGSTAB<Eigen::MatrixXd, Eigen::IdentityPreconditioner> bi;
    out.push_back(eigen(scenario, "bicgstab", "none", s, bi, x0, o));
    Eigen::BiCGSTAB<Eigen::MatrixXd, Eigen::DiagonalPreconditioner<double>> bd;
    out.push_back(eigen(scenario, "bicgstab", "diagonal", s, bd, x0, o));
  }
  // Ratios: ours / Eigen's, same method, preconditioner and restart.
  for (Result& r : out) {
    if (r.library != "bemsurg") continue;
    for (const Result& e : out)
      if (e.library == "eigen" && e.method == r.method && e.preconditioner == r.preconditioner && e.restart == r.restart)
        r.ratio_vs_eigen = r.median_seconds / e.median_seconds;
  }
  return out;
}

void print(const System& s, const std::vector<Result>& results) {
  std::printf("\n%s: n = %ld, cond1 ~ %s, assembly %s s, dense LU %s s (median)\n", s.name.c_str(), static_cast<long>(s.A.rows()),
              scientific_text(s.condition, 2).c_str(), fixed_text(s.assembly_seconds, 2).c_str(), fixed_text(s.lu_seconds, 4).c_str());
  std::printf("  %-5s %-8s %-9s %-13s %3s %-17s %6s %11s %10s %10s %10s %8s\n", "scen.", "library", "method", "precond.", "m", "status",
              "iters", "median [s]", "setup [s]", "true res.", "err vs LU", "ours/Eig");
  for (const Result& r : results) {
    std::printf("  %-5s %-8s %-9s %-13s %3d %-17s %6d %11s %10s %10s %10s", r.scenario.c_str(), r.library.c_str(), r.method.c_str(),
                r.preconditioner.c_str(), r.restart, r.status.c_str(), r.iterations, fixed_text(r.median_seconds, 5).c_str(),
                fixed_text(r.setup_seconds, 5).c_str(), scientific_text(r.true_residual, 2).c_str(),
                scientific_text(r.error_vs_lu, 2).c_str());
    if (r.ratio_vs_eigen > 0) std::printf(" %8s", fixed_text(r.ratio_vs_eigen, 2).c_str());
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path, csv_path;
  Options o;
  std::vector<int> equations;
  cli::OptionParser parser = bench::command_line(
      "bench_krylov", "bemsurg's Krylov solvers against Eigen's and the dense LU on BEM systems (docs/solvers.md).\n", quick, json_path);
  parser.value("--csv", "PATH", csv_path, "write one row per solve to PATH as CSV");
  parser.value("--tolerance", "T", o.tolerance, "on ||b - A x|| / ||b||").above(0.0);
  parser.value("--repeats", "R", o.repeats, "solves per figure (median; --quick: at most 3)").at_least(1);
  parser.value("--equations", "N1,N2,...", equations, "only the systems of these sizes (of 324, 1080, 1272, 1584)")
      .at_least(1)
      .default_text("all four; --quick: 324");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (quick) o.repeats = std::min(o.repeats, 3);
  // (nx, ny, nz) cells: 4 (nx ny + ny nz + nz nx) elements, 3 unknowns each.
  const std::vector<std::array<int, 3>> boxes = {{3, 3, 3}, {6, 3, 8}, {2, 8, 9}, {6, 6, 8}};  // n = 324; 1080, 1272, 1584 (Table 1)
  auto unknowns = [](const std::array<int, 3>& c) { return 12 * (c[0] * c[1] + c[1] * c[2] + c[2] * c[0]); };
  std::vector<std::array<int, 3>> sizes;
  for (const auto& c : boxes)
    if (equations.empty() ? (!quick || unknowns(c) == 324) : std::count(equations.begin(), equations.end(), unknowns(c)) > 0)
      sizes.push_back(c);
  for (int n : equations)
    if (std::none_of(boxes.begin(), boxes.end(), [&](const std::array<int, 3>& c) { return unknowns(c) == n; })) {
      std::cerr << "bench_krylov: --equations " << n << ": no such system (324, 1080, 1272, 1584)\n";
      return 2;
    }
  int threads = 1;
#ifdef _OPENMP
  threads = omp_get_max_threads();
#endif
#ifdef EIGEN_USE_BLAS
  const char* backend = "OpenBLAS gemv";
#else
  const char* backend = "Eigen gemv (OpenMP row split)";
#endif
  std::printf("bench_krylov: tolerance %s on ||b - A x|| / ||b||, %d repeats (median), %d OpenMP threads, products: %s\n",
              scientific_text(o.tolerance, 1).c_str(), o.repeats, threads, backend);
  json report = {{"benchmark", "bench_krylov"},
                 {"mode", quick ? "quick" : "full"},
                 {"tolerance", o.tolerance},
                 {"max_iterations", o.max_iterations},
                 {"repeats", o.repeats},
                 {"threads", threads},
                 {"matrix_vector_backend", backend},
                 {"systems", json::array()}};
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    use_classic_locale(csv);
    csv << "system,n,scenario,library,method,preconditioner,restart,status,iterations,median_seconds,setup_seconds,true_residual,"
           "error_vs_lu,ratio_vs_eigen,min_seconds,max_seconds,repeats\n";
  }
  try {
    for (const auto& c : sizes) {
      const System before = make_system(c[0], c[1], c[2], 0.0, o.repeats);
      const System after = make_system(c[0], c[1], c[2], 0.05, o.repeats);
      json pc_cold, pc_warm;
      std::vector<Result> results = run_scenario("cold", before, Eigen::VectorXd::Zero(before.A.rows()), o, pc_cold);
      const std::vector<Result> warm = run_scenario("warm", after, before.x_lu, o, pc_warm);
      results.insert(results.end(), warm.begin(), warm.end());
      print(before, results);
      const double change = (after.x_lu - before.x_lu).norm() / after.x_lu.norm();
      std::printf(
          "  warm: start from the solution before the push; ||x_after - x_before|| / ||x_after|| = %s; LU of the pushed system "
          "%s s\n",
          scientific_text(change, 2).c_str(), fixed_text(after.lu_seconds, 4).c_str());
      json sys = {{"name", before.name},
                  {"n", before.A.rows()},
                  {"elements", before.mesh.num_elements()},
                  {"assembly_seconds", before.assembly_seconds},
                  {"lu_seconds", before.lu_seconds},
                  {"lu_seconds_after_change", after.lu_seconds},
                  {"condition_estimate", before.condition},
                  {"warm_start_distance", change},
                  {"preconditioners", pc_cold},
                  {"runs", json::array()}};
      for (const Result& r : results) {
        sys["runs"].push_back(to_json(r));
        if (csv.is_open())
          csv << '"' << before.name << "\"," << before.A.rows() << ',' << r.scenario << ',' << r.library << ',' << r.method << ','
              << r.preconditioner << ',' << r.restart << ',' << r.status << ',' << r.iterations << ',' << r.median_seconds << ','
              << r.setup_seconds << ',' << r.true_residual << ',' << r.error_vs_lu << ',' << r.ratio_vs_eigen << ',' << r.min_seconds << ','
              << r.max_seconds << ',' << r.repeats << '\n';
      }
      report["systems"].push_back(sys);
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_krylov: " << e.what() << "\n";
    return 1;
  }
  if (!bench::write_json_file(json_path, report, "bench_krylov")) return 1;
  return 0;
}
