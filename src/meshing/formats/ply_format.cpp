// PLY, ASCII or binary in either byte order: read_ply; write_ply writes ASCII (bemsurg/meshing/mesh_io.hpp).
//
// The steps: the text header (elements and their properties), a check that the declared counts
// can fit the data, the layout (which properties are x, y, z and the face's index list), then
// the element instances, read as ASCII tokens or binary values by the same loop.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
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

enum class PlyType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct PlyProperty {
  std::string name;
  bool is_list = false;
  PlyType count_type = PlyType::UInt8;  // lists only
  PlyType type = PlyType::Float32;      // value type, or list item type
};

struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
  std::size_t line = 0;  // of its 'element' line, for messages
};

/// What the text header declares; the data start right after its 'end_header' line.
struct PlyHeader {
  std::vector<PlyElement> elements;
  std::string format;          // ascii, binary_little_endian or binary_big_endian
  std::size_t data_start = 0;  // byte offset of the first value (may be past the end)
  std::size_t last_line = 0;   // the header's last line, for messages and ASCII line numbers
};

/// Where the mesh is in the elements: the vertex and face elements, the property index of each
/// coordinate, and that of the face's index list (-1 without a face element).
struct PlyLayout {
  const PlyElement* vertex = nullptr;
  const PlyElement* face = nullptr;
  std::array<int, 3> xyz{{-1, -1, -1}};
  int index_list = -1;
};

bool ply_type(std::string_view name, PlyType& type) {
  static const std::array<std::pair<const char*, PlyType>, 16> table{{
      {"char", PlyType::Int8},
      {"int8", PlyType::Int8},
      {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},
      {"short", PlyType::Int16},
      {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16},
      {"uint16", PlyType::UInt16},
      {"int", PlyType::Int32},
      {"int32", PlyType::Int32},
      {"uint", PlyType::UInt32},
      {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32},
      {"float32", PlyType::Float32},
      {"double", PlyType::Float64},
      {"float64", PlyType::Float64},
  }};
  for (const auto& [n, t] : table)
    if (name == n) {
      type = t;
      return true;
    }
  return false;
}

std::size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::Int8:
    case PlyType::UInt8: return 1;
    case PlyType::Int16:
    case PlyType::UInt16: return 2;
    case PlyType::Int32:
    case PlyType::UInt32:
    case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 0;
}

/// Reads binary PLY values in either byte order into doubles (exact for every PLY integer type).
class BinaryReader {
 public:
  BinaryReader(const std::string& data, std::size_t pos, bool big_endian, const std::string& path)
      : data_(data), pos_(pos), big_endian_(big_endian), path_(path) {}

  double read(PlyType t, const char* what) {
    const std::size_t n = ply_size(t);
    if (pos_ + n > data_.size()) fail(path_, 0, std::string("unexpected end of binary data while reading ") + what);
    unsigned char b[8];
    std::memcpy(b, data_.data() + pos_, n);
    pos_ += n;
    // Assemble as little endian in memory independently of the host's byte order.
    const bool host_little = [] {
      const std::uint16_t probe = 1;
      unsigned char c;
      std::memcpy(&c, &probe, 1);
      return c == 1;
    }();
    if (big_endian_ == host_little) std::reverse(b, b + n);
    switch (t) {
      case PlyType::Int8: return load<std::int8_t>(b);
      case PlyType::UInt8: return load<std::uint8_t>(b);
      case PlyType::Int16: return load<std::int16_t>(b);
      case PlyType::UInt16: return load<std::uint16_t>(b);
      case PlyType::Int32: return load<std::int32_t>(b);
      case PlyType::UInt32: return load<std::uint32_t>(b);
      case PlyType::Float32: return load<float>(b);
      case PlyType::Float64: return load<double>(b);
    }
    return 0.0;
  }

  std::size_t position() const { return pos_; }

 private:
  /// The value of type T whose bytes (already in host order) start at b.
  template <typename T>
  static double load(const unsigned char* b) {
    T v;
    std::memcpy(&v, b, sizeof v);
    return static_cast<double>(v);
  }

