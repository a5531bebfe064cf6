// Implementation of bemsurg/cutting/surface_cutter.hpp: a groove along mesh edges (Wang et al.
// 2007 §5.3), built on a copy of the state and published only after the surface checks pass.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/bvh.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/self_intersection.hpp"

namespace bemsurg {

namespace detail {
constexpr double kCutPi = 3.14159265358979323846;

// One face around a vertex v, seen as (v, a, b) counter-clockwise from outside.
struct CutFanFace {
  Index face;
  Index a, b;
};

// The smallest interior angle of a triangle, in degrees (0 for a degenerate one).
BEMSURG_INLINE double cut_min_angle_degrees(const Vec3& p, const Vec3& q, const Vec3& r) {
  const std::array<Vec3, 3> c{{p, q, r}};
  double smallest = 180.0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 u = c[(k + 1) % 3] - c[k], v = c[(k + 2) % 3] - c[k];
    const double nu = u.norm(), nv = v.norm();
    if (nu <= 0.0 || nv <= 0.0) return 0.0;
    const double cosine = std::clamp(u.dot(v) / (nu * nv), -1.0, 1.0);
    smallest = std::min(smallest, std::acos(cosine) * 180.0 / kCutPi);
  }
  return smallest;
}
// Distance from p to the triangle (a, b, c): closest point by Voronoi regions (Ericson,
// Real-Time Collision Detection, §5.1.5).
BEMSURG_INLINE double cut_point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}
}  // namespace detail

struct SurfaceCutter::Work {
  std::vector<Vec3> V;
  std::vector<std::array<Index, 3>> F;
  std::vector<char> groove;      // per face: a wall or bottom triangle of this cut
  std::vector<char> cut_vertex;  // per vertex
  std::vector<Section> path;
  std::vector<double> segment_length;
  int levels = 0;
  std::map<std::tuple<int, int, int, int>, Index> groove_faces;
  Index elements_before = 0;
  MeshDelta delta;
  std::shared_ptr<const TriangleMesh> result;

  Index add_vertex(const Vec3& p) {
    V.push_back(p);
    cut_vertex.push_back(1);
    return static_cast<Index>(V.size()) - 1;
  }
  std::vector<Index> parent;  // per face appended by this step: the element it was split from, or -1
  Index add_face(const std::array<Index, 3>& f, bool is_groove, Index split_from = -1) {
    F.push_back(f);
    groove.push_back(is_groove ? 1 : 0);
    parent.push_back(split_from);
    return static_cast<Index>(F.size()) - 1;
  }
  Vec3 face_normal_area(Index f) const {  // twice the area times the unit normal
    const auto& t = F[static_cast<std::size_t>(f)];
    return (V[static_cast<std::size_t>(t[1])] - V[static_cast<std::size_t>(t[0])])
        .cross(V[static_cast<std::size_t>(t[2])] - V[static_cast<std::size_t>(t[0])]);
  }
  const Vec3& pos(Index v) const { return V[static_cast<std::size_t>(v)]; }

  // Faces around v, counter-clockwise from outside, starting with the face that runs v -> start
  // (any face when start < 0). Empty with a reason if the fan is not a single closed cycle.
  std::vector<detail::CutFanFace> fan(Index v, Index start, std::string& reason) const {
    std::vector<detail::CutFanFace> all;
    for (std::size_t f = 0; f < F.size(); ++f)
      for (int k = 0; k < 3; ++k)
        if (F[f][static_cast<std::size_t>(k)] == v)
          all.push_back({static_cast<Index>(f), F[f][static_cast<std::size_t>((k + 1) % 3)],
                         F[f][static_cast<std::size_t>((k + 2) % 3)]});
    std::vector<detail::CutFanFace> out;
    if (all.empty()) {
      reason = "vertex " + std::to_string(v) + " is used by no face";
      return out;
    }
    auto find_a = [&](Index a) {
      return std::find_if(all.begin(), all.end(), [&](const detail::CutFanFace& x) { return x.a == a; });
    };
    auto it = start >= 0 ? find_a(start) : all.begin();
    if (it == all.end()) {
      reason = "no face runs from vertex " + std::to_string(v) + " to vertex " + std::to_string(start);
      return out;
    }
    out.push_back(*it);
    while (out.size() < all.size()) {
      auto next = find_a(out.back().b);
      if (next == all.end() || next->face == out.front().face) break;
      out.push_back(*next);
    }
    if (out.size() != all.size() || out.back().b != out.front().a) {
      reason = "the faces around vertex " + std::to_string(v) + " do not form one closed fan";
      out.clear();
    }
    return out;
  }

