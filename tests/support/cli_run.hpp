// tests/support/cli_run.hpp: running the built `bemsurg` program from a test (BEMSURG_CLI_PATH,
// tests/CMakeLists.txt) with its standard output and error captured in the test's directory.
#pragma once

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "temp_dir.hpp"

namespace bemsurg_test {

/// A file's whole content ("" when it cannot be read).
inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A CSV of numbers: its header line and rows.
struct CsvTable {
  std::string header;
  std::vector<std::vector<double>> rows;
};

/// A CSV file of numbers as its header line and rows (blank lines skipped).
inline CsvTable read_table(const std::string& path) {
  std::ifstream in(path);
  CsvTable t;
  std::getline(in, t.header);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<double> row;
    std::stringstream fields(line);
    std::string f;
    while (std::getline(fields, f, ',')) row.push_back(std::stod(f));
    t.rows.push_back(row);
  }
  return t;
}

/// Per column of two tables of the same shape, max |a - b| over the rows relative to the column's
/// largest |b| (0 for two all-zero columns, infinity when only b's is all zero).
inline std::vector<double> column_differences(const CsvTable& a, const CsvTable& b) {
  std::vector<double> out;
  if (a.rows.empty() || a.rows.size() != b.rows.size()) return out;
  for (std::size_t k = 0; k < a.rows.front().size(); ++k) {
    double worst = 0.0, largest = 0.0;
    for (std::size_t i = 0; i < a.rows.size(); ++i) {
      worst = std::max(worst, std::abs(a.rows[i][k] - b.rows[i][k]));
      largest = std::max(largest, std::abs(b.rows[i][k]));
    }
    out.push_back(largest > 0.0 ? worst / largest : (worst > 0.0 ? std::numeric_limits<double>::infinity() : 0.0));
  }
  return out;
}

/// What a run of the program gave: its exit status (-1 when it did not exit normally) and output.
struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

/// Runs the built program with `args` (already quoted), capturing stdout and stderr in `dir`.
inline CliRun run_cli(const std::string& args, const TempDir& dir) {
  const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
  const std::string command = "'" + std::string(BEMSURG_CLI_PATH) + "' " + args + " >'" + out + "' 2>'" + err + "'";
  const int status = std::system(command.c_str());
  CliRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

}  // namespace bemsurg_test