  const std::string& data_;
  std::size_t pos_;
  bool big_endian_;
  const std::string& path_;
};

/// "3 vertex, 1 face": the declared counts, for messages.
std::string element_counts(const std::vector<PlyElement>& elements) {
  std::string out;
  for (const auto& e : elements) out += (out.empty() ? "" : ", ") + std::to_string(e.count) + " " + e.name;
  return out;
}

/// PLY values arrive as doubles; an index or a list length must be a whole number in int range
/// (and the check must come before the cast, which is undefined for out-of-range values).
long long whole_number(double v, const std::string& path, std::size_t line, const char* what) {
  if (!(v >= static_cast<double>(std::numeric_limits<int>::min()) && v <= static_cast<double>(std::numeric_limits<int>::max())) ||
      v != std::floor(v))
    fail(path, line, std::string("invalid ") + what + " " + number_text(v));
  return static_cast<long long>(v);
}

/// One 'property' line: a scalar ('property float x') or a list ('property list uchar int ...').
PlyProperty parse_property(const std::vector<std::string_view>& tok, const std::string& path, std::size_t line) {
  PlyProperty prop;
  if (tok.size() >= 5 && tok[1] == "list") {
    prop.is_list = true;
    if (!ply_type(tok[2], prop.count_type) || !ply_type(tok[3], prop.type))
      fail(path, line, "unknown PLY list types '" + std::string(tok[2]) + " " + std::string(tok[3]) + "'");
    prop.name = std::string(tok[4]);
  } else if (tok.size() >= 3 && tok[1] != "list") {
    if (!ply_type(tok[1], prop.type)) fail(path, line, "unknown PLY type '" + std::string(tok[1]) + "'");
    prop.name = std::string(tok[2]);
  } else {
    fail(path, line, "malformed 'property' line");
  }
  return prop;
}

/// The header is text up to and including the 'end_header' line; binary data starts right after.
PlyHeader parse_ply_header(const std::string& data, const std::string& path) {
  PlyHeader h;
  std::size_t& pos = h.data_start;
  std::size_t& line = h.last_line;
  bool ended = false;
  std::vector<std::string_view> tok;
  while (pos < data.size() && !ended) {
    std::size_t end = data.find('\n', pos);
    if (end == std::string::npos) end = data.size();
    LineReader(std::string_view(data).substr(pos, end - pos)).next(tok);
    pos = end + 1;
    ++line;
    if (line == 1) {
      if (tok.empty() || tok[0] != "ply") fail(path, 1, "not a PLY file (the first line must be 'ply')");
      continue;
    }
    if (tok.empty() || tok[0] == "comment" || tok[0] == "obj_info") continue;
    if (tok[0] == "format") {
      if (tok.size() < 2) fail(path, line, "'format' needs a value");
      h.format = std::string(tok[1]);
      if (h.format != "ascii" && h.format != "binary_little_endian" && h.format != "binary_big_endian")
        fail(path, line, "unknown PLY format '" + h.format + "'");
    } else if (tok[0] == "element") {
      if (tok.size() < 3) fail(path, line, "'element' needs a name and a count");
      const long long count = to_integer(tok[2], path, line, "the element count");
      if (count < 0) fail(path, line, "negative element count");
      h.elements.push_back({std::string(tok[1]), count, {}, line});
    } else if (tok[0] == "property") {
      if (h.elements.empty()) fail(path, line, "'property' before any 'element'");
      h.elements.back().properties.push_back(parse_property(tok, path, line));
    } else if (tok[0] == "end_header") {
      ended = true;
    } else {
      fail(path, line, "unexpected '" + std::string(tok[0]) + "' in the PLY header");
    }
  }
  if (!ended) fail(path, line, "the PLY header has no 'end_header'");
  if (h.format.empty()) fail(path, line, "the PLY header has no 'format' line");
  return h;
}

