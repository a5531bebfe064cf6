// Kelvin kernels: closed-form properties and the source-point derivatives used for interior stress.
#include <catch2/catch.hpp>

#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/kernels/kernel_gradients.hpp"

using namespace bemsurg;

namespace {
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
  CHECK((U - U.transpose()).norm() < 1e-15);
  const Eigen::Matrix3d U2 = k.displacement(2.0 * kR);
  CHECK((2.0 * U2 - U).norm() < 1e-14 * U.norm());
  const double mu = kMaterial.shear_modulus(), nu = kMaterial.poisson_ratio, r = kR.norm();
  const Eigen::Vector3d d = kR / r;
  const double expected_xy = d(0) * d(1) / (16.0 * M_PI * mu * (1.0 - nu) * r);
  CHECK(U(0, 1) == Approx(expected_xy).epsilon(1e-13));
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
  CHECK((T - T_from_U).norm() < 1e-12 * T.norm());
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
    CHECK((gU[static_cast<std::size_t>(b)] - fdU).norm() < 1e-8 * fdU.norm());
    CHECK((gT[static_cast<std::size_t>(b)] - fdT).norm() < 1e-8 * fdT.norm());
    CHECK((gP.col(b) - fdP).norm() < 1e-8 * fdP.norm());
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
  CHECK((div - expected).norm() < 1e-7 * expected.norm());
}
