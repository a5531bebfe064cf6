// Implementation of bemsurg/mesh/bvh.hpp: median-split BVH with refit, ray / segment / box
// queries (picking on the deformed surface, Wang et al. 2007 §6).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "bemsurg/error.hpp"

namespace bemsurg {

namespace detail {
BEMSURG_INLINE thread_local Index g_nodes_visited = 0;
BEMSURG_INLINE constexpr int kLeafSize = 4;
BEMSURG_INLINE constexpr int kStackSize = 128;

BEMSURG_INLINE bool ray_box(const Eigen::Vector3d& o, const Eigen::Vector3d& inv_d, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                            double t_min, double t_max) {
  for (int a = 0; a < 3; ++a) {
    double t0 = (lo(a) - o(a)) * inv_d(a);
    double t1 = (hi(a) - o(a)) * inv_d(a);
    if (t0 > t1) std::swap(t0, t1);
    // NaN (0 * inf when the origin lies on a slab face and the direction is parallel) keeps the box.
    if (t0 > t_min) t_min = t0;
    if (t1 < t_max) t_max = t1;
    if (t_min > t_max) return false;
  }
  return true;
}
}  // namespace detail

BEMSURG_INLINE Index TriangleBvh::last_nodes_visited() { return detail::g_nodes_visited; }

BEMSURG_INLINE TriangleBvh::TriangleBvh(const RowMatrixX3d& vertices, const RowMatrixX3i& faces) : vertices_(vertices), faces_(faces) {
  const Index E = faces.rows();
  if (E == 0) throw InvalidMeshError("TriangleBvh: the mesh has no faces");
  if (!vertices.allFinite()) throw InvalidMeshError("TriangleBvh: a vertex is not finite");
  for (Index f = 0; f < E; ++f)
    for (int k = 0; k < 3; ++k)
      if (faces(f, k) < 0 || faces(f, k) >= vertices.rows())
        throw InvalidMeshError("TriangleBvh: face " + std::to_string(f) + " refers to a missing vertex");
  order_.resize(static_cast<std::size_t>(E));
  std::vector<Eigen::Vector3d> centers(static_cast<std::size_t>(E));
  for (Index f = 0; f < E; ++f) {
    order_[static_cast<std::size_t>(f)] = static_cast<int>(f);
    centers[static_cast<std::size_t>(f)] =
        (vertices.row(faces(f, 0)) + vertices.row(faces(f, 1)) + vertices.row(faces(f, 2))).transpose() / 3.0;
  }
  nodes_.reserve(static_cast<std::size_t>(2 * E / detail::kLeafSize + 2));
  build(0, static_cast<int>(E), centers);
}

BEMSURG_INLINE void TriangleBvh::triangle_box(Index f, Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
  const Eigen::Vector3d a = vertices_.row(faces_(f, 0)).transpose();
  const Eigen::Vector3d b = vertices_.row(faces_(f, 1)).transpose();
  const Eigen::Vector3d c = vertices_.row(faces_(f, 2)).transpose();
  lo = a.cwiseMin(b).cwiseMin(c);
  hi = a.cwiseMax(b).cwiseMax(c);
}

BEMSURG_INLINE int TriangleBvh::build(int begin, int end, std::vector<Eigen::Vector3d>& centers) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  Eigen::Vector3d clo = lo, chi = hi;
  for (int i = begin; i < end; ++i) {
    Eigen::Vector3d tlo, thi;
    triangle_box(order_[static_cast<std::size_t>(i)], tlo, thi);
    lo = lo.cwiseMin(tlo);
    hi = hi.cwiseMax(thi);
    const Eigen::Vector3d& c = centers[static_cast<std::size_t>(order_[static_cast<std::size_t>(i)])];
    clo = clo.cwiseMin(c);
    chi = chi.cwiseMax(c);
  }
  nodes_[static_cast<std::size_t>(index)].lo = lo;
  nodes_[static_cast<std::size_t>(index)].hi = hi;
  if (end - begin <= detail::kLeafSize) {
    nodes_[static_cast<std::size_t>(index)].first = begin;
    nodes_[static_cast<std::size_t>(index)].count = end - begin;
    return index;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int mid = (begin + end) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
                   [&](int x, int y) { return centers[static_cast<std::size_t>(x)](axis) < centers[static_cast<std::size_t>(y)](axis); });
  const int left = build(begin, mid, centers);
  const int right = build(mid, end, centers);
  nodes_[static_cast<std::size_t>(index)].left = left;
  nodes_[static_cast<std::size_t>(index)].right = right;
  return index;
}

