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

#include <Eigen/Core>
#include <Eigen/LU>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/dense_storage.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/solvers/structured_products.hpp"
#include "bemsurg/solvers/system_factorization.hpp"
#include "bemsurg/timing.hpp"
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
  Index apply_base_inverse(Eigen::MatrixXd& B) const {
    check_rows(B.rows(), "apply_base_inverse");
    const Index n0 = base_->size();
    std::vector<Index> busy;
    busy.reserve(static_cast<std::size_t>(B.cols()));
    for (Index j = 0; j < B.cols(); ++j)
      if (!B.col(j).head(n0).isZero(0.0)) busy.push_back(j);
    if (busy.empty()) return 0;
    if (static_cast<Index>(busy.size()) == B.cols()) {
      base_->solve_in_place(B.topRows(n0));
      return B.cols();
    }
    Eigen::MatrixXd top(n0, static_cast<Index>(busy.size()));
    for (std::size_t c = 0; c < busy.size(); ++c) top.col(static_cast<Index>(c)) = B.col(busy[c]).head(n0);
    base_->solve_in_place(top);
    for (std::size_t c = 0; c < busy.size(); ++c) B.col(busy[c]).head(n0) = top.col(static_cast<Index>(c));
    return static_cast<Index>(busy.size());
  }

  /// Given Y = K^-1 B, completes the Woodbury solve: Y <- A^-1 B.
  void finish_solve(Eigen::MatrixXd& Y) const {
    check_rows(Y.rows(), "finish_solve");
    if (rank() == 0 || Y.cols() == 0) return;
    Eigen::MatrixXd t = V_.transpose() * Y;
    t = C_lu_.solve(t);
    Y.noalias() -= W_ * t;
  }

  /// B <- A^-1 B.
  void solve_in_place(Eigen::MatrixXd& B) const {
    apply_base_inverse(B);
    finish_solve(B);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
    Eigen::MatrixXd x = b;
    solve_in_place(x);
    return x.col(0);
  }

  /// V^T K_new^-1 (k x new_size) for V (new_size x k), K_new = blockdiag(A0, I): rows of the base's
  /// explicit inverse for V's unit columns, one GEMM (k_dense x n0 x n0) for the others. Needs has_rows().
  Eigen::MatrixXd left_base_inverse(const Eigen::MatrixXd& V) const {
    if (!has_rows()) throw SolverError("LowRankUpdatedLu::left_base_inverse: the base keeps no explicit inverse");
    const Eigen::MatrixXd& B0t = *base_->inverse_transposed();  // (A0^-1)^T
    const Index n0 = B0t.rows(), n1 = V.rows(), k = V.cols();
    if (n1 < n0) throw InvalidArgumentError("LowRankUpdatedLu::left_base_inverse: fewer rows than the base");
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(k, n1);
    out.rightCols(n1 - n0) = V.bottomRows(n1 - n0).transpose();
    std::vector<Index> dense;
    for (Index j = 0; j < k; ++j) {
      const Index at = unit_column_row(V.topRows(n0), j);
      if (at >= 0)
        out.row(j).head(n0) = V(at, j) * B0t.col(at).transpose();
      else if (at == -2)
        dense.push_back(j);
    }
    if (!dense.empty()) {
      Eigen::MatrixXd Vd(n0, static_cast<Index>(dense.size()));
      for (std::size_t c = 0; c < dense.size(); ++c) Vd.col(static_cast<Index>(c)) = V.col(dense[c]).head(n0);
      // Vd^T A0^-1 = (B0t Vd)^T: OpenBLAS runs this tall product about 1.6 times faster than the wide
      // one (n = 8,976, 35 columns, two threads: 68 against 42 GFLOP/s).
      Eigen::MatrixXd Pt(n0, Vd.cols());
      Pt.noalias() = B0t * Vd;
      for (std::size_t c = 0; c < dense.size(); ++c) out.row(dense[c]).head(n0) = Pt.col(static_cast<Index>(c)).transpose();
    }
    return out;
  }

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
                                 const Eigen::MatrixXd& also, LowRankUpdateProfile* profile = nullptr) const {
    if (!has_rows()) throw SolverError("LowRankUpdatedLu::rows_after_update: the base keeps no explicit inverse");
    if (new_size < n_) throw InvalidArgumentError("LowRankUpdatedLu::rows_after_update: the system cannot shrink");
    if (Us.rows() != new_size || Vs.rows() != new_size || Us.cols() != Vs.cols() || also.rows() != new_size)
      throw InvalidArgumentError("LowRankUpdatedLu::rows_after_update: Us, Vs and also must have new_size rows (Us, Vs alike)");
    const auto t0 = SteadyClock::now();
    const Eigen::MatrixXd& B0t = *base_->inverse_transposed();  // (A0^-1)^T: rows of A0^-1 are its columns
    const Index n0 = B0t.rows(), r0 = rank(), k = Us.cols(), m = static_cast<Index>(rows.size()), r = r0 + k;
    RowsOfUpdate out;
    out.Qs = left_base_inverse(Vs);
    const auto t1 = SteadyClock::now();
    // Rows R of K_new^-1 M for M = [Us, also]: the inverse's rows are columns of B0t (gathered in
    // panels, selected_columns_transposed_times; no new_size x |R| copy), unit rows for added dofs.
    // The step's unit columns (E_D in Us) are entries of the inverse, not products.
    for (Index row : rows)
      if (row < 0 || row >= new_size) throw InvalidArgumentError("LowRankUpdatedLu::rows_after_update: row out of range");
    std::vector<Index> dense;  // Us's columns that need the product
    std::vector<Index> unit_at(static_cast<std::size_t>(k), -1);
    for (Index j = 0; j < k; ++j) {
      unit_at[static_cast<std::size_t>(j)] = unit_column_row(Us, j);
      if (unit_at[static_cast<std::size_t>(j)] == -2) dense.push_back(j);
    }
    const Index kd = static_cast<Index>(dense.size()), c = also.cols();
    Eigen::MatrixXd M(n0, kd + c);
    for (Index j = 0; j < kd; ++j) M.col(j) = Us.col(dense[static_cast<std::size_t>(j)]).head(n0);
    M.rightCols(c) = also.topRows(n0);
    std::vector<Index> base_rows, base_at;  // rows below n0, and where they go
    for (Index i = 0; i < m; ++i)
      if (rows[static_cast<std::size_t>(i)] < n0) {
        base_rows.push_back(rows[static_cast<std::size_t>(i)]);
        base_at.push_back(i);
      }
    Eigen::MatrixXd P(static_cast<Index>(base_rows.size()), kd + c);
    selected_columns_transposed_times(B0t, base_rows, M, P);
    // Rows of W_new = [W, K^-1 Us] and of K^-1 also, written where Woodbury's finish reads them.
    Eigen::MatrixXd WR = Eigen::MatrixXd::Zero(m, r);
    out.also_rows.resize(m, c);
    for (std::size_t b = 0; b < base_rows.size(); ++b) {
      for (Index j = 0; j < kd; ++j) WR(base_at[b], r0 + dense[static_cast<std::size_t>(j)]) = P(static_cast<Index>(b), j);
      out.also_rows.row(base_at[b]) = P.row(static_cast<Index>(b)).tail(c);
    }
    for (Index i = 0; i < m; ++i) {
      const Index row = rows[static_cast<std::size_t>(i)];
      if (r0 > 0 && row < n_) WR.row(i).head(r0) = W_.row(row);
      if (row >= n0) {  // K_new is the identity there
        WR.row(i).tail(k) = Us.row(row);
        out.also_rows.row(i) = also.row(row);
        continue;
      }
      for (Index j = 0; j < k; ++j) {
        const Index at = unit_at[static_cast<std::size_t>(j)];
        if (at >= 0) WR(i, r0 + j) = at < n0 ? Us(at, j) * B0t(at, row) : 0.0;  // (A0^-1)(row, at)
      }
    }
    // C_new = [[C, Q Us], [Vs^T W, I + Qs Us]] (Q's columns for added dofs are zero: V's rows are).
    Eigen::MatrixXd Cn(r, r), QU(r, k);
    if (r0 > 0) {
      Cn.topLeftCorner(r0, r0) = C_;
      QU.topRows(r0) = times_sparse_columns(Q_, Us.topRows(n_));
      Cn.bottomLeftCorner(k, r0) = sparse_columns_transposed_times(Vs.topRows(n_), W_);
    }
    QU.bottomRows(k) = times_sparse_columns(out.Qs, Us);
    Cn.rightCols(k) = QU;
    Cn.bottomRightCorner(k, k).diagonal().array() += 1.0;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(Cn);
    const double rc = r > 0 ? lu.rcond() : 1.0;
    if (!(rc > 1e-15))
      throw SolverError("the updated system is singular to working precision (capacitance reciprocal condition " + number_text(rc) + ")");
    out.z_rows = WR.rightCols(k);
    out.z_rows.noalias() -= WR * lu.solve(QU);
    Eigen::MatrixXd Qa(r, also.cols());
    if (r0 > 0) Qa.topRows(r0).noalias() = Q_ * also.topRows(n_);
    Qa.bottomRows(k).noalias() = out.Qs * also;
    out.also_rows.noalias() -= WR * lu.solve(Qa);
    if (profile) {
      profile->base_solve_seconds = seconds_between(t0, t1);
      profile->base_solve_columns = 0;
      profile->correction_seconds = seconds_since(t1);
    }
    return out;
  }

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
                           const Eigen::MatrixXd* known_qs = nullptr) const {
    if (empty()) throw SolverError("LowRankUpdatedLu::updated: no factorisation");
    if (new_size < n_) throw InvalidArgumentError("LowRankUpdatedLu::updated: the system cannot shrink");
    if (Us.rows() != new_size || Vs.rows() != new_size || Us.cols() != Vs.cols())
      throw InvalidArgumentError("LowRankUpdatedLu::updated: Us and Vs must both be new_size x k");
    if (also && also->rows() != new_size)
      throw InvalidArgumentError("LowRankUpdatedLu::updated: the extra right-hand sides must have new_size rows");
    LowRankUpdatedLu out;
    out.base_ = base_;
    out.n_ = new_size;
    const Index r0 = rank(), k = Us.cols(), r = r0 + k;
    Eigen::MatrixXd Ws;
    const auto t_solve = SteadyClock::now();
    Index solved = 0;
    if (also && also->cols() > 0) {
      Eigen::MatrixXd both(new_size, k + also->cols());
      both.leftCols(k) = Us;
      both.rightCols(also->cols()) = *also;
      solved = out.apply_base_inverse(both);
      Ws = both.leftCols(k);
      *also = both.rightCols(also->cols());
    } else {
      Ws = Us;
      solved = out.apply_base_inverse(Ws);
    }
    const auto t_correction = SteadyClock::now();
    auto grow = [&](const Eigen::MatrixXd& old, const Eigen::MatrixXd& add) {
      Eigen::MatrixXd m = large_dense_matrix(new_size, r);  // huge pages: see dense_storage.hpp
      if (r0 > 0) {  // at rank 0 `old` is 0 x 0, not n x 0: assigning it to the block asserts in Debug
        m.topLeftCorner(n_, r0) = old;
        m.bottomLeftCorner(new_size - n_, r0).setZero();
      }
      m.rightCols(k) = add;
      return m;
    };
    out.V_ = grow(V_, Vs);
    out.W_ = grow(W_, Ws);
    if (has_rows()) {
      if (known_qs && (known_qs->rows() != k || known_qs->cols() != new_size))
        throw InvalidArgumentError("LowRankUpdatedLu::updated: the known Vs^T K^-1 is of another step");
      out.Q_.resize(r, new_size);
      if (r0 > 0) {
        out.Q_.topLeftCorner(r0, n_) = Q_;
        out.Q_.topRightCorner(r0, new_size - n_).setZero();
      }
      out.Q_.bottomRows(k) = known_qs ? *known_qs : left_base_inverse(Vs);
    }
    // C_new = I + V_new^T W_new, grown by blocks: the old block is kept as it was.
    out.C_.resize(r, r);
    out.C_.topLeftCorner(r0, r0) = C_;
    out.C_.topRightCorner(r0, k).noalias() = out.V_.leftCols(r0).transpose() * Ws;
    out.C_.bottomRows(k).noalias() = Vs.transpose() * out.W_;
    out.C_.bottomRightCorner(k, k).diagonal().array() += 1.0;
    out.C_lu_.compute(out.C_);
    const double rc = r > 0 ? out.C_lu_.rcond() : 1.0;
    if (!(rc > 1e-15))
      throw SolverError("the updated system is singular to working precision (capacitance reciprocal condition " + number_text(rc) + ")");
    if (kinv_us) *kinv_us = std::move(Ws);
    if (profile) {
      profile->base_solve_seconds = seconds_between(t_solve, t_correction);
      profile->base_solve_columns = solved;
      profile->correction_seconds = seconds_since(t_correction);
    }
    return out;
  }

 private:
  void check_rows(Index rows, const char* where) const {
    if (empty()) throw SolverError(std::string("LowRankUpdatedLu::") + where + ": no factorisation");
    if (rows != n_)
      throw InvalidArgumentError(std::string("LowRankUpdatedLu::") + where + ": " + std::to_string(rows) + " rows, expected " +
                                 std::to_string(n_));
  }

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
