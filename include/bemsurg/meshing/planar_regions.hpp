// bemsurg/meshing/planar_regions.hpp: the flat faces of a surface (a resection plane, a flat cut,
// the brain's underside, a box's sides) found as groups of coplanar triangles, so a remesh can
// keep each one flat up to its rim (docs/graded.md, "What a remesh keeps").
//
// A dihedral-angle test cannot find such a rim where the input's triangles meet the plane at a
// shallow angle: a faceted round body cut by a plane (an icosphere, the brain model) has many
// triangles along the rim that rise only a few degrees from the face, so Gmsh's crease
// detection merges the face with its sides and rounds the rim off. Coplanarity is a property of
// the triangles on the face, not of the angles at its rim, and finds the whole face wherever its
// rim runs. The groups are grown across edges from the largest triangles: a neighbour joins when
// its three corners lie within `distance_tolerance` of the seed's plane and it faces the same way.
// Only groups of at least `min_area_fraction` of the surface's area count as planes, so a
// triangle or two that happen to be coplanar on a curved surface are not.
#pragma once

#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Thresholds of find_planar_regions.
/// \ingroup meshing
struct PlanarRegionOptions {
  /// Largest distance of a corner from the plane, as a fraction of the bounding-box diagonal:
  /// loose enough for coordinates rounded to single precision (STL), tight enough that a curved
  /// surface's neighbouring triangles (their sagitta is ~ edge^2 / radius) are not coplanar.
  double distance_tolerance = 1e-6;
  /// Smallest area of a planar region, as a fraction of the surface's total area.
  double min_area_fraction = 0.01;
};

/// One flat face of a surface: its triangles and the plane n . x = offset they lie on, with n the
/// area-weighted mean of their unit normals (pointing out of the material) and offset the
/// area-weighted mean of n . centroid.
/// \ingroup meshing
struct PlanarRegion {
  Vec3 normal = Vec3::UnitZ();
  double offset = 0.0;
  double area = 0.0;
  std::vector<Index> faces;

  /// Signed distance of x from the plane (positive on the side the normal points to).
  double signed_distance(const Vec3& x) const { return normal.dot(x) - offset; }
  /// The point of the plane nearest to x.
  Vec3 project(const Vec3& x) const { return x - signed_distance(x) * normal; }
};

/// The planar regions of `mesh`, largest first; a face belongs to at most one. Faces of zero area
/// are never part of one.
std::vector<PlanarRegion> find_planar_regions(const TriangleMesh& mesh, const PlanarRegionOptions& options = {});

/// Moves each vertex of `vertices` that lies within `max_distance` of a region's plane, and whose
/// projection onto the plane lies within `max_distance` of one of the region's triangles of
/// `source` (the mesh the regions were found on), onto that plane; with `min_cos` above -1, only
/// the vertices whose faces (rows of `faces` indexing `vertices`) all face the region's way
/// (unit normal . region normal >= min_cos), so a face turned sideways is never flattened over.
/// Returns how many vertices moved. Puts a remeshed or rewrapped surface back onto the input's
/// flat faces; with `max_distance` well below the element size no triangle turns over.
Index snap_to_planar_regions(RowMatrixX3d& vertices, const RowMatrixX3i& faces, const TriangleMesh& source,
                             const std::vector<PlanarRegion>& regions, double max_distance, double min_cos = -1.0);

}  // namespace bemsurg
