// Wavefront OBJ: read_obj and write_obj (bemsurg/meshing/mesh_io.hpp).
#include <string>
#include <string_view>
#include <vector>

#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/number_text.hpp"
#include "mesh_builder.hpp"
#include "text_tokens.hpp"

namespace bemsurg {

namespace {

using namespace mesh_formats;

TriangleMesh parse_obj(const std::string& text, const std::string& path) {
  MeshBuilder mesh;
  LineReader reader(text);
  std::vector<std::string_view> tok;
  std::vector<long long> polygon;
  while (reader.next_nonempty(tok, '#')) {
    const std::size_t line = reader.line();
    if (tok[0] == "v") {
      if (tok.size() < 4) fail(path, line, "a 'v' line needs three coordinates");
      mesh.add_vertex(to_double(tok[1], path, line, "x"), to_double(tok[2], path, line, "y"), to_double(tok[3], path, line, "z"));
    } else if (tok[0] == "f") {
      if (tok.size() < 4) fail(path, line, "a face needs at least three vertices, got " + std::to_string(tok.size() - 1));
      polygon.clear();
      for (std::size_t k = 1; k < tok.size(); ++k) {
        // 'a', 'a/t', 'a/t/n', 'a//n': only the vertex index matters for a surface mesh.
        const long long i = to_integer(tok[k].substr(0, tok[k].find('/')), path, line, "a vertex index");
        if (i == 0) fail(path, line, "vertex index 0 is invalid (OBJ indices start at 1)");
        const long long v = i > 0 ? i - 1 : mesh.num_vertices() + i;  // negative: relative to the latest vertex
        if (i < 0 && v < 0)
          fail(path, line,
               "relative vertex index " + std::to_string(i) + " reaches before the first vertex (" + std::to_string(mesh.num_vertices()) +
                   " defined so far)");
        polygon.push_back(checked_index(v, path, line));
      }
      mesh.add_polygon(polygon, line);
    }
    // Texture coordinates, normals, groups, materials, lines, ...: not part of the surface.
  }
  return mesh.build(path);
}

}  // namespace

TriangleMesh read_obj(const std::string& path) { return parse_obj(mesh_formats::read_file(path), path); }

void write_obj(const std::string& path, const TriangleMesh& mesh) {
  std::string out =
      "# bemsurg triangle mesh: " + std::to_string(mesh.num_vertices()) + " vertices, " + std::to_string(mesh.num_elements()) + " faces\n";
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    out += 'v';
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      append_number(out, mesh.vertices()(v, c));
    }
    out += '\n';
  }
  for (Index f = 0; f < mesh.num_elements(); ++f) {
    out += 'f';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_integer(out, static_cast<long long>(mesh.faces()(f, k)) + 1);
    }
    out += '\n';
  }
  mesh_formats::write_file(path, out);
}

}  // namespace bemsurg
