// Implementation of bemsurg/elastostatic_solver.hpp: validate, check memory, assemble, swap
// columns, solve.
#pragma once

#include "bemsurg/config.hpp"

#include <chrono>
#include <string>

#include "bemsurg/memory_budget.hpp"
#include "bemsurg/quadrature/quadrature_cost.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

BEMSURG_INLINE double estimate_elastostatic_bytes(Index num_elements) {
  const double n = 3.0 * double(num_elements);
  // Peak: H and G while the system is built (A* is built in H's storage, G is released before
  // the solve, so the LU copy or the Krylov workspace then fits in its place), plus O(n) vectors.
  return 8.0 * (2.0 * n * n + 8.0 * n);
}

BEMSURG_INLINE ElastostaticSolution solve_elastostatic(const ElastostaticProblem& problem, const LinearSolverOptions& solver) {
  problem.material.validate();
  if (!problem.gravity.allFinite()) throw BoundaryConditionError("gravity must be finite");
  problem.boundary_conditions.require_supported(problem.mesh);

  const Index E = problem.mesh.num_elements();
  const double need = estimate_elastostatic_bytes(E);
  const double limit = default_memory_limit_bytes();
  if (need > limit) {
    const double physical = physical_memory_bytes();
    throw ResourceError("solve_elastostatic: the dense solve of " + std::to_string(E) + " elements (" + std::to_string(3 * E) +
                        " equations) needs about " + format_gib(need) + " (H and G, each " + format_gib(8.0 * 9.0 * double(E) * double(E)) +
                        "), more than " + format_gib(limit) + " (80 % of this machine's " +
                        (physical > 0.0 ? format_gib(physical) : std::string("unknown")) + " of physical memory); coarsen the mesh");
  }
  // The quadrature options' cost, estimated before the work (docs/design.md §4, §10).
  require_assembly_quadrature_within(problem.mesh, problem.quadrature, "solve_elastostatic");

  ElastostaticSolution out;
  out.report.elements = E;
  out.report.equations = problem.mesh.num_dofs();

  LinearSystem system;
  {
    auto t0 = SteadyClock::now();
    const InfluenceAssembler assembler(problem.mesh, problem.material, problem.quadrature);
    Eigen::VectorXd gravity;  // H, G and the self-weight term in one pass over the element pairs
    InfluenceMatrices hg = assembler.assemble(problem.gravity, gravity);
    out.report.assembly_seconds = seconds_since(t0);

    t0 = SteadyClock::now();
    system.rhs = build_right_hand_side(hg, problem.boundary_conditions, gravity);  // needs H: before A* takes it
    system.matrix = build_system_matrix_in_place(hg, problem.boundary_conditions);
    out.report.system_seconds = seconds_since(t0);
  }  // G is freed here, before the solver allocates

  const Eigen::VectorXd x = solve_linear_system(system.matrix, system.rhs, solver, out.report.solver, &problem.mesh);
  out.boundary = recover_boundary_solution(problem.boundary_conditions, x);
  return out;
}

}  // namespace bemsurg
