// Readers (OBJ, STL, OFF, PLY, VTK) and writers (OBJ, VTK) for triangle meshes.
//
// Files are read whole into memory and parsed from the buffer: meshes for BEM are small (the
// system is dense), and a buffer makes binary PLY/STL parsing and line counting simple.
// Numbers are parsed and printed with <charconv>, which ignores the global locale (a German
// locale must not turn "0.5" into 0) and prints the shortest text that reads back exactly.
#include "bemsurg/mesh/mesh_io.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string_view>

#include "bemsurg/mesh/vertex_welding.hpp"

namespace bemsurg {

namespace {

// ---- shared helpers --------------------------------------------------------------------------

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open mesh file '" + path + "' for reading: " + std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw IoError("error while reading mesh file '" + path + "'");
  return buffer.str();
}

/// Parse errors: "path:line: what" (line 0 = no line, for binary data).
[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& what) {
  throw InvalidMeshError(path + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what);
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

/// Splits text into lines and lines into whitespace-separated tokens, counting lines from 1.
class LineReader {
 public:
  explicit LineReader(std::string_view text, std::size_t first_line = 1) : text_(text), line_(first_line - 1) {}

  /// Next line's tokens (comments after `comment` removed when comment != 0); false at the end.
  bool next(std::vector<std::string_view>& tokens, char comment = 0) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++line_;
    if (comment != 0) line = line.substr(0, line.find(comment));
    tokens.clear();
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && is_space(line[i])) ++i;
      const std::size_t start = i;
      while (i < line.size() && !is_space(line[i])) ++i;
      if (i > start) tokens.push_back(line.substr(start, i - start));
    }
    return true;
  }
  /// Like next, but skips lines without tokens.
  bool next_nonempty(std::vector<std::string_view>& tokens, char comment = 0) {
    while (next(tokens, comment))
      if (!tokens.empty()) return true;
    return false;
  }
  std::size_t line() const { return line_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_;
};

template <typename T>
bool parse_number(std::string_view token, T& value) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);  // from_chars rejects '+'
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

double to_double(std::string_view token, const std::string& path, std::size_t line, const char* what) {
  double v = 0.0;
  if (!parse_number(token, v)) fail(path, line, "expected a number for " + std::string(what) + ", got '" + std::string(token) + "'");
  return v;
}

long long to_integer(std::string_view token, const std::string& path, std::size_t line, const char* what) {
  long long v = 0;
  if (!parse_number(token, v)) fail(path, line, "expected an integer for " + std::string(what) + ", got '" + std::string(token) + "'");
  return v;
}

/// Collects vertices and polygons, remembering the line of each polygon so an out-of-range index
/// or an untriangulable polygon can be reported where it was written. Polygons become triangles
/// in build(), once every vertex is known: a convex polygon as a fan from its first corner (an
/// OBJ quad becomes two consecutive elements), a non-convex one by ear clipping, which respects
/// its concave corners (a fan would put an inside-out triangle outside the face).
struct MeshBuilder {
  std::vector<double> coords;
  std::vector<int> corners;        // polygon corners, one polygon after another
  std::vector<std::size_t> sizes;  // corners per polygon
  std::vector<std::size_t> lines;  // file position of each polygon

