// The CSV files of a scene (csv_reader.hpp).
#include "csv_reader.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <utility>

#include "bemsurg/number_text.hpp"
#include "json_reader.hpp"

namespace bemsurg::io {
namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(trim(field));
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string line_key(const std::string& key, std::size_t line) { return key + " line " + std::to_string(line); }

}  // namespace

std::vector<CsvRow> read_csv(const std::string& path, const std::vector<std::string>& headers, const std::string& key, std::size_t& which) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail_at(key, "cannot read '" + path + "': " + std::strerror(errno));
  std::string named;  // the accepted headers, for messages
  for (std::size_t h = 0; h < headers.size(); ++h) named += (h == 0 ? "'" : (h + 1 == headers.size() ? "' or '" : "', '")) + headers[h];
  named += "'";
  std::vector<CsvRow> rows;
  std::vector<std::string> expected;
  std::string line;
  std::size_t number = 0;
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // UTF-8 BOM
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    std::vector<std::string> fields = split_fields(t);
    if (!header_seen) {
      for (which = 0; which < headers.size() && fields != split_fields(headers[which]); ++which) {}
      if (which == headers.size()) fail_at(line_key(key, number), "expected the header " + named + ", got '" + t + "'");
      expected = std::move(fields);
      header_seen = true;
      continue;
    }
    if (fields.size() != expected.size())
      fail_at(line_key(key, number), "expected " + std::to_string(expected.size()) + " fields, got " + std::to_string(fields.size()));
    rows.push_back({number, std::move(fields)});
  }
  if (!header_seen) fail_at(key, "'" + path + "' is empty (expected the header " + named + ")");
  return rows;
}

std::vector<CsvRow> read_csv(const std::string& path, const std::string& header, const std::string& key) {
  std::size_t which = 0;
  return read_csv(path, std::vector<std::string>{header}, key, which);
}

std::string csv_row_key(const std::string& key, const CsvRow& row) { return line_key(key, row.line); }

double parse_csv_number(const std::string& text, const std::string& where) {
  const std::optional<double> x = parse_number<double>(text);
  if (!x || !std::isfinite(*x)) fail_at(where, "expected a finite number, got '" + text + "'");
  return *x;
}

long long parse_csv_integer(const std::string& text, const std::string& where, const std::string& what) {
  const std::optional<long long> x = parse_number<long long>(text);
  if (!x) fail_at(where, "expected " + what + ", got '" + text + "'");
  return *x;
}

}  // namespace bemsurg::io
