// Implementation of bemsurg/solvers/low_rank_updated_lu.hpp: the Woodbury solves, the rows of an
// updated inverse for a first response, and the update by one cut step (docs/cutting.md). Out of the
// class so that a program linking the compiled library instantiates none of it per translation unit
// (bemsurg/config.hpp; docs/development.md, "How the build is kept small").
#pragma once

#include "bemsurg/config.hpp"

#include <Eigen/Core>
#include <Eigen/LU>
#include <string>
#include <vector>

#include "bemsurg/dense_storage.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/solvers/low_rank_updated_lu.hpp"
#include "bemsurg/solvers/structured_products.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

BEMSURG_INLINE Index LowRankUpdatedLu::apply_base_inverse(Eigen::MatrixXd& B) const {
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

BEMSURG_INLINE void LowRankUpdatedLu::finish_solve(Eigen::MatrixXd& Y) const {
  check_rows(Y.rows(), "finish_solve");
  if (rank() == 0 || Y.cols() == 0) return;
  Eigen::MatrixXd t = V_.transpose() * Y;
  t = C_lu_.solve(t);
  Y.noalias() -= W_ * t;
}

BEMSURG_INLINE void LowRankUpdatedLu::solve_in_place(Eigen::MatrixXd& B) const {
  apply_base_inverse(B);
  finish_solve(B);
}

BEMSURG_INLINE Eigen::VectorXd LowRankUpdatedLu::solve(const Eigen::VectorXd& b) const {
  Eigen::MatrixXd x = b;
  solve_in_place(x);
  return x.col(0);
}

BEMSURG_INLINE Eigen::MatrixXd LowRankUpdatedLu::left_base_inverse(const Eigen::MatrixXd& V) const {
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

BEMSURG_INLINE LowRankUpdatedLu::RowsOfUpdate LowRankUpdatedLu::rows_after_update(Index new_size, const Eigen::MatrixXd& Us,
                                                                                  const Eigen::MatrixXd& Vs, const std::vector<Index>& rows,
                                                                                  const Eigen::MatrixXd& also,
                                                                                  LowRankUpdateProfile* profile) const {
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

BEMSURG_INLINE LowRankUpdatedLu LowRankUpdatedLu::updated(Index new_size, const Eigen::MatrixXd& Us, const Eigen::MatrixXd& Vs,
                                                          Eigen::MatrixXd* kinv_us, Eigen::MatrixXd* also, LowRankUpdateProfile* profile,
                                                          const Eigen::MatrixXd* known_qs) const {
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
    if (r0 > 0) {                                         // at rank 0 `old` is 0 x 0, not n x 0: assigning it to the block asserts in Debug
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

BEMSURG_INLINE void LowRankUpdatedLu::check_rows(Index rows, const char* where) const {
  if (empty()) throw SolverError(std::string("LowRankUpdatedLu::") + where + ": no factorisation");
  if (rows != n_)
    throw InvalidArgumentError(std::string("LowRankUpdatedLu::") + where + ": " + std::to_string(rows) + " rows, expected " +
                               std::to_string(n_));
}

}  // namespace bemsurg
