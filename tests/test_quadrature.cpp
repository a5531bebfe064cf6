// Quadrature rules and the self-element polar rules, each against an exact or independent reference.
#include <catch2/catch.hpp>

#include <limits>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"
#include "bemsurg/quadrature/triangle_rules.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {
using bemsurg_test::kEps;

// int over the reference triangle of xi^a eta^b = a! b! / (a + b + 2)!
double monomial_integral(int a, int b) { return std::tgamma(a + 1.0) * std::tgamma(b + 1.0) / std::tgamma(a + b + 3.0); }
double apply(const TriangleRule& r, int a, int b) {
  double s = 0.0;
  for (std::size_t k = 0; k < r.weights.size(); ++k) s += 0.5 * r.weights[k] * std::pow(r.points[k].x(), a) * std::pow(r.points[k].y(), b);
  return s;
}

// Independent reference for an integral over a triangle with a 1/r singularity at its centroid:
// split into three triangles at the centroid, each mapped by a Duffy transform that cancels 1/r,
// then a high-order tensor Gauss rule.
template <class F>
Eigen::Matrix3d duffy_about_centroid(const std::array<Eigen::Vector3d, 3>& v, F&& f, int order = 40) {
  const Eigen::Vector3d p = (v[0] + v[1] + v[2]) / 3.0;
  const LineRule g = gauss_legendre(order);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = v[static_cast<std::size_t>(k)], b = v[static_cast<std::size_t>((k + 1) % 3)];
    const double jac = (a - p).cross(b - p).norm();  // 2 x area of the sub-triangle
    for (std::size_t i = 0; i < g.points.size(); ++i)
      for (std::size_t j = 0; j < g.points.size(); ++j) {
        const double s = g.points[i], t = g.points[j];
        const Eigen::Vector3d x = p + s * ((a - p) + t * (b - a));
        sum += g.weights[i] * g.weights[j] * s * jac * f(x);
      }
  }
  return sum;
}

// Closed forms over a flat triangle v (vertices counter-clockwise about n = unit (v1-v0)x(v2-v0)),
// independent of the library. For edge k from a to b: l = unit(b - a), u = l x n (outward in the
// plane), rho = the projection of p on the plane, d = (p - v0).n, P0 = (a - rho).u,
// R0 = sqrt(P0^2 + d^2), l+- = (b|a - rho).l; int_edge dl / |x - p| = asinh(l+/R0) - asinh(l-/R0).
struct EdgeGeometry {
  Eigen::Vector3d u;
  double P0, R0, line_integral;  // line_integral = int over the edge of 1/|x - p|
};
std::array<EdgeGeometry, 3> edges_seen_from(const std::array<Eigen::Vector3d, 3>& v, const Eigen::Vector3d& p) {
  const Eigen::Vector3d n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
  const double d = (p - v[0]).dot(n);
  const Eigen::Vector3d rho = p - d * n;
  std::array<EdgeGeometry, 3> out;
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = v[k], b = v[(k + 1) % 3];
    const Eigen::Vector3d l = (b - a).normalized(), u = l.cross(n);
    const double P0 = (a - rho).dot(u), R0 = std::sqrt(P0 * P0 + d * d);
    out[k] = {u, P0, R0, std::asinh((b - rho).dot(l) / R0) - std::asinh((a - rho).dot(l) / R0)};
  }
  return out;
}

/// Signed solid angle int_T (x - p).n / |x - p|^3 dS (Van Oosterom & Strackee 1983).
double solid_angle(const std::array<Eigen::Vector3d, 3>& v, const Eigen::Vector3d& p) {
  const Eigen::Vector3d a = v[0] - p, b = v[1] - p, c = v[2] - p;
  const double na = a.norm(), nb = b.norm(), nc = c.norm();
  return 2.0 * std::atan2(a.dot(b.cross(c)), na * nb * nc + a.dot(b) * nc + a.dot(c) * nb + b.dot(c) * na);
}

