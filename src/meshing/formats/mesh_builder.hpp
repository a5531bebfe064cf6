// Private to the mesh readers (src/meshing/formats/): vertices and polygons as a file lists them,
// turned into a TriangleMesh once every vertex is known.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg::mesh_formats {

/// Collects vertices and polygons, remembering the line of each polygon so an out-of-range index
/// or an untriangulable polygon can be reported where it was written. Polygons become triangles
/// in build(), once every vertex is known: a convex polygon as a fan from its first corner (an
/// OBJ quad becomes two consecutive elements), a non-convex one by ear clipping, which respects
/// its concave corners (a fan would put an inside-out triangle outside the face).
class MeshBuilder {
 public:
  Index num_vertices() const { return static_cast<Index>(coords_.size() / 3); }
  void add_vertex(double x, double y, double z) { coords_.insert(coords_.end(), {x, y, z}); }
  void add_polygon(const std::vector<long long>& polygon, std::size_t line);

  /// Indices are checked here (not by TriangleMesh) so the message can carry the file position;
  /// `face_word` names a polygon in messages ("face", "polygon").
  TriangleMesh build(const std::string& path, const char* face_word = "face") const;

 private:
  Vec3 vertex(int v) const;
  void check_indices(const std::string& path, const char* face_word) const;
  void triangulate(const int* poly, std::size_t n, const std::string& path, std::size_t line, const char* face_word,
                   std::vector<int>& out) const;

  std::vector<double> coords_;
  std::vector<int> corners_;        // polygon corners, one polygon after another
  std::vector<std::size_t> sizes_;  // corners per polygon
  std::vector<std::size_t> lines_;  // file position of each polygon
};

}  // namespace bemsurg::mesh_formats
