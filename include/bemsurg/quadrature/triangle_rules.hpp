// bemsurg/quadrature/triangle_rules.hpp: regular quadrature rules on a triangle and a line.
// Points are barycentric-free reference coordinates (xi, eta) on the triangle (0,0),(1,0),(0,1);
// weights are fractions of the area (they sum to 1), so int_T f dS ~ area * sum_k w_k f(x_k).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "bemsurg/mesh/geometry.hpp"

namespace bemsurg {

/// A quadrature rule on the reference triangle (0,0), (1,0), (0,1): points (xi, eta) and weights that sum to 1, so
/// int_T f dS ~ area * sum_k w_k f(x_k); polynomials up to `degree` are integrated exactly.
/// \ingroup quadrature
struct TriangleRule {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> weights;
  int degree = 0;  // polynomials up to this degree are integrated exactly
};

/// A quadrature rule on the interval [0, 1]: the 1D factor of the collapsed Gauss rule and the angular rule of the
/// polar one.
/// \ingroup quadrature
struct LineRule {  // on [0, 1], weights sum to 1
  std::vector<double> points;
  std::vector<double> weights;
};

/// Gauss-Legendre with n points on [0, 1] (Newton iteration on the Legendre recurrence).
inline LineRule gauss_legendre(int n) {
  LineRule rule;
  rule.points.resize(static_cast<std::size_t>(n));
  rule.weights.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    double x = std::cos(numbers::pi * (i + 0.75) / (n + 0.5));
    double dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double pk = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = pk;
      }
      dp = n * (x * p1 - p0) / (x * x - 1.0);
      const double dx = p1 / dp;
      x -= dx;
      if (std::abs(dx) < 1e-16) break;
    }
    rule.points[static_cast<std::size_t>(i)] = 0.5 * (1.0 - x);
    rule.weights[static_cast<std::size_t>(i)] = 1.0 / ((1.0 - x * x) * dp * dp);  // (2/((1-x^2)p'^2)) / 2
  }
  return rule;
}

/// Radon's 7-point rule, degree 5: the workhorse for well-separated elements.
inline const TriangleRule& radon7_rule() {
  static const TriangleRule rule = [] {
    TriangleRule r;
    r.degree = 5;
    const double s15 = std::sqrt(15.0);
    const double a1 = (6.0 - s15) / 21.0, a2 = (6.0 + s15) / 21.0;
    const double w1 = (155.0 - s15) / 1200.0, w2 = (155.0 + s15) / 1200.0;
    r.points = {{1.0 / 3.0, 1.0 / 3.0}, {a1, a1}, {1.0 - 2.0 * a1, a1}, {a1, 1.0 - 2.0 * a1}, {a2, a2}, {1.0 - 2.0 * a2, a2},
                {a2, 1.0 - 2.0 * a2}};
    r.weights = {9.0 / 40.0, w1, w1, w1, w2, w2, w2};
    return r;
  }();
  return rule;
}

/// Collapsed (Duffy) Gauss product rule with n x n points, degree 2n - 2: any order from one
/// 1D rule, used where an element is close enough that 7 points would not do but not so close
/// that it must be split.
inline TriangleRule collapsed_gauss_rule(int n) {
  const LineRule g = gauss_legendre(n);
  TriangleRule r;
  r.degree = 2 * n - 2;  // the Jacobian (1 - v) costs one degree in v
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double u = g.points[static_cast<std::size_t>(i)], v = g.points[static_cast<std::size_t>(j)];
      // (u, v) in the unit square -> (xi, eta) = (u (1 - v), v): Jacobian (1 - v); area 1/2 -> factor 2.
      r.points.emplace_back(u * (1.0 - v), v);
      r.weights.push_back(2.0 * g.weights[static_cast<std::size_t>(i)] * g.weights[static_cast<std::size_t>(j)] * (1.0 - v));
    }
  return r;
}

}  // namespace bemsurg
