// Implementation of bemsurg/cutting/surface_cutter.hpp: a groove along mesh edges (Wang et al.
// 2007 §5.3), built on a copy of the state and published only after the surface checks pass.
//
// This file holds a step's life (start, open or extend the path, split the path vertices,
// commit); the groove's triangles are built in cut_groove_impl.hpp and the checks that decide
// whether a step is published are in cut_checks_impl.hpp. SurfaceCutter::Work, the candidate
// state they all work on, is in cut_work_impl.hpp.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bemsurg/cutting/impl/cut_work_impl.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"

namespace bemsurg {

BEMSURG_INLINE SurfaceCutter::SurfaceCutter(std::shared_ptr<const TriangleMesh> mesh, std::vector<char> locked_elements, CutOptions options)
    : mesh_(std::move(mesh)), locked_(std::move(locked_elements)), options_(options) {
  if (!mesh_) throw InvalidArgumentError("SurfaceCutter: the mesh is null");
  if (locked_.empty()) locked_.assign(static_cast<std::size_t>(mesh_->num_elements()), 0);
  if (static_cast<Index>(locked_.size()) != mesh_->num_elements())
    throw InvalidArgumentError("SurfaceCutter: " + std::to_string(locked_.size()) + " lock flags for a mesh of " +
                               std::to_string(mesh_->num_elements()) + " elements");
  auto positive = [](double x) { return std::isfinite(x) && x > 0.0; };
  if (!positive(options_.gap_fraction) || !(std::isfinite(options_.gap_width) && options_.gap_width >= 0.0) ||
      !positive(options_.depth_fraction) || !(options_.min_angle_degrees >= 0.0 && options_.min_angle_degrees < 60.0) ||
      !(options_.max_normal_deviation_degrees > 0.0 && options_.max_normal_deviation_degrees <= 90.0))
    throw InvalidArgumentError(
        "SurfaceCutter: options out of range (gap_fraction > 0, gap_width >= 0, depth_fraction > 0, "
        "0 <= min_angle_degrees < 60, 0 < max_normal_deviation_degrees <= 90)");
  require_valid_mesh(*mesh_);
  cut_vertex_.assign(static_cast<std::size_t>(mesh_->num_vertices()), 0);
}

BEMSURG_INLINE std::vector<Index> SurfaceCutter::path_vertices() const {
  std::vector<Index> out;
  for (const auto& s : path_) out.push_back(s.split ? s.left.front() : s.vertex);
  return out;
}

BEMSURG_INLINE CutStep SurfaceCutter::refuse(std::string reason) const {
  CutStep out;
  out.accepted = false;
  out.reason = std::move(reason);
  out.delta.elements_before = out.delta.elements_after = mesh_->num_elements();
  return out;
}

BEMSURG_INLINE SurfaceCutter::Work SurfaceCutter::start_work() const {
  Work w;
  const TriangleMesh& m = *mesh_;
  w.V.resize(static_cast<std::size_t>(m.num_vertices()));
  for (Index v = 0; v < m.num_vertices(); ++v) w.V[static_cast<std::size_t>(v)] = m.vertex(v);
  w.F.resize(static_cast<std::size_t>(m.num_elements()));
  for (Index f = 0; f < m.num_elements(); ++f) w.F[static_cast<std::size_t>(f)] = {m.faces()(f, 0), m.faces()(f, 1), m.faces()(f, 2)};
  w.groove.assign(w.F.size(), 0);
  for (const auto& kv : groove_faces_) w.groove[static_cast<std::size_t>(kv.second)] = 1;
  w.cut_vertex = cut_vertex_;
  w.path = path_;
  w.segment_length = segment_length_;
  w.levels = levels_;
  w.groove_faces = groove_faces_;
  w.elements_before = m.num_elements();
  return w;
}

BEMSURG_INLINE CutStep SurfaceCutter::step(const Eigen::Vector3d& from, const Eigen::Vector3d& direction) {
  if (!from.allFinite() || !direction.allFinite() || direction.norm() == 0.0)
    return refuse("the tool position and direction must be finite and the direction non-zero");
  Work w = start_work();
  std::string reason;
  const bool ok = path_.empty() ? open(w, from, direction, reason) : extend(w, direction, reason);
  if (!ok) return refuse(reason);
  rebuild_groove(w);
  if (!check(w, reason)) return refuse(reason);
  return commit(w);
}

BEMSURG_INLINE CutStep SurfaceCutter::deepen() {
  if (path_.empty()) return refuse("there is no cut to deepen: open one with step() first");
  Work w = start_work();
  ++w.levels;
  for (auto& s : w.path) {
    if (!s.split) continue;
    const double depth = w.levels * s.level_depth;  // the groove lies right of the path (split_section)
    s.left.push_back(w.add_vertex(s.center - depth * s.normal));
    s.right.push_back(w.add_vertex(s.center - s.width * s.left_dir - depth * s.normal));
  }
  rebuild_groove(w);
  std::string reason;
  if (!check(w, reason)) return refuse(reason);
  return commit(w);
}

BEMSURG_INLINE bool SurfaceCutter::open(Work& w, const Vec3& from, const Vec3& direction, std::string& reason) const {
  const Index a = w.nearest_surface_vertex(from);
  const auto fan = w.fan(a, -1, reason);
  if (fan.empty()) return false;
  const Vec3 n = w.fan_normal(fan, false);
  const Vec3 along = direction - direction.dot(n) * n;
  if (along.norm() < 1e-6 * direction.norm()) {
    reason =
        "the direction is along the surface normal at vertex " + std::to_string(a) + ": it gives no direction to cut along the surface";
    return false;
  }
  double best_dot = 0.0;
  const Index b = w.best_aligned_neighbour(a, fan, along, false, best_dot);
  if (touches_lock(w, a, reason) || touches_lock(w, b, reason) || w.sharp_at(a, options_.max_normal_deviation_degrees, reason) ||
      w.sharp_at(b, options_.max_normal_deviation_degrees, reason))
    return false;
  const Index mid = w.split_edge_at_midpoint(a, b, reason);
  if (mid < 0) return false;
  const double length = (w.pos(b) - w.pos(a)).norm();
  for (Index v : {a, mid, b}) {
    Section s;
    s.vertex = v;
    s.center = w.pos(v);
    w.path.push_back(s);
    w.cut_vertex[static_cast<std::size_t>(v)] = 1;
  }
  w.segment_length = {length, length};
  w.levels = 1;
  return split_section(w, 1, reason);
}

BEMSURG_INLINE bool SurfaceCutter::touches_lock(const Work& w, Index v, std::string& reason) const {
  for (std::size_t f = 0; f < w.F.size() && f < locked_.size(); ++f)
    if (locked_[f] && std::find(w.F[f].begin(), w.F[f].end(), v) != w.F[f].end()) {
      reason = "the cut would reach supported element " + std::to_string(f) + " at vertex " + std::to_string(v);
      return true;
    }
  return false;
}

BEMSURG_INLINE bool SurfaceCutter::extend(Work& w, const Vec3& direction, std::string& reason) const {
  const Index v = w.path.back().vertex;
  const auto fan = w.fan(v, -1, reason);
  if (fan.empty()) return false;
  const Vec3 n = w.fan_normal(fan, true);
  const Vec3 along = direction - direction.dot(n) * n;
  if (along.norm() < 1e-6 * direction.norm()) {
    reason = "the direction is along the surface normal at the cut's end (vertex " + std::to_string(v) + ")";
    return false;
  }
  double best_dot = 0.0;
  const Index b = w.best_aligned_neighbour(v, fan, along, true, best_dot);
  if (b < 0 || best_dot <= 0.0) {
    reason = "no surface edge from the cut's end (vertex " + std::to_string(v) + ") runs along the direction without re-entering the cut";
    return false;
  }
  // A turn of more than 90 degrees would fold the groove back onto itself.
  const Vec3 previous = w.path.back().center - w.path[w.path.size() - 2].center;
  if (previous.dot(w.pos(b) - w.pos(v)) <= 0.0) {
    reason = "the direction turns the cut back on itself at vertex " + std::to_string(v) + " (more than 90 degrees)";
    return false;
  }
  if (touches_lock(w, b, reason) || w.sharp_at(b, options_.max_normal_deviation_degrees, reason)) return false;
  Section s;
  s.vertex = b;
  s.center = w.pos(b);
  w.path.push_back(s);
  w.cut_vertex[static_cast<std::size_t>(b)] = 1;
  w.segment_length.push_back((w.pos(b) - w.pos(v)).norm());
  return split_section(w, w.path.size() - 2, reason);
}

BEMSURG_INLINE bool SurfaceCutter::divide_sides(const Work& w, std::size_t i, std::vector<Index>& left, std::vector<Index>& right,
                                                std::string& reason) const {
  const Section& prev = w.path[i - 1];
  const Index v = w.path[i].vertex;
  const auto fan = w.fan(v, w.path[i + 1].vertex, reason);
  if (fan.empty()) return false;
  // Left faces: counter-clockwise from the one running v -> next up to the incoming path edge
  // (an unsplit previous vertex) or up to the groove (a split one); the rest are right faces.
  int state = 0;  // 0 left, 1 groove, 2 right
  bool saw_groove = false;
  for (const auto& x : fan) {
    const bool is_groove = w.groove[static_cast<std::size_t>(x.face)] != 0;
    if (is_groove) {
      if (state == 2) {
        reason = "the cut meets its own groove twice at vertex " + std::to_string(v);
        return false;
      }
      state = 1;
      saw_groove = true;
      continue;
    }
    if (state == 1) state = 2;
    (state == 0 ? left : right).push_back(x.face);
    if (state == 0 && !prev.split && x.b == prev.vertex) state = 2;
  }
  if (left.empty() || right.empty() || saw_groove != prev.split) {
    reason = "the surface around vertex " + std::to_string(v) + " cannot be divided into the two sides of the cut";
    return false;
  }
  for (const auto* side : {&left, &right})
    for (Index f : *side)  // faces appended by this step (f beyond the locks) are new, never locked
      if (static_cast<std::size_t>(f) < locked_.size() && locked_[static_cast<std::size_t>(f)]) {
        reason = "the cut would reach supported element " + std::to_string(f);
        return false;
      }
  return true;
}

BEMSURG_INLINE bool SurfaceCutter::split_section(Work& w, std::size_t i, std::string& reason) const {
  std::vector<Index> left, right;
  if (!divide_sides(w, i, left, right, reason)) return false;
  Section& s = w.path[i];
  const Section& prev = w.path[i - 1];
  const Section& next = w.path[i + 1];
  const Index v = s.vertex;
  // Depth direction: the mean outward normal of the surface around v (the groove is cut along it).
  Vec3 n = Vec3::Zero();
  for (Index f : left) n += w.face_normal_area(f);
  for (Index f : right) n += w.face_normal_area(f);
  n.normalize();
  std::vector<Index> sides = left;
  sides.insert(sides.end(), right.begin(), right.end());
  const Index turned = w.first_turned_face(sides, n, options_.max_normal_deviation_degrees);
  if (turned >= 0) {
    reason = Work::turn_reason(options_.max_normal_deviation_degrees, v, turned, "cross a sharp edge or another cut's wall");
    return false;
  }
  Vec3 tangent = next.center - prev.center;
  tangent -= tangent.dot(n) * n;
  if (tangent.norm() <= 0.0) {
    reason = "the cut path has no direction along the surface at vertex " + std::to_string(v);
    return false;
  }
  s.split = true;
  s.normal = n;
  s.left_dir = n.cross(tangent).normalized();
  s.edge_length = 0.5 * (w.segment_length[i - 1] + w.segment_length[i]);
  s.width = options_.gap_width > 0.0 ? options_.gap_width : options_.gap_fraction * s.edge_length;
  s.level_depth = options_.depth_fraction * s.edge_length;
  // The groove lies right of the path: the left rim keeps v (index and position) and the right
  // rim, a new vertex, is one gap width away. Faces on the left therefore keep their corners bit
  // for bit and are not reshaped (mesh/mesh_delta.hpp): only the right side's faces change, so
  // a step's update rank is lower than with a groove centred on the path, which would move both
  // sides by half a gap (docs/cutting.md "Topology").
  s.left = {v};
  s.right = {w.add_vertex(s.center - s.width * s.left_dir)};
  for (int l = 1; l <= w.levels; ++l) {
    s.left.push_back(w.add_vertex(s.center - l * s.level_depth * n));
    s.right.push_back(w.add_vertex(s.center - s.width * s.left_dir - l * s.level_depth * n));
  }
  for (Index f : right)
    for (Index& c : w.F[static_cast<std::size_t>(f)])
      if (c == v) c = s.right[0];
  return true;
}

BEMSURG_INLINE CutStep SurfaceCutter::commit(Work& w) {
  CutStep out;
  out.accepted = true;
  out.delta = w.delta;
  out.added_parent = w.parent;
  mesh_ = std::move(w.result);
  ++version_;
  locked_.resize(static_cast<std::size_t>(mesh_->num_elements()), 0);
  cut_vertex_ = std::move(w.cut_vertex);
  path_ = std::move(w.path);
  segment_length_ = std::move(w.segment_length);
  levels_ = w.levels;
  groove_faces_ = std::move(w.groove_faces);
  return out;
}

}  // namespace bemsurg
