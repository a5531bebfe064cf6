// bemsurg/solvers/linear_solve.hpp: one entry point that solves A* x = b by the method a scene
// asks for (direct LU or a Krylov method with a preconditioner) and reports what happened.
// The report is part of the answer: a solve that did not converge throws SolverError with it.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/solvers/krylov_result.hpp"

namespace bemsurg {

/// The method for A* x = b: direct LU, or a Krylov method (the paper's Table 1 re-solves).
/// \ingroup solvers
enum class SolverMethod { Lu, Gmres, BiCgStab, BiCg };
/// Where the system lives (docs/solvers.md): dense (A* in full, the reference), hierarchical (a
/// compressed H-matrix, factorised by H-LU: elastostatics/hierarchical_solver.hpp, compiled component)
/// or split over MPI ranks (ScaLAPACK's block-cyclic dense LU: distributed/scalapack_solver.hpp,
/// compiled component; docs/distributed.md).
/// \ingroup solvers
enum class SolverBackend { Dense, HMatrix, ScaLapack };
/// "dense", "hmatrix", "scalapack".
inline const char* to_string(SolverBackend backend) {
  switch (backend) {
    case SolverBackend::HMatrix: return "hmatrix";
    case SolverBackend::ScaLapack: return "scalapack";
    case SolverBackend::Dense: break;
  }
  return "dense";
}

/// The preconditioner of a Krylov method (docs/solvers.md).
/// \ingroup solvers
enum class PreconditionerKind { None, BlockJacobi, NearField };

/// Names as scene files and report.json write them: "lu", "gmres", "bicgstab", "bicg".
inline const char* to_string(SolverMethod method) {
  switch (method) {
    case SolverMethod::Lu: return "lu";
    case SolverMethod::Gmres: return "gmres";
    case SolverMethod::BiCgStab: return "bicgstab";
    case SolverMethod::BiCg: return "bicg";
  }
  return "unknown";
}
/// "none", "block_jacobi", "near_field".
inline const char* to_string(PreconditionerKind kind) {
  switch (kind) {
    case PreconditionerKind::None: return "none";
    case PreconditionerKind::BlockJacobi: return "block_jacobi";
    case PreconditionerKind::NearField: return "near_field";
  }
  return "unknown";
}
/// The inverse of to_string; throws SolverError naming the name and the accepted ones.
inline SolverMethod parse_solver_method(const std::string& name) {
  for (SolverMethod m : {SolverMethod::Lu, SolverMethod::Gmres, SolverMethod::BiCgStab, SolverMethod::BiCg})
    if (name == to_string(m)) return m;
  throw SolverError("unknown solver method '" + name + "' (expected lu, gmres, bicgstab or bicg)");
}
inline PreconditionerKind parse_preconditioner(const std::string& name) {
  for (PreconditionerKind k : {PreconditionerKind::None, PreconditionerKind::BlockJacobi, PreconditionerKind::NearField})
    if (name == to_string(k)) return k;
  throw SolverError("unknown preconditioner '" + name + "' (expected none, block_jacobi or near_field)");
}

/// What solve_linear_system is asked to do: the method (direct LU or a Krylov method), the Krylov stopping rule and
/// restart length, and the preconditioner (block-Jacobi by default) with its near-field radius.
/// \ingroup solvers
struct LinearSolverOptions {
  /// Dense (method below) or hierarchical (scene "method": "hmatrix"; then `method` is not used).
  SolverBackend backend = SolverBackend::Dense;
  /// Scene "method": "auto": a command chooses `backend` per mesh (choose_backend,
  /// elastostatics/hierarchical_solver.hpp) before it solves; until then `backend` is Dense.
  bool automatic_backend = false;
  double compression_tolerance = 1e-4;  // hierarchical: ACA+'s relative tolerance per far-field block
  SolverMethod method = SolverMethod::Lu;
  double tolerance = 1e-10;  // relative residual ||b - A x|| / ||b|| for Krylov methods
  int max_iterations = 1000;
  int restart = 0;  // GMRES(m) restart length; 0 = full GMRES
  // block_jacobi by default: A* mixes O(1) H columns with O(1/mu) G columns, and unpreconditioned
  // Krylov methods stall on that scaling (bench_krylov: GMRES(30) does not converge without it).
  PreconditionerKind preconditioner = PreconditionerKind::BlockJacobi;
  double near_field_radius = 2.0;  // near-field preconditioner: element diameters
};

/// Deprecated name (before 0.2), kept one minor version: use LinearSolverOptions.

using LinearSolverSettings [[deprecated("renamed to LinearSolverOptions in bemsurg 0.2")]] = LinearSolverOptions;

/// What solve_linear_system reports about a solve: method, preconditioner, status, iterations, true relative residual
/// and timings, plus the Krylov details (zero or empty for LU).
/// \ingroup solvers
struct LinearSolveResult {
  SolverMethod method = SolverMethod::Lu;
  PreconditionerKind preconditioner = PreconditionerKind::None;  // None for LU
  KrylovStatus status = KrylovStatus::NotComputed;               // LU too: Converged, Breakdown (singular) or NonFinite
  int iterations = 0;                                            // 0 for LU
  double relative_residual = 0.0;                                // true residual ||b - A x|| / ||b||, recomputed
  double setup_seconds = 0.0;                                    // factorisation or preconditioner build
  double solve_seconds = 0.0;
  // Added for the Krylov methods (solvers/krylov_result.hpp); zero or empty for LU.
  std::string breakdown;                     // status breakdown/non_finite: which quantity vanished or went non-finite
  double initial_residual = 0.0;             // ||b - A x0|| / ||b|| (1 for a cold start)
  int restarts = 0;                          // GMRES(m) cycles after the first; residual replacements in BiCG(Stab)
  std::vector<double> residual_history;      // the recurrence's relative residual per iteration, from x0
  Eigen::Index preconditioner_nonzeros = 0;  // near_field: entries kept; block_jacobi: 9 per element
  double preconditioner_fill = 0.0;          // near_field: nonzeros of L + U / nonzeros kept
};

/// Deprecated name (before 0.2), kept one minor version: use LinearSolveResult.

using LinearSolveSummary [[deprecated("renamed to LinearSolveResult in bemsurg 0.2")]] = LinearSolveResult;

/// Solves A x = b. `mesh` gives the geometry the near-field preconditioner needs (may be null
/// otherwise). `x0` (optional, may be empty) is a warm start for Krylov methods.
Eigen::VectorXd solve_linear_system(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const LinearSolverOptions& settings,
                                    LinearSolveResult& summary, const TriangleMesh* mesh = nullptr,
                                    const Eigen::VectorXd& x0 = Eigen::VectorXd());

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/solvers/impl/linear_solve_impl.hpp"
#endif
