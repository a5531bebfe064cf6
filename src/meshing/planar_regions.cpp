// Planar regions of a surface and snapping onto them (bemsurg/meshing/planar_regions.hpp).
#include "bemsurg/meshing/planar_regions.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"

namespace bemsurg {

namespace {

bool corners_within(const TriangleMesh& mesh, Index f, const Vec3& normal, double offset, double tolerance) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(normal.dot(mesh.vertex(mesh.faces()(f, k))) - offset) > tolerance) return false;
  return true;
}

/// The faces reachable across edges from `seed` that lie on the seed's plane (within `tolerance`)
/// and face its way; faces already in a region (`taken`) are not. `seen` holds, per face, the last
/// seed that looked at it (one array for all seeds: a fresh one each would cost O(faces^2)).
std::vector<Index> grow_coplanar(const TriangleMesh& mesh, const MeshTopology& topo, Index seed, const std::vector<char>& taken,
                                 std::vector<Index>& seen, double tolerance) {
  const Vec3 n = mesh.normal(seed);
  const double offset = n.dot(mesh.centroid(seed));
  std::vector<Index> group{seed};
  seen[static_cast<std::size_t>(seed)] = seed;
  for (std::size_t i = 0; i < group.size(); ++i)
    for (const Index g : topo.neighbours(group[i])) {
      if (g < 0 || seen[static_cast<std::size_t>(g)] == seed || taken[static_cast<std::size_t>(g)]) continue;
      seen[static_cast<std::size_t>(g)] = seed;
      // Same side: a fold back onto the plane (a thin sheet's other face) is not the same face.
      if (mesh.area(g) > 0.0 && mesh.normal(g).dot(n) > 0.0 && corners_within(mesh, g, n, offset, tolerance)) group.push_back(g);
    }
  return group;
}

/// The plane of a group, fitted by area weights (a seed's own normal is only as good as its shape).
PlanarRegion fit_region(const TriangleMesh& mesh, std::vector<Index> faces) {
  PlanarRegion r;
  Vec3 n = Vec3::Zero();
  for (const Index f : faces) n += mesh.area(f) * mesh.normal(f), r.area += mesh.area(f);
  r.normal = n.normalized();
  double offset = 0.0;
  for (const Index f : faces) offset += mesh.area(f) * r.normal.dot(mesh.centroid(f));
  r.offset = offset / r.area;
  std::sort(faces.begin(), faces.end());
  r.faces = std::move(faces);
  return r;
}

/// A uniform grid of the region's triangles (each in every cell its box, grown by `margin`,
/// touches), so "is this point within margin of the region" costs a few triangle tests.
class TriangleGrid {
 public:
  TriangleGrid(const TriangleMesh& mesh, const std::vector<Index>& faces, double margin) : mesh_(mesh), margin_(margin) {
    double area = 0.0;
    for (const Index f : faces) area += mesh.area(f);
    cell_ = std::max(2.0 * margin, 2.0 * std::sqrt(area / double(std::max<std::size_t>(faces.size(), 1))));
    for (const Index f : faces) {
      Vec3 lo = mesh.vertex(mesh.faces()(f, 0)), hi = lo;
      for (int k = 1; k < 3; ++k) lo = lo.cwiseMin(mesh.vertex(mesh.faces()(f, k))), hi = hi.cwiseMax(mesh.vertex(mesh.faces()(f, k)));
      const std::array<std::int64_t, 3> a = cell_of(lo.array() - margin), b = cell_of(hi.array() + margin);
      for (std::int64_t i = a[0]; i <= b[0]; ++i)
        for (std::int64_t j = a[1]; j <= b[1]; ++j)
          for (std::int64_t k = a[2]; k <= b[2]; ++k) cells_[key({i, j, k})].push_back(f);
    }
  }

  bool near(const Vec3& p) const {
    const auto it = cells_.find(key(cell_of(p)));
    if (it == cells_.end()) return false;
    for (const Index f : it->second) {
      const auto c = mesh_.corners(f);
      if (point_triangle_distance(p, c[0], c[1], c[2]) <= margin_) return true;
    }
    return false;
  }

