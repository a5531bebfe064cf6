// Construction of MeshTopology: half-edges sorted into edges, union-find into shells.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

#include "bemsurg/mesh/geometry.hpp"

namespace bemsurg {

namespace detail {

struct HalfEdge {
  Index lo, hi;  // sorted vertex pair
  Index face;
  int local;
  bool forward;
};

BEMSURG_INLINE Index find_root(std::vector<Index>& parent, Index x) {
  while (parent[static_cast<std::size_t>(x)] != x) {
    // Path halving keeps the trees flat without recursion.
    parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
    x = parent[static_cast<std::size_t>(x)];
  }
  return x;
}

}  // namespace detail

BEMSURG_INLINE MeshTopology::MeshTopology(const TriangleMesh& mesh) {
  const Index nf = mesh.num_elements();
  const auto& F = mesh.faces();

  // Sorting the 3F half-edges groups each undirected edge; this gives a deterministic edge
  // numbering and avoids a hash table.
  std::vector<detail::HalfEdge> half(static_cast<std::size_t>(3 * nf));
  for (Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const Index a = F(f, k), b = F(f, (k + 1) % 3);
      half[static_cast<std::size_t>(3 * f + k)] = {std::min(a, b), std::max(a, b), f, k, a <= b};
    }
  std::sort(half.begin(), half.end(), [](const detail::HalfEdge& x, const detail::HalfEdge& y) {
    return std::tie(x.lo, x.hi, x.face, x.local) < std::tie(y.lo, y.hi, y.face, y.local);
  });

  face_edges_.assign(static_cast<std::size_t>(3 * nf), -1);
  for (std::size_t i = 0; i < half.size();) {
    MeshEdge edge;
    edge.vertices = {half[i].lo, half[i].hi};
    std::size_t j = i;
    const Index id = static_cast<Index>(edges_.size());
    for (; j < half.size() && half[j].lo == half[i].lo && half[j].hi == half[i].hi; ++j) {
      edge.faces.push_back({half[j].face, half[j].local, half[j].forward});
      face_edges_[static_cast<std::size_t>(3 * half[j].face + half[j].local)] = id;
    }
    edges_.push_back(std::move(edge));
    i = j;
  }

  vertex_faces_.assign(static_cast<std::size_t>(mesh.num_vertices()), {});
  for (Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      auto& list = vertex_faces_[static_cast<std::size_t>(F(f, k))];
      if (list.empty() || list.back() != f) list.push_back(f);  // a face repeating a vertex counts once
    }

  // Shells: union the faces of every edge (non-manifold edges included, so a fin stays attached
  // to the shell it hangs from).
  std::vector<Index> parent(static_cast<std::size_t>(nf));
  std::iota(parent.begin(), parent.end(), Index{0});
  for (const MeshEdge& e : edges_)
    for (std::size_t k = 1; k < e.faces.size(); ++k) {
      const Index a = detail::find_root(parent, e.faces[0].face), b = detail::find_root(parent, e.faces[k].face);
      if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
  shell_of_face_.assign(static_cast<std::size_t>(nf), -1);
  std::vector<Index> shell_of_root(static_cast<std::size_t>(nf), -1);
  for (Index f = 0; f < nf; ++f) {
    const Index r = detail::find_root(parent, f);
    Index& s = shell_of_root[static_cast<std::size_t>(r)];
    if (s < 0) {
      s = static_cast<Index>(shells_.size());
      shells_.emplace_back();
    }
    shell_of_face_[static_cast<std::size_t>(f)] = s;
    shells_[static_cast<std::size_t>(s)].push_back(f);
  }

  // Volume by the divergence theorem about a point of the shell itself: for a closed shell the
  // result does not depend on the point, and a nearby one avoids cancellation far from the origin.
  shell_volumes_.assign(shells_.size(), 0.0);
  shell_closed_.assign(shells_.size(), true);
  for (std::size_t s = 0; s < shells_.size(); ++s) {
    const Vec3 origin = mesh.vertex(F(shells_[s].front(), 0));
    double volume = 0.0;
    for (Index f : shells_[s]) {
      const auto c = mesh.corners(f);
      volume += (c[0] - origin).dot((c[1] - origin).cross(c[2] - origin)) / 6.0;
      for (int k = 0; k < 3; ++k)
        if (!edge(face_edge(f, k)).is_manifold_oriented()) shell_closed_[s] = false;
    }
    shell_volumes_[s] = volume;
  }
}

BEMSURG_INLINE Index MeshTopology::find_edge(Index a, Index b) const {
  const std::array<Index, 2> key{{std::min(a, b), std::max(a, b)}};
  const auto it =
      std::lower_bound(edges_.begin(), edges_.end(), key, [](const MeshEdge& e, const std::array<Index, 2>& k) { return e.vertices < k; });
  return (it != edges_.end() && it->vertices == key) ? static_cast<Index>(it - edges_.begin()) : -1;
}

BEMSURG_INLINE Index MeshTopology::neighbour(Index f, int k) const {
  const MeshEdge& e = edge(face_edge(f, k));
  if (e.faces.size() != 2) return -1;
  return e.faces[0].face == f && e.faces[0].local == k ? e.faces[1].face : e.faces[0].face;
}

BEMSURG_INLINE std::vector<Index> MeshTopology::boundary_edges() const {
  std::vector<Index> out;
  for (Index e = 0; e < num_edges(); ++e)
    if (edge(e).is_boundary()) out.push_back(e);
  return out;
}

BEMSURG_INLINE std::vector<Index> MeshTopology::non_manifold_edges() const {
  std::vector<Index> out;
  for (Index e = 0; e < num_edges(); ++e)
    if (edge(e).is_non_manifold()) out.push_back(e);
  return out;
}

BEMSURG_INLINE bool MeshTopology::is_closed_and_oriented() const {
  return std::all_of(edges_.begin(), edges_.end(), [](const MeshEdge& e) { return e.is_manifold_oriented(); });
}

namespace detail {
// Van Oosterom & Strackee: the solid angle of triangle (a, b, c) seen from the origin is
// 2 atan2(a.(b x c), |a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|). A point in a triangle's plane
// (numerator 0) and inside it (denominator <= 0), or at a corner, is on the surface: there the
// formula jumps by a whole half-turn.
template <class ForEachFace>
double winding_number_over(const TriangleMesh& mesh, const Vec3& p, bool* on_surface, ForEachFace&& for_each_face) {
  double total = 0.0;
  if (on_surface) *on_surface = false;
  for_each_face([&](Index f) {
    const auto c = mesh.corners(f);
    const Vec3 a = c[0] - p, b = c[1] - p, d = c[2] - p;
    const double la = a.norm(), lb = b.norm(), ld = d.norm();
    const double numerator = a.dot(b.cross(d));
    const double denominator = la * lb * ld + a.dot(b) * ld + a.dot(d) * lb + b.dot(d) * la;
    if (on_surface && std::abs(numerator) <= 1e-12 * la * lb * ld && denominator <= 1e-12 * la * lb * ld) *on_surface = true;
    total += 2.0 * std::atan2(numerator, denominator);
  });
  return total / (4.0 * numbers::pi);
}
}  // namespace detail

BEMSURG_INLINE double winding_number(const TriangleMesh& mesh, const std::vector<Index>& faces, const Vec3& p, bool* on_surface) {
  return detail::winding_number_over(mesh, p, on_surface, [&](auto&& visit) {
    for (Index f : faces) visit(f);
  });
}

BEMSURG_INLINE double winding_number(const TriangleMesh& mesh, const Vec3& p, bool* on_surface) {
  return detail::winding_number_over(mesh, p, on_surface, [&](auto&& visit) {
    for (Index f = 0; f < mesh.num_elements(); ++f) visit(f);
  });
}

BEMSURG_INLINE std::vector<Index> shell_bodies(const TriangleMesh& mesh, const MeshTopology& topo) {
  const Index ns = topo.num_shells();
  std::vector<Index> root(static_cast<std::size_t>(ns));
  std::iota(root.begin(), root.end(), Index{0});
  // Bounding box and a probe point (the centroid of the largest face) of each closed shell.
  std::vector<Index> closed;
  std::vector<Vec3> lo, hi, probe;
  for (Index s = 0; s < ns; ++s) {
    if (!topo.shell_is_closed_and_oriented(s)) continue;
    Vec3 a = Vec3::Constant(std::numeric_limits<double>::infinity()), b = -a;
    Index largest = topo.shell(s).front();
    for (Index f : topo.shell(s)) {
      for (const Vec3& c : mesh.corners(f)) {
        a = a.cwiseMin(c);
        b = b.cwiseMax(c);
      }
      if (mesh.area(f) > mesh.area(largest)) largest = f;
    }
    closed.push_back(s);
    lo.push_back(a);
    hi.push_back(b);
    probe.push_back(mesh.centroid(largest));
  }
  for (std::size_t i = 0; i < closed.size(); ++i) {
    int depth = 0;
    Index parent = -1;
    for (std::size_t j = 0; j < closed.size(); ++j) {
      if (i == j || !(lo[j].array() <= lo[i].array()).all() || !(hi[i].array() <= hi[j].array()).all()) continue;
      const Index t = closed[j];
      if (std::abs(winding_number(mesh, topo.shell(t), probe[i])) > 0.5) {
        ++depth;
        if (parent < 0 || std::abs(topo.shell_volume(t)) < std::abs(topo.shell_volume(parent))) parent = t;
      }
    }
    if (depth % 2 == 1) root[static_cast<std::size_t>(closed[i])] = parent;  // a cavity: parent is at even depth
  }
  // Number the bodies in the order of their outer shells.
  std::vector<Index> number(static_cast<std::size_t>(ns), -1), body(static_cast<std::size_t>(ns));
  Index next = 0;
  for (Index s = 0; s < ns; ++s)
    if (root[static_cast<std::size_t>(s)] == s) number[static_cast<std::size_t>(s)] = next++;
  for (Index s = 0; s < ns; ++s) body[static_cast<std::size_t>(s)] = number[static_cast<std::size_t>(root[static_cast<std::size_t>(s)])];
  return body;
}

}  // namespace bemsurg
