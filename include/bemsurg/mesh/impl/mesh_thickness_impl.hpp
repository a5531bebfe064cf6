// Implementation of bemsurg/mesh/mesh_thickness.hpp.
#pragma once

#include "bemsurg/config.hpp"

#include <cmath>

#include "bemsurg/mesh/bvh.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

BEMSURG_INLINE ThinElements find_thin_elements(const TriangleMesh& mesh) {
  ThinElements out;
  if (mesh.num_elements() == 0) return out;
  const TriangleBvh bvh(mesh);
  double worst = 1.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const double size = std::sqrt(2.0 * mesh.area(e));
    if (!(size > 0.0) || !std::isfinite(size)) continue;  // degenerate: the validator's business
    // Start just inside the face so that the face itself is not hit.
    const Eigen::Vector3d inward = -mesh.normal(e);
    const Eigen::Vector3d origin = mesh.centroid(e) + 1e-9 * size * inward;
    RayHit hit;
    if (!bvh.intersect_ray(origin, inward, hit, 4.0 * size)) continue;  // thicker than 4 sizes here
    const double thickness = hit.t + 1e-9 * size;
    if (!(size > (1.0 + 1e-6) * thickness)) continue;  // a one-division cube is exactly as thick as its elements
    ++out.count;
    if (size / thickness > worst) {
      worst = size / thickness;
      out.element = e;
      out.size = size;
      out.thickness = thickness;
    }
  }
  return out;
}

BEMSURG_INLINE std::string thin_elements_warning(const ThinElements& thin) {
  if (thin.count == 0) return std::string();
  return std::to_string(thin.count) + " elements are larger than the body is thick under them (element " + std::to_string(thin.element) +
         ": size " + general_text(thin.size, 3) + ", thickness " + general_text(thin.thickness, 3) +
         " along its inward normal); constant elements cannot resolve a part thinner than themselves and the results there may be far "
         "off: refine the mesh to elements no larger than the thickness, and to " +
         general_text(kBendingAccurateThicknessPerElement, 3) +
         " elements across it where the part bends (10 % accuracy, docs/stability.md)";
}

}  // namespace bemsurg
