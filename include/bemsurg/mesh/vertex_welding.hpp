// bemsurg/mesh/vertex_welding.hpp: finding and merging coincident vertices.
//
// Two jobs need the same search: the STL reader must weld a triangle soup into an indexed,
// closed mesh, and the validator must report coincident vertices (which almost always mean an
// unwelded mesh whose "closed" surface is really a set of loose patches). Both use a hash grid
// with cells of the tolerance's size, so the search is O(V) instead of O(V^2), even for the
// many vertices that share one coordinate on a flat face.
#pragma once

#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Length of the diagonal of the axis-aligned bounding box of the finite rows of `vertices`
/// (0 for an empty or single-point set). Tolerances in the mesh module are relative to it, so
/// they do not depend on the unit of length.
double bounding_box_diagonal(const RowMatrixX3d& vertices);

/// For each vertex, the index of the vertex it coincides with: the lowest-index earlier vertex
/// within Euclidean distance `tolerance` (absolute) that is itself its own representative, or
/// the vertex itself. Clustering is greedy in index order, so chains a-b-c with |a-c| > tol are
/// not merged transitively. Non-finite vertices are never merged. tolerance = 0 merges only
/// bit-identical coordinates.
std::vector<Index> coincident_vertex_representatives(const RowMatrixX3d& vertices, double tolerance);

/// Merges coincident vertices (tolerance relative to the bounding-box diagonal), drops vertices
/// that no face uses, and renumbers the faces. Vertex order follows first use by the faces, so
/// the result does not depend on how the unused vertices were laid out. Faces that collapse
/// (two corners welded together) are kept so that validation can report them by index.
TriangleMesh weld_vertices(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, double relative_tolerance = 1e-9);

inline TriangleMesh weld_vertices(const TriangleMesh& mesh, double relative_tolerance = 1e-9) {
  return weld_vertices(mesh.vertices(), mesh.faces(), relative_tolerance);
}

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/vertex_welding_impl.hpp"
#endif