/// int_T 1/|x - p| dS (Wilton et al. 1984, IEEE TAP 32:276).
double integral_of_inverse_distance(const std::array<Eigen::Vector3d, 3>& v, const Eigen::Vector3d& p) {
  const Eigen::Vector3d n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
  const double ad = std::abs((p - v[0]).dot(n));
  const auto edges = edges_seen_from(v, p);
  double s = 0.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const EdgeGeometry& e = edges[k];
    const Eigen::Vector3d a = v[k], b = v[(k + 1) % 3];
    const Eigen::Vector3d l = (b - a).normalized();
    const Eigen::Vector3d rho = p - (p - v[0]).dot(n) * n;
    const double R02 = e.R0 * e.R0;
    s += e.P0 * e.line_integral;
    s -= ad *
         (std::atan2(e.P0 * (b - rho).dot(l), R02 + ad * (b - p).norm()) - std::atan2(e.P0 * (a - rho).dot(l), R02 + ad * (a - p).norm()));
  }
  return s;
}

/// int_T (x - p) / |x - p|^3 dS = grad_p int_T 1/|x - p| dS: tangential part by the divergence
/// theorem on the flat triangle, -sum_k u_k int_edge dl/|x - p|; normal part the solid angle.
Eigen::Vector3d integral_of_r_over_r_cubed(const std::array<Eigen::Vector3d, 3>& v, const Eigen::Vector3d& p) {
  const Eigen::Vector3d n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
  Eigen::Vector3d K = solid_angle(v, p) * n;
  for (const EdgeGeometry& e : edges_seen_from(v, p)) K -= e.u * e.line_integral;
  return K;
}

/// Principal value about the centroid p: A = PV int_T (x - p) / |x - p|^2 dS (in the plane). For
/// the edge with foot point f of p, h = |f - p|, e1 = (f - p)/h, s the coordinate along the edge
/// and r = sqrt(h^2 + s^2), polar coordinates give int d(theta) ln(R(theta)/eps) dtheta, whose eps
/// term vanishes over the full circle; per edge it integrates in closed form to
/// e1 [s/r (ln r + 1) - asinh(s/h)] + l h [-(ln r + 1)/r], taken between the edge's ends.
Eigen::Vector3d principal_value_about_centroid(const std::array<Eigen::Vector3d, 3>& v) {
  const Eigen::Vector3d p = (v[0] + v[1] + v[2]) / 3.0;
  Eigen::Vector3d A = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = v[k], b = v[(k + 1) % 3];
    const Eigen::Vector3d l = (b - a).normalized(), f = a + (p - a).dot(l) * l;
    const double h = (f - p).norm();
    const Eigen::Vector3d e1 = (f - p) / h;
    auto F = [h](double s) {
      const double r = std::hypot(h, s);
      return s / r * (std::log(r) + 1.0) - std::asinh(s / h);
    };
    auto G = [h](double s) {
      const double r = std::hypot(h, s);
      return -(std::log(r) + 1.0) / r;
    };
    const double sa = (a - f).dot(l), sb = (b - f).dot(l);
    A += e1 * (F(sb) - F(sa)) + l * h * (G(sb) - G(sa));
  }
  return A;
}

/// The same principal value by brute force, for checking the closed form: polar coordinates about
/// p with the radial integral from eps to R exact (ln(R/eps)) and the midpoint rule in the
/// parameter along each edge (N points per edge).
Eigen::Vector3d principal_value_by_midpoint_rule(const std::array<Eigen::Vector3d, 3>& v, int N) {
  const Eigen::Vector3d p = (v[0] + v[1] + v[2]) / 3.0, n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
  const double eps = 1e-3;
  Eigen::Vector3d A = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = v[k], b = v[(k + 1) % 3];
    for (int i = 0; i < N; ++i) {
      const Eigen::Vector3d d = a + (i + 0.5) / N * (b - a) - p;
      const double R = d.norm(), dtheta = d.cross(b - a).dot(n) / (R * R) / N;
      A += d / R * std::log(R / eps) * dtheta;
    }
  }
  return A;
}

const std::array<Eigen::Vector3d, 3> kTriangle = {Eigen::Vector3d(0.1, 0.0, 0.2), Eigen::Vector3d(1.3, 0.2, 0.1),
                                                  Eigen::Vector3d(0.4, 0.9, 0.5)};
}  // namespace

