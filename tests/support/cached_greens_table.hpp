// tests/support/cached_greens_table.hpp: a test fixture's Green's table computed once and then
// read back by every later test process (ctest runs each test case in a process of its own, so a
// function-local static would recompute it per case), through the library's one load-or-compute
// (presolution/table_file.hpp): its key holds the mesh, material, conditions, gravity and
// quadrature, so a fixture whose inputs changed finds its file stale and recomputes it, a corrupt
// file is never used, and two processes computing it at once each write a private file and rename
// it into place. The files live in the build tree (BEMSURG_TEST_CACHE_DIR, tests/CMakeLists.txt),
// never in the working directory of whoever runs a test.
// The key names the inputs, not the code that computed the table: a tree rebuilt after a change to
// assembly or to the solvers would otherwise read a table the old code made (and pass a test the
// new code fails). So the file name also carries the test program's build stamp (its modification
// time and size), and a program drops the files an earlier build of it left.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>

#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/presolution/table_file.hpp"

namespace bemsurg::testing {

/// This program's build stamp ("<mtime>-<size>" of /proc/self/exe), empty where it cannot be read.
inline std::string program_build_stamp() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::canonical("/proc/self/exe", ec);
  if (ec) return {};
  const auto time = std::filesystem::last_write_time(self, ec);
  if (ec) return {};
  const auto size = std::filesystem::file_size(self, ec);
  if (ec) return {};
  return std::to_string(time.time_since_epoch().count()) + "-" + std::to_string(size);
}

inline GreensTable cached_greens_table(const std::string& name, const TriangleMesh& mesh, const Material& material,
                                       const BoundaryConditions& base, const GreensTableOptions& options) {
#ifdef BEMSURG_TEST_CACHE_DIR
  const std::filesystem::path dir(BEMSURG_TEST_CACHE_DIR);
#else
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "bemsurg-fixture-cache";
#endif
  std::filesystem::create_directories(dir);
  const std::string prefix = "fixture-" + name + "@", file = prefix + program_build_stamp() + ".bemsgtbl";
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {  // an earlier build's tables
    const std::string other = entry.path().filename().string();
    // Not this build's file, nor the private file another process of this build is writing (file + ".tmp<pid>").
    if (other.rfind(prefix, 0) == 0 && other.rfind(file, 0) != 0) std::filesystem::remove(entry.path(), ec);
  }
  ElastostaticProblem problem{mesh, material, options.gravity, base, options.quadrature};
  return load_or_compute_greens_table(problem, options.region, (dir / file).string()).table;
}

}  // namespace bemsurg::testing
