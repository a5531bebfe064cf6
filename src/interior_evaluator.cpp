// Implementation of bemsurg/post/interior_evaluator.hpp (Somigliana's identity and its gradient).
#include "bemsurg/post/interior_evaluator.hpp"

#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/kernels/kernel_gradients.hpp"

namespace bemsurg {

InteriorEvaluator::InteriorEvaluator(const TriangleMesh& mesh, const Material& material, const Eigen::Vector3d& gravity,
                                     const QuadratureOptions& options)
    : mesh_(mesh), material_(material), body_force_(material.density * gravity), quadrature_(options) {
  material_.validate();
}

RowMatrixX3d InteriorEvaluator::displacement(const RowMatrixX3d& points, const BoundarySolution& s) const {
  const KelvinKernel kernel(material_);
  const GravityKernel gravity(material_, body_force_);
  const bool has_gravity = body_force_.squaredNorm() > 0.0;
  RowMatrixX3d out(points.rows(), 3);
#pragma omp parallel for schedule(dynamic, 1)
  for (Index k = 0; k < points.rows(); ++k) {
    const Eigen::Vector3d p = points.row(k).transpose();
    Eigen::Vector3d u = Eigen::Vector3d::Zero();
    Eigen::Matrix3d U, T;
    for (Index e = 0; e < mesh_.num_elements(); ++e) {
      const auto c = mesh_.corners(e);
      const Eigen::Vector3d n = mesh_.normal(e);
      const Eigen::Vector3d te = s.traction.row(e).transpose(), ue = s.displacement.row(e).transpose();
      quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double w) {
        const Eigen::Vector3d r = x - p;
        kernel.displacement_and_traction(r, n, U, T);
        u += w * (U * te - T * ue);
        if (has_gravity) u += w * gravity(r, n);
      });
    }
    out.row(k) = u.transpose();
  }
  return out;
}

StressRows InteriorEvaluator::stress(const RowMatrixX3d& points, const BoundarySolution& s) const {
  const KelvinKernelGradients grad(material_);
  const double lambda = material_.lame_lambda(), mu = material_.shear_modulus();
  const bool has_gravity = body_force_.squaredNorm() > 0.0;
  StressRows out(points.rows(), 6);
#pragma omp parallel for schedule(dynamic, 1)
  for (Index k = 0; k < points.rows(); ++k) {
    const Eigen::Vector3d p = points.row(k).transpose();
    Eigen::Matrix3d du = Eigen::Matrix3d::Zero();  // du(a, b) = d u_a / d p_b
    for (Index e = 0; e < mesh_.num_elements(); ++e) {
      const auto c = mesh_.corners(e);
      const Eigen::Vector3d n = mesh_.normal(e);
      const Eigen::Vector3d te = s.traction.row(e).transpose(), ue = s.displacement.row(e).transpose();
      quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double w) {
        const Eigen::Vector3d r = x - p;
        const KernelGradient gU = grad.displacement(r);
        const KernelGradient gT = grad.traction(r, n);
        for (int b = 0; b < 3; ++b)
          du.col(b) += w * (gU[static_cast<std::size_t>(b)] * te - gT[static_cast<std::size_t>(b)] * ue);
        if (has_gravity) du += w * grad.gravity(r, n, body_force_);
      });
    }
    const Eigen::Matrix3d strain = 0.5 * (du + du.transpose());
    Eigen::Matrix3d sigma = 2.0 * mu * strain;
    sigma.diagonal().array() += lambda * strain.trace();
    out.row(k) << sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(0, 2);
  }
  return out;
}

}  // namespace bemsurg
