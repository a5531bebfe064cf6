// tests/support/reference_assembler.hpp: the straightforward assembly of H, G and the gravity
// vector, one element pair at a time through ElementQuadrature and KelvinKernel (the library's
// implementation before the blocked far-field loop of issue 9). Kept here as the independent
// answer the fast InfluenceAssembler is compared against (tests/test_assembly_fast_vs_reference.cpp):
// same rules, same points, only the order of the arithmetic differs.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"

namespace bemsurg::testing {

class ReferenceAssembler {
 public:
  ReferenceAssembler(const TriangleMesh& mesh, const Material& material, const QuadratureOptions& options = {})
      : mesh_(mesh), material_(material), kernel_(material), quadrature_(options) {}

  /// H and G blocks of collocation element i and element e (H includes 1/2 I when i == e).
  void element_pair(Index i, Index e, Eigen::Matrix3d& H, Eigen::Matrix3d& G) const {
    const Eigen::Vector3d p = mesh_.centroid(i);
    const auto c = mesh_.corners(e);
    const Eigen::Vector3d n = mesh_.normal(e);
    H.setZero();
    G.setZero();
    if (i == e) {
      quadrature_.polar(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& d, double R, double w) {
        G.noalias() += (w * R) * kernel_.displacement_times_r(d);
        H.noalias() += (w * std::log(R)) * kernel_.traction_tangential_part(d, n);
      });
      H.diagonal().array() += 0.5;
      return;
    }
    Eigen::Matrix3d u, t;
    quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double w) {
      kernel_.displacement_and_traction(x - p, n, u, t);
      G.noalias() += w * u;
      H.noalias() += w * t;
    });
  }

  /// Rows (3 per listed element) x columns (3 per listed element) of H and G.
  void assemble(const std::vector<Index>& rows, const std::vector<Index>& cols, Eigen::MatrixXd& H, Eigen::MatrixXd& G) const {
    const Index R = static_cast<Index>(rows.size()), C = static_cast<Index>(cols.size());
    H.resize(3 * R, 3 * C);
    G.resize(3 * R, 3 * C);
    Eigen::Matrix3d h, g;
    for (Index k = 0; k < R; ++k)
      for (Index l = 0; l < C; ++l) {
        element_pair(rows[static_cast<std::size_t>(k)], cols[static_cast<std::size_t>(l)], h, g);
        H.block<3, 3>(3 * k, 3 * l) = h;
        G.block<3, 3>(3 * k, 3 * l) = g;
      }
  }

  std::vector<Index> all() const {
    std::vector<Index> v(static_cast<std::size_t>(mesh_.num_elements()));
    for (Index e = 0; e < mesh_.num_elements(); ++e) v[static_cast<std::size_t>(e)] = e;
    return v;
  }

  Eigen::Vector3d gravity_element(const Eigen::Vector3d& p, Index e, const GravityKernel& kernel, bool self) const {
    const auto c = mesh_.corners(e);
    const Eigen::Vector3d n = mesh_.normal(e);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    if (self) {
      quadrature_.polar(p, c[0], c[1], c[2],
                        [&](const Eigen::Vector3d& d, double R, double w) { sum += (0.5 * w * R * R) * kernel.tangential_part(d, n); });
    } else {
      quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double w) { sum += w * kernel(x - p, n); });
    }
    return sum;
  }

  Eigen::VectorXd gravity_vector(const Eigen::Vector3d& gravity) const {
    const Index E = mesh_.num_elements();
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * E);
    const Eigen::Vector3d body_force = material_.density * gravity;
    if (body_force.squaredNorm() == 0.0) return g;
    const GravityKernel kernel(material_, body_force);
    for (Index i = 0; i < E; ++i) {
      const Eigen::Vector3d p = mesh_.centroid(i);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (Index e = 0; e < E; ++e) sum += gravity_element(p, e, kernel, e == i);
      g.segment<3>(3 * i) = sum;
    }
    return g;
  }

 private:
  const TriangleMesh& mesh_;
  Material material_;
  KelvinKernel kernel_;
  ElementQuadrature quadrature_;
};

}  // namespace bemsurg::testing
