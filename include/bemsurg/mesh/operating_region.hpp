// bemsurg/mesh/operating_region.hpp: where the surgery happens (docs/graded.md). Wang et al. 2007
// §6 recommend locating it before the operation, meshing it finely and grading into a coarse
// remainder, and computing pre-solutions only there ("model no more than a scene needs",
// docs/design.md §6). One OperatingRegion therefore drives both the graded remesher
// (mesh/graded_remesher.hpp) and the Green's table region (GreensTableOptions::region).
//
// A region is a sphere, an axis-aligned box, or a set of elements of a given mesh. Its distance
// function d(x) (0 inside, Euclidean distance outside) is what the remesher grades by.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Where the surgery happens: a sphere, an axis-aligned box or a set of elements of a mesh, with its distance
/// function. One region drives both the graded remesher and the Green's table region (docs/graded.md).
/// \ingroup mesh
class OperatingRegion {
 public:
  enum class Kind { Sphere, Box, Elements };

  /// Throws InvalidArgumentError for a non-finite centre or a radius <= 0.
  static OperatingRegion sphere(const Vec3& center, double radius);
  /// Throws InvalidArgumentError unless lo < hi componentwise (finite).
  static OperatingRegion box(const Vec3& lo, const Vec3& hi);
  /// The union of the listed elements (triangles) of `mesh`; the triangles are copied, so the
  /// region outlives the mesh and keeps meaning the same place after remeshing. Throws
  /// InvalidArgumentError for an empty list or an element out of range (naming it).
  static OperatingRegion element_set(const TriangleMesh& mesh, const std::vector<Index>& elements);

  Kind kind() const { return kind_; }
  const Vec3& center() const { return center_; }
  double radius() const { return radius_; }
  const Vec3& lo() const { return lo_; }
  const Vec3& hi() const { return hi_; }
  /// For Kind::Elements: the copied triangles, three rows (corners) each.
  const RowMatrixX3d& triangles() const { return triangles_; }

  /// Distance from x to the region: 0 inside (or on an element of the set), else Euclidean.
  double distance(const Vec3& x) const;

  /// Elements of `mesh` whose centroid lies within `slack` of the region (for an element set
  /// meshed anew, slack ~ half an element length picks the new elements covering the old ones).
  std::vector<Index> elements_of(const TriangleMesh& mesh, double slack = 0.0) const;

  /// Throws InvalidArgumentError when the region does not meet the surface of `mesh` within
  /// `slack` (a sphere whose closest surface point is farther than its radius, a box holding no
  /// vertex, centroid or edge midpoint): tools could never act there.
  void require_meets_surface(const TriangleMesh& mesh, double slack = 0.0) const;

  /// One line for messages and reports, e.g. "sphere (centre (0, 0.03, 0.08), radius 0.02)".
  std::string describe() const;

 private:
  Kind kind_ = Kind::Sphere;
  Vec3 center_ = Vec3::Zero();
  double radius_ = 0.0;
  Vec3 lo_ = Vec3::Zero(), hi_ = Vec3::Zero();
  RowMatrixX3d triangles_;
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/operating_region_impl.hpp"
#endif
