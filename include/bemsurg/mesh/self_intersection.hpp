// bemsurg/mesh/self_intersection.hpp: does a triangle surface cut through itself (docs/design.md §2)?
//
// A BEM boundary that crosses itself encloses no well-defined body: the system is solvable but
// the answer belongs to no physical object, and no topological check (closed, manifold, oriented)
// sees it. A cut (docs/design.md §7) can cause exactly that: a wall pushed through a thin part,
// or through another cut's wall. find_self_intersections reports every pair of faces that meet
// anywhere except where the mesh's connectivity says they should:
//   - faces sharing an edge meet only along it; they intersect if they fold onto each other
//     (the third vertex of one lies in the other's plane, on the same side of the shared edge);
//   - faces sharing one vertex meet only at it; they intersect if the edge opposite the shared
//     vertex of either one touches the other triangle;
//   - other faces must not touch at all (within the tolerance).
// Candidate pairs come from the picking hierarchy (mesh/bvh.hpp): each face queries the faces
// whose boxes overlap its own, O(F log F) for a surface whose faces are of similar size.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Touching tolerance and pair limit of find_self_intersections.
/// \ingroup mesh
struct SelfIntersectionOptions {
  /// Distance below which two triangles count as touching, as a fraction of the bounding-box
  /// diagonal (closed-surface meshes in double precision are far from it).
  double tolerance = 1e-10;
  /// Stop after this many pairs (0: report all). Validation only needs the first few.
  std::size_t max_pairs = 0;
};

/// Face pairs (first < second), ascending, that intersect improperly. Empty for a clean surface.
std::vector<std::pair<Index, Index>> find_self_intersections(const TriangleMesh& mesh, const SelfIntersectionOptions& options = {});

/// The same, restricted to pairs in which at least one face is in `faces` (for instance the
/// faces a cut step changed or added, the rest having been checked before).
std::vector<std::pair<Index, Index>> find_self_intersections(const TriangleMesh& mesh, const std::vector<Index>& faces,
                                                             const SelfIntersectionOptions& options = {});

/// Whether faces f and g of the mesh intersect improperly (the pair test the search uses).
bool faces_intersect(const TriangleMesh& mesh, Index f, Index g, double tolerance);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/self_intersection_impl.hpp"
#endif
