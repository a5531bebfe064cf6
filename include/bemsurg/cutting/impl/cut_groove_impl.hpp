// Part of the implementation of bemsurg/cutting/surface_cutter.hpp: the groove's triangles.
//
// Between two consecutive cross-sections of the path, each split into a ring of rim and wall
// vertices (left rim, left wall levels, bottom, right wall levels, right rim), the groove is a
// band of quads, each cut into two triangles along the diagonal that gives the better smallest
// angle. At the cut's two ends the band closes in a fan to the end vertex. Every groove triangle
// is keyed by (segment, wall or bottom, level, half) so that a later step that reshapes it keeps
// its id (mesh/mesh_delta.hpp).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <array>
#include <tuple>
#include <vector>

#include "bemsurg/cutting/impl/cut_work_impl.hpp"
#include "bemsurg/mesh/geometry.hpp"

namespace bemsurg {

namespace detail {
// Whether the quad (a, b, c, d) is better cut along a-c than along b-d: the smallest angle of its
// two triangles is at least as large (ties go to a-c).
BEMSURG_INLINE bool cut_quad_along_ac(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double q1 = std::min(smallest_angle_degrees(a, b, c), smallest_angle_degrees(a, c, d));
  const double q2 = std::min(smallest_angle_degrees(a, b, d), smallest_angle_degrees(b, c, d));
  return q1 >= q2;
}
}  // namespace detail

BEMSURG_INLINE void SurfaceCutter::rebuild_groove(Work& w) const {
  const int L = w.levels;
  auto ring = [L](const Section& s) {
    std::vector<Index> r;
    for (int l = 0; l <= L; ++l) r.push_back(s.left[static_cast<std::size_t>(l)]);
    for (int l = L; l >= 0; --l) r.push_back(s.right[static_cast<std::size_t>(l)]);
    return r;
  };
  auto key_of = [L](int seg, int j, int half) {
    if (j < L) return std::make_tuple(seg, 0, j, half);   // left wall, level j
    if (j == L) return std::make_tuple(seg, 1, 0, half);  // bottom
    return std::make_tuple(seg, 2, 2 * L - j, half);      // right wall
  };
  auto place = [&](const std::tuple<int, int, int, int>& key, const std::array<Index, 3>& tri) {
    auto it = w.groove_faces.find(key);
    if (it != w.groove_faces.end()) {
      w.F[static_cast<std::size_t>(it->second)] = tri;
    } else {
      w.groove_faces[key] = w.add_face(tri, true);
    }
  };
  for (std::size_t s = 0; s + 1 < w.path.size(); ++s) {
    const Section& p = w.path[s];
    const Section& q = w.path[s + 1];
    const int seg = static_cast<int>(s);
    if (p.split && q.split) {
      const auto rp = ring(p), rq = ring(q);
      for (int j = 0; j < 2 * L + 1; ++j) {
        // Quad (a, b, c, d): ring segment j at p, then at q; its normal points into the gap.
        const Index a = rp[static_cast<std::size_t>(j)], b = rp[static_cast<std::size_t>(j + 1)];
        const Index c = rq[static_cast<std::size_t>(j + 1)], d = rq[static_cast<std::size_t>(j)];
        if (detail::cut_quad_along_ac(w.pos(a), w.pos(b), w.pos(c), w.pos(d))) {
          place(key_of(seg, j, 0), {a, b, c});
          place(key_of(seg, j, 1), {a, c, d});
        } else {
          place(key_of(seg, j, 0), {a, b, d});
          place(key_of(seg, j, 1), {b, c, d});
        }
      }
    } else if (q.split) {  // the start of the cut: a fan from the end vertex
      const auto rq = ring(q);
      for (int j = 0; j < 2 * L + 1; ++j)
        place(key_of(seg, j, 0), {p.vertex, rq[static_cast<std::size_t>(j + 1)], rq[static_cast<std::size_t>(j)]});
    } else {  // the far end
      const auto rp = ring(p);
      for (int j = 0; j < 2 * L + 1; ++j)
        place(key_of(seg, j, 0), {rp[static_cast<std::size_t>(j)], rp[static_cast<std::size_t>(j + 1)], q.vertex});
    }
  }
}

}  // namespace bemsurg
