// bemsurg/io/scene.hpp: a scene file (JSON) read into a ready-to-solve elastostatic problem:
// mesh (file or generator), material, gravity, boundary conditions (rules and/or a CSV file),
// linear-solver settings and optional interior points. The format is specified key by key in
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

#include "bemsurg/elastostatic_solver.hpp"
#include "bemsurg/solvers/linear_solve.hpp"

namespace bemsurg {

struct Scene {
  /// Mesh (validated: closed, manifold, oriented, non-degenerate), material (validated), gravity
  /// (acceleration; body force = density * gravity), boundary conditions (every element set:
  /// unspecified elements are traction-free), quadrature options.
  ElastostaticProblem problem;
  LinearSolverSettings solver;
  /// Points at which to evaluate displacement and stress, one per row; each lies strictly inside
  /// the body (checked when loading). Empty when the scene asks for none.
  RowMatrixX3d interior_points = RowMatrixX3d(0, 3);
  bool has_interior_points = false;

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
Scene load_scene_from_string(const std::string& json_text, const std::string& directory,
                             const std::string& name = "<scene>");

}  // namespace bemsurg
