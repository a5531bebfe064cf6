// bemsurg/solvers/gmres.hpp: GMRES, full (the paper's "GMRES without restart", which needed the
// fewest iterations after a cut: Wang et al. 2007 §5.3, Table 1) and restarted GMRES(m).
//
// Right preconditioning, A M^-1 y = b, x = M^-1 y: the residual GMRES minimises is then the true
// residual b - A x, so the stopping test is on the quantity the caller asked for, whatever M is.
// Arnoldi uses classical Gram-Schmidt, repeated once when the first pass cancelled more than 1 - 1/sqrt(2)
// of the vector (the Daniel-Gragg-Kaufman-Stewart criterion): as stable as modified Gram-Schmidt in
// practice, but each pass is one matrix-vector product with the basis (BLAS-2), not j dot products.
// The least-squares problem is kept triangular by Givens rotations, so |g(j+1)| estimates the
// residual every iteration for free; when the estimate meets the tolerance, x is formed and the
// residual recomputed from it, and only that recomputed value can declare convergence (otherwise
// the method restarts from the new x).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>

#include "bemsurg/solvers/krylov_solver_base.hpp"
#include "bemsurg/solvers/linear_operator.hpp"

namespace bemsurg {

/// Solves A x = b through solve(b, x) (KrylovSolverBase). One iteration = one product with A.
/// \ingroup solvers
template <class Operator = DenseOperator, class Preconditioner = IdentityPreconditioner>
class Gmres : public KrylovSolverBase<Gmres<Operator, Preconditioner>, Operator, Preconditioner> {
  using Base = KrylovSolverBase<Gmres<Operator, Preconditioner>, Operator, Preconditioner>;
  // The workspace: the basis V (n x (m+1)), the Hessenberg matrix H kept triangular by the Givens
  // rotations (cs, sn), the rotated right-hand side g, y for the least-squares solution, and r,
  // t, w (n).
  Eigen::MatrixXd V_, H_;
  Eigen::VectorXd g_, y_, cs_, sn_, r_, t_, w_;
  Eigen::Index basis_size_ = 0;  // m: the basis holds m + 1 vectors

 public:
  using Base::Base;

 private:
  friend Base;  // solve() calls workspace() and iterate()

  Eigen::VectorXd& workspace(Eigen::Index n) {
    const KrylovOptions& s = this->settings_;
    // Basis size: the restart length, or (full GMRES) as many vectors as iterations allowed, never more than n.
    basis_size_ = std::min<Eigen::Index>(n, s.restart > 0 ? std::min(s.restart, s.max_iterations) : s.max_iterations);
    reserve(n, basis_size_);
    return r_;
  }