 private:
  std::array<std::int64_t, 3> cell_of(const Vec3& p) const {
    return {std::int64_t(std::floor(p.x() / cell_)), std::int64_t(std::floor(p.y() / cell_)), std::int64_t(std::floor(p.z() / cell_))};
  }
  static std::uint64_t key(const std::array<std::int64_t, 3>& c) {
    return (std::uint64_t(c[0]) * 73856093u) ^ (std::uint64_t(c[1]) * 19349663u) ^ (std::uint64_t(c[2]) * 83492791u);
  }

  const TriangleMesh& mesh_;
  double margin_;
  double cell_ = 1.0;
  std::unordered_map<std::uint64_t, std::vector<Index>> cells_;  // hash collisions only add candidates
};

}  // namespace

std::vector<PlanarRegion> find_planar_regions(const TriangleMesh& mesh, const PlanarRegionOptions& options) {
  std::vector<PlanarRegion> regions;
  if (mesh.num_elements() == 0) return regions;
  const MeshTopology topo(mesh);
  const double tolerance = options.distance_tolerance * bounding_box_diagonal(mesh.vertices());
  const double min_area = options.min_area_fraction * mesh.total_area();
  // Largest faces first: their planes are the best-conditioned seeds.
  std::vector<Index> order(static_cast<std::size_t>(mesh.num_elements()));
  std::iota(order.begin(), order.end(), Index(0));
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return mesh.area(a) > mesh.area(b); });
  std::vector<char> taken(order.size(), 0), tried(order.size(), 0);
  std::vector<Index> seen(order.size(), -1);
  for (const Index seed : order) {
    if (taken[static_cast<std::size_t>(seed)] || tried[static_cast<std::size_t>(seed)] || !(mesh.area(seed) > 0.0)) continue;
    std::vector<Index> group = grow_coplanar(mesh, topo, seed, taken, seen, tolerance);
    // A group too small to count is not claimed: its faces may still join a plane seeded elsewhere,
    // but need not seed again (they would grow the same small group).
    double area = 0.0;
    for (const Index f : group) area += mesh.area(f), tried[static_cast<std::size_t>(f)] = 1;
    if (area < min_area) continue;
    for (const Index f : group) taken[static_cast<std::size_t>(f)] = 1;
    regions.push_back(fit_region(mesh, std::move(group)));
  }
  std::stable_sort(regions.begin(), regions.end(), [](const PlanarRegion& a, const PlanarRegion& b) { return a.area > b.area; });
  return regions;
}

namespace {

/// Per vertex: whether every face that uses it faces along `normal` (unit normal . normal >= min_cos).
std::vector<char> facing_vertices(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, const Vec3& normal, double min_cos) {
  std::vector<char> facing(static_cast<std::size_t>(vertices.rows()), 1);
  if (min_cos <= -1.0) return facing;
  for (Index f = 0; f < faces.rows(); ++f) {
    const Vec3 a = vertices.row(faces(f, 0)).transpose(), b = vertices.row(faces(f, 1)).transpose(),
               c = vertices.row(faces(f, 2)).transpose();
    const Vec3 n = (b - a).cross(c - a);
    if (!(n.norm() > 0.0 && n.dot(normal) >= min_cos * n.norm()))
      for (int k = 0; k < 3; ++k) facing[static_cast<std::size_t>(faces(f, k))] = 0;
  }
  return facing;
}

}  // namespace

Index snap_to_planar_regions(RowMatrixX3d& vertices, const RowMatrixX3i& faces, const TriangleMesh& source,
                             const std::vector<PlanarRegion>& regions, double max_distance, double min_cos) {
  Index moved = 0;
  for (const PlanarRegion& region : regions) {
    const TriangleGrid grid(source, region.faces, max_distance);
    const std::vector<char> facing = facing_vertices(vertices, faces, region.normal, min_cos);
    for (Index v = 0; v < vertices.rows(); ++v) {
      const Vec3 x = vertices.row(v).transpose();
      if (!facing[static_cast<std::size_t>(v)] || std::abs(region.signed_distance(x)) > max_distance) continue;
      const Vec3 p = region.project(x);
      if (p == x || !grid.near(p)) continue;
      vertices.row(v) = p.transpose();
      ++moved;
    }
  }
  return moved;
}

}  // namespace bemsurg
