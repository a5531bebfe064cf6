// Implementation of bemsurg/elastostatic_solver.hpp: validate, assemble, swap columns, solve.
#include "bemsurg/elastostatic_solver.hpp"

#include <chrono>

namespace bemsurg {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

ElastostaticSolution solve_elastostatic(const ElastostaticProblem& problem, const LinearSolverSettings& solver) {
  problem.material.validate();
  if (!problem.gravity.allFinite()) throw BoundaryConditionError("gravity must be finite");
  problem.boundary_conditions.require_supported(problem.mesh);

  ElastostaticSolution out;
  out.report.elements = problem.mesh.num_elements();
  out.report.equations = problem.mesh.num_dofs();

  auto t0 = std::chrono::steady_clock::now();
  const InfluenceAssembler assembler(problem.mesh, problem.material, problem.quadrature);
  const InfluenceMatrices hg = assembler.assemble();
  const Eigen::VectorXd gravity = assembler.gravity_vector(problem.gravity);
  out.report.assembly_seconds = seconds_since(t0);

  t0 = std::chrono::steady_clock::now();
  const LinearSystem system = build_linear_system(hg, problem.boundary_conditions, gravity);
  out.report.system_seconds = seconds_since(t0);

  const Eigen::VectorXd x = solve_linear_system(system.matrix, system.rhs, solver, out.report.solver, &problem.mesh);
  out.boundary = recover_boundary_solution(problem.boundary_conditions, x);
  return out;
}

}  // namespace bemsurg