TEST_CASE("triangle rules integrate polynomials of their degree exactly") {
  // Round-off only. gauss_legendre's points and weights (n <= 6 here) are within 1.5 eps and 4 eps
  // (relative) of the exact ones (checked against 50-digit Newton iterates); with those, the
  // rules' own products and the n-term sums of positive terms, the first-order bounds are: weight
  // sums 4, 7 and 21 eps (radon7, 3 x 3, 6 x 6), monomials 11, 15 and 32 eps. Measured: 3 eps
  // and 8.4 eps at worst. Bounds 32 eps and 64 eps.
  for (const TriangleRule& r : {radon7_rule(), collapsed_gauss_rule(3), collapsed_gauss_rule(6)}) {
    double wsum = 0.0;
    for (double w : r.weights) wsum += w;
    CHECK(wsum == Approx(1.0).epsilon(32.0 * kEps));
    for (int a = 0; a <= r.degree; ++a)
      for (int b = 0; a + b <= r.degree; ++b) CHECK(apply(r, a, b) == Approx(monomial_integral(a, b)).epsilon(64.0 * kEps));
  }
}

TEST_CASE("Gauss-Legendre integrates degree 2n-1 exactly on the unit interval") {
  // Round-off only: the n <= 12 points and weights are within 2.8 eps and 11 eps (relative) of the
  // exact ones (50-digit Newton iterates); x^d carries d times the point's error, the sum n
  // roundings of positive terms: first-order bound 17 eps (n = 12), measured 5.5 eps; bound 32 eps.
  for (int n : {1, 2, 5, 12}) {
    const LineRule g = gauss_legendre(n);
    for (int d = 0; d <= 2 * n - 1; ++d) {
      double s = 0.0;
      for (std::size_t k = 0; k < g.points.size(); ++k) s += g.weights[k] * std::pow(g.points[k], d);
      CHECK(s == Approx(1.0 / (d + 1)).epsilon(32.0 * kEps));
    }
  }
}

TEST_CASE("self-element U integral (polar, exact in r) matches a Duffy reference") {
  const Material m{1.0, 0.3, 0.0};
  const KelvinKernel k(m);
  const Eigen::Vector3d p = (kTriangle[0] + kTriangle[1] + kTriangle[2]) / 3.0;
  const ElementQuadrature q;
  Eigen::Matrix3d polar = Eigen::Matrix3d::Zero();
  q.polar(p, kTriangle[0], kTriangle[1], kTriangle[2],
          [&](const Eigen::Vector3d& d, double R, double w) { polar += w * R * k.displacement_times_r(d); });
  const Eigen::Matrix3d ref = duffy_about_centroid(kTriangle, [&](const Eigen::Vector3d& x) { return k.displacement(x - p); });
  // Measured 3.0e-15 relative (14 eps): both rules have converged to rounding. Worst-case rounding:
  // the reference sums N = 3 x 40^2 = 4800 terms (the polar rule 208), N/2 eps of sum |terms|,
  // which is at most ~2 |ref| (the positive diagonal dominates), plus the 40-point Gauss weights'
  // own error (<= 92 eps, against 50-digit values): ~5000 eps. Bound 1e4 eps = 2.2e-12.
  CHECK((polar - ref).norm() < 1e4 * kEps * ref.norm());
}

