// bemsurg/solvers/structured_products.hpp: products with matrices whose structure a cut step knows —
// columns of one non-zero (the unit columns E_D of a step's change, docs/cutting.md) and a chosen
// subset of another matrix's columns (rows of an explicit inverse held transposed, a first response's
// table columns). Used by ExplicitInverse, LowRankUpdatedLu and the table update after a cut.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <vector>

#include "bemsurg/types.hpp"

namespace bemsurg {

/// The row of column j's only non-zero in C; -1 when the column is zero, -2 when it has two or more.
inline Index unit_column_row(const Eigen::Ref<const Eigen::MatrixXd>& C, Index j) {
  Index at = -1;
  for (Index i = 0; i < C.rows(); ++i)
    if (C(i, j) != 0.0) {
      if (at >= 0) return -2;
      at = i;
    }
  return at;
}

/// M C, with C's columns of one non-zero taken as scaled columns of M (no flops) and the others in one GEMM.
inline Eigen::MatrixXd times_sparse_columns(const Eigen::Ref<const Eigen::MatrixXd>& M, const Eigen::Ref<const Eigen::MatrixXd>& C) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(M.rows(), C.cols());
  std::vector<Index> dense;
  for (Index j = 0; j < C.cols(); ++j) {
    const Index at = unit_column_row(C, j);
    if (at >= 0)
      out.col(j) = C(at, j) * M.col(at);
    else if (at == -2)
      dense.push_back(j);
  }
  if (dense.empty()) return out;
  Eigen::MatrixXd Cd(C.rows(), static_cast<Index>(dense.size()));
  for (std::size_t c = 0; c < dense.size(); ++c) Cd.col(static_cast<Index>(c)) = C.col(dense[c]);
  Eigen::MatrixXd P(M.rows(), Cd.cols());
  P.noalias() = M * Cd;
  for (std::size_t c = 0; c < dense.size(); ++c) out.col(dense[c]) = P.col(static_cast<Index>(c));
  return out;
}

/// C^T M, with C's columns of one non-zero taken as scaled rows of M (no flops) and the others in one GEMM.
inline Eigen::MatrixXd sparse_columns_transposed_times(const Eigen::Ref<const Eigen::MatrixXd>& C,
                                                       const Eigen::Ref<const Eigen::MatrixXd>& M) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(C.cols(), M.cols());
  std::vector<Index> dense;
  for (Index j = 0; j < C.cols(); ++j) {
    const Index at = unit_column_row(C, j);
    if (at >= 0)
      out.row(j) = C(at, j) * M.row(at);
    else if (at == -2)
      dense.push_back(j);
  }
  if (dense.empty()) return out;
  Eigen::MatrixXd Cd(C.rows(), static_cast<Index>(dense.size()));
  for (std::size_t c = 0; c < dense.size(); ++c) Cd.col(static_cast<Index>(c)) = C.col(dense[c]);
  Eigen::MatrixXd P(Cd.cols(), M.cols());
  P.noalias() = Cd.transpose() * M;
  for (std::size_t c = 0; c < dense.size(); ++c) out.row(dense[c]) = P.row(static_cast<Index>(c));
  return out;
}

/// out = A(:, cols)^T M (|cols| x M.cols()) without copying the chosen columns into one n x |cols|
/// matrix: that copy is a fresh allocation as large as the table it serves, and its first touches
/// cost more than the product (a first response over 1,890 rows of a 5,358-dof inverse: 81 MB).
/// Runs of at least `min_run` consecutive columns are multiplied where they lie; shorter runs are
/// gathered into one reused panel of at most `panel` columns, so M is packed once per panel rather than
/// once per run (a GEMM with three output rows repacks all of M). `cols` in any order, each in range.
inline void selected_columns_transposed_times(const Eigen::Ref<const Eigen::MatrixXd>& A, const std::vector<Index>& cols,
                                              const Eigen::Ref<const Eigen::MatrixXd>& M, Eigen::Ref<Eigen::MatrixXd> out,
                                              Index panel = 192, Index min_run = 96) {
  const Index n = A.rows(), m = static_cast<Index>(cols.size());
  Eigen::MatrixXd buffer;
  std::vector<Index> pending;  // output rows gathered in the buffer
  auto flush = [&] {
    if (pending.empty()) return;
    const Index p = static_cast<Index>(pending.size());
    Eigen::MatrixXd P(p, M.cols());
    P.noalias() = buffer.leftCols(p).transpose() * M;
    for (Index i = 0; i < p; ++i) out.row(pending[static_cast<std::size_t>(i)]) = P.row(i);
    pending.clear();
  };
  for (Index i = 0; i < m;) {
    Index run = 1;
    while (i + run < m && cols[static_cast<std::size_t>(i + run)] == cols[static_cast<std::size_t>(i)] + run) ++run;
    if (run >= min_run) {
      out.middleRows(i, run).noalias() = A.middleCols(cols[static_cast<std::size_t>(i)], run).transpose() * M;
    } else {
      if (buffer.cols() == 0) buffer.resize(n, std::min(panel, m));
      for (Index r = 0; r < run; ++r) {
        if (static_cast<Index>(pending.size()) == buffer.cols()) flush();
        buffer.col(static_cast<Index>(pending.size())) = A.col(cols[static_cast<std::size_t>(i + r)]);
        pending.push_back(i + r);
      }
    }
    i += run;
  }
  flush();
}

}  // namespace bemsurg
