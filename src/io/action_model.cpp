// The action-script model (bemsurg/io/action_script.hpp) without its JSON reader: names of the
// enums and the script's small queries. Kept apart from action_script.cpp so that the haptics
// adapter (bemsurg::haptics), which plays scripts in sessions, links no JSON code: this file is
// compiled into bemsurg::numerics, the reader into bemsurg::bemsurg (CMakeLists.txt).
#include <algorithm>
#include <string>

#include "bemsurg/io/action_script.hpp"

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
