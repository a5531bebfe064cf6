// contact_accuracy_closed_forms.hpp: the half-space closed forms bench_contact_accuracy measures
// against (Johnson, Contact Mechanics, 1985, §3.8 flat punch and §4.2 Hertz sphere), and the
// element averages of their contact pressures. E* = E / (1 - nu^2); depths and displacements are
// positive into the body.
//   flat punch of radius a pressed by d:  F = 2 a E* d,  p(r) = F / (2 pi a sqrt(a^2 - r^2)),
//     u_z(r) = d (r <= a),  (2 d / pi) asin(a / r) (r >= a).
//   sphere of radius R pressed by d:  a = sqrt(R d),  p0 = 2 a E* / (pi R),  F = (4/3) E* sqrt(R) d^1.5,
//     p(r) = p0 sqrt(1 - r^2 / a^2),  u_z(r) = d - r^2 / (2 R) (r <= a),
//     u_z(r) = [(2 a^2 - r^2) asin(a / r) + a sqrt(r^2 - a^2)] / (pi R) (r >= a).
// The outer Hertz displacement has a sqrt(r^2 - a^2) times a, not r: with r it would grow like r^2;
// with a it equals a^2 / (2 R) = d - a^2 / (2 R) at r = a (continuous with the inner form) and tends
// to F / (pi E* r), Boussinesq's point load, far away. check_closed_forms() tests both limits.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace bemsurg::bench::contact_accuracy {

enum class Problem { Punch, Sphere };

/// One closed-form contact problem: the radius of the contact zone a, the force, the pressure's
/// radial antiderivative and the surface displacement.
struct ClosedForm {
  Problem problem = Problem::Punch;
  double E_star = 1.0;
  double a = 1.0;      // contact radius
  double d = 0.01;     // depth
  double R = 0.0;      // sphere radius (sphere only)
  double force = 0.0;  // F of the closed form
  double p0 = 0.0;     // sphere: peak pressure

  static ClosedForm punch(double E_star, double a, double d) {
    ClosedForm c;
    c.problem = Problem::Punch;
    c.E_star = E_star, c.a = a, c.d = d, c.force = 2.0 * a * E_star * d;
    return c;
  }
  /// The sphere pressed so that its contact radius is `a`: d = a^2 / R.
  static ClosedForm sphere(double E_star, double R, double a) {
    ClosedForm c;
    c.problem = Problem::Sphere;
    c.E_star = E_star, c.a = a, c.R = R, c.d = a * a / R;
    c.p0 = 2.0 * a * E_star / (M_PI * R);
    c.force = 4.0 / 3.0 * E_star * std::sqrt(R) * std::pow(c.d, 1.5);
    return c;
  }

  /// Q(r) = int_0^min(r,a) p(s) s ds: the pressure over a sector is its angle times Q. Closed
  /// forms, so the punch's edge singularity 1 / sqrt(a^2 - r^2) costs nothing in r.
  double radial_antiderivative(double r) const {
    const double x = std::max(0.0, 1.0 - std::min(r, a) * std::min(r, a) / (a * a));
    if (problem == Problem::Punch) return force / (2.0 * M_PI * a) * (a - a * std::sqrt(x));
    return p0 * a * a / 3.0 * (1.0 - x * std::sqrt(x));
  }
  /// Vertical surface displacement (into the body) at distance r from the axis.
  double displacement(double r) const {
    if (r <= a) return problem == Problem::Punch ? d : d - r * r / (2.0 * R);
    const double s = std::asin(a / r);
    if (problem == Problem::Punch) return 2.0 * d / M_PI * s;
    return ((2.0 * a * a - r * r) * s + a * std::sqrt(r * r - a * a)) / (M_PI * R);
  }
};

/// The outer displacement continuous at r = a and Boussinesq's point load far away (1e-6
/// relative); false means the formulas above are wrong.
inline bool check_closed_forms(const ClosedForm& c) {
  const double at_edge = c.displacement(c.a * (1.0 + 1e-12)), inner = c.displacement(c.a);
  const double far_r = 1e4 * c.a, far = c.displacement(far_r), point_load = c.force / (M_PI * c.E_star * far_r);
  return std::abs(at_edge - inner) <= 1e-6 * c.d && std::abs(far - point_load) <= 1e-6 * point_load;
}

