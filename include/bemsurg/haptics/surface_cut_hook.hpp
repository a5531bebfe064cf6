// bemsurg/haptics/surface_cut_hook.hpp: the cutting module as a session's CutHook (docs/design.md
// §7, docs/haptics.md "Sessions"): `bemsurg session`, the viewer-free benchmarks and the tests cut
// through the same entry point as `bemsurg cut` and the viewer (CutSystemUpdate).
#pragma once

#include "bemsurg/haptics/session.hpp"

namespace bemsurg::haptics {

/// Cuts through one CutSystemUpdate on the session's table: each cut action opens a new groove (its first
/// step) and later steps extend it along the action's direction, under the one set of cut rules (locking,
/// conditions, region, refactorisation: cutting/cut_system_update.hpp), each step an exact table update.
/// The hook is called for one step at a time (from the simulation side or its background thread, never
/// concurrently); a refused step throws ContactError naming the action's step and the reason.
CutHook surface_cut_hook();

/// surface_cut_hook's cuts and what makes them ready: `prepare` sets up the hook's cut entry point on the
/// session's table and touches the storage of its first steps' tables (CutSystemUpdate::reserve_snapshot_buffers),
/// so that the first steps cost what later ones do (SessionOptions::cut_prepare).
/// \ingroup haptics
struct SurfaceCuts {
  CutHook hook;
  CutPrepare prepare;
};
SurfaceCuts surface_cuts();

}  // namespace bemsurg::haptics
