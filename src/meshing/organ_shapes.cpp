// The liver-like and kidney-like signed functions (bemsurg/meshing/organ_shapes.hpp).
#include "bemsurg/meshing/organ_shapes.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/liver_model.hpp"

namespace bemsurg {

double smooth_min(double a, double b, double k) {
  const double s = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * k * s * s;
}

double smooth_max(double a, double b, double k) { return -smooth_min(-a, -b, k); }

namespace detail {

/// Signed distance to the ellipsoid |(x - c) / a| = 1, to first order near its surface: (|q| - 1)
/// over the gradient's length of |q|, q = (x - c) / a.
double ellipsoid_function(const Vec3& x, const Vec3& centre, const Vec3& semi_axes) {
  const Vec3 q = (x - centre).cwiseQuotient(semi_axes);
  const double r = q.norm(), g = q.cwiseQuotient(semi_axes).norm();
  if (!(g > 1e-12 / semi_axes.minCoeff())) return -semi_axes.minCoeff();
  return (r - 1.0) * r / g;
}

/// The support and operating points of an organ, found along rays from a point inside it.
void place_organ_regions(OrganShape& organ, const Vec3& inside, const Vec3& support_direction, const Vec3& operating_direction,
                         double reach) {
  organ.support_center = implicit_ray_crossing(organ.signed_function, inside, support_direction, reach);
  organ.operating_center = implicit_ray_crossing(organ.signed_function, inside, operating_direction, reach);
}

}  // namespace detail

OrganShape liver_shape(const LiverShapeOptions& options) {
  if (!(options.size.allFinite() && (options.size.array() > 0.0).all()))
    throw InvalidMeshError("liver_shape: size must be three positive lengths");
  LiverModelOptions model;
  model.size = options.size;
  OrganShape organ;
  const double r0 = liver_surface_point(model, Vec3::UnitZ()).norm();
  organ.signed_function = [model, r0](const Vec3& x) {
    const double r = x.norm();
    return r > 0.0 ? r - liver_surface_point(model, x).norm() : -r0;
  };
  // The lobes reach 0.52 size.x to the left and the smooth union swells them by up to 2^(1/6).
  organ.box_lo = -0.7 * options.size;
  organ.box_hi = 0.7 * options.size;
  detail::place_organ_regions(organ, Vec3::Zero(), Vec3(0.0, 1.0, 1.0), Vec3(0.5, -1.0, 0.3), options.size.norm());
  organ.support_radius = 0.3 * options.size.y();
  organ.operating_radius = 0.15 * options.size.y();
  return organ;
}

OrganShape kidney_shape(const KidneyShapeOptions& options) {
  const KidneyShapeOptions& o = options;
  if (!(o.size.allFinite() && (o.size.array() > 0.0).all())) throw InvalidMeshError("kidney_shape: size must be three positive lengths");
  if (!(o.hilum_depth > 0.0 && o.hilum_depth < 1.0 && o.hilum_radius > 0.0 && o.hilum_radius < 1.0))
    throw InvalidMeshError("kidney_shape: hilum_depth and hilum_radius must be fractions between 0 and 1");
  if (!(std::isfinite(o.blend) && o.blend > 0.0)) throw InvalidMeshError("kidney_shape: blend must be a positive length");
  const Vec3 semi_axes = 0.5 * o.size;
  const double radius = o.hilum_radius * o.size.z();
  // The sphere reaches hilum_depth * size.x into the ellipsoid from its medial extreme.
  const Vec3 hilum(-semi_axes.x() - radius + o.hilum_depth * o.size.x(), 0.0, 0.0);
  OrganShape organ;
  organ.signed_function = [semi_axes, hilum, radius, blend = o.blend](const Vec3& x) {
    const double body = detail::ellipsoid_function(x, Vec3::Zero(), semi_axes);
    const double sphere = (x - hilum).norm() - radius;
    return smooth_max(body, -sphere, blend);
  };
  organ.box_lo = -0.6 * o.size;
  organ.box_hi = 0.6 * o.size;
  // A point inside the bean on the lateral side of the hilum: rays from it reach both sides.
  const Vec3 inside(0.2 * o.size.x(), 0.0, 0.0);
  detail::place_organ_regions(organ, inside, Vec3(-1.0, 1.0, 0.0), Vec3(0.0, -1.0, 0.2), o.size.norm());
  organ.support_radius = 0.35 * o.size.z();
  organ.operating_radius = 0.15 * o.size.z();
  return organ;
}

OrganShape organ_shape(const std::string& name) {
  if (name == "liver") return liver_shape();
  if (name == "kidney") return kidney_shape();
  throw InvalidArgumentError("unknown organ shape '" + name + "' (known: liver, kidney)");
}

}  // namespace bemsurg
