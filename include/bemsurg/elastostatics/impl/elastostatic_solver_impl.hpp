// Implementation of bemsurg/elastostatics/elastostatic_solver.hpp: validate, check memory, assemble, swap
// columns, solve.
#pragma once

#include "bemsurg/config.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <numeric>
#include <string>
#include <vector>

#include "bemsurg/assembly/node_influence_assembler.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/quadrature/quadrature_cost.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

BEMSURG_INLINE double estimate_elastostatic_bytes(Index num_elements, ElementType type) {
  const double n = 3.0 * double(nodes_per_element(type)) * double(num_elements);
  // Peak: H and G while the system is built (A* is built in H's storage, G is released before
  // the solve, so the LU copy or the Krylov workspace then fits in its place), plus O(n) vectors.
  return 8.0 * (2.0 * n * n + 8.0 * n);
}

namespace detail {

/// The per-node boundary conditions of a linear-element problem (3E "nodes", node 3e + k): the kinds
/// of element e, the values of problem.node_values (or the element's value where it is empty).
BEMSURG_INLINE BoundaryConditions linear_node_conditions(const ElastostaticProblem& problem) {
  const BoundaryConditions& bc = problem.boundary_conditions;
  const Index E = bc.num_elements();
  if (problem.node_values.size() != 0 && problem.node_values.rows() != 3 * E)
    throw BoundaryConditionError("node_values has " + std::to_string(problem.node_values.rows()) +
                                 " rows; linear elements need 3 per element (" + std::to_string(3 * E) + ")");
  BoundaryConditions nodes(3 * E);
  for (Index e = 0; e < E; ++e)
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) {
        const double v = problem.node_values.size() != 0 ? problem.node_values(3 * e + k, c) : bc.value(3 * e + c);
        if (!std::isfinite(v))
          throw BoundaryConditionError("element " + std::to_string(e) + ", node " + std::to_string(k) + ": prescribed value is not finite");
        nodes.prescribe_component(3 * e + k, c, bc.kind(3 * e + c), v);
      }
  return nodes;
}

/// Assembles and swaps columns for either element type; `node_bc` is the per-node conditions for
/// linear elements (unused for constant ones).
BEMSURG_INLINE LinearSystem build_elastostatic_system(const ElastostaticProblem& problem, const BoundaryConditions& node_bc,
                                                      ElastostaticResult& report) {
  LinearSystem system;
  auto t0 = SteadyClock::now();
  Eigen::VectorXd gravity;  // H, G and the self-weight term in one pass over the element pairs
  InfluenceMatrices hg;
  if (problem.elements == ElementType::Linear)
    hg = LinearInfluenceAssembler(problem.mesh, problem.material, problem.quadrature).assemble(problem.gravity, gravity);
  else
    hg = InfluenceAssembler(problem.mesh, problem.material, problem.quadrature).assemble(problem.gravity, gravity);
  report.assembly_seconds = seconds_since(t0);
  const BoundaryConditions& bc = problem.elements == ElementType::Linear ? node_bc : problem.boundary_conditions;
  t0 = SteadyClock::now();
  system.rhs = build_right_hand_side(hg, bc, gravity);  // needs H: before A* takes it
  system.matrix = build_system_matrix_in_place(hg, bc);
  report.system_seconds = seconds_since(t0);
  return system;  // G is freed here, before the solver allocates
}

/// Centroid values (the mean of the three nodes' values: N_k(centroid) = 1/3) from per-node ones.
BEMSURG_INLINE BoundarySolution centroid_values(const BoundarySolution& nodes) {
  const Index E = nodes.displacement.rows() / 3;
  BoundarySolution out{RowMatrixX3d(E, 3), RowMatrixX3d(E, 3)};
  for (Index e = 0; e < E; ++e) {
    out.displacement.row(e) = (nodes.displacement.row(3 * e) + nodes.displacement.row(3 * e + 1) + nodes.displacement.row(3 * e + 2)) / 3.0;
    out.traction.row(e) = (nodes.traction.row(3 * e) + nodes.traction.row(3 * e + 1) + nodes.traction.row(3 * e + 2)) / 3.0;
  }
  return out;
}

}  // namespace detail