  Index num_vertices() const { return static_cast<Index>(coords.size() / 3); }
  void add_vertex(double x, double y, double z) { coords.insert(coords.end(), {x, y, z}); }
  void add_polygon(const std::vector<long long>& polygon, std::size_t line) {
    for (long long v : polygon) corners.push_back(static_cast<int>(v));
    sizes.push_back(polygon.size());
    lines.push_back(line);
  }
  Eigen::Vector3d vertex(int v) const {
    const std::size_t i = 3 * static_cast<std::size_t>(v);
    return {coords[i], coords[i + 1], coords[i + 2]};
  }
  /// Indices are checked here (not by TriangleMesh) so the message can carry the file position.
  TriangleMesh build(const std::string& path, const char* face_word = "face") const {
    const Index nv = num_vertices();
    std::size_t first = 0;
    for (std::size_t p = 0; p < sizes.size(); first += sizes[p], ++p)
      for (std::size_t k = 0; k < sizes[p]; ++k) {
        const int v = corners[first + k];
        if (v < 0 || v >= nv)
          fail(path, lines[p], std::string(face_word) + " refers to vertex " + std::to_string(v) + " (0-based), but the file has " +
                                   std::to_string(nv) + " vertices");
      }
    std::vector<int> triangles;
    triangles.reserve(3 * corners.size());
    first = 0;
    for (std::size_t p = 0; p < sizes.size(); first += sizes[p], ++p)
      triangulate(&corners[first], sizes[p], path, lines[p], face_word, triangles);
    RowMatrixX3d V(nv, 3);
    for (Index v = 0; v < nv; ++v)
      for (int k = 0; k < 3; ++k) V(v, k) = coords[static_cast<std::size_t>(3 * v + k)];
    const Index nf = static_cast<Index>(triangles.size() / 3);
    RowMatrixX3i F(nf, 3);
    for (Index f = 0; f < nf; ++f)
      for (int k = 0; k < 3; ++k) F(f, k) = triangles[static_cast<std::size_t>(3 * f + k)];
    return TriangleMesh(std::move(V), std::move(F));
  }

 private:
  void triangulate(const int* poly, std::size_t n, const std::string& path, std::size_t line, const char* face_word,
                   std::vector<int>& out) const {
    const auto fan = [&] {
      for (std::size_t k = 1; k + 1 < n; ++k) out.insert(out.end(), {poly[0], poly[k], poly[k + 1]});
    };
    if (n <= 3) return fan();
    // Newell's normal: the polygon's area vector, robust for non-planar and concave polygons.
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < n; ++k) normal += vertex(poly[k]).cross(vertex(poly[(k + 1) % n]));
    if (!(normal.norm() > 0.0) || !normal.allFinite()) return fan();  // degenerate: the validator names it
    normal.normalize();
    // In-plane coordinates: a 2D polygon, counter-clockwise about the normal.
    const Eigen::Vector3d ex = (std::abs(normal.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(normal).normalized();
    const Eigen::Vector3d ey = normal.cross(ex);
    std::vector<Eigen::Vector2d> q(n);
    for (std::size_t k = 0; k < n; ++k) q[k] = {vertex(poly[k]).dot(ex), vertex(poly[k]).dot(ey)};
    const auto cross = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
      return (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
    };
    bool convex = true;
    // Convex (flat corners allowed): the fan, as before, so element numbering of such files is
    // unchanged.
    for (std::size_t k = 0; k < n && convex; ++k) convex = cross(q[(k + n - 1) % n], q[k], q[(k + 1) % n]) >= 0.0;
    if (convex) return fan();
    // Ear clipping: cut off a convex corner whose triangle holds no other remaining corner, until
    // three remain. O(n^2) per polygon, which is fine for the polygons of a surface mesh.
    std::vector<std::size_t> left(n);
    for (std::size_t k = 0; k < n; ++k) left[k] = k;
    const auto inside = [&](const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
      return cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0;
    };
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
      if (!clipped)
        fail(path, line, std::string(face_word) + " with " + std::to_string(n) +
                             " corners cannot be triangulated: it crosses itself (or folds onto itself) in its plane");
    }
    if (cross(q[left[0]], q[left[1]], q[left[2]]) > 0.0) out.insert(out.end(), {poly[left[0]], poly[left[1]], poly[left[2]]});
    else
      fail(path, line, std::string(face_word) + " with " + std::to_string(n) +
                           " corners cannot be triangulated: it crosses itself (or folds onto itself) in its plane");
  }
};

/// Indices are stored as int; anything beyond that cannot be a valid index of an in-memory mesh.
long long checked_index(long long v, const std::string& path, std::size_t line) {
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    fail(path, line, "vertex index " + std::to_string(v) + " is out of range");
  return v;
}

