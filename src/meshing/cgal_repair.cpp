// The CGAL steps of mesh preparation (src/meshing/cgal_repair.hpp, mesh/mesh_preparation.hpp): hole
// filling and alpha wrapping from CGAL 5.5's Polygon Mesh Processing and 3D Alpha Wrapping
// packages, and distances by its AABB tree. The only file of bemsurg that includes CGAL.
#include "cgal_repair.hpp"

#include "bemsurg/error.hpp"

#ifdef BEMSURG_HAVE_CGAL
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/alpha_wrap_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <vector>
#endif

namespace bemsurg::detail {

#ifdef BEMSURG_HAVE_CGAL
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;

/// Vertices and faces in the Surface_mesh's index order (no garbage: nothing is removed here).
TriangleMesh from_surface_mesh(const SurfaceMesh& sm) {
  RowMatrixX3d v(static_cast<Index>(sm.number_of_vertices()), 3);
  std::vector<Index> index(sm.num_vertices(), -1);
  Index n = 0;
  for (const auto vi : sm.vertices()) {
    const Point& p = sm.point(vi);
    v.row(n) << p.x(), p.y(), p.z();
    index[std::size_t(vi)] = n++;
  }
  RowMatrixX3i f(static_cast<Index>(sm.number_of_faces()), 3);
  Index k = 0;
  for (const auto fi : sm.faces()) {
    int c = 0;
    for (const auto vi : CGAL::vertices_around_face(sm.halfedge(fi), sm)) {
      if (c == 3) throw Error("CGAL returned a face that is not a triangle");
      f(k, c++) = index[std::size_t(vi)];
    }
    ++k;
  }
  return TriangleMesh(std::move(v), std::move(f));
}

}  // namespace

bool cgal_repair_available() { return true; }

namespace {

/// Fills the holes of `sm` shorter than max_length, one border cycle at a time, in the order
/// extract_boundary_cycles finds them (deterministic for a given mesh).
void fill_short_holes(SurfaceMesh& sm, double max_length, OrientedClosedSoup& out) {
  std::vector<SurfaceMesh::Halfedge_index> borders;
  CGAL::Polygon_mesh_processing::extract_boundary_cycles(sm, std::back_inserter(borders));
  out.holes = static_cast<Index>(borders.size());
  for (const auto h : borders) {
    double length = 0.0;
    for (const auto b : CGAL::halfedges_around_face(h, sm))
      length += std::sqrt(CGAL::squared_distance(sm.point(sm.source(b)), sm.point(sm.target(b))));
    std::vector<SurfaceMesh::Face_index> patch;
    std::vector<SurfaceMesh::Vertex_index> added;
    if (length <= max_length)
      CGAL::Polygon_mesh_processing::triangulate_and_refine_hole(sm, h, std::back_inserter(patch), std::back_inserter(added));
    if (length > max_length) {
      ++out.unfilled;
      out.longest_unfilled = std::max(out.longest_unfilled, length);
    } else if (patch.empty()) {
      ++out.failed;  // short, but no triangulation fits its rim (e.g. a rim folded flat)
    } else {
      ++out.filled;
    }
  }
}

}  // namespace

OrientedClosedSoup cgal_orient_and_close(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, double max_hole_length) {
  std::vector<Point> points;
  points.reserve(static_cast<std::size_t>(vertices.rows()));
  for (Index i = 0; i < vertices.rows(); ++i) points.emplace_back(vertices(i, 0), vertices(i, 1), vertices(i, 2));
  std::vector<std::array<std::size_t, 3>> polygons(static_cast<std::size_t>(faces.rows()));
  for (Index e = 0; e < faces.rows(); ++e)
    for (int c = 0; c < 3; ++c) polygons[std::size_t(e)][std::size_t(c)] = static_cast<std::size_t>(faces(e, c));
  const std::size_t input_points = points.size();
  CGAL::Polygon_mesh_processing::orient_polygon_soup(points, polygons);
  OrientedClosedSoup out;
  out.duplicated_vertices = static_cast<Index>(points.size() - input_points);
  // A copy made at a non-manifold place sits where its original is: compare corners by position.
  out.reversed.assign(polygons.size(), 0);
  for (std::size_t e = 0; e < polygons.size(); ++e) {
    const auto& q = polygons[e];
    const Point a(vertices(faces(Index(e), 0), 0), vertices(faces(Index(e), 0), 1), vertices(faces(Index(e), 0), 2));
    const Point b(vertices(faces(Index(e), 1), 0), vertices(faces(Index(e), 1), 1), vertices(faces(Index(e), 1), 2));
    for (int c = 0; c < 3; ++c)
      if (points[q[std::size_t(c)]] == a) out.reversed[e] = !(points[q[std::size_t((c + 1) % 3)]] == b);
  }
  SurfaceMesh sm;
  CGAL::Polygon_mesh_processing::polygon_soup_to_polygon_mesh(points, polygons, sm);
  fill_short_holes(sm, max_hole_length, out);
  out.mesh = from_surface_mesh(sm);
  return out;
}

