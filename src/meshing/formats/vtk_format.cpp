// Legacy VTK, ASCII POLYDATA: read_vtk and write_vtk (bemsurg/meshing/mesh_io.hpp). The writer adds
// named per-element and per-vertex fields that ParaView opens directly.
#include <algorithm>
#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/number_text.hpp"
#include "mesh_builder.hpp"
#include "text_tokens.hpp"

namespace bemsurg {

namespace {

using namespace mesh_formats;

/// Reads the sections of a POLYDATA body (after its 4 header lines) as token streams: values may
/// wrap over lines.
class VtkSections {
 public:
  VtkSections(LineReader& reader, const std::string& path) : reader_(reader), path_(path) {}

  /// The next value of the current section, read across line ends.
  std::string_view next_token(const char* what) {
    while (next_value_ >= values_.size()) {
      if (!reader_.next(values_)) fail(path_, reader_.line(), std::string("unexpected end of file while reading ") + what);
      next_value_ = 0;
    }
    return values_[next_value_++];
  }

  /// POINTS n: 3 n coordinates.
  void read_points(long long n, MeshBuilder& mesh) {
    restart();
    for (long long i = 0; i < n; ++i) {
      std::array<double, 3> x{};
      for (auto& c : x) c = to_double(next_token("POINTS"), path_, reader_.line(), "a coordinate");
      mesh.add_vertex(x[0], x[1], x[2]);
    }
  }

  /// POLYGONS, VERTICES or LINES n size: n cells 'k i1 ... ik'; only polygons are surface.
  void read_cells(long long n, bool polygons, MeshBuilder& mesh) {
    restart();
    std::vector<long long> polygon;
    for (long long i = 0; i < n; ++i) {
      const long long k = to_integer(next_token("a cell"), path_, reader_.line(), "a cell size");
      const std::size_t cell_line = reader_.line();
      polygon.clear();
      for (long long j = 0; j < k; ++j)
        polygon.push_back(checked_index(to_integer(next_token("a cell"), path_, reader_.line(), "a point index"), path_, reader_.line()));
      if (!polygons) continue;  // points and lines are not surface
      if (k < 3) fail(path_, cell_line, "a polygon needs at least three points, got " + std::to_string(k));
      mesh.add_polygon(polygon, cell_line);
    }
  }

 private:
  void restart() {
    values_.clear();
    next_value_ = 0;
  }

  LineReader& reader_;
  const std::string& path_;
  std::vector<std::string_view> values_;
  std::size_t next_value_ = 0;
};

TriangleMesh parse_vtk(const std::string& text, const std::string& path) {
  LineReader reader(text);
  std::vector<std::string_view> tok;
  if (!reader.next(tok) || tok.size() < 2 || tok[0] != "#" || lower(tok[1]) != "vtk")
    fail(path, 1, "not a legacy VTK file (the first line must be '# vtk DataFile Version ...')");
  reader.next(tok);  // title: free text
  if (!reader.next_nonempty(tok) || lower(tok[0]) != "ascii") fail(path, reader.line(), "only ASCII legacy VTK is supported");
  if (!reader.next_nonempty(tok) || tok.size() < 2 || lower(tok[0]) != "dataset" || lower(tok[1]) != "polydata")
    fail(path, reader.line(), "only 'DATASET POLYDATA' is supported");

  MeshBuilder mesh;
  VtkSections sections(reader, path);
  while (reader.next_nonempty(tok)) {
    const std::string section = lower(tok[0]);
    const std::size_t line = reader.line();
    if (section == "points") {
      if (tok.size() < 2) fail(path, line, "'POINTS' needs a count");
      sections.read_points(to_integer(tok[1], path, line, "the point count"), mesh);
    } else if (section == "polygons" || section == "vertices" || section == "lines") {
      if (tok.size() < 2) fail(path, line, "'" + std::string(tok[0]) + "' needs a count");
      sections.read_cells(to_integer(tok[1], path, line, "the cell count"), section == "polygons", mesh);
    } else if (section == "cell_data" || section == "point_data") {
      break;  // attributes follow; the mesh is complete
    } else {
      fail(path, line, "unsupported POLYDATA section '" + std::string(tok[0]) + "'");
    }
  }
  return mesh.build(path, "polygon");
}

void put_field(std::string& out, const MeshField& field, Index rows, const char* where, const std::string& path) {
  if (field.name.empty() || std::any_of(field.name.begin(), field.name.end(), [](char c) { return is_space(c); }))
    throw InvalidArgumentError("write_vtk '" + path + "': field name '" + field.name + "' must be non-empty without whitespace");
  if (field.values.rows() != rows || (field.values.cols() != 1 && field.values.cols() != 3))
    throw InvalidArgumentError("write_vtk '" + path + "': " + where + " field '" + field.name + "' is " +
                               std::to_string(field.values.rows()) + " x " + std::to_string(field.values.cols()) + ", expected " +
                               std::to_string(rows) + " x 3 (vectors) or " + std::to_string(rows) + " x 1 (scalars)");
  if (field.values.cols() == 3) {
    out += "VECTORS " + field.name + " double\n";
  } else {
    out += "SCALARS " + field.name + " double 1\nLOOKUP_TABLE default\n";
  }
  for (Index i = 0; i < rows; ++i) {
    for (Index c = 0; c < field.values.cols(); ++c) {
      if (c > 0) out += ' ';
      append_number(out, field.values(i, c));
    }
    out += '\n';
  }
}

}  // namespace

TriangleMesh read_vtk(const std::string& path) { return parse_vtk(read_file(path), path); }

void write_vtk(const std::string& path, const TriangleMesh& mesh, const std::vector<MeshField>& cell_fields,
               const std::vector<MeshField>& point_fields, const std::string& title) {
  std::string clean_title = title.substr(0, 255);  // one line of at most 256 characters
  std::replace(clean_title.begin(), clean_title.end(), '\n', ' ');
  std::string out = "# vtk DataFile Version 3.0\n" + clean_title + "\nASCII\nDATASET POLYDATA\n";
  const Index nv = mesh.num_vertices(), nf = mesh.num_elements();
  out += "POINTS " + std::to_string(nv) + " double\n";
  for (Index v = 0; v < nv; ++v) {
    for (int c = 0; c < 3; ++c) {
      if (c > 0) out += ' ';
      append_number(out, mesh.vertices()(v, c));
    }
    out += '\n';
  }
  out += "POLYGONS " + std::to_string(nf) + " " + std::to_string(4 * nf) + "\n";
  for (Index f = 0; f < nf; ++f) {
    out += '3';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_integer(out, static_cast<long long>(mesh.faces()(f, k)));
    }
    out += '\n';
  }
  if (!cell_fields.empty()) {
    out += "CELL_DATA " + std::to_string(nf) + "\n";
    for (const MeshField& field : cell_fields) put_field(out, field, nf, "cell", path);
  }
  if (!point_fields.empty()) {
    out += "POINT_DATA " + std::to_string(nv) + "\n";
    for (const MeshField& field : point_fields) put_field(out, field, nv, "point", path);
  }
  write_file(path, out);
}

}  // namespace bemsurg
