// bemsurg/mesh/mesh_quality.hpp: shape and grading figures of a triangle surface (docs/graded.md).
//
// Collocation with constant elements (docs/design.md §2, §4) is accurate when elements are close
// to equilateral (the near-singular quadrature and the centroid collocation both degrade with
// slivers) and when neighbouring elements have similar sizes (an abrupt jump in size is an
// abrupt jump in the resolution of the traction). These are the two figures the graded remesher
// promises and its tests check.
#pragma once

#include <algorithm>
#include <cmath>

#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Shape and grading figures of a triangle surface (measure_mesh_quality): smallest angles and neighbouring element
/// size ratios, the two figures the graded remesher promises and its tests check.
struct MeshQuality {
  Index elements = 0;
  /// Smallest interior angle of any element, degrees (60 for equilateral elements).
  double min_angle_degrees = 0.0;
  /// Mean over elements of each element's smallest angle, degrees.
  double mean_min_angle_degrees = 0.0;
  /// Fraction of elements whose smallest angle is below 20 degrees.
  double fraction_below_20_degrees = 0.0;
  /// Element size h = mean edge length; the largest h_a / h_b over pairs sharing an edge.
  double max_neighbour_size_ratio = 0.0;
  /// The 99th percentile of that ratio over the pairs (the few worst pairs aside).
  double p99_neighbour_size_ratio = 0.0;
  double min_size = 0.0;
  double max_size = 0.0;
};

/// Element size used by MeshQuality: the mean of the three edge lengths (mean_edge_length).
inline double element_size(const TriangleMesh& mesh, Index e) {
  const auto c = mesh.corners(e);
  return mean_edge_length(c[0], c[1], c[2]);
}

inline MeshQuality measure_mesh_quality(const TriangleMesh& mesh) {
  MeshQuality q;
  q.elements = mesh.num_elements();
  if (q.elements == 0) return q;
  double min_angle = 180.0, sum_min = 0.0;
  Index below = 0;
  Eigen::VectorXd h(q.elements);
  for (Index e = 0; e < q.elements; ++e) {
    const auto c = mesh.corners(e);
    const double smallest = smallest_angle_degrees(c[0], c[1], c[2]);
    min_angle = std::min(min_angle, smallest);
    sum_min += smallest;
    if (smallest < 20.0) ++below;
    h(e) = element_size(mesh, e);
  }
  q.min_angle_degrees = min_angle;
  q.mean_min_angle_degrees = sum_min / static_cast<double>(q.elements);
  q.fraction_below_20_degrees = static_cast<double>(below) / static_cast<double>(q.elements);
  q.min_size = h.minCoeff();
  q.max_size = h.maxCoeff();
  const MeshTopology topo(mesh);
  std::vector<double> ratios;
  ratios.reserve(static_cast<std::size_t>(topo.num_edges()));
  for (const MeshEdge& edge : topo.edges()) {
    if (edge.faces.size() != 2) continue;
    const double a = h(edge.faces[0].face), b = h(edge.faces[1].face);
    ratios.push_back(std::max(a, b) / std::min(a, b));
  }
  if (!ratios.empty()) {
    std::sort(ratios.begin(), ratios.end());
    q.max_neighbour_size_ratio = ratios.back();
    q.p99_neighbour_size_ratio = ratios[static_cast<std::size_t>(0.99 * static_cast<double>(ratios.size() - 1))];
  }
  return q;
}

}  // namespace bemsurg
