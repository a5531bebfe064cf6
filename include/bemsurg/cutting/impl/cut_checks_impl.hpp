// Part of the implementation of bemsurg/cutting/surface_cutter.hpp: the checks a step must pass
// before it is published, in the order they run: supported elements untouched, no sliver among
// the changed triangles, no self-intersection, a gap width of clearance around the groove, and a
// closed 2-manifold valid surface. The first that fails gives the step's reason.
#pragma once

#include "bemsurg/config.hpp"

#include <array>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bemsurg/cutting/gap_limit.hpp"
#include "bemsurg/cutting/impl/cut_work_impl.hpp"
#include "bemsurg/mesh/bvh.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

namespace detail {
// The candidate state as a mesh.
BEMSURG_INLINE std::shared_ptr<const TriangleMesh> cut_candidate_mesh(const std::vector<Vec3>& vertices,
                                                                      const std::vector<std::array<Index, 3>>& faces) {
  RowMatrixX3d V(static_cast<Index>(vertices.size()), 3);
  for (std::size_t v = 0; v < vertices.size(); ++v) V.row(static_cast<Index>(v)) = vertices[v].transpose();
  RowMatrixX3i F(static_cast<Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int k = 0; k < 3; ++k) F(static_cast<Index>(f), k) = static_cast<int>(faces[f][static_cast<std::size_t>(k)]);
  return std::make_shared<const TriangleMesh>(std::move(V), std::move(F));
}

// The delta, by the contract's definition: an old id is unchanged iff its three corner positions
// are bit-identical (mesh/mesh_delta.hpp).
BEMSURG_INLINE MeshDelta cut_delta(const TriangleMesh& old, const TriangleMesh& mesh) {
  MeshDelta d;
  d.elements_before = old.num_elements();
  d.elements_after = mesh.num_elements();
  for (Index f = 0; f < old.num_elements(); ++f) {
    const auto a = old.corners(f), b = mesh.corners(f);
    if (!(a[0] == b[0] && a[1] == b[1] && a[2] == b[2])) d.modified.push_back(f);
  }
  for (Index f = old.num_elements(); f < mesh.num_elements(); ++f) d.added.push_back(f);
  return d;
}
}  // namespace detail

BEMSURG_INLINE bool SurfaceCutter::check(Work& w, std::string& reason) const {
  auto mesh = detail::cut_candidate_mesh(w.V, w.F);
  w.delta = detail::cut_delta(*mesh_, *mesh);
  if (!check_locks(w, reason)) return false;
  const std::vector<Index> changed = w.delta.changed();
  if (!check_angles(*mesh, changed, reason) || !check_self_intersection(*mesh, changed, reason) || !check_clearance(w, *mesh, reason) ||
      !check_manifold(w, *mesh, changed, reason) || !check_gap(w, reason))
    return false;
  w.result = std::move(mesh);
  return true;
}

// Gaps below kMinimumGapRatio x the local edge length are refused (cutting/gap_limit.hpp,
// docs/stability.md (d)): the BEM solution across them is no longer trusted. Checked last, so a
// gap narrow enough to make slivers is refused for its angles first.
BEMSURG_INLINE bool SurfaceCutter::check_gap(const Work& w, std::string& reason) const {
  if (options_.allow_narrow_gap_for_studies) return true;
  for (const auto& s : w.path)
    if (s.split && !(reason = narrow_gap_reason(s.width, s.edge_length)).empty()) return false;
  return true;
}

// No modified element may be locked, and no locked element may touch the cut's path either (its
// ends included).
BEMSURG_INLINE bool SurfaceCutter::check_locks(const Work& w, std::string& reason) const {
  const TriangleMesh& old = *mesh_;
  for (Index f : w.delta.modified)
    if (locked_[static_cast<std::size_t>(f)]) {
      reason = "the cut would reach supported element " + std::to_string(f);
      return false;
    }
  std::vector<Index> locked_by_vertex(static_cast<std::size_t>(old.num_vertices()), -1);
  for (Index f = 0; f < old.num_elements(); ++f)
    if (locked_[static_cast<std::size_t>(f)])
      for (int k = 0; k < 3; ++k) locked_by_vertex[static_cast<std::size_t>(old.faces()(f, k))] = f;
  for (const auto& s : w.path) {
    const Index v = s.split ? s.left.front() : s.vertex;
    if (v < old.num_vertices() && locked_by_vertex[static_cast<std::size_t>(v)] >= 0) {
      reason = "the cut would reach supported element " + std::to_string(locked_by_vertex[static_cast<std::size_t>(v)]) + " at vertex " +
               std::to_string(v);
      return false;
    }
  }
  return true;
}

