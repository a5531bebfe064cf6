// Implementation of bemsurg/elastostatics/elastostatic_problem.hpp: the one check before a solve or a
// table (docs/design.md §5, §6; docs/robustness.md lists what is checked and the thresholds).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/quadrature/quadrature_cost.hpp"

namespace bemsurg {

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
BEMSURG_INLINE void check_nearly_incompressible(const TriangleMesh& mesh, const Material& material, const BoundaryConditions& conditions,
                                                std::vector<std::string>& warnings) {
  const double nu = material.poisson_ratio;
  if (nu < kPoissonRatioWarning) return;
  const auto held = displacement_only_components(mesh, conditions);
  if (held.empty()) return;
  const std::string where = "the surface component of element " + std::to_string(held.front().first) + " (" +
                            std::to_string(held.front().second) + " elements" +
                            (held.size() > 1 ? ", and " + std::to_string(held.size() - 1) + " more" : std::string()) +
                            ") has its displacement prescribed on every element, so its tractions are fixed only up to a pressure "
                            "whose error grows as 1/(1 - 2 nu) (docs/stability.md (a))";
  if (nu >= kPoissonRatioLimit)
    throw InvalidMaterialError("material: poisson_ratio " + number_text(nu) + " is at or above " + number_text(kPoissonRatioLimit) +
                               ", the limit for this problem: " + where +
                               "; lower poisson_ratio, or prescribe the traction on part of that surface (a mixed condition)");
  warnings.push_back("poisson_ratio " + number_text(nu) + " is at or above " + number_text(kPoissonRatioWarning) + ": " + where +
                     "; expect the tractions there to be less accurate (refused from " + number_text(kPoissonRatioLimit) + ")");
}

}  // namespace detail

BEMSURG_INLINE std::vector<std::string> check_before_solve(const TriangleMesh& mesh, const Material& material,
                                                           const Eigen::Vector3d& gravity, const BoundaryConditions& conditions,
                                                           const QuadratureOptions& quadrature, const MemoryNeed& memory,
                                                           const std::string& who) {
  if (mesh.num_elements() == 0) throw InvalidMeshError(who + ": the mesh has no elements");
  material.validate();
  if (!gravity.allFinite()) throw BoundaryConditionError(who + ": gravity must be finite");
  conditions.require_supported(mesh);
  std::vector<std::string> warnings;
  detail::check_nearly_incompressible(mesh, material, conditions, warnings);
  // Slivers cost the traction on them accuracy (docs/stability.md, study (c)).
  if (std::string w = sliver_warning(mesh); !w.empty()) warnings.push_back(std::move(w));
  const double limit = memory.limit_bytes > 0.0 ? memory.limit_bytes : default_memory_limit_bytes();
  if (memory.bytes > limit)
    throw ResourceError(who + ": " +
                        (memory.refusal ? memory.refusal(memory.bytes, limit)
                                        : "needs about " + format_gib(memory.bytes) + ", more than " + format_gib(limit)));
  // The quadrature options' cost, estimated before the work (docs/design.md §4, §10).
  require_assembly_quadrature_within(mesh, quadrature, who);
  return warnings;
}

}  // namespace bemsurg
