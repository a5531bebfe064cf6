// src/haptics/session_text.hpp: what session.cpp and session_cuts.cpp share: how a message names an
// action, and a polygon's centroid (private to the haptics sources).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "bemsurg/haptics/action_script.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg::haptics::detail {

/// "PATH: the press of tool 'probe' at t = 0.5 s": the action at fault, for messages.
inline std::string describe(const ActionScript& s, const Action& a) {
  return s.path + ": the " + to_string(a.type) + " of tool '" + s.tools[static_cast<std::size_t>(a.tool)].name +
         "' at t = " + number_text(a.time) + " s";
}

/// The mean of a polygon's vertices.
inline Eigen::Vector3d centroid(const std::vector<Eigen::Vector3d>& poly) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (const auto& p : poly) c += p;
  return c / double(poly.size());
}

}  // namespace bemsurg::haptics::detail
