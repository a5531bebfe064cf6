// bemsurg/elastostatics/hierarchical_solver.hpp: the hierarchical-matrix backend of a static solve
// (docs/solvers.md, "Hierarchical matrices"; issue 40). A* (the mixed system of eq. 6) is assembled
// block by block through the same quadrature as the dense path (near-field blocks exactly as today),
// far-field blocks compressed by ACA+ to a relative tolerance, factorised by an H-LU and solved, by
// hmat-oss (Airbus; Debian's libhmat-oss-dev, GPL-2.0-or-later).
//
// A compiled component: library bemsurg_hmatrix, CMake target bemsurg::hmatrix, built on hmat-oss
// when CMake finds it (BEMSURG_WITH_HMATRIX). Built without it, hierarchical_backend_available() is
// false and solve_elastostatic_hierarchical throws SolverError saying so; the header-only core never
// needs it. Today it covers solves of constant elements (`bemsurg solve`); tables, cuts, sessions,
// interior points and linear elements still use the dense backend.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/solvers/linear_solve.hpp"

namespace bemsurg {

/// What the hierarchical backend did: its compression and its phases (report.json's "backend").
/// \ingroup elastostatics
struct HierarchicalResult {
  double compression_tolerance = 0.0;  // ACA+'s relative tolerance per block (LinearSolverOptions::compression_tolerance)
  std::size_t stored_entries = 0;      // doubles stored by the H-matrix (full and low-rank leaves) before the H-LU
  std::size_t dense_entries = 0;       // n^2: what the dense A* stores
  double compression_ratio = 0.0;      // stored / dense
  int largest_rank = 0;                // rank of the largest low-rank block (by memory)
  int leaves_full = 0, leaves_low_rank = 0;
  double column_scale = 1.0;  // traction-unknown columns multiplied by mu / h (see hierarchical_solver.cpp)
  double assembly_seconds = 0.0, factorization_seconds = 0.0, solve_seconds = 0.0;
  double relative_residual = 0.0;  // ||b - A x|| / ||b|| with A the compressed matrix before its H-LU
};

/// True when this build has the hierarchical backend (hmat-oss was found).
bool hierarchical_backend_available();

/// A planning estimate of the hierarchical solve's peak bytes for `elements` constant elements, before
/// anything is assembled (the scene loader's and the solve's memory checks; docs/solvers.md): the
/// stored fraction of dense A* measured on organ meshes, 0.41 at 1,778 elements falling as E^-0.74
/// (0.126 at 9,344, 0.064 at 20,480), counted twice (the H-LU's factors and the copy the residual
/// needs), plus a leaf's block rows per unknown.
inline double estimate_hierarchical_bytes(Index elements) {
  const double e = elements > 1 ? double(elements) : 1.0, n = 3.0 * e;
  const double fraction = std::min(1.0, 0.41 * std::pow(e / 1778.0, -0.74));
  return 2.0 * 8.0 * n * n * fraction + 64.0 * n * 120.0;
}

/// The static solve of `problem` on the hierarchical backend, with the same checks as
/// solve_elastostatic (check_before_solve), except memory: the compressed matrix's size is not known
/// before assembly. Constant elements only. `options.compression_tolerance` sets ACA+'s tolerance;
/// the Krylov settings are not used. Throws SolverError when the backend is missing, the elements are
/// linear, or the factorisation or solve fails, and whatever check_before_solve throws.
ElastostaticSolution solve_elastostatic_hierarchical(const ElastostaticProblem& problem, const LinearSolverOptions& options,
                                                     HierarchicalResult* result = nullptr);

}  // namespace bemsurg
