// Implementation of bemsurg/haptics/surface_cut_hook.hpp: a session's cuts through the one cut entry
// point, CutSystemUpdate (cutting/cut_system_update.hpp), so they meet the rules `bemsurg cut` and the
// viewer meet.
#include "bemsurg/haptics/surface_cut_hook.hpp"

#include <memory>
#include <string>

#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/error.hpp"

namespace bemsurg::haptics {

CutHook surface_cut_hook() {
  struct State {
    std::unique_ptr<CutSystemUpdate> system;
    std::shared_ptr<const GreensTable> returned;  // the table the last step handed to the session
    int action = -1;
  };
  auto state = std::make_shared<State>();
  return [state](const CutRequest& r) -> CutResult {
    // A table the hook did not hand out (the session's first, or another session's): cut from it.
    if (!state->system || r.table != state->returned) {
      state->system.reset();  // joins a refactorisation still running for the old table
      // Refactorisations run inside the step: the hook already runs on the session's simulation side,
      // whose single thread leaves the haptic loop its core, and a session's trace stays deterministic.
      CutSystemOptions options;
      options.background_refactor = false;
      state->system = std::make_unique<CutSystemUpdate>(r.table, options);
      state->action = -1;
    }
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
}

}  // namespace bemsurg::haptics