BEMSURG_INLINE void TriangleBvh::refit(const RowMatrixX3d& vertices) {
  if (vertices.rows() != vertices_.rows())
    throw InvalidMeshError("TriangleBvh::refit: " + std::to_string(vertices.rows()) + " vertices given, the hierarchy has " +
                           std::to_string(vertices_.rows()));
  if (!vertices.allFinite()) throw InvalidMeshError("TriangleBvh::refit: a vertex is not finite");
  vertices_ = vertices;
  // Children have larger indices than their parent (depth-first build): sweep backwards.
  for (std::size_t i = nodes_.size(); i-- > 0;) {
    Node& n = nodes_[i];
    if (n.left < 0) {
      n.lo.setConstant(std::numeric_limits<double>::infinity());
      n.hi = -n.lo;
      for (int k = n.first; k < n.first + n.count; ++k) {
        Eigen::Vector3d tlo, thi;
        triangle_box(order_[static_cast<std::size_t>(k)], tlo, thi);
        n.lo = n.lo.cwiseMin(tlo);
        n.hi = n.hi.cwiseMax(thi);
      }
    } else {
      n.lo = nodes_[static_cast<std::size_t>(n.left)].lo.cwiseMin(nodes_[static_cast<std::size_t>(n.right)].lo);
      n.hi = nodes_[static_cast<std::size_t>(n.left)].hi.cwiseMax(nodes_[static_cast<std::size_t>(n.right)].hi);
    }
  }
}

BEMSURG_INLINE bool TriangleBvh::intersect_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, RayHit& hit, double t_max,
                                               bool front_only) const {
  detail::g_nodes_visited = 0;
  hit = RayHit();
  if (nodes_.empty() || !(direction.squaredNorm() > 0.0) || !direction.allFinite() || !origin.allFinite()) return false;
  const Eigen::Vector3d inv_d = direction.cwiseInverse();
  int stack[detail::kStackSize];
  int top = 0;
  stack[top++] = 0;
  double best = t_max;
  const double t_min = 0.0;
  while (top > 0) {
    const Node& n = nodes_[static_cast<std::size_t>(stack[--top])];
    ++detail::g_nodes_visited;
    if (!detail::ray_box(origin, inv_d, n.lo, n.hi, t_min, best)) continue;
    if (n.left >= 0) {
      if (top + 2 > detail::kStackSize) continue;  // cannot happen for depth < 64 (median split: log2 E)
      stack[top++] = n.right;
      stack[top++] = n.left;
      continue;
    }
    for (int k = n.first; k < n.first + n.count; ++k) {
      const Index f = order_[static_cast<std::size_t>(k)];
      const Eigen::Vector3d a = vertices_.row(faces_(f, 0)).transpose();
      const Eigen::Vector3d e1 = vertices_.row(faces_(f, 1)).transpose() - a;
      const Eigen::Vector3d e2 = vertices_.row(faces_(f, 2)).transpose() - a;
      // Moller-Trumbore.
      const Eigen::Vector3d p = direction.cross(e2);
      const double det = e1.dot(p);
      const bool front = det > 0.0;  // direction . (e1 x e2) < 0: entering through the outer side
      if (front_only && !front) continue;
      if (std::abs(det) < 1e-300) continue;
      const double inv = 1.0 / det;
      const Eigen::Vector3d s = origin - a;
      const double u = s.dot(p) * inv;
      if (u < 0.0 || u > 1.0) continue;
      const Eigen::Vector3d q = s.cross(e1);
      const double v = direction.dot(q) * inv;
      if (v < 0.0 || u + v > 1.0) continue;
      const double t = e2.dot(q) * inv;
      if (t < t_min || t > best) continue;
      best = t;
      hit.element = f;
      hit.t = t;
      hit.u = u;
      hit.v = v;
      hit.front_facing = front;
    }
  }
  if (hit.element < 0) return false;
  hit.point = origin + hit.t * direction;
  return true;
}

BEMSURG_INLINE bool TriangleBvh::intersect_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, RayHit& hit, bool front_only) const {
  return intersect_ray(a, b - a, hit, 1.0, front_only);
}

BEMSURG_INLINE Index TriangleBvh::query_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<Index>& out,
                                            bool no_grow) const {
  detail::g_nodes_visited = 0;
  Index found = 0;
  if (nodes_.empty()) return 0;
  int stack[detail::kStackSize];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& n = nodes_[static_cast<std::size_t>(stack[--top])];
    ++detail::g_nodes_visited;
    if ((n.lo.array() > hi.array()).any() || (n.hi.array() < lo.array()).any()) continue;
    if (n.left >= 0) {
      if (top + 2 > detail::kStackSize) continue;
      stack[top++] = n.right;
      stack[top++] = n.left;
      continue;
    }
    for (int k = n.first; k < n.first + n.count; ++k) {
      const Index f = order_[static_cast<std::size_t>(k)];
      Eigen::Vector3d tlo, thi;
      triangle_box(f, tlo, thi);
      if ((tlo.array() > hi.array()).any() || (thi.array() < lo.array()).any()) continue;
      ++found;
      if (no_grow && out.size() >= out.capacity()) continue;
      out.push_back(f);
    }
  }
  return found;
}

BEMSURG_INLINE RowMatrixX3d deformed_vertices(const TriangleMesh& mesh, const Eigen::VectorXd& element_displacement) {
  if (element_displacement.size() != mesh.num_dofs())
    throw InvalidArgumentError("deformed_vertices: " + std::to_string(element_displacement.size()) + " displacement entries, expected " +
                               std::to_string(mesh.num_dofs()));
  const RowMatrixX3d per_element = Eigen::Map<const RowMatrixX3d>(element_displacement.data(), mesh.num_elements(), 3);
  return mesh.vertices() + mesh.element_to_vertex(per_element);
}

}  // namespace bemsurg
