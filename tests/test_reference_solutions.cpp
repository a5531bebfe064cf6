// The closed-form fields of verification/reference_solutions.hpp checked without the library's
// kernel classes (the Kelvin field is built from KelvinKernel and KelvinKernelGradients, so a sign
// or index error there would otherwise go unseen in every test that compares with it):
//   - the displacement against the formula written out here;
//   - the stress against Hooke's law of the finite-difference gradient of the displacement;
//   - equilibrium, div sigma + b = 0, by finite differences of the stress;
//   - the Kelvin resultant: the traction sigma n over a closed surface around the source sums to
//     -f (the ball's equilibrium with the point force f inside it), over one not enclosing it to 0,
//     and its moment about the source vanishes.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "bemsurg/quadrature/triangle_rules.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;

namespace {

using Vec = Eigen::Vector3d;
using Mat = Eigen::Matrix3d;

/// grad(j, b) = d u_j / d x_b by central differences with step h, Richardson-extrapolated (h, h/2).
Mat gradient_fd(const ElasticField& f, const Vec& x, double h) {
  auto central = [&](double s) {
    Mat g;
    for (int b = 0; b < 3; ++b) g.col(b) = (f.displacement(x + s * Vec::Unit(b)) - f.displacement(x - s * Vec::Unit(b))) / (2.0 * s);
    return g;
  };
  return (4.0 * central(0.5 * h) - central(h)) / 3.0;
}

/// (div sigma)_i = d sigma_ib / d x_b by central differences, Richardson-extrapolated.
Vec divergence_fd(const ElasticField& f, const Vec& x, double h) {
  auto central = [&](double s) {
    Vec d = Vec::Zero();
    for (int b = 0; b < 3; ++b) d += (f.stress(x + s * Vec::Unit(b)) - f.stress(x - s * Vec::Unit(b))).col(b) / (2.0 * s);
    return d;
  };
  return (4.0 * central(0.5 * h) - central(h)) / 3.0;
}

/// Hooke's law written out: sigma = lambda tr(eps) I + 2 mu eps, lambda = E nu / ((1 + nu)(1 - 2 nu)),
/// mu = E / (2 (1 + nu)).
Mat hooke_here(double E, double nu, const Mat& grad) {
  const Mat eps = 0.5 * (grad + grad.transpose());
  const double lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), mu = E / (2.0 * (1.0 + nu));
  return lambda * eps.trace() * Mat::Identity() + 2.0 * mu * eps;
}

/// Integral of g(x, n) dS over the sphere |x - c| = R: Gauss-Legendre in cos(theta) (n points),
/// trapezoid in phi (2n points); exact for polynomials in n of degree < 2n.
template <class G>
auto sphere_integral(const Vec& c, double R, int n, G&& g) {
  const LineRule rule = gauss_legendre(n);  // on [0, 1]
  decltype(g(c, c)) sum = decltype(g(c, c))::Zero();
  for (std::size_t i = 0; i < rule.points.size(); ++i) {
    const double ct = 2.0 * rule.points[i] - 1.0, st = std::sqrt(1.0 - ct * ct);
    for (int k = 0; k < 2 * n; ++k) {
      const double phi = M_PI * k / n;
      const Vec normal(st * std::cos(phi), st * std::sin(phi), ct);
      sum += (2.0 * rule.weights[i]) * (M_PI / n) * R * R * g(Vec(c + R * normal), normal);
    }
  }
  return sum;
}

/// Integral of g(x, n) dS over the surface of the box [lo, hi] (outward normals), tensor
/// Gauss-Legendre with n x n points per face.
template <class G>
auto box_integral(const Vec& lo, const Vec& hi, int n, G&& g) {
  const LineRule rule = gauss_legendre(n);
  decltype(g(lo, lo)) sum = decltype(g(lo, lo))::Zero();
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int a = (axis + 1) % 3, b = (axis + 2) % 3;
      const Vec normal = (side == 0 ? -1.0 : 1.0) * Vec::Unit(axis);
      const double area = (hi(a) - lo(a)) * (hi(b) - lo(b));
      for (std::size_t i = 0; i < rule.points.size(); ++i)
        for (std::size_t j = 0; j < rule.points.size(); ++j) {
          Vec x;
          x(axis) = side == 0 ? lo(axis) : hi(axis);
          x(a) = lo(a) + rule.points[i] * (hi(a) - lo(a));
          x(b) = lo(b) + rule.points[j] * (hi(b) - lo(b));
          sum += rule.weights[i] * rule.weights[j] * area * g(x, normal);
        }
    }
  return sum;
}

