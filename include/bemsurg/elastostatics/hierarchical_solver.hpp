// bemsurg/elastostatics/hierarchical_solver.hpp: the hierarchical-matrix backend of a static solve
// (docs/solvers.md, "Hierarchical matrices"; issue 40). A* (the mixed system of eq. 6) is assembled
// block by block through the same quadrature as the dense path (near-field blocks exactly as today),
// far-field blocks compressed by ACA+ to a relative tolerance, factorised by an H-LU and solved, by
// hmat-oss (Airbus; Debian's libhmat-oss-dev, GPL-2.0-or-later).
//
// A compiled component: library bemsurg_hmatrix, CMake target bemsurg::hmatrix, built on hmat-oss
// when CMake finds it (BEMSURG_WITH_HMATRIX). Built without it, hierarchical_backend_available() is
// false and solve_elastostatic_hierarchical throws SolverError saying so; the header-only core never
// needs it. It covers static solves of constant and linear elements (`bemsurg solve`, interior
// points included; linear elements' unknowns sit at their nodes, nine columns per element), and the
// pre-solution tables and cuts of constant elements (presolution/hierarchical_table.hpp for `table`,
// `press`, `session`, `cut` and the viewer, whose exact update runs on top of the kept H-LU:
// solvers/system_factorization.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <string>

#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/solvers/linear_solve.hpp"
#include "bemsurg/solvers/system_factorization.hpp"

namespace bemsurg {

/// What the hierarchical backend did: its compression and its phases (report.json's "backend").
/// \ingroup elastostatics
struct HierarchicalResult {
  double compression_tolerance = 0.0;  // ACA+'s relative tolerance per block (LinearSolverOptions::compression_tolerance)
  std::size_t stored_entries = 0;      // doubles stored by the H-matrix (full and low-rank leaves) before the H-LU
  std::size_t dense_entries = 0;       // n^2: what the dense A* stores
  std::size_t factor_entries = 0;      // doubles the H-LU's factors store (what a table kept for cuts holds)
  double compression_ratio = 0.0;      // stored / dense
  int largest_rank = 0;                // rank of the largest low-rank block (by memory)
  int leaves_full = 0, leaves_low_rank = 0;
  double column_scale = 1.0;  // traction-unknown columns multiplied by mu / h (see hierarchical_solver.cpp)
  double assembly_seconds = 0.0, factorization_seconds = 0.0, solve_seconds = 0.0;
  double relative_residual = 0.0;  // ||b - A x|| / ||b|| with A the compressed matrix before its H-LU
};

/// True when this build has the hierarchical backend (hmat-oss was found).
bool hierarchical_backend_available();

/// A planning estimate of the hierarchical solve's peak bytes for `elements` elements of `type`,
/// before anything is assembled (the scene loader's and the solve's memory checks; docs/solvers.md):
/// the stored fraction of dense A* measured on organ meshes of constant elements, 0.41 at 5,334
/// unknowns (1,778 elements) falling as n^-0.74 (0.126 at 9,344 elements, 0.064 at 20,480), taken
/// by unknowns for linear elements (9 per element), counted twice (the H-LU's factors and the copy
/// the residual needs), plus a leaf's block rows per unknown.
inline double estimate_hierarchical_bytes(Index elements, ElementType type = ElementType::Constant) {
  const double e = elements > 1 ? double(elements) : 1.0, n = 3.0 * double(nodes_per_element(type)) * e;
  const double fraction = std::min(1.0, 0.41 * std::pow(n / 5334.0, -0.74));
  return 2.0 * 8.0 * n * n * fraction + 64.0 * n * 120.0;
}

/// A* of a problem (constant or linear elements) assembled block by block, compressed by ACA+ and factorised
/// by an H-LU on hmat-oss, kept to solve many right-hand sides: the static solve's one, a table's
/// columns, and (as a SystemFactorization) the base of a cut's low-rank update. The traction
/// unknowns' columns are scaled by mu / h inside (solve_in_place takes and returns unscaled vectors,
/// as the dense LU does). Move-only.
/// \ingroup elastostatics
class HierarchicalFactorization : public SystemFactorization {
 public:
  /// Assembles and factorises A* of `problem` at ACA+'s `compression_tolerance` (in [1e-12, 0.1]);
  /// `keep_copy` keeps the assembled matrix for relative_residual (as much memory again). Throws
  /// SolverError when the backend is missing or hmat-oss fails, and
  /// InvalidArgumentError for a tolerance outside its range. No checks of the problem itself: callers
  /// run check_before_solve first. `problem` must outlive it.
  HierarchicalFactorization(const ElastostaticProblem& problem, double compression_tolerance, bool keep_copy);
  /// The same, sharing ownership of `problem` (what a table kept for cuts holds: the factorisation
  /// outlives the caller's problem). InvalidArgumentError for a null problem.
  HierarchicalFactorization(std::shared_ptr<const ElastostaticProblem> problem, double compression_tolerance, bool keep_copy);
  ~HierarchicalFactorization() override;
  HierarchicalFactorization(HierarchicalFactorization&&) noexcept;
  HierarchicalFactorization& operator=(HierarchicalFactorization&&) noexcept;
  HierarchicalFactorization(const HierarchicalFactorization&) = delete;
  HierarchicalFactorization& operator=(const HierarchicalFactorization&) = delete;