BEMSURG_INLINE bool SurfaceCutter::check_angles(const TriangleMesh& mesh, const std::vector<Index>& changed, std::string& reason) const {
  for (Index f : changed) {
    const auto c = mesh.corners(f);
    const double angle = smallest_angle_degrees(c[0], c[1], c[2]);
    if (angle < options_.min_angle_degrees) {
      std::ostringstream msg;
      use_classic_locale(msg) << "element " << f << " would have an angle of " << angle << " degrees, below the minimum of "
                              << options_.min_angle_degrees << " (a sliver: the gap is too narrow or the cut too deep here)";
      reason = msg.str();
      return false;
    }
  }
  return true;
}

BEMSURG_INLINE bool SurfaceCutter::check_self_intersection(const TriangleMesh& mesh, const std::vector<Index>& changed,
                                                           std::string& reason) {
  SelfIntersectionOptions so;
  so.max_pairs = 1;
  const auto pairs = find_self_intersections(mesh, changed, so);
  if (pairs.empty()) return true;
  reason = "the cut would make the surface intersect itself (elements " + std::to_string(pairs[0].first) + " and " +
           std::to_string(pairs[0].second) + "): it would break through a thin part or cross a wall";
  return false;
}

// Clearance: the groove's walls and bottom keep at least one gap width from the rest of the
// surface, so that a cut that nearly breaks through a thin part (leaving a skin thinner than the
// gap, whose two sides the BEM would integrate as near-singular neighbours) is refused like one
// that breaks through.
BEMSURG_INLINE bool SurfaceCutter::check_clearance(const Work& w, const TriangleMesh& mesh, std::string& reason) {
  const TriangleBvh bvh(mesh);
  std::vector<Index> near;
  for (const auto& s : w.path) {
    if (!s.split) continue;
    for (std::size_t l = 1; l < s.left.size(); ++l)
      for (Index v : {s.left[l], s.right[l]}) {
        const Vec3 p = w.pos(v);
        const double r = s.width;
        near.clear();
        bvh.query_box(p.array() - r, p.array() + r, near);
        for (Index g : near) {
          const auto& t = w.F[static_cast<std::size_t>(g)];
          if (w.groove[static_cast<std::size_t>(g)] || w.cut_vertex[static_cast<std::size_t>(t[0])] ||
              w.cut_vertex[static_cast<std::size_t>(t[1])] || w.cut_vertex[static_cast<std::size_t>(t[2])])
            continue;
          const double dist = point_triangle_distance(p, w.pos(t[0]), w.pos(t[1]), w.pos(t[2]));
          if (dist < r) {
            std::ostringstream msg;
            use_classic_locale(msg) << "the cut would come within " << dist << " of element " << g << " (less than the gap width " << r
                                    << "): it would break through a thin part";
            reason = msg.str();
            return false;
          }
        }
      }
  }
  return true;
}

// Last, the topology: a groove that breaks through a wall also breaks the shells' nesting, and
// the reasons above name that cause. Every vertex of a changed face has one closed fan of faces
// around it (validate_mesh checks edges; a vertex where two cones touch would pass it but is no
// 2-manifold either).
BEMSURG_INLINE bool SurfaceCutter::check_manifold(const Work& w, const TriangleMesh& mesh, const std::vector<Index>& changed,
                                                  std::string& reason) {
  std::vector<char> seen(w.V.size(), 0);
  for (Index f : changed)
    for (Index v : w.F[static_cast<std::size_t>(f)]) {
      if (seen[static_cast<std::size_t>(v)]) continue;
      seen[static_cast<std::size_t>(v)] = 1;
      std::string why;
      if (w.fan(v, -1, why).empty()) {
        reason = "the cut would leave a surface that is not 2-manifold: " + why;
        return false;
      }
    }
  MeshValidationOptions vo;
  vo.warn_unreferenced_vertices = false;
  const MeshValidationResult report = validate_mesh(mesh, vo);
  if (!report.valid()) {
    reason = "the cut would leave an invalid surface: " + report.summary();
    return false;
  }
  return true;
}

}  // namespace bemsurg
