// bench_hmatrix: the hierarchical backend against the dense one (issue 40, item 5; docs/solvers.md,
// "Hierarchical matrices"; the report's "Hierarchical matrices" part). A cube of soft tissue resting
// on its bottom face under gravity, N x N cells per face (12 N^2 constant elements), solved at each
// size by both backends in the same process: hierarchical first (solve_elastostatic_hierarchical at
// --tolerance), then dense LU (the reference): wall time of each whole solve (assembly, factorisation,
// solve), each one's own peak resident memory (the kernel's high-water mark reset before it:
// /proc/self/clear_refs, "5"), the compression and the hierarchical answer's difference from the
// dense one; then the same series with linear elements (--linear-divisions; 9 unknowns per element,
// so the sizes are smaller). Then, at --sweep-divisions, the hierarchical solve at each of --sweep-tolerances: stored
// fraction and added error against the tolerance. Then the cut study (docs/cutting.md, "On either
// backend"): at each of --cut-divisions, a table kept for cuts (region: the top face within 0.3 edges
// of its centre) on each backend and --cut-steps exact cut steps along x across the top, from a quarter
// of the way in: the precompute's and each step's wall time, the factors' memory and the two final
// tables' difference.
//
//   bench_hmatrix [--quick] [--json PATH] [--divisions N,N,...] [--linear-divisions N,N,...] [--tolerance T]
//                 [--sweep-divisions N] [--sweep-tolerances T,T,...] [--cut-divisions N,N,...] [--cut-steps K]
//
// The JSON's "crossover_elements" is where the hierarchical solve's time falls below the dense
// one's (log-log interpolation between the sizes on either side; null when it does not within the
// sizes run), "memory_crossover_elements" the same for peak memory, "time_exponent" the least-squares
// slope of log time against log n per backend; "linear_..." the same for linear elements. Built without hmat-oss it says so and writes
// "available": false.

#include <malloc.h>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/hierarchical_table.hpp"
#include "bench_support.hpp"

using namespace bemsurg;

namespace {

constexpr double kEdge = 0.1;  // m: the cube's edge
constexpr double kYoung = 3000.0, kPoisson = 0.45, kDensity = 1000.0, kGravity = 9.81;

ElastostaticProblem resting_cube(int divisions, ElementType type = ElementType::Constant) {
  ElastostaticProblem p;
  p.elements = type;
  p.mesh = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(kEdge, kEdge, kEdge), divisions, divisions, divisions);
  p.material = Material{kYoung, kPoisson, kDensity};
  p.gravity = Eigen::Vector3d(0.0, 0.0, -kGravity);
  p.boundary_conditions = BoundaryConditions(p.mesh.num_elements());
  for (Index e = 0; e < p.mesh.num_elements(); ++e)
    if (p.mesh.centroid(e).z() < 1e-9) p.boundary_conditions.prescribe_displacement(e, Eigen::Vector3d::Zero());
  return p;
}

/// Resets the kernel's peak-RSS mark of this process (Linux >= 4.0); false when it cannot. The mark
/// can only fall to what is resident, so the heap's free pages go back to the system first
/// (malloc_trim): otherwise a small solve after a large one reads the memory the large one left
/// cached in the allocator (the linear series after the constant one read 826 MB at every size).
bool reset_peak_memory() {
  malloc_trim(0);
  std::ofstream f("/proc/self/clear_refs");
  f << "5";
  return static_cast<bool>(f);
}

struct Timed {
  ElastostaticSolution solution;
  double seconds = 0.0, peak_mb = 0.0;
};

Timed timed_solve(const ElastostaticProblem& p, bool hierarchical, double tolerance, HierarchicalResult* r) {
  reset_peak_memory();
  const auto t0 = bench::Clock::now();
  Timed out;
  if (hierarchical) {
    LinearSolverOptions o;
    o.backend = SolverBackend::HMatrix;
    o.compression_tolerance = tolerance;
    out.solution = solve_elastostatic_hierarchical(p, o, r);
  } else {
    out.solution = solve_elastostatic(p, LinearSolverOptions{});
  }
  out.seconds = seconds_since(t0);
  out.peak_mb = peak_memory_mb();
  return out;
}

double relative_max(const RowMatrixX3d& a, const RowMatrixX3d& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
}