  void iterate(const Operator& A, const Preconditioner& M, const Eigen::VectorXd& b, Eigen::VectorXd& x, double residual,
               typename Base::Clock::time_point start) {
    const KrylovOptions& s = this->settings_;
    KrylovResult& report = this->report_;
    const Eigen::Index m = basis_size_;
    const double tiny = std::max(s.breakdown_tolerance, 16 * std::numeric_limits<double>::epsilon());
    for (;;) {  // one restart cycle per pass
      const double beta = residual * this->b_norm_;
      V_.col(0) = r_ / beta;
      g_.setZero();
      g_(0) = beta;
      Eigen::Index k = 0;      // columns of the Hessenberg matrix in use
      bool invariant = false;  // A M^-1 v_j fell into the span of the basis (h(j+1,j) = 0)
      bool singular = false;   // ... and the rotated diagonal vanished too: A M^-1 singular there
      while (k < m && report.iterations < s.max_iterations) {
        const Eigen::Index j = k;
        M.apply(V_.col(j), t_);
        A.apply(t_, V_.col(j + 1));
        const double w_norm = V_.col(j + 1).norm();
        auto h = H_.col(j).head(j + 1);
        auto correction = y_.head(j + 1);
        h.noalias() = V_.leftCols(j + 1).transpose() * V_.col(j + 1);
        V_.col(j + 1).noalias() -= V_.leftCols(j + 1) * h;
        double h_next = V_.col(j + 1).norm();
        if (h_next < kReorthogonalise * w_norm) {  // cancellation: a second pass restores orthogonality (DGKS)
          correction.noalias() = V_.leftCols(j + 1).transpose() * V_.col(j + 1);
          V_.col(j + 1).noalias() -= V_.leftCols(j + 1) * correction;
          h += correction;
          h_next = V_.col(j + 1).norm();
        }
        ++report.iterations;
        if (!std::isfinite(w_norm) || !std::isfinite(h_next) || !h.allFinite()) {
          x_update(k, x);  // keep the last finite iterate's progress
          report.true_residual = this->true_residual(b, x, r_);
          return this->finish(KrylovStatus::NonFinite, "Arnoldi vector A M^-1 v", start);
        }
        for (Eigen::Index i = 0; i < j; ++i) rotate(cs_(i), sn_(i), H_(i, j), H_(i + 1, j));
        const double diagonal = std::hypot(H_(j, j), h_next);
        if (!(diagonal > tiny * w_norm)) {  // this column adds nothing: the projected matrix is singular
          singular = invariant = true;
          break;
        }
        cs_(j) = H_(j, j) / diagonal;
        sn_(j) = h_next / diagonal;
        H_(j, j) = diagonal;
        g_(j + 1) = -sn_(j) * g_(j);
        g_(j) *= cs_(j);
        k = j + 1;
        if (this->record(std::abs(g_(j + 1))) <= s.tolerance) break;
        if (h_next <= tiny * w_norm) {  // lucky breakdown: the Krylov space is invariant, x is exact in it
          invariant = true;
          break;
        }
        V_.col(j + 1) /= h_next;
      }
      x_update(k, x);
      const double previous = residual;
      residual = this->true_residual(b, x, r_);
      report.true_residual = residual;
      if (!std::isfinite(residual)) return this->finish(KrylovStatus::NonFinite, "solution update", start);
      if (residual <= s.tolerance) return this->finish(KrylovStatus::Converged, "", start);
      if (singular) return this->finish(KrylovStatus::Breakdown, "h(j,j) = h(j+1,j) = 0: A M^-1 is singular on the Krylov space", start);
      if (invariant)
        return this->finish(KrylovStatus::Breakdown, "h(j+1,j) = 0: the Krylov space is invariant but the residual is above tolerance",
                            start);
      if (report.iterations >= s.max_iterations) return this->finish(KrylovStatus::IterationLimit, "", start);
      if (residual > (1.0 - s.stagnation_reduction) * previous) return this->finish(KrylovStatus::Stagnation, "", start);
      ++report.restarts;
    }
  }

  void reserve(Eigen::Index n, Eigen::Index m) {
    if (V_.rows() != n || V_.cols() != m + 1) V_.resize(n, m + 1);
    if (H_.rows() != m + 1 || H_.cols() != m) H_.resize(m + 1, m);
    if (g_.size() != m + 1) g_.resize(m + 1);
    if (y_.size() != m + 1) y_.resize(m + 1);
    if (cs_.size() != m) cs_.resize(m), sn_.resize(m);
    if (r_.size() != n) r_.resize(n), t_.resize(n), w_.resize(n);
  }

  /// x += M^-1 V_k y, with y solving the k x k triangular least-squares system R y = g.
  void x_update(Eigen::Index k, Eigen::VectorXd& x) {
    if (k == 0) return;
    auto y = y_.head(k);
    y = g_.head(k);
    H_.topLeftCorner(k, k).template triangularView<Eigen::Upper>().solveInPlace(y);
    t_.noalias() = V_.leftCols(k) * y;
    this->M_->apply(t_, w_);
    x += w_;
  }

  static constexpr double kReorthogonalise = 0.7071067811865476;  // 1/sqrt(2)

  static void rotate(double c, double s, double& a, double& b) {
    const double t = c * a + s * b;
    b = -s * a + c * b;
    a = t;
  }
};

}  // namespace bemsurg
