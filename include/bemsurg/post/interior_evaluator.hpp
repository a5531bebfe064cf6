// bemsurg/post/interior_evaluator.hpp: displacement and stress at points inside the body from
// the boundary solution (Wang et al. 2007 eqs. 7-9; Somigliana's identity with c = I):
//   u_i(p)      = sum_e [ int_e U_ij t_j - int_e T_ij u_j ] + int_Gamma P_i
//   sigma_ij(p) = sum_e [ int_e D_kij t_k - int_e S_kij u_k ] + gravity term
// The same adaptive quadrature as assembly is used; it is accurate down to a distance from each
// element of min_clearance_fraction (2.9e-3 by default) times the element's size, and points
// closer are refused (interior_clearance.hpp, docs/design.md §4). Stress is refused closer than
// kMinStressClearanceFraction (0.25) x the size, where constant elements make it wrong whatever
// the quadrature (docs/stability.md, study (b)).
#pragma once

#include <Eigen/Core>

#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/post/interior_clearance.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"

namespace bemsurg {

/// Stress in Voigt-like order sxx, syy, szz, sxy, syz, sxz, one row per point.
using StressRows = Eigen::Matrix<double, Eigen::Dynamic, 6, Eigen::RowMajor>;

/// Displacement and stress at points inside the body from the boundary solution by Somigliana's identity (Wang et
/// al. 2007 eqs. 7-9), with the adaptive quadrature of assembly; points too close to an element are refused.
/// \ingroup post
class InteriorEvaluator {
 public:
  InteriorEvaluator(const TriangleMesh& mesh, const Material& material, const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero(),
                    const QuadratureOptions& options = {});

  /// Both throw InvalidArgumentError naming the first point closer to an element than the
  /// quadrature resolves (interior_clearance.hpp), before evaluating anything; stress also for
  /// points closer than min_stress_clearance_fraction x the element's longest edge.
  RowMatrixX3d displacement(const RowMatrixX3d& points, const BoundarySolution& solution) const;
  StressRows stress(const RowMatrixX3d& points, const BoundarySolution& solution) const;

  /// For stability studies only (bench_stability --study interior, docs/stability.md): evaluate
  /// points closer than the limits above instead of refusing them, to measure what goes wrong there.
  void allow_points_too_close_for_studies(bool allow) { allow_too_close_ = allow; }

 private:
  void require_clearance(const RowMatrixX3d& points, ClearanceQuantity quantity) const;

  /// The traversal both evaluations share: every point (in parallel) against every element, with
  /// the adaptive rule of assembly; integrand(sum, r = x - p, n_e, w, t_e, u_e) per quadrature
  /// point, then finish(k, sum) per point.
  template <class Accumulator, class Integrand, class Finish>
  void traverse(const RowMatrixX3d& points, const BoundarySolution& s, const Integrand& integrand, const Finish& finish) const;

  const TriangleMesh& mesh_;
  Material material_;
  Eigen::Vector3d body_force_;
  ElementQuadrature quadrature_;
  bool allow_too_close_ = false;
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/post/impl/interior_evaluator_impl.hpp"
#endif
