// Quadrature rules and the self-element polar rules, each against an exact or independent reference.
#include <catch2/catch.hpp>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"
#include "bemsurg/quadrature/triangle_rules.hpp"

using namespace bemsurg;

namespace {
// int over the reference triangle of xi^a eta^b = a! b! / (a + b + 2)!
double monomial_integral(int a, int b) {
  return std::tgamma(a + 1.0) * std::tgamma(b + 1.0) / std::tgamma(a + b + 3.0);
}
double apply(const TriangleRule& r, int a, int b) {
  double s = 0.0;
  for (std::size_t k = 0; k < r.weights.size(); ++k)
    s += 0.5 * r.weights[k] * std::pow(r.points[k].x(), a) * std::pow(r.points[k].y(), b);
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

const std::array<Eigen::Vector3d, 3> kTriangle = {Eigen::Vector3d(0.1, 0.0, 0.2), Eigen::Vector3d(1.3, 0.2, 0.1),
                                                 Eigen::Vector3d(0.4, 0.9, 0.5)};
}  // namespace

TEST_CASE("triangle rules integrate polynomials of their degree exactly") {
  for (const TriangleRule& r : {radon7_rule(), collapsed_gauss_rule(3), collapsed_gauss_rule(6)}) {
    double wsum = 0.0;
    for (double w : r.weights) wsum += w;
    CHECK(wsum == Approx(1.0).epsilon(1e-14));
    for (int a = 0; a <= r.degree; ++a)
      for (int b = 0; a + b <= r.degree; ++b) CHECK(apply(r, a, b) == Approx(monomial_integral(a, b)).epsilon(1e-12));
  }
}

TEST_CASE("Gauss-Legendre integrates degree 2n-1 exactly on the unit interval") {
  for (int n : {1, 2, 5, 12}) {
    const LineRule g = gauss_legendre(n);
    for (int d = 0; d <= 2 * n - 1; ++d) {
      double s = 0.0;
      for (std::size_t k = 0; k < g.points.size(); ++k) s += g.weights[k] * std::pow(g.points[k], d);
      CHECK(s == Approx(1.0 / (d + 1)).epsilon(1e-13));
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
  CHECK((polar - ref).norm() < 1e-10 * ref.norm());
}

TEST_CASE("adaptive rule on a neighbouring element converges to a heavily subdivided reference") {
  const Material m{1.0, 0.3, 0.0};
  const KelvinKernel k(m);
  // Source point just outside the triangle (like the centroid of a neighbour across an edge).
  const Eigen::Vector3d mid = 0.5 * (kTriangle[0] + kTriangle[1]);
  const Eigen::Vector3d n = (kTriangle[1] - kTriangle[0]).cross(kTriangle[2] - kTriangle[0]).normalized();
  const Eigen::Vector3d inward = (kTriangle[2] - mid).normalized();
  const Eigen::Vector3d p = mid - 0.15 * inward;
  auto run = [&](const QuadratureOptions& o) {
    const ElementQuadrature q(o);
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    q.integrate(p, kTriangle[0], kTriangle[1], kTriangle[2],
                [&](const Eigen::Vector3d& x, double w) { H += w * k.traction(x - p, n); });
    return H;
  };
  QuadratureOptions reference;
  reference.far_ratio = 40.0;
  reference.mid_ratio = 12.0;
  reference.mid_order = 12;
  reference.max_depth = 14;
  const Eigen::Matrix3d ref = run(reference);
  const Eigen::Matrix3d ours = run(QuadratureOptions());
  CHECK((ours - ref).norm() < 1e-6 * ref.norm());
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
  const Eigen::Matrix3d S = H - 0.5 * Eigen::Matrix3d::Identity();
  CHECK((S + S.transpose()).norm() < 1e-14);
  const Eigen::Vector3d n = mesh.normal(0);
  CHECK(std::abs(n.dot(S * n)) < 1e-14);
  CHECK((G - G.transpose()).norm() < 1e-14 * G.norm());
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
