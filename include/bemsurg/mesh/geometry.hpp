// bemsurg/mesh/geometry.hpp: the geometry of one triangle that every module shares.
//
// One definition of each figure, so that the quadrature's near/far decision, the assembler's
// precomputed geometry, the cutter's checks and the mesh's cached diameters agree to the last
// bit (they compare the same expressions). Small and inline: these run inside the assembly and
// quadrature loops.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "bemsurg/constants.hpp"  // numbers::pi, which users of this header have always had
#include "bemsurg/types.hpp"

namespace bemsurg {

/// Closest point to p on the triangle (a, b, c) (Ericson, Real-Time Collision Detection, 2005,
/// §5.1.5): the Voronoi regions of the vertices, then the edges, else the face (barycentric
/// coordinates).
inline Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// Distance from p to the triangle (a, b, c).
inline double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  return (p - closest_point_on_triangle(p, a, b, c)).norm();
}

/// The smallest interior angle of the triangle (a, b, c), in degrees: 60 for an equilateral one,
/// 0 for a degenerate one. atan2(|u x w|, u . w) rather than acos of the cosine: acos loses half
/// the digits near 0 and 180 degrees, exactly where slivers are judged.
inline double smallest_angle_degrees(const Vec3& a, const Vec3& b, const Vec3& c) {
  const std::array<Vec3, 3> corner{{a, b, c}};
  const double degrees_per_radian = 180.0 / numbers::pi;
  double smallest = 180.0;
  for (std::size_t k = 0; k < 3; ++k) {
    const Vec3 u = corner[(k + 1) % 3] - corner[k];
    const Vec3 w = corner[(k + 2) % 3] - corner[k];
    smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)) * degrees_per_radian);
  }
  return smallest;
}

/// The element diameter h: the longest edge (the quadrature's distance / diameter ratios,
/// docs/design.md §4, and TriangleMesh::diameter).
inline double element_diameter(const Vec3& a, const Vec3& b, const Vec3& c) {
  return std::sqrt(std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()}));
}

/// The mean of the three edge lengths: the element size of mesh grading (mesh_quality.hpp,
/// docs/graded.md).
inline double mean_edge_length(const Vec3& a, const Vec3& b, const Vec3& c) {
  return ((b - a).norm() + (c - b).norm() + (a - c).norm()) / 3.0;
}

}  // namespace bemsurg