  /// n, the number of unknowns.
  Index size() const override;
  /// Bytes of the H-LU's factors (result().factor_entries), the column scales and, while kept, the copy.
  std::size_t bytes() const override;
  /// Solves A* X = B in place for all columns of `B` (n x k) at once; adds the time to
  /// result().solve_seconds. Solves are serialised (one hmat-oss solve at a time per factorisation).
  /// Throws SolverError when hmat-oss fails or the result is not finite.
  void solve_in_place(Eigen::Ref<Eigen::MatrixXd> B) const override;
  /// ||b - A* x|| / ||b|| with the assembled copy (0 when `keep_copy` was false or after release_copy).
  double relative_residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x) const;
  /// Frees the assembled copy (relative_residual returns 0 afterwards): a factorisation kept beyond
  /// its first solve keeps only its factors.
  void release_copy();
  /// The right-hand side of eq. 6 for the problem's conditions and gravity (G t_known - H u_known plus
  /// gravity), assembled from the loaded elements' columns only.
  Eigen::VectorXd right_hand_side() const;
  /// Columns 3e..3e+2 of G for each element e of `elements`, in order, into `out` (n x 3|elements|):
  /// a table's right-hand sides, unit tractions on its region. Constant elements only
  /// (InvalidArgumentError for linear ones: tables take constant elements).
  void g_columns(const std::vector<Index>& elements, Eigen::Ref<Eigen::MatrixXd> out) const;
  /// Compression, phases and (after a solve) the residual of the last relative_residual call.
  const HierarchicalResult& result() const;

 private:
  HierarchicalFactorization(std::shared_ptr<const ElastostaticProblem> owned, const ElastostaticProblem& problem,
                            double compression_tolerance, bool keep_copy);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Where "method": "auto" switches to the hierarchical backend, in unknowns (3 per constant element,
/// 9 per linear one: both backends' work follows n): from there its whole solve measured faster than
/// dense LU on this project's 2-core machines (bench_hmatrix, the report's "Hierarchical matrices
/// against dense": a resting cube crossed over at about 4,050 constant elements, n = 12,150, and
/// 1,445 and 1,513 linear ones, n = 13,000 and 13,600, in two runs with the H-LU on one BLAS
/// thread; at 2,028 linear elements 0.76 x dense), set at or a little above them, since near them
/// the two are within their run-to-run spread and dense is the reference.
inline constexpr Index kAutoHierarchicalUnknowns = 13500;

/// kAutoHierarchicalUnknowns in elements of `type`, rounded up: 4,500 constant, 1,500 linear.
inline constexpr Index auto_hierarchical_elements(ElementType type) {
  const Index per = type == ElementType::Linear ? 9 : 3;
  return (kAutoHierarchicalUnknowns + per - 1) / per;
}

/// What "method": "auto" chose for a mesh, and why in words (the commands print it).
/// \ingroup elastostatics
struct BackendChoice {
  SolverBackend backend = SolverBackend::Dense;
  std::string reason;
};

/// The choice of "method": "auto" for `elements` elements of `type`: the hierarchical backend when
/// it is built (hierarchical_backend_available()) and either elements >=
/// auto_hierarchical_elements(type) or the dense solve would not fit in memory (estimate_elastostatic_bytes
/// against 80 % of physical memory); dense LU otherwise. Cuts do not change it: a cut step on the
/// H-LU measured faster than on the dense LU from about 1,000 elements (bench_hmatrix's cut study).
BackendChoice choose_backend(Index elements, ElementType type);

/// The static solve of `problem` on the hierarchical backend, with the same checks as
/// solve_elastostatic (check_before_solve), except memory: the compressed matrix's size is not known
/// before assembly. Constant or linear elements (for linear ones `nodes` holds the per-node values and
/// `boundary` their centroid means, as the dense solve gives). `options.compression_tolerance` sets
/// ACA+'s tolerance; the Krylov settings are not used. Throws SolverError when the backend is missing
/// or the factorisation or solve fails, and whatever check_before_solve throws.
ElastostaticSolution solve_elastostatic_hierarchical(const ElastostaticProblem& problem, const LinearSolverOptions& options,
                                                     HierarchicalResult* result = nullptr);

}  // namespace bemsurg
