// The sections of a scene file (docs/scene-format.md), each read by a file of its own in src/io/
// and put together by scene.cpp in the order the physics needs: mesh, operating region (which may
// remesh), boundary conditions on the mesh that is solved, quadrature, solver, interior points.
// Every reader takes the section's JsonReader (json_reader.hpp: errors are SceneErrors naming the
// key path, unknown keys become warnings of the scene). Private to the library.
#pragma once

#include <string>

#include "bemsurg/io/scene.hpp"
#include "bemsurg/meshing/graded_remesher.hpp"
#include "bemsurg/meshing/mesh_preparation.hpp"
#include "json_reader.hpp"

namespace bemsurg::io {

/// The file named by `file` (a string), resolved against the scene's directory; refuses an empty
/// name, a missing file and a directory (scene.cpp).
std::string resolve_existing(const std::string& directory, const JsonReader& file);

/// "mesh": a file (with an optional scale and translation) or a generator, validated and refined
/// where "refine" asks. `source` says where the mesh came from, for reports (scene_mesh.cpp). The
/// size and thin-part checks of the mesh solved come later (scene.cpp), after any graded remesh.
/// `graded_inside_edge` > 0 when the scene's operating region will grade the mesh (its inside edge
/// length): a "prepare" section then repairs without remeshing. `prepare_default`: a "prepare"
/// section's target when it gives none (MeshPreparationOptions::default_elements).
TriangleMesh load_mesh(const JsonReader& mesh, const std::string& directory, std::string& source, double graded_inside_edge = 0.0,
                       Index prepare_default = kDefaultPreparedElements);

/// "mesh.prepare": the raw mesh file repaired and remeshed by prepare_mesh (scene_prepare.cpp);
/// its warnings become the scene's, at the key's path.
/// `outer_scale`: the mesh section has its own "scale" (then no millimetre warning);
/// `default_elements`: the target when the section gives none.
TriangleMesh prepare_in_scene(const JsonReader& prepare, const TriangleMesh& raw, double graded_inside_edge, bool outer_scale,
                              Index default_elements, std::string& source);

/// "material", "solver", "quadrature" (scene_settings.cpp).
Material load_material(const JsonReader& material, bool gravity_on);
LinearSolverOptions load_solver(const JsonReader& solver);
QuadratureOptions load_quadrature(const JsonReader& quadrature);

/// What load_boundary_conditions returns.
struct LoadedBoundaryConditions {
  BoundaryConditions conditions;
  /// The value at every corner (3E x 3, row 3e + c for corner c in the face's vertex order), or
  /// at every linear node when the file is the node variant, which `at_nodes` then says.
  RowMatrixX3d corner_values;
  bool at_nodes = false;
  /// report.json's "boundary_rules", one per rule in scene order.
  std::vector<BoundaryRuleArea> rules;
  /// When "conform" or "refine_rim" split the mesh: each solved element's element of the mesh given.
  std::vector<Index> origin;
  /// With `origin`: the size each element counts with in the safe-grading rule (Scene::element_grading_size).
  std::vector<double> grading_size;
  /// What the rules did to the mesh, one phrase each (for the mesh's source line).
  std::vector<std::string> mesh_changes;
  /// Things allowed but probably unintended (a conformed rule still more than 1 % off its region).
  std::vector<std::string> warnings;
};

/// "boundary_conditions": rules in order, then the CSV file, per element, per corner or per linear
/// node (docs/design.md §5, docs/elements.md; scene_boundary_conditions.cpp). Rules and rows name
/// elements of `mesh` as given; a rule's "conform" and "refine_rim" split `mesh` (replaced by the
/// mesh solved; the rules' and rows' elements carry over to the pieces). The values are the
/// elements' (at the centroids, the mean of the corners' or nodes'). `as_read` is the mesh before
/// any remesh, on which the rules' regions are measured ("region_area"); `elements`, the scene's
/// element type, decides how far "refine_rim" spreads and whether it refines the whole surface first
/// (constant elements; scene_rule_meshing.cpp).
LoadedBoundaryConditions load_boundary_conditions(const JsonReader& conditions, const std::string& directory, TriangleMesh& mesh,
                                                  const TriangleMesh& as_read, ElementType elements);

/// "interior_points": inline points, then the CSV file's; each strictly inside the body and far
/// enough from the surface for the quadrature (scene_interior_points.cpp).
RowMatrixX3d load_interior_points(const JsonReader& points, const std::string& directory, const TriangleMesh& mesh,
                                  const QuadratureOptions& quadrature);

/// "operating_region" as read and checked against the mesh as generated or read: the region and,
/// when inside and outside edge lengths are given, the graded remesh it asks for (docs/graded.md).
struct OperatingRegionRequest {
  OperatingRegion region;
  bool graded = false;
  GradedRemeshOptions options;  // meaningful when graded
};

/// Reads "operating_region" (scene_operating_region.cpp). Changes nothing: the remeshing is
/// remesh_for_operating_region's.
OperatingRegionRequest parse_operating_region(const JsonReader& region, const TriangleMesh& mesh);

/// Performs what the request asks of the scene's mesh (operating_region_remesh.cpp): refuses a
/// graded mesh too large for the dense solve before Gmsh spends minutes on it, remeshes (or warns
/// when this build has no remesher), and records input_elements, graded, remesh_seconds and the
/// mesh source in `scene`. Throws SceneError at "operating_region" when remeshing fails.
void remesh_for_operating_region(const OperatingRegionRequest& request, Scene& scene);

}  // namespace bemsurg::io
