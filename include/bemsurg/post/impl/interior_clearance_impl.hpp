// Implementation of bemsurg/post/interior_clearance.hpp.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "bemsurg/number_text.hpp"

namespace bemsurg {

BEMSURG_INLINE double min_clearance_fraction(const QuadratureOptions& options) {
  return 2.0 * options.mid_ratio * std::ldexp(1.0, -options.max_depth);
}

BEMSURG_INLINE double min_stress_clearance_fraction(const QuadratureOptions& options) {
  return std::max(kMinStressClearanceFraction, min_clearance_fraction(options));
}

BEMSURG_INLINE ClearanceViolation find_point_too_close(const TriangleMesh& mesh, const RowMatrixX3d& points,
                                                       const QuadratureOptions& options, ClearanceQuantity quantity) {
  const bool stress = quantity == ClearanceQuantity::Stress;
  const double fraction = stress ? min_stress_clearance_fraction(options) : min_clearance_fraction(options);
  ClearanceViolation v;
  v.quantity = quantity;
  for (Index k = 0; k < points.rows(); ++k) {
    const Eigen::Vector3d p = points.row(k).transpose();
    double worst = 1.0;  // distance / required of the closest call so far; < 1 is a violation
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const auto c = mesh.corners(e);
      const double h = element_diameter(c[0], c[1], c[2]);
      const double required = fraction * h;
      // Every point of the triangle lies within h of its centroid: a cheap rejection first.
      if ((p - mesh.centroid(e)).norm() - h >= required) continue;
      const double d = point_triangle_distance(p, c[0], c[1], c[2]);
      if (d < worst * required) {
        worst = d / required;
        v = {k, e, d, h, required, quantity};
      }
    }
    if (v.point >= 0) return v;
  }
  return v;
}

BEMSURG_INLINE std::string describe_clearance_violation(const ClearanceViolation& v, const QuadratureOptions& options) {
  std::ostringstream s;
  use_classic_locale(s).precision(3);
  if (v.quantity == ClearanceQuantity::Stress && v.required > min_clearance_fraction(options) * v.element_size) {
    s << "is " << v.distance << " from element " << v.element << " (longest edge " << v.element_size << "), closer than "
      << min_stress_clearance_fraction(options) << " x " << v.element_size << " = " << v.required
      << ", where the stress of constant elements is wrong (its error grows like h / distance next to element edges and "
         "vertices; docs/stability.md); evaluate only the displacement there (allowed down to "
      << min_clearance_fraction(options) << " x the edge), move the point further inside, or refine the mesh near it";
    return s.str();
  }
  s << "is " << v.distance << " from element " << v.element << " (longest edge " << v.element_size << "), closer than "
    << min_clearance_fraction(options) << " x " << v.element_size << " = " << v.required << ", where the quadrature (mid_ratio "
    << options.mid_ratio << ", max_depth " << options.max_depth
    << ") cannot resolve the near-singular integrals; move it further inside, or raise quadrature.max_depth "
       "(each level halves the distance; docs/design.md §4)";
  return s.str();
}

}  // namespace bemsurg