TEST_CASE("adaptive rule matches closed-form integrals of 1/r and r/r^3 near and far from the triangle") {
  const std::array<Eigen::Vector3d, 3>& v = kTriangle;
  const Eigen::Vector3d n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
  const Eigen::Vector3d c = (v[0] + v[1] + v[2]) / 3.0, mid = 0.5 * (v[0] + v[1]);
  const Eigen::Vector3d inward = (v[2] - mid).normalized();
  const double diam = std::max({(v[1] - v[0]).norm(), (v[2] - v[1]).norm(), (v[0] - v[2]).norm()});
  // Source points and bounds on the relative errors of int 1/r and of int (x - p)/r^3 with the
  // default options. Measured (1/r, r/r^3): 7.3e-10, 8.8e-9; 1.4e-9, 1.5e-8; 1.5e-10, 6.4e-9;
  // 7.5e-11, 4.9e-9; 1.6e-9, 1.8e-8; 8.5e-13, 5.4e-11; 3.0e-10, 3.3e-9. Bounds ~1.5x those.
  struct Case {
    const char* what;
    Eigen::Vector3d p;
    double bound_inverse, bound_vector;
  };
  const Case cases[] = {
      {"in the plane, 0.15 outside an edge (a neighbour's centroid)", mid - 0.15 * inward, 1.1e-9, 1.3e-8},
      {"in the plane, 0.01 outside an edge", mid - 0.01 * inward, 2.2e-9, 2.3e-8},
      {"0.01 diameters above the centroid", c + 0.01 * diam * n, 2.3e-10, 1e-8},
      {"0.02 diameters below, near a vertex", 0.8 * v[0] + 0.1 * v[1] + 0.1 * v[2] - 0.02 * diam * n, 1.2e-10, 7.5e-9},
      {"0.005 above an edge's midpoint", mid + 0.005 * n, 2.4e-9, 2.7e-8},
      {"far (mid rule)", c + 3.0 * diam * n + Eigen::Vector3d(1, 1, 0), 1.3e-12, 8e-11},
      {"two diameters away", c + 2.0 * diam * Eigen::Vector3d(0.3, 0.5, 0.8).normalized(), 4.5e-10, 5e-9},
  };
  const ElementQuadrature q;
  for (const Case& k : cases) {
    INFO(k.what);
    double inverse = 0.0;
    Eigen::Vector3d vector = Eigen::Vector3d::Zero();
    q.integrate(k.p, v[0], v[1], v[2], [&](const Eigen::Vector3d& x, double w) {
      const double r = (x - k.p).norm();
      inverse += w / r;
      vector += w * (x - k.p) / (r * r * r);
    });
    const double exact_inverse = integral_of_inverse_distance(v, k.p);
    const Eigen::Vector3d exact_vector = integral_of_r_over_r_cubed(v, k.p);
    const double e_inverse = std::abs(inverse - exact_inverse) / exact_inverse;
    const double e_vector = (vector - exact_vector).norm() / exact_vector.norm();
    INFO("relative errors: 1/r " << e_inverse << ", r/r^3 " << e_vector);
    CHECK(e_inverse < k.bound_inverse);
    CHECK(e_vector < k.bound_vector);
  }
}

TEST_CASE("adaptive rule integrates the Kelvin traction kernel from a neighbour in the plane to its closed form") {
  // Source point in the element's plane (like the centroid of a coplanar neighbour): dr/dn = 0, so
  // T_ij = (1 - 2nu)(r,i n_j - r,j n_i) / (8 pi (1 - nu) r^2) and int T = c (K n^T - n K^T) with
  // K = int (x - p)/r^3 dS in closed form. Measured relative error 8.8e-9 (0.15 off the edge) and
  // 1.5e-8 (0.01 off); bounds ~1.5x.
  const Material m{1.0, 0.3, 0.0};
  const KelvinKernel k(m);
  const std::array<Eigen::Vector3d, 3>& v = kTriangle;
  const Eigen::Vector3d mid = 0.5 * (v[0] + v[1]);
  const Eigen::Vector3d n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
  const Eigen::Vector3d inward = (v[2] - mid).normalized();
  const double c = (1.0 - 2.0 * m.poisson_ratio) / (8.0 * M_PI * (1.0 - m.poisson_ratio));
  for (const auto& [offset, bound] : {std::pair<double, double>{0.15, 1.3e-8}, {0.01, 2.3e-8}}) {
    INFO("source " << offset << " outside the edge");
    const Eigen::Vector3d p = mid - offset * inward;
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    ElementQuadrature().integrate(p, v[0], v[1], v[2], [&](const Eigen::Vector3d& x, double w) { H += w * k.traction(x - p, n); });
    const Eigen::Vector3d K = integral_of_r_over_r_cubed(v, p);
    const Eigen::Matrix3d exact = c * (K * n.transpose() - n * K.transpose());
    INFO("relative error " << (H - exact).norm() / exact.norm());
    CHECK((H - exact).norm() < bound * exact.norm());
  }
}

