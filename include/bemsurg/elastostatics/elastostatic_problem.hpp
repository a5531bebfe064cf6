// bemsurg/elastostatics/elastostatic_problem.hpp: the boundary value problem as one object, and the
// one check made before anything is assembled for it (docs/design.md §5, §6).
//
// Mesh, material, gravity, boundary conditions and quadrature travel together: solve_elastostatic
// solves a problem, GreensTable::compute tabulates a problem on a region, and both run
// check_before_solve first, so a solve and a table refuse the same inputs with the same words.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/element_types.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"

namespace bemsurg {

/// The whole boundary value problem: mesh, material, gravity (an acceleration; body force = density * gravity),
/// boundary conditions, quadrature options and the element type (docs/elements.md). solve_elastostatic solves it;
/// GreensTable::compute tabulates it on a region.
/// \ingroup elastostatics
struct ElastostaticProblem {
  TriangleMesh mesh;
  Material material;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // acceleration; body force = density * gravity
  BoundaryConditions boundary_conditions;             // per element: the kinds, and the values at the centroids
  QuadratureOptions quadrature;
  ElementType elements = ElementType::Constant;
  // Linear elements only, optional: the prescribed values at the collocation nodes, 3E x 3 (row 3e + k
  // for node k of element e; the kinds stay boundary_conditions'). Empty: every node takes its element's value.
  RowMatrixX3d node_values = RowMatrixX3d();
};

/// What a solve or a table will need at its peak, for check_before_solve: the estimate in bytes, the limit (0: 80 %
/// of physical memory, bemsurg/memory_budget.hpp) and the ResourceError's message for (need, limit).
/// \ingroup elastostatics
struct MemoryNeed {
  double bytes = 0.0;
  double limit_bytes = 0.0;
  std::function<std::string(double need, double limit)> refusal;
};

/// The closed connected surface components (by shared vertices; every edge shared by two of their
/// elements) on which no element has a traction component prescribed, each as {first element,
/// number of elements}. At a Poisson's ratio near 0.5 their tractions are fixed only up to a pressure
/// (docs/stability.md (a)): check_before_solve warns or refuses for them (kPoissonRatioWarning,
/// kPoissonRatioLimit in bemsurg/material.hpp).
std::vector<std::pair<Index, Index>> displacement_only_components(const TriangleMesh& mesh, const BoundaryConditions& bc);

/// The one check before a dense solve or a table, in this order: a mesh with elements (InvalidMeshError), the
/// material (InvalidMaterialError), finite gravity and a support that holds every body
/// (BoundaryConditionError, BoundaryConditions::require_supported), a nearly incompressible surface held by
/// displacement only (refused from kPoissonRatioLimit, warned from kPoissonRatioWarning), slivers (warned), the
/// memory estimate (ResourceError with `memory.refusal`'s message) and the quadrature's cost (ResourceError,
/// docs/design.md §4). `who` starts every message. Returns the warnings; nothing large is allocated.
std::vector<std::string> check_before_solve(const TriangleMesh& mesh, const Material& material, const Eigen::Vector3d& gravity,
                                            const BoundaryConditions& conditions, const QuadratureOptions& quadrature,
                                            const MemoryNeed& memory, const std::string& who);

/// The same for a whole problem.
inline std::vector<std::string> check_before_solve(const ElastostaticProblem& problem, const MemoryNeed& memory, const std::string& who) {
  return check_before_solve(problem.mesh, problem.material, problem.gravity, problem.boundary_conditions, problem.quadrature, memory, who);
}

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/elastostatics/impl/elastostatic_problem_impl.hpp"
#endif
