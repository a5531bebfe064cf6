// bemsurg/kernels/kernel_gradients.hpp: derivatives of the Kelvin kernels U, T and of the gravity
// kernel P with respect to the source point p, for stresses at interior points (Wang et al. 2007
// eqs. 7-9). Rather than transcribing the stress kernels D, S and W from a table (where index and
// sign conventions differ between books), the code differentiates the same U, T, P that assembly
// uses; Hooke's law then gives sigma(p). tests/test_kernels.cpp checks every derivative against
// central finite differences of the kernel itself.
//
// Layout: grad[b](a, j) = d K_aj / d p_b for the 3x3 kernels; grad(a, b) = d P_a / d p_b for P.
// Because every kernel depends on r = x_Q - p only, d/dp_b = -d/dr_b.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>

#include "bemsurg/kernels/kelvin_constants.hpp"
#include "bemsurg/material.hpp"

namespace bemsurg {

using KernelGradient = std::array<Eigen::Matrix3d, 3>;

/// Derivatives of the kernels U, T and P with respect to the source point p (grad[b](a, j) = d K_aj / d p_b), for
/// stresses at interior points through Hooke's law (Wang et al. 2007 eqs. 7-9).
/// \ingroup kernels
class KelvinKernelGradients {
 public:
  explicit KelvinKernelGradients(const Material& m) : c_(m) {}

  /// U_aj = C [(3 - 4nu) delta_aj / r + r_a r_j / r^3]
  /// dU_aj/dr_b = C [-(3 - 4nu) delta_aj r_b / r^3 + (delta_ab r_j + delta_jb r_a) / r^3 - 3 r_a r_j r_b / r^5]
  KernelGradient displacement(const Eigen::Vector3d& r) const {
    const double rn = r.norm(), r3 = rn * rn * rn, r5 = r3 * rn * rn;
    KernelGradient g;
    for (int b = 0; b < 3; ++b) {
      Eigen::Matrix3d& m = g[static_cast<std::size_t>(b)];
      m = (-3.0 / r5 * r(b)) * (r * r.transpose());
      m.diagonal().array() -= c_.three_minus_4nu * r(b) / r3;
      m.row(b) += r.transpose() / r3;  // delta_ab r_j
      m.col(b) += r / r3;              // delta_jb r_a
      m *= -c_.u_scale;                // d/dp = -d/dr
    }
    return g;
  }

  /// T_aj = K [A (r.n) delta_aj / r^3 + 3 (r.n) r_a r_j / r^5 - A (r_a n_j - r_j n_a) / r^3], A = 1 - 2nu.
  KernelGradient traction(const Eigen::Vector3d& r, const Eigen::Vector3d& n) const {
    const double a = c_.one_minus_2nu;
    const double rn = r.norm(), r2 = rn * rn, r3 = r2 * rn, r5 = r3 * r2, r7 = r5 * r2;
    const double rdn = r.dot(n);
    const Eigen::Matrix3d rr = r * r.transpose();
    const Eigen::Matrix3d skew = r * n.transpose() - n * r.transpose();  // r_a n_j - r_j n_a
    KernelGradient g;
    for (int b = 0; b < 3; ++b) {
      Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
      m.diagonal().array() += a * (n(b) / r3 - 3.0 * rdn * r(b) / r5);
      m += (3.0 * n(b) / r5 - 15.0 * rdn * r(b) / r7) * rr;
      m.row(b) += (3.0 * rdn / r5) * r.transpose();  // delta_ab r_j
      m.col(b) += (3.0 * rdn / r5) * r;              // delta_jb r_a
      // -A d/dr_b (r_a n_j - r_j n_a) / r^3
      m.row(b) -= (a / r3) * n.transpose();  // delta_ab n_j
      m.col(b) += (a / r3) * n;              // delta_jb n_a
      m += (3.0 * a * r(b) / r5) * skew;
      g[static_cast<std::size_t>(b)] = -c_.t_scale * m;
    }
    return g;
  }

  /// P_a = s [b_a (r.n)/r - n_a (b.r) / (2 (1 - nu) r)]; returns dP_a/dp_b as a 3x3 (a, b).
  Eigen::Matrix3d gravity(const Eigen::Vector3d& r, const Eigen::Vector3d& n, const Eigen::Vector3d& body_force) const {
    const double rn = r.norm(), r3 = rn * rn * rn;
    const Eigen::Vector3d d_rdn = n / rn - (r.dot(n) / r3) * r;                    // d((r.n)/r)/dr_b
    const Eigen::Vector3d d_bdr = body_force / rn - (body_force.dot(r) / r3) * r;  // d((b.r)/r)/dr_b
    return -c_.p_scale * (body_force * d_rdn.transpose() - c_.p_half_inv * n * d_bdr.transpose());
  }

 private:
  KelvinConstants c_;
};

}  // namespace bemsurg
