// tests/support/convergence.hpp: observed orders of convergence, and the row of elements along the
// edges of a box mesh. Constant elements converge more slowly in that row, and its error dominates
// a box's total, so tests assert its order separately from the rest's.
#pragma once

#include <cmath>
#include <functional>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

namespace bemsurg_test {

/// True for the elements with a vertex on an edge of the mesh's bounding box (a vertex with at least
/// two coordinates on the box's bounds): the row of elements along the box's edges and corners.
inline std::function<bool(bemsurg::Index)> box_edge_row(const bemsurg::TriangleMesh& mesh) {
  Eigen::Vector3d lo = mesh.vertex(0), hi = mesh.vertex(0);
  for (bemsurg::Index v = 1; v < mesh.num_vertices(); ++v) {
    lo = lo.cwiseMin(mesh.vertex(v));
    hi = hi.cwiseMax(mesh.vertex(v));
  }
  const double tol = 1e-9 * (hi - lo).norm();
  std::vector<char> on_edge(static_cast<std::size_t>(mesh.num_vertices()));
  for (bemsurg::Index v = 0; v < mesh.num_vertices(); ++v) {
    int bounds = 0;
    for (int c = 0; c < 3; ++c) bounds += (std::abs(mesh.vertex(v)(c) - lo(c)) < tol || std::abs(mesh.vertex(v)(c) - hi(c)) < tol) ? 1 : 0;
    on_edge[static_cast<std::size_t>(v)] = bounds >= 2;
  }
  std::vector<char> row(static_cast<std::size_t>(mesh.num_elements()));
  for (bemsurg::Index e = 0; e < mesh.num_elements(); ++e)
    for (int k = 0; k < 3; ++k)
      if (on_edge[static_cast<std::size_t>(mesh.faces()(e, k))]) row[static_cast<std::size_t>(e)] = 1;
  return [row](bemsurg::Index e) { return row[static_cast<std::size_t>(e)] != 0; };
}

/// Observed order p of an error e ~ h^p from two levels.
inline double observed_order(double e_coarse, double e_fine, double h_coarse, double h_fine) {
  return std::log(e_coarse / e_fine) / std::log(h_coarse / h_fine);
}

/// Relative L2 errors of an exact-trace problem (verification::solve_exact_trace_problem) over all
/// elements, over the box-edge row and over the rest.
struct SplitErrors {
  bemsurg::verification::RelativeErrors all, edge, rest;
};

inline SplitErrors solve_split(const bemsurg::TriangleMesh& mesh, const bemsurg::Material& m,
                               const bemsurg::verification::ElasticField& field,
                               const std::function<bool(bemsurg::Index)>& displacement_prescribed,
                               const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero()) {
  using namespace bemsurg::verification;
  bemsurg::BoundarySolution s;
  SplitErrors out;
  out.all = solve_exact_trace_problem(mesh, m, field, displacement_prescribed, gravity, &s);
  const bemsurg::BoundaryConditions bc = exact_trace_conditions(mesh, field, displacement_prescribed);
  const bemsurg::BoundarySolution exact = exact_traces(mesh, field);
  const auto edge = box_edge_row(mesh);
  out.edge = relative_l2_errors(mesh, bc, s, exact, edge);
  out.rest = relative_l2_errors(mesh, bc, s, exact, [&](bemsurg::Index e) { return !edge(e); });
  return out;
}

}  // namespace bemsurg_test
