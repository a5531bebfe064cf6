// bemsurg/assembly/influence_assembler.hpp: the dense influence matrices of constant-element
// collocation BEM (DESIGN.md §3-4; Wang et al. 2007 eq. 5):
//   H(3i.., 3e..) = 1/2 I delta_ie + int_e T(p_i, Q) dS   (acts on displacements u_e)
//   G(3i.., 3e..) =                  int_e U(p_i, Q) dS   (acts on tractions t_e)
//   g(3i..)       = sum_e int_e P(p_i, Q) dS               (gravity, body force b = rho * gravity)
// so that H u = G t + g. The diagonal H block is evaluated directly (1/2 I plus the principal
// value), never from row sums, so a change to a few elements (a cut) changes only their rows and
// columns, and the rigid-body identity (rows of H sum to zero) stays an honest test of quadrature.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"

namespace bemsurg {

struct InfluenceMatrices {
  Eigen::MatrixXd H;  // 3E x 3E, includes the free term 1/2 I
  Eigen::MatrixXd G;  // 3E x 3E
};

class InfluenceAssembler {
 public:
  InfluenceAssembler(const TriangleMesh& mesh, const Material& material, const QuadratureOptions& options = {});

  const TriangleMesh& mesh() const { return mesh_; }
  const Material& material() const { return material_; }
  const KelvinKernel& kernel() const { return kernel_; }
  const ElementQuadrature& quadrature() const { return quadrature_; }

  /// The 3x3 blocks for collocation element i and element e (H includes 1/2 I when i == e).
  void element_pair(Index i, Index e, Eigen::Matrix3d& H, Eigen::Matrix3d& G) const;

  /// Both full matrices, rows in parallel (OpenMP).
  InfluenceMatrices assemble() const;

  /// Rows (3 per listed element, in list order) of H and G over all columns: out_H, out_G are
  /// resized to 3|rows| x 3E. Used when elements are added or reshaped (cutting).
  void assemble_rows(const std::vector<Index>& rows, Eigen::MatrixXd& out_H, Eigen::MatrixXd& out_G) const;
  /// Columns (3 per listed element) of H and G over all rows: 3E x 3|cols|.
  void assemble_columns(const std::vector<Index>& cols, Eigen::MatrixXd& out_H, Eigen::MatrixXd& out_G) const;

  /// Gravity right-hand side for body force per volume b = density * gravity (m/s^2).
  Eigen::VectorXd gravity_vector(const Eigen::Vector3d& gravity) const;
  /// Contribution of element e to the gravity term at a source point p (p may be any point;
  /// p equal to e's centroid uses the polar rule).
  Eigen::Vector3d gravity_element(const Eigen::Vector3d& p, Index e, const GravityKernel& kernel, bool self) const;

 private:
  const TriangleMesh& mesh_;
  Material material_;
  KelvinKernel kernel_;
  ElementQuadrature quadrature_;
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#include "bemsurg/assembly/impl/influence_assembler_impl.hpp"
