// bemsurg/solvers/low_rank_updated_lu.hpp: the solver of a system that a cut has grown and
// reshaped, kept as the precompute's LU plus an accumulated low-rank correction (docs/design.md §7).
//
//   A = K + U V^T,   K = blockdiag(A0, I)
//
// A0 (n0 x n0) is the matrix factorised once (a SystemFactorization: the dense backend's LuFactors
// or the hierarchical backend's H-LU); dofs added later extend K by identity;
// every change since (new rows and columns: bordering; reshaped elements: their rows and columns
// replaced) is a term U_s V_s^T appended to U V^T. Solves use Woodbury:
//   A^-1 b = y - W C^-1 (V^T y),  y = K^-1 b,  W = K^-1 U,  C = I + V^T W (r x r, factorised).
// For dofs added by a step, K^-1 is the identity, so bordering new rows and columns costs one
// LU solve per new column (Q): this is the paper's inversion by partitioning (Wang et al. 2007
// eqs. 11-13, 2 n^2 m flops), in factorised form: the capacitance C restricted to the new block
// is, up to a permutation of its block structure, S - P A0^-1 Q (tests/test_cut_algebra.cpp
// checks it against solvers/partitioned_inverse.hpp and against a direct inverse).
// Objects are immutable once built: updated() returns a new one (snapshots, docs/design.md §9).
#pragma once

#include "bemsurg/config.hpp"

#include <Eigen/Core>
#include <Eigen/LU>
#include <memory>
#include <utility>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/solvers/system_factorization.hpp"
#include "bemsurg/types.hpp"

namespace bemsurg {

/// Where the time of one LowRankUpdatedLu::updated() went (docs/cutting.md, "Timing"): the LU's
/// triangular solves against the work the accumulated correction costs.
/// \ingroup solvers
struct LowRankUpdateProfile {
  double base_solve_seconds = 0.0;  // K^-1 applied to the step's columns: one multi-right-hand-side dgetrs
  Index base_solve_columns = 0;     // right-hand sides that went through the LU (new dofs' unit columns need none)
  double correction_seconds = 0.0;  // V and W grown by the step's columns and the capacitance C refactorised
};

/// The solver of a system a cut has grown and reshaped: the precompute's factorisation (SystemFactorization) plus an accumulated low-rank
/// correction A = K + U V^T, solved with Woodbury as described at the top of this header. Immutable: updated() returns a new one.
/// \ingroup solvers
class LowRankUpdatedLu {
 public:
  LowRankUpdatedLu() = default;
  explicit LowRankUpdatedLu(std::shared_ptr<const SystemFactorization> base) : base_(std::move(base)) {
    if (!base_ || base_->size() == 0) throw SolverError("LowRankUpdatedLu: no factorisation");
    n_ = base_->size();
  }

  bool empty() const { return !base_; }
  Index size() const { return n_; }
  Index base_size() const { return base_ ? base_->size() : 0; }
  /// Rank of the accumulated correction U V^T (columns of U).
  Index rank() const { return W_.cols(); }
  const std::shared_ptr<const SystemFactorization>& base() const { return base_; }
  /// Bytes held beyond the shared base factorisation: V, W (n x r each), Q (r x n, with an explicit
  /// inverse as base) and C (r x r, twice).
  std::size_t bytes() const { return static_cast<std::size_t>(2 * W_.size() + Q_.size() + 2 * C_.size()) * sizeof(double); }
  /// True when rows of A^-1 can be had without a solve per row: the base stores its inverse
  /// (SystemFactorization::inverse_transposed()), and Q = V^T K^-1 is kept beside V and W (rows_after_update).
  bool has_rows() const { return base_ && base_->inverse_transposed() != nullptr; }

  /// B <- K^-1 B in place: the LU solve on the first n0 rows (only for the columns that have
  /// anything there), identity on the rest. Returns the number of columns that went through the LU.
  Index apply_base_inverse(Eigen::MatrixXd& B) const;

  /// Given Y = K^-1 B, completes the Woodbury solve: Y <- A^-1 B.
  void finish_solve(Eigen::MatrixXd& Y) const;