  // Whether the faces around v (the groove's own excepted) turn by more than `limit_degrees` from
  // their mean normal: v sits on a sharp edge or on another cut's wall, where a groove cut
  // "perpendicular to the surface" has no meaning.
  bool sharp_at(Index v, double limit_degrees, std::string& reason) const {
    const auto around = fan(v, -1, reason);
    if (around.empty()) return true;
    const Vec3 n = fan_normal(around, true);
    const double cos_limit = std::cos(limit_degrees * detail::kCutPi / 180.0);
    for (const auto& x : around)
      if (!groove[static_cast<std::size_t>(x.face)] && face_normal_area(x.face).normalized().dot(n) < cos_limit) {
        std::ostringstream msg;
        msg << "the surface turns by more than " << limit_degrees << " degrees around vertex " << v << " (face "
            << x.face << "): the cut would run onto a sharp edge or another cut's wall";
        reason = msg.str();
        return true;
      }
    return false;
  }

  Vec3 fan_normal(const std::vector<detail::CutFanFace>& fan, bool surface_only) const {
    Vec3 n = Vec3::Zero();
    for (const auto& x : fan)
      if (!surface_only || !groove[static_cast<std::size_t>(x.face)]) n += face_normal_area(x.face);
    const double len = n.norm();
    return len > 0.0 ? Vec3(n / len) : n;
  }
};

