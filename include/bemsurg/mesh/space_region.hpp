// bemsurg/mesh/space_region.hpp: a region of space bounded by planes and at most one sphere (what a
// boundary rule's sphere, box and plane selectors describe), and the exact area of a surface mesh
// inside it (issue 38: "every solve says what it held"; docs/scene-format.md, "boundary_rules").
//
// The region is the intersection of half-spaces n . x <= d (a box is six, a plane's slab of
// tolerance tol is two) and, optionally, a closed ball. The area inside is exact up to rounding:
// each flat triangle is clipped by the half-spaces (a convex polygon), and the polygon is cut
// with the disc the ball leaves in the triangle's plane by the usual sum over the polygon's edges
// of the signed area of (centre, edge) within the disc (straight parts and circular sectors).
// Selectors test centroids (io/element_selector.hpp); this is what the region itself covers.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// The points x with n . x <= offset. \ingroup mesh
struct HalfSpace {
  Vec3 normal = Vec3::UnitZ();
  double offset = 0.0;
};

/// The intersection of half-spaces and, when has_ball, the closed ball |x - center| <= radius.
/// An empty list and no ball is all of space. \ingroup mesh
struct SpaceRegion {
  std::vector<HalfSpace> half_spaces;
  bool has_ball = false;
  Vec3 center = Vec3::Zero();
  double radius = 0.0;

  static SpaceRegion ball(const Vec3& c, double r) {
    SpaceRegion s;
    s.has_ball = true;
    s.center = c;
    s.radius = r;
    return s;
  }
  static SpaceRegion box(const Vec3& lo, const Vec3& hi) {
    SpaceRegion s;
    for (int k = 0; k < 3; ++k) {
      s.half_spaces.push_back({Vec3::Unit(k), hi(k)});
      s.half_spaces.push_back({-Vec3::Unit(k), -lo(k)});
    }
    return s;
  }
  /// The slab within `tolerance` of the plane through `point` with normal `normal` (any length > 0).
  static SpaceRegion slab(const Vec3& point, const Vec3& normal, double tolerance) {
    const Vec3 n = normal.normalized();
    SpaceRegion s;
    s.half_spaces.push_back({n, n.dot(point) + tolerance});
    s.half_spaces.push_back({-n, -n.dot(point) + tolerance});
    return s;
  }
  /// The intersection of this region and `other` (at most one of them may hold a ball).
  SpaceRegion intersected(const SpaceRegion& other) const {
    SpaceRegion s = *this;
    s.half_spaces.insert(s.half_spaces.end(), other.half_spaces.begin(), other.half_spaces.end());
    if (other.has_ball) {
      s.has_ball = true;
      s.center = other.center;
      s.radius = other.radius;
    }
    return s;
  }

  /// A level function of the region: negative inside, zero on its boundary, positive outside, and
  /// continuous (the largest of the half-spaces' signed distances and the ball's). Its zero set is
  /// where conforming splits cut (mesh/conforming_split.hpp).
  double level(const Vec3& x) const {
    double f = has_ball ? (x - center).norm() - radius : -std::numeric_limits<double>::infinity();
    for (const HalfSpace& h : half_spaces) f = std::max(f, h.normal.dot(x) - h.offset);
    return f;
  }
  bool contains(const Vec3& x) const { return level(x) <= 0.0; }
};

namespace detail::space_region {

/// Sutherland-Hodgman: the part of the convex polygon `p` with n . x <= offset.
inline std::vector<Vec3> clip(const std::vector<Vec3>& p, const HalfSpace& h) {
  std::vector<Vec3> out;
  const std::size_t m = p.size();
  for (std::size_t i = 0; i < m; ++i) {
    const Vec3& a = p[i];
    const Vec3& b = p[(i + 1) % m];
    const double fa = h.normal.dot(a) - h.offset, fb = h.normal.dot(b) - h.offset;
    if (fa <= 0.0) out.push_back(a);
    if ((fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0)) out.push_back(a + (fa / (fa - fb)) * (b - a));
  }
  return out;
}

/// Signed area of the triangle (0, a, b) inside the disc of radius r about 0 (2-D).
inline double center_triangle_in_disc(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double r) {
  const auto cross = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) { return u.x() * v.y() - u.y() * v.x(); };
  // Points where the segment a -> b meets the circle split it into parts wholly inside or outside.
  const Eigen::Vector2d d = b - a;
  const double A = d.squaredNorm(), B = 2.0 * a.dot(d), C = a.squaredNorm() - r * r;
  std::array<double, 4> t{0.0, 1.0, 1.0, 1.0};
  int count = 1;
  const double disc = B * B - 4.0 * A * C;
  // A line that misses or only touches the circle leaves the segment outside it: one sector (a
  // midpoint test on a tangent segment would count it as a straight triangle).
  if (A > 0.0 && !(disc > 0.0)) return 0.5 * r * r * std::atan2(cross(a, b), a.dot(b));
  if (A > 0.0 && disc > 0.0) {
    const double s = std::sqrt(disc);
    for (const double root : {(-B - s) / (2.0 * A), (-B + s) / (2.0 * A)})
      if (root > 0.0 && root < 1.0) t[static_cast<std::size_t>(count++)] = root;
  }
  t[static_cast<std::size_t>(count++)] = 1.0;
  double area = 0.0;
  for (int i = 0; i + 1 < count; ++i) {
    const Eigen::Vector2d p = a + t[static_cast<std::size_t>(i)] * d, q = a + t[static_cast<std::size_t>(i + 1)] * d;
    const Eigen::Vector2d mid = 0.5 * (p + q);
    if (mid.squaredNorm() < r * r)
      area += 0.5 * cross(p, q);
    else
      area += 0.5 * r * r * std::atan2(cross(p, q), p.dot(q));
  }
  return area;
}

}  // namespace detail::space_region

/// The area of the flat triangle (a, b, c) inside `region` (exact up to rounding).
inline double triangle_area_inside(const Vec3& a, const Vec3& b, const Vec3& c, const SpaceRegion& region) {
  std::vector<Vec3> poly{a, b, c};
  for (const HalfSpace& h : region.half_spaces) {
    poly = detail::space_region::clip(poly, h);
    if (poly.size() < 3) return 0.0;
  }
  const Vec3 n_raw = (b - a).cross(c - a);
  if (n_raw.norm() == 0.0) return 0.0;
  if (!region.has_ball) {
    Vec3 s = Vec3::Zero();
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) s += (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]);
    return 0.5 * s.norm();
  }
  const Vec3 n = n_raw.normalized();
  const double dz = n.dot(region.center - a);
  if (std::abs(dz) >= region.radius) return 0.0;
  const double rho = std::sqrt(region.radius * region.radius - dz * dz);
  const Vec3 c2 = region.center - dz * n;  // the disc's centre in the triangle's plane
  const Vec3 u = (b - a).normalized(), v = n.cross(u);
  double area = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec3 p = poly[i] - c2, q = poly[(i + 1) % poly.size()] - c2;
    area += detail::space_region::center_triangle_in_disc({p.dot(u), p.dot(v)}, {q.dot(u), q.dot(v)}, rho);
  }
  return std::abs(area);
}

/// The area of `mesh` inside `region`.
inline double area_inside(const TriangleMesh& mesh, const SpaceRegion& region) {
  double total = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const std::array<Vec3, 3> c = mesh.corners(e);
    total += triangle_area_inside(c[0], c[1], c[2], region);
  }
  return total;
}

}  // namespace bemsurg
