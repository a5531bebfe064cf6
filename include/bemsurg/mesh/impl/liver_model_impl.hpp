// The radial function of the liver-like surface (mesh/liver_model.hpp) and its icosphere mesh.
#pragma once

#include "bemsurg/config.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "bemsurg/mesh/impl/mesh_generators_impl.hpp"  // detail::unit_icosphere, detail::to_mesh
#include "bemsurg/mesh/liver_model.hpp"

namespace bemsurg {

namespace detail {

/// One lobe: an ellipsoid as fractions of the overall size (centre and semi-axes).
struct LiverLobe {
  Vec3 centre, semi_axes;
};
// Right lobe: large and rounded; left lobe: longer towards -x, thinner and set a little higher.
// Both contain the origin, so each is seen from it along every direction exactly once.
BEMSURG_INLINE LiverLobe liver_right_lobe(const Vec3& size) {
  return {Vec3(0.12 * size.x(), 0.0, 0.0), Vec3(0.38 * size.x(), 0.48 * size.y(), 0.44 * size.z())};
}
BEMSURG_INLINE LiverLobe liver_left_lobe(const Vec3& size) {
  return {Vec3(-0.2 * size.x(), -0.05 * size.y(), 0.08 * size.z()), Vec3(0.32 * size.x(), 0.34 * size.y(), 0.26 * size.z())};
}

/// Distance from the origin (inside the ellipsoid) to its surface along unit direction d: the
/// positive root of |(t d - c) / a|^2 = 1.
BEMSURG_INLINE double ray_to_ellipsoid(const LiverLobe& e, const Vec3& d) {
  const Vec3 da = d.cwiseQuotient(e.semi_axes), ca = e.centre.cwiseQuotient(e.semi_axes);
  const double A = da.squaredNorm(), B = da.dot(ca), C = ca.squaredNorm() - 1.0;  // C < 0: origin inside
  return (B + std::sqrt(B * B - A * C)) / A;
}

BEMSURG_INLINE double liver_radius(const Vec3& size, const Vec3& d) {
  constexpr double p = 6.0;  // the smooth maximum's exponent: a rounded notch between the lobes
  const double r1 = ray_to_ellipsoid(liver_right_lobe(size), d), r2 = ray_to_ellipsoid(liver_left_lobe(size), d);
  return std::pow(std::pow(r1, p) + std::pow(r2, p), 1.0 / p);
}

BEMSURG_INLINE void check_liver_options(const LiverModelOptions& o) {
  if (!(o.size.allFinite() && (o.size.array() > 0.0).all())) throw InvalidMeshError("liver_mesh: size must be three positive lengths");
  if (o.subdivisions < 0 || o.subdivisions > 7)
    throw InvalidMeshError("liver_mesh: subdivisions must lie in 0..7, got " + std::to_string(o.subdivisions));
}

}  // namespace detail

BEMSURG_INLINE Vec3 liver_surface_point(const LiverModelOptions& options, const Vec3& direction) {
  detail::check_liver_options(options);
  if (!(direction.allFinite() && direction.norm() > 0.0))
    throw InvalidArgumentError("liver_surface_point: direction must be a non-zero finite vector");
  const Vec3 d = direction.normalized();
  return detail::liver_radius(options.size, d) * d;
}

BEMSURG_INLINE TriangleMesh liver_mesh(const LiverModelOptions& options) {
  detail::check_liver_options(options);
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;
  detail::unit_icosphere(options.subdivisions, v, f);
  for (Vec3& p : v) {
    const Vec3 d = p.normalized();
    p = detail::liver_radius(options.size, d) * d;
  }
  return detail::to_mesh(v, f);
}

}  // namespace bemsurg
