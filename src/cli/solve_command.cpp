// `bemsurg solve SCENE.json -o OUTDIR`: load a scene, solve the elastostatic boundary value
// problem (Wang et al. 2007 eq. 6; docs/design.md §5), evaluate interior points (eqs. 7-9) and write
// elements.csv, interior.csv, surface.vtk, solved_mesh.obj and report.json (docs/cli.md, docs/scene-format.md).
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

#include "backend_choice.hpp"
#include "bemsurg/distributed/mpi_runtime.hpp"
#include "bemsurg/distributed/scalapack_solver.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/post/interior_evaluator.hpp"
#include "bemsurg/timing.hpp"
#include "commands.hpp"
#include "on_ranks.hpp"

namespace {

constexpr const char* kSolveUsage =
    "usage: bemsurg solve SCENE.json -o OUTDIR [--quiet]\n"
    "\n"
    "Solves the scene and writes into OUTDIR (created if needed):\n"
    "  elements.csv   element,cx,cy,cz,nx,ny,nz,area,ux,uy,uz,tx,ty,tz (every element)\n"
    "  interior.csv   x,y,z,ux,uy,uz,sxx,syy,szz,sxy,syz,sxz (when the scene has interior_points)\n"
    "  corners.csv    element,corner,x,y,z,ux,uy,uz,tx,ty,tz (linear elements: the field at each corner)\n"
    "  nodes.csv      element,node,x,y,z,ux,uy,uz,tx,ty,tz (linear elements: the field at each collocation node,\n"
    "                 where the node variant of bc.csv gives prescribed values; docs/elements.md)\n"
    "  surface.vtk    the surface with displacement and traction fields\n"
    "  solved_mesh.obj  the mesh solved (after refine and remesh): the elements warnings name\n"
    "  report.json    sizes, time per phase, peak memory (per rank), solver method, iterations and residual,\n"
    "                 and the backend (dense, hmatrix with its compression, or scalapack with its process\n"
    "                 grid: docs/solvers.md, docs/distributed.md)\n"
    "\n"
    "Under mpirun the scene's method must be \"scalapack\": the ranks share A* and rank 0 writes the outputs.\n"
    "\n"
    "The scene format is described in docs/scene-format.md.\n";

struct SolveOptions {
  std::string scene;
  std::string output;
  bool quiet = false;
};

/// What each displacement rule holds (docs/scene-format.md, "boundary_rules").
void print_held_areas(const bemsurg::Scene& scene) {
  for (const bemsurg::BoundaryRuleArea& r : scene.boundary_rules)
    if (r.displacement)
      std::cout << "  " << r.key << " holds " << bemsurg::general_text(r.area, 4) << " m^2"
                << (r.has_region && r.region_area > 0.0
                        ? " of the " + bemsurg::general_text(r.region_area, 4) + " m^2 inside its region (" +
                              bemsurg::general_text(100.0 * r.area / r.region_area, 3) + " %)"
                        : std::string())
                << "\n";
}

/// The run's last lines: the solver (or the hierarchical or distributed backend), the phases and what was written.
void print_summary(const bemsurg::RunResult& report, const std::filesystem::path& out, bool interior, bool linear) {
  using namespace bemsurg;
  const LinearSolveResult& s = report.solver;
  const HierarchicalResult& h = report.hierarchical;
  if (report.backend == SolverBackend::ScaLapack)
    std::cout << std::setprecision(3) << "  scalapack: " << report.ranks << " rank(s) on a " << report.scalapack.process_rows << " x "
              << report.scalapack.process_columns << " grid, pdgetrf " << report.scalapack.factorization_seconds << " s, relative residual "
              << report.scalapack.relative_residual << "\n";
  else if (report.backend == SolverBackend::HMatrix)
    std::cout << std::setprecision(3) << "  hmatrix: " << h.compression_ratio << " of dense storage, largest rank " << h.largest_rank
              << ", assembly " << h.assembly_seconds << " s, H-LU " << h.factorization_seconds << " s, relative residual "
              << h.relative_residual << "\n";
  else
    std::cout << std::setprecision(3) << "  solver " << to_string(s.method) << " (" << to_string(s.preconditioner)
              << "): " << to_string(s.status) << ", " << s.iterations << " iterations, relative residual " << s.relative_residual << "\n";
  std::cout << std::setprecision(3) << "  time: load " << report.timings.load << " s, assembly " << report.timings.assembly << " s, system "
            << report.timings.system << " s, solve " << report.timings.solve << " s, post " << report.timings.post << " s, total "
            << report.timings.total << " s; peak memory " << report.peak_memory_mb << " MiB\n"
            << "  wrote " << (out / "elements.csv").string() << (interior ? ", " + (out / "interior.csv").string() : std::string())
            << (linear ? ", " + (out / "corners.csv").string() + ", " + (out / "nodes.csv").string() : std::string()) << ", "
            << (out / "surface.vtk").string() << ", " << (out / "report.json").string() << "\n";
}

int solve_scene(const SolveOptions& options, const bemsurg::Scene& scene, const bemsurg::MpiRuntime& mpi,
                bemsurg::SteadyClock::time_point start);

}  // namespace