  /// B <- A^-1 B.
  void solve_in_place(Eigen::MatrixXd& B) const;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

  /// V^T K_new^-1 (k x new_size) for V (new_size x k), K_new = blockdiag(A0, I): rows of the base's
  /// explicit inverse for V's unit columns, one GEMM (k_dense x n0 x n0) for the others. Needs has_rows().
  Eigen::MatrixXd left_base_inverse(const Eigen::MatrixXd& V) const;

  /// What rows_after_update returns: rows of the updated inverse applied to the step's columns.
  struct RowsOfUpdate {
    Eigen::MatrixXd z_rows;     // |rows| x k: those rows of A_new^-1 Us
    Eigen::MatrixXd also_rows;  // |rows| x c: those rows of A_new^-1 also
    Eigen::MatrixXd Qs;         // k x new_size: Vs^T K_new^-1, which updated() takes (known_qs) instead of computing it again
  };

  /// The rows `rows` (indices below new_size) of A_new^-1 Us and of A_new^-1 also, for the A_new of
  /// updated(new_size, Us, Vs), without updating the solver (docs/cutting.md, "First response on the
  /// rows within reach"). With Q = V^T K^-1 kept and W = K^-1 U, Woodbury's rows are
  ///   (A_new^-1 M)_R = (K^-1 M)_R - W_R C_new^-1 (Q_new M),  C_new = I + Q_new U_new,
  /// so the only product over all of A0^-1 is Qs = Vs^T K^-1 (one GEMM, k_dense x n0 x n0, which the
  /// completion needs anyway); the rest costs O(n (k + r)(k + c) + |rows| n (k + c)). Needs has_rows().
  /// Throws SolverError when the new capacitance is singular.
  RowsOfUpdate rows_after_update(Index new_size, const Eigen::MatrixXd& Us, const Eigen::MatrixXd& Vs, const std::vector<Index>& rows,
                                 const Eigen::MatrixXd& also, LowRankUpdateProfile* profile = nullptr) const;

  /// A new solver for A_new = blockdiag(A, I_{new_size - size()}) + Us Vs^T (Us, Vs: new_size x k).
  /// `kinv_us` (optional) receives K_new^-1 Us, which the caller can finish into A_new^-1 Us
  /// with the new object's finish_solve (the push-through identity), at no further LU cost.
  /// `also` (optional, new_size rows) is overwritten by K_new^-1 also in the same LU solve as Us
  /// (one multi-right-hand-side dgetrs instead of two: a cut step's table columns ride along);
  /// finish it with the new object's finish_solve.
  /// `profile` (optional) receives where the time went. With an explicit inverse as base (has_rows())
  /// the new solver also keeps Q = V^T K^-1, grown by Vs^T K^-1: `known_qs` when the caller has it
  /// (rows_after_update), else computed here.
  /// Throws SolverError when the new capacitance matrix is singular (A_new singular).
  LowRankUpdatedLu updated(Index new_size, const Eigen::MatrixXd& Us, const Eigen::MatrixXd& Vs, Eigen::MatrixXd* kinv_us = nullptr,
                           Eigen::MatrixXd* also = nullptr, LowRankUpdateProfile* profile = nullptr,
                           const Eigen::MatrixXd* known_qs = nullptr) const;

 private:
  void check_rows(Index rows, const char* where) const;

  std::shared_ptr<const SystemFactorization> base_;
  Index n_ = 0;
  // n x r. U itself is not kept: solves need only W = K^-1 U (and V); keeping U cost a copy of n r
  // doubles per step (the accumulated rank's share of a cut step, docs/cutting.md).
  Eigen::MatrixXd V_, W_;
  // r x n: V^T K^-1, kept only over an explicit inverse (has_rows()): rows of A^-1 then cost no solve.
  Eigen::MatrixXd Q_;
  Eigen::MatrixXd C_;  // r x r: I + V^T W
  Eigen::PartialPivLU<Eigen::MatrixXd> C_lu_;
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/solvers/impl/low_rank_updated_lu_impl.hpp"
#endif
