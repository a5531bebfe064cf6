// bemsurg/mesh/red_green_refinement.hpp: conforming local refinement of a triangle surface by
// red-green splitting (Bank, Sherman & Weiser 1983; docs/graded.md#local-refinement-red-green).
//
// Red: a marked triangle splits 1 -> 4 at its edge midpoints. Closure: a triangle with two or three
// split edges, or with an edge whose halves are split again (two levels finer across it), becomes
// red too, until none is left (the red hierarchy is 1-irregular). Green: a triangle with exactly
// one split edge is bisected from that midpoint to the opposite corner (1 -> 2). Green triangles
// are never refined further: they are emitted only at the end, from their red parent, so a later
// level that marks their region refines the parent red instead (the usual "remove the green
// closure" rule). Midpoints stay on the flat faces (no projection onto a curved surface), so area
// and enclosed volume are preserved exactly (up to rounding) and a box stays a box.
//
// The surface stays closed, 2-manifold and oriented as the input: every child keeps its parent's
// corner order.
#pragma once

#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// What refine_red_green returns: the refined surface, the input element each new element lies in
/// (so boundary conditions and element selections carry over), and counts of what was done.
/// \ingroup mesh
struct RedGreenRefinement {
  TriangleMesh mesh;
  /// parent[e]: the element of the input mesh that new element e lies in. Children of one input
  /// element are consecutive, in increasing parent order.
  std::vector<Index> parent;
  Index red_splits = 0;    ///< 1 -> 4 splits, marked and closure together, over all levels
  Index green_splits = 0;  ///< 1 -> 2 bisections closing the refined region
};

namespace detail::red_green {

struct Leaf {
  std::array<int, 3> v;
  Index origin;  // input element
  int level;     // red level (0: an input element)
};

class Refiner {
 public:
  explicit Refiner(const TriangleMesh& mesh) {
    for (Index i = 0; i < mesh.num_vertices(); ++i) points_.push_back(mesh.vertex(i));
    for (Index e = 0; e < mesh.num_elements(); ++e) leaves_.push_back({{mesh.faces()(e, 0), mesh.faces()(e, 1), mesh.faces()(e, 2)}, e, 0});
  }

  /// One level: splits every leaf of red level `level - 1` descended from a marked element, then
  /// closes the red hierarchy.
  void level(const std::vector<char>& marked, int level) {
    std::vector<Leaf> next;
    for (const Leaf& l : leaves_) {
      if (l.level == level - 1 && marked[static_cast<std::size_t>(l.origin)])
        split_red(l, next);
      else
        next.push_back(l);
    }
    leaves_ = std::move(next);
    for (bool changed = true; changed;) {  // closure: each pass only adds midpoints, so it ends
      changed = false;
      next.clear();
      for (const Leaf& l : leaves_) {
        int split = 0;
        bool deep = false;
        for (int k = 0; k < 3; ++k) {
          const int m = midpoint_of(l.v[k], l.v[(k + 1) % 3]);
          if (m < 0) continue;
          ++split;
          deep = deep || midpoint_of(l.v[k], m) >= 0 || midpoint_of(m, l.v[(k + 1) % 3]) >= 0;
        }
        if (split >= 2 || deep) {
          split_red(l, next);
          changed = true;
        } else {
          next.push_back(l);
        }
      }
      leaves_.swap(next);
    }
  }

