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
#include <limits>
#include <string>

#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

/// Shape and grading figures of a triangle surface (measure_mesh_quality): smallest angles and neighbouring element
/// size ratios, the two figures the graded remesher promises and its tests check.
/// \ingroup mesh
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
  /// The largest aspect_ratio of any element (1 for equilateral elements).
  double max_aspect_ratio = 0.0;
};

/// Aspect ratio of the triangle (a, b, c): longest edge / shortest altitude, scaled by sqrt(3)/2 so
/// that an equilateral triangle has 1; a right isosceles one has 1.73, a needle of legs L and
/// eps << L about 0.87 L / eps, a flat cap of base L and height eps the same. Infinite for a
/// degenerate triangle. (Longest edge squared over twice the area: exact for needles and caps
/// alike, where the smallest angle misses caps.)
inline double aspect_ratio(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double longest2 = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  const double twice_area = (b - a).cross(c - a).norm();
  return twice_area > 0.0 ? 0.5 * std::sqrt(3.0) * longest2 / twice_area : std::numeric_limits<double>::infinity();
}

/// The element of largest aspect_ratio and that ratio (element -1 for an empty mesh).
/// \ingroup mesh
struct WorstAspectRatio {
  Index element = -1;
  double ratio = 0.0;
};
inline WorstAspectRatio worst_aspect_ratio(const TriangleMesh& mesh) {
  WorstAspectRatio w;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto c = mesh.corners(e);
    const double r = aspect_ratio(c[0], c[1], c[2]);
    if (w.element < 0 || r > w.ratio) w = {e, r};
  }
  return w;
}

/// Above this aspect ratio sliver_warning warns (docs/stability.md, study (c); bench_stability
/// --study sliver): on a Kelvin box with a band of needles, the traction solved on a sliver was off
/// by about 0.07 x its aspect ratio, and the box's whole traction error had doubled at 40-110
/// (needles or flat caps, two mesh sizes) and was 2-3 times the sliver-free error at 100;
/// displacement and interior fields stayed as accurate as without slivers. The warning sits where
/// the doubling begins, 40 (issue 37; it was 100). bemsurg's own cutter makes up to ~20 (the gap
/// walls at kMinimumGapRatio), so cuts do not warn. Scenes warn at load (solve, press, cut,
/// session) and check_before_solve warns again for programs that call the library directly.
inline constexpr double kSliverWarningAspectRatio = 40.0;

/// Above this aspect ratio validate_mesh reports the element as degenerate (an error): there the
/// default quadrature itself departs from a deeper one and the traction error of the needle box
/// was several times the traction (docs/stability.md, study (c)).
inline constexpr double kMaxAspectRatio = 1e4;

/// "element 12 has aspect ratio 250 ..." when some element's aspect ratio exceeds
/// kSliverWarningAspectRatio (naming the worst one and how many exceed it); empty otherwise. For
/// ElastostaticResult::warnings (solve_elastostatic adds it).
inline std::string sliver_warning(const TriangleMesh& mesh) {
  const WorstAspectRatio w = worst_aspect_ratio(mesh);
  if (!(w.ratio > kSliverWarningAspectRatio)) return {};
  Index count = 0;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const auto c = mesh.corners(e);
    if (aspect_ratio(c[0], c[1], c[2]) > kSliverWarningAspectRatio) ++count;
  }
  return "element " + std::to_string(w.element) + " has aspect ratio " + general_text(w.ratio, 3) +
         " (longest edge / shortest altitude, 1 for equilateral), above " + general_text(kSliverWarningAspectRatio, 3) + " (" +
         std::to_string(count) + " element" + (count > 1 ? "s" : "") +
         "): the traction solved on such slivers is unreliable (its error grows like the aspect ratio; docs/stability.md); "
         "remesh them";
}

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
  q.max_aspect_ratio = worst_aspect_ratio(mesh).ratio;
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
