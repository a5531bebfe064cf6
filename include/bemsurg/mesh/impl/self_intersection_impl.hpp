// Implementation of bemsurg/mesh/self_intersection.hpp: exact-in-spirit triangle-triangle tests
// with a length tolerance, and a BVH sweep over candidate pairs.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "bemsurg/mesh/bvh.hpp"

namespace bemsurg {

namespace detail {

struct SiTriangle {
  Vec3 a, b, c;
  Vec3 unit_normal;  // zero for a degenerate triangle
};

BEMSURG_INLINE SiTriangle si_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  return {a, b, c, len > 0.0 ? Vec3(n / len) : Vec3(Vec3::Zero())};
}

BEMSURG_INLINE double si_plane_distance(const SiTriangle& t, const Vec3& p) { return t.unit_normal.dot(p - t.a); }

// Distance between segments [p0, p1] and [q0, q1] (closest points, clamped; Ericson §5.1.9).
BEMSURG_INLINE double si_segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 0.0 && e <= 0.0) return r.norm();
  if (a <= 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return ((p0 + s * d1) - (q0 + t * d2)).norm();
}

// p (assumed in or near the triangle's plane) lies inside the triangle or within tol of it.
BEMSURG_INLINE bool si_point_in_triangle(const SiTriangle& t, const Vec3& p, double tol) {
  const std::array<Vec3, 3> v{{t.a, t.b, t.c}};
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = v[(k + 1) % 3] - v[k];
    const double len = e.norm();
    if (len <= 0.0) return false;
    // n x e points into the triangle for a counter-clockwise triangle.
    if (t.unit_normal.cross(e).dot(p - v[k]) / len < -tol) return false;
  }
  return true;
}

// Segment [p, q] meets the triangle (touching within tol counts).
BEMSURG_INLINE bool si_segment_triangle(const Vec3& p, const Vec3& q, const SiTriangle& t, double tol) {
  if (t.unit_normal.isZero()) return false;  // degenerate: validation reports it, not this test
  const double dp = si_plane_distance(t, p), dq = si_plane_distance(t, q);
  if ((dp > tol && dq > tol) || (dp < -tol && dq < -tol)) return false;
  if (std::abs(dp) <= tol && std::abs(dq) <= tol) {
    // In the plane: an end inside, or the segment within tol of an edge.
    if (si_point_in_triangle(t, p, tol) || si_point_in_triangle(t, q, tol)) return true;
    return si_segment_distance(p, q, t.a, t.b) <= tol || si_segment_distance(p, q, t.b, t.c) <= tol ||
           si_segment_distance(p, q, t.c, t.a) <= tol;
  }
  const double s = std::clamp(dp / (dp - dq), 0.0, 1.0);
  return si_point_in_triangle(t, p + s * (q - p), tol);
}

}  // namespace detail

BEMSURG_INLINE bool faces_intersect(const TriangleMesh& mesh, Index f, Index g, double tol) {
  if (f == g) return false;
  const auto& F = mesh.faces();
  std::array<int, 3> fi{{F(f, 0), F(f, 1), F(f, 2)}}, gi{{F(g, 0), F(g, 1), F(g, 2)}};
  int shared = 0;
  for (int a : fi)
    for (int b : gi) shared += a == b ? 1 : 0;
  if (shared >= 3) return true;  // the same triangle twice
  const auto tf = detail::si_triangle(mesh.vertex(fi[0]), mesh.vertex(fi[1]), mesh.vertex(fi[2]));
  const auto tg = detail::si_triangle(mesh.vertex(gi[0]), mesh.vertex(gi[1]), mesh.vertex(gi[2]));
  // Vertices of `x` not in `y`, in corner order.
  auto own = [](const std::array<int, 3>& x, const std::array<int, 3>& y) {
    std::vector<int> out;
    for (int a : x)
      if (std::find(y.begin(), y.end(), a) == y.end()) out.push_back(a);
    return out;
  };
  if (shared == 2) {
    // Folded onto each other: g's third vertex in f's plane, on the side of f's third vertex.
    const Vec3 a = mesh.vertex(own(fi, gi)[0]), b = mesh.vertex(own(gi, fi)[0]);
    if (tf.unit_normal.isZero() || std::abs(detail::si_plane_distance(tf, b)) > tol) return false;
    std::vector<int> common;
    for (int x : fi)
      if (std::find(gi.begin(), gi.end(), x) != gi.end()) common.push_back(x);
    const Vec3 p = mesh.vertex(common[0]), e = mesh.vertex(common[1]) - p;
    const Vec3 side = tf.unit_normal.cross(e);
    return side.dot(a - p) * side.dot(b - p) > 0.0;
  }
  if (shared == 1) {
    const auto fo = own(fi, gi), go = own(gi, fi);
    return detail::si_segment_triangle(mesh.vertex(go[0]), mesh.vertex(go[1]), tf, tol) ||
           detail::si_segment_triangle(mesh.vertex(fo[0]), mesh.vertex(fo[1]), tg, tol);
  }
  for (int k = 0; k < 3; ++k) {
    if (detail::si_segment_triangle(mesh.vertex(gi[k]), mesh.vertex(gi[(k + 1) % 3]), tf, tol)) return true;
    if (detail::si_segment_triangle(mesh.vertex(fi[k]), mesh.vertex(fi[(k + 1) % 3]), tg, tol)) return true;
  }
  return false;
}

