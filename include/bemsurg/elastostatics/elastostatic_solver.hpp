// bemsurg/elastostatics/elastostatic_solver.hpp: the whole boundary value problem in one call: the
// problem (elastostatic_problem.hpp) in; surface displacements and tractions out, with timings.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/element_types.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/solvers/linear_solve.hpp"

namespace bemsurg {

/// Size and timings of one solve_elastostatic call: elements, equations, seconds spent assembling and building the
/// system, and the linear solver's summary.
/// \ingroup elastostatics
struct ElastostaticResult {
  ElementType element_type = ElementType::Constant;
  Index elements = 0;
  Index equations = 0;
  double assembly_seconds = 0.0;  // H, G and gravity
  double system_seconds = 0.0;    // column swap into A* and the right-hand side
  LinearSolveResult solver;
  // What the solve did near a stability limit (docs/stability.md): e.g. a ratio of Poisson close to
  // 0.5 or slivers in the mesh. Empty when nothing applies; the CLI prints each and report.json lists them.
  std::vector<std::string> warnings;
};
/// Deprecated name (before 0.2), kept one minor version: use ElastostaticResult.
using ElastostaticReport [[deprecated("renamed to ElastostaticResult in bemsurg 0.2")]] = ElastostaticResult;

/// What solve_elastostatic returns: the displacement and traction of every element (for linear elements the values
/// at the centroids, interpolated), per collocation node for linear elements, and the report of the run.
/// \ingroup elastostatics
struct ElastostaticSolution {
  BoundarySolution boundary;  // E rows
  BoundarySolution nodes;     // linear elements: 3E rows, row 3e + k = node k of element e; empty for constant
  ElastostaticResult report;
};

/// Bytes solve_elastostatic needs at its peak for a mesh of `num_elements`: H and G (n = 3E unknowns
/// for constant elements, 9E for linear; 2 n^2 doubles) plus a few vectors.
double estimate_elastostatic_bytes(Index num_elements, ElementType type = ElementType::Constant);

/// Estimated seconds of the dense solve (assembly and LU) of `num_elements` constant elements on
/// this machine: E^2 element pairs and (2/3)(3E)^3 flops at the rates of a small assembly (320
/// elements) and LU (960 equations) timed once per process (~0.05 s). An order of magnitude for
/// messages and reports (`bemsurg prepare`, docs/organs.md), not a benchmark.
double estimate_elastostatic_seconds(Index num_elements);

/// Runs the problem's one check (check_before_solve: material, gravity, support, a nearly
/// incompressible held surface, slivers, the memory estimate against 80 % of physical memory, the
/// quadrature's cost), assembles, solves. Throws InvalidMaterialError, BoundaryConditionError,
/// ResourceError (before allocating anything large) or SolverError with a message (a Krylov solve
/// that did not converge included, with the solve's warnings appended).
/// The mesh is not validated here (callers that read files run require_valid_mesh first).
ElastostaticSolution solve_elastostatic(const ElastostaticProblem& problem, const LinearSolverOptions& solver = LinearSolverOptions());

namespace detail {
/// The per-node conditions of a linear-element problem (3E nodes, node 3e + k): element e's kinds,
/// problem.node_values' values (or the element's where it is empty). BoundaryConditionError for a
/// node_values of the wrong size or a value that is not finite. Both backends' linear solves use it.
BoundaryConditions linear_node_conditions(const ElastostaticProblem& problem);
/// Centroid values (the mean of an element's three nodes: N_k(centroid) = 1/3) from per-node ones.
BoundarySolution centroid_values(const BoundarySolution& nodes);
}  // namespace detail

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/elastostatics/impl/elastostatic_solver_impl.hpp"
#endif
