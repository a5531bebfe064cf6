// bemsurg/kernels/kelvin_kernel.hpp: the 3D Kelvin fundamental solution of linear elastostatics
// (docs/design.md, kernels; Wang et al. 2007 eqs. 2-3). U_ij and T_ij are the displacement and traction in
// direction j at the field point Q due to a unit point force in direction i at the source point p.
// Every function takes r = x_Q - x_p, so the caller decides where points come from (collocation
// node, interior point, quadrature point) and the kernels stay free of geometry.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "bemsurg/kernels/kelvin_constants.hpp"
#include "bemsurg/material.hpp"

namespace bemsurg {

/// The 3D Kelvin fundamental solution (Wang et al. 2007 eqs. 2-3): U_ij and T_ij, the displacement and traction in
/// direction j at the field point Q due to a unit point force in direction i at the source point p, from r = x_Q - x_p.
/// \ingroup kernels
class KelvinKernel {
 public:
  explicit KelvinKernel(const Material& m) : c_(m) {}

  double shear_modulus() const { return c_.mu; }
  double poisson_ratio() const { return c_.nu; }
  const KelvinConstants& constants() const { return c_; }

  /// U_ij = [(3 - 4 nu) delta_ij + r,i r,j] / (16 pi mu (1 - nu) r)
  Eigen::Matrix3d displacement(const Eigen::Vector3d& r) const {
    const double rn = r.norm();
    const Eigen::Vector3d d = r / rn;
    Eigen::Matrix3d u = d * d.transpose();
    u.diagonal().array() += c_.three_minus_4nu;
    return (c_.u_scale / rn) * u;
  }

  /// T_ij = -[dr/dn ((1 - 2nu) delta_ij + 3 r,i r,j) - (1 - 2nu)(r,i n_j - r,j n_i)] / (8 pi (1 - nu) r^2)
  /// with n the unit outward normal at Q.
  Eigen::Matrix3d traction(const Eigen::Vector3d& r, const Eigen::Vector3d& n) const {
    const double rn = r.norm();
    const Eigen::Vector3d d = r / rn;
    const double drdn = d.dot(n);
    const double a = c_.one_minus_2nu;
    Eigen::Matrix3d t = (3.0 * drdn) * (d * d.transpose()) - a * (d * n.transpose() - n * d.transpose());
    t.diagonal().array() += a * drdn;
    return (c_.t_scale / (rn * rn)) * t;
  }

  /// Both kernels at once: the quadrature loop needs both at every point, and they share r, r,i.
  void displacement_and_traction(const Eigen::Vector3d& r, const Eigen::Vector3d& n, Eigen::Matrix3d& u, Eigen::Matrix3d& t) const {
    const double rn = r.norm();
    const double inv = 1.0 / rn;
    const Eigen::Vector3d d = r * inv;
    const Eigen::Matrix3d dd = d * d.transpose();
    const double drdn = d.dot(n);
    const double a = c_.one_minus_2nu;
    u = dd;
    u.diagonal().array() += c_.three_minus_4nu;
    u *= c_.u_scale * inv;
    t = (3.0 * drdn) * dd - a * (d * n.transpose() - n * d.transpose());
    t.diagonal().array() += a * drdn;
    t *= c_.t_scale * inv * inv;
  }

  /// The traction kernel without its 1/r^2 factor and with dr/dn = 0: what remains on the source's
  /// own flat element, (1 - 2nu)(r,i n_j - r,j n_i) / (8 pi (1 - nu)). Used by the principal-value rule.
  Eigen::Matrix3d traction_tangential_part(const Eigen::Vector3d& d, const Eigen::Vector3d& n) const {
    return (-c_.t_scale * c_.one_minus_2nu) * (d * n.transpose() - n * d.transpose());
  }

  /// The displacement kernel times r: U_ij r = [(3 - 4 nu) delta_ij + r,i r,j] / (16 pi mu (1 - nu)).
  /// It depends on the direction d only, which makes the self-element integral exact in r.
  Eigen::Matrix3d displacement_times_r(const Eigen::Vector3d& d) const {
    Eigen::Matrix3d u = d * d.transpose();
    u.diagonal().array() += c_.three_minus_4nu;
    return c_.u_scale * u;
  }

 private:
  KelvinConstants c_;
};

/// Gravity (uniform body force per volume b = rho g) moved from the volume to the surface:
/// P_i = [b_i dr/dn - n_i (b . r,) / (2 (1 - nu))] / (8 pi mu), integrated over the boundary, adds
/// to the displacement at the source point (docs/design.md, kernels). P is bounded, so no singular rule is needed.
/// \ingroup kernels
class GravityKernel {
 public:
  GravityKernel(const Material& m, const Eigen::Vector3d& body_force) : GravityKernel(KelvinConstants(m), body_force) {}
  GravityKernel(const KelvinConstants& c, const Eigen::Vector3d& body_force) : b_(body_force), scale_(c.p_scale), half_inv_(c.p_half_inv) {}

  const Eigen::Vector3d& body_force() const { return b_; }

  Eigen::Vector3d operator()(const Eigen::Vector3d& r, const Eigen::Vector3d& n) const {
    const Eigen::Vector3d d = r / r.norm();
    return scale_ * (b_ * d.dot(n) - n * (half_inv_ * b_.dot(d)));
  }

  /// int_e P dS from the integrals of its two direction terms over a flat element with normal n:
  /// s_n = int dr/dn dS and s_d = int r, dS (P is linear in both; the blocked assembler's form).
  Eigen::Vector3d from_integrals(double s_n, const Eigen::Vector3d& s_d, const Eigen::Vector3d& n) const {
    return scale_ * (b_ * s_n - n * (half_inv_ * b_.dot(s_d)));
  }

  /// P with dr/dn = 0 (the source's own flat element): -n (b . r,) / (2(1-nu)) / (8 pi mu).
  Eigen::Vector3d tangential_part(const Eigen::Vector3d& d, const Eigen::Vector3d& n) const { return -scale_ * half_inv_ * b_.dot(d) * n; }

 private:
  Eigen::Vector3d b_;
  double scale_;
  double half_inv_;
};

}  // namespace bemsurg
