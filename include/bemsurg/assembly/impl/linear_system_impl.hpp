// Implementation of bemsurg/assembly/linear_system.hpp (the paper's eq. 6 column swap).
#pragma once

#include "bemsurg/config.hpp"

namespace bemsurg {

namespace detail {
BEMSURG_INLINE void check_sizes(const InfluenceMatrices& hg, const BoundaryConditions& bc) {
  if (hg.H.rows() != bc.num_dofs() || hg.G.rows() != bc.num_dofs())
    throw BoundaryConditionError("boundary conditions have " + std::to_string(bc.num_dofs()) + " dofs, the influence matrices " +
                                 std::to_string(hg.H.rows()));
}
}  // namespace detail

BEMSURG_INLINE Eigen::MatrixXd build_system_matrix(const InfluenceMatrices& hg, const BoundaryConditions& bc) {
  detail::check_sizes(hg, bc);
  const Index n = bc.num_dofs();
  Eigen::MatrixXd A = large_dense_matrix(n, n);  // huge-page advice: see dense_storage.hpp
#pragma omp parallel for schedule(static)
  for (Index k = 0; k < n; ++k) {
    if (bc.kind(k) == BcKind::Traction)
      A.col(k) = hg.H.col(k);
    else
      A.col(k) = -hg.G.col(k);
  }
  return A;
}

BEMSURG_INLINE Eigen::MatrixXd build_system_matrix_in_place(InfluenceMatrices& hg, const BoundaryConditions& bc) {
  detail::check_sizes(hg, bc);
  const Index n = bc.num_dofs();
  Eigen::MatrixXd A = std::move(hg.H);  // traction-prescribed columns are H's already
  hg.H.resize(0, 0);
#pragma omp parallel for schedule(static)
  for (Index k = 0; k < n; ++k)
    if (bc.kind(k) != BcKind::Traction) A.col(k) = -hg.G.col(k);
  return A;
}

BEMSURG_INLINE Eigen::VectorXd build_right_hand_side(const InfluenceMatrices& hg, const BoundaryConditions& bc,
                                                     const Eigen::VectorXd& gravity) {
  detail::check_sizes(hg, bc);
  const Index n = bc.num_dofs();
  // Split the prescribed values by kind, then two matrix-vector products (BLAS-friendly).
  Eigen::VectorXd known_t = Eigen::VectorXd::Zero(n), known_u = Eigen::VectorXd::Zero(n);
  for (Index k = 0; k < n; ++k) (bc.kind(k) == BcKind::Traction ? known_t : known_u)(k) = bc.value(k);
  Eigen::VectorXd rhs = gravity.size() == n ? gravity : Eigen::VectorXd::Zero(n);
  if (gravity.size() != 0 && gravity.size() != n)
    throw BoundaryConditionError("gravity vector has " + std::to_string(gravity.size()) + " entries, expected " + std::to_string(n));
  if (known_t.squaredNorm() > 0.0) rhs.noalias() += hg.G * known_t;
  if (known_u.squaredNorm() > 0.0) rhs.noalias() -= hg.H * known_u;
  return rhs;
}

BEMSURG_INLINE BoundarySolution recover_boundary_solution(const BoundaryConditions& bc, const Eigen::VectorXd& x) {
  const Index E = bc.num_elements();
  if (x.size() != bc.num_dofs())
    throw BoundaryConditionError("solution has " + std::to_string(x.size()) + " entries, expected " + std::to_string(bc.num_dofs()));
  BoundarySolution s{RowMatrixX3d(E, 3), RowMatrixX3d(E, 3)};
  for (Index k = 0; k < 3 * E; ++k) {
    const bool traction_known = bc.kind(k) == BcKind::Traction;
    s.displacement(k / 3, k % 3) = traction_known ? x(k) : bc.value(k);
    s.traction(k / 3, k % 3) = traction_known ? bc.value(k) : x(k);
  }
  return s;
}

}  // namespace bemsurg