/// Where log(h / d) crosses zero between consecutive sizes, interpolated in log(elements); null if never.
nlohmann::json crossover(const std::vector<double>& elements, const std::vector<double>& h, const std::vector<double>& d) {
  for (std::size_t i = 0; i + 1 < elements.size(); ++i) {
    const double a = std::log(h[i] / d[i]), b = std::log(h[i + 1] / d[i + 1]);
    if (a > 0.0 && b <= 0.0) {
      const double s = a / (a - b);
      return std::exp(std::log(elements[i]) + s * (std::log(elements[i + 1]) - std::log(elements[i])));
    }
  }
  if (!elements.empty() && h.front() <= d.front()) return elements.front();  // faster already at the smallest size
  return nullptr;
}

double fit_exponent(const std::vector<double>& n, const std::vector<double>& t) {
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < n.size(); ++i) mx += std::log(n[i]), my += std::log(t[i]);
  mx /= double(n.size());
  my /= double(n.size());
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < n.size(); ++i) {
    sxy += (std::log(n[i]) - mx) * (std::log(t[i]) - my);
    sxx += (std::log(n[i]) - mx) * (std::log(n[i]) - mx);
  }
  return sxx > 0.0 ? sxy / sxx : 0.0;
}

/// The size series of one element type: both backends per size, in the same process, hierarchical
/// first; the rows, the fitted time exponents (against n) and the interpolated crossovers.
nlohmann::json size_series(const std::vector<int>& sizes, ElementType type, double tolerance) {
  std::vector<double> elements, th, td, mh, md, nh;
  nlohmann::json rows = nlohmann::json::array();
  for (const int N : sizes) {
    const ElastostaticProblem p = resting_cube(N, type);
    HierarchicalResult r;
    const Timed h = timed_solve(p, true, tolerance, &r);
    const Timed d = timed_solve(p, false, tolerance, nullptr);
    const double du = relative_max(h.solution.boundary.displacement, d.solution.boundary.displacement);
    const double dt = relative_max(h.solution.boundary.traction, d.solution.boundary.traction);
    const double E = double(p.mesh.num_elements());
    const Index n = 3 * nodes_per_element(type) * p.mesh.num_elements();
    elements.push_back(E);
    nh.push_back(double(n));
    th.push_back(h.seconds);
    td.push_back(d.seconds);
    mh.push_back(h.peak_mb);
    md.push_back(d.peak_mb);
    rows.push_back({{"divisions", N},
                    {"element_type", to_string(type)},
                    {"elements", p.mesh.num_elements()},
                    {"equations", n},
                    {"dense_seconds", d.seconds},
                    {"hierarchical_seconds", h.seconds},
                    {"time_ratio", h.seconds / d.seconds},
                    {"dense_peak_mb", d.peak_mb},
                    {"hierarchical_peak_mb", h.peak_mb},
                    {"memory_ratio", h.peak_mb / d.peak_mb},
                    {"compression_ratio", r.compression_ratio},
                    {"largest_rank", r.largest_rank},
                    {"hierarchical_assembly_seconds", r.assembly_seconds},
                    {"hierarchical_factorization_seconds", r.factorization_seconds},
                    {"displacement_difference", du},
                    {"traction_difference", dt}});
    std::cout << "bench_hmatrix: " << p.mesh.num_elements() << " " << to_string(type) << " elements (n = " << n
              << "): hierarchical / dense time " << fixed_text(h.seconds, 2) << " / " << fixed_text(d.seconds, 2) << " s ("
              << fixed_text(h.seconds / d.seconds, 2) << "), peak memory " << fixed_text(h.peak_mb, 0) << " / " << fixed_text(d.peak_mb, 0)
              << " MB, stored " << fixed_text(r.compression_ratio, 3) << " of dense, displacement " << number_text(du) << " off"
              << std::endl;
  }
  nlohmann::json out;
  out["rows"] = rows;
  if (elements.size() >= 2) out["time_exponent"] = {{"dense", fit_exponent(nh, td)}, {"hierarchical", fit_exponent(nh, th)}};
  out["crossover_elements"] = crossover(elements, th, td);
  out["memory_crossover_elements"] = crossover(elements, mh, md);
  return out;
}

/// One backend's table of `p` for cuts (region: `region`) and `steps` exact cut steps across the top
/// face: the precompute's and each step's wall time, and the final table.
struct CutRun {
  double precompute_seconds = 0.0, factor_mb = 0.0;
  std::vector<double> step_seconds;
  std::shared_ptr<const GreensTable> table;
};

