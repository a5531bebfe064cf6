// bemsurg/quadrature/element_quadrature.hpp: how a kernel is integrated over one flat triangle
// from one source point (docs/design.md, integration). The rule is chosen by the policy here, never inside the
// assembly loop:
//   - far   (distance / diameter >= far_ratio): Radon's 7-point rule;
//   - mid   (>= mid_ratio): a collapsed Gauss rule of mid_order^2 points;
//   - near  (below): the triangle is split in four and each child is judged again, so refinement
//     concentrates where the source point is (adjacent elements, the far wall of a cut gap,
//     interior points close to the surface);
//   - self  (source point = the element's own centroid): polar coordinates about the centroid;
//     the visitor receives directions d, the distance R(theta) to the edge and the angle weight,
//     so U (exact in r), the principal value of T (ln R) and P (R^2/2) are all regular integrals.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/quadrature/triangle_rules.hpp"

namespace bemsurg {

/// Parameters of the quadrature policy: the distance / diameter ratios that select the far and mid rules, the
/// collapsed Gauss order, the depth at which splitting stops, and the polar rule used on the self element.
/// \ingroup quadrature
struct QuadratureOptions {
  double far_ratio = 4.0;
  double mid_ratio = 1.5;
  int mid_order = 5;
  int max_depth = 10;             // depth at which splitting stops and the mid rule is used regardless
  int polar_order = 8;            // Gauss points per angular piece of the self-element rule
  double polar_max_angle = 0.25;  // radians per angular piece

  /// Throws bemsurg::Error naming the first field out of range: ratios finite and positive with
  /// mid_ratio <= far_ratio, mid_order in [1, 20], max_depth in [0, 20], polar_order in [1, 40],
  /// polar_max_angle in (0, pi] (0 would divide by zero, polar_order 0 would zero self terms).
  void validate() const {
    auto fail = [](const char* field, const std::string& what) {
      throw InvalidArgumentError(std::string("quadrature options: ") + field + " " + what);
    };
    if (!(std::isfinite(far_ratio) && far_ratio > 0.0)) fail("far_ratio", "must be finite and positive, got " + number_text(far_ratio));
    if (!(std::isfinite(mid_ratio) && mid_ratio > 0.0)) fail("mid_ratio", "must be finite and positive, got " + number_text(mid_ratio));
    if (mid_ratio > far_ratio)
      fail("mid_ratio", "must not exceed far_ratio (" + number_text(far_ratio) + "), got " + number_text(mid_ratio));
    if (mid_order < 1 || mid_order > 20) fail("mid_order", "must lie in [1, 20], got " + std::to_string(mid_order));
    if (max_depth < 0 || max_depth > 20) fail("max_depth", "must lie in [0, 20], got " + std::to_string(max_depth));
    if (polar_order < 1 || polar_order > 40) fail("polar_order", "must lie in [1, 40], got " + std::to_string(polar_order));
    if (!(polar_max_angle > 0.0 && polar_max_angle <= numbers::pi))
      fail("polar_max_angle", "must lie in (0, pi] radians, got " + number_text(polar_max_angle));
  }
};

/// Integrates a kernel over one flat triangle from one source point with the rule the policy chooses (far, mid, near
/// by subdivision, or polar about the centroid for the self element), passing points and weights to a visitor.
/// \ingroup quadrature
class ElementQuadrature {
 public:
  explicit ElementQuadrature(const QuadratureOptions& options = {})
      : options_((options.validate(), options)),
        mid_rule_(collapsed_gauss_rule(options.mid_order)),
        line_(gauss_legendre(options.polar_order)) {}

  const QuadratureOptions& options() const { return options_; }

  /// Regular (far, mid, near) integration over the triangle (a, b, c) for a source point p that is
  /// not inside it. Calls visit(x, w) with quadrature points x and weights w (sum = area).
  template <class Visit>
  void integrate(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                 Visit&& visit) const {
    integrate_adaptive(p, a, b, c, 0, visit);
  }

  /// The number of quadrature points integrate(p, a, b, c, ...) would visit, found by the same
  /// recursion without evaluating anything (cost estimates, quadrature_cost.hpp). Counting stops
  /// once the count exceeds `cap`, so a pair that would take minutes is counted in bounded time.
  double count_points(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      double cap) const {
    double count = 0.0;
    count_adaptive(p, a, b, c, 0, cap, count);
    return count;
  }

