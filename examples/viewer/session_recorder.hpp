// examples/viewer/session_recorder.hpp: a session recorded from the mouse, written as an action
// script that --script plays back (docs/viewer.md, docs/actions.md).
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>

#include "bemsurg/timing.hpp"
#include "tool_kind.hpp"

namespace bemsurg::viewer {

struct SessionRecorder {
  bool on = false;
  SteadyClock::time_point start = SteadyClock::now();
  nlohmann::json actions = nlohmann::json::array();
  nlohmann::json tools = nlohmann::json::array();
  double last_move = -1.0;  // recorder time of the last move sample

  /// Seconds since the recording started.
  double now() const { return seconds_since(start); }
  /// The script's name of the tool in `slot` (added to `tools` the first time it is used).
  std::string tool_name(int slot, ToolKind k, double radius);
  /// Writes the action script; false with `error` set when the file cannot be written.
  bool save(const std::string& path, const std::string& scene, std::string& error) const;
};

/// A point or direction as a JSON array [x, y, z].
nlohmann::json vec_json(const Eigen::Vector3d& v);

}  // namespace bemsurg::viewer
