// STL, ASCII and binary: read_stl and write_stl (bemsurg/meshing/mesh_io.hpp). STL stores a triangle
// soup, three corners per facet; the reader welds the corners into an indexed mesh at the end.
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "bemsurg/mesh/vertex_welding.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/number_text.hpp"
#include "text_tokens.hpp"

namespace bemsurg {

namespace {

using namespace mesh_formats;

std::uint32_t le_u32(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) | (static_cast<std::uint32_t>(b[2]) << 16) |
         (static_cast<std::uint32_t>(b[3]) << 24);
}

float le_f32(const char* p) {
  const std::uint32_t bits = le_u32(p);
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

void parse_stl_binary(const std::string& data, const std::string& path, RowMatrixX3d& V, RowMatrixX3i& F) {
  const std::uint32_t n = le_u32(data.data() + 80);
  const std::size_t expected = 84 + 50 * static_cast<std::size_t>(n);
  if (data.size() < expected)
    fail(path, 0,
         "truncated binary STL: the header announces " + std::to_string(n) + " triangles (" + std::to_string(expected) +
             " bytes) but the file has " + std::to_string(data.size()) + " bytes");
  // More bytes than the count announces: a wrong count would silently drop the rest (a second
  // body vanishes), so refuse it rather than guess which is right.
  if (data.size() > expected) {
    const std::size_t extra = data.size() - expected;
    fail(path, 0,
         "binary STL: the header announces " + std::to_string(n) + " triangles (" + std::to_string(expected) + " bytes) but the file has " +
             std::to_string(data.size()) + " bytes: " + std::to_string(extra) + " bytes (" + std::to_string(extra / 50) +
             " triangles and " + std::to_string(extra % 50) +
             " bytes) follow the declared triangles; the triangle count at byte 80 is wrong or the file is corrupt");
  }
  V.resize(3 * static_cast<Index>(n), 3);
  F.resize(n, 3);
  for (std::uint32_t t = 0; t < n; ++t) {
    const char* rec = data.data() + 84 + 50 * static_cast<std::size_t>(t) + 12;  // skip the facet normal
    for (int k = 0; k < 3; ++k) {
      for (int c = 0; c < 3; ++c) V(3 * t + k, c) = le_f32(rec + 12 * k + 4 * c);
      F(t, k) = static_cast<int>(3 * t + static_cast<std::uint32_t>(k));
    }
  }
}

void parse_stl_ascii(const std::string& text, const std::string& path, RowMatrixX3d& V, RowMatrixX3i& F) {
  std::vector<double> coords;
  LineReader reader(text);
  std::vector<std::string_view> tok;
  bool in_loop = false;
  int loop_vertices = 0;
  std::size_t loop_line = 0;
  while (reader.next_nonempty(tok)) {
    const std::size_t line = reader.line();
    const std::string word = lower(tok[0]);
    if (word == "vertex") {
      if (!in_loop) fail(path, line, "'vertex' outside an 'outer loop'");
      if (tok.size() < 4) fail(path, line, "a 'vertex' line needs three coordinates");
      for (int c = 1; c <= 3; ++c) coords.push_back(to_double(tok[static_cast<std::size_t>(c)], path, line, "a coordinate"));
      ++loop_vertices;
    } else if (word == "outer") {
      if (in_loop) fail(path, line, "'outer loop' inside another loop");
      in_loop = true;
      loop_vertices = 0;
      loop_line = line;
    } else if (word == "endloop") {
      if (!in_loop) fail(path, line, "'endloop' without 'outer loop'");
      if (loop_vertices != 3)
        fail(path, loop_line,
             "facet with " + std::to_string(loop_vertices) + " vertices: STL allows triangles only (the mesh is not a triangle mesh)");
      in_loop = false;
    } else if (word == "solid" || word == "endsolid" || word == "facet" || word == "endfacet") {
      // Structure only; the facet normal is recomputed from the vertex order.
    } else {
      fail(path, line, "unexpected '" + std::string(tok[0]) + "' in ASCII STL");
    }
  }
  if (in_loop) fail(path, loop_line, "unterminated 'outer loop'");
  const Index n = static_cast<Index>(coords.size() / 9);
  V.resize(3 * n, 3);
  F.resize(n, 3);
  for (Index i = 0; i < 3 * n; ++i)
    for (int c = 0; c < 3; ++c) V(i, c) = coords[static_cast<std::size_t>(3 * i + c)];
  for (Index t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) F(t, k) = static_cast<int>(3 * t + k);
}

void put_le_u32(std::string& out, std::uint32_t x) {
  for (int b = 0; b < 4; ++b) out += static_cast<char>((x >> (8 * b)) & 0xFFu);
}

void put_le_f32(std::string& out, double x) {
  const auto f = static_cast<float>(x);
  std::uint32_t bits;
  std::memcpy(&bits, &f, sizeof bits);
  put_le_u32(out, bits);
}

std::string stl_binary(const TriangleMesh& mesh) {
  std::string out = "binary STL written by bemsurg";
  out.resize(80, ' ');
  put_le_u32(out, static_cast<std::uint32_t>(mesh.num_elements()));
  out.reserve(84 + 50 * static_cast<std::size_t>(mesh.num_elements()));
  for (Index f = 0; f < mesh.num_elements(); ++f) {
    for (int c = 0; c < 3; ++c) put_le_f32(out, mesh.normals()(f, c));
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) put_le_f32(out, mesh.vertices()(mesh.faces()(f, k), c));
    out += std::string(2, '\0');  // attribute byte count
  }
  return out;
}

std::string stl_ascii(const TriangleMesh& mesh) {
  std::string out = "solid bemsurg\n";
  const auto xyz = [&out](const auto& row) {
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      append_number(out, row(c));
    }
    out += '\n';
  };
  for (Index f = 0; f < mesh.num_elements(); ++f) {
    out += "facet normal";
    xyz(mesh.normals().row(f));
    out += "  outer loop\n";
    for (int k = 0; k < 3; ++k) {
      out += "    vertex";
      xyz(mesh.vertices().row(mesh.faces()(f, k)));
    }
    out += "  endloop\nendfacet\n";
  }
  return out + "endsolid bemsurg\n";
}

}  // namespace

void write_stl(const std::string& path, const TriangleMesh& mesh, bool binary) {
  if (binary && mesh.num_elements() > static_cast<Index>(0xFFFFFFFFu))
    throw InvalidArgumentError("write_stl '" + path + "': binary STL holds at most 2^32 - 1 triangles");
  write_file(path, binary ? stl_binary(mesh) : stl_ascii(mesh));
}

TriangleMesh read_stl(const std::string& path, double relative_weld_tolerance) {
  const std::string data = read_file(path);
  RowMatrixX3d V;
  RowMatrixX3i F;
  // A binary STL's size is fixed by its triangle count; ASCII files that happen to match are
  // astronomically unlikely, whereas binary files starting with "solid" are common.
  const bool binary_size = data.size() >= 84 && data.size() == 84 + 50 * static_cast<std::size_t>(le_u32(data.data() + 80));
  std::size_t first = data.find_first_not_of(" \t\r\n");
  const bool starts_solid = first != std::string::npos && lower(std::string_view(data).substr(first, 5)) == "solid";
  if (binary_size || !starts_solid) {
    if (data.size() < 84) fail(path, 0, "too short for a binary STL (" + std::to_string(data.size()) + " bytes) and not ASCII STL");
    parse_stl_binary(data, path, V, F);
  } else {
    parse_stl_ascii(data, path, V, F);
  }
  return weld_vertices(V, F, relative_weld_tolerance);
}

}  // namespace bemsurg
