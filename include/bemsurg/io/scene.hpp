// bemsurg/io/scene.hpp: a scene file (JSON) read into a ready-to-solve elastostatic problem:
// mesh (file or generator), material, gravity, boundary conditions (rules and/or a CSV file),
// linear-solver settings, optional interior points and an optional operating region (where tools
// act: it grades the mesh and is the Green's table region, docs/graded.md). The format is specified key by key in
// docs/scene-format.md; the physics it feeds is docs/design.md §2-§5 (Wang et al. 2007, eq. 6).
//
// Every error is a SceneError whose message starts with the JSON key path or the file and line
// that is wrong, e.g. "material.poisson_ratio: expected a number, got a string" or
// "boundary_conditions.file line 17: element 999 out of range (mesh has 512 elements)", because
// a user editing a scene by hand must be able to go straight to the mistake.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/io/boundary_rule_area.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/operating_region.hpp"
#include "bemsurg/solvers/linear_solve.hpp"

namespace bemsurg {

/// A scene file read into a ready-to-solve problem (docs/scene-format.md): the elastostatic problem, solver settings,
/// optional interior points and operating region, and what loading did (grading, mesh source, warnings).
/// \ingroup io
struct Scene {
  /// Mesh (validated: closed, manifold, oriented, non-degenerate), material (validated), gravity
  /// (acceleration; body force = density * gravity), boundary conditions (every element set:
  /// unspecified elements are traction-free), quadrature options.
  ElastostaticProblem problem;
  LinearSolverOptions solver;
  /// Points at which to evaluate displacement and stress, one per row; each lies strictly inside
  /// the body (checked when loading). Empty when the scene asks for none.
  RowMatrixX3d interior_points = RowMatrixX3d(0, 3);
  bool has_interior_points = false;

  /// The "operating_region" key, said once for both of its uses (docs/graded.md): when it gives
  /// inside/outside edge lengths the mesh above is the graded remesh of the generated or read
  /// surface, and `operating_elements` are the free elements of that mesh inside the region, in
  /// increasing order: pass them as GreensTableOptions::region so pre-solutions are computed only
  /// where tools may act. Without the key: has_operating_region false, operating_elements empty
  /// (a Green's table then covers every free element).
  bool has_operating_region = false;
  OperatingRegion operating_region;
  std::vector<Index> operating_elements;
  /// Whether the mesh was remeshed (graded), with its quality and the remeshing time.
  bool graded = false;
  MeshQuality mesh_quality;
  double remesh_seconds = 0.0;
  /// Elements of the mesh before remeshing (equal to the mesh's count when not graded).
  Index input_elements = 0;
  /// One entry per boundary rule, in scene order.
  std::vector<BoundaryRuleArea> boundary_rules;
  /// Where rules split or refined the mesh ("conform", "refine_rim"): for every solved element,
  /// the element of the mesh the rules and the CSV file refer to (the mesh after any remesh, before
  /// the rules' splits). Empty when no rule changed the mesh.
  std::vector<Index> element_origin;
  /// The size (mean edge length) each solved element counts with in the safe-grading rule: its
  /// own, or for a piece of a conforming split or a linear rim band the size of the element it was
  /// cut from. Empty when every element counts with its own (no rule changed the mesh, or only
  /// constant elements' refine_rim did).
  std::vector<double> element_grading_size;

  /// The scene file as given and the directory relative paths in it are resolved against.
  std::string path;
  std::string directory;
  /// Where the mesh came from, for reports: a file path or a generator description.
  std::string mesh_source;
  /// Things that are allowed but probably unintended (unknown keys). The CLI prints them.
  std::vector<std::string> warnings;
};

/// Reads and checks the scene file at `path`. Throws SceneError (see the header comment) for a file
/// that cannot be read, is not JSON, or holds a missing key, a value of the wrong type or range, an
/// unreadable or invalid mesh, an invalid material, a bad boundary-condition rule or CSV row, or an
/// interior point outside the body. The support check (rigid-body modes) is left to
/// solve_elastostatic, which throws BoundaryConditionError naming the free motions.
Scene load_scene(const std::string& path);

/// The same from JSON text already in memory; relative paths resolve against `directory`.
/// `name` is used in messages in place of a file name.
Scene load_scene_from_string(const std::string& json_text, const std::string& directory, const std::string& name = "<scene>");

/// Throws SceneError naming the scene, its "elements" key and `command` (e.g. "bemsurg press") unless the
/// scene uses constant elements: contact tables, cutting, the haptic session and the viewer do not
/// support linear elements yet (docs/elements.md). A refusal, never a silent fallback. Returns the
/// scene, so a loader's line can check in place: `Scene s = require_constant_elements(load_scene(p), "...")`.
const Scene& require_constant_elements(const Scene& scene, const std::string& command);
/// The same for a scene just loaded (moved through, not copied).
Scene require_constant_elements(Scene&& scene, const std::string& command);

/// The scene at `path` with its "mesh" replaced by the mesh file `mesh_file` (any format
/// mesh_io.hpp reads), solved as it is (an operating region's remesh keys are dropped, its shape
/// kept): what the scene's rules prescribe on another surface, such as the mesh a
Scene load_scene_with_mesh(const std::string& path, const std::string& mesh_file);

}  // namespace bemsurg
