// Implementation of bemsurg/distributed/distributed_table.hpp: each rank's share of the columns on
// its own factorisation, gathered by rank 0 as whole columns (an MPI datatype of n doubles, so the
// counts stay small whatever n).
#include "bemsurg/distributed/distributed_table.hpp"

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/presolution/hierarchical_table.hpp"
#include "bemsurg/solvers/lu_factors.hpp"
#include "bemsurg/timing.hpp"

#if BEMSURG_HAVE_MPI
#include <mpi.h>
#endif

namespace bemsurg {

std::vector<Index> table_shares(Index region_elements, int ranks) {
  if (ranks < 1) throw InvalidArgumentError("table_shares: the number of ranks must be positive, got " + std::to_string(ranks));
  std::vector<Index> first(static_cast<std::size_t>(ranks) + 1, 0);
  const Index base = region_elements / ranks, extra = region_elements % ranks;
  for (int r = 0; r < ranks; ++r) first[static_cast<std::size_t>(r) + 1] = first[static_cast<std::size_t>(r)] + base + (r < extra ? 1 : 0);
  return first;
}

namespace {

/// One rank's share: the solution of A* X = [G columns of `elements`, (the base right-hand side)],
/// n x (3|elements| + with_base), on the dense LU. The same steps as GreensTable::compute, restricted
/// to the share's columns (each rank holds H and G once during assembly, then A*'s LU).
Eigen::MatrixXd dense_share(const ElastostaticProblem& problem, const std::vector<Index>& elements, bool with_base, PrecomputeTimings& t) {
  const Index n = 3 * problem.mesh.num_elements(), k = static_cast<Index>(elements.size());
  auto t0 = SteadyClock::now();
  Eigen::MatrixXd A, B(n, 3 * k + (with_base ? 1 : 0));
  {
    const InfluenceAssembler assembler(problem.mesh, problem.material, problem.quadrature);
    Eigen::VectorXd gvec;
    InfluenceMatrices hg = assembler.assemble(problem.gravity, gvec);
    for (Index s = 0; s < k; ++s) B.middleCols(3 * s, 3) = hg.G.middleCols(3 * elements[static_cast<std::size_t>(s)], 3);
    if (with_base) B.col(3 * k) = build_right_hand_side(hg, problem.boundary_conditions, gvec);
    A = build_system_matrix_in_place(hg, problem.boundary_conditions);
  }
  t.assembly_seconds = seconds_since(t0);
  const LuFactors lu = LuFactors::factor(std::move(A), &t.factorization_seconds);
  t0 = SteadyClock::now();
  lu.solve_in_place(B);
  t.table_seconds = seconds_since(t0);
  return B;
}

/// The same on the H-LU (compute_greens_table_hierarchical's steps for the share's columns).
Eigen::MatrixXd hierarchical_share(const ElastostaticProblem& problem, const std::vector<Index>& elements, bool with_base,
                                   double compression_tolerance, PrecomputeTimings& t) {
  const Index n = 3 * problem.mesh.num_elements(), k = static_cast<Index>(elements.size());
  const HierarchicalFactorization factors(problem, compression_tolerance, false);
  t.factorization_seconds = factors.result().factorization_seconds;
  const auto t_rhs = SteadyClock::now();
  Eigen::MatrixXd B(n, 3 * k + (with_base ? 1 : 0));
  if (k > 0) factors.g_columns(elements, B.leftCols(3 * k));
  if (with_base) B.col(3 * k) = factors.right_hand_side();
  t.assembly_seconds = factors.result().assembly_seconds + seconds_since(t_rhs);
  const auto t0 = SteadyClock::now();
  factors.solve_in_place(B);
  t.table_seconds = seconds_since(t0);
  return B;
}

}  // namespace

GreensTable compute_greens_table_across_ranks(const MpiRuntime& mpi, const ElastostaticProblem& problem, const std::vector<Index>& region,
                                              const LinearSolverOptions& solver, DistributedTableReport* report) {
  const bool hierarchical = solver.backend == SolverBackend::HMatrix;
  if (solver.backend != SolverBackend::Dense && !hierarchical)
    throw InvalidArgumentError(std::string("compute_greens_table_across_ranks: the ") + to_string(solver.backend) +
                               " backend has no table across ranks; use dense or hmatrix");
  if (problem.elements != ElementType::Constant)
    throw InvalidArgumentError("compute_greens_table_across_ranks: tables take constant elements (a tool's traction acts on an element)");
  if (hierarchical && !hierarchical_backend_available())
    solve_elastostatic_hierarchical(problem, solver);  // throws, saying what is missing
  GreensTable::require_conditions_for(problem.boundary_conditions, problem.mesh);
  std::vector<Index> elements = GreensTable::resolve_region(problem.boundary_conditions, region);
  const Index E = problem.mesh.num_elements(), n = 3 * E, R = static_cast<Index>(elements.size());
  const int K = mpi.size(), me = mpi.rank();
  const std::vector<Index> first = table_shares(R, K);
  const std::vector<Index> mine(elements.begin() + first[static_cast<std::size_t>(me)],
                                elements.begin() + first[static_cast<std::size_t>(me) + 1]);
  const Index k = static_cast<Index>(mine.size());

  // The problem's one check, with what this rank will hold: the factorisation's need plus its share
  // of the table (rank 0: the whole table, which it gathers).
  MemoryNeed memory;
  const double share = 8.0 * double(n) * double(mpi.root() ? 3 * R + 1 + 3 * k : 3 * k);
  memory.bytes = (hierarchical ? estimate_hierarchical_bytes(E) : GreensTable::estimate_bytes(E, 0)) + share;
  memory.limit_bytes = mpi.memory_limit_bytes();  // the node's limit shared by its ranks
  memory.refusal = [E, n, R, me](double need, double limit) {
    return "rank " + std::to_string(me) + "'s part of the table for " + std::to_string(E) + " elements (" + std::to_string(n) +
           " equations) with a region of " + std::to_string(R) + " elements needs about " + format_gib(need) +
           ", more than its share of the node's memory, " + format_gib(limit) +
           "; run fewer ranks per node, restrict the region, or coarsen the mesh";
  };
  std::vector<std::string> warnings = check_before_solve(problem, memory, "GreensTable");

  const auto t_start = SteadyClock::now();
  PrecomputeTimings timings;
  Eigen::MatrixXd B = hierarchical ? hierarchical_share(problem, mine, mpi.root(), solver.compression_tolerance, timings)
                                   : dense_share(problem, mine, mpi.root(), timings);
  const double own_seconds = seconds_since(t_start);
  if (!B.allFinite()) throw SolverError("GreensTable: rank " + std::to_string(me) + "'s columns have non-finite entries");

  Eigen::MatrixXd X;
  const auto t_gather = SteadyClock::now();
  if (K == 1) {
    X = std::move(B);
  } else {
#if BEMSURG_HAVE_MPI
    // Whole columns of n doubles: counts and displacements in columns fit an int for any table that fits memory.
    MPI_Datatype column;
    MPI_Type_contiguous(static_cast<int>(n), MPI_DOUBLE, &column);
    MPI_Type_commit(&column);
    std::vector<int> counts(static_cast<std::size_t>(K)), displacements(static_cast<std::size_t>(K));
    for (int r = 0; r < K; ++r) {
      counts[static_cast<std::size_t>(r)] =
          static_cast<int>(3 * (first[static_cast<std::size_t>(r) + 1] - first[static_cast<std::size_t>(r)]));
      displacements[static_cast<std::size_t>(r)] = static_cast<int>(3 * first[static_cast<std::size_t>(r)]);
    }
    if (mpi.root()) X.resize(n, 3 * R + 1);
    MPI_Gatherv(B.data(), static_cast<int>(3 * k), column, mpi.root() ? X.data() : nullptr, counts.data(), displacements.data(), column, 0,
                MPI_COMM_WORLD);
    MPI_Type_free(&column);
    if (mpi.root()) X.col(3 * R) = B.col(3 * k);  // the base state, solved by rank 0 after its share
#else
    throw SolverError("compute_greens_table_across_ranks: several ranks, and this build has no MPI");
#endif
  }
  B.resize(0, 0);
  const double gather_seconds = seconds_since(t_gather);
  const double slowest = mpi.max(own_seconds);
  if (report) {
    report->ranks = K;
    report->columns_per_rank.clear();
    for (int r = 0; r < K; ++r)
      report->columns_per_rank.push_back(3 * (first[static_cast<std::size_t>(r) + 1] - first[static_cast<std::size_t>(r)]));
    report->factorization = hierarchical ? "H-LU on every rank" : "dense LU on every rank";
    report->timings = timings;
    report->slowest_rank_seconds = slowest;
    report->gather_seconds = gather_seconds;
  }
  if (!mpi.root()) return GreensTable();
  auto mesh = std::make_shared<const TriangleMesh>(problem.mesh);
  return GreensTable::from_solution(std::move(mesh), problem, std::move(elements), std::move(X), solver.backend,
                                    solver.compression_tolerance, std::move(warnings), timings);
}

}  // namespace bemsurg
