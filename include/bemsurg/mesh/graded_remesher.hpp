// bemsurg/mesh/graded_remesher.hpp: a closed surface remeshed finely in an operating region and
// graded smoothly into a coarse remainder (Wang et al. 2007 §6; docs/graded.md, docs/design.md §6).
//
// The target element size is h(x) = min(h_out, h_in + (growth - 1) d(x)), d the distance to the
// region (mesh/operating_region.hpp): h_in inside, and growing by the factor `growth` per element
// outward, so neighbouring elements differ in size by about that factor, until h_out. The
// surface is resampled by Gmsh (its discrete-surface reparametrisation, classifySurfaces /
// createGeometry, and the Frontal-Delaunay 2-D mesher with this size function); docs/graded.md
// says why Gmsh and not CGAL, with measurements. Creases sharper than `feature_angle_degrees`
// (box edges, the brain's rim on its support) are kept as mesh edges.
//
// Compiled in src/mesh/graded_remesher.cpp, and only with BEMSURG_WITH_REMESHER (on when CMake
// finds libgmsh): graded_remesher_available() says whether this build has it; without it
// graded_remesh throws bemsurg::Error saying so. Everything else of bemsurg works either way.
#pragma once

#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/operating_region.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Target sizes of graded_remesh: the edge length inside the operating region and far from it, the size growth per
/// element between them, and the dihedral angle above which an input edge is kept as a crease.
struct GradedRemeshOptions {
  /// Target edge length inside the operating region and far from it (m); 0 < inside <= outside.
  double inside_edge_length = 0.0;
  double outside_edge_length = 0.0;
  /// Size growth per element away from the region (> 1, at most 2): the neighbouring size ratio
  /// the grading aims at. The measured ratio is a little larger (docs/graded.md).
  double growth = 1.25;
  /// Dihedral angle (degrees) above which an edge of the input is a crease to keep.
  double feature_angle_degrees = 40.0;
};

/// What graded_remesh returns: the remeshed and validated surface, its quality figures and the time taken (seconds).
struct GradedRemeshResult {
  TriangleMesh mesh;
  MeshQuality quality;
  double seconds = 0.0;
};

/// Whether this build of bemsurg includes the remesher (BEMSURG_WITH_REMESHER).
bool graded_remesher_available();

/// Remeshes `input` (closed, manifold, outward-oriented: require_valid_mesh must accept it; every
/// shell is remeshed) with the size function above. The result is closed, 2-manifold, oriented
/// like the input and validated (require_valid_mesh) before it is returned.
/// Throws InvalidMeshError for an invalid (e.g. open) input, InvalidArgumentError for target
/// lengths that are not positive and finite, an inside length larger than the outside one, a
/// growth outside (1, 2], or a region that does not meet the surface, and bemsurg::Error when
/// this build has no remesher or Gmsh fails.
GradedRemeshResult graded_remesh(const TriangleMesh& input, const OperatingRegion& region, const GradedRemeshOptions& options);

/// The size function used: h(x) for a point x (exposed for tests and reports).
double graded_target_size(const OperatingRegion& region, const GradedRemeshOptions& options, const Vec3& x);

}  // namespace bemsurg
