// OFF (and its COFF, NOFF, ... variants): read_off and write_off (bemsurg/meshing/mesh_io.hpp).
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "bemsurg/meshing/mesh_io.hpp"
#include "mesh_builder.hpp"
#include "text_tokens.hpp"

namespace bemsurg {

namespace {

using namespace mesh_formats;

TriangleMesh parse_off(const std::string& text, const std::string& path) {
  LineReader reader(text);
  std::vector<std::string_view> tok;
  if (!reader.next_nonempty(tok, '#')) fail(path, 0, "empty file, expected an 'OFF' header");
  const std::string header(tok[0]);
  // Prefixes: ST (texture), C (colour), N (normal), 4 (homogeneous), n (dimension). The first three
  // add columns we skip; the last two change the layout.
  const bool off_like =
      header.size() >= 3 && header.compare(header.size() - 3, 3, "OFF") == 0 && header.find_first_not_of("STCN") >= header.size() - 3;
  if (!off_like) fail(path, reader.line(), "expected an 'OFF' header (or COFF, NOFF, ...), got '" + header + "'");
  std::vector<std::string_view> counts(tok.begin() + 1, tok.end());
  if (!counts.empty() && lower(counts[0]) == "binary") fail(path, reader.line(), "binary OFF is not supported");
  if (counts.empty()) {
    if (!reader.next_nonempty(tok, '#')) fail(path, reader.line(), "missing the vertex and face counts");
    counts = tok;
  }
  if (counts.size() < 2) fail(path, reader.line(), "expected 'vertices faces [edges]' counts");
  const long long nv = to_integer(counts[0], path, reader.line(), "the vertex count");
  const long long nf = to_integer(counts[1], path, reader.line(), "the face count");
  if (nv < 0 || nf < 0 || nv > std::numeric_limits<int>::max())
    fail(path, reader.line(), "invalid counts " + std::to_string(nv) + " " + std::to_string(nf));

  MeshBuilder mesh;
  for (long long v = 0; v < nv; ++v) {
    if (!reader.next_nonempty(tok, '#'))
      fail(path, reader.line(), "file ends after " + std::to_string(v) + " of " + std::to_string(nv) + " vertices");
    if (tok.size() < 3) fail(path, reader.line(), "a vertex needs three coordinates");
    const std::size_t line = reader.line();
    mesh.add_vertex(to_double(tok[0], path, line, "x"), to_double(tok[1], path, line, "y"), to_double(tok[2], path, line, "z"));
  }
  std::vector<long long> polygon;
  for (long long f = 0; f < nf; ++f) {
    if (!reader.next_nonempty(tok, '#'))
      fail(path, reader.line(), "file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
    const std::size_t line = reader.line();
    const long long k = to_integer(tok[0], path, line, "the face's vertex count");
    if (k < 3) fail(path, line, "a face needs at least three vertices, got " + std::to_string(k));
    if (k > static_cast<long long>(tok.size()) - 1)
      fail(path, line, "face announces " + std::to_string(k) + " vertices but lists " + std::to_string(tok.size() - 1));
    polygon.clear();
    for (long long i = 1; i <= k; ++i)
      polygon.push_back(checked_index(to_integer(tok[static_cast<std::size_t>(i)], path, line, "a vertex index"), path, line));
    mesh.add_polygon(polygon, line);  // trailing colour values are ignored
  }
  // Content after the declared faces means the counts lie (a second body would vanish).
  if (reader.next_nonempty(tok, '#'))
    fail(path, reader.line(),
         "unexpected content '" + std::string(tok[0]) + "' after the " + std::to_string(nv) + " vertices and " + std::to_string(nf) +
             " faces the header declares: the counts are wrong or the file is corrupt");
  return mesh.build(path);
}

}  // namespace

TriangleMesh read_off(const std::string& path) { return parse_off(read_file(path), path); }

void write_off(const std::string& path, const TriangleMesh& mesh) {
  std::string out = "OFF\n" + std::to_string(mesh.num_vertices()) + " " + std::to_string(mesh.num_elements()) + " 0\n";
  append_vertex_and_face_lines(out, mesh);
  write_file(path, out);
}

}  // namespace bemsurg
