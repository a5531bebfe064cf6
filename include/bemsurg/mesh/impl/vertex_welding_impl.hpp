// Hash-grid search for coincident vertices and the weld that STL reading relies on
// (bemsurg/mesh/vertex_welding.hpp). Header-defined: mesh validation calls it, and validation is
// part of the header-only core (docs/design.md §1).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <unordered_map>

#include "bemsurg/mesh/vertex_welding.hpp"

namespace bemsurg {

namespace detail::vertex_welding {

using CellKey = std::array<std::int64_t, 3>;

struct CellKeyHash {
  std::size_t operator()(const detail::vertex_welding::CellKey& k) const {
    // Large odd multipliers spread neighbouring cells over the table.
    std::uint64_t h = static_cast<std::uint64_t>(k[0]) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<std::uint64_t>(k[1]) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= static_cast<std::uint64_t>(k[2]) * 0x165667B19E3779F9ull + (h << 6) + (h >> 2);
    return static_cast<std::size_t>(h);
  }
};

}  // namespace detail::vertex_welding

BEMSURG_INLINE double bounding_box_diagonal(const RowMatrixX3d& vertices) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  bool any = false;
  for (Index v = 0; v < vertices.rows(); ++v) {
    const Vec3 p = vertices.row(v).transpose();
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    any = true;
  }
  return any ? (hi - lo).norm() : 0.0;
}

BEMSURG_INLINE std::vector<Index> coincident_vertex_representatives(const RowMatrixX3d& vertices, double tolerance) {
  const Index n = vertices.rows();
  std::vector<Index> rep(static_cast<std::size_t>(n));
  for (Index v = 0; v < n; ++v) rep[static_cast<std::size_t>(v)] = v;
  if (n == 0) return rep;

  // The cell must be at least the tolerance (so that a partner lies in one of the 27 cells around
  // a point) and large enough that coordinate / cell fits comfortably in 64 bits.
  double max_abs = 0.0;
  for (Index v = 0; v < n; ++v)
    if (vertices.row(v).allFinite()) max_abs = std::max(max_abs, vertices.row(v).cwiseAbs().maxCoeff());
  const double cell = std::max({tolerance, max_abs * 1e-12, std::numeric_limits<double>::min()});
  const double tol2 = tolerance * tolerance;

  std::unordered_map<detail::vertex_welding::CellKey, std::vector<Index>, detail::vertex_welding::CellKeyHash> grid;
  grid.reserve(static_cast<std::size_t>(n));
  for (Index v = 0; v < n; ++v) {
    const Vec3 p = vertices.row(v).transpose();
    if (!p.allFinite()) continue;
    const detail::vertex_welding::CellKey key = {static_cast<std::int64_t>(std::floor(p.x() / cell)),
                                                 static_cast<std::int64_t>(std::floor(p.y() / cell)),
                                                 static_cast<std::int64_t>(std::floor(p.z() / cell))};
    Index found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx)
      for (int dy = -1; dy <= 1 && found < 0; ++dy)
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          const auto it = grid.find({key[0] + dx, key[1] + dy, key[2] + dz});
          if (it == grid.end()) continue;
          for (Index w : it->second)
            if ((vertices.row(w).transpose() - p).squaredNorm() <= tol2) {
              // Several candidates may qualify; the lowest index keeps the result independent of
              // hash-table iteration order.
              if (found < 0 || w < found) found = w;
            }
        }
    if (found >= 0) {
      rep[static_cast<std::size_t>(v)] = found;
    } else {
      grid[key].push_back(v);
    }
  }
  return rep;
}

BEMSURG_INLINE TriangleMesh weld_vertices(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, double relative_tolerance) {
  const double tol = relative_tolerance * bounding_box_diagonal(vertices);
  const std::vector<Index> rep = coincident_vertex_representatives(vertices, tol);
  std::vector<int> new_index(rep.size(), -1);
  RowMatrixX3d out_vertices(vertices.rows(), 3);
  RowMatrixX3i out_faces(faces.rows(), 3);
  int count = 0;
  for (Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int old = faces(f, k);
      if (old < 0 || old >= vertices.rows())
        throw InvalidMeshError("face " + std::to_string(f) + " refers to vertex " + std::to_string(old) + ", but the mesh has " +
                               std::to_string(vertices.rows()) + " vertices");
      const auto r = static_cast<std::size_t>(rep[static_cast<std::size_t>(old)]);
      if (new_index[r] < 0) {
        new_index[r] = count;
        out_vertices.row(count) = vertices.row(static_cast<Index>(r));
        ++count;
      }
      out_faces(f, k) = new_index[r];
    }
  out_vertices.conservativeResize(count, 3);
  return TriangleMesh(std::move(out_vertices), std::move(out_faces));
}

}  // namespace bemsurg