const Material kReferenceMaterial{2.5, 0.3, 1.0};
const Vec kSource(0.3, 0.2, 1.4), kForce(0.4, -0.3, 1.0);

}  // namespace

TEST_CASE("Kelvin reference: displacement is the closed form, stress is Hooke of its gradient") {
  const ElasticField field = kelvin_field(kReferenceMaterial, kSource, kForce);
  const double E = kReferenceMaterial.young_modulus, nu = kReferenceMaterial.poisson_ratio, mu = E / (2.0 * (1.0 + nu));
  // Points at distances 0.3 to 2.6 from the source, in several directions.
  const Vec points[] = {Vec(0, 0, 0), Vec(0.5, -0.2, 0.1), Vec(0.3, 0.2, 1.1), Vec(-1.0, 0.6, 1.5), Vec(0.9, 0.9, 2.0)};
  double worst_u = 0.0, worst_stress = 0.0;
  for (const Vec& x : points) {
    INFO("x = " << x.transpose());
    const Vec r = x - kSource;
    const double d = r.norm();
    const Vec rh = r / d;
    // u_j = f_i U_ij = [(3 - 4 nu) f_j + (f . r^) r^_j] / (16 pi mu (1 - nu) d)
    const Vec exact = ((3.0 - 4.0 * nu) * kForce + kForce.dot(rh) * rh) / (16.0 * M_PI * mu * (1.0 - nu) * d);
    worst_u = std::max(worst_u, (field.displacement(x) - exact).norm() / exact.norm());
    const Mat from_u = hooke_here(E, nu, gradient_fd(field, x, 1e-3 * d));
    worst_stress = std::max(worst_stress, (field.stress(x) - from_u).norm() / from_u.norm());
  }
  // Measured: displacement 2.6e-16 (1.2 eps), rounding of two paths of ~13 roundings (eps/2) each
  // whose terms do not cancel ((3 - 4 nu) f and (f . r^) r^: sum of |terms| <= 1.7 |u| at these
  // points), so within ~22 eps; bound 32 eps. Stress vs the Richardson-extrapolated FD gradient
  // 1.1e-12 (bound 1.7e-12). A transposed gradient or a wrong sign is O(1).
  INFO("displacement " << worst_u << ", stress " << worst_stress);
  CHECK(worst_u < 32.0 * std::numeric_limits<double>::epsilon());
  CHECK(worst_stress < 1.7e-12);
}

TEST_CASE("Kelvin reference: equilibrium, div sigma = 0 away from the source") {
  const ElasticField field = kelvin_field(kReferenceMaterial, kSource, kForce);
  const Vec points[] = {Vec(0, 0, 0), Vec(0.5, -0.2, 0.1), Vec(0.3, 0.2, 1.1), Vec(-1.0, 0.6, 1.5), Vec(0.9, 0.9, 2.0)};
  double worst = 0.0;
  for (const Vec& x : points) {
    const double d = (x - kSource).norm();
    // Scale: |sigma| / d, the size of one stress derivative there.
    const double scale = field.stress(x).norm() / d;
    worst = std::max(worst, divergence_fd(field, x, 1e-3 * d).norm() / scale);
  }
  // Measured 3.1e-12 relative to |sigma|/d; bound 4.6e-12 (a single term of the stress with a
  // wrong coefficient gives O(1)).
  INFO("worst |div sigma| / (|sigma|/d) = " << worst);
  CHECK(worst < 4.6e-12);
}

