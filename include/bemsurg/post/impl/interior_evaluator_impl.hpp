// Implementation of bemsurg/post/interior_evaluator.hpp (Somigliana's identity and its gradient).
#pragma once

#include "bemsurg/config.hpp"

#include <sstream>

#include "bemsurg/assembly/element_types.hpp"
#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/kernels/kernel_gradients.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

BEMSURG_INLINE InteriorEvaluator::InteriorEvaluator(const TriangleMesh& mesh, const Material& material, const Eigen::Vector3d& gravity,
                                                    const QuadratureOptions& options)
    : mesh_(mesh), material_(material), body_force_(material.density * gravity), quadrature_(options) {
  material_.validate();
}

BEMSURG_INLINE void InteriorEvaluator::require_clearance(const RowMatrixX3d& points, ClearanceQuantity quantity) const {
  if (allow_too_close_) return;
  const ClearanceViolation v = find_point_too_close(mesh_, points, quadrature_.options(), quantity);
  if (v.point < 0) return;
  std::ostringstream s;
  use_classic_locale(s).precision(10);
  s << "InteriorEvaluator::" << (quantity == ClearanceQuantity::Stress ? "stress" : "displacement") << ": point " << v.point << " ("
    << points(v.point, 0) << ", " << points(v.point, 1) << ", " << points(v.point, 2) << ") "
    << describe_clearance_violation(v, quadrature_.options());
  throw InvalidArgumentError(s.str());
}

BEMSURG_INLINE RowMatrixX3d InteriorEvaluator::displacement(const RowMatrixX3d& points, const BoundarySolution& s) const {
  require_clearance(points, ClearanceQuantity::Displacement);
  const KelvinKernel kernel(material_);
  const GravityKernel gravity(material_, body_force_);
  const bool has_gravity = body_force_.squaredNorm() > 0.0;
  RowMatrixX3d out(points.rows(), 3);
  // u(p) = sum_e int_e (U t_e - T u_e) dS + int P dS (Somigliana, c = I).
  traverse<Eigen::Vector3d>(
      points, s,
      [&](Eigen::Vector3d& u, const Eigen::Vector3d& r, const Eigen::Vector3d& n, double w, const Eigen::Vector3d& te,
          const Eigen::Vector3d& ue) {
        Eigen::Matrix3d U, T;
        kernel.displacement_and_traction(r, n, U, T);
        u += w * (U * te - T * ue);
        if (has_gravity) u += w * gravity(r, n);
      },
      [&](Index k, const Eigen::Vector3d& u) { out.row(k) = u.transpose(); });
  return out;
}

BEMSURG_INLINE StressRows InteriorEvaluator::stress(const RowMatrixX3d& points, const BoundarySolution& s) const {
  require_clearance(points, ClearanceQuantity::Stress);
  const KelvinKernelGradients grad(material_);
  const bool has_gravity = body_force_.squaredNorm() > 0.0;
  StressRows out(points.rows(), 6);
  // du(a, b) = d u_a / d p_b: the source-point derivative of the identity above (eqs. 7-9).
  traverse<Eigen::Matrix3d>(
      points, s,
      [&](Eigen::Matrix3d& du, const Eigen::Vector3d& r, const Eigen::Vector3d& n, double w, const Eigen::Vector3d& te,
          const Eigen::Vector3d& ue) {
        const KernelGradient gU = grad.displacement(r);
        const KernelGradient gT = grad.traction(r, n);
        for (int b = 0; b < 3; ++b) du.col(b) += w * (gU[static_cast<std::size_t>(b)] * te - gT[static_cast<std::size_t>(b)] * ue);
        if (has_gravity) du += w * grad.gravity(r, n, body_force_);
      },
      [&](Index k, const Eigen::Matrix3d& du) {
        const Eigen::Matrix3d sigma = material_.stress(du);
        out.row(k) << sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(0, 2);
      });
  return out;
}

template <class Accumulator, class Integrand, class Finish>
void InteriorEvaluator::traverse(const RowMatrixX3d& points, const BoundarySolution& s, const Integrand& integrand,
                                 const Finish& finish) const {
  const Index E = mesh_.num_elements();
  const bool linear = s.displacement.rows() == 3 * E && E > 0;  // per-node values of linear elements (3E rows)
  if (!linear && (s.displacement.rows() != E || s.traction.rows() != E))
    throw InvalidArgumentError("InteriorEvaluator: the boundary solution has " + std::to_string(s.displacement.rows()) +
                               " rows; expected one per element (" + std::to_string(E) + ") or one per linear node (" +
                               std::to_string(3 * E) + ")");
#pragma omp parallel for schedule(dynamic, 1)
  for (Index k = 0; k < points.rows(); ++k) {
    const Eigen::Vector3d p = points.row(k).transpose();
    Accumulator sum = Accumulator::Zero();
    for (Index e = 0; e < mesh_.num_elements(); ++e) {
      const auto c = mesh_.corners(e);
      const Eigen::Vector3d n = mesh_.normal(e);
      if (!linear) {
        const Eigen::Vector3d te = s.traction.row(e).transpose(), ue = s.displacement.row(e).transpose();
        quadrature_.integrate(p, c[0], c[1], c[2],
                              [&](const Eigen::Vector3d& x, double w) { integrand(sum, Eigen::Vector3d(x - p), n, w, te, ue); });
        continue;
      }
      // Linear elements: the field N_k(x) u_(e,k) at each quadrature point (docs/elements.md).
      const Eigen::Matrix3d tn = s.traction.middleRows<3>(3 * e), un = s.displacement.middleRows<3>(3 * e);
      quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double w) {
        const Eigen::Vector3d N = linear_shape_values(c, n, x);
        integrand(sum, Eigen::Vector3d(x - p), n, w, Eigen::Vector3d(tn.transpose() * N), Eigen::Vector3d(un.transpose() * N));
      });
    }
    finish(k, sum);
  }
}

}  // namespace bemsurg
