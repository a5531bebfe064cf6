// Implementation of bemsurg/elastostatic_solver.hpp: validate, check memory, assemble, swap
// columns, solve.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/quadrature/quadrature_cost.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

BEMSURG_INLINE double estimate_elastostatic_bytes(Index num_elements) {
  const double n = 3.0 * double(num_elements);
  // Peak: H and G while the system is built (A* is built in H's storage, G is released before
  // the solve, so the LU copy or the Krylov workspace then fits in its place), plus O(n) vectors.
  return 8.0 * (2.0 * n * n + 8.0 * n);
}

BEMSURG_INLINE std::vector<std::pair<Index, Index>> displacement_only_components(const TriangleMesh& mesh, const BoundaryConditions& bc) {
  std::vector<Index> parent(static_cast<std::size_t>(mesh.num_vertices()));
  std::iota(parent.begin(), parent.end(), Index(0));
  auto root = [&parent](Index v) {
    while (parent[std::size_t(v)] != v) v = parent[std::size_t(v)] = parent[std::size_t(parent[std::size_t(v)])];
    return v;
  };
  const RowMatrixX3i& f = mesh.faces();
  for (Index e = 0; e < f.rows(); ++e)
    for (int c = 1; c < 3; ++c) parent[std::size_t(root(f(e, c)))] = root(f(e, 0));
  std::vector<Index> first(parent.size(), -1), count(parent.size(), 0);
  std::vector<char> excluded(parent.size(), 0);  // a traction component prescribed, or not closed
  for (Index e = 0; e < f.rows(); ++e) {
    const std::size_t r = std::size_t(root(f(e, 0)));
    if (first[r] < 0) first[r] = e;
    ++count[r];
    for (int c = 0; c < 3; ++c) excluded[r] |= bc.kind(3 * e + c) == BcKind::Traction ? 1 : 0;
  }
  // Only a closed component (every edge shared by exactly two of its elements) carries the pressure
  // mode: an open patch held by displacement (a clamp, or triangles whose vertices are not shared) does not.
  std::vector<std::pair<std::int64_t, Index>> edges;  // (edge key, root)
  edges.reserve(std::size_t(3 * f.rows()));
  for (Index e = 0; e < f.rows(); ++e)
    for (int c = 0; c < 3; ++c) {
      const std::int64_t a = f(e, c), b = f(e, (c + 1) % 3);
      edges.emplace_back(std::min(a, b) * mesh.num_vertices() + std::max(a, b), root(f(e, 0)));
    }
  std::sort(edges.begin(), edges.end());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    if (j - i != 2) excluded[std::size_t(edges[i].second)] = 1;  // open or non-manifold: not counted
    i = j;
  }
  std::vector<std::pair<Index, Index>> out;
  for (std::size_t r = 0; r < parent.size(); ++r)
    if (count[r] > 0 && !excluded[r]) out.emplace_back(first[r], count[r]);
  return out;
}

namespace detail {

/// Nearly incompressible material and a surface component held by displacement only (docs/stability.md
/// (a), kPoissonRatioWarning and kPoissonRatioLimit in bemsurg/material.hpp): refuses at the limit,
/// warns from the warning threshold; a component with some traction prescribed is not affected.
BEMSURG_INLINE void check_nearly_incompressible(const ElastostaticProblem& problem, std::vector<std::string>& warnings) {
  const double nu = problem.material.poisson_ratio;
  if (nu < kPoissonRatioWarning) return;
  const auto held = displacement_only_components(problem.mesh, problem.boundary_conditions);
  if (held.empty()) return;
  const std::string where = "the surface component of element " + std::to_string(held.front().first) + " (" +
                            std::to_string(held.front().second) + " elements" +
                            (held.size() > 1 ? ", and " + std::to_string(held.size() - 1) + " more" : std::string()) +
                            ") has its displacement prescribed on every element, so its tractions are fixed only up to a pressure "
                            "whose error grows as 1/(1 - 2 nu) (docs/stability.md (a))";
  if (nu >= kPoissonRatioLimit)
    throw InvalidMaterialError("material: poisson_ratio " + number_text(nu) + " is at or above " + number_text(kPoissonRatioLimit) +
                               ", the limit for this problem: " + where +
                               "; lower poisson_ratio or prescribe the traction on part of that surface");
  warnings.push_back("poisson_ratio " + number_text(nu) + " is at or above " + number_text(kPoissonRatioWarning) + ": " + where +
                     "; expect the tractions there to be less accurate (refused from " + number_text(kPoissonRatioLimit) + ")");
}

}  // namespace detail

BEMSURG_INLINE ElastostaticSolution solve_elastostatic(const ElastostaticProblem& problem, const LinearSolverOptions& solver) {
  problem.material.validate();
  if (!problem.gravity.allFinite()) throw BoundaryConditionError("gravity must be finite");
  problem.boundary_conditions.require_supported(problem.mesh);
  std::vector<std::string> warnings;
  detail::check_nearly_incompressible(problem, warnings);
  // Slivers cost the traction on them accuracy (docs/stability.md, study (c)).
  if (std::string w = sliver_warning(problem.mesh); !w.empty()) warnings.push_back(std::move(w));

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
  out.report.warnings = std::move(warnings);

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

  Eigen::VectorXd x;
  try {
    x = solve_linear_system(system.matrix, system.rhs, solver, out.report.solver, &problem.mesh);
  } catch (const SolverError& e) {  // a failed solve still says what it was warned about (no report reaches the caller)
    if (out.report.warnings.empty()) throw;
    std::string text = e.what();
    for (const std::string& w : out.report.warnings) text += "; warning: " + w;
    throw SolverError(text);
  }
  out.boundary = recover_boundary_solution(problem.boundary_conditions, x);
  return out;
}

}  // namespace bemsurg