/// An instance with no properties reads nothing, so a huge count would loop without ever reaching
/// the end of the data; for binary data each instance needs at least its scalars and list counts,
/// so the counts must fit in the bytes left (ASCII runs out of tokens and stops at end of file).
void check_ply_counts(const PlyHeader& h, const std::string& data, const std::string& path) {
  for (const auto& e : h.elements)
    if (e.count > 0 && e.properties.empty())
      fail(path, e.line, "element '" + e.name + "' has " + std::to_string(e.count) + " instances but no properties");
  if (h.format == "ascii") return;
  std::size_t remaining = data.size() - std::min(h.data_start, data.size());
  for (const auto& e : h.elements) {
    std::size_t record = 0;
    for (const auto& prop : e.properties) record += ply_size(prop.is_list ? prop.count_type : prop.type);
    if (e.count == 0) continue;
    const auto count = static_cast<unsigned long long>(e.count);
    if (count > remaining / record)
      fail(path, e.line,
           "unexpected end of binary data: element '" + e.name + "' declares " + std::to_string(e.count) + " instances of at least " +
               std::to_string(record) + " bytes, but only " + std::to_string(remaining) + " bytes of binary data remain");
    remaining -= static_cast<std::size_t>(count) * record;
  }
}

PlyLayout find_ply_layout(const PlyHeader& h, const std::string& path) {
  PlyLayout layout;
  for (const auto& e : h.elements) {
    if (e.name == "vertex") layout.vertex = &e;
    if (e.name == "face") layout.face = &e;
  }
  if (!layout.vertex) fail(path, 0, "no 'vertex' element");
  const auto& vertex_properties = layout.vertex->properties;
  for (std::size_t p = 0; p < vertex_properties.size(); ++p)
    for (int c = 0; c < 3; ++c)
      if (!vertex_properties[p].is_list && vertex_properties[p].name == std::string(1, "xyz"[c]))
        layout.xyz[static_cast<std::size_t>(c)] = static_cast<int>(p);
  if (*std::min_element(layout.xyz.begin(), layout.xyz.end()) < 0) fail(path, 0, "the 'vertex' element lacks an x, y or z property");
  if (layout.face) {
    const auto& face_properties = layout.face->properties;
    for (std::size_t p = 0; p < face_properties.size(); ++p)
      if (face_properties[p].is_list && (face_properties[p].name == "vertex_indices" || face_properties[p].name == "vertex_index"))
        layout.index_list = static_cast<int>(p);
    if (layout.index_list < 0) fail(path, 0, "the 'face' element has no list property 'vertex_indices'");
  }
  return layout;
}

/// Reads the instances of element e into the mesh. `value(type, what)` returns the next scalar
/// (list counts and items included) and `where()` the line for messages: the readers for ASCII
/// and binary differ only there.
template <typename Value, typename Where>
void read_ply_instances(const PlyElement& e, const PlyLayout& layout, Value&& value, Where&& where, MeshBuilder& mesh,
                        const std::string& path) {
  const bool is_vertex = &e == layout.vertex, is_face = &e == layout.face;
  std::vector<long long> polygon;
  std::array<double, 3> p{};
  for (long long i = 0; i < e.count; ++i) {
    for (std::size_t q = 0; q < e.properties.size(); ++q) {
      const PlyProperty& prop = e.properties[q];
      if (!prop.is_list) {
        const double v = value(prop.type, prop.name.c_str());
        if (is_vertex)
          for (int c = 0; c < 3; ++c)
            if (layout.xyz[static_cast<std::size_t>(c)] == static_cast<int>(q)) p[static_cast<std::size_t>(c)] = v;
        continue;
      }
      const long long n = whole_number(value(prop.count_type, "a list count"), path, where(), "list length");
      if (n < 0) fail(path, where(), "negative list length in element '" + e.name + "'");
      const bool wanted = is_face && static_cast<int>(q) == layout.index_list;
      if (wanted) {
        if (n < 3) fail(path, where(), "face " + std::to_string(i) + " has " + std::to_string(n) + " vertices; at least three are needed");
        polygon.clear();
      }
      for (long long k = 0; k < n; ++k) {
        const double v = value(prop.type, "a list item");
        if (wanted) polygon.push_back(whole_number(v, path, where(), "vertex index"));
      }
      if (wanted) mesh.add_polygon(polygon, where());
    }
    if (is_vertex) mesh.add_vertex(p[0], p[1], p[2]);
  }
}

