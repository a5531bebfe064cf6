// near_field_preconditioner.cpp: the UMFPACK side of the near-field preconditioner
// (include/bemsurg/solvers/near_field_preconditioner.hpp): choose the near element pairs, copy
// their 3x3 blocks of A* into a compressed-column matrix, factorise once, back-substitute per
// iteration with caller-free workspace (umfpack_di_wsolve allocates nothing).
#include "bemsurg/solvers/near_field_preconditioner.hpp"

#include <umfpack.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

struct NearFieldPreconditioner::Factor {
  int n = 0;
  std::vector<int> column_starts, row_indices;
  std::vector<double> values;
  void* numeric = nullptr;
  double control[UMFPACK_CONTROL];
  mutable std::vector<int> wi;
  mutable std::vector<double> w;

  Factor() { umfpack_di_defaults(control); }
  ~Factor() {
    if (numeric) umfpack_di_free_numeric(&numeric);
  }
  Factor(const Factor&) = delete;
  Factor& operator=(const Factor&) = delete;

  void solve(int system, const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const {
    if (r.size() != n || z.size() != n)
      throw SolverError("near-field preconditioner: vector of size " + std::to_string(r.size()) + " for a " + std::to_string(n) + " x " +
                        std::to_string(n) + " factor");
    double info[UMFPACK_INFO];
    const int status = umfpack_di_wsolve(system, column_starts.data(), row_indices.data(), values.data(), z.data(), r.data(), numeric,
                                         control, info, wi.data(), w.data());
    // A non-finite right-hand side passes through as NaN and the Krylov solver reports it.
    if (status != UMFPACK_OK && status != UMFPACK_WARNING_singular_matrix)
      throw SolverError("near-field preconditioner: UMFPACK solve failed with status " + std::to_string(status));
  }
};

NearFieldPreconditioner::NearFieldPreconditioner() = default;
NearFieldPreconditioner::NearFieldPreconditioner(const Eigen::MatrixXd& A, const TriangleMesh& mesh, double radius) {
  compute(A, mesh, radius);
}
NearFieldPreconditioner::~NearFieldPreconditioner() = default;
NearFieldPreconditioner::NearFieldPreconditioner(NearFieldPreconditioner&&) noexcept = default;
NearFieldPreconditioner& NearFieldPreconditioner::operator=(NearFieldPreconditioner&&) noexcept = default;

Eigen::Index NearFieldPreconditioner::rows() const { return factor_ ? factor_->n : 0; }
const NearFieldStatistics& NearFieldPreconditioner::statistics() const { return statistics_; }

NearFieldPreconditioner& NearFieldPreconditioner::compute(const Eigen::MatrixXd& A, const TriangleMesh& mesh, double radius) {
  const auto start = SteadyClock::now();
  const Index E = mesh.num_elements();
  if (A.rows() != A.cols() || A.rows() != 3 * E)
    throw SolverError("near-field preconditioner: the matrix is " + std::to_string(A.rows()) + " x " + std::to_string(A.cols()) +
                      ", the mesh has " + std::to_string(E) + " elements (needs " + std::to_string(3 * E) + " x " + std::to_string(3 * E) +
                      ")");
  if (!(std::isfinite(radius) && radius > 0.0))
    throw SolverError("near-field preconditioner: radius must be a positive number of element diameters, got " + number_text(radius));
  if (3 * E > std::numeric_limits<int>::max() / 4)
    throw SolverError("near-field preconditioner: the system is too large for UMFPACK's int interface");

  // Near pairs, per column element e, rows ascending (compressed-column order). The O(E^2) scan
  // costs a few milliseconds at the sizes a dense A* allows; the O(n^2) copy dominates anyway.
  const RowMatrixX3d& c = mesh.centroids();
  const Eigen::VectorXd& d = mesh.diameters();
  std::vector<int> near_start(static_cast<std::size_t>(E) + 1, 0);
  std::vector<int> near;
  near.reserve(static_cast<std::size_t>(E) * 16);
  for (Index e = 0; e < E; ++e) {
    for (Index i = 0; i < E; ++i) {
      const double reach = radius * std::max(d(i), d(e));
      if (i == e || (c.row(i) - c.row(e)).squaredNorm() < reach * reach) near.push_back(static_cast<int>(i));
    }
    // UMFPACK's int interface indexes the 9 nonzeros of every pair; stop before they overflow int
    // (checked per column, so a radius that selects nearly every pair fails before filling memory).
    if (near.size() > static_cast<std::size_t>(std::numeric_limits<int>::max() / 9))
      throw SolverError("near-field preconditioner: radius " + number_text(radius) + " selects more than " +
                        std::to_string(std::numeric_limits<int>::max() / 9) + " element pairs (over " +
                        std::to_string(std::numeric_limits<int>::max()) +
                        " nonzeros, the limit of UMFPACK's int interface); use a smaller radius or block_jacobi");
    near_start[static_cast<std::size_t>(e) + 1] = static_cast<int>(near.size());
  }

  auto f = std::make_unique<Factor>();
  f->n = static_cast<int>(3 * E);
  const std::size_t pairs = near.size();
  f->column_starts.resize(static_cast<std::size_t>(f->n) + 1);
  f->row_indices.resize(9 * pairs);
  f->values.resize(9 * pairs);
  std::size_t k = 0;
  for (Index e = 0; e < E; ++e)
    for (int col = 0; col < 3; ++col) {
      const Index j = 3 * e + col;
      f->column_starts[static_cast<std::size_t>(j)] = static_cast<int>(k);
      for (int q = near_start[static_cast<std::size_t>(e)]; q < near_start[static_cast<std::size_t>(e) + 1]; ++q)
        for (int row = 0; row < 3; ++row) {
          const Index i = 3 * static_cast<Index>(near[static_cast<std::size_t>(q)]) + row;
          const double value = A(i, j);
          if (!std::isfinite(value))
            throw SolverError("near-field preconditioner: entry (" + std::to_string(i) + ", " + std::to_string(j) +
                              ") of the matrix is not finite");
          f->row_indices[k] = static_cast<int>(i);
          f->values[k] = value;
          ++k;
        }
    }
  f->column_starts[static_cast<std::size_t>(f->n)] = static_cast<int>(k);
  const auto selected = SteadyClock::now();

  f->control[UMFPACK_IRSTEP] = 0;  // refining against the near-field matrix would not bring M^-1 closer to A^-1
  double info[UMFPACK_INFO];
  void* symbolic = nullptr;
  int status =
      umfpack_di_symbolic(f->n, f->n, f->column_starts.data(), f->row_indices.data(), f->values.data(), &symbolic, f->control, info);
  if (status != UMFPACK_OK)
    throw SolverError("near-field preconditioner: UMFPACK symbolic analysis failed with status " + std::to_string(status));
  status = umfpack_di_numeric(f->column_starts.data(), f->row_indices.data(), f->values.data(), symbolic, &f->numeric, f->control, info);
  umfpack_di_free_symbolic(&symbolic);
  if (status == UMFPACK_WARNING_singular_matrix)
    throw SolverError("near-field preconditioner: the near-field matrix (radius " + number_text(radius) +
                      " element diameters) is singular; try a larger radius or block_jacobi");
  if (status != UMFPACK_OK)
    throw SolverError("near-field preconditioner: UMFPACK factorisation failed with status " + std::to_string(status));
  int lnz = 0, unz = 0, n_row = 0, n_col = 0, nz_udiag = 0;
  umfpack_di_get_lunz(&lnz, &unz, &n_row, &n_col, &nz_udiag, f->numeric);
  f->wi.resize(static_cast<std::size_t>(f->n));
  f->w.resize(5 * static_cast<std::size_t>(f->n));
  const auto factored = SteadyClock::now();

  NearFieldStatistics s;
  s.radius = radius;
  s.element_pairs = static_cast<Index>(pairs);
  s.nonzeros = static_cast<Index>(k);
  s.density = static_cast<double>(k) / (static_cast<double>(f->n) * f->n);
  // L has a unit diagonal that UMFPACK counts in lnz and U's diagonal is in unz: count it once.
  s.factor_nonzeros = static_cast<Index>(lnz) + unz - f->n;
  s.fill = static_cast<double>(s.factor_nonzeros) / static_cast<double>(k);
  s.selection_seconds = seconds_between(start, selected);
  s.factor_seconds = seconds_between(selected, factored);
  s.build_seconds = seconds_between(start, factored);
  factor_ = std::move(f);
  statistics_ = s;
  return *this;
}

void NearFieldPreconditioner::apply(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const {
  if (!factor_) throw SolverError("near-field preconditioner: apply() called before compute()");
  factor_->solve(UMFPACK_A, r, z);
}

void NearFieldPreconditioner::apply_transpose(const Eigen::Ref<const Eigen::VectorXd>& r, Eigen::Ref<Eigen::VectorXd> z) const {
  if (!factor_) throw SolverError("near-field preconditioner: apply() called before compute()");
  factor_->solve(UMFPACK_At, r, z);
}

}  // namespace bemsurg
