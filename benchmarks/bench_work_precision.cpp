// bench_work_precision: accuracy against cost (issue 24, item 2: work-precision diagrams). One
// configuration per process, so that the peak resident memory the report's driver reads from
// wait4 belongs to that configuration alone (scripts/report/parts/accuracy.py runs the list).
//   bench_work_precision --list [--quick]          the configurations, one line of arguments each
//   bench_work_precision --problem P --study S --level L --quadrature Q --solver M --tolerance T
//                        --mesh uniform --json PATH  runs one and writes its metrics
//   bench_work_precision --quick --json PATH        the smoke test: the smallest level of each problem
// Baseline of the one-factor-at-a-time studies: default QuadratureOptions, LU, uniform mesh
// (work_precision_setup.hpp). Errors: relative L2 of what was solved against the closed form, as
// verification::relative_l2_errors (u where traction is prescribed and t where u is).

#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/timing.hpp"
#include "bench_support.hpp"
#include "work_precision_setup.hpp"

using namespace bemsurg;
using namespace bemsurg::work_precision;

namespace {

const char* const kBaseline = "default QuadratureOptions, LU, uniform mesh";

nlohmann::json finite_or_null(double x, bool measured) { return measured && std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }

LinearSolverOptions solver_options(const Config& c) {
  LinearSolverOptions o;
  if (c.solver == "hmatrix") {  // the hierarchical backend (docs/solvers.md); the tolerance is ACA+'s
    if (!(c.tolerance >= 1e-12 && c.tolerance <= 0.1)) throw InvalidArgumentError("--tolerance: hmatrix needs one in [1e-12, 0.1]");
    o.backend = SolverBackend::HMatrix;
    o.compression_tolerance = c.tolerance;
    return o;
  }
  o.method = parse_solver_method(c.solver);
  if (o.method == SolverMethod::BiCg) throw InvalidArgumentError("--solver bicg: this benchmark compares lu, gmres and bicgstab");
  if (o.method != SolverMethod::Lu) {
    if (!(c.tolerance > 0.0 && c.tolerance < 1.0)) throw InvalidArgumentError("--tolerance: a Krylov solver needs one in (0, 1)");
    o.tolerance = c.tolerance;
    o.preconditioner = PreconditionerKind::BlockJacobi;  // the default, said here: the report names it
  }
  return o;
}

// The timings of repeated solves of one problem (the machines are shared: bench_support.hpp) and
// the last solution. Up to `max_repeats` solves, stopping once 10 s have been spent, so the large
// levels run once and the small ones give medians. A solve that throws SolverError (a Krylov
// method stopping short) ends the repeats with status "failed" and no solution.
struct Repeated {
  std::optional<ElastostaticSolution> solution;
  std::string status;
  std::vector<double> assembly, factor, solve, total;
};

Repeated solve_repeated(const ElastostaticProblem& p, const LinearSolverOptions& options, int max_repeats) {
  Repeated out;
  const SteadyClock::time_point first = SteadyClock::now();
  while (static_cast<int>(out.total.size()) < max_repeats && (out.total.empty() || seconds_since(first) < 10.0)) {
    const SteadyClock::time_point start = SteadyClock::now();
    try {
      out.solution =
          options.backend == SolverBackend::HMatrix ? solve_elastostatic_hierarchical(p, options) : solve_elastostatic(p, options);
    } catch (const SolverError& e) {
      out.solution.reset();
      out.status = "failed";
      std::cerr << "bench_work_precision: " << e.what() << "\n";
      return out;
    }
    out.total.push_back(seconds_since(start));
    const ElastostaticResult& r = out.solution->report;
    out.assembly.push_back(r.assembly_seconds + r.system_seconds);
    out.factor.push_back(r.solver.setup_seconds);
    out.solve.push_back(r.solver.solve_seconds);
    out.status = to_string(r.solver.status);
  }
  return out;
}

// Runs one configuration and returns its JSON object (parameters and metrics). A Krylov solve
// that stops short throws SolverError from solve_elastostatic; it is recorded with its status
// and no errors, so the list still completes and the chart shows what converged.
nlohmann::json run_config(const Config& c, int max_repeats) {
  const Material m{1.0, 0.3, 1.0};
  const Setup s = make_setup(c, m);
  const auto prescribed = [&](Index e) { return s.displacement_prescribed_at(s.mesh.centroid(e)); };
  ElastostaticProblem p{s.mesh, m, s.gravity, verification::exact_trace_conditions(s.mesh, s.field, prescribed),
                        quadrature_setting(c.quadrature)};
  p.elements = parse_element_type(c.element_type);
  const bool linear = p.elements == ElementType::Linear;
  // Exact values at each type's collocation points (docs/elements.md); errors measured there.
  const BoundarySolution exact = linear ? verification::exact_node_traces(s.mesh, s.field) : verification::exact_traces(s.mesh, s.field);
  if (linear) {
    if (c.feed != "nodes" && c.feed != "corners") throw InvalidArgumentError("--feed: expected nodes or corners, got '" + c.feed + "'");
    p.node_values.resize(exact.displacement.rows(), 3);
    for (Index e = 0; e < s.mesh.num_elements(); ++e) {
      // The prescribed rows of element e: the exact field at its nodes, or at its corners (the
      // traction with the element's own normal) interpolated to the nodes as the solver does with
      // bc.csv's corner form.
      Eigen::Matrix3d given;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d x = c.feed == "nodes" ? Eigen::Vector3d(collocation_node<LinearElement>(s.mesh.corners(e), k))
                                                    : Eigen::Vector3d(s.mesh.vertex(s.mesh.faces()(e, k)));
        const Eigen::Vector3d u = s.field.displacement(x), t = s.field.stress(x) * s.mesh.normal(e);
        for (int d = 0; d < 3; ++d) given(k, d) = p.boundary_conditions.kind(3 * e + d) == BcKind::Displacement ? u(d) : t(d);
      }
      p.node_values.middleRows<3>(3 * e) = c.feed == "nodes" ? given : linear_corners_to_nodes(given);
    }
  }
  const LinearSolverOptions options = solver_options(c);
  nlohmann::json j = {{"problem", c.problem},
                      {"study", c.study},
                      {"level", c.level},
                      {"quadrature", c.quadrature},
                      {"solver", c.solver},
                      {"tolerance", c.tolerance},
                      {"mesh", c.mesh},
                      {"element_type", c.element_type},
                      {"baseline", kBaseline},
                      {"preconditioner", c.solver == "lu" || c.solver == "hmatrix" ? "none" : "block_jacobi"},
                      {"feed", linear ? c.feed : std::string()}};
  j["elements"] = s.mesh.num_elements();
  j["equations"] = 3 * nodes_per_element(p.elements) * s.mesh.num_elements();
  j["mean_h"] = s.mesh.diameters().mean();
  const Repeated run = solve_repeated(p, options, max_repeats);
  if (run.solution) {
    const ElastostaticResult& r = run.solution->report;
    const auto all = [](Index) { return true; };
    const verification::RelativeErrors err =
        linear ? verification::node_relative_l2_errors(p.mesh, p.boundary_conditions, run.solution->nodes, exact, all)
               : verification::relative_l2_errors(p.mesh, p.boundary_conditions, run.solution->boundary, exact);
    // An error is measured where some element has that quantity unknown (both problems here do).
    bool any_u = false, any_t = false;
    for (Index e = 0; e < s.mesh.num_elements(); ++e) (prescribed(e) ? any_t : any_u) = true;
    j["error_u"] = finite_or_null(err.displacement, any_u);
    j["error_t"] = finite_or_null(err.traction, any_t);
    j["assembly_s"] = bench::median(run.assembly);  // H, G, gravity, and the column swap into A*
    j["factor_s"] = bench::median(run.factor);
    j["solve_s"] = bench::median(run.solve);
    j["iterations"] = r.solver.iterations;
    j["relative_residual"] = r.solver.relative_residual;
  }
  j["total_s"] = bench::median(run.total);  // the wall time of solve_elastostatic
  j["repeats"] = run.total.size();
  j["status"] = run.status;
  j["peak_hwm_bytes"] = peak_memory_mb() * 1048576.0;  // this process's own peak (VmHWM)
  std::cerr << arguments(c) << ": " << s.mesh.num_elements() << " elements, " << run.status << ", u "
            << j.value("error_u", nlohmann::json()).dump() << ", t " << j.value("error_t", nlohmann::json()).dump() << ", "
            << fixed_text(bench::median(run.total), 3) << " s (median of " << run.total.size() << ")\n";
  return j;
}