  /// The conforming mesh: leaves with one split edge are bisected (green).
  RedGreenRefinement finish() {
    std::stable_sort(leaves_.begin(), leaves_.end(), [](const Leaf& a, const Leaf& b) { return a.origin < b.origin; });
    std::vector<std::array<int, 3>> faces;
    for (const Leaf& l : leaves_) {
      int k = 0;
      while (k < 3 && midpoint_of(l.v[k], l.v[(k + 1) % 3]) < 0) ++k;
      if (k == 3) {
        faces.push_back(l.v);
        result_.parent.push_back(l.origin);
        continue;
      }
      const int a = l.v[k], b = l.v[(k + 1) % 3], c = l.v[(k + 2) % 3], m = midpoint_of(a, b);
      faces.push_back({a, m, c});
      faces.push_back({m, b, c});
      result_.parent.insert(result_.parent.end(), 2, l.origin);
      ++result_.green_splits;
    }
    RowMatrixX3d V(static_cast<Index>(points_.size()), 3);
    for (std::size_t i = 0; i < points_.size(); ++i) V.row(static_cast<Index>(i)) = points_[i].transpose();
    RowMatrixX3i F(static_cast<Index>(faces.size()), 3);
    for (std::size_t f = 0; f < faces.size(); ++f) F.row(static_cast<Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
    result_.mesh = TriangleMesh(std::move(V), std::move(F));
    return std::move(result_);
  }

 private:
  int midpoint_of(int a, int b) const {
    const auto it = midpoints_.find(std::minmax(a, b));
    return it == midpoints_.end() ? -1 : it->second;
  }
  int make_midpoint(int a, int b) {
    const auto key = std::minmax(a, b);
    const auto it = midpoints_.find(key);
    if (it != midpoints_.end()) return it->second;
    points_.push_back(0.5 * (points_[static_cast<std::size_t>(a)] + points_[static_cast<std::size_t>(b)]));
    const int m = static_cast<int>(points_.size() - 1);
    midpoints_.emplace(key, m);
    return m;
  }
  void split_red(const Leaf& l, std::vector<Leaf>& out) {
    const int a = l.v[0], b = l.v[1], c = l.v[2];
    const int ab = make_midpoint(a, b), bc = make_midpoint(b, c), ca = make_midpoint(c, a);
    for (const std::array<int, 3>& v : {std::array<int, 3>{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}})
      out.push_back({v, l.origin, l.level + 1});
    ++result_.red_splits;
  }

  std::vector<Vec3> points_;
  std::vector<Leaf> leaves_;
  std::map<std::pair<int, int>, int> midpoints_;
  RedGreenRefinement result_;
};

}  // namespace detail::red_green

/// Refines the `marked` elements of `mesh` (indices into it, any order, repeats allowed) red,
/// `levels` times (each level splits once more every element descended from a marked one), and
/// closes the refined region conformingly (green bisections; see the top of this header). The
/// input should be valid (require_valid_mesh); the result is then valid too, with the same
/// orientation, area and volume. levels = 0 or no marked element returns the mesh unchanged.
/// Throws InvalidArgumentError for a marked element out of range or levels outside [0, 8] (each
/// level multiplies the marked elements by four).
inline RedGreenRefinement refine_red_green(const TriangleMesh& mesh, const std::vector<Index>& marked, int levels = 1) {
  if (levels < 0 || levels > 8)
    throw InvalidArgumentError("red-green refinement: levels must lie in [0, 8], got " + std::to_string(levels));
  std::vector<char> mark(static_cast<std::size_t>(mesh.num_elements()), 0);
  for (Index e : marked) {
    if (e < 0 || e >= mesh.num_elements())
      throw InvalidArgumentError("red-green refinement: marked element " + std::to_string(e) + " out of range (mesh has " +
                                 std::to_string(mesh.num_elements()) + " elements)");
    mark[static_cast<std::size_t>(e)] = 1;
  }
  detail::red_green::Refiner refiner(mesh);
  for (int l = 1; l <= levels; ++l) refiner.level(mark, l);
  return refiner.finish();
}

/// The same with a number of levels per element (levels[e] in [0, 8], one per element of `mesh`):
/// level l splits the leaves of red level l - 1 descended from elements asking for at least l, so
/// elements of different sizes can be refined to one target size in one conforming hierarchy.
inline RedGreenRefinement refine_red_green_levels(const TriangleMesh& mesh, const std::vector<int>& levels) {
  if (static_cast<Index>(levels.size()) != mesh.num_elements())
    throw InvalidArgumentError("red-green refinement: " + std::to_string(levels.size()) + " levels given for " +
                               std::to_string(mesh.num_elements()) + " elements");
  int deepest = 0;
  for (int l : levels) {
    if (l < 0 || l > 8) throw InvalidArgumentError("red-green refinement: levels must lie in [0, 8], got " + std::to_string(l));
    deepest = std::max(deepest, l);
  }
  detail::red_green::Refiner refiner(mesh);
  for (int l = 1; l <= deepest; ++l) {
    std::vector<char> mark(levels.size());
    for (std::size_t e = 0; e < levels.size(); ++e) mark[e] = levels[e] >= l;
    refiner.level(mark, l);
  }
  return refiner.finish();
}

}  // namespace bemsurg
