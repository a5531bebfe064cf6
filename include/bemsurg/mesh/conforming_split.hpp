// bemsurg/mesh/conforming_split.hpp: split the elements a region's boundary crosses along it, so
// that a boundary rule holds the region's area on the surface and not the elements whose centroid
// happens to lie inside (issue 38 item 2; docs/scene-format.md, "conform").
//
// The surface is unchanged: new vertices lie on the mesh's edges, where the boundary crosses them
// (found by bisection of the region's level function, mesh/space_region.hpp), and each crossed
// triangle becomes a triangle and a quadrilateral (split along its better diagonal) or, where the
// boundary runs through a corner, two triangles. Crossings are shared by the two triangles of an
// edge, so the result is as closed, manifold and oriented as the input.
//
// Slivers are avoided by snapping: a crossing within `snap` (a fraction of the edge) of a corner is
// moved to that corner, which is then treated as on the boundary, so no piece is thinner than
// about snap / (1 - snap) of its parent (aspect ratio at most ~4 times the parent's for snap 0.2).
// The chords between crossings cut a curved boundary short (relative area error about
// chord^2 / (6 rho^2) for a circle of radius rho), and snapping moves it by up to a fifth of an
// edge; conform_to_region therefore refines the crossed elements red-green (mesh/
// red_green_refinement.hpp, surface unchanged) until the pieces inside hold the region's exact
// area within a tolerance.
//
// Numbering: one piece of every input element keeps its index (the largest piece), the others
// are appended in increasing order of their parents, and `parent` maps every output element to
// the input element it lies in, so element lists and per-element files given for the input carry
// over (keep_parent_ids).
#pragma once

#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/red_green_refinement.hpp"
#include "bemsurg/mesh/space_region.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// A mesh made from another by splitting elements: the new mesh, the input element each new
/// element lies in, and (for a conforming split) whether each new element lies in the region.
/// \ingroup mesh
struct ElementSplit {
  TriangleMesh mesh;
  std::vector<Index> parent;  ///< parent[e]: the input element new element e lies in
  std::vector<char> inside;   ///< conforming splits: 1 where the element lies in the region
  Index split_elements = 0;   ///< input elements cut into pieces
  Index snapped_crossings = 0;
  int refinement_levels = 0;  ///< red-green levels conform_to_region added along the boundary
  double region_area = 0.0;   ///< conform_to_region: the exact area of the surface inside the region
  double held_area = 0.0;     ///< conform_to_region: the area of the elements marked inside
};

/// Renumbers elements so that one child of each input element e (the largest) has index e and
/// the others follow in increasing order of their parents (ties: as given). `parent` must give
/// every input element 0..parents-1 at least one child. `inside`, when not empty, is permuted too.
inline ElementSplit keep_parent_ids(const TriangleMesh& mesh, const std::vector<Index>& parent, Index parents,
                                    const std::vector<char>& inside = {}) {
  const Index n = mesh.num_elements();
  std::vector<Index> keeper(static_cast<std::size_t>(parents), -1);
  for (Index e = 0; e < n; ++e) {
    Index& k = keeper[static_cast<std::size_t>(parent[static_cast<std::size_t>(e)])];
    if (k < 0 || mesh.area(e) > mesh.area(k)) k = e;
  }
  std::vector<Index> order;  // order[new] = old
  order.reserve(static_cast<std::size_t>(n));
  for (Index p = 0; p < parents; ++p) {
    if (keeper[static_cast<std::size_t>(p)] < 0)
      throw InvalidArgumentError("keep_parent_ids: input element " + std::to_string(p) + " has no child");
    order.push_back(keeper[static_cast<std::size_t>(p)]);
  }
  std::vector<std::pair<Index, Index>> rest;  // (parent, old index) of the other children
  for (Index e = 0; e < n; ++e)
    if (keeper[static_cast<std::size_t>(parent[static_cast<std::size_t>(e)])] != e)
      rest.emplace_back(parent[static_cast<std::size_t>(e)], e);
  std::stable_sort(rest.begin(), rest.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& r : rest) order.push_back(r.second);
  ElementSplit out;
  RowMatrixX3i F(n, 3);
  out.parent.resize(static_cast<std::size_t>(n));
  if (!inside.empty()) out.inside.resize(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) {
    const Index old = order[static_cast<std::size_t>(i)];
    F.row(i) = mesh.faces().row(old);
    out.parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(old)];
    if (!inside.empty()) out.inside[static_cast<std::size_t>(i)] = inside[static_cast<std::size_t>(old)];
  }
  out.mesh = TriangleMesh(mesh.vertices(), std::move(F));
  return out;
}

