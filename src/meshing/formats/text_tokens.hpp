// Private to the mesh readers and writers (src/meshing/formats/): what every format shares.
//
// Files are read whole into memory and parsed from the buffer: meshes for BEM are small (the
// system is dense), and a buffer makes binary PLY/STL parsing and line counting simple. Numbers
// go through bemsurg/number_text.hpp (<charconv>), which ignores the global locale (a German
// locale must not turn "0.5" into 0) and prints the shortest text that reads back exactly.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg::mesh_formats {

/// The whole file; throws IoError (naming the file and the system's reason) if it cannot be read.
std::string read_file(const std::string& path);

/// Replaces the file with `content`; throws IoError if it cannot be opened or written.
void write_file(const std::string& path, const std::string& content);

/// The body OFF and ASCII PLY share: one "x y z" line per vertex (shortest exact text), then one
/// "3 a b c" line per face (0-based indices).
void append_vertex_and_face_lines(std::string& out, const TriangleMesh& mesh);

/// Parse errors: throws InvalidMeshError "path:line: what" (line 0 = no line, for binary data).
[[noreturn]] void fail(const std::string& path, std::size_t line, const std::string& what);

/// ASCII lower case (format keywords are case-insensitive in STL and VTK).
std::string lower(std::string_view s);

bool is_space(char c);

/// Splits text into lines and lines into whitespace-separated tokens, counting lines from 1.
class LineReader {
 public:
  explicit LineReader(std::string_view text, std::size_t first_line = 1) : text_(text), line_(first_line - 1) {}

  /// Next line's tokens (comments after `comment` removed when comment != 0); false at the end.
  bool next(std::vector<std::string_view>& tokens, char comment = 0);
  /// Like next, but skips lines without tokens.
  bool next_nonempty(std::vector<std::string_view>& tokens, char comment = 0);
  std::size_t line() const { return line_; }

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  std::size_t line_;
};

/// The token as a number or an integer; otherwise fail() naming `what` and the token.
double to_double(std::string_view token, const std::string& path, std::size_t line, const char* what);
long long to_integer(std::string_view token, const std::string& path, std::size_t line, const char* what);

/// Indices are stored as int; anything beyond that cannot be a valid index of an in-memory mesh.
long long checked_index(long long v, const std::string& path, std::size_t line);

}  // namespace bemsurg::mesh_formats
