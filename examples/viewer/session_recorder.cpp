// examples/viewer/session_recorder.cpp: the mouse session as an action script (see
// session_recorder.hpp).
#include "session_recorder.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>

namespace bemsurg::viewer {

std::string SessionRecorder::tool_name(int slot, ToolKind k, double radius) {
  const std::string name =
      "tool" + std::to_string(slot + 1) + "-" + tool_kind_name(k) + "-" + std::to_string(static_cast<long>(std::lround(radius * 1e5)));
  for (const auto& t : tools)
    if (t["name"] == name) return name;
  nlohmann::json t = {{"name", name}, {"shape", tool_kind_name(k)}, {"device", slot}};
  if (radius > 0.0) t["radius"] = radius;
  tools.push_back(t);
  return name;
}

bool SessionRecorder::save(const std::string& path, const std::string& scene, std::string& error) const {
  nlohmann::json root = {{"format", "bemsurg-actions"}, {"version", 1}, {"tools", tools}, {"actions", actions}};
  if (!scene.empty()) root["scene"] = scene;
  std::ofstream out(path);
  if (!out) {
    error = "cannot write " + path;
    return false;
  }
  out << std::setw(2) << root << "\n";
  return true;
}

nlohmann::json vec_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace bemsurg::viewer
