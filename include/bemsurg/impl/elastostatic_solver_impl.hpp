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

#include "bemsurg/assembly/node_influence_assembler.hpp"
#include "bemsurg/memory_budget.hpp"
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
  problem.material.validate();
  if (!problem.gravity.allFinite()) throw BoundaryConditionError("gravity must be finite");
  problem.boundary_conditions.require_supported(problem.mesh);
  std::vector<std::string> warnings;
  detail::check_nearly_incompressible(problem, warnings);
  // Slivers cost the traction on them accuracy (docs/stability.md, study (c)).
  if (std::string w = sliver_warning(problem.mesh); !w.empty()) warnings.push_back(std::move(w));

  const Index E = problem.mesh.num_elements();
  const Index unknowns = 3 * nodes_per_element(problem.elements) * E;
  const double need = estimate_elastostatic_bytes(E, problem.elements);
  const double limit = default_memory_limit_bytes();
  if (need > limit) {
    const double physical = physical_memory_bytes();
    throw ResourceError("solve_elastostatic: the dense solve of " + std::to_string(E) + " elements (" +
                        (problem.elements == ElementType::Linear ? std::string("linear, 9 unknowns each: ") : std::string()) +
                        std::to_string(unknowns) + " equations) needs about " + format_gib(need) + " (H and G, each " +
                        format_gib(8.0 * double(unknowns) * double(unknowns)) + "), more than " + format_gib(limit) +
                        " (80 % of this machine's " + (physical > 0.0 ? format_gib(physical) : std::string("unknown")) +
                        " of physical memory); coarsen the mesh");
  }
  // The quadrature options' cost, estimated before the work (docs/design.md §4, §10).
  require_assembly_quadrature_within(problem.mesh, problem.quadrature, "solve_elastostatic");
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

}  // namespace bemsurg
