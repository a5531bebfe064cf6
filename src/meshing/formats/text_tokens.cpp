// The helpers every mesh format shares (text_tokens.hpp).
#include "text_tokens.hpp"

#include <cctype>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg::mesh_formats {

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open mesh file '" + path + "' for reading: " + std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw IoError("error while reading mesh file '" + path + "'");
  return buffer.str();
}

void write_file(const std::string& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError("cannot open '" + path + "' for writing: " + std::strerror(errno));
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.close();
  if (!out) throw IoError("error while writing '" + path + "'");
}

void append_vertex_and_face_lines(std::string& out, const TriangleMesh& mesh) {
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    for (int c = 0; c < 3; ++c) {
      if (c > 0) out += ' ';
      append_number(out, mesh.vertices()(v, c));
    }
    out += '\n';
  }
  for (Index f = 0; f < mesh.num_elements(); ++f) {
    out += '3';
    for (int k = 0; k < 3; ++k) {
      out += ' ';
      append_integer(out, static_cast<long long>(mesh.faces()(f, k)));
    }
    out += '\n';
  }
}

void fail(const std::string& path, std::size_t line, const std::string& what) {
  throw InvalidMeshError(path + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what);
}

std::string lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

bool LineReader::next(std::vector<std::string_view>& tokens, char comment) {
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

bool LineReader::next_nonempty(std::vector<std::string_view>& tokens, char comment) {
  while (next(tokens, comment))
    if (!tokens.empty()) return true;
  return false;
}

double to_double(std::string_view token, const std::string& path, std::size_t line, const char* what) {
  const auto v = parse_number<double>(token);
  if (!v) fail(path, line, "expected a number for " + std::string(what) + ", got '" + std::string(token) + "'");
  return *v;
}

long long to_integer(std::string_view token, const std::string& path, std::size_t line, const char* what) {
  const auto v = parse_number<long long>(token);
  if (!v) fail(path, line, "expected an integer for " + std::string(what) + ", got '" + std::string(token) + "'");
  return *v;
}

long long checked_index(long long v, const std::string& path, std::size_t line) {
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    fail(path, line, "vertex index " + std::to_string(v) + " is out of range");
  return v;
}

}  // namespace bemsurg::mesh_formats
