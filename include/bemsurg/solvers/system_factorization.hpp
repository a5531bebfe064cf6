// bemsurg/solvers/system_factorization.hpp: a factorised system matrix A* kept to solve later
// right-hand sides, whatever stores it: the dense backend's LU (solvers/lu_factors.hpp) or the
// hierarchical backend's H-LU (elastostatics/hierarchical_solver.hpp, issue 40). A cut's exact
// update (solvers/low_rank_updated_lu.hpp) needs nothing else of its base: K^-1 applied to the
// step's columns, so it runs on either backend (docs/cutting.md, "On either backend").
#pragma once

#include <Eigen/Core>
#include <cstddef>

#include "bemsurg/types.hpp"

namespace bemsurg {

/// A factorised square system A (n x n) that solves many right-hand sides: the base of a cut's
/// low-rank update. Implementations are immutable once built and solve_in_place is safe to call
/// from one thread while another reads the same object (the background refactorisation and the
/// cut worker share snapshots, docs/design.md §9).
/// \ingroup solvers
class SystemFactorization {
 public:
  virtual ~SystemFactorization() = default;
  /// n, the order of A.
  virtual Index size() const = 0;
  /// B <- A^-1 B for all columns of B (n rows) at once.
  virtual void solve_in_place(Eigen::Ref<Eigen::MatrixXd> B) const = 0;
  /// Bytes the factors hold (what the table's memory report counts).
  virtual std::size_t bytes() const = 0;
  /// (A^-1)^T when A^-1 is stored (solvers/explicit_inverse.hpp), else null: a cut's first response
  /// reads rows of A^-1, its columns (docs/cutting.md, "First response on the rows within reach").
  virtual const Eigen::MatrixXd* inverse_transposed() const { return nullptr; }

 protected:
  SystemFactorization() = default;
  SystemFactorization(const SystemFactorization&) = default;
  SystemFactorization(SystemFactorization&&) = default;
  SystemFactorization& operator=(const SystemFactorization&) = default;
  SystemFactorization& operator=(SystemFactorization&&) = default;
};

}  // namespace bemsurg