void read_ply_ascii(const std::string& data, const PlyHeader& h, const PlyLayout& layout, MeshBuilder& mesh, const std::string& path) {
  // One element instance per line in practice, but the standard only asks for whitespace, so
  // values are taken as a stream of tokens; the line is kept for messages.
  LineReader reader(std::string_view(data).substr(std::min(h.data_start, data.size())), h.last_line + 1);
  std::vector<std::string_view> values;
  std::size_t next_value = 0;
  auto value = [&](PlyType, const char* what) {
    while (next_value >= values.size()) {
      if (!reader.next(values)) fail(path, reader.line(), std::string("unexpected end of file while reading ") + what);
      next_value = 0;
    }
    return to_double(values[next_value++], path, reader.line(), what);
  };
  auto where = [&] { return reader.line(); };
  for (const auto& e : h.elements) read_ply_instances(e, layout, value, where, mesh, path);
  // Values after the declared elements mean the counts lie (a second body would vanish).
  // Blank lines and 'comment' lines may follow.
  std::string_view extra;
  if (next_value < values.size()) {
    extra = values[next_value];
  } else {
    while (reader.next_nonempty(values))
      if (values[0] != "comment") {
        extra = values[0];
        break;
      }
  }
  if (!extra.empty())
    fail(path, reader.line(),
         "unexpected value '" + std::string(extra) + "' after the elements the header declares (" + element_counts(h.elements) +
             "): the counts are wrong or the file is corrupt");
}

void read_ply_binary(const std::string& data, const PlyHeader& h, const PlyLayout& layout, MeshBuilder& mesh, const std::string& path) {
  BinaryReader reader(data, std::min(h.data_start, data.size()), h.format == "binary_big_endian", path);
  auto value = [&](PlyType t, const char* what) { return reader.read(t, what); };
  auto where = [] { return std::size_t{0}; };
  for (const auto& e : h.elements) read_ply_instances(e, layout, value, where, mesh, path);
  // Trailing bytes other than line ends or spaces mean the counts lie.
  const std::size_t end = reader.position();
  if (end < data.size() && data.find_first_not_of(" \t\r\n", end) != std::string::npos)
    fail(path, 0,
         std::to_string(data.size() - end) + " bytes of binary data follow the elements the header declares (" +
             element_counts(h.elements) + "): the counts are wrong or the file is corrupt");
}

TriangleMesh parse_ply(const std::string& data, const std::string& path) {
  const PlyHeader header = parse_ply_header(data, path);
  check_ply_counts(header, data, path);
  const PlyLayout layout = find_ply_layout(header, path);
  MeshBuilder mesh;
  if (header.format == "ascii") {
    read_ply_ascii(data, header, layout, mesh, path);
  } else {
    read_ply_binary(data, header, layout, mesh, path);
  }
  return mesh.build(path);
}

}  // namespace

TriangleMesh read_ply(const std::string& path) { return parse_ply(read_file(path), path); }

void write_ply(const std::string& path, const TriangleMesh& mesh) {
  std::string out = "ply\nformat ascii 1.0\ncomment bemsurg triangle mesh\nelement vertex " + std::to_string(mesh.num_vertices()) +
                    "\nproperty double x\nproperty double y\nproperty double z\nelement face " + std::to_string(mesh.num_elements()) +
                    "\nproperty list uchar int vertex_indices\nend_header\n";
  mesh_formats::append_vertex_and_face_lines(out, mesh);
  mesh_formats::write_file(path, out);
}

}  // namespace bemsurg
