// bemsurg/io/results_io.hpp: what `bemsurg solve` writes (docs/scene-format.md, "Outputs"):
// elements.csv (per element geometry with prescribed and solved boundary values, docs/design.md §2 and
// §5), interior.csv (Somigliana displacement and stress at interior points, Wang et al. 2007 eqs.
// 7-9), surface.vtk (the same fields for a viewer) and report.json (size, timings, memory, solver).
//
// The CSV headers are a contract other tools parse; numbers are written with 17 significant
// digits so that a value read back is the double that was computed. Every writer throws Error
// naming the path when the file cannot be written.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/distributed/scalapack_solver.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/io/boundary_rule_area.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/post/interior_evaluator.hpp"
#include "bemsurg/solvers/linear_solve.hpp"

namespace bemsurg {

/// Header of elements.csv, exactly.
inline constexpr const char* kElementsCsvHeader = "element,cx,cy,cz,nx,ny,nz,area,ux,uy,uz,tx,ty,tz";
/// Header of corners.csv (linear elements: the field at each corner of each element), exactly.
inline constexpr const char* kCornersCsvHeader = "element,corner,x,y,z,ux,uy,uz,tx,ty,tz";
/// Header of nodes.csv (linear elements: the field at each collocation node of each element), exactly.
inline constexpr const char* kNodesCsvHeader = "element,node,x,y,z,ux,uy,uz,tx,ty,tz";
/// Header of interior.csv, exactly.
inline constexpr const char* kInteriorCsvHeader = "x,y,z,ux,uy,uz,sxx,syy,szz,sxy,syz,sxz";

/// One row per element in mesh order: index, centroid, unit outward normal, area, displacement,
/// traction.
void write_elements_csv(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& solution);

/// Linear elements (docs/elements.md): one row per element and corner (0-2, the face's vertex order):
/// the corner's position and the element's linear field there (extrapolated from the three nodes,
/// linear_nodes_to_corners). `nodes` is the per-node solution (3E rows, ElastostaticSolution::nodes).
void write_corners_csv(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& nodes);

/// Linear elements: one row per element and collocation node (0-2, docs/elements.md): the node's
/// position and the solved field there, as collocated. A user samples prescribed data at these
/// positions for the node variant of bc.csv (docs/scene-format.md).
void write_nodes_csv(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& nodes);

/// One row per point: position, displacement, stress (sxx, syy, szz, sxy, syz, sxz).
void write_interior_csv(const std::string& path, const RowMatrixX3d& points, const RowMatrixX3d& displacement, const StressRows& stress);

/// Legacy VTK surface with cell fields "displacement" and "traction" and the point field
/// "displacement" (area-weighted vertex average, TriangleMesh::element_to_vertex).
void write_solution_vtk(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& solution);

/// Linear elements: the surface with unshared points (three per element, the corners), point fields
/// "displacement" and "traction" holding the linear field at each element's corners (a smooth colour
/// map in ParaView) and the cell fields of write_solution_vtk at the centroids.
void write_linear_solution_vtk(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& centroids,
                               const BoundarySolution& nodes);

/// Seconds per phase of a run. `total` is wall time from start to the last file written.
/// \ingroup io
struct PhaseTimings {
  double load = 0.0;      // scene, mesh, validation, boundary conditions
  double assembly = 0.0;  // H, G and gravity
  double system = 0.0;    // column swap into A* and the right-hand side
  double solve = 0.0;     // factorisation or preconditioner set-up plus the solve
  double post = 0.0;      // interior points and writing the outputs
  double total = 0.0;
};

/// What report.json records of a `bemsurg solve` run (write_report_json): scene and mesh source, sizes, phase timings,
/// peak memory and the solver summary.
/// \ingroup io
struct RunResult {
  std::string scene;
  std::string element_type = "constant";  // "constant" or "linear" (docs/elements.md)
  std::string mesh_source;
  Index elements = 0;
  Index equations = 0;
  Index interior_points = 0;
  PhaseTimings timings;
  double peak_memory_mb = 0.0;
  LinearSolveResult solver;
  SolverBackend backend = SolverBackend::Dense;  // hmatrix: `hierarchical` says what the backend did
  bool backend_automatic = false;                // chosen by "method": "auto" (report.json backend.chosen_by)
  HierarchicalResult hierarchical;
  ScalapackResult scalapack;  // backend scalapack: the grid and the slowest rank's phases
  /// Ranks of the run (1 outside mpirun) and each rank's peak resident memory in MiB, in rank order
  /// (empty: one rank, peak_memory_mb).
  int ranks = 1;
  std::vector<double> peak_memory_mb_per_rank;
  std::vector<std::string> warnings;             // the scene's and the solve's (docs/stability.md), in that order
  std::vector<BoundaryRuleArea> boundary_rules;  // what each rule held (Scene::boundary_rules)
};
/// Deprecated name (before 0.2), kept one minor version: use RunResult.
using RunReport [[deprecated("renamed to RunResult in bemsurg 0.2")]] = RunResult;

/// Peak resident memory of this process so far, in MiB: VmHWM of /proc/self/status (this image's
/// own, not its parent's), getrusage's ru_maxrss where /proc is not there.
double peak_memory_mb();

/// report.json: {"element_type", "elements", "equations", "interior_points", "timings": {load, assembly, system,
/// solve, post, total}, "peak_memory_mb", "ranks", "peak_memory_mb_per_rank": [MiB per rank], "solver": {method, preconditioner, iterations, status,
/// relative_residual, setup_seconds, solve_seconds}, "backend": {"name": "dense", "chosen_by"} or {"name": "hmatrix", "chosen_by",
/// "compression_tolerance", "compression_ratio", "largest_rank", "stored_entries", "dense_entries",
/// "leaves_full", "leaves_low_rank", "column_scale", "assembly_seconds", "factorization_seconds",
/// "solve_seconds"} or {"name": "scalapack", "chosen_by", "process_grid": [rows, columns], "block_size", "local_rows",
/// "local_columns", "assembly_seconds", "factorization_seconds", "solve_seconds", "gather_seconds"}, "boundary_rules": [{"rule", "area", "region_area" (where the
/// selectors describe a region), "conform", "refine_rim"}, ...], "warnings": [text, ...], "scene", "mesh", "bemsurg_version"}.
void write_report_json(const std::string& path, const RunResult& report);

}  // namespace bemsurg
