// Implementation of bemsurg/post/interior_clearance.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace bemsurg {

inline double min_clearance_fraction(const QuadratureOptions& options) {
  return 2.0 * options.mid_ratio * std::ldexp(1.0, -options.max_depth);
}

inline Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                                 const Eigen::Vector3d& c) {
  // Voronoi regions of the vertices, then the edges, else the face (barycentric coordinates).
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

inline ClearanceViolation find_point_too_close(const TriangleMesh& mesh, const RowMatrixX3d& points,
                                               const QuadratureOptions& options) {
  const double fraction = min_clearance_fraction(options);
  ClearanceViolation v;
  for (Index k = 0; k < points.rows(); ++k) {
    const Eigen::Vector3d p = points.row(k).transpose();
    double worst = 1.0;  // distance / required of the closest call so far; < 1 is a violation
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const auto c = mesh.corners(e);
      const double h = std::sqrt(std::max({(c[1] - c[0]).squaredNorm(), (c[2] - c[1]).squaredNorm(), (c[0] - c[2]).squaredNorm()}));
      const double required = fraction * h;
      // Every point of the triangle lies within h of its centroid: a cheap rejection first.
      if ((p - mesh.centroid(e)).norm() - h >= required) continue;
      const double d = (p - closest_point_on_triangle(p, c[0], c[1], c[2])).norm();
      if (d < worst * required) {
        worst = d / required;
        v = {k, e, d, h, required};
      }
    }
    if (v.point >= 0) return v;
  }
  return v;
}

inline std::string describe_clearance_violation(const ClearanceViolation& v, const QuadratureOptions& options) {
  std::ostringstream s;
  s.precision(3);
  s << "is " << v.distance << " from element " << v.element << " (longest edge " << v.element_size << "), closer than "
    << min_clearance_fraction(options) << " x " << v.element_size << " = " << v.required
    << ", where the quadrature (mid_ratio " << options.mid_ratio << ", max_depth " << options.max_depth
    << ") cannot resolve the near-singular integrals; move it further inside, or raise quadrature.max_depth "
       "(each level halves the distance; docs/design.md §4)";
  return s.str();
}

}  // namespace bemsurg
