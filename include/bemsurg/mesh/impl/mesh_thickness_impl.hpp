// Implementation of bemsurg/mesh/mesh_thickness.hpp.
#pragma once

#include "bemsurg/config.hpp"

#include <cmath>

#include "bemsurg/mesh/bvh.hpp"

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

}  // namespace bemsurg