TEST_CASE("Kelvin reference: the traction over a closed surface around the source balances the force") {
  const ElasticField field = kelvin_field(kReferenceMaterial, kSource, kForce);
  auto traction = [&](const Vec& x, const Vec& n) { return Vec(field.stress(x) * n); };
  auto moment = [&](const Vec& x, const Vec& n) { return Vec((x - kSource).cross(field.stress(x) * n)); };
  // Sphere about the source: the integrand is a cubic in n over R^2, integrated exactly.
  // Measured |resultant + f| / |f| <= 1.2e-15, |moment| / (|f| R) <= 1.3e-17: rounding (bounds
  // 1e-14, 1e-15); a resultant of +f (sign) or 2f is O(1).
  for (double R : {0.05, 1.0, 7.0}) {
    INFO("sphere of radius " << R);
    const Vec resultant = sphere_integral(kSource, R, 6, traction), turning = sphere_integral(kSource, R, 6, moment);
    INFO("|resultant + f| / |f| = " << (resultant + kForce).norm() / kForce.norm()
                                    << ", |moment| / (|f| R) = " << turning.norm() / (kForce.norm() * R));
    CHECK((resultant + kForce).norm() < 1e-14 * kForce.norm());
    CHECK(turning.norm() < 1e-15 * kForce.norm() * R);
  }
  // A box around the source, off centre (smooth integrand, Gauss 24 x 24 per face): measured
  // 2.8e-11; bound 4.5e-11. A box beside the source encloses no force: resultant 0 (measured
  // 2.4e-15; bound 1e-14).
  const Vec around = box_integral(Vec(-0.5, -0.4, 1.0), Vec(0.8, 0.6, 2.5), 24, traction);
  INFO("box around: |resultant + f| / |f| = " << (around + kForce).norm() / kForce.norm());
  CHECK((around + kForce).norm() < 4.5e-11 * kForce.norm());
  const Vec beside = box_integral(Vec(-1, -0.6, -0.6), Vec(1, 0.6, 0.6), 24, traction);
  INFO("box beside: |resultant| / |f| = " << beside.norm() / kForce.norm());
  CHECK(beside.norm() < 1e-14 * kForce.norm());
}

TEST_CASE("Lame, uniform pressure and hanging bar references: Hooke of the gradient and equilibrium") {
  const Material m = kReferenceMaterial;
  const double g = 1.3;
  struct Case {
    const char* what;
    ElasticField field;
    Vec body_force;  // b in div sigma + b = 0
    std::vector<Vec> points;
  };
  const Case cases[] = {
      {"Lame sphere",
       lame_field(m, Vec(0.1, 0, 0), 1.0, 2.0, 1.0, 0.4),
       Vec::Zero(),
       {Vec(1.5, 0, 0), Vec(0.1, -1.2, 0.9), Vec(0.9, 0.8, 0.8)}},
      {"uniform pressure", uniform_pressure_field(m, 2.0), Vec::Zero(), {Vec(0.3, -0.2, 0.1), Vec(-0.4, 0.4, -0.4)}},
      // sigma_zz = rho g z with gravity g along -z: b = (0, 0, -rho g)
      {"hanging bar", hanging_bar_field(m, g, 3.0), Vec(0, 0, -m.density * g), {Vec(0.2, -0.1, 0.8), Vec(-0.3, 0.3, 2.6)}},
  };
  for (const Case& c : cases) {
    for (const Vec& x : c.points) {
      INFO(c.what << " at " << x.transpose());
      const Mat sigma = c.field.stress(x);
      const Mat from_u = hooke_here(m.young_modulus, m.poisson_ratio, gradient_fd(c.field, x, 1e-3));
      const Vec residual = divergence_fd(c.field, x, 1e-3) + c.body_force;
      const double scale = std::max(sigma.norm(), c.body_force.norm());
      INFO("|sigma - Hooke(grad u)| / |sigma| = " << (sigma - from_u).norm() / sigma.norm()
                                                  << ", |div sigma + b| / max(|sigma|, |b|) = " << residual.norm() / scale);
      // Measured: at most 9.0e-13 and 6.6e-13 (the latter per unit length); bounds 1.4e-12, 1e-12.
      CHECK((sigma - from_u).norm() < 1.4e-12 * sigma.norm());
      CHECK(residual.norm() < 1e-12 * scale);
    }
  }
}
