// The CSV files a scene names (docs/scene-format.md: the boundary-condition file and the interior
// points file): a fixed header, one row per line, every error naming the file key and the line
// ("boundary_conditions.file line 17: value_x: expected a finite number, got 'abc'"). Numbers are
// read with parse_number (bemsurg/number_text.hpp), the same in every locale. Private to the library.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace bemsurg::io {

struct CsvRow {
  std::size_t line = 0;  // 1-based line number in the file
  std::vector<std::string> fields;
};

/// Reads a CSV whose first non-blank line must be `header` exactly (fields compared after trimming
/// blanks). Blank lines and lines starting with '#' are skipped; a UTF-8 byte order mark is
/// dropped; every row must have as many fields as the header. `key` names the file in messages
/// (SceneError "<key> line <n>: ...").
std::vector<CsvRow> read_csv(const std::string& path, const std::string& header, const std::string& key);

/// The same for a file that may use one of several headers (variants of one format): `which` is set
/// to the index of the header the file uses; a file with none of them names all in its message.
std::vector<CsvRow> read_csv(const std::string& path, const std::vector<std::string>& headers, const std::string& key, std::size_t& which);

/// "<key> line <n>": how a message names a row.
std::string csv_row_key(const std::string& key, const CsvRow& row);

/// A finite number; SceneError "<where>: expected a finite number, got '<text>'" otherwise.
double parse_csv_number(const std::string& text, const std::string& where);

/// A decimal integer; SceneError "<where>: expected <what>, got '<text>'" otherwise.
long long parse_csv_integer(const std::string& text, const std::string& where, const std::string& what);

}  // namespace bemsurg::io
