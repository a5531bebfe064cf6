// Implementation of bemsurg/haptics/surface_cut_hook.hpp.
#include "bemsurg/haptics/surface_cut_hook.hpp"

#include <memory>
#include <string>
#include <vector>

#include "bemsurg/cutting/surface_cutter.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/presolution/greens_table.hpp"

namespace bemsurg::haptics {

CutHook surface_cut_hook() {
  struct State {
    std::unique_ptr<SurfaceCutter> cutter;
    int action = -1;
  };
  auto state = std::make_shared<State>();
  return [state](const CutRequest& r) -> CutResult {
    if (!state->cutter || state->action != r.action || state->cutter->mesh() != r.mesh) {
      const Index E = r.mesh->num_elements();
      std::vector<char> locked(static_cast<std::size_t>(E), 0);
      for (Index e = 0; e < E; ++e) locked[static_cast<std::size_t>(e)] = r.table->is_free(e) ? 0 : 1;
      state->cutter = std::make_unique<SurfaceCutter>(r.mesh, std::move(locked));
      state->action = r.action;
    }
    const CutStep step = state->cutter->step(r.from, r.direction);
    if (!step.accepted)
      throw ContactError("cut action " + std::to_string(r.action) + ", step " + std::to_string(r.step + 1) + " refused: " + step.reason);
    std::shared_ptr<const TriangleMesh> mesh = state->cutter->mesh();
    return {mesh, r.table->updated(mesh, step.delta)};
  };
}

}  // namespace bemsurg::haptics
