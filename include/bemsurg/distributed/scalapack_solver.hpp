// bemsurg/distributed/scalapack_solver.hpp: the dense solve with A* split over the ranks of an MPI
// run (issue 41, item 3; docs/distributed.md, "A distributed dense solve"; scene "method": "scalapack").
//
// A* (n x n, constant elements) lives in ScaLAPACK's 2-D block-cyclic layout on a process grid as
// square as the rank count allows, in blocks of kScalapackBlock rows and columns (a multiple of 3,
// so a block holds whole elements). Each rank assembles only its own blocks, through the same block
// routine as the dense assembly (InfluenceAssembler::assemble_block: near field, far field and self
// pairs exactly as the dense A*), the gravity term of an equal share of the rows and the known
// values' part of the right-hand side of its blocks; the right-hand side is summed over the ranks.
// pdgetrf factorises with partial pivoting, pdgetrs solves, and rank 0 gathers the solution. No
// rank ever holds the whole matrix: a rank's peak is about 2 n^2 / P doubles (its blocks, and their
// copy for the true residual), against the single process's 2 n^2 (H and G).
#pragma once

#include "bemsurg/distributed/mpi_runtime.hpp"
#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"

namespace bemsurg {

/// Rows and columns of a block of the block-cyclic layout: a multiple of 3 (whole elements); 96 is
/// where pdgetrf's panel work and the block routine's tiles both run near their best on small grids.
constexpr int kScalapackBlock = 96;

/// What solve_elastostatic_scalapack did.
/// \ingroup distributed
struct ScalapackResult {
  int ranks = 1;
  int process_rows = 1, process_columns = 1;  // the grid (process_rows <= process_columns)
  int block_size = kScalapackBlock;
  Index local_rows = 0, local_columns = 0;  // this rank's part of A*
  double local_matrix_bytes = 0.0;          // this rank's blocks and their copy
  /// The slowest rank's phases: its blocks and its share of the right-hand side, pdgetrf, pdgetrs.
  double assembly_seconds = 0.0, factorization_seconds = 0.0, solve_seconds = 0.0;
  double gather_seconds = 0.0;     // rank 0 collecting the solution (its own time)
  double relative_residual = 0.0;  // ||b - A* x|| / ||b||, from the blocks' copy (pdgemv)
};

/// Bytes one of `ranks` ranks needs at its peak for `num_elements` constant elements: its blocks of
/// A* and their copy (2 n^2 / P doubles, rounded up to whole blocks), O(n) vectors and a block column
/// of H and G.
double estimate_scalapack_bytes_per_rank(Index num_elements, int ranks);

/// The problem (constant elements) solved by the ranks of `mpi` together (see the file comment);
/// a single rank when `mpi` has one. Runs the problem's one check on every rank with the per-rank
/// memory need against the node's limit shared by its ranks (ResourceError names the rank's share). Rank 0 returns the solution (and the report:
/// method lu, its residual and phases); the other ranks return the report with empty fields. Throws
/// InvalidArgumentError for linear elements, SolverError for a singular A* (every rank alike) and
/// when this build has no MPI (distributed_backend_available()).
ElastostaticSolution solve_elastostatic_scalapack(const MpiRuntime& mpi, const ElastostaticProblem& problem,
                                                  ScalapackResult* result = nullptr);

}  // namespace bemsurg
