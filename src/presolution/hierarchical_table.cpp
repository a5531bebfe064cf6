// Implementation of bemsurg/presolution/hierarchical_table.hpp: the table's columns and base state
// as one multi-right-hand-side solve on the hierarchical backend's H-LU (library bemsurg_hmatrix).
#include "bemsurg/presolution/hierarchical_table.hpp"

#include <memory>
#include <string>
#include <utility>

#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

namespace {

/// compute_greens_table_hierarchical on a problem it shares (the factorisation kept for cuts owns it)
/// for a table whose mesh is `mesh` (null: the problem's own): a refactorisation keeps the cut's mesh
/// snapshot, which the cutter recognises by its address (cutting/cut_system_update.hpp).
GreensTable hierarchical_table_on(std::shared_ptr<const ElastostaticProblem> owned, std::shared_ptr<const TriangleMesh> mesh,
                                  const std::vector<Index>& region, const LinearSolverOptions& options, HierarchicalResult* result,
                                  bool for_cuts) {
  const ElastostaticProblem& problem = *owned;
  if (!hierarchical_backend_available()) solve_elastostatic_hierarchical(problem, options);  // throws, saying what is missing
  GreensTable::require_conditions_for(problem.boundary_conditions, problem.mesh);
  std::vector<Index> elements = GreensTable::resolve_region(problem.boundary_conditions, region);
  const Index E = problem.mesh.num_elements(), n = 3 * E, R = static_cast<Index>(elements.size());
  // The problem's one check (as GreensTable::compute runs it), with the hierarchical estimate (which
  // counts a copy of the compressed matrix, kept only when `result` is asked for) plus the table.
  MemoryNeed memory;
  memory.bytes = estimate_hierarchical_bytes(E) + 8.0 * double(n) * double(3 * R + 1);
  memory.refusal = [E, n, R](double need, double limit) {
    return "the hierarchical precomputation for " + std::to_string(E) + " elements with a region of " + std::to_string(R) +
           " elements needs about " + format_gib(need) + " (table: " + format_gib(8.0 * double(n) * 3.0 * double(R)) +
           "), more than the limit of " + format_gib(limit) + "; restrict the region to where tools act, or coarsen the mesh away from it";
  };
  std::vector<std::string> warnings = check_before_solve(problem, memory, "GreensTable");

  // The assembled copy (the compressed matrix again) only when the caller asks for the result,
  // whose relative_residual is the base state's; the commands do not. A table kept for cuts owns
  // its problem.
  auto factorization = std::make_shared<HierarchicalFactorization>(owned, options.compression_tolerance, result != nullptr);
  HierarchicalFactorization& factors = *factorization;
  PrecomputeTimings timings;
  timings.factorization_seconds = factors.result().factorization_seconds;
  const auto t_rhs = SteadyClock::now();
  Eigen::MatrixXd X(n, 3 * R + 1);
  factors.g_columns(elements, X.leftCols(3 * R));
  const Eigen::VectorXd rhs = factors.right_hand_side();
  X.col(3 * R) = rhs;
  timings.assembly_seconds = factors.result().assembly_seconds + seconds_since(t_rhs);
  const auto t_solve = SteadyClock::now();
  factors.solve_in_place(X);
  timings.table_seconds = seconds_since(t_solve);
  factors.relative_residual(rhs, X.col(3 * R));
  factors.release_copy();
  if (result) *result = factors.result();
  KeptFactorization kept;
  if (for_cuts) {
    kept.factors = factorization;
    kept.rhs = rhs;
    const LinearSolverOptions solver = options;
    kept.recompute = [solver](std::shared_ptr<const TriangleMesh> mesh, const Material& material, const BoundaryConditions& base,
                              const Eigen::Vector3d& gravity, const QuadratureOptions& quadrature, const std::vector<Index>& cells) {
      auto p = std::make_shared<ElastostaticProblem>();
      p->mesh = *mesh;
      p->material = material;
      p->boundary_conditions = base;
      p->gravity = gravity;
      p->quadrature = quadrature;
      return hierarchical_table_on(std::move(p), std::move(mesh), cells, solver, nullptr, true);
    };
  }
  factorization.reset();                                                       // kept.factors holds it when kept; freed here otherwise
  if (!mesh) mesh = std::shared_ptr<const TriangleMesh>(owned, &owned->mesh);  // one copy for the table and the factorisation
  return GreensTable::from_solution(std::move(mesh), problem, std::move(elements), std::move(X), SolverBackend::HMatrix,
                                    options.compression_tolerance, std::move(warnings), timings, std::move(kept));
}

}  // namespace

GreensTable compute_greens_table_hierarchical(const ElastostaticProblem& problem, const std::vector<Index>& region,
                                              const LinearSolverOptions& options, HierarchicalResult* result, bool for_cuts) {
  return hierarchical_table_on(std::make_shared<const ElastostaticProblem>(problem), nullptr, region, options, result, for_cuts);
}

GreensTable compute_greens_table_hierarchical(std::shared_ptr<const TriangleMesh> mesh, const ElastostaticProblem& problem,
                                              const std::vector<Index>& region, const LinearSolverOptions& options,
                                              HierarchicalResult* result, bool for_cuts) {
  if (!mesh || mesh->num_elements() != problem.mesh.num_elements() || mesh->num_vertices() != problem.mesh.num_vertices())
    throw InvalidArgumentError("compute_greens_table_hierarchical: the shared mesh is not the problem's mesh");
  return hierarchical_table_on(std::make_shared<const ElastostaticProblem>(problem), std::move(mesh), region, options, result, for_cuts);
}

}  // namespace bemsurg
