// Polygons to triangles for the mesh readers (mesh_builder.hpp).
#include "mesh_builder.hpp"

#include <cmath>
#include <cstddef>

#include "text_tokens.hpp"

namespace bemsurg::mesh_formats {

namespace {

using Point2 = Eigen::Vector2d;

/// Twice the signed area of (a, b, c): positive when counter-clockwise.
double cross(const Point2& a, const Point2& b, const Point2& c) { return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x(); }

bool inside(const Point2& p, const Point2& a, const Point2& b, const Point2& c) {
  return cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0;
}

/// Convex (flat corners allowed) in the counter-clockwise orientation.
bool is_convex(const std::vector<Point2>& q) {
  const std::size_t n = q.size();
  bool convex = true;
  for (std::size_t k = 0; k < n && convex; ++k) convex = cross(q[(k + n - 1) % n], q[k], q[(k + 1) % n]) >= 0.0;
  return convex;
}

/// Ear clipping: cut off a convex corner whose triangle holds no other remaining corner, until
/// three remain. O(n^2) per polygon, which is fine for the polygons of a surface mesh. False if
/// the polygon crosses or folds onto itself in its plane (no ear, or an inside-out last triangle).
bool clip_ears(const int* poly, const std::vector<Point2>& q, std::vector<int>& out) {
  const std::size_t n = q.size();
  std::vector<std::size_t> left(n);
  for (std::size_t k = 0; k < n; ++k) left[k] = k;
  while (left.size() > 3) {
    bool clipped = false;
    for (std::size_t i = 0; i < left.size() && !clipped; ++i) {
      const std::size_t a = left[(i + left.size() - 1) % left.size()], b = left[i], c = left[(i + 1) % left.size()];
      if (!(cross(q[a], q[b], q[c]) > 0.0)) continue;  // reflex or flat corner
      bool empty = true;
      for (std::size_t j : left)
        if (j != a && j != b && j != c && inside(q[j], q[a], q[b], q[c])) {
          empty = false;
          break;
        }
      if (!empty) continue;
      out.insert(out.end(), {poly[a], poly[b], poly[c]});
      left.erase(left.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
    }
    if (!clipped) return false;
  }
  if (!(cross(q[left[0]], q[left[1]], q[left[2]]) > 0.0)) return false;
  out.insert(out.end(), {poly[left[0]], poly[left[1]], poly[left[2]]});
  return true;
}

}  // namespace

void MeshBuilder::add_polygon(const std::vector<long long>& polygon, std::size_t line) {
  for (long long v : polygon) corners_.push_back(static_cast<int>(v));
  sizes_.push_back(polygon.size());
  lines_.push_back(line);
}

Vec3 MeshBuilder::vertex(int v) const {
  const std::size_t i = 3 * static_cast<std::size_t>(v);
  return {coords_[i], coords_[i + 1], coords_[i + 2]};
}

void MeshBuilder::check_indices(const std::string& path, const char* face_word) const {
  const Index nv = num_vertices();
  std::size_t first = 0;
  for (std::size_t p = 0; p < sizes_.size(); first += sizes_[p], ++p)
    for (std::size_t k = 0; k < sizes_[p]; ++k) {
      const int v = corners_[first + k];
      if (v < 0 || v >= nv)
        fail(path, lines_[p],
             std::string(face_word) + " refers to vertex " + std::to_string(v) + " (0-based), but the file has " + std::to_string(nv) +
                 " vertices");
    }
}

TriangleMesh MeshBuilder::build(const std::string& path, const char* face_word) const {
  check_indices(path, face_word);
  const Index nv = num_vertices();
  std::vector<int> triangles;
  triangles.reserve(3 * corners_.size());
  std::size_t first = 0;
  for (std::size_t p = 0; p < sizes_.size(); first += sizes_[p], ++p)
    triangulate(&corners_[first], sizes_[p], path, lines_[p], face_word, triangles);
  RowMatrixX3d V(nv, 3);
  for (Index v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) V(v, k) = coords_[static_cast<std::size_t>(3 * v + k)];
  const Index nf = static_cast<Index>(triangles.size() / 3);
  RowMatrixX3i F(nf, 3);
  for (Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) F(f, k) = triangles[static_cast<std::size_t>(3 * f + k)];
  return TriangleMesh(std::move(V), std::move(F));
}

void MeshBuilder::triangulate(const int* poly, std::size_t n, const std::string& path, std::size_t line, const char* face_word,
                              std::vector<int>& out) const {
  const auto fan = [&] {
    for (std::size_t k = 1; k + 1 < n; ++k) out.insert(out.end(), {poly[0], poly[k], poly[k + 1]});
  };
  if (n <= 3) return fan();
  // Newell's normal: the polygon's area vector, robust for non-planar and concave polygons.
  Vec3 normal = Vec3::Zero();
  for (std::size_t k = 0; k < n; ++k) normal += vertex(poly[k]).cross(vertex(poly[(k + 1) % n]));
  if (!(normal.norm() > 0.0) || !normal.allFinite()) return fan();  // degenerate: the validator names it
  normal.normalize();
  // In-plane coordinates: a 2D polygon, counter-clockwise about the normal.
  const Vec3 ex = (std::abs(normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(normal).normalized();
  const Vec3 ey = normal.cross(ex);
  std::vector<Point2> q(n);
  for (std::size_t k = 0; k < n; ++k) q[k] = {vertex(poly[k]).dot(ex), vertex(poly[k]).dot(ey)};
  // Convex: the fan, as before, so element numbering of such files is unchanged.
  if (is_convex(q)) return fan();
  if (!clip_ears(poly, q, out))
    fail(path, line,
         std::string(face_word) + " with " + std::to_string(n) +
             " corners cannot be triangulated: it crosses itself (or folds onto itself) in its plane");
}

}  // namespace bemsurg::mesh_formats
