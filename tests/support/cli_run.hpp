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

/// Runs `prefix` (a launcher and its options, or nothing) then the built program with `args` (already
/// quoted), capturing stdout and stderr in `dir`.
inline CliRun run_cli_prefixed(const std::string& prefix, const std::string& args, const TempDir& dir) {
  const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
  const std::string command = prefix + "'" + std::string(BEMSURG_CLI_PATH) + "' " + args + " >'" + out + "' 2>'" + err + "'";
  const int status = std::system(command.c_str());
  CliRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

/// Runs the built program with `args` (already quoted), capturing stdout and stderr in `dir`.
inline CliRun run_cli(const std::string& args, const TempDir& dir) { return run_cli_prefixed("", args, dir); }

/// True when this build can launch the program on several MPI ranks (BEMSURG_MPIEXEC: tests/CMakeLists.txt).
inline bool can_run_on_ranks() {
#ifdef BEMSURG_MPIEXEC
  return true;
#else
  return false;
#endif
}

/// Runs the built program on `ranks` MPI ranks on this machine (mpiexec, one OpenMP and one BLAS
/// thread per rank, allowed as root and beyond the cores: CI's container), capturing as run_cli does.
/// Exit code -1 when this build has no MPI launcher.
inline CliRun run_cli_on_ranks(int ranks, const std::string& args, const TempDir& dir) {
#ifdef BEMSURG_MPIEXEC
  return run_cli_prefixed("'" + std::string(BEMSURG_MPIEXEC) + "' -n " + std::to_string(ranks) +
                              " --allow-run-as-root --oversubscribe -x OMP_NUM_THREADS=1 -x OPENBLAS_NUM_THREADS=1 ",
                          args, dir);
#else
  (void)ranks, (void)args, (void)dir;
  return CliRun{};
#endif
}

}  // namespace bemsurg_test