/// Gauss-Legendre nodes and weights on [0, 1] (Golub-Welsch free: Newton on P_n).
inline void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(static_cast<std::size_t>(n), 0.0);
  w.assign(static_cast<std::size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    double t = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1.0, p1 = t;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2.0 * k - 1.0) * t * p1 - (k - 1.0) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (t * p1 - p0) / (t * t - 1.0);
      const double step = p1 / dp;
      t -= step;
      if (std::abs(step) < 1e-16) break;
    }
    x[static_cast<std::size_t>(i)] = 0.5 * (1.0 - t);
    w[static_cast<std::size_t>(i)] = 1.0 / ((1.0 - t * t) * dp * dp);
  }
}

/// The radial interval [lo, hi] where the ray from the origin along `dir` lies in the triangle v
/// (counterclockwise); false when it misses.
inline bool ray_interval(const std::array<Eigen::Vector2d, 3>& v, const Eigen::Vector2d& dir, double& lo, double& hi) {
  lo = 0.0, hi = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d& p = v[static_cast<std::size_t>(i)];
    const Eigen::Vector2d e = v[static_cast<std::size_t>((i + 1) % 3)] - p;
    const Eigen::Vector2d n(-e.y(), e.x());  // inward for a counterclockwise triangle
    const double s = n.dot(dir), b = n.dot(p);
    if (std::abs(s) <= 1e-15 * n.norm()) {
      if (b > 0.0) return false;
    } else if (s > 0.0) {
      lo = std::max(lo, b / s);
    } else {
      hi = std::min(hi, b / s);
    }
  }
  return lo < hi;
}

/// int over the triangle (x, y corners) of the closed-form pressure: in polar coordinates about the
/// axis, exact in r (radial_antiderivative) and Gauss-Legendre in the angle between breakpoints
/// (the corners' angles and where the edges cross the circle r = a), with the substitution
/// theta = theta0 + D (3 s^2 - 2 s^3) that turns the sqrt-type kinks at the breakpoints smooth.
inline double pressure_integral(const ClosedForm& c, std::array<Eigen::Vector2d, 3> v) {
  if ((v[1] - v[0]).x() * (v[2] - v[0]).y() - (v[1] - v[0]).y() * (v[2] - v[0]).x() < 0.0) std::swap(v[1], v[2]);
  const double scale = std::max({v[0].norm(), v[1].norm(), v[2].norm()});
  std::vector<double> angles;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d p = v[static_cast<std::size_t>(i)], e = v[static_cast<std::size_t>((i + 1) % 3)] - p;
    if (p.norm() > 1e-12 * scale) angles.push_back(std::atan2(p.y(), p.x()));
    const double A = e.squaredNorm(), B = 2.0 * p.dot(e), C = p.squaredNorm() - c.a * c.a, disc = B * B - 4.0 * A * C;
    if (disc <= 0.0) continue;
    for (double t : {(-B - std::sqrt(disc)) / (2.0 * A), (-B + std::sqrt(disc)) / (2.0 * A)}) {
      if (t <= 0.0 || t >= 1.0) continue;
      const Eigen::Vector2d q = p + t * e;
      angles.push_back(std::atan2(q.y(), q.x()));
    }
  }
  std::sort(angles.begin(), angles.end());
  angles.push_back(angles.front() + 2.0 * M_PI);
  static thread_local std::vector<double> gx, gw;
  if (gx.empty()) gauss_legendre(20, gx, gw);
  double total = 0.0;
  for (std::size_t k = 0; k + 1 < angles.size(); ++k) {
    const double t0 = angles[k], D = angles[k + 1] - t0;
    if (D <= 0.0) continue;
    for (std::size_t g = 0; g < gx.size(); ++g) {
      const double s = gx[g], theta = t0 + D * s * s * (3.0 - 2.0 * s), jac = D * 6.0 * s * (1.0 - s);
      double lo = 0.0, hi = 0.0;
      if (!ray_interval(v, Eigen::Vector2d(std::cos(theta), std::sin(theta)), lo, hi)) continue;
      total += gw[g] * jac * (c.radial_antiderivative(hi) - c.radial_antiderivative(lo));
    }
  }
  return total;
}

}  // namespace bemsurg::bench::contact_accuracy