CutRun run_cuts(const ElastostaticProblem& p, const std::vector<Index>& region, bool hierarchical, double tolerance, int steps) {
  CutRun out;
  const auto t0 = bench::Clock::now();
  if (hierarchical) {
    LinearSolverOptions o;
    o.backend = SolverBackend::HMatrix;
    o.compression_tolerance = tolerance;
    out.table = std::make_shared<const GreensTable>(compute_greens_table_hierarchical(p, region, o, nullptr, true));
  } else {
    out.table = std::make_shared<const GreensTable>(GreensTable::compute(p, region));
  }
  out.precompute_seconds = seconds_since(t0);
  out.factor_mb = double(out.table->solver()->base()->bytes()) / 1048576.0;
  CutSystemOptions so;
  so.background_refactor = false;  // a refactorisation (none within these steps) would land inside a step
  CutSystemUpdate system(out.table, so);
  system.begin_cut({});
  for (int i = 0; i < steps; ++i) {
    const auto ts = bench::Clock::now();
    const CutStepResult r =
        system.cut(Eigen::Vector3d(0.25 * kEdge, 0.5 * kEdge, kEdge + 0.005), Eigen::Vector3d::UnitX(), CutUpdateMethod::Exact);
    if (!r.accepted) throw std::runtime_error("bench_hmatrix: cut step " + std::to_string(i + 1) + " refused: " + r.reason);
    out.step_seconds.push_back(seconds_since(ts));
  }
  out.table = system.table();
  return out;
}

