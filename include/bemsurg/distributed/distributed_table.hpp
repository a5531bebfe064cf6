// bemsurg/distributed/distributed_table.hpp: a pre-solution table whose columns the ranks of an MPI
// run share (issue 41, item 2; docs/distributed.md, "Tables across ranks").
//
// A table is many independent solves with one matrix: three columns per element of the region, each
// 2 n^2 flops once A* is factorised. Every rank therefore holds the factorisation of the backend the
// scene names (the dense LU, or the H-LU where hmat-oss is built in: the same factorisation a single
// process would compute, so the same numbers to round-off) and solves a contiguous share of the
// region's elements; rank 0 solves the base state as well and gathers the columns. No rank talks to
// another until the gather, so the columns scale with the ranks; the assembly and the factorisation
// are repeated on every rank and do not (on one node, the ranks share its cores for them). Memory
// per rank is that of a single process: replication scales the columns, not the size of organ a
// rank holds (what does is the "scalapack" solve, scalapack_solver.hpp).
#pragma once

#include <vector>

#include "bemsurg/distributed/mpi_runtime.hpp"
#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/solvers/linear_solve.hpp"

namespace bemsurg {

/// What compute_greens_table_across_ranks did: how the region was shared and what each phase cost.
/// \ingroup distributed
struct DistributedTableReport {
  int ranks = 1;
  /// Region columns each rank solved, in rank order (3 per element; rank 0 also solved the base state).
  std::vector<Index> columns_per_rank;
  /// "dense LU on every rank" or "H-LU on every rank": the factorisation each rank held.
  const char* factorization = "";
  /// Rank 0's phases (assembly, factorisation, its share of the columns).
  PrecomputeTimings timings;
  /// The slowest rank's seconds before the gather (assembly, factorisation and its columns).
  double slowest_rank_seconds = 0.0;
  /// Rank 0's seconds to gather every rank's columns (waiting for the slowest included).
  double gather_seconds = 0.0;
};

/// The table of `problem` (constant elements) on `region` (as GreensTable::compute: elements where
/// tools act, each free; empty: every free element) computed by the ranks of `mpi` together, on the
/// backend `solver` names (dense, or hmatrix at its compression tolerance; another backend is
/// refused with InvalidArgumentError). Every rank runs the problem's check (its need against the
/// node's memory limit shared by the node's ranks), assembles and factorises
/// A*, and solves its share of the region (equal shares of elements, in region order); rank 0 also
/// solves the base state and gathers the rest. Rank 0 returns the table, with the key a single
/// process gives it (so a file of it loads wherever that one would) and no factorisation (it cannot
/// be cut: a session that cuts computes its own); the other ranks return an empty table. With one
/// rank, the single-process table. Throws what GreensTable::compute throws, on every rank alike for
/// a bad problem (each holds the same input); an error on one rank only (memory) leaves the others
/// in the gather: the caller aborts the run (MpiRuntime::abort).
GreensTable compute_greens_table_across_ranks(const MpiRuntime& mpi, const ElastostaticProblem& problem, const std::vector<Index>& region,
                                              const LinearSolverOptions& solver, DistributedTableReport* report = nullptr);

/// The first region element of each rank's share and, last, the region's size: `ranks` + 1 entries,
/// shares as equal as possible (the first R mod ranks one larger).
std::vector<Index> table_shares(Index region_elements, int ranks);

}  // namespace bemsurg
