// bemsurg/mesh/bvh.hpp: a bounding-volume hierarchy over the triangles of the current (deformed)
// surface, for picking: where a tool's ray or segment first meets the tissue (Wang et al. 2007 §6:
// ray-intersection picking), and which elements lie near a tool (contact candidates).
//
// Meshes of 10^4-10^5 elements: a query visits O(log E) nodes instead of looping over all
// triangles. The hierarchy is built once per topology (median split along the longest axis of
// the centroids' box, leaves of at most 4 triangles) and refitted, O(E), when the vertices move
// (every graphics frame), which keeps queries valid on the deformed surface without a rebuild.
// Queries allocate nothing (a fixed traversal stack), so the haptic thread may call them.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Where a ray or segment meets the surface (TriangleBvh::intersect_ray, intersect_segment): the element, the ray
/// parameter t, barycentric coordinates, the point, and whether the ray enters the material there.
/// \ingroup mesh
struct RayHit {
  Index element = -1;
  double t = std::numeric_limits<double>::infinity();  // origin + t * direction (segment: t in [0, 1])
  double u = 0.0, v = 0.0;                             // barycentric: point = (1-u-v) a + u b + v c
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  bool front_facing = false;  // the ray enters the material here
};

/// Bounding-volume hierarchy over the triangles of the current (deformed) surface, for picking with a tool's ray or
/// segment and for finding elements near a tool; built once per topology and refitted when the vertices move.
/// \ingroup mesh
class TriangleBvh {
 public:
  TriangleBvh() = default;
  /// Builds over the mesh's own vertices.
  explicit TriangleBvh(const TriangleMesh& mesh) : TriangleBvh(mesh.vertices(), mesh.faces()) {}
  TriangleBvh(const RowMatrixX3d& vertices, const RowMatrixX3i& faces);

  /// Same faces, moved vertices (e.g. mesh.vertices() + vertex displacements): updates every box
  /// bottom-up, O(E). Throws if the vertex count differs.
  void refit(const RowMatrixX3d& vertices);

  /// Closest intersection with t in (t_min, t_max]; `direction` need not be unit length.
  /// `front_only` ignores triangles whose normal faces along the ray (back faces).
  bool intersect_ray(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, RayHit& hit,
                     double t_max = std::numeric_limits<double>::infinity(), bool front_only = false) const;
  /// First intersection of the segment from a to b (hit.t in [0, 1]).
  bool intersect_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b, RayHit& hit, bool front_only = false) const;

  /// Elements whose triangle box overlaps the box [lo, hi]; appends to `out` up to its capacity
  /// when `no_grow` (real-time callers reserve first), otherwise push_back. Returns the count found.
  Index query_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::vector<Index>& out, bool no_grow = false) const;

  Index num_nodes() const { return static_cast<Index>(nodes_.size()); }
  Index num_triangles() const { return faces_.rows(); }
  /// Nodes visited by the last query from this thread (a cost measure for tests and benchmarks).
  static Index last_nodes_visited();
  const RowMatrixX3d& vertices() const { return vertices_; }

 private:
  struct Node {
    Eigen::Vector3d lo, hi;
    int left = -1;  // inner: first child (second child = right); leaf: -1
    int right = -1;
    int first = 0;  // leaf: range in order_
    int count = 0;
  };
  int build(int begin, int end, std::vector<Eigen::Vector3d>& centers);
  void triangle_box(Index f, Eigen::Vector3d& lo, Eigen::Vector3d& hi) const;

  RowMatrixX3d vertices_;
  RowMatrixX3i faces_;
  std::vector<Node> nodes_;
  std::vector<int> order_;  // triangle indices, leaves refer to ranges
};

/// mesh vertices moved by per-element displacements (3E entries), averaged to the vertices as
/// TriangleMesh::element_to_vertex does: the surface that is drawn and picked.
RowMatrixX3d deformed_vertices(const TriangleMesh& mesh, const Eigen::VectorXd& element_displacement);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/bvh_impl.hpp"
#endif