/// PLY values arrive as doubles; an index or a list length must be a whole number in int range
/// (and the check must come before the cast, which is undefined for out-of-range values).
long long whole_number(double v, const std::string& path, std::size_t line, const char* what) {
  if (!(v >= static_cast<double>(std::numeric_limits<int>::min()) && v <= static_cast<double>(std::numeric_limits<int>::max())) ||
      v != std::floor(v))
    fail(path, line, std::string("invalid ") + what + " " + std::to_string(v));
  return static_cast<long long>(v);
}

// ---- OBJ -------------------------------------------------------------------------------------

TriangleMesh parse_obj(const std::string& text, const std::string& path) {
  MeshBuilder mesh;
  LineReader reader(text);
  std::vector<std::string_view> tok;
  std::vector<long long> polygon;
  while (reader.next_nonempty(tok, '#')) {
    const std::size_t line = reader.line();
    if (tok[0] == "v") {
      if (tok.size() < 4) fail(path, line, "a 'v' line needs three coordinates");
      mesh.add_vertex(to_double(tok[1], path, line, "x"), to_double(tok[2], path, line, "y"),
                      to_double(tok[3], path, line, "z"));
    } else if (tok[0] == "f") {
      if (tok.size() < 4) fail(path, line, "a face needs at least three vertices, got " + std::to_string(tok.size() - 1));
      polygon.clear();
      for (std::size_t k = 1; k < tok.size(); ++k) {
        // 'a', 'a/t', 'a/t/n', 'a//n': only the vertex index matters for a surface mesh.
        const long long i = to_integer(tok[k].substr(0, tok[k].find('/')), path, line, "a vertex index");
        if (i == 0) fail(path, line, "vertex index 0 is invalid (OBJ indices start at 1)");
        const long long v = i > 0 ? i - 1 : mesh.num_vertices() + i;  // negative: relative to the latest vertex
        if (i < 0 && v < 0)
          fail(path, line, "relative vertex index " + std::to_string(i) + " reaches before the first vertex (" +
                               std::to_string(mesh.num_vertices()) + " defined so far)");
        polygon.push_back(checked_index(v, path, line));
      }
      mesh.add_polygon(polygon, line);
    }
    // Texture coordinates, normals, groups, materials, lines, ...: not part of the surface.
  }
  return mesh.build(path);
}

// ---- STL -------------------------------------------------------------------------------------

