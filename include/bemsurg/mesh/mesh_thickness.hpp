// bemsurg/mesh/mesh_thickness.hpp: parts of a body thinner than its elements (docs/design.md §2).
//
// Constant elements collocate at centroids; where the body is thinner than its elements the two
// faces of a thin part see each other at less than an element's size, the near-singular
// integrals are resolved but the piecewise-constant field cannot represent what happens across
// the part: displacements of a thin plate meshed with elements much larger than its thickness
// came out 1e6 too large. Such a mesh is legal, so it is warned about, not refused.
#pragma once

#include <cstddef>
#include <string>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Elements larger than the body is thick under them: size sqrt(2 area) (the grid spacing of a
/// box-grid triangle) above the local thickness, the distance from the centroid along the inward
/// normal to the next face. `count` such elements; `element` is the one with the largest
/// size / thickness, with its size and thickness (-1, 0, 0 when count is 0).
/// \ingroup mesh
struct ThinElements {
  std::size_t count = 0;
  Index element = -1;
  double size = 0.0;
  double thickness = 0.0;
};

/// Casts one ray per element into the material (TriangleBvh, O(E log E)). Elements whose ray
/// leaves through no face (an open surface) are skipped.
ThinElements find_thin_elements(const TriangleMesh& mesh);

/// Element sizes across a part's thickness below which its bending stiffness is more than 10 %
/// off (constant elements make a bent plate too stiff: 40 % at 4 sizes, 10-fold at 1; a part
/// compressed through its thickness stays exact even at 0.1). Measured by bench_stability (g),
/// docs/stability.md. find_thin_elements flags only parts thinner than one element size (where
/// the error is ten-fold and more); the warning's text quotes this figure for accuracy.
constexpr double kBendingAccurateThicknessPerElement = 7.0;

/// The warning for a mesh with thin elements (empty when thin.count is 0): the count, the worst
/// element with its size and thickness, and the refinement that makes the part reliable.
std::string thin_elements_warning(const ThinElements& thin);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/mesh_thickness_impl.hpp"
#endif
