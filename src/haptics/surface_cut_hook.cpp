// Implementation of bemsurg/haptics/surface_cut_hook.hpp: a session's cuts through the one cut entry
// point, CutSystemUpdate (cutting/cut_system_update.hpp), so they meet the rules `bemsurg cut` and the
// viewer meet.
#include "bemsurg/haptics/surface_cut_hook.hpp"

#include <memory>
#include <new>
#include <string>

#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/error.hpp"

namespace bemsurg::haptics {

namespace {
struct SurfaceCutState {
  std::unique_ptr<CutSystemUpdate> system;
  std::shared_ptr<const GreensTable> returned;  // the table the last step handed to the session
  int action = -1;

  /// The cut entry point on `table`: a table the hook did not hand out (the session's first, or
  /// another session's) gets a new one.
  void cut_from(const std::shared_ptr<const GreensTable>& table) {
    if (system && table == returned) return;
    system.reset();  // joins a refactorisation still running for the old table
    // Refactorisations run inside the step: the hook already runs on the session's simulation side,
    // whose single thread leaves the haptic loop its core, and a session's trace stays deterministic.
    CutSystemOptions options;
    options.background_refactor = false;
    system = std::make_unique<CutSystemUpdate>(table, options);
    returned = table;
    action = -1;
  }
};
}  // namespace

CutHook surface_cut_hook() { return surface_cuts().hook; }

SurfaceCuts surface_cuts() {
  auto state = std::make_shared<SurfaceCutState>();
  SurfaceCuts cuts;
  cuts.prepare = [state](const std::shared_ptr<const GreensTable>& table) {
    if (!table || !table->has_factorization()) return;  // the first step will say why it cannot cut
    state->cut_from(table);
    try {
      state->system->reserve_snapshot_buffers();
    } catch (const std::bad_alloc&) {
      // Reserving only saves time: without the memory the steps allocate their tables as they go
      // (and say so, as a ResourceError, if even that fails).
    }
  };
  cuts.hook = [state](const CutRequest& r) -> CutResult {
    state->cut_from(r.table);
    if (state->action != r.action) {  // a new cut action opens a new groove
      state->system->begin_cut();
      state->action = r.action;
    }
    const auto refused = [&r](const std::string& reason) {
      return ContactError("cut action " + std::to_string(r.action) + ", step " + std::to_string(r.step + 1) + " refused: " + reason);
    };
    if (r.reach > 0.0) {  // two phases: the first response now, the complete table when the session asks
      std::shared_ptr<const GreensTable> first;
      const CutStepResult step = state->system->cut_first(r.from, r.direction, r.tools, r.reach, first);
      if (!step.accepted) throw refused(step.reason);
      auto complete = [state] {
        state->system->complete_step();
        state->returned = state->system->table();
        return state->returned;
      };
      return {first->mesh(), first, complete};
    }
    const CutStepResult step = state->system->cut(r.from, r.direction, CutUpdateMethod::Exact);
    if (!step.accepted) throw refused(step.reason);
    state->returned = state->system->table();
    return {state->returned->mesh(), state->returned, {}};
  };
  return cuts;
}

}  // namespace bemsurg::haptics
