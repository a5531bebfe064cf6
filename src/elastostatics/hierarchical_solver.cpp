// Implementation of bemsurg/elastostatics/hierarchical_solver.hpp: the static solve on hmat-oss
// (docs/solvers.md, "Hierarchical matrices"). Built as library bemsurg_hmatrix; without hmat-oss
// (BEMSURG_HAVE_HMAT unset) only the refusals below are compiled.
#include "bemsurg/elastostatics/hierarchical_solver.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/node_influence_assembler.hpp"
#include "bemsurg/blas_threads.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/timing.hpp"

#ifdef BEMSURG_HAVE_HMAT
#include <hmat/hmat.h>
#endif

namespace bemsurg {

BackendChoice choose_backend(Index elements, ElementType type) {
  BackendChoice c;
  const std::string count = std::to_string(elements) + " " + to_string(type) + " elements";
  const Index threshold = auto_hierarchical_elements(type);  // kAutoHierarchicalUnknowns in elements of this type
  if (!hierarchical_backend_available()) {
    c.reason = "dense LU: this bemsurg was built without hmat-oss";
  } else if (estimate_elastostatic_bytes(elements, type) > default_memory_limit_bytes()) {
    c.backend = SolverBackend::HMatrix;
    c.reason = "hmatrix: " + count + ", whose dense solve would need about " + format_gib(estimate_elastostatic_bytes(elements, type)) +
               ", more than 80 % of this machine's memory";
  } else if (elements >= threshold) {
    c.backend = SolverBackend::HMatrix;
    c.reason = "hmatrix: " + count + ", at or above " + std::to_string(threshold) + " (" + std::to_string(kAutoHierarchicalUnknowns) +
               " unknowns), where it solves faster than dense LU (docs/solvers.md)";
  } else {
    c.reason = "dense LU: " + count + ", below " + std::to_string(threshold) + " (" + std::to_string(kAutoHierarchicalUnknowns) +
               " unknowns), where dense LU is faster (docs/solvers.md)";
  }
  return c;
}

namespace {
const ElastostaticProblem& owned_problem(const std::shared_ptr<const ElastostaticProblem>& problem) {
  if (!problem) throw InvalidArgumentError("HierarchicalFactorization: no problem");
  return *problem;
}
}  // namespace

#ifndef BEMSURG_HAVE_HMAT

namespace {
[[noreturn]] void missing_backend() {
  throw SolverError(
      "solver method hmatrix: this bemsurg was built without hmat-oss (install libhmat-oss-dev, scripts/setup-deps.sh, and "
      "reconfigure); use \"method\": \"lu\"");
}
}  // namespace

struct HierarchicalFactorization::Impl {
  HierarchicalResult result;
};

bool hierarchical_backend_available() { return false; }

HierarchicalFactorization::HierarchicalFactorization(std::shared_ptr<const ElastostaticProblem>, const ElastostaticProblem&, double, bool) {
  missing_backend();
}
Index HierarchicalFactorization::size() const { missing_backend(); }
std::size_t HierarchicalFactorization::bytes() const { missing_backend(); }
void HierarchicalFactorization::solve_in_place(Eigen::Ref<Eigen::MatrixXd>) const { missing_backend(); }
double HierarchicalFactorization::relative_residual(const Eigen::VectorXd&, const Eigen::VectorXd&) const { missing_backend(); }
void HierarchicalFactorization::release_copy() {}
Eigen::VectorXd HierarchicalFactorization::right_hand_side() const { missing_backend(); }
void HierarchicalFactorization::g_columns(const std::vector<Index>&, Eigen::Ref<Eigen::MatrixXd>) const { missing_backend(); }

ElastostaticSolution solve_elastostatic_hierarchical(const ElastostaticProblem&, const LinearSolverOptions&, HierarchicalResult*) {
  missing_backend();
}

#else

// Named (not anonymous): HierarchicalFactorization::Impl holds these types.
namespace hmat_glue {

/// What every block of A* needs: the quadrature, the conditions (which of H or -G a column takes)
/// and the column scales.
struct SystemContext {
  const InfluenceAssembler* assembler = nullptr;     // constant elements
  const LinearInfluenceAssembler* linear = nullptr;  // linear elements (node rows, 9 columns per element)
  const BoundaryConditions* conditions = nullptr;    // per element, or per node for linear elements
  int column_unknowns = 3;                           // unknowns per column element: 3, or 9 for linear elements
  std::vector<double> scale;                         // per unknown: 1, or mu / h for a traction unknown
};

/// One block of the H-matrix: its rows and columns as unknowns of A* (the client's numbering).
struct BlockDofs {
  const SystemContext* context = nullptr;
  std::vector<int> rows, cols;
};

void release_block(void* data) { delete static_cast<BlockDofs*>(data); }

void prepare_block(int row_start, int row_count, int col_start, int col_count, int* row_hmat2client, int*, int* col_hmat2client, int*,
                   void* context, hmat_block_info_t* info) {
  auto* b = new BlockDofs;
  b->context = static_cast<const SystemContext*>(context);
  b->rows.assign(row_hmat2client + row_start, row_hmat2client + row_start + row_count);
  b->cols.assign(col_hmat2client + col_start, col_hmat2client + col_start + col_count);
  info->user_data = b;
  info->release_user_data = release_block;
  info->block_type = hmat_block_full;
}

/// The units of `dofs` (sorted, unique; a unit holds `per` consecutive unknowns: a row's element or
/// node, 3, or a column's element, 3 or 9) and, for each dof, its place in the per x |units| block.
std::vector<Index> units_of(const int* dofs, int count, int per, std::vector<Index>& local) {
  std::vector<Index> units(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) units[static_cast<std::size_t>(i)] = dofs[i] / per;
  std::sort(units.begin(), units.end());
  units.erase(std::unique(units.begin(), units.end()), units.end());
  local.resize(static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const Index u = dofs[i] / per;
    local[static_cast<std::size_t>(i)] = per * (std::lower_bound(units.begin(), units.end(), u) - units.begin()) + dofs[i] % per;
  }
  return units;
}

/// Entries of A* (scaled) for a sub-block, a row or a column: the blocks of the elements (or, for
/// linear elements, nodes x elements) involved through the dense path's block routines (near field
/// as today), then H or -G per column as its condition says (linear_system.hpp: the paper's eq. 6
/// column swap).
void compute_block(void* data, int row0, int rows, int col0, int cols, void* out) {
  const BlockDofs& b = *static_cast<const BlockDofs*>(data);
  const SystemContext& c = *b.context;
  std::vector<Index> row_local, col_local;
  const std::vector<Index> re = units_of(b.rows.data() + row0, rows, 3, row_local);
  const std::vector<Index> ce = units_of(b.cols.data() + col0, cols, c.column_unknowns, col_local);
  const Index R = static_cast<Index>(re.size()), C = static_cast<Index>(ce.size());
  std::vector<double> H(static_cast<std::size_t>(3 * R * c.column_unknowns * C)), G(H.size());
  if (c.linear)
    c.linear->assemble_block(re.data(), R, ce.data(), C, H.data(), G.data());
  else
    c.assembler->assemble_block(re.data(), R, ce.data(), C, H.data(), G.data(), nullptr, Eigen::Vector3d::Zero());
  double* o = static_cast<double*>(out);
  for (int j = 0; j < cols; ++j) {
    const int dof = b.cols[static_cast<std::size_t>(col0 + j)];
    const bool traction_known = c.conditions->kind(dof) == BcKind::Traction;
    const std::size_t offset = static_cast<std::size_t>(3 * R * col_local[static_cast<std::size_t>(j)]);
    const double s = c.scale[static_cast<std::size_t>(dof)];
    for (int i = 0; i < rows; ++i) {
      const std::size_t k = offset + static_cast<std::size_t>(row_local[static_cast<std::size_t>(i)]);
      o[static_cast<std::size_t>(i) + static_cast<std::size_t>(rows) * static_cast<std::size_t>(j)] = traction_known ? H[k] : -G[k] * s;
    }
  }
}

/// H and G's columns of `elements` over all rows (n x column_unknowns |elements| each): for linear
/// elements every node's rows, pair by pair.
void assemble_columns(const SystemContext& c, const std::vector<Index>& elements, Eigen::MatrixXd& H, Eigen::MatrixXd& G) {
  if (!c.linear) return c.assembler->assemble_columns(elements, H, G);
  const Index N = c.linear->num_nodes(), C = static_cast<Index>(elements.size());
  std::vector<Index> nodes(static_cast<std::size_t>(N));
  for (Index i = 0; i < N; ++i) nodes[static_cast<std::size_t>(i)] = i;
  H.resize(3 * N, 9 * C);
  G.resize(3 * N, 9 * C);
  // One element's columns per task: pair-by-pair rows of every node.
#pragma omp parallel for schedule(dynamic, 1)
  for (Index k = 0; k < C; ++k)
    c.linear->assemble_block(nodes.data(), N, elements.data() + k, 1, H.data() + 9 * k * 3 * N, G.data() + 9 * k * 3 * N);
}

/// The right-hand side of eq. 6: gravity plus the known values' columns, G t_known - H u_known, from
/// the columns of the elements with a nonzero prescribed value, 192 columns at a time (n x 192 of H
/// and G each: 64 constant or 21 linear elements).
Eigen::VectorXd right_hand_side(const SystemContext& c, const ElastostaticProblem& p) {
  const BoundaryConditions& bc = *c.conditions;
  const int per = c.column_unknowns;
  Eigen::VectorXd rhs = c.linear ? c.linear->gravity_vector(p.gravity) : c.assembler->gravity_vector(p.gravity);
  std::vector<Index> loaded;
  for (Index e = 0; e < p.mesh.num_elements(); ++e)
    for (int k = 0; k < per; ++k)
      if (bc.value(per * e + k) != 0.0) {
        loaded.push_back(e);
        break;
      }
  const std::size_t per_chunk = std::size_t(192 / per);  // n x 192 of H and G at a time, whatever the element type
  for (std::size_t start = 0; start < loaded.size(); start += per_chunk) {
    const std::vector<Index> chunk(loaded.begin() + static_cast<std::ptrdiff_t>(start),
                                   loaded.begin() + static_cast<std::ptrdiff_t>(std::min(loaded.size(), start + per_chunk)));
    Eigen::MatrixXd H, G;
    assemble_columns(c, chunk, H, G);
    for (std::size_t col_element = 0; col_element < chunk.size(); ++col_element)
      for (int k = 0; k < per; ++k) {
        const Index dof = per * chunk[col_element] + k, col = per * static_cast<Index>(col_element) + k;
        if (bc.kind(dof) == BcKind::Traction)
          rhs.noalias() += G.col(col) * bc.value(dof);
        else
          rhs.noalias() -= H.col(col) * bc.value(dof);
      }
  }
  return rhs;
}

/// Owns the hmat-oss objects of one solve (the library's C API frees nothing by itself).
struct HmatObjects {
  hmat_interface_t hi{};
  hmat_clustering_algorithm_t* median = nullptr;
  hmat_clustering_algorithm_t* clustering = nullptr;
  hmat_cluster_tree_t* tree = nullptr;
  hmat_admissibility_t* admissibility = nullptr;
  hmat_compression_algorithm_t* compression = nullptr;
  hmat_matrix_t* matrix = nullptr;
  hmat_matrix_t* copy = nullptr;  // the assembled matrix, kept for the residual
  ~HmatObjects() {
    if (copy) hi.destroy(copy);
    if (matrix) hi.destroy(matrix);
    if (compression) hmat_delete_compression(compression);
    if (admissibility) hmat_delete_admissibility(admissibility);
    if (tree) hmat_delete_cluster_tree(tree);
    if (clustering) hmat_delete_clustering(clustering);
    if (median) hmat_delete_clustering(median);
  }
};

// Leaves of at most 120 unknowns (40 elements) and the standard admissibility with eta = 2: the
// settings the probe measured on organ meshes (docs/solvers.md).
constexpr int kLeafUnknowns = 120;
constexpr double kEta = 2.0;

/// What the backend refuses, whatever the problem's size: a tolerance outside its range.
void check_request(double compression_tolerance) {
  if (!(compression_tolerance >= 1e-12 && compression_tolerance <= 0.1))
    throw InvalidArgumentError("solver method hmatrix: the compression tolerance must lie in [1e-12, 0.1], got " +
                               std::to_string(compression_tolerance));
}

}  // namespace hmat_glue

using namespace hmat_glue;

bool hierarchical_backend_available() { return true; }

struct HierarchicalFactorization::Impl {
  Impl(std::shared_ptr<const ElastostaticProblem> owner, const ElastostaticProblem& p) : owned(std::move(owner)), problem(p) {
    if (p.elements == ElementType::Linear) {
      linear.emplace(p.mesh, p.material, p.quadrature);
      node_conditions = detail::linear_node_conditions(p);
    } else {
      assembler.emplace(p.mesh, p.material, p.quadrature);
    }
  }
  std::shared_ptr<const ElastostaticProblem> owned;  // null when the caller keeps the problem alive
  const ElastostaticProblem& problem;
  std::optional<InfluenceAssembler> assembler;     // constant elements
  std::optional<LinearInfluenceAssembler> linear;  // linear elements
  BoundaryConditions node_conditions;              // linear elements: the per-node conditions the unknowns follow
  SystemContext context;
  HmatObjects hm;
  HierarchicalResult result;
  std::mutex solve_mutex;  // one hmat-oss solve at a time (the cut worker and a refactorisation share snapshots)
};

// long: the set-up in the order hmat-oss needs it (scales, cluster tree, admissibility, compression,
// assembly, the copy, H-LU), each a few lines around one of its calls.
HierarchicalFactorization::HierarchicalFactorization(std::shared_ptr<const ElastostaticProblem> owned, const ElastostaticProblem& problem,
                                                     double compression_tolerance, bool keep_copy) {
  check_request(compression_tolerance);
  const Index E = problem.mesh.num_elements(), n = 3 * nodes_per_element(problem.elements) * E;
  impl_ = std::make_unique<Impl>(std::move(owned), problem);
  Impl& m = *impl_;
  HierarchicalResult& r = m.result;
  r.compression_tolerance = compression_tolerance;
  // hmat-oss's assembly and H-LU call BLAS on leaves of at most kLeafUnknowns rows: one BLAS thread
  // (bemsurg/blas_threads.hpp; on 2 cores a second one made the H-LU 1.37x slower).
  const BlasThreadCap one_blas_thread(1);
  const auto t_assembly = SteadyClock::now();
  const bool linear = m.linear.has_value();
  m.context.assembler = linear ? nullptr : &*m.assembler;
  m.context.linear = linear ? &*m.linear : nullptr;
  m.context.conditions = linear ? &m.node_conditions : &problem.boundary_conditions;
  m.context.column_unknowns = 3 * nodes_per_element(problem.elements);
  // Traction unknowns' columns (-G: about h / mu) scaled to the displacement unknowns' (H: about 1):
  // without it the unpivoted H-LU of a mixed system lost the answer (19 % off on a hung liver, issue 40).
  double h = 0.0;
  for (Index e = 0; e < E; ++e) h += std::sqrt(problem.mesh.area(e));
  h /= double(E);
  r.column_scale = problem.material.shear_modulus() / h;
  m.context.scale.assign(static_cast<std::size_t>(n), 1.0);
  for (Index k = 0; k < n; ++k)
    if (m.context.conditions->kind(k) != BcKind::Traction) m.context.scale[static_cast<std::size_t>(k)] = r.column_scale;
  // Each unknown at its collocation point: the element's centroid, or a linear element's node.
  std::vector<double> coordinates(static_cast<std::size_t>(3 * n));
  for (Index k = 0; k < n; ++k) {
    const Eigen::Vector3d c = linear ? m.linear->node(k / 3) : problem.mesh.centroid(k / 3);
    for (int d = 0; d < 3; ++d) coordinates[static_cast<std::size_t>(3 * k + d)] = c[d];
  }
  HmatObjects& hm = m.hm;
  hmat_init_default_interface(&hm.hi, HMAT_DOUBLE_PRECISION);
  hm.median = hmat_create_clustering_median();
  hm.clustering = hmat_create_clustering_max_dof(hm.median, kLeafUnknowns);
  hm.tree = hmat_create_cluster_tree(coordinates.data(), 3, static_cast<int>(n), hm.clustering);
  hm.admissibility = hmat_create_admissibility_standard(kEta);
  hm.compression = hmat_create_compression_aca_plus(compression_tolerance);
  if (!hm.tree || !hm.admissibility || !hm.compression)
    throw SolverError("solver method hmatrix: hmat-oss could not set up the cluster tree");
  hm.matrix = hm.hi.create_empty_hmatrix_admissibility(hm.tree, hm.tree, 0, hm.admissibility);
  if (!hm.matrix) throw SolverError("solver method hmatrix: hmat-oss could not create the matrix");
  // The H-LU's recompressions truncate to the same tolerance as the assembly (hmat-oss's default,
  // 1e-4, would cap a tighter tolerance's accuracy there).
  hm.hi.set_low_rank_epsilon(hm.matrix, compression_tolerance);
  hmat_assemble_context_t assemble;
  hmat_assemble_context_init(&assemble);
  assemble.compression = hm.compression;
  assemble.block_compute = compute_block;
  assemble.prepare = prepare_block;
  assemble.user_context = &m.context;
  assemble.progress = nullptr;
  if (hm.hi.assemble_generic(hm.matrix, &assemble) != 0) throw SolverError("solver method hmatrix: the assembly failed in hmat-oss");
  r.assembly_seconds = seconds_since(t_assembly);
  hmat_info_t info{};
  hm.hi.get_info(hm.matrix, &info);
  r.stored_entries = info.compressed_size;
  r.dense_entries = info.uncompressed_size;
  r.compression_ratio = info.uncompressed_size > 0 ? double(info.compressed_size) / double(info.uncompressed_size) : 1.0;
  r.largest_rank = info.largest_rk_mem_rank;
  r.leaves_full = static_cast<int>(info.full_count);
  r.leaves_low_rank = static_cast<int>(info.rk_count);
  if (keep_copy) hm.copy = hm.hi.copy(hm.matrix);

  const auto t_factor = SteadyClock::now();
  hmat_factorization_context_t factor;
  hmat_factorization_context_init(&factor);
  factor.factorization = hmat_factorization_lu;
  factor.progress = nullptr;
  if (hm.hi.factorize_generic(hm.matrix, &factor) != 0) throw SolverError("solver method hmatrix: the H-LU factorisation failed");
  r.factorization_seconds = seconds_since(t_factor);
  hmat_info_t factored{};
  hm.hi.get_info(hm.matrix, &factored);
  r.factor_entries = factored.compressed_size;
}

Index HierarchicalFactorization::size() const { return static_cast<Index>(impl_->context.scale.size()); }

std::size_t HierarchicalFactorization::bytes() const {
  const Impl& m = *impl_;
  std::size_t copy_entries = 0;
  if (m.hm.copy) copy_entries = m.result.stored_entries;
  return (m.result.factor_entries + copy_entries + m.context.scale.size()) * sizeof(double);
}

void HierarchicalFactorization::release_copy() {
  if (impl_->hm.copy) impl_->hm.hi.destroy(impl_->hm.copy);
  impl_->hm.copy = nullptr;
}

Eigen::VectorXd HierarchicalFactorization::right_hand_side() const { return hmat_glue::right_hand_side(impl_->context, impl_->problem); }

void HierarchicalFactorization::g_columns(const std::vector<Index>& elements, Eigen::Ref<Eigen::MatrixXd> out) const {
  if (!impl_->assembler)  // a table's columns: tables take constant elements (docs/presolution.md)
    throw InvalidArgumentError(
        "HierarchicalFactorization::g_columns: pre-solution tables take constant elements; this problem has linear ones");
  const Index n = 3 * impl_->problem.mesh.num_elements();
  if (out.rows() != n || out.cols() != 3 * static_cast<Index>(elements.size()))
    throw InvalidArgumentError("HierarchicalFactorization::g_columns: the output is " + std::to_string(out.rows()) + " x " +
                               std::to_string(out.cols()) + ", expected " + std::to_string(n) + " x " +
                               std::to_string(3 * elements.size()));
  // 64 elements at a time (n x 192 of H and G each), as right_hand_side.
  for (std::size_t start = 0; start < elements.size(); start += 64) {
    const std::vector<Index> chunk(elements.begin() + static_cast<std::ptrdiff_t>(start),
                                   elements.begin() + static_cast<std::ptrdiff_t>(std::min(elements.size(), start + 64)));
    Eigen::MatrixXd H, G;
    impl_->assembler->assemble_columns(chunk, H, G);
    out.middleCols(3 * static_cast<Index>(start), G.cols()) = G;
  }
}

void HierarchicalFactorization::solve_in_place(Eigen::Ref<Eigen::MatrixXd> B) const {
  Impl& m = *impl_;
  if (B.rows() != size())
    throw SolverError("HierarchicalFactorization::solve_in_place: " + std::to_string(B.rows()) + " rows, expected " +
                      std::to_string(size()));
  if (B.cols() == 0) return;
  std::lock_guard<std::mutex> lock(m.solve_mutex);
  const auto t_solve = SteadyClock::now();
  // hmat-oss takes columns of exactly n rows: a block of a taller matrix (a cut's grown system) goes through a copy.
  Eigen::MatrixXd packed;
  double* data = B.data();
  if (B.outerStride() != B.rows()) {
    packed = B;
    data = packed.data();
  }
  if (m.hm.hi.solve_systems(m.hm.matrix, data, static_cast<int>(B.cols())) != 0)
    throw SolverError("solver method hmatrix: the H-LU solve failed");
  if (packed.size() > 0) B = packed;
  m.result.solve_seconds += seconds_since(t_solve);
  if (!B.allFinite())
    throw SolverError("solver method hmatrix: the solution is not finite (a singular system, or a compression tolerance too loose)");
  for (Index k = 0; k < B.rows(); ++k) B.row(k) *= m.context.scale[static_cast<std::size_t>(k)];
}

double HierarchicalFactorization::relative_residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x) const {
  const Impl& m = *impl_;
  if (!m.hm.copy) return 0.0;
  // The copy holds the scaled matrix A* S: apply it to S^-1 x.
  Eigen::VectorXd y = x;
  for (Index k = 0; k < y.size(); ++k) y(k) /= m.context.scale[static_cast<std::size_t>(k)];
  Eigen::VectorXd residual = b;
  double minus_one = -1.0, one = 1.0;
  if (m.hm.hi.gemv('N', &minus_one, m.hm.copy, y.data(), &one, residual.data(), 1) != 0) return 0.0;
  const double norm = b.norm();
  impl_->result.relative_residual = norm > 0.0 ? residual.norm() / norm : residual.norm();
  return impl_->result.relative_residual;
}