bool errors_finite(const nlohmann::json& run) {
  for (const char* k : {"error_u", "error_t"})
    if (!run.contains(k) || !(run[k].is_null() || std::isfinite(run[k].get<double>()))) return false;
  return run.value("status", "") == "converged" && !(run["error_u"].is_null() && run["error_t"].is_null());
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, list = false;
  int repeats = 3;
  std::string json_path;
  Config c;
  c.level = 0;
  cli::OptionParser parser =
      bench::command_line("bench_work_precision",
                          "Accuracy against cost of the BEM on closed-form problems, one configuration per process (issue 24, item 2).\n"
                          "--list prints the configurations (one line of arguments each); --problem ... runs one; --quick alone runs the\n"
                          "smallest level of every problem (the smoke test).\n",
                          quick, json_path);
  parser.flag("--list", list, "print the configurations, one per line, and exit (with --quick: the quick ones)");
  parser.value("--problem", "NAME", c.problem, "lame, kelvin or bar");
  parser.value("--study", "NAME", c.study, "levels, quadrature or solver (a label the report groups by)");
  parser.value("--level", "L", c.level, "mesh level, from 1");
  parser.value("--quadrature", "NAME", c.quadrature, "cheap, baseline or fine");
  parser.value("--solver", "NAME", c.solver, "lu, gmres or bicgstab (block-Jacobi preconditioned), or hmatrix");
  parser.value("--tolerance", "T", c.tolerance, "Krylov relative residual, or hmatrix's compression tolerance (0 for lu)");
  parser.value("--mesh", "KIND", c.mesh, "uniform");
  parser.value("--element_type", "TYPE", c.element_type, "constant or linear (docs/elements.md)");
  parser.value("--feed", "WHERE", c.feed, "linear elements: the data given at the nodes or at the corners");
  parser.value("--repeats", "N", repeats, "solve up to N times (stopping after 10 s) and report median times");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (repeats < 1) {
    std::cerr << "bench_work_precision: --repeats: expected a number >= 1, got " << repeats << "\n";
    return 2;
  }
  try {
    if (list) {
      for (const Config& k : all_configs(quick)) std::cout << arguments(k) << "\n";
      return 0;
    }
    nlohmann::json result;
    if (c.problem.empty()) {
      // The smoke test: the smallest level of each problem, all finite or exit 1.
      result = {{"benchmark", "bench_work_precision"}, {"quick", quick}, {"baseline", kBaseline}, {"runs", nlohmann::json::array()}};
      bool ok = true;
      for (const char* p : {"lame", "kelvin", "bar"}) {
        Config k;
        k.problem = p;
        result["runs"].push_back(run_config(k, 1));  // one solve each: seconds under ASan too
        ok = ok && errors_finite(result["runs"].back());
      }
      if (!bench::write_json_file(json_path, result, "bench_work_precision")) return 1;
      if (!ok) std::cerr << "bench_work_precision: a run did not converge or gave a non-finite error\n";
      return ok ? 0 : 1;
    }
    if (c.level == 0) c.level = 1;
    result = run_config(c, repeats);
    result["benchmark"] = "bench_work_precision";
    return bench::write_json_file(json_path, result, "bench_work_precision") ? 0 : 1;
  } catch (const Error& e) {
    std::cerr << "bench_work_precision: " << e.what() << "\n";
    return 2;
  }
}
