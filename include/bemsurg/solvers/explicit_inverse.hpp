// bemsurg/solvers/explicit_inverse.hpp: A*^-1 kept as an explicit matrix, the paper's stored inverse
// (Wang et al. 2007 §5.3, eqs. 11-13), as the base of a cut's low-rank update (docs/cutting.md,
// "First response on the rows within reach").
//
// Why keep the inverse and not the LU: a product with it costs what a triangular solve costs, but its
// rows are there to read. A cut's first response needs the new inverse only on the rows of the elements
// within the tools' reach, and the step's capacitance needs X A*^-1 (the step's d changed rows times
// the inverse): with the LU each of those rows is a transposed solve of 2 n^2 flops, with the inverse a
// row read and one d x n x n GEMM. The unit columns of a step's change are columns of the inverse:
// they cost a copy, not a solve. Price: dgetri's 4/3 n^3 flops after the LU's 2/3 n^3, in the LU's own
// storage (no more memory).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/solvers/lu_factors.hpp"
#include "bemsurg/solvers/structured_products.hpp"
#include "bemsurg/solvers/system_factorization.hpp"
#include "bemsurg/timing.hpp"
#include "bemsurg/types.hpp"

namespace bemsurg {

/// A*^-1 stored explicitly (n x n doubles, the LU's storage inverted in place): a SystemFactorization
/// whose solves are GEMMs and whose rows can be read (inverse_transposed(): rows of A^-1 are its columns).
/// Immutable once built.
/// \ingroup solvers
class ExplicitInverse : public SystemFactorization {
 public:
  /// Inverts the factorisation in place (LAPACK dgetri; without BLAS, Eigen's solve of the identity).
  /// `seconds` (optional) receives the inversion's wall time.
  static ExplicitInverse from(LuFactors&& lu, double* seconds = nullptr) {
    const auto t0 = SteadyClock::now();
    ExplicitInverse out;
    out.inverse_transposed_ = std::move(lu).inverse_in_place();
    // Kept transposed: a row of A^-1 is then a contiguous column (a first response gathers hundreds).
    out.inverse_transposed_.transposeInPlace();
    if (!out.inverse_transposed_.allFinite())
      throw SolverError("the inverse of A* has non-finite entries (A* is singular to working precision)");
    if (seconds) *seconds = seconds_since(t0);
    return out;
  }

  Index size() const override { return inverse_transposed_.rows(); }
  std::size_t bytes() const override { return static_cast<std::size_t>(inverse_transposed_.size()) * sizeof(double); }
  const Eigen::MatrixXd* inverse_transposed() const override { return &inverse_transposed_; }

  /// B <- A^-1 B. Columns with one non-zero (the unit columns of a cut's change) are scaled columns of
  /// the inverse; the others go through one GEMM.
  void solve_in_place(Eigen::Ref<Eigen::MatrixXd> B) const override {
    const Index n = size();
    if (B.rows() != n)
      throw SolverError("ExplicitInverse::solve_in_place: " + std::to_string(B.rows()) + " rows, expected " + std::to_string(n));
    std::vector<Index> dense;
    for (Index j = 0; j < B.cols(); ++j) {
      const Index at = unit_column_row(B, j);
      if (at >= 0) {
        const double v = B(at, j);
        B.col(j) = v * inverse_transposed_.row(at).transpose();
      } else if (at == -2) {
        dense.push_back(j);
      }
    }
    if (dense.empty()) return;
    if (static_cast<Index>(dense.size()) == B.cols()) {
      Eigen::MatrixXd x(n, B.cols());
      x.noalias() = inverse_transposed_.transpose() * B;
      B = x;
      return;
    }
    Eigen::MatrixXd b(n, static_cast<Index>(dense.size()));
    for (std::size_t c = 0; c < dense.size(); ++c) b.col(static_cast<Index>(c)) = B.col(dense[c]);
    Eigen::MatrixXd x(n, b.cols());
    x.noalias() = inverse_transposed_.transpose() * b;
    for (std::size_t c = 0; c < dense.size(); ++c) B.col(dense[c]) = x.col(static_cast<Index>(c));
  }

 private:
  Eigen::MatrixXd inverse_transposed_;  // (A^-1)^T
};

}  // namespace bemsurg