std::uint32_t le_u32(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
         (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
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
    fail(path, 0, "truncated binary STL: the header announces " + std::to_string(n) + " triangles (" +
                      std::to_string(expected) + " bytes) but the file has " + std::to_string(data.size()) + " bytes");
  // More bytes than the count announces: a wrong count would silently drop the rest (a second
  // body vanishes), so refuse it rather than guess which is right.
  if (data.size() > expected) {
    const std::size_t extra = data.size() - expected;
    fail(path, 0, "binary STL: the header announces " + std::to_string(n) + " triangles (" + std::to_string(expected) +
                      " bytes) but the file has " + std::to_string(data.size()) + " bytes: " + std::to_string(extra) +
                      " bytes (" + std::to_string(extra / 50) + " triangles and " + std::to_string(extra % 50) +
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
        fail(path, loop_line, "facet with " + std::to_string(loop_vertices) +
                                  " vertices: STL allows triangles only (the mesh is not a triangle mesh)");
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

// ---- OFF -------------------------------------------------------------------------------------

TriangleMesh parse_off(const std::string& text, const std::string& path) {
  LineReader reader(text);
  std::vector<std::string_view> tok;
  if (!reader.next_nonempty(tok, '#')) fail(path, 0, "empty file, expected an 'OFF' header");
  const std::string header(tok[0]);
  // Prefixes: ST (texture), C (colour), N (normal), 4 (homogeneous), n (dimension). The first three
  // add columns we skip; the last two change the layout.
  const bool off_like = header.size() >= 3 && header.compare(header.size() - 3, 3, "OFF") == 0 &&
                        header.find_first_not_of("STCN") >= header.size() - 3;
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
    mesh.add_vertex(to_double(tok[0], path, line, "x"), to_double(tok[1], path, line, "y"),
                    to_double(tok[2], path, line, "z"));
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
    fail(path, reader.line(), "unexpected content '" + std::string(tok[0]) + "' after the " + std::to_string(nv) + " vertices and " +
                                  std::to_string(nf) + " faces the header declares: the counts are wrong or the file is corrupt");
  return mesh.build(path);
}

// ---- PLY -------------------------------------------------------------------------------------

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

bool ply_type(std::string_view name, PlyType& type) {
  static const std::array<std::pair<const char*, PlyType>, 16> table{{
      {"char", PlyType::Int8},      {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},   {"uint8", PlyType::UInt8},
      {"short", PlyType::Int16},    {"int16", PlyType::Int16},     {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},
      {"int", PlyType::Int32},      {"int32", PlyType::Int32},     {"uint", PlyType::UInt32},   {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32},  {"float32", PlyType::Float32}, {"double", PlyType::Float64}, {"float64", PlyType::Float64},
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
      case PlyType::Int8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case PlyType::UInt8: { std::uint8_t v; std::memcpy(&v, b, 1); return v; }
      case PlyType::Int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::UInt16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::Int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::UInt32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::Float32: { float v; std::memcpy(&v, b, 4); return v; }
      case PlyType::Float64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0.0;
  }

  std::size_t position() const { return pos_; }

 private:
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

TriangleMesh parse_ply(const std::string& data, const std::string& path) {
  // The header is text up to and including the 'end_header' line; binary data starts right after.
  std::vector<PlyElement> elements;
  std::string format;
  std::size_t pos = 0, line = 0;
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
      format = std::string(tok[1]);
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        fail(path, line, "unknown PLY format '" + format + "'");
    } else if (tok[0] == "element") {
      if (tok.size() < 3) fail(path, line, "'element' needs a name and a count");
      const long long count = to_integer(tok[2], path, line, "the element count");
      if (count < 0) fail(path, line, "negative element count");
      elements.push_back({std::string(tok[1]), count, {}, line});
    } else if (tok[0] == "property") {
      if (elements.empty()) fail(path, line, "'property' before any 'element'");
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
      elements.back().properties.push_back(prop);
    } else if (tok[0] == "end_header") {
      ended = true;
    } else {
      fail(path, line, "unexpected '" + std::string(tok[0]) + "' in the PLY header");
    }
  }
  if (!ended) fail(path, line, "the PLY header has no 'end_header'");
  if (format.empty()) fail(path, line, "the PLY header has no 'format' line");
  // An instance with no properties reads nothing, so a huge count would loop without ever reaching
  // the end of the data; for binary data each instance needs at least its scalars and list counts,
  // so the counts must fit in the bytes left (ASCII runs out of tokens and stops at end of file).
  for (const auto& e : elements)
    if (e.count > 0 && e.properties.empty())
      fail(path, e.line, "element '" + e.name + "' has " + std::to_string(e.count) + " instances but no properties");
  if (format != "ascii") {
    std::size_t remaining = data.size() - std::min(pos, data.size());
    for (const auto& e : elements) {
      std::size_t record = 0;
      for (const auto& prop : e.properties) record += ply_size(prop.is_list ? prop.count_type : prop.type);
      if (e.count == 0) continue;
      const auto count = static_cast<unsigned long long>(e.count);
      if (count > remaining / record)
        fail(path, e.line, "unexpected end of binary data: element '" + e.name + "' declares " + std::to_string(e.count) +
                               " instances of at least " +
                               std::to_string(record) + " bytes, but only " + std::to_string(remaining) +
                               " bytes of binary data remain");
      remaining -= static_cast<std::size_t>(count) * record;
    }
  }

  const PlyElement* vertex_el = nullptr;
  const PlyElement* face_el = nullptr;
  for (const auto& e : elements) {
    if (e.name == "vertex") vertex_el = &e;
    if (e.name == "face") face_el = &e;
  }
  if (!vertex_el) fail(path, 0, "no 'vertex' element");
  std::array<int, 3> xyz{{-1, -1, -1}};
  for (std::size_t p = 0; p < vertex_el->properties.size(); ++p)
    for (int c = 0; c < 3; ++c)
      if (!vertex_el->properties[p].is_list && vertex_el->properties[p].name == std::string(1, "xyz"[c]))
        xyz[static_cast<std::size_t>(c)] = static_cast<int>(p);
  if (*std::min_element(xyz.begin(), xyz.end()) < 0) fail(path, 0, "the 'vertex' element lacks an x, y or z property");
  int index_prop = -1;
  if (face_el) {
    for (std::size_t p = 0; p < face_el->properties.size(); ++p)
      if (face_el->properties[p].is_list &&
          (face_el->properties[p].name == "vertex_indices" || face_el->properties[p].name == "vertex_index"))
        index_prop = static_cast<int>(p);
    if (index_prop < 0) fail(path, 0, "the 'face' element has no list property 'vertex_indices'");
  }

  MeshBuilder mesh;
  std::vector<long long> polygon;
  std::array<double, 3> p{};
  // Each element instance calls `value` once per scalar (list count and items included) and
  // gets back what it read; the readers for ASCII and binary differ only there.
  auto read_instances = [&](const PlyElement& e, auto&& value, auto&& where) {
    const bool is_vertex = &e == vertex_el, is_face = &e == face_el;
    for (long long i = 0; i < e.count; ++i) {
      for (std::size_t q = 0; q < e.properties.size(); ++q) {
        const PlyProperty& prop = e.properties[q];
        if (!prop.is_list) {
          const double v = value(prop.type, prop.name.c_str());
          if (is_vertex)
            for (int c = 0; c < 3; ++c)
              if (xyz[static_cast<std::size_t>(c)] == static_cast<int>(q)) p[static_cast<std::size_t>(c)] = v;
          continue;
        }
        const long long n = whole_number(value(prop.count_type, "a list count"), path, where(), "list length");
        if (n < 0) fail(path, where(), "negative list length in element '" + e.name + "'");
        const bool wanted = is_face && static_cast<int>(q) == index_prop;
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
  };

  if (format == "ascii") {
    // One element instance per line in practice, but the standard only asks for whitespace, so
    // values are taken as a stream of tokens; the line is kept for messages.
    LineReader reader(std::string_view(data).substr(std::min(pos, data.size())), line + 1);
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
    for (const auto& e : elements) read_instances(e, value, where);
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
      fail(path, reader.line(), "unexpected value '" + std::string(extra) + "' after the elements the header declares (" +
                                    element_counts(elements) + "): the counts are wrong or the file is corrupt");
  } else {
    BinaryReader reader(data, std::min(pos, data.size()), format == "binary_big_endian", path);
    auto value = [&](PlyType t, const char* what) { return reader.read(t, what); };
    auto where = [] { return std::size_t{0}; };
    for (const auto& e : elements) read_instances(e, value, where);
    // Trailing bytes other than line ends or spaces mean the counts lie.
    const std::size_t end = reader.position();
    if (end < data.size() && data.find_first_not_of(" \t\r\n", end) != std::string::npos)
      fail(path, 0, std::to_string(data.size() - end) + " bytes of binary data follow the elements the header declares (" +
                        element_counts(elements) + "): the counts are wrong or the file is corrupt");
  }
  return mesh.build(path);
}

// ---- VTK -------------------------------------------------------------------------------------

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
  // Values may wrap over lines, so sections are read as token streams.
  std::vector<std::string_view> values;
  std::size_t next_value = 0;
  auto next_token = [&](const char* what) {
    while (next_value >= values.size()) {
      if (!reader.next(values)) fail(path, reader.line(), std::string("unexpected end of file while reading ") + what);
      next_value = 0;
    }
    return values[next_value++];
  };
  std::vector<long long> polygon;
  while (reader.next_nonempty(tok)) {
    const std::string section = lower(tok[0]);
    const std::size_t line = reader.line();
    if (section == "points") {
      if (tok.size() < 2) fail(path, line, "'POINTS' needs a count");
      const long long n = to_integer(tok[1], path, line, "the point count");
      values.clear();
      next_value = 0;
      for (long long i = 0; i < n; ++i) {
        std::array<double, 3> x{};
        for (auto& c : x) c = to_double(next_token("POINTS"), path, reader.line(), "a coordinate");
        mesh.add_vertex(x[0], x[1], x[2]);
      }
    } else if (section == "polygons" || section == "vertices" || section == "lines") {
      if (tok.size() < 2) fail(path, line, "'" + std::string(tok[0]) + "' needs a count");
      const long long n = to_integer(tok[1], path, line, "the cell count");
      values.clear();
      next_value = 0;
      for (long long i = 0; i < n; ++i) {
        const long long k = to_integer(next_token("a cell"), path, reader.line(), "a cell size");
        const std::size_t cell_line = reader.line();
        polygon.clear();
        for (long long j = 0; j < k; ++j)
          polygon.push_back(checked_index(to_integer(next_token("a cell"), path, reader.line(), "a point index"), path, reader.line()));
        if (section != "polygons") continue;  // points and lines are not surface
        if (k < 3) fail(path, cell_line, "a polygon needs at least three points, got " + std::to_string(k));
        mesh.add_polygon(polygon, cell_line);
      }
    } else if (section == "cell_data" || section == "point_data") {
      break;  // attributes follow; the mesh is complete
    } else {
      fail(path, line, "unsupported POLYDATA section '" + std::string(tok[0]) + "'");
    }
  }
  return mesh.build(path, "polygon");
}

// ---- writers ---------------------------------------------------------------------------------

/// Shortest decimal text that reads back to the same double.
void put(std::string& out, double x) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, r.ptr);
}

void put(std::string& out, long long x) {
  char buf[24];
  const auto r = std::to_chars(buf, buf + sizeof buf, x);
  out.append(buf, r.ptr);
}

void write_file(const std::string& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError("cannot open '" + path + "' for writing: " + std::strerror(errno));
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.close();
  if (!out) throw IoError("error while writing '" + path + "'");
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
      put(out, field.values(i, c));
    }
    out += '\n';
  }
}

}  // namespace