TEST_CASE("the closed forms used as references agree with brute-force sums") {
  // Guards the references themselves. Measured: principal value vs a 1e5-point midpoint rule
  // 4.5e-10 relative (second order: 4.5e-6 at 1e3 points); bound 7e-10.
  const Eigen::Vector3d pv = principal_value_about_centroid(kTriangle);
  INFO("principal value: " << (principal_value_by_midpoint_rule(kTriangle, 100000) - pv).norm() / pv.norm());
  CHECK((principal_value_by_midpoint_rule(kTriangle, 100000) - pv).norm() < 7e-10 * pv.norm());
  // 1/r and r/r^3 from a point 0.05 above the triangle vs the centroid rule on 1000^2 subtriangles.
  const Eigen::Vector3d p = 0.3 * kTriangle[0] + 0.3 * kTriangle[1] + 0.4 * kTriangle[2] +
                            0.05 * (kTriangle[1] - kTriangle[0]).cross(kTriangle[2] - kTriangle[0]).normalized();
  const int N = 1000;
  double inverse = 0.0;
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();
  const Eigen::Vector3d e1 = kTriangle[1] - kTriangle[0], e2 = kTriangle[2] - kTriangle[0];
  const double w = 0.5 * e1.cross(e2).norm() / (double(N) * N);
  for (int i = 0; i < N; ++i)
    for (int j = 0; i + j < N; ++j)
      for (int up = 0; up < 2; ++up) {
        if (up == 1 && i + j == N - 1) continue;
        const double a = (i + (up ? 2.0 : 1.0) / 3.0) / N, b = (j + (up ? 2.0 : 1.0) / 3.0) / N;
        const Eigen::Vector3d r = kTriangle[0] + a * e1 + b * e2 - p;
        inverse += w / r.norm();
        vector += w * r / std::pow(r.norm(), 3);
      }
  const double exact_inverse = integral_of_inverse_distance(kTriangle, p);
  const Eigen::Vector3d exact_vector = integral_of_r_over_r_cubed(kTriangle, p);
  INFO("1/r " << std::abs(inverse - exact_inverse) / exact_inverse << ", r/r^3 " << (vector - exact_vector).norm() / exact_vector.norm());
  // Measured: 1/r 1.9e-7, r/r^3 1.0e-7 (the centroid rule's error); bounds 2.8e-7, 1.5e-7.
  CHECK(std::abs(inverse - exact_inverse) < 2.8e-7 * exact_inverse);
  CHECK((vector - exact_vector).norm() < 1.5e-7 * exact_vector.norm());
}

TEST_CASE("assembled self block: U by polar rule, T by principal value with 1/2 I free term") {
  // A flat element alone: the principal value of T over its own plane is skew (r,i n_j - r,j n_i),
  // so H_ee - 1/2 I must be antisymmetric with zero normal-normal part.
  const std::array<Eigen::Vector3d, 3>& v = kTriangle;
  RowMatrixX3d V(3, 3);
  for (int i = 0; i < 3; ++i) V.row(i) = v[static_cast<std::size_t>(i)].transpose();
  RowMatrixX3i F(1, 3);
  F << 0, 1, 2;
  const TriangleMesh mesh(V, F);
  const InfluenceAssembler assembler(mesh, Material{1.0, 0.25, 0.0});
  Eigen::Matrix3d H, G;
  assembler.element_pair(0, 0, H, G);
  // Round-off. Every term of S is a scalar times d n^T - n d^T, whose (i, j) and (j, i) entries are
  // exact negatives (products commute) and whose diagonal is exactly 0; G's terms are scalars times
  // d d^T + (3 - 4 nu) I, exactly symmetric. So both are (anti)symmetric to the bit: measured 0;
  // bounds allow one rounding per entry. n . (S n) of an exactly antisymmetric S is two 3-term dot
  // products' rounding, <= 2 x 1.5 eps |S| (|n| = 1): measured 1.1e-19 = 0.09 eps |S|; bound 4 eps |S|.
  const Eigen::Matrix3d S = H - 0.5 * Eigen::Matrix3d::Identity();
  CHECK((S + S.transpose()).norm() <= 2.0 * kEps * S.norm());
  const Eigen::Vector3d n = mesh.normal(0);
  CHECK(std::abs(n.dot(S * n)) <= 4.0 * kEps * S.norm());
  CHECK((G - G.transpose()).norm() <= 2.0 * kEps * G.norm());
}

