// Part of the implementation of bemsurg/cutting/surface_cutter.hpp: SurfaceCutter::Work, the
// candidate state of one step (a copy of the mesh as vertex and face lists, the path and the
// groove), and the questions the steps ask of it: the fan of faces around a vertex, its normal,
// whether the surface is sharp there. Built fully, checked, and only then published (commit).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

namespace detail {
// One face around a vertex v, seen as (v, a, b) counter-clockwise from outside.
struct CutFanFace {
  Index face;
  Index a, b;
};
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
          all.push_back({static_cast<Index>(f), F[f][static_cast<std::size_t>((k + 1) % 3)], F[f][static_cast<std::size_t>((k + 2) % 3)]});
    std::vector<detail::CutFanFace> out;
    if (all.empty()) {
      reason = "vertex " + std::to_string(v) + " is used by no face";
      return out;
    }
    auto find_a = [&](Index a) { return std::find_if(all.begin(), all.end(), [&](const detail::CutFanFace& x) { return x.a == a; }); };
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

  // The first of `faces` whose normal turns by more than `limit_degrees` from n, or -1.
  Index first_turned_face(const std::vector<Index>& faces, const Vec3& n, double limit_degrees) const {
    const double cos_limit = std::cos(limit_degrees * numbers::pi / 180.0);
    for (Index f : faces)
      if (face_normal_area(f).normalized().dot(n) < cos_limit) return f;
    return -1;
  }

  // "the surface turns by more than 40 degrees around vertex 7 (face 12): the cut would ..."
  static std::string turn_reason(double limit_degrees, Index v, Index f, const char* consequence) {
    std::ostringstream msg;
    use_classic_locale(msg) << "the surface turns by more than " << limit_degrees << " degrees around vertex " << v << " (face " << f
                            << "): the cut would " << consequence;
    return msg.str();
  }

  // Whether the faces around v (the groove's own excepted) turn by more than `limit_degrees` from
  // their mean normal: v sits on a sharp edge or on another cut's wall, where a groove cut
  // "perpendicular to the surface" has no meaning.
  bool sharp_at(Index v, double limit_degrees, std::string& reason) const {
    const auto around = fan(v, -1, reason);
    if (around.empty()) return true;
    const Vec3 n = fan_normal(around, true);
    std::vector<Index> surface;
    for (const auto& x : around)
      if (!groove[static_cast<std::size_t>(x.face)]) surface.push_back(x.face);
    const Index f = first_turned_face(surface, n, limit_degrees);
    if (f < 0) return false;
    reason = turn_reason(limit_degrees, v, f, "run onto a sharp edge or another cut's wall");
    return true;
  }

  Vec3 fan_normal(const std::vector<detail::CutFanFace>& fan, bool surface_only) const {
    Vec3 n = Vec3::Zero();
    for (const auto& x : fan)
      if (!surface_only || !groove[static_cast<std::size_t>(x.face)]) n += face_normal_area(x.face);
    const double len = n.norm();
    return len > 0.0 ? Vec3(n / len) : n;
  }

  // The vertex used by some face that lies nearest to `from` (the paper's starting node).
  Index nearest_surface_vertex(const Vec3& from) const {
    std::vector<char> used(V.size(), 0);
    for (const auto& f : F)
      for (Index v : f) used[static_cast<std::size_t>(v)] = 1;
    Index a = -1;
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < V.size(); ++v)
      if (used[v] && (V[v] - from).squaredNorm() < best) {
        best = (V[v] - from).squaredNorm();
        a = static_cast<Index>(v);
      }
    return a;
  }

  // The neighbour b of v in `around` whose edge v -> b has the largest dot product of its unit
  // vector with the unit travel direction `along` (the paper's rule), or -1; with skip_cut, edges
  // on the groove or to a vertex the cut made are no candidates. best_dot receives that product.
  Index best_aligned_neighbour(Index v, const std::vector<detail::CutFanFace>& around, const Vec3& along, bool skip_cut,
                               double& best_dot) const {
    Index b = -1;
    best_dot = -2.0;
    for (const auto& x : around) {
      if (skip_cut && (groove[static_cast<std::size_t>(x.face)] || cut_vertex[static_cast<std::size_t>(x.a)])) continue;
      const double d = (pos(x.a) - pos(v)).normalized().dot(along.normalized());
      if (d > best_dot) {
        best_dot = d;
        b = x.a;
      }
    }
    return b;
  }

  // Splits the edge (a, b) at its midpoint, so the cut has an inner vertex to open; each of its
  // two triangles keeps one half under its id and appends the other (mesh/mesh_delta.hpp).
  // Returns the new vertex, or -1 with a reason if the edge does not have two faces.
  Index split_edge_at_midpoint(Index a, Index b, std::string& reason) {
    Index f1 = -1, f2 = -1, x1 = -1, x2 = -1;
    for (std::size_t f = 0; f < F.size(); ++f)
      for (int k = 0; k < 3; ++k) {
        const Index p = F[f][static_cast<std::size_t>(k)], q = F[f][static_cast<std::size_t>((k + 1) % 3)];
        const Index r = F[f][static_cast<std::size_t>((k + 2) % 3)];
        if (p == a && q == b) f1 = static_cast<Index>(f), x1 = r;
        if (p == b && q == a) f2 = static_cast<Index>(f), x2 = r;
      }
    if (f1 < 0 || f2 < 0) {
      reason = "edge (" + std::to_string(a) + ", " + std::to_string(b) + ") does not have two faces";
      return -1;
    }
    const Index mid = add_vertex(0.5 * (pos(a) + pos(b)));
    F[static_cast<std::size_t>(f1)] = {a, mid, x1};
    add_face({mid, b, x1}, false, f1);
    F[static_cast<std::size_t>(f2)] = {b, mid, x2};
    add_face({mid, a, x2}, false, f2);
    return mid;
  }
};

}  // namespace bemsurg
