// Operating regions: construction, distance, membership (mesh/operating_region.hpp).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "bemsurg/number_text.hpp"

namespace bemsurg {

BEMSURG_INLINE OperatingRegion OperatingRegion::sphere(const Vec3& center, double radius) {
  if (!center.allFinite()) throw InvalidArgumentError("operating region: sphere centre is not finite");
  if (!(radius > 0.0 && std::isfinite(radius)))
    throw InvalidArgumentError("operating region: sphere radius must be positive, got " + number_text(radius));
  OperatingRegion r;
  r.kind_ = Kind::Sphere;
  r.center_ = center;
  r.radius_ = radius;
  return r;
}

BEMSURG_INLINE OperatingRegion OperatingRegion::box(const Vec3& lo, const Vec3& hi) {
  if (!(lo.allFinite() && hi.allFinite() && (lo.array() < hi.array()).all()))
    throw InvalidArgumentError("operating region: box needs min < max in every coordinate");
  OperatingRegion r;
  r.kind_ = Kind::Box;
  r.lo_ = lo;
  r.hi_ = hi;
  r.center_ = 0.5 * (lo + hi);
  return r;
}

BEMSURG_INLINE OperatingRegion OperatingRegion::element_set(const TriangleMesh& mesh, const std::vector<Index>& elements) {
  if (elements.empty()) throw InvalidArgumentError("operating region: the element set is empty");
  OperatingRegion r;
  r.kind_ = Kind::Elements;
  r.triangles_.resize(3 * static_cast<Index>(elements.size()), 3);
  Vec3 sum = Vec3::Zero();
  for (std::size_t i = 0; i < elements.size(); ++i) {
    const Index e = elements[i];
    if (e < 0 || e >= mesh.num_elements())
      throw InvalidArgumentError("operating region: element " + std::to_string(e) + " (entry " + std::to_string(i) +
                                 ") out of range (mesh has " + std::to_string(mesh.num_elements()) + " elements)");
    const auto c = mesh.corners(e);
    for (int k = 0; k < 3; ++k) r.triangles_.row(3 * static_cast<Index>(i) + k) = c[static_cast<std::size_t>(k)].transpose();
    sum += mesh.centroid(e);
  }
  r.center_ = sum / static_cast<double>(elements.size());
  r.lo_ = r.triangles_.colwise().minCoeff().transpose();
  r.hi_ = r.triangles_.colwise().maxCoeff().transpose();
  return r;
}

BEMSURG_INLINE double OperatingRegion::distance(const Vec3& x) const {
  switch (kind_) {
    case Kind::Sphere: return std::max(0.0, (x - center_).norm() - radius_);
    case Kind::Box: return (x - x.cwiseMax(lo_).cwiseMin(hi_)).norm();
    case Kind::Elements: {
      double best = std::numeric_limits<double>::infinity();
      for (Index t = 0; t < triangles_.rows(); t += 3) {
        const Vec3 q = closest_point_on_triangle(x, triangles_.row(t).transpose(), triangles_.row(t + 1).transpose(),
                                                 triangles_.row(t + 2).transpose());
        best = std::min(best, (x - q).squaredNorm());
      }
      return std::sqrt(best);
    }
  }
  return std::numeric_limits<double>::infinity();
}

BEMSURG_INLINE std::vector<Index> OperatingRegion::elements_of(const TriangleMesh& mesh, double slack) const {
  std::vector<Index> out;
  for (Index e = 0; e < mesh.num_elements(); ++e)
    if (distance(mesh.centroid(e)) <= slack) out.push_back(e);
  return out;
}

BEMSURG_INLINE void OperatingRegion::require_meets_surface(const TriangleMesh& mesh, double slack) const {
  if (mesh.num_elements() == 0) throw InvalidArgumentError("operating region: the mesh is empty");
  bool meets = false;
  if (kind_ == Kind::Sphere) {
    // Exact: the closest surface point to the centre lies within the radius.
    for (Index e = 0; e < mesh.num_elements() && !meets; ++e) {
      const auto c = mesh.corners(e);
      meets = distance(closest_point_on_triangle(center_, c[0], c[1], c[2])) <= slack;
    }
  } else if (kind_ == Kind::Box) {
    // Samples: vertices, centroids and edge midpoints (a box smaller than the elements and lying
    // inside one face is missed; such a box cannot be resolved by that mesh anyway).
    for (Index v = 0; v < mesh.num_vertices() && !meets; ++v) meets = distance(mesh.vertex(v)) <= slack;
    for (Index e = 0; e < mesh.num_elements() && !meets; ++e) {
      const auto c = mesh.corners(e);
      meets = distance(mesh.centroid(e)) <= slack || distance(0.5 * (c[0] + c[1])) <= slack || distance(0.5 * (c[1] + c[2])) <= slack ||
              distance(0.5 * (c[2] + c[0])) <= slack;
    }
  } else {
    meets = true;  // made of the surface's own elements (checked in element_set)
  }
  if (!meets)
    throw InvalidArgumentError("operating region: " + describe() + " does not meet the surface of the body (tools could never act there)");
}

BEMSURG_INLINE std::string OperatingRegion::describe() const {
  std::ostringstream s;
  use_classic_locale(s).precision(6);
  auto v = [&s](const Vec3& p) { s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")"; };
  switch (kind_) {
    case Kind::Sphere:
      s << "sphere (centre ";
      v(center_);
      s << ", radius " << radius_ << ")";
      break;
    case Kind::Box:
      s << "box (min ";
      v(lo_);
      s << ", max ";
      v(hi_);
      s << ")";
      break;
    case Kind::Elements: s << "element set (" << triangles_.rows() / 3 << " elements)"; break;
  }
  return s.str();
}

}  // namespace bemsurg