BEMSURG_INLINE SurfaceCutter::SurfaceCutter(std::shared_ptr<const TriangleMesh> mesh, std::vector<char> locked_elements,
                                    CutOptions options)
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
  for (Index f = 0; f < m.num_elements(); ++f)
    w.F[static_cast<std::size_t>(f)] = {m.faces()(f, 0), m.faces()(f, 1), m.faces()(f, 2)};
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
  // The surface vertex nearest the tool (the paper's starting node).
  std::vector<char> used(w.V.size(), 0);
  for (const auto& f : w.F)
    for (Index v : f) used[static_cast<std::size_t>(v)] = 1;
  Index a = -1;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < w.V.size(); ++v)
    if (used[v] && (w.V[v] - from).squaredNorm() < best) {
      best = (w.V[v] - from).squaredNorm();
      a = static_cast<Index>(v);
    }
  const auto fan = w.fan(a, -1, reason);
  if (fan.empty()) return false;
  const Vec3 n = w.fan_normal(fan, false);
  const Vec3 along = direction - direction.dot(n) * n;
  if (along.norm() < 1e-6 * direction.norm()) {
    reason = "the direction is along the surface normal at vertex " + std::to_string(a) +
             ": it gives no direction to cut along the surface";
    return false;
  }
  // The edge from a with the largest dot product of its unit vector and the travel direction.
  Index b = -1;
  double best_dot = -2.0;
  for (const auto& x : fan) {
    const double d = (w.pos(x.a) - w.pos(a)).normalized().dot(along.normalized());
    if (d > best_dot) {
      best_dot = d;
      b = x.a;
    }
  }
  if (touches_lock(w, a, reason) || touches_lock(w, b, reason) ||
      w.sharp_at(a, options_.max_normal_deviation_degrees, reason) ||
      w.sharp_at(b, options_.max_normal_deviation_degrees, reason))
    return false;
  // Split that edge at its midpoint, so the cut has an inner vertex to open; each split triangle
  // keeps one half under its id and appends the other (mesh/mesh_delta.hpp).
  Index f1 = -1, f2 = -1, x1 = -1, x2 = -1;
  for (std::size_t f = 0; f < w.F.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index p = w.F[f][static_cast<std::size_t>(k)], q = w.F[f][static_cast<std::size_t>((k + 1) % 3)];
      const Index r = w.F[f][static_cast<std::size_t>((k + 2) % 3)];
      if (p == a && q == b) f1 = static_cast<Index>(f), x1 = r;
      if (p == b && q == a) f2 = static_cast<Index>(f), x2 = r;
    }
  if (f1 < 0 || f2 < 0) {
    reason = "edge (" + std::to_string(a) + ", " + std::to_string(b) + ") does not have two faces";
    return false;
  }
  const Index mid = w.add_vertex(0.5 * (w.pos(a) + w.pos(b)));
  w.F[static_cast<std::size_t>(f1)] = {a, mid, x1};
  w.add_face({mid, b, x1}, false, f1);
  w.F[static_cast<std::size_t>(f2)] = {b, mid, x2};
  w.add_face({mid, a, x2}, false, f2);
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
  Index b = -1;
  double best_dot = -2.0;
  for (const auto& x : fan) {
    if (w.groove[static_cast<std::size_t>(x.face)] || w.cut_vertex[static_cast<std::size_t>(x.a)]) continue;
    const double d = (w.pos(x.a) - w.pos(v)).normalized().dot(along.normalized());
    if (d > best_dot) {
      best_dot = d;
      b = x.a;
    }
  }
  if (b < 0 || best_dot <= 0.0) {
    reason = "no surface edge from the cut's end (vertex " + std::to_string(v) +
             ") runs along the direction without re-entering the cut";
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

BEMSURG_INLINE bool SurfaceCutter::split_section(Work& w, std::size_t i, std::string& reason) const {
  Section& s = w.path[i];
  const Section& prev = w.path[i - 1];
  const Section& next = w.path[i + 1];
  const Index v = s.vertex;
  const auto fan = w.fan(v, next.vertex, reason);
  if (fan.empty()) return false;
  // Left faces: counter-clockwise from the one running v -> next up to the incoming path edge
  // (an unsplit previous vertex) or up to the groove (a split one); the rest are right faces.
  std::vector<Index> left, right;
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
  // Depth direction: the mean outward normal of the surface around v (the groove is cut along it).
  Vec3 n = Vec3::Zero();
  for (Index f : left) n += w.face_normal_area(f);
  for (Index f : right) n += w.face_normal_area(f);
  n.normalize();
  const double cos_limit = std::cos(options_.max_normal_deviation_degrees * detail::kCutPi / 180.0);
  for (const auto* side : {&left, &right})
    for (Index f : *side)
      if (w.face_normal_area(f).normalized().dot(n) < cos_limit) {
        std::ostringstream msg;
        msg << "the surface turns by more than " << options_.max_normal_deviation_degrees << " degrees around vertex " << v
            << " (face " << f << "): the cut would cross a sharp edge or another cut's wall";
        reason = msg.str();
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

BEMSURG_INLINE void SurfaceCutter::rebuild_groove(Work& w) const {
  const int L = w.levels;
  auto ring = [L](const Section& s) {
    std::vector<Index> r;
    for (int l = 0; l <= L; ++l) r.push_back(s.left[static_cast<std::size_t>(l)]);
    for (int l = L; l >= 0; --l) r.push_back(s.right[static_cast<std::size_t>(l)]);
    return r;
  };
  auto key_of = [L](int seg, int j, int half) {
    if (j < L) return std::make_tuple(seg, 0, j, half);       // left wall, level j
    if (j == L) return std::make_tuple(seg, 1, 0, half);      // bottom
    return std::make_tuple(seg, 2, 2 * L - j, half);          // right wall
  };
  auto place = [&](const std::tuple<int, int, int, int>& key, const std::array<Index, 3>& tri) {
    auto it = w.groove_faces.find(key);
    if (it != w.groove_faces.end()) {
      w.F[static_cast<std::size_t>(it->second)] = tri;
    } else {
      w.groove_faces[key] = w.add_face(tri, true);
    }
  };
  for (std::size_t s = 0; s + 1 < w.path.size(); ++s) {
    const Section& p = w.path[s];
    const Section& q = w.path[s + 1];
    const int seg = static_cast<int>(s);
    if (p.split && q.split) {
      const auto rp = ring(p), rq = ring(q);
      for (int j = 0; j < 2 * L + 1; ++j) {
        // Quad (a, b, c, d): ring segment j at p, then at q; its normal points into the gap.
        const Index a = rp[static_cast<std::size_t>(j)], b = rp[static_cast<std::size_t>(j + 1)];
        const Index c = rq[static_cast<std::size_t>(j + 1)], d = rq[static_cast<std::size_t>(j)];
        const double q1 = std::min(detail::cut_min_angle_degrees(w.pos(a), w.pos(b), w.pos(c)),
                                   detail::cut_min_angle_degrees(w.pos(a), w.pos(c), w.pos(d)));
        const double q2 = std::min(detail::cut_min_angle_degrees(w.pos(a), w.pos(b), w.pos(d)),
                                   detail::cut_min_angle_degrees(w.pos(b), w.pos(c), w.pos(d)));
        if (q1 >= q2) {
          place(key_of(seg, j, 0), {a, b, c});
          place(key_of(seg, j, 1), {a, c, d});
        } else {
          place(key_of(seg, j, 0), {a, b, d});
          place(key_of(seg, j, 1), {b, c, d});
        }
      }
    } else if (q.split) {  // the start of the cut: a fan from the end vertex
      const auto rq = ring(q);
      for (int j = 0; j < 2 * L + 1; ++j)
        place(key_of(seg, j, 0), {p.vertex, rq[static_cast<std::size_t>(j + 1)], rq[static_cast<std::size_t>(j)]});
    } else {  // the far end
      const auto rp = ring(p);
      for (int j = 0; j < 2 * L + 1; ++j)
        place(key_of(seg, j, 0), {rp[static_cast<std::size_t>(j)], rp[static_cast<std::size_t>(j + 1)], q.vertex});
    }
  }
}

BEMSURG_INLINE bool SurfaceCutter::check(Work& w, std::string& reason) const {
  const TriangleMesh& old = *mesh_;
  RowMatrixX3d V(static_cast<Index>(w.V.size()), 3);
  for (std::size_t v = 0; v < w.V.size(); ++v) V.row(static_cast<Index>(v)) = w.V[v].transpose();
  RowMatrixX3i F(static_cast<Index>(w.F.size()), 3);
  for (std::size_t f = 0; f < w.F.size(); ++f)
    for (int k = 0; k < 3; ++k) F(static_cast<Index>(f), k) = static_cast<int>(w.F[f][static_cast<std::size_t>(k)]);
  auto mesh = std::make_shared<const TriangleMesh>(std::move(V), std::move(F));

  // The delta, by the contract's definition: an old id is unchanged iff its three corner
  // positions are bit-identical (mesh/mesh_delta.hpp).
  MeshDelta& d = w.delta;
  d = MeshDelta{};
  d.elements_before = old.num_elements();
  d.elements_after = mesh->num_elements();
  for (Index f = 0; f < old.num_elements(); ++f) {
    const auto a = old.corners(f), b = mesh->corners(f);
    if (!(a[0] == b[0] && a[1] == b[1] && a[2] == b[2])) d.modified.push_back(f);
  }
  for (Index f = old.num_elements(); f < mesh->num_elements(); ++f) d.added.push_back(f);
  for (Index f : d.modified)
    if (locked_[static_cast<std::size_t>(f)]) {
      reason = "the cut would reach supported element " + std::to_string(f);
      return false;
    }
  // No locked element may touch the cut's path either (its ends included).
  std::vector<Index> locked_by_vertex(static_cast<std::size_t>(old.num_vertices()), -1);
  for (Index f = 0; f < old.num_elements(); ++f)
    if (locked_[static_cast<std::size_t>(f)])
      for (int k = 0; k < 3; ++k) locked_by_vertex[static_cast<std::size_t>(old.faces()(f, k))] = f;
  for (const auto& s : w.path) {
    const Index v = s.split ? s.left.front() : s.vertex;
    if (v < old.num_vertices() && locked_by_vertex[static_cast<std::size_t>(v)] >= 0) {
      reason = "the cut would reach supported element " + std::to_string(locked_by_vertex[static_cast<std::size_t>(v)]) +
               " at vertex " + std::to_string(v);
      return false;
    }
  }
  const std::vector<Index> changed = d.changed();
  for (Index f : changed) {
    const auto c = mesh->corners(f);
    const double angle = detail::cut_min_angle_degrees(c[0], c[1], c[2]);
    if (angle < options_.min_angle_degrees) {
      std::ostringstream msg;
      msg << "element " << f << " would have an angle of " << angle << " degrees, below the minimum of "
          << options_.min_angle_degrees << " (a sliver: the gap is too narrow or the cut too deep here)";
      reason = msg.str();
      return false;
    }
  }
  SelfIntersectionOptions so;
  so.max_pairs = 1;
  const auto pairs = find_self_intersections(*mesh, changed, so);
  if (!pairs.empty()) {
    reason = "the cut would make the surface intersect itself (elements " + std::to_string(pairs[0].first) + " and " +
             std::to_string(pairs[0].second) + "): it would break through a thin part or cross a wall";
    return false;
  }
  // Clearance: the groove's walls and bottom keep at least one gap width from the rest of the
  // surface, so that a cut that nearly breaks through a thin part (leaving a skin thinner than
  // the gap, whose two sides the BEM would integrate as near-singular neighbours) is refused
  // like one that breaks through.
  const TriangleBvh bvh(*mesh);
  std::vector<Index> near;
  for (const auto& s : w.path) {
    if (!s.split) continue;
    for (std::size_t l = 1; l < s.left.size(); ++l)
      for (Index v : {s.left[l], s.right[l]}) {
        const Vec3 p = w.pos(v);
        const double r = s.width;
        near.clear();
        bvh.query_box(p.array() - r, p.array() + r, near);
        for (Index g : near) {
          const auto& t = w.F[static_cast<std::size_t>(g)];
          if (w.groove[static_cast<std::size_t>(g)] || w.cut_vertex[static_cast<std::size_t>(t[0])] ||
              w.cut_vertex[static_cast<std::size_t>(t[1])] || w.cut_vertex[static_cast<std::size_t>(t[2])])
            continue;
          const double dist = detail::cut_point_triangle_distance(p, w.pos(t[0]), w.pos(t[1]), w.pos(t[2]));
          if (dist < r) {
            std::ostringstream msg;
            msg << "the cut would come within " << dist << " of element " << g << " (less than the gap width " << r
                << "): it would break through a thin part";
            reason = msg.str();
            return false;
          }
        }
      }
  }
  // Last, the topology: a groove that breaks through a wall also breaks the shells' nesting, and
  // the reasons above name that cause.
  // Every vertex of a changed face has one closed fan of faces around it (validate_mesh checks
  // edges; a vertex where two cones touch would pass it but is no 2-manifold either).
  std::vector<char> seen(w.V.size(), 0);
  for (Index f : changed)
    for (Index v : w.F[static_cast<std::size_t>(f)]) {
      if (seen[static_cast<std::size_t>(v)]) continue;
      seen[static_cast<std::size_t>(v)] = 1;
      std::string why;
      if (w.fan(v, -1, why).empty()) {
        reason = "the cut would leave a surface that is not 2-manifold: " + why;
        return false;
      }
    }
  MeshValidationOptions vo;
  vo.warn_unreferenced_vertices = false;
  const MeshValidationReport report = validate_mesh(*mesh, vo);
  if (!report.valid()) {
    reason = "the cut would leave an invalid surface: " + report.summary();
    return false;
  }
  w.result = std::move(mesh);
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
