// bemsurg/presolution/hierarchical_table.hpp: a pre-solution table computed on the hierarchical
// backend (issue 40; docs/solvers.md, "Hierarchical matrices"): A* compressed by ACA+ and
// factorised by an H-LU (elastostatics/hierarchical_solver.hpp), the table's columns (unit tractions
// on the region's elements, G's columns) and the base state solved as one multi-right-hand-side
// solve. The same table as GreensTable::compute's to the compression's accuracy, in a fraction of
// the dense A*'s memory; its key records the backend and tolerance (a file of it never loads into a
// dense scene). Asked to (`for_cuts`), it keeps the H-LU so that cuts update it exactly, as they
// update the dense LU (docs/cutting.md, "On either backend"); otherwise it keeps no factorisation.
//
// Part of the optional compiled component bemsurg::hmatrix (hmat-oss, GPL-2.0-or-later): without
// hmat-oss it throws SolverError saying so.
#pragma once

#include <memory>
#include <vector>

#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/solvers/linear_solve.hpp"

namespace bemsurg {

/// The table of `problem` (constant elements) on `region` (as GreensTable::compute: elements where
/// tools act, each free; empty: every free element) on the hierarchical backend at
/// `options.compression_tolerance`. Runs check_before_solve with the hierarchical memory estimate
/// plus the table's n x 3|region| (its warnings are the table's warnings()); `result` receives the
/// compression and phases, with the base state's relative residual (for which a copy of the
/// compressed matrix is kept through the factorisation: without `result`, none is). With `for_cuts`
/// the table keeps the H-LU (has_factorization(); its factors stay in memory, result().factor_entries)
/// and recomputes on this backend at this tolerance when a cut's rank asks for a refactorisation.
/// Throws as GreensTable::compute does for the problem and region, and SolverError when the backend
/// is missing or fails.
GreensTable compute_greens_table_hierarchical(const ElastostaticProblem& problem, const std::vector<Index>& region,
                                              const LinearSolverOptions& options, HierarchicalResult* result = nullptr,
                                              bool for_cuts = false);
/// The same for a mesh snapshot shared with its other users (the viewer's): the table's mesh() is
/// `mesh`, which must equal problem.mesh (InvalidArgumentError when its size differs or it is null).
GreensTable compute_greens_table_hierarchical(std::shared_ptr<const TriangleMesh> mesh, const ElastostaticProblem& problem,
                                              const std::vector<Index>& region, const LinearSolverOptions& options,
                                              HierarchicalResult* result = nullptr, bool for_cuts = false);

}  // namespace bemsurg
