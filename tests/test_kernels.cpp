// Kelvin kernels: closed-form properties and the source-point derivatives used for interior stress.
#include <catch2/catch.hpp>

#include <limits>

#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/kernels/kernel_gradients.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {
using bemsurg_test::kEps;
const Material kMaterial{2.5, 0.3, 1.7};
const Eigen::Vector3d kR(0.3, -0.7, 0.45);
const Eigen::Vector3d kN = Eigen::Vector3d(0.2, 0.5, -0.8).normalized();
const Eigen::Vector3d kB(0.1, -0.4, -2.0);

// Central difference of a kernel with respect to the source point p (r = x - p, so dr = -dp).
template <class F>
auto source_derivative(F&& f, int b) {
  const double h = 1e-5;
  Eigen::Vector3d dp = Eigen::Vector3d::Zero();
  dp(b) = h;
  return ((f(kR - dp) - f(kR + dp)) / (2.0 * h)).eval();
}
}  // namespace

TEST_CASE("U is symmetric, decays as 1/r and matches the Kelvin formula") {
  const KelvinKernel k(kMaterial);
  const Eigen::Matrix3d U = k.displacement(kR);
  // Measured 0: U_ij = s r,i r,j (+ s (3 - 4 nu) on the diagonal) and products commute exactly, so
  // U is symmetric to the bit; the bound allows one rounding (eps/2 relative) in each of U_ij, U_ji.
  CHECK((U - U.transpose()).norm() <= 2.0 * kEps * U.norm());
  // Measured 0: r -> 2r scales every intermediate by a power of two, exact in binary floating
  // point, so U(2r) = U(r)/2 to the bit; the bound allows one rounding per entry.
  const Eigen::Matrix3d U2 = k.displacement(2.0 * kR);
  CHECK((2.0 * U2 - U).norm() <= 2.0 * kEps * U.norm());
  const double mu = kMaterial.shear_modulus(), nu = kMaterial.poisson_ratio, r = kR.norm();
  const Eigen::Vector3d d = kR / r;
  const double expected_xy = d(0) * d(1) / (16.0 * M_PI * mu * (1.0 - nu) * r);
  // Measured 0. Both sides are the same r,x r,y times products and quotients of mu, 1 - nu and r
  // (no sums that cancel): 7 and 6 roundings of eps/2, so within 6.5 eps; bound 8 eps.
  CHECK(U(0, 1) == Approx(expected_xy).epsilon(8.0 * kEps));
}

TEST_CASE("T is the traction of the Kelvin field: T n-derivative check via Hooke of grad U") {
  // The traction at Q due to a unit force at p is sigma(Q) n; sigma from the gradient of U with
  // respect to the field point (= -gradient with respect to p). Independent of the T formula.
  const KelvinKernel k(kMaterial);
  const KelvinKernelGradients g(kMaterial);
  const KernelGradient gU = g.displacement(kR);  // d U_aj / d p_b
  Eigen::Matrix3d T_from_U;
  for (int a = 0; a < 3; ++a) {
    Eigen::Matrix3d grad;  // grad(j, b) = d u_j / d x_b (field point) for the force in direction a
    for (int b = 0; b < 3; ++b) grad.col(b) = -gU[static_cast<std::size_t>(b)].row(a).transpose();
    T_from_U.row(a) = (kMaterial.stress(grad) * kN).transpose();
  }
  const Eigen::Matrix3d T = k.traction(kR, kN);
  // Round-off between two exact paths: measured 2.9e-16 relative (1.3 eps). Each path takes about
  // 20 roundings (eps/2 relative) and its sums cancel little here (sum of |terms| / |T| = 1.25 for
  // both the kernel formula and Hooke's law: dr/dn = -0.76 at this r, n), so they agree within
  // ~2 x 20 x 1.25 x eps/2 = 25 eps; bound 32 eps.
  CHECK((T - T_from_U).norm() < 32.0 * kEps * T.norm());
}

TEST_CASE("kernel gradients match central finite differences of the kernels") {
  const KelvinKernel k(kMaterial);
  const KelvinKernelGradients g(kMaterial);
  const GravityKernel p(kMaterial, kB);
  const KernelGradient gU = g.displacement(kR), gT = g.traction(kR, kN);
  const Eigen::Matrix3d gP = g.gravity(kR, kN, kB);
  for (int b = 0; b < 3; ++b) {
    const Eigen::Matrix3d fdU = source_derivative([&](const Eigen::Vector3d& r) { return k.displacement(r); }, b);
    const Eigen::Matrix3d fdT = source_derivative([&](const Eigen::Vector3d& r) { return k.traction(r, kN); }, b);
    const Eigen::Vector3d fdP = source_derivative([&](const Eigen::Vector3d& r) { return p(r, kN); }, b);
    // The central differences' O(h^2) error (h = 1e-5; it grows 4.2x at h = 2e-5, so truncation,
    // not rounding, dominates). Measured, worst over b: U 1.7e-10, T 3.5e-10, P 1.1e-10; bounds ~3x.
    CHECK((gU[static_cast<std::size_t>(b)] - fdU).norm() < 5e-10 * fdU.norm());
    CHECK((gT[static_cast<std::size_t>(b)] - fdT).norm() < 1e-9 * fdT.norm());
    CHECK((gP.col(b) - fdP).norm() < 3.5e-10 * fdP.norm());
  }
}

TEST_CASE("gravity kernel: divergence of P equals U b (the volume integrand it replaces)") {
  // P was built so that int_Gamma P dS = int_Omega U b dV; by the divergence theorem that needs
  // P_i = F_ik n_k with div_Q F_i. = U_ij b_j. Check with finite differences of F in Q.
  const KelvinKernel k(kMaterial);
  const GravityKernel p(kMaterial, kB);
  const double h = 1e-5;
  Eigen::Vector3d div = Eigen::Vector3d::Zero();
  for (int m = 0; m < 3; ++m) {
    Eigen::Vector3d dq = Eigen::Vector3d::Zero();
    dq(m) = h;
    // F_im = P_i evaluated with n = e_m (P is linear in n).
    div += (p(kR + dq, Eigen::Vector3d::Unit(m)) - p(kR - dq, Eigen::Vector3d::Unit(m))) / (2.0 * h);
  }
  const Eigen::Vector3d expected = k.displacement(kR) * kB;
  // Measured 2.5e-11 relative: the O(h^2) error of the differences (1.2e-10 at h = 2e-5; the
  // rounding floor, seen at smaller h, is ~1e-11). Bound ~3x.
  CHECK((div - expected).norm() < 7.5e-11 * expected.norm());
}
