// bemsurg/mesh/mesh_generators.hpp: closed, outward-oriented meshes of simple solids.
//
// The closed-form test problems (docs/design.md §8) need boxes, spheres, ellipsoids and hollow
// spheres whose refinement is controlled, and the contact problems need a block that is fine
// under the tool and coarse elsewhere. Every generator returns a mesh that validate_mesh accepts:
// closed, 2-manifold, normals out of the material, welded (shared vertices along box edges).
#pragma once

#include <array>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Axis-aligned box [lo, hi] with each face divided into a structured grid of n1 x n2 quads
/// (nx along x, ny along y, nz along z), each quad split into two triangles. The diagonals
/// alternate in a checkerboard pattern, so the mesh has no preferred diagonal direction and is
/// symmetric about the box's mid-planes when the counts are even: a loaded face then deforms
/// symmetrically. Faces: 4 (nx ny + ny nz + nz nx); vertices: 2 (nx ny + ny nz + nz nx) + 2.
/// Throws InvalidMeshError if lo >= hi in some coordinate or a count is below 1.
TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi, int nx, int ny, int nz);

/// Box whose surface follows the tensor-product grid lines xs x ys x zs (strictly increasing,
/// at least two values each, any spacing): conforming on all six faces, with the same
/// checkerboard diagonals as box_mesh. The box is [xs.front(), xs.back()] x ...
TriangleMesh box_mesh_from_grid(const std::vector<double>& xs, const std::vector<double>& ys, const std::vector<double>& zs);

/// Strictly increasing coordinates from lo to hi with spacing h_min near `focus` (which is one
/// of the coordinates; it is clamped into [lo, hi]), uniform within fine_half_width of the focus,
/// then growing geometrically away from it by a ratio of at most `growth` up to h_max.
/// Guarantees, on each side of the focus longer than a few h_min: every spacing lies in
/// [h_min, h_max] and consecutive spacings differ by a factor of at most `growth`. To end
/// exactly at lo and hi, the graded part of each side uses the largest ratio q <= growth that
/// fits (so the transition can be a little gentler than asked). A side shorter than that is
/// divided uniformly with the spacing closest to h_min.
/// Throws InvalidMeshError unless lo < hi, 0 < h_min <= h_max and growth >= 1.
std::vector<double> graded_coordinates(double lo, double hi, double focus, double h_min, double h_max, double growth,
                                       double fine_half_width = 0.0);

/// Sphere by subdividing an icosahedron `subdivisions` times (each triangle into four, new
/// vertices projected onto the sphere): 20 * 4^s faces, 10 * 4^s + 2 vertices, nearly uniform
/// element size. The polyhedron is inscribed, so area and volume converge from below, O(h^2).
TriangleMesh icosphere_mesh(const Vec3& center, double radius, int subdivisions);

/// Ellipsoid with the given semi-axes along x, y, z: an icosphere scaled axis by axis (which
/// keeps the orientation, since all factors are positive).
TriangleMesh ellipsoid_mesh(const Vec3& center, const Vec3& semi_axes, int subdivisions);

/// Hollow sphere (material between inner_radius and outer_radius): an outward outer shell
/// (faces first) and an inner shell with reversed faces, whose normals point into the cavity,
/// i.e. out of the material (docs/design.md §2). Two shells; the Lamé test problem of docs/design.md §8.
TriangleMesh hollow_sphere_mesh(const Vec3& center, double inner_radius, double outer_radius, int subdivisions_inner,
                                int subdivisions_outer);

/// The faces of a followed by those of b (b's vertex indices shifted by a's vertex count). No
/// welding: the two meshes become separate shells.
TriangleMesh merge_meshes(const TriangleMesh& a, const TriangleMesh& b);

/// The same surface with every face's vertex order reversed (normals negated).
TriangleMesh flip_orientation(const TriangleMesh& mesh);

namespace detail {
/// A mesh from vertex and face lists: the generators' last step, shared with the organ samples (meshing/).
TriangleMesh to_mesh(const std::vector<Vec3>& v, const std::vector<std::array<int, 3>>& f);
}  // namespace detail

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/mesh_generators_impl.hpp"
#endif