ElastostaticSolution solve_elastostatic_hierarchical(const ElastostaticProblem& problem, const LinearSolverOptions& options,
                                                     HierarchicalResult* result) {
  // Before check_before_solve: a request the backend refuses fails before any other work.
  check_request(options.compression_tolerance);
  const Index E = problem.mesh.num_elements(), n = 3 * nodes_per_element(problem.elements) * E;
  const bool linear = problem.elements == ElementType::Linear;
  MemoryNeed memory;
  memory.bytes = estimate_hierarchical_bytes(E, problem.elements);
  memory.refusal = [E, linear](double need, double limit) {
    return "the hierarchical solve of " + std::to_string(E) + (linear ? " linear" : "") + " elements needs about " + format_gib(need) +
           " (an estimate from the compression measured on organ meshes), more than " + format_gib(limit) + "; coarsen the mesh";
  };
  ElastostaticSolution out;
  out.report.element_type = problem.elements;
  out.report.elements = E;
  out.report.equations = n;
  out.report.warnings = check_before_solve(problem, memory, "solve_elastostatic_hierarchical");

  HierarchicalFactorization factors(problem, options.compression_tolerance, true);
  const auto t_rhs = SteadyClock::now();
  const Eigen::VectorXd rhs = factors.right_hand_side();
  const double rhs_seconds = seconds_since(t_rhs);
  Eigen::MatrixXd x = rhs;
  factors.solve_in_place(x);
  factors.relative_residual(rhs, x.col(0));
  HierarchicalResult r = factors.result();
  r.assembly_seconds += rhs_seconds;
  if (linear) {  // as the dense path: per-node values, and their means at the centroids
    out.nodes = recover_boundary_solution(detail::linear_node_conditions(problem), x.col(0));
    out.boundary = detail::centroid_values(out.nodes);
  } else {
    out.boundary = recover_boundary_solution(problem.boundary_conditions, x.col(0));
  }
  LinearSolveResult& s = out.report.solver;
  s.method = SolverMethod::Lu;
  s.preconditioner = PreconditionerKind::None;
  s.status = KrylovStatus::Converged;
  s.relative_residual = r.relative_residual;
  s.setup_seconds = r.factorization_seconds;
  s.solve_seconds = r.solve_seconds;
  out.report.assembly_seconds = r.assembly_seconds;
  if (result) *result = r;
  return out;
}

#endif

// Both builds: the public constructors delegate to the one that builds (or refuses, without hmat-oss).
HierarchicalFactorization::HierarchicalFactorization(const ElastostaticProblem& problem, double compression_tolerance, bool keep_copy)
    : HierarchicalFactorization(nullptr, problem, compression_tolerance, keep_copy) {}

HierarchicalFactorization::HierarchicalFactorization(std::shared_ptr<const ElastostaticProblem> problem, double compression_tolerance,
                                                     bool keep_copy)
    : HierarchicalFactorization(problem, owned_problem(problem), compression_tolerance, keep_copy) {}

HierarchicalFactorization::~HierarchicalFactorization() = default;
HierarchicalFactorization::HierarchicalFactorization(HierarchicalFactorization&&) noexcept = default;
HierarchicalFactorization& HierarchicalFactorization::operator=(HierarchicalFactorization&&) noexcept = default;

const HierarchicalResult& HierarchicalFactorization::result() const { return impl_->result; }

}  // namespace bemsurg