TriangleMesh cgal_alpha_wrap(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, double alpha, double offset) {
  std::vector<Point> points;
  points.reserve(static_cast<std::size_t>(vertices.rows()));
  for (Index i = 0; i < vertices.rows(); ++i) points.emplace_back(vertices(i, 0), vertices(i, 1), vertices(i, 2));
  std::vector<std::array<std::size_t, 3>> triangles(static_cast<std::size_t>(faces.rows()));
  for (Index e = 0; e < faces.rows(); ++e)
    for (int c = 0; c < 3; ++c) triangles[std::size_t(e)][std::size_t(c)] = static_cast<std::size_t>(faces(e, c));
  SurfaceMesh wrap;
  CGAL::alpha_wrap_3(points, triangles, alpha, offset, wrap);
  return from_surface_mesh(wrap);
}

Eigen::VectorXd cgal_distances(const RowMatrixX3d& points, const RowMatrixX3d& vertices, const RowMatrixX3i& faces) {
  using Triangle = Kernel::Triangle_3;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
  using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  std::vector<Triangle> triangles;
  triangles.reserve(static_cast<std::size_t>(faces.rows()));
  const auto point = [&](Index v) { return Point(vertices(v, 0), vertices(v, 1), vertices(v, 2)); };
  for (Index e = 0; e < faces.rows(); ++e) {
    const Triangle t(point(faces(e, 0)), point(faces(e, 1)), point(faces(e, 2)));
    if (!t.is_degenerate()) triangles.push_back(t);
  }
  if (triangles.empty()) throw InvalidMeshError("no non-degenerate triangle to measure a distance to");
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  Eigen::VectorXd d(points.rows());
  for (Index i = 0; i < points.rows(); ++i) d(i) = std::sqrt(tree.squared_distance(Point(points(i, 0), points(i, 1), points(i, 2))));
  return d;
}

std::vector<char> cgal_inside(const RowMatrixX3d& points, const TriangleMesh& mesh) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> ids;
  for (Index i = 0; i < mesh.num_vertices(); ++i)
    ids.push_back(sm.add_vertex(Point(mesh.vertices()(i, 0), mesh.vertices()(i, 1), mesh.vertices()(i, 2))));
  for (Index e = 0; e < mesh.num_elements(); ++e)
    sm.add_face(ids[std::size_t(mesh.faces()(e, 0))], ids[std::size_t(mesh.faces()(e, 1))], ids[std::size_t(mesh.faces()(e, 2))]);
  const CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel> side(sm);
  std::vector<char> inside(static_cast<std::size_t>(points.rows()));
  for (Index i = 0; i < points.rows(); ++i)
    inside[std::size_t(i)] = side(Point(points(i, 0), points(i, 1), points(i, 2))) != CGAL::ON_UNBOUNDED_SIDE;
  return inside;
}

#else  // no CGAL in this build: mesh_preparation.cpp checks cgal_repair_available() first

bool cgal_repair_available() { return false; }
OrientedClosedSoup cgal_orient_and_close(const RowMatrixX3d&, const RowMatrixX3i&, double) {
  throw Error("this build of bemsurg has no CGAL (BEMSURG_WITH_PREPARE=OFF)");
}
TriangleMesh cgal_alpha_wrap(const RowMatrixX3d&, const RowMatrixX3i&, double, double) {
  throw Error("this build of bemsurg has no CGAL (BEMSURG_WITH_PREPARE=OFF)");
}
Eigen::VectorXd cgal_distances(const RowMatrixX3d&, const RowMatrixX3d&, const RowMatrixX3i&) {
  throw Error("this build of bemsurg has no CGAL (BEMSURG_WITH_PREPARE=OFF)");
}
std::vector<char> cgal_inside(const RowMatrixX3d&, const TriangleMesh&) {
  throw Error("this build of bemsurg has no CGAL (BEMSURG_WITH_PREPARE=OFF)");
}

#endif

}  // namespace bemsurg::detail