  /// Polar rule about the centroid p of the flat triangle (a, b, c). Calls visit(d, R, w): unit
  /// in-plane direction d, distance R from p to the boundary along d, and angle weight w
  /// (sum of w = 2 pi). Then int_T f dS = sum w int_0^R f(p + r d) r dr.
  template <class Visit>
  void polar(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, Visit&& visit) const {
    const Eigen::Vector3d v[3] = {a, b, c};
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& s = v[k];
      const Eigen::Vector3d& e = v[(k + 1) % 3];
      const Eigen::Vector3d tangent = (e - s).normalized();
      const Eigen::Vector3d foot = s + (p - s).dot(tangent) * tangent;
      const Eigen::Vector3d to_foot = foot - p;
      const double h = to_foot.norm();
      const Eigen::Vector3d perp = to_foot / h;
      const double theta_s = std::atan2((s - foot).dot(tangent), h);
      const double theta_e = std::atan2((e - foot).dot(tangent), h);
      // R(theta) = h / cos(theta) is smooth on the edge's range, but steep near a sharp vertex;
      // short angular pieces keep Gauss accurate there.
      const int pieces = std::max(1, static_cast<int>(std::ceil((theta_e - theta_s) / options_.polar_max_angle)));
      const double width = (theta_e - theta_s) / pieces;
      for (int q = 0; q < pieces; ++q)
        for (std::size_t g = 0; g < line_.points.size(); ++g) {
          const double theta = theta_s + width * (q + line_.points[g]);
          const double ct = std::cos(theta), st = std::sin(theta);
          visit(Eigen::Vector3d(ct * perp + st * tangent), h / ct, width * line_.weights[g]);
        }
    }
  }

 private:
  template <class Visit>
  void apply_rule(const TriangleRule& rule, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, double area,
                  Visit& visit) const {
    const Eigen::Vector3d e1 = b - a, e2 = c - a;
    for (std::size_t k = 0; k < rule.weights.size(); ++k)
      visit(Eigen::Vector3d(a + rule.points[k].x() * e1 + rule.points[k].y() * e2), area * rule.weights[k]);
  }

  template <class Visit>
  void integrate_adaptive(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, int depth,
                          Visit& visit) const {
    const double h = element_diameter(a, b, c);
    const double dist = (p - (a + b + c) / 3.0).norm();
    const double area = 0.5 * (b - a).cross(c - a).norm();
    if (dist >= options_.far_ratio * h) return apply_rule(radon7_rule(), a, b, c, area, visit);
    if (dist >= options_.mid_ratio * h || depth >= options_.max_depth) return apply_rule(mid_rule_, a, b, c, area, visit);
    const Eigen::Vector3d ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
    integrate_adaptive(p, a, ab, ca, depth + 1, visit);
    integrate_adaptive(p, ab, b, bc, depth + 1, visit);
    integrate_adaptive(p, ca, bc, c, depth + 1, visit);
    integrate_adaptive(p, ab, bc, ca, depth + 1, visit);
  }

  // integrate_adaptive's decisions, counting points instead of visiting them (keep the two alike).
  void count_adaptive(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, int depth,
                      double cap, double& count) const {
    if (count > cap) return;
    const double h = element_diameter(a, b, c);
    const double dist = (p - (a + b + c) / 3.0).norm();
    if (dist >= options_.far_ratio * h) {
      count += static_cast<double>(radon7_rule().weights.size());
      return;
    }
    if (dist >= options_.mid_ratio * h || depth >= options_.max_depth) {
      count += static_cast<double>(mid_rule_.weights.size());
      return;
    }
    const Eigen::Vector3d ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
    count_adaptive(p, a, ab, ca, depth + 1, cap, count);
    count_adaptive(p, ab, b, bc, depth + 1, cap, count);
    count_adaptive(p, ca, bc, c, depth + 1, cap, count);
    count_adaptive(p, ab, bc, ca, depth + 1, cap, count);
  }

  QuadratureOptions options_;
  TriangleRule mid_rule_;
  LineRule line_;
};

}  // namespace bemsurg
