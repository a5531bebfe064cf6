// Implementation of bemsurg/distributed/scalapack_solver.hpp: A* assembled block by block into
// ScaLAPACK's block-cyclic layout, pdgetrf / pdgetrs, the solution gathered on rank 0.
#include "bemsurg/distributed/scalapack_solver.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/timing.hpp"

#if BEMSURG_HAVE_MPI
#include "scalapack_api.hpp"
#endif

namespace bemsurg {

namespace {

/// The process grid for `ranks`: rows <= columns, as square as the count's divisors allow.
void process_grid(int ranks, int& rows, int& columns) {
  rows = static_cast<int>(std::sqrt(double(ranks)));
  while (rows > 1 && ranks % rows != 0) --rows;
  columns = ranks / rows;
}

/// Rows (or columns) of an n-vector's blocks that process `p` of `procs` holds: numroc's count.
Index local_count(Index n, int p, int procs) {
  const Index blocks = (n + kScalapackBlock - 1) / kScalapackBlock;
  Index count = 0;
  for (Index b = p; b < blocks; b += procs) count += std::min<Index>(kScalapackBlock, n - b * kScalapackBlock);
  return count;
}

}  // namespace

double estimate_scalapack_bytes_per_rank(Index num_elements, int ranks) {
  const Index n = 3 * num_elements;
  int rows = 1, columns = 1;
  process_grid(std::max(ranks, 1), rows, columns);
  const double local = double(local_count(n, 0, rows)) * double(local_count(n, 0, columns));  // rank 0 holds the most
  return 2.0 * 8.0 * local + 2.0 * 8.0 * double(local_count(n, 0, rows)) * kScalapackBlock + 8.0 * 8.0 * double(n);
}

#if BEMSURG_HAVE_MPI

namespace {

/// Global index of local index `i` of a process at grid coordinate `p` of `procs`.
Index global_index(Index i, int p, int procs) { return (p + (i / kScalapackBlock) * procs) * kScalapackBlock + i % kScalapackBlock; }

/// The BLACS grid on MPI_COMM_WORLD, released at scope exit.
struct BlacsGrid {
  int system = 0, context = 0, rows = 1, columns = 1, my_row = 0, my_column = 0;
  explicit BlacsGrid(int ranks) {
    process_grid(ranks, rows, columns);
    system = Csys2blacs_handle(MPI_COMM_WORLD);
    context = system;
    Cblacs_gridinit(&context, "Row", rows, columns);
    Cblacs_gridinfo(context, &rows, &columns, &my_row, &my_column);
  }
  ~BlacsGrid() {
    Cblacs_gridexit(context);
    Cfree_blacs_system_handle(system);
  }
  BlacsGrid(const BlacsGrid&) = delete;
  BlacsGrid& operator=(const BlacsGrid&) = delete;
};

/// This rank's blocks of A* (column-major, local_rows x local_columns) and its part of the right-hand
/// side's known-value terms, summed into `rhs` (length n, global rows): per local block column, the
/// H and G of all local rows against that block's elements, then H or -G per column as the condition
/// says (the paper's eq. 6 column swap, as build_system_matrix_in_place).
void assemble_local(const InfluenceAssembler& assembler, const BoundaryConditions& bc, const BlacsGrid& grid, Eigen::MatrixXd& A,
                    Eigen::VectorXd& rhs) {
  const Index mloc = A.rows(), nloc = A.cols();
  std::vector<Index> row_elements;
  for (Index i = 0; i < mloc; i += 3) row_elements.push_back(global_index(i, grid.my_row, grid.rows) / 3);
  const Index R = static_cast<Index>(row_elements.size());
  Eigen::MatrixXd H, G;
  for (Index c0 = 0; c0 < nloc; c0 += kScalapackBlock) {
    const Index width = std::min<Index>(kScalapackBlock, nloc - c0);
    const Index g0 = global_index(c0, grid.my_column, grid.columns);
    std::vector<Index> col_elements;
    for (Index j = 0; j < width; j += 3) col_elements.push_back((g0 + j) / 3);
    H.resize(3 * R, width);
    G.resize(3 * R, width);
    if (R > 0)
      assembler.assemble_block(row_elements.data(), R, col_elements.data(), static_cast<Index>(col_elements.size()), H.data(), G.data(),
                               nullptr, Eigen::Vector3d::Zero());
    for (Index j = 0; j < width; ++j) {
      const Index dof = g0 + j;
      const bool traction_known = bc.kind(dof) == BcKind::Traction;
      if (traction_known)  // no temporary per column: -G is written in place
        A.col(c0 + j) = H.col(j);
      else
        A.col(c0 + j) = -G.col(j);
      const double value = bc.value(dof);
      if (value == 0.0) continue;
      for (Index i = 0; i < mloc; ++i) rhs(global_index(i, grid.my_row, grid.rows)) += traction_known ? G(i, j) * value : -H(i, j) * value;
    }
  }
}

}  // namespace

// long: one solve's phases in order, each on every rank (check, grid, blocks, right-hand side,
// factorisation, solve, residual, gather); splitting them would pass the grid and descriptors around.
ElastostaticSolution solve_elastostatic_scalapack(const MpiRuntime& mpi, const ElastostaticProblem& problem, ScalapackResult* result) {
  if (problem.elements != ElementType::Constant)
    throw InvalidArgumentError("solver method scalapack: constant elements only (linear elements: use lu, a Krylov method or hmatrix)");
  if (!mpi.active()) throw SolverError("solve_elastostatic_scalapack: MPI is not initialised (construct MpiRuntime(true) first)");
  const Index E = problem.mesh.num_elements(), n = 3 * E;
  const int P = mpi.size();
  MemoryNeed memory;
  memory.bytes = estimate_scalapack_bytes_per_rank(E, P);
  memory.limit_bytes = mpi.memory_limit_bytes();  // the node's limit shared by its ranks
  memory.refusal = [E, n, P, &mpi](double need, double limit) {
    return "rank " + std::to_string(mpi.rank()) + "'s part of the scalapack solve of " + std::to_string(E) + " elements (" +
           std::to_string(n) + " equations) on " + std::to_string(P) + " ranks needs about " + format_gib(need) +
           ", more than its share of the node's memory, " + format_gib(limit) +
           " (80 % of physical memory over the node's ranks); spread the ranks over more nodes";
  };
  ElastostaticSolution out;
  out.report.elements = E;
  out.report.equations = n;
  out.report.warnings = check_before_solve(problem, memory, "solve_elastostatic_scalapack");

  const BlacsGrid grid(P);
  ScalapackResult r;
  r.ranks = P;
  r.process_rows = grid.rows;
  r.process_columns = grid.columns;
  const Index mloc = local_count(n, grid.my_row, grid.rows), nloc = local_count(n, grid.my_column, grid.columns);
  r.local_rows = mloc;
  r.local_columns = nloc;
  r.local_matrix_bytes = 2.0 * 8.0 * double(mloc) * double(nloc);

  // Blocks, the gravity of an equal share of the rows, the known values' terms; b summed over the ranks.
  auto t0 = SteadyClock::now();
  const InfluenceAssembler assembler(problem.mesh, problem.material, problem.quadrature);
  Eigen::MatrixXd A(mloc, nloc);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  assemble_local(assembler, problem.boundary_conditions, grid, A, rhs);
  const Eigen::Vector3d body_force = problem.material.density * problem.gravity;
  const Index e0 = E * mpi.rank() / P, e1 = E * (mpi.rank() + 1) / P;
  if (body_force.squaredNorm() > 0.0 && e1 > e0) {
    std::vector<Index> rows;
    for (Index e = e0; e < e1; ++e) rows.push_back(e);
    Eigen::VectorXd g(3 * (e1 - e0));
    assembler.assemble_block(rows.data(), e1 - e0, nullptr, E, nullptr, nullptr, g.data(), body_force);
    rhs.segment(3 * e0, 3 * (e1 - e0)) += g;
  }
  MPI_Allreduce(MPI_IN_PLACE, rhs.data(), static_cast<int>(n), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  const Eigen::MatrixXd A_copy = A;  // for the true residual: pdgetrf overwrites A
  r.assembly_seconds = mpi.max(seconds_since(t0));

  const int N = static_cast<int>(n), nb = kScalapackBlock, zero = 0, one = 1, lld = static_cast<int>(std::max<Index>(1, mloc));
  int desc_a[9], desc_b[9], info = 0;
  descinit_(desc_a, &N, &N, &nb, &nb, &zero, &zero, &grid.context, &lld, &info);
  if (info == 0) descinit_(desc_b, &N, &one, &nb, &nb, &zero, &zero, &grid.context, &lld, &info);
  if (info != 0) throw SolverError("scalapack: descinit rejected argument " + std::to_string(-info) + " (an internal error)");
  // b in the layout of A's first block column: the ranks of process column 0 hold its rows.
  const bool holds_b = grid.my_column == 0;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(std::max<Index>(1, holds_b ? mloc : 0));
  if (holds_b)
    for (Index i = 0; i < mloc; ++i) b(i) = rhs(global_index(i, grid.my_row, grid.rows));
  const Eigen::VectorXd b0 = b;

  t0 = SteadyClock::now();
  std::vector<int> pivots(static_cast<std::size_t>(mloc + kScalapackBlock));
  pdgetrf_(&N, &N, A.data(), &one, &one, desc_a, pivots.data(), &info);
  r.factorization_seconds = mpi.max(seconds_since(t0));
  if (info > 0) throw SolverError("scalapack: the system matrix is singular to working precision (is the body supported?)");
  if (info < 0) throw SolverError("scalapack: pdgetrf rejected argument " + std::to_string(-info) + " (an internal error)");
  t0 = SteadyClock::now();
  pdgetrs_("N", &N, &one, A.data(), &one, &one, desc_a, pivots.data(), b.data(), &one, &one, desc_b, &info);
  r.solve_seconds = mpi.max(seconds_since(t0));
  if (info != 0) throw SolverError("scalapack: pdgetrs rejected argument " + std::to_string(-info) + " (an internal error)");

  // The true residual b - A* x on the blocks' copy: y = b0 - A x in b's layout.
  Eigen::VectorXd y = b0;
  const double minus_one = -1.0, plus_one = 1.0;
  pdgemv_("N", &N, &N, &minus_one, A_copy.data(), &one, &one, desc_a, b.data(), &one, &one, desc_b, &one, &plus_one, y.data(), &one, &one,
          desc_b, &one);

  // Rank 0 gathers x (and the residual's squares) from the ranks of process column 0.
  t0 = SteadyClock::now();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  double squares[2] = {0.0, 0.0};
  if (holds_b) {
    for (Index i = 0; i < mloc; ++i) x(global_index(i, grid.my_row, grid.rows)) = b(i);
    squares[0] = y.head(mloc).squaredNorm();
  }
  squares[1] = mpi.root() ? rhs.squaredNorm() : 0.0;
  MPI_Reduce(mpi.root() ? MPI_IN_PLACE : x.data(), mpi.root() ? x.data() : nullptr, static_cast<int>(n), MPI_DOUBLE, MPI_SUM, 0,
             MPI_COMM_WORLD);
  MPI_Allreduce(MPI_IN_PLACE, squares, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  r.gather_seconds = seconds_since(t0);
  r.relative_residual = squares[1] > 0.0 ? std::sqrt(squares[0] / squares[1]) : std::sqrt(squares[0]);

  LinearSolveResult& s = out.report.solver;
  s.method = SolverMethod::Lu;
  s.preconditioner = PreconditionerKind::None;
  s.relative_residual = r.relative_residual;
  s.setup_seconds = r.factorization_seconds;
  s.solve_seconds = r.solve_seconds;
  s.initial_residual = 1.0;
  out.report.assembly_seconds = r.assembly_seconds;
  if (mpi.root() && (!x.allFinite() || !std::isfinite(r.relative_residual))) {
    s.status = KrylovStatus::NonFinite;
    throw SolverError("scalapack: the solution is not finite (NaN or infinity in the matrix or the right-hand side)");
  }
  s.status = KrylovStatus::Converged;
  if (mpi.root()) out.boundary = recover_boundary_solution(problem.boundary_conditions, x);
  if (result) *result = r;
  return out;
}

#else

ElastostaticSolution solve_elastostatic_scalapack(const MpiRuntime&, const ElastostaticProblem&, ScalapackResult*) {
  throw SolverError(
      "solver method scalapack: this build of bemsurg has no MPI and ScaLAPACK (configure with -DBEMSURG_WITH_MPI=ON; Debian: "
      "libopenmpi-dev, openmpi-bin, libscalapack-openmpi-dev; scripts/setup-deps.sh installs them)");
}

#endif

}  // namespace bemsurg