TEST_CASE("assembled self block: H_ee equals 1/2 I plus the closed-form principal value of T") {
  // On the flat element dr/dn = 0, so PV int T_ij = c (A_i n_j - A_j n_i) with
  // c = (1 - 2nu) / (8 pi (1 - nu)) and A = PV int (x - p)/|x - p|^2 dS in closed form
  // (principal_value_about_centroid). Measured |H - 1/2 I - PV| / |PV|: 9.2e-15 and 3.7e-15 (41 and
  // 17 eps) on the two regular triangles (rounding in the 208-point polar sum, whose terms cancel to
  // the principal value, so a worst-case N eps bound would be looser; bound 1e-13 = 450 eps kept),
  // 4.7e-10 on the sliver, where R(theta) is steep near its sharp vertices and the default polar
  // rule loses digits (bound 7e-10). An H_ee of 1/2 I, a wrong sign or a wrong (1 - 2 nu) factor
  // fails by O(1).
  const std::array<std::pair<std::array<Eigen::Vector3d, 3>, double>, 3> triangles = {{
      {kTriangle, 1e-13},
      {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 1, 0)}, 1e-13},
      {{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2.0, 0.1, -0.3), Eigen::Vector3d(1.1, 0.12, 0.05)}, 7e-10},
  }};
  for (const auto& [v, bound] : triangles)
    for (double nu : {0.0, 0.25, 0.45}) {
      RowMatrixX3d V(3, 3);
      for (int i = 0; i < 3; ++i) V.row(i) = v[static_cast<std::size_t>(i)].transpose();
      RowMatrixX3i F(1, 3);
      F << 0, 1, 2;
      const TriangleMesh mesh(V, F);
      const InfluenceAssembler assembler(mesh, Material{1.0, nu, 0.0});
      Eigen::Matrix3d H, G;
      assembler.element_pair(0, 0, H, G);
      const Eigen::Vector3d n = mesh.normal(0), A = principal_value_about_centroid(v);
      const Eigen::Matrix3d pv = (1.0 - 2.0 * nu) / (8.0 * M_PI * (1.0 - nu)) * (A * n.transpose() - n * A.transpose());
      const Eigen::Matrix3d S = H - 0.5 * Eigen::Matrix3d::Identity();
      INFO("nu " << nu << ", |H - I/2 - PV| = " << (S - pv).norm() << ", |PV| = " << pv.norm());
      CHECK(pv.norm() > 1e-3);  // the reference is not trivially zero (smallest measured: 1.5e-3)
      CHECK((S - pv).norm() < bound * pv.norm());
    }
}

TEST_CASE("quadrature options out of range are refused, naming the field") {
  using Catch::Matchers::Contains;
  CHECK_NOTHROW(QuadratureOptions().validate());
  CHECK_NOTHROW(ElementQuadrature(QuadratureOptions()));
  auto with = [](auto change) {
    QuadratureOptions o;
    change(o);
    return o;
  };
  const std::pair<QuadratureOptions, const char*> bad[] = {
      {with([](QuadratureOptions& o) { o.polar_order = 0; }), "polar_order"},
      {with([](QuadratureOptions& o) { o.polar_order = 41; }), "polar_order"},
      {with([](QuadratureOptions& o) { o.polar_max_angle = 0.0; }), "polar_max_angle"},
      {with([](QuadratureOptions& o) { o.polar_max_angle = std::nan(""); }), "polar_max_angle"},
      {with([](QuadratureOptions& o) { o.polar_max_angle = 4.0; }), "polar_max_angle"},
      {with([](QuadratureOptions& o) { o.mid_order = 0; }), "mid_order"},
      {with([](QuadratureOptions& o) { o.max_depth = -1; }), "max_depth"},
      {with([](QuadratureOptions& o) { o.far_ratio = 0.0; }), "far_ratio"},
      {with([](QuadratureOptions& o) { o.far_ratio = INFINITY; }), "far_ratio"},
      {with([](QuadratureOptions& o) { o.mid_ratio = -1.0; }), "mid_ratio"},
      {with([](QuadratureOptions& o) { o.mid_ratio = 5.0; }), "mid_ratio"},
  };
  for (const auto& [options, field] : bad) {
    INFO(field);
    CHECK_THROWS_AS(options.validate(), bemsurg::Error);
    CHECK_THROWS_WITH(ElementQuadrature(options), Contains(field));
  }
}
