// tests/support/cached_greens_table.hpp: a test fixture's Green's table computed once and then
// read back by every later test process (ctest runs each test case in a process of its own, so a
// function-local static would recompute it per case), through the library's one load-or-compute
// (presolution/table_file.hpp): its key holds the mesh, material, conditions, gravity and
// quadrature, so a fixture whose inputs changed finds its file stale and recomputes it, a corrupt
// file is never used, and two processes computing it at once each write a private file and rename
// it into place. The files live in the build tree (BEMSURG_TEST_CACHE_DIR, tests/CMakeLists.txt),
// never in the working directory of whoever runs a test.
#pragma once

#include <filesystem>
#include <string>

#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/presolution/table_file.hpp"

namespace bemsurg::testing {

inline GreensTable cached_greens_table(const std::string& name, const TriangleMesh& mesh, const Material& material,
                                       const BoundaryConditions& base, const GreensTableOptions& options) {
#ifdef BEMSURG_TEST_CACHE_DIR
  const std::filesystem::path dir(BEMSURG_TEST_CACHE_DIR);
#else
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "bemsurg-fixture-cache";
#endif
  std::filesystem::create_directories(dir);
  ElastostaticProblem problem{mesh, material, options.gravity, base, options.quadrature};
  return load_or_compute_greens_table(problem, options.region, (dir / ("fixture-" + name + ".bemsgtbl")).string()).table;
}

}  // namespace bemsurg::testing