namespace detail::conforming {

/// The parameter t in (0, 1) where the level function changes sign along a -> b (bisection: the
/// function is continuous, and 60 halvings reach rounding).
inline double crossing(const SpaceRegion& region, const Vec3& a, const Vec3& b) {
  double lo = 0.0, hi = 1.0;
  const bool a_inside = region.level(a) <= 0.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    ((region.level(a + mid * (b - a)) <= 0.0) == a_inside ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

inline int sign_of(double f) { return f < 0.0 ? -1 : (f > 0.0 ? 1 : 0); }

}  // namespace detail::conforming

/// Splits the elements of `mesh` crossed by the boundary of `region` along it (see the header
/// comment); `snap` in [0, 0.5) is the fraction of an edge within which a crossing moves to the
/// corner. The result's `inside` marks the elements in the region.
// long: snapping, cutting and classifying share the crossings' table; apart they would pass it around
inline ElementSplit split_along_region(const TriangleMesh& mesh, const SpaceRegion& region, double snap = 0.2) {
  using detail::conforming::sign_of;
  if (!(snap > 0.0 && snap < 0.5))
    throw InvalidArgumentError("conforming split: snap must lie in (0, 0.5) (a fraction of an edge), got " + std::to_string(snap));
  const Index V = mesh.num_vertices(), E = mesh.num_elements();
  std::vector<double> level(static_cast<std::size_t>(V));
  for (Index v = 0; v < V; ++v) level[static_cast<std::size_t>(v)] = region.level(mesh.vertex(v));
  ElementSplit out;
  // Snapping first, over every edge, so that both triangles of an edge see the same corners (each
  // edge of a closed surface is met once in each direction; the a < b one is taken).
  std::vector<char> on_boundary(static_cast<std::size_t>(V), 0);
  const auto edge_crossing = [&](int a, int b) { return detail::conforming::crossing(region, mesh.vertex(a), mesh.vertex(b)); };
  for (Index e = 0; e < E; ++e)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.faces()(e, k), b = mesh.faces()(e, (k + 1) % 3);
      if (a > b || sign_of(level[std::size_t(a)]) * sign_of(level[std::size_t(b)]) >= 0) continue;
      const double t = edge_crossing(a, b);
      if (t < snap) on_boundary[std::size_t(a)] = 1;
      if (t > 1.0 - snap) on_boundary[std::size_t(b)] = 1;
    }
  for (Index v = 0; v < V; ++v)
    if (on_boundary[static_cast<std::size_t>(v)]) {
      level[static_cast<std::size_t>(v)] = 0.0;
      ++out.snapped_crossings;
    }

  std::vector<Vec3> points;
  for (Index v = 0; v < V; ++v) points.push_back(mesh.vertex(v));
  std::map<std::pair<int, int>, int> crossing_vertex;
  const auto cross_at = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    const auto it = crossing_vertex.find(key);
    if (it != crossing_vertex.end()) return it->second;
    const Vec3 pa = mesh.vertex(key.first), pb = mesh.vertex(key.second);
    points.push_back(pa + edge_crossing(key.first, key.second) * (pb - pa));
    const int id = static_cast<int>(points.size() - 1);
    crossing_vertex.emplace(key, id);
    level.push_back(0.0);
    return id;
  };

