// examples/viewer/tool_kind.hpp: the tools a person picks in the viewer (and a script names, as
// shapes in docs/actions.md): prod with a point, sphere or flat tip, pinch, retract with a plate,
// cut with a blade.
#pragma once

namespace bemsurg::viewer {

enum class ToolKind { Point, Sphere, Flat, Pinch, Plate, Cut };

inline const char* tool_kind_name(ToolKind k) {
  switch (k) {
    case ToolKind::Point: return "point";
    case ToolKind::Sphere: return "sphere";
    case ToolKind::Flat: return "flat";
    case ToolKind::Pinch: return "pinch";
    case ToolKind::Plate: return "plate";
    case ToolKind::Cut: return "blade";
  }
  return "?";
}

}  // namespace bemsurg::viewer
