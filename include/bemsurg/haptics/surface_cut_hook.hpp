// bemsurg/haptics/surface_cut_hook.hpp: the cutting module as a session's CutHook (docs/design.md
// §7, docs/haptics.md "Sessions"): `bemsurg session`, the viewer-free benchmarks and the tests cut
// through the same code.
#pragma once

#include "bemsurg/haptics/session.hpp"

namespace bemsurg::haptics {

/// One SurfaceCutter per cut action (its first step opens the groove, later ones extend it along
/// the action's direction), elements that are not free in the table's base state locked, and the
/// exact table of the cut mesh from GreensTable::updated. The hook is called for one step at a
/// time (from the simulation side or its background thread, never concurrently); a refused step
/// throws ContactError naming the action's step and the cutter's reason.
CutHook surface_cut_hook();

}  // namespace bemsurg::haptics
