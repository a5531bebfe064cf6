// The CGAL steps of mesh preparation (mesh/mesh_preparation.hpp), behind plain Eigen types so that
// only src/meshing/cgal_repair.cpp includes CGAL (it costs ~35 s to compile). Internal to bemsurg.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg::detail {

/// Whether this build compiled the CGAL steps (BEMSURG_HAVE_CGAL).
bool cgal_repair_available();

/// A triangle soup (no repeated corner in a face) oriented and closed where it can be: faces that
/// share an edge made to agree (CGAL's orient_polygon_soup, which copies a vertex or edge where
/// separate fans meet, so the result is manifold), then holes whose boundary loop is shorter than
/// max_hole_length filled (triangulate_and_refine_hole). Faces 0..F-1 are the input's, in order.
struct OrientedClosedSoup {
  TriangleMesh mesh;
  std::vector<char> reversed;     // per input face: its corner order was reversed
  Index duplicated_vertices = 0;  // copies made where separate fans met (non-manifold places)
  Index holes = 0, filled = 0;    // boundary loops found after orienting, and those filled
  Index unfilled = 0;             // holes longer than max_hole_length, left open
  double longest_unfilled = 0.0;  // boundary length of the longest of those (0: none)
  Index failed = 0;               // short holes that no triangulation could close, left open
};
OrientedClosedSoup cgal_orient_and_close(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, double max_hole_length);

/// CGAL's 3-D alpha wrap of any triangle soup: watertight, 2-manifold, outward, at distance
/// `offset` outside the input, closing details narrower than `alpha`.
TriangleMesh cgal_alpha_wrap(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, double alpha, double offset);

/// The distance from each of `points` to the triangle soup (vertices, faces), by an AABB tree.
Eigen::VectorXd cgal_distances(const RowMatrixX3d& points, const RowMatrixX3d& vertices, const RowMatrixX3i& faces);

/// For each of `points`, whether it lies inside the closed surface `mesh` (CGAL's
/// Side_of_triangle_mesh: ray casting on an AABB tree; a point on the surface counts as inside).
std::vector<char> cgal_inside(const RowMatrixX3d& points, const TriangleMesh& mesh);

}  // namespace bemsurg::detail