int run_solve(int argc, char** argv) {
  using namespace bemsurg;
  SolveOptions options;
  cli::OptionParser parser("solve", kSolveUsage);
  parser.positional("SCENE.json", options.scene, "one scene file per run").required();
  parser.value("-o, --output", "OUTDIR", options.output, "output directory").required();
  parser.flag("-q, --quiet", options.quiet, "print nothing but warnings and errors");
  if (!parser.parse(argc, argv)) {
    std::cout << parser.help();
    return 0;
  }
  const SteadyClock::time_point start = SteadyClock::now();
  if (launcher_rank() != 0) options.quiet = true;  // rank 0 alone speaks
  const Scene scene = cli::with_chosen_backend(load_scene(options.scene), options.quiet, "bemsurg solve");
  // MPI where the method needs it or mpirun started this process (docs/distributed.md).
  const bool distributed = scene.solver.backend == SolverBackend::ScaLapack;
  const MpiRuntime mpi(distributed);
  if (!mpi.root()) options.quiet = true;
  return cli::run_on_ranks(mpi, [&] { return solve_scene(options, scene, mpi, start); });
}

namespace {

// long: the command's steps in the order a user sees them (warnings, outputs folder, the solve on
// its backend, interior points, files, report); each is a few lines, and rank 0 alone does the last ones.
int solve_scene(const SolveOptions& options, const bemsurg::Scene& scene, const bemsurg::MpiRuntime& mpi,
                bemsurg::SteadyClock::time_point start) {
  using namespace bemsurg;
  const bool distributed = scene.solver.backend == SolverBackend::ScaLapack;
  if (mpi.size() > 1 && !distributed)
    throw SolverError(std::string("bemsurg solve runs on ") + std::to_string(mpi.size()) +
                      " ranks (mpirun) only with \"method\": " + "\"scalapack\"; this scene's solver is " +
                      (scene.solver.backend == SolverBackend::HMatrix ? "hmatrix" : to_string(scene.solver.method)) +
                      " (run it without mpirun, or set solver.method to scalapack: docs/distributed.md)");
  if (mpi.root())
    for (const std::string& w : scene.warnings) std::cerr << "bemsurg: warning: " << options.scene << ": " << w << "\n";
  const SteadyClock::time_point loaded = SteadyClock::now();

  // Create the output directory before the (possibly long) solve, so a bad path fails at once.
  // Rank 0 writes every output (the others may run on nodes that do not share its file system).
  namespace fs = std::filesystem;
  if (mpi.root()) {
    std::error_code ec;
    fs::create_directories(options.output, ec);
    if (ec || !fs::is_directory(options.output))
      throw IoError("cannot create the output directory '" + options.output +
                    "': " + (ec ? ec.message() : std::string("a file of that name exists")));
    // The mesh solved, before the solve: the element numbers of every warning refer to it.
    write_obj((fs::path(options.output) / "solved_mesh.obj").string(), scene.problem.mesh);
  }

  const bool hierarchical = scene.solver.backend == SolverBackend::HMatrix;
  if (!options.quiet)
    std::cout << "bemsurg solve: " << scene.problem.mesh.num_elements() << " " << to_string(scene.problem.elements) << " elements, "
              << 3 * nodes_per_element(scene.problem.elements) * scene.problem.mesh.num_elements() << " equations, mesh "
              << scene.mesh_source << ", solver "
              << (hierarchical  ? std::string("hmatrix (compression tolerance ") + number_text(scene.solver.compression_tolerance) + ")"
                  : distributed ? "scalapack on " + std::to_string(mpi.size()) + " rank(s)"
                                : std::string(to_string(scene.solver.method)))
              << std::endl;
  if (!options.quiet) print_held_areas(scene);

  // The dense backend (the reference), the hierarchical one (docs/solvers.md, "Hierarchical matrices")
  // or the dense LU split over the ranks (docs/distributed.md).
  HierarchicalResult backend;
  ScalapackResult split;
  const ElastostaticSolution solution = hierarchical  ? solve_elastostatic_hierarchical(scene.problem, scene.solver, &backend)
                                        : distributed ? solve_elastostatic_scalapack(mpi, scene.problem, &split)
                                                      : solve_elastostatic(scene.problem, scene.solver);
  const std::vector<double> peaks = mpi.gather(peak_memory_mb());  // every rank's peak, before rank 0's post-processing
  if (!mpi.root()) return 0;
  // A warning the scene gave at load already (slivers: "mesh: " + the same text) is not repeated.
  std::vector<std::string> solve_warnings;
  for (const std::string& w : solution.report.warnings)
    if (std::find(scene.warnings.begin(), scene.warnings.end(), "mesh: " + w) == scene.warnings.end()) solve_warnings.push_back(w);
  for (const std::string& w : solve_warnings) std::cerr << "bemsurg: warning: " << options.scene << ": " << w << "\n";
  const SteadyClock::time_point solved = SteadyClock::now();

  const fs::path out(options.output);
  const bool linear = scene.problem.elements == ElementType::Linear;
  if (scene.has_interior_points) {  // Somigliana with the linear field for linear elements (per-node values)
    const InteriorEvaluator evaluator(scene.problem.mesh, scene.problem.material, scene.problem.gravity, scene.problem.quadrature);
    const BoundarySolution& field = linear ? solution.nodes : solution.boundary;
    const RowMatrixX3d u = evaluator.displacement(scene.interior_points, field);
    const StressRows s = evaluator.stress(scene.interior_points, field);
    write_interior_csv((out / "interior.csv").string(), scene.interior_points, u, s);
  }
  write_elements_csv((out / "elements.csv").string(), scene.problem.mesh, solution.boundary);
  if (linear) {
    write_corners_csv((out / "corners.csv").string(), scene.problem.mesh, solution.nodes);
    write_nodes_csv((out / "nodes.csv").string(), scene.problem.mesh, solution.nodes);
    write_linear_solution_vtk((out / "surface.vtk").string(), scene.problem.mesh, solution.boundary, solution.nodes);
  } else {
    write_solution_vtk((out / "surface.vtk").string(), scene.problem.mesh, solution.boundary);
  }
  const SteadyClock::time_point finished = SteadyClock::now();

  RunResult report;
  report.scene = options.scene;
  report.element_type = to_string(scene.problem.elements);
  report.mesh_source = scene.mesh_source;
  report.elements = solution.report.elements;
  report.equations = solution.report.equations;
  report.interior_points = scene.interior_points.rows();
  report.timings.load = seconds_between(start, loaded);
  report.timings.assembly = solution.report.assembly_seconds;
  report.timings.system = solution.report.system_seconds;
  report.timings.solve = solution.report.solver.setup_seconds + solution.report.solver.solve_seconds;
  report.timings.post = seconds_between(solved, finished);
  report.timings.total = seconds_between(start, finished);
  report.peak_memory_mb = peak_memory_mb();
  report.solver = solution.report.solver;
  report.backend = scene.solver.backend;
  report.backend_automatic = scene.solver.automatic_backend;
  report.hierarchical = backend;
  report.scalapack = split;
  report.ranks = mpi.size();
  report.peak_memory_mb_per_rank = peaks;
  report.peak_memory_mb_per_rank[0] = report.peak_memory_mb;  // rank 0's, after its post-processing
  report.boundary_rules = scene.boundary_rules;
  report.warnings = scene.warnings;
  report.warnings.insert(report.warnings.end(), solve_warnings.begin(), solve_warnings.end());
  write_report_json((out / "report.json").string(), report);

  if (!options.quiet) print_summary(report, out, scene.has_interior_points, linear);
  return 0;
}

}  // namespace
