// bemsurg/assembly/linear_system.hpp: the column swap that puts every unknown on the left
// (Wang et al. 2007 eq. 6): [A*]{x} = {R_bc} + {R_G}. For dof k with traction prescribed the
// unknown is u_k and column k of A* is H's; with displacement prescribed the unknown is t_k and
// column k is -G's. The known values move to the right-hand side.
#pragma once

#include <Eigen/Core>

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"

namespace bemsurg {

/// The system after the column swap that puts every unknown on the left (Wang et al. 2007 eq. 6): the matrix A* and
/// the right-hand side R_bc + R_G.
/// \ingroup assembly
struct LinearSystem {
  Eigen::MatrixXd matrix;  // A*
  Eigen::VectorXd rhs;     // R_bc + R_G
};

/// Per-element boundary values after a solve: prescribed and solved values side by side.
/// \ingroup assembly
struct BoundarySolution {
  RowMatrixX3d displacement;  // E x 3
  RowMatrixX3d traction;      // E x 3
};

/// A* alone: depends only on which kind is prescribed where (not on the values), so it can be
/// factorised once and reused for any values of the same kinds (the pre-solution tables do).
Eigen::MatrixXd build_system_matrix(const InfluenceMatrices& hg, const BoundaryConditions& bc);

/// The same A*, built in H's storage: hg.H is consumed (left empty), hg.G kept. Spares a second
/// n x n matrix (its allocation, first touch and copy); build the right-hand side first.
Eigen::MatrixXd build_system_matrix_in_place(InfluenceMatrices& hg, const BoundaryConditions& bc);

/// Right-hand side R_bc + R_G; gravity may be empty (no body force).
Eigen::VectorXd build_right_hand_side(const InfluenceMatrices& hg, const BoundaryConditions& bc,
                                      const Eigen::VectorXd& gravity = Eigen::VectorXd());

inline LinearSystem build_linear_system(const InfluenceMatrices& hg, const BoundaryConditions& bc,
                                        const Eigen::VectorXd& gravity = Eigen::VectorXd()) {
  return {build_system_matrix(hg, bc), build_right_hand_side(hg, bc, gravity)};
}

/// Puts the solved unknowns x and the prescribed values back into displacement and traction.
BoundarySolution recover_boundary_solution(const BoundaryConditions& bc, const Eigen::VectorXd& x);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/assembly/impl/linear_system_impl.hpp"
#endif
