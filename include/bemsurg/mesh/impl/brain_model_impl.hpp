// The radial function of the brain-like surface (mesh/brain_model.hpp) and its icosphere mesh.
#pragma once

#include "bemsurg/config.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/impl/mesh_generators_impl.hpp"  // detail::unit_icosphere, detail::to_mesh
#include "bemsurg/mesh/mesh_generators.hpp"

namespace bemsurg {

namespace detail {

// The flat underside cuts the ellipsoid this fraction of its vertical semi-axis below its centre:
// at 0.5 the rim meets the support at 55-65 degrees, a crease the remesher keeps as a feature.
BEMSURG_INLINE constexpr double kBrainClipFraction = 0.5;

BEMSURG_INLINE double smoothstep(double lo, double hi, double x) {
  const double t = std::min(1.0, std::max(0.0, (x - lo) / (hi - lo)));
  return t * t * (3.0 - 2.0 * t);
}

BEMSURG_INLINE void check_brain_options(const BrainModelOptions& o) {
  auto bad = [](const std::string& what) { throw InvalidMeshError("brain_mesh: " + what); };
  if (!(o.size.allFinite() && (o.size.array() > 0.0).all())) bad("size must be three positive lengths");
  if (!(o.fissure_depth >= 0.0 && o.fissure_depth < 0.8)) bad("fissure_depth must lie in [0, 0.8)");
  if (!(o.fissure_half_width > 0.0 && std::isfinite(o.fissure_half_width))) bad("fissure_half_width must be positive");
  if (!(o.fold_amplitude >= 0.0 && o.fold_amplitude < 0.2)) bad("fold_amplitude must lie in [0, 0.2)");
  if (!(o.fold_wavelength > 0.0 && std::isfinite(o.fold_wavelength))) bad("fold_wavelength must be positive");
  if (o.subdivisions < 0 || o.subdivisions > 7) bad("subdivisions must lie in 0..7, got " + std::to_string(o.subdivisions));
}

struct BrainFrame {
  Vec3 semi_axes;  // of the ellipsoid before clipping
  Vec3 centre;     // of the ellipsoid; the support plane z = 0 lies kBrainClipFraction * c below it
};

BEMSURG_INLINE BrainFrame brain_frame(const BrainModelOptions& o) {
  const double c = o.size.z() / (1.0 + kBrainClipFraction);
  return {Vec3(0.5 * o.size.x(), 0.5 * o.size.y(), c), Vec3(0.0, 0.0, kBrainClipFraction * c)};
}

// R(d): distance from the centre to the surface along unit direction d.
BEMSURG_INLINE double brain_radius(const BrainModelOptions& o, const BrainFrame& fr, const Vec3& d) {
  const Vec3 s = d.cwiseQuotient(fr.semi_axes);
  const double r_ellipsoid = 1.0 / s.norm();
  const Vec3 p0 = r_ellipsoid * d;  // the ellipsoid point, relative to the centre
  // Midline fissure: a Gaussian groove about the plane y = 0, deep on top, gone on the underside.
  const double fissure =
      o.fissure_depth * std::exp(-(p0.y() * p0.y()) / (o.fissure_half_width * o.fissure_half_width)) * smoothstep(-0.35, 0.25, d.z());
  // Gyri: a fixed sum of crossed sinusoids (no random numbers: bit-for-bit reproducible), mirror
  // symmetric about the midline (|y| smoothed so the surface stays smooth there), faded out
  // towards the underside so the rim and the support stay clean.
  const double k = 2.0 * numbers::pi / o.fold_wavelength;
  const double x = p0.x(), z = p0.z();
  const double y = std::sqrt(p0.y() * p0.y() + o.fissure_half_width * o.fissure_half_width);
  const double pattern = std::sin(k * x + 1.9 * std::sin(0.45 * k * z + 0.3)) * std::sin(k * z + 1.6 * std::sin(0.5 * k * y)) +
                         0.6 * std::sin(0.8 * k * (x + 0.7 * y) + 2.1 * std::cos(0.35 * k * z)) +
                         0.4 * std::cos(1.3 * k * y - 0.9 * std::sin(0.6 * k * x));
  const double folds = o.fold_amplitude * (pattern / 2.0) * smoothstep(-0.7, -0.2, d.z());
  double r = r_ellipsoid * (1.0 - fissure) * (1.0 + folds);
  // The flat underside: nothing below the support plane z = 0.
  if (d.z() < 0.0) r = std::min(r, fr.centre.z() / -d.z());
  return r;
}

}  // namespace detail

BEMSURG_INLINE Vec3 brain_surface_point(const BrainModelOptions& options, const Vec3& direction) {
  detail::check_brain_options(options);
  if (!(direction.allFinite() && direction.norm() > 0.0))
    throw InvalidArgumentError("brain_surface_point: direction must be a non-zero finite vector");
  const detail::BrainFrame fr = detail::brain_frame(options);
  const Vec3 d = direction.normalized();
  return fr.centre + detail::brain_radius(options, fr, d) * d;
}

BEMSURG_INLINE TriangleMesh brain_mesh(const BrainModelOptions& options) {
  detail::check_brain_options(options);
  const detail::BrainFrame fr = detail::brain_frame(options);
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;
  detail::unit_icosphere(options.subdivisions, v, f);
  for (Vec3& p : v) {
    const Vec3 d = p.normalized();
    p = fr.centre + detail::brain_radius(options, fr, d) * d;
    if (std::abs(p.z()) < 1e-15) p.z() = 0.0;  // exactly on the support plane
  }
  return detail::to_mesh(v, f);
}

}  // namespace bemsurg
