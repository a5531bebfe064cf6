// bemsurg/mesh/mesh_delta.hpp: what one change of the surface (a cut step) did to the elements,
// with stable element ids (docs/design.md §7 and §9).
//
// The contract between the topology (cutting/) and everything that holds per-element state (the
// system matrix, the Green's table, the contact operator, boundary conditions):
//   - elements [0, elements_before) keep their id. Those not listed in `modified` are unchanged
//     bit for bit (same three vertex positions), so their rows and columns of H and G between
//     each other are unchanged;
//   - `modified` (ascending, each < elements_before): same id, new geometry; they keep their
//     boundary condition;
//   - `added` (ascending, exactly elements_before .. elements_after-1): appended; new cut surface,
//     traction-free unless the scene says otherwise;
//   - `removed`: a gap cut never needs it (a split triangle keeps one piece under its old id), so
//     the topology never emits it; it exists so that a future remesher can retire ids. Updates
//     refuse a delta with removed elements (InvalidArgumentError) rather than guess.
// Vertices may be added (appended) and existing vertices may move; a moved vertex makes every
// face that uses it `modified`.
#pragma once
#include <vector>
#include "bemsurg/types.hpp"

namespace bemsurg {

/// What one change of the surface (a cut step) did to the elements, with stable element ids: counts before and after,
/// and the added, modified and removed elements, under the contract written at the top of mesh/mesh_delta.hpp.
/// \ingroup mesh
struct MeshDelta {
  Index elements_before = 0;
  Index elements_after = 0;
  std::vector<Index> added;
  std::vector<Index> modified;
  std::vector<Index> removed;

  bool empty() const { return added.empty() && modified.empty() && removed.empty(); }
  /// Elements whose rows and columns must be integrated anew.
  std::vector<Index> changed() const {
    std::vector<Index> out = modified;
    out.insert(out.end(), added.begin(), added.end());
    return out;
  }
};

}  // namespace bemsurg
