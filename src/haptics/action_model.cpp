// The action-script model (bemsurg/haptics/action_script.hpp): names of the enums and the script's
// small queries. Compiled into bemsurg::haptics, which plays scripts in sessions; the JSON reader
// (src/io/action_script.cpp) is in bemsurg::bemsurg, so a device program links no JSON code.
#include <algorithm>
#include <string>

#include "bemsurg/haptics/action_script.hpp"

namespace bemsurg {

const char* to_string(ScriptToolShape shape) {
  switch (shape) {
    case ScriptToolShape::Point: return "point";
    case ScriptToolShape::Flat: return "flat";
    case ScriptToolShape::Sphere: return "sphere";
    case ScriptToolShape::Pinch: return "pinch";
    case ScriptToolShape::Plate: return "plate";
    case ScriptToolShape::Blade: return "blade";
  }
  return "?";
}

const char* to_string(ActionType type) {
  switch (type) {
    case ActionType::Move: return "move";
    case ActionType::Press: return "press";
    case ActionType::Pinch: return "pinch";
    case ActionType::Release: return "release";
    case ActionType::Retract: return "retract";
    case ActionType::Cut: return "cut";
  }
  return "?";
}

double Action::end_time() const {
  if (type == ActionType::Cut) return time + (steps - 1) * step_interval;
  return time + duration;
}

int ActionScript::tool_index(const std::string& name) const {
  for (std::size_t i = 0; i < tools.size(); ++i)
    if (tools[i].name == name) return static_cast<int>(i);
  return -1;
}

bool ActionScript::has_cuts() const {
  return std::any_of(actions.begin(), actions.end(), [](const Action& a) { return a.type == ActionType::Cut; });
}

}  // namespace bemsurg
