// bemsurg/meshing/implicit_surface.hpp: the zero level set of a signed function as a triangle mesh,
// the way a segmentation tool's marching cubes turns a labelled volume into a surface
// (docs/organs.md).
//
// The function f is negative inside the body and positive outside. It is sampled at the nodes of
// a regular grid of cubic cells; each cell is split into six tetrahedra along its main diagonal
// (the Kuhn or Freudenthal triangulation: every tetrahedron runs from the cell's lowest corner to
// its highest along one order of the three axes, so neighbouring cells' tetrahedra meet face to
// face), and within each tetrahedron the surface is the plane through the points where f changes
// sign on its edges (marching tetrahedra: one or two triangles, no ambiguous case). Every grid edge
// that f crosses gets exactly one vertex, shared by all the tetrahedra around it, so the result is
// closed, 2-manifold and indexed; triangles are ordered so their normals point to where f > 0. A
// node where f == 0 counts as outside, and a crossing is kept at least 1/100 of an edge from either
// node, so no vertex lands on a node (two crossings would coincide there) and the worst triangle's
// aspect ratio stays bounded (slivers remain, as in any marching-cubes surface).
//
// The grid is swept one layer of cells at a time, so memory grows with the surface (the output)
// and one layer of nodes, not with the grid's volume: 500,000 triangles take a few seconds.
#pragma once

#include <functional>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// A signed function of position: negative inside the body, positive outside, zero on its surface.
using ImplicitFunction = std::function<double(const Vec3&)>;

/// The surface f = 0 sampled on the grid of cubic cells of edge `cell_size` whose first node is
/// `lo` and which covers `hi` (marching tetrahedra, above): closed, 2-manifold, outward-oriented
/// (normals towards f > 0), deterministic. Every grid node on the box's boundary must be outside
/// (f >= 0), else the surface would leave the box open: throws InvalidArgumentError naming the
/// node. Also throws for a non-positive cell size, lo >= hi, a grid of more than 2^31 nodes or a
/// non-finite value of f (naming the point). An f that is positive everywhere gives an empty mesh.
TriangleMesh sample_implicit_surface(const ImplicitFunction& f, const Vec3& lo, const Vec3& hi, double cell_size);

/// The cell size for which sample_implicit_surface returns about `triangles` triangles (within a
/// few per cent for a smooth surface whose features the cells resolve): the count falls as
/// 1 / cell_size^2, so one pilot sampling at a coarser cell (about triangles / 16 of them) fixes
/// the constant. Throws InvalidArgumentError for triangles < 100 or a surface the pilot misses.
double cell_size_for_triangle_count(const ImplicitFunction& f, const Vec3& lo, const Vec3& hi, Index triangles);

/// The first point where f changes sign along the ray from `origin` (f(origin) must be negative)
/// in `direction`, within `max_distance`: stepped in 1/256 of max_distance, then bisected to
/// machine precision. For placing supports and tools on an implicit organ. Throws
/// InvalidArgumentError if f(origin) >= 0 or f stays negative up to max_distance.
Vec3 implicit_ray_crossing(const ImplicitFunction& f, const Vec3& origin, const Vec3& direction, double max_distance);

}  // namespace bemsurg