/// The cut study: at each size, the same cut steps on a table kept for cuts on either backend.
nlohmann::json cut_study(const std::vector<int>& sizes, double tolerance, int steps) {
  nlohmann::json rows = nlohmann::json::array();
  for (const int N : sizes) {
    const ElastostaticProblem p = resting_cube(N);
    std::vector<Index> region;  // the top face within 0.3 edges of its centre: where the blade and a probe act
    for (Index e = 0; e < p.mesh.num_elements(); ++e) {
      const Eigen::Vector3d c = p.mesh.centroid(e);
      if (c.z() > kEdge - 1e-9 && std::hypot(c.x() - 0.5 * kEdge, c.y() - 0.5 * kEdge) < 0.3 * kEdge) region.push_back(e);
    }
    const CutRun h = run_cuts(p, region, true, tolerance, steps);
    const CutRun d = run_cuts(p, region, false, tolerance, steps);
    const auto relative = [](const auto& a, const auto& b) { return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff(); };
    const double columns = relative(h.table->columns(), d.table->columns());
    const double base = relative(h.table->base_displacement(), d.table->base_displacement());
    const double sh = bench::median(h.step_seconds), sd = bench::median(d.step_seconds);
    rows.push_back({{"divisions", N},
                    {"elements", p.mesh.num_elements()},
                    {"equations", 3 * p.mesh.num_elements()},
                    {"region_elements", region.size()},
                    {"steps", steps},
                    {"elements_after", h.table->num_elements()},
                    {"dense_step_seconds", d.step_seconds},
                    {"hierarchical_step_seconds", h.step_seconds},
                    {"dense_step_median_seconds", sd},
                    {"hierarchical_step_median_seconds", sh},
                    {"step_time_ratio", sh / sd},
                    {"dense_precompute_seconds", d.precompute_seconds},
                    {"hierarchical_precompute_seconds", h.precompute_seconds},
                    {"dense_factor_mb", d.factor_mb},
                    {"hierarchical_factor_mb", h.factor_mb},
                    {"final_rank", h.table->solver()->rank()},
                    {"columns_difference", columns},
                    {"base_displacement_difference", base}});
    std::cout << "bench_hmatrix: cuts at " << p.mesh.num_elements() << " elements (region " << region.size()
              << "): step median hierarchical / dense " << fixed_text(sh, 3) << " / " << fixed_text(sd, 3) << " s ("
              << fixed_text(sh / sd, 2) << "), factors " << fixed_text(h.factor_mb, 0) << " / " << fixed_text(d.factor_mb, 0)
              << " MB, after " << steps << " steps columns " << number_text(columns) << " and base state " << number_text(base) << " off"
              << std::endl;
  }
  return rows;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path;
  std::vector<int> sizes;
  std::vector<double> tolerances;
  double tolerance = 1e-4;
  int sweep_divisions = 0, cut_steps = 4;
  std::vector<int> cut_sizes, linear_sizes;
  auto parser = bench::command_line("bench_hmatrix", "The hierarchical backend against dense LU: time, memory, compression, error.\n",
                                    quick, json_path);
  parser.value("--divisions", "N,N,...", sizes, "cells per cube edge at each size (12 N^2 elements)")
      .at_least(2)
      .default_text("6,9,13,18,22; --quick: 4,8");
  parser.value("--linear-divisions", "N,N,...", linear_sizes, "the linear-element series (12 N^2 elements, 9 unknowns each)")
      .at_least(2)
      .default_text("4,6,8,11; --quick: 3,5");
  parser.value("--tolerance", "T", tolerance, "ACA+'s compression tolerance of the size series").between(1e-12, 0.1);
  parser.value("--sweep-divisions", "N", sweep_divisions, "the size of the tolerance sweep").default_text("13; --quick: 6");
  parser.value("--sweep-tolerances", "T,T,...", tolerances, "the tolerances of the sweep")
      .between(1e-12, 0.1)
      .default_text("1e-2 ... 1e-8 by decades; --quick: 1e-2,1e-4,1e-6");
  parser.value("--cut-divisions", "N,N,...", cut_sizes, "sizes of the cut study (tables kept for cuts on both backends)")
      .at_least(2)
      .default_text("9,13,18; --quick: 8");
  parser.value("--cut-steps", "K", cut_steps, "exact cut steps per size and backend").between(1, 20);
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (cut_sizes.empty()) cut_sizes = quick ? std::vector<int>{8} : std::vector<int>{9, 13, 18};
  if (linear_sizes.empty()) linear_sizes = quick ? std::vector<int>{3, 5} : std::vector<int>{4, 6, 8, 11};
  if (sizes.empty()) sizes = quick ? std::vector<int>{4, 8} : std::vector<int>{6, 9, 13, 18, 22};
  if (tolerances.empty())
    tolerances = quick ? std::vector<double>{1e-2, 1e-4, 1e-6} : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8};
  if (sweep_divisions <= 0) sweep_divisions = quick ? 6 : 13;

  nlohmann::json result;
  result["benchmark"] = "bench_hmatrix";
  result["quick"] = quick;
  result["body"] = "cube of edge 0.1 m resting on its bottom face under gravity (E 3 kPa, nu 0.45, rho 1000 kg/m^3)";
  result["available"] = hierarchical_backend_available();
  if (!hierarchical_backend_available()) {
    std::cout << "bench_hmatrix: built without hmat-oss (libhmat-oss-dev): nothing to measure\n";
    return bench::write_json_file(json_path, result, "bench_hmatrix") ? 0 : 1;
  }
  result["tolerance"] = tolerance;
  result["peak_memory_resets"] = reset_peak_memory();
  const nlohmann::json constant = size_series(sizes, ElementType::Constant, tolerance);
  result["sizes"] = constant["rows"];
  if (constant.contains("time_exponent")) result["time_exponent"] = constant["time_exponent"];
  result["crossover_elements"] = constant["crossover_elements"];
  result["memory_crossover_elements"] = constant["memory_crossover_elements"];
  // Linear elements (9 unknowns each): where their crossover lies, for method auto's threshold.
  const nlohmann::json linear = size_series(linear_sizes, ElementType::Linear, tolerance);
  result["linear_sizes"] = linear["rows"];
  if (linear.contains("time_exponent")) result["linear_time_exponent"] = linear["time_exponent"];
  result["linear_crossover_elements"] = linear["crossover_elements"];
  result["linear_memory_crossover_elements"] = linear["memory_crossover_elements"];

  // The tolerance sweep at one size: the dense answer once, then each tolerance.
  const ElastostaticProblem p = resting_cube(sweep_divisions);
  const ElastostaticSolution dense = solve_elastostatic(p, LinearSolverOptions{});
  nlohmann::json sweep = nlohmann::json::array();
  for (const double t : tolerances) {
    HierarchicalResult r;
    const Timed h = timed_solve(p, true, t, &r);
    const double du = relative_max(h.solution.boundary.displacement, dense.boundary.displacement);
    sweep.push_back({{"tolerance", t},
                     {"compression_ratio", r.compression_ratio},
                     {"largest_rank", r.largest_rank},
                     {"seconds", h.seconds},
                     {"displacement_difference", du},
                     {"traction_difference", relative_max(h.solution.boundary.traction, dense.boundary.traction)},
                     {"relative_residual", r.relative_residual}});
    std::cout << "bench_hmatrix: sweep at " << p.mesh.num_elements() << " elements: tolerance " << number_text(t) << ": stored "
              << fixed_text(r.compression_ratio, 3) << ", displacement " << number_text(du) << " off, " << fixed_text(h.seconds, 2) << " s"
              << std::endl;
  }
  result["sweep"] = {{"divisions", sweep_divisions}, {"elements", p.mesh.num_elements()}, {"rows", sweep}};
  result["cuts"] = cut_study(cut_sizes, tolerance, cut_steps);
  return bench::write_json_file(json_path, result, "bench_hmatrix") ? 0 : 1;
}