  std::vector<std::array<int, 3>> faces;
  std::vector<Index> parent;
  const auto emit = [&](Index p, int a, int b, int c) {
    faces.push_back({a, b, c});
    parent.push_back(p);
  };
  const auto quality = [&](int a, int b, int c) {
    return aspect_ratio(points[std::size_t(a)], points[std::size_t(b)], points[std::size_t(c)]);
  };
  for (Index e = 0; e < E; ++e) {
    std::array<int, 3> v{mesh.faces()(e, 0), mesh.faces()(e, 1), mesh.faces()(e, 2)};
    std::array<int, 3> s{};
    int neg = 0, pos = 0;
    for (int k = 0; k < 3; ++k) {
      s[std::size_t(k)] = sign_of(level[std::size_t(v[std::size_t(k)])]);
      neg += s[std::size_t(k)] < 0;
      pos += s[std::size_t(k)] > 0;
    }
    if (neg == 0 || pos == 0) {
      emit(e, v[0], v[1], v[2]);
      continue;
    }
    ++out.split_elements;
    // Rotate so that corner 0 is the one alone on its side (or the one on the boundary).
    int lone = 0;
    for (int k = 0; k < 3; ++k) {
      const int a = s[std::size_t((k + 1) % 3)], b = s[std::size_t((k + 2) % 3)];
      if (s[std::size_t(k)] == 0 || (a == b && a != s[std::size_t(k)] && a != 0)) lone = k;
    }
    std::rotate(v.begin(), v.begin() + lone, v.end());
    std::rotate(s.begin(), s.begin() + lone, s.end());
    if (s[0] == 0) {  // the boundary runs through corner 0 and across the opposite edge
      const int q = cross_at(v[1], v[2]);
      emit(e, v[0], v[1], q);
      emit(e, v[0], q, v[2]);
      continue;
    }
    const int p = cross_at(v[0], v[1]), q = cross_at(v[0], v[2]);
    emit(e, v[0], p, q);
    // The quadrilateral p, v1, v2, q: the diagonal whose worse triangle is better.
    if (std::max(quality(p, v[1], v[2]), quality(p, v[2], q)) <= std::max(quality(p, v[1], q), quality(v[1], v[2], q))) {
      emit(e, p, v[1], v[2]);
      emit(e, p, v[2], q);
    } else {
      emit(e, p, v[1], q);
      emit(e, v[1], v[2], q);
    }
  }

  RowMatrixX3d P(static_cast<Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) P.row(static_cast<Index>(i)) = points[i].transpose();
  RowMatrixX3i F(static_cast<Index>(faces.size()), 3);
  std::vector<char> inside(faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f) {
    F.row(static_cast<Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
    double worst = -std::numeric_limits<double>::infinity(), best = std::numeric_limits<double>::infinity();
    for (int c : faces[f]) worst = std::max(worst, level[std::size_t(c)]), best = std::min(best, level[std::size_t(c)]);
    if (worst == 0.0 && best == 0.0)  // every corner on the boundary: the piece's centre decides
      worst = region.level((points[std::size_t(faces[f][0])] + points[std::size_t(faces[f][1])] + points[std::size_t(faces[f][2])]) / 3.0);
    inside[f] = worst <= 0.0;
  }
  ElementSplit kept = keep_parent_ids(TriangleMesh(std::move(P), std::move(F)), parent, E, inside);
  kept.split_elements = out.split_elements;
  kept.snapped_crossings = out.snapped_crossings;
  return kept;
}

/// split_along_region, refined first where needed: the elements the boundary crosses are refined
/// red-green one level more (up to `max_levels`) until the elements inside hold the region's exact
/// area (area_inside) within `area_tolerance` (relative). `parent` maps to `mesh`'s elements;
/// `held_area` against `region_area` says how close the last level came (a region smaller than
/// an element's 2^-max_levels may hold nothing).
inline ElementSplit conform_to_region(const TriangleMesh& mesh, const SpaceRegion& region, double area_tolerance = 0.005,
                                      int max_levels = 3, double snap = 0.2) {
  const Index E = mesh.num_elements();
  double exact = 0.0;
  std::vector<Index> crossed;
  for (Index e = 0; e < E; ++e) {
    const std::array<Vec3, 3> c = mesh.corners(e);
    const double a = triangle_area_inside(c[0], c[1], c[2], region);
    exact += a;
    if (a > 1e-12 * mesh.area(e) && a < (1.0 - 1e-12) * mesh.area(e)) crossed.push_back(e);
  }
  for (int level = 0;; ++level) {
    ElementSplit refined;
    if (level == 0) {
      refined.mesh = mesh;
      for (Index e = 0; e < E; ++e) refined.parent.push_back(e);
    } else {
      const RedGreenRefinement r = refine_red_green(mesh, crossed, level);
      refined = keep_parent_ids(r.mesh, r.parent, E);
    }
    ElementSplit split = split_along_region(refined.mesh, region, snap);
    double held = 0.0;
    for (Index e = 0; e < split.mesh.num_elements(); ++e)
      if (split.inside[static_cast<std::size_t>(e)]) held += split.mesh.area(e);
    if (std::abs(held - exact) <= area_tolerance * exact || level >= max_levels) {
      for (Index& p : split.parent) p = refined.parent[static_cast<std::size_t>(p)];
      // Keep the input's numbering: the largest descendant of element e has index e.
      ElementSplit out = keep_parent_ids(split.mesh, split.parent, E, split.inside);
      out.split_elements = split.split_elements;
      out.snapped_crossings = split.snapped_crossings;
      out.refinement_levels = level;
      out.region_area = exact;
      out.held_area = held;
      return out;
    }
  }
}

}  // namespace bemsurg