TriangleMesh read_obj(const std::string& path) { return parse_obj(read_file(path), path); }

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

TriangleMesh read_off(const std::string& path) { return parse_off(read_file(path), path); }
TriangleMesh read_ply(const std::string& path) { return parse_ply(read_file(path), path); }
TriangleMesh read_vtk(const std::string& path) { return parse_vtk(read_file(path), path); }

TriangleMesh read_mesh(const std::string& path) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  if (ext == ".obj") return read_obj(path);
  if (ext == ".stl") return read_stl(path);
  if (ext == ".off") return read_off(path);
  if (ext == ".ply") return read_ply(path);
  if (ext == ".vtk") return read_vtk(path);
  throw InvalidMeshError("cannot read '" + path + "': unknown mesh file extension '" + ext +
                         "' (known: .obj, .stl, .off, .ply, .vtk)");
}

void write_obj(const std::string& path, const TriangleMesh& mesh) {
  std::string out = "# bemsurg triangle mesh: " + std::to_string(mesh.num_vertices()) + " vertices, " +
                    std::to_string(mesh.num_elements()) + " faces\n";
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    out += 'v';
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      put(out, mesh.vertices()(v, c));
    }
    out += '\n';
  }
  for (Index f = 0; f < mesh.num_elements(); ++f) {
    out += 'f';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      put(out, static_cast<long long>(mesh.faces()(f, k)) + 1);
    }
    out += '\n';
  }
  write_file(path, out);
}

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
      put(out, mesh.vertices()(v, c));
    }
    out += '\n';
  }
  out += "POLYGONS " + std::to_string(nf) + " " + std::to_string(4 * nf) + "\n";
  for (Index f = 0; f < nf; ++f) {
    out += '3';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      put(out, static_cast<long long>(mesh.faces()(f, k)));
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
