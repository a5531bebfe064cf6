// bemsurg/solvers/near_field_preconditioner.hpp: M = the near-field part of A* — for each row
// (collocation element i) only the columns of elements e whose centroid lies within
// radius x max(diameter_i, diameter_e) of i's. The BEM kernels decay like 1/r and 1/r^2, so those
// entries carry the singular and near-singular couplings that make A* hard for Krylov methods
// (Wang et al. 2007 §5.3 re-solve after a cut); the far field is smooth and left to the iteration.
// The sparse M is factorised once by UMFPACK (SuiteSparse) and back-substituted every iteration.
//
// Compiled, unlike the rest of the numerical core (src/solvers/near_field_preconditioner.cpp):
// it is the one part that needs SuiteSparse, so UMFPACK stays out of this header and a program
// that uses the core from headers alone needs no SuiteSparse (it then has no near-field
// preconditioner: BEMSURG_HAVE_NEAR_FIELD is defined only by bemsurg::numerics (and so bemsurg::bemsurg), and
// solve_linear_system says so when asked for one). The factor lives behind a pointer. apply() uses workspace owned by the object (umfpack_di_wsolve allocates
// nothing), so it is const but not safe to call from two threads on one object at once.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// What building the preconditioner cost: reported next to the iteration counts.
/// \ingroup solvers
struct NearFieldStatistics {
  double radius = 0.0;               // in element diameters
  Eigen::Index element_pairs = 0;    // (i, e) pairs kept, self pairs included
  Eigen::Index nonzeros = 0;         // entries of the sparse near-field matrix (9 per pair)
  double density = 0.0;              // nonzeros / n^2
  Eigen::Index factor_nonzeros = 0;  // entries of UMFPACK's L and U together
  double fill = 0.0;                 // factor_nonzeros / nonzeros
  double selection_seconds = 0.0;    // choosing pairs and copying entries
  double factor_seconds = 0.0;       // UMFPACK symbolic + numeric
  double build_seconds = 0.0;        // the two together
};

/// Preconditioner M = the near-field part of A* (element pairs within radius element diameters), factorised once by UMFPACK
/// and back-substituted every iteration. Compiled, needs SuiteSparse; apply() is const but not safe from two threads at once.
/// \ingroup solvers
class NearFieldPreconditioner {
 public:
  NearFieldPreconditioner();
  /// Builds and factorises (see compute()).
  NearFieldPreconditioner(const Eigen::MatrixXd& A, const TriangleMesh& mesh, double radius = 2.0);
  ~NearFieldPreconditioner();
  NearFieldPreconditioner(NearFieldPreconditioner&&) noexcept;
  NearFieldPreconditioner& operator=(NearFieldPreconditioner&&) noexcept;
  NearFieldPreconditioner(const NearFieldPreconditioner&) = delete;
  NearFieldPreconditioner& operator=(const NearFieldPreconditioner&) = delete;

  /// Keeps the entries of A* for element pairs closer than radius element diameters (3x3 blocks;
  /// element e owns rows/columns 3e..3e+2) and factorises them. Throws SolverError if A is not
  /// 3E x 3E for the mesh's E elements, radius is not positive, or the near-field matrix is singular.
  NearFieldPreconditioner& compute(const Eigen::MatrixXd& A, const TriangleMesh& mesh, double radius = 2.0);

  Eigen::Index rows() const;
  const NearFieldStatistics& statistics() const;

  /// z = M^-1 r and z = M^-T r (UMFPACK's A x = b and A' x = b; no iterative refinement).
  void apply(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const;
  void apply_transpose(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const;

 private:
  struct Factor;
  std::unique_ptr<Factor> factor_;
  NearFieldStatistics statistics_;
};

}  // namespace bemsurg