namespace detail {
BEMSURG_INLINE std::vector<std::pair<Index, Index>> si_search(const TriangleMesh& mesh, const std::vector<Index>* subset,
                                                              const SelfIntersectionOptions& options) {
  std::vector<std::pair<Index, Index>> pairs;
  if (mesh.num_elements() < 2) return pairs;
  const auto box = mesh.bounding_box();
  const double tol = options.tolerance * (box.col(1) - box.col(0)).norm();
  const TriangleBvh bvh(mesh);
  std::vector<Index> queries;
  if (subset) {
    queries = *subset;
    std::sort(queries.begin(), queries.end());
    queries.erase(std::unique(queries.begin(), queries.end()), queries.end());
  } else {
    queries.resize(static_cast<std::size_t>(mesh.num_elements()));
    for (Index f = 0; f < mesh.num_elements(); ++f) queries[static_cast<std::size_t>(f)] = f;
  }
  std::vector<char> in_subset;
  if (subset) {
    in_subset.assign(static_cast<std::size_t>(mesh.num_elements()), 0);
    for (Index f : queries) in_subset.at(static_cast<std::size_t>(f)) = 1;
  }
  std::vector<Index> hits;
  for (Index f : queries) {
    const auto c = mesh.corners(f);
    const Vec3 lo = c[0].cwiseMin(c[1]).cwiseMin(c[2]).array() - tol;
    const Vec3 hi = c[0].cwiseMax(c[1]).cwiseMax(c[2]).array() + tol;
    hits.clear();
    bvh.query_box(lo, hi, hits);
    for (Index g : hits) {
      if (g == f) continue;
      // Each unordered pair once: the global sweep keeps g > f; the subset sweep keeps a pair of
      // two subset faces only from its lower face.
      if (!subset && g < f) continue;
      if (subset && in_subset[static_cast<std::size_t>(g)] && g < f) continue;
      if (!faces_intersect(mesh, f, g, tol)) continue;
      pairs.emplace_back(std::min(f, g), std::max(f, g));
      if (options.max_pairs && pairs.size() >= options.max_pairs) break;
    }
    if (options.max_pairs && pairs.size() >= options.max_pairs) break;
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}
}  // namespace detail

BEMSURG_INLINE std::vector<std::pair<Index, Index>> find_self_intersections(const TriangleMesh& mesh,
                                                                            const SelfIntersectionOptions& options) {
  return detail::si_search(mesh, nullptr, options);
}

BEMSURG_INLINE std::vector<std::pair<Index, Index>> find_self_intersections(const TriangleMesh& mesh, const std::vector<Index>& faces,
                                                                            const SelfIntersectionOptions& options) {
  for (Index f : faces)
    if (f < 0 || f >= mesh.num_elements())
      throw InvalidArgumentError("find_self_intersections: face " + std::to_string(f) + " does not exist (the mesh has " +
                                 std::to_string(mesh.num_elements()) + " faces)");
  return detail::si_search(mesh, &faces, options);
}

}  // namespace bemsurg