BEMSURG_INLINE ElastostaticSolution solve_elastostatic(const ElastostaticProblem& problem, const LinearSolverOptions& solver) {
  if (solver.backend != SolverBackend::Dense)
    throw SolverError(std::string("solve_elastostatic is the dense backend; the solver asks for ") + to_string(solver.backend) +
                      (solver.backend == SolverBackend::ScaLapack
                           ? ": call solve_elastostatic_scalapack (bemsurg/distributed/scalapack_solver.hpp, bemsurg::distributed)"
                           : ": call solve_elastostatic_hierarchical (bemsurg/elastostatics/hierarchical_solver.hpp, bemsurg::hmatrix)"));
  const Index E = problem.mesh.num_elements();
  const Index unknowns = 3 * nodes_per_element(problem.elements) * E;
  MemoryNeed memory;
  memory.bytes = estimate_elastostatic_bytes(E, problem.elements);
  memory.refusal = [&problem, E, unknowns](double need, double limit) {
    const double physical = physical_memory_bytes();
    return "the dense solve of " + std::to_string(E) + " elements (" +
           (problem.elements == ElementType::Linear ? std::string("linear, 9 unknowns each: ") : std::string()) + std::to_string(unknowns) +
           " equations) needs about " + format_gib(need) + " (H and G, each " + format_gib(8.0 * double(unknowns) * double(unknowns)) +
           "), more than " + format_gib(limit) + " (80 % of this machine's " +
           (physical > 0.0 ? format_gib(physical) : std::string("unknown")) + " of physical memory); coarsen the mesh";
  };
  std::vector<std::string> warnings = check_before_solve(problem, memory, "solve_elastostatic");
  const bool linear = problem.elements == ElementType::Linear;
  const BoundaryConditions node_bc = linear ? detail::linear_node_conditions(problem) : BoundaryConditions();

  ElastostaticSolution out;
  out.report.element_type = problem.elements;
  out.report.elements = E;
  out.report.equations = unknowns;
  out.report.warnings = std::move(warnings);

  LinearSystem system = detail::build_elastostatic_system(problem, node_bc, out.report);
  // The near-field preconditioner reads one element per 3 unknowns: for linear elements, the proxy
  // mesh of each element's corner children, whose centroids are the nodes (docs/elements.md).
  const TriangleMesh proxy = linear ? linear_node_proxy_mesh(problem.mesh) : TriangleMesh();
  const TriangleMesh* geometry = linear ? &proxy : &problem.mesh;
  Eigen::VectorXd x;
  try {
    x = solve_linear_system(system.matrix, system.rhs, solver, out.report.solver, geometry);
  } catch (const SolverError& e) {  // a failed solve still says what it was warned about (no report reaches the caller)
    if (out.report.warnings.empty()) throw;
    std::string text = e.what();
    for (const std::string& w : out.report.warnings) text += "; warning: " + w;
    throw SolverError(text);
  }
  if (!linear) {
    out.boundary = recover_boundary_solution(problem.boundary_conditions, x);
    return out;
  }
  out.nodes = recover_boundary_solution(node_bc, x);
  out.boundary = detail::centroid_values(out.nodes);
  return out;
}

// Timed once per process (a function-local static: one instance in every program, header-only or not).
BEMSURG_INLINE double estimate_elastostatic_seconds(Index num_elements) {
  static std::once_flag once;
  static double pair_seconds = 0.0, flop_seconds = 0.0;
  std::call_once(once, [] {
    using Clock = std::chrono::steady_clock;
    const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 2);  // 320 elements
    const InfluenceAssembler assembler(sphere, Material{});
    auto t0 = Clock::now();
    const InfluenceMatrices hg = assembler.assemble();
    const double E = double(sphere.num_elements());
    pair_seconds = std::chrono::duration<double>(Clock::now() - t0).count() / (E * E);
    t0 = Clock::now();
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(hg.H);
    const double n = double(hg.H.rows());
    flop_seconds = std::chrono::duration<double>(Clock::now() - t0).count() / (2.0 / 3.0 * n * n * n);
  });
  const double E = double(num_elements), n = 3.0 * E;
  return pair_seconds * E * E + flop_seconds * 2.0 / 3.0 * n * n * n;
}

}  // namespace bemsurg
