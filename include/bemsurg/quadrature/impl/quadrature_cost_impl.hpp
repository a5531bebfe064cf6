// Implementation of bemsurg/quadrature/quadrature_cost.hpp (docs/design.md §4, §10).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

BEMSURG_INLINE QuadratureCostEstimate estimate_assembly_quadrature(const TriangleMesh& mesh, const QuadratureOptions& options,
                                                                   double limit_points, Index max_sampled_sources) {
  QuadratureCostEstimate est;
  const Index E = mesh.num_elements();
  if (E == 0) return est;
  const ElementQuadrature quadrature(options);
  const Index S = std::max<Index>(1, std::min(E, max_sampled_sources));
  const double scale = double(E) / double(S);
  // The self pair's polar rule: at most 2 pi / polar_max_angle + 3 pieces (one partial per edge).
  const double self_points = (2.0 * numbers::pi / options.polar_max_angle + 3.0) * options.polar_order;
  const double cap = limit_points / scale;  // the sampled count at which the estimate passes the limit
  double counted = 0.0;
  for (Index k = 0; k < S && counted <= cap; ++k) {
    const Index i = (k * E) / S;  // evenly spread over the elements (file order is often spatial)
    const Vec3 p = mesh.centroid(i);
    counted += self_points;
    for (Index j = 0; j < E && counted <= cap; ++j) {
      if (j == i) continue;
      const auto c = mesh.corners(j);
      counted += quadrature.count_points(p, c[0], c[1], c[2], cap - counted);
    }
    ++est.sampled_sources;
    // Projected over the remaining samples, already past the limit: stop (a lower bound).
    if (counted * double(S) / double(est.sampled_sources) > cap) break;
  }
  est.exceeded = counted * double(S) / double(est.sampled_sources) > cap;
  est.points = counted * double(S) / double(est.sampled_sources) * scale;
  est.points_per_pair = est.points / (double(E) * double(E));
  return est;
}

BEMSURG_INLINE void require_assembly_quadrature_within(const TriangleMesh& mesh, const QuadratureOptions& options, const std::string& who) {
  const QuadratureCostEstimate reference = estimate_assembly_quadrature(mesh, QuadratureOptions(), 1e300);
  const double limit = std::max(kQuadratureCostFloor, kQuadratureCostFactor * reference.points);
  const QuadratureCostEstimate est = estimate_assembly_quadrature(mesh, options, limit);
  if (!(est.points > limit)) return;
  std::ostringstream m;
  use_classic_locale(m).precision(3);
  m << who << ": the quadrature options (far_ratio " << options.far_ratio << ", mid_ratio " << options.mid_ratio << ", mid_order "
    << options.mid_order << ", max_depth " << options.max_depth << ") would take " << (est.exceeded ? "more than " : "about ") << est.points
    << " kernel evaluations on " << mesh.num_elements() << " elements (" << est.points_per_pair << " per element pair, against "
    << reference.points_per_pair << " with the default options), above the limit " << limit << " (the larger of " << kQuadratureCostFloor
    << " and " << kQuadratureCostFactor << " x the defaults' " << reference.points
    << "); lower mid_ratio (it drives the near-field splitting), max_depth or mid_order (docs/design.md §4)";
  throw ResourceError(m.str());
}

}  // namespace bemsurg
