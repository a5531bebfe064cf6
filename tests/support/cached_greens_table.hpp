// tests/support/cached_greens_table.hpp: a test fixture's Green's table computed once and then
// read back by every later test process (ctest runs each test case in a process of its own, so a
// function-local static would recompute it per case). The file lives in the ctest working
// directory and goes through the library's own table files (presolution/table_file.hpp): its key
// holds the mesh, material, conditions, gravity and quadrature, so a fixture whose inputs changed
// finds its file stale and recomputes it, and a corrupt file is never used. Two processes that
// compute it at once each write a private file and rename it into place, which is atomic.
#pragma once

#include <unistd.h>
#include <cstdio>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/presolution/table_file.hpp"

namespace bemsurg::testing {

inline GreensTable cached_greens_table(const std::string& name, const TriangleMesh& mesh, const Material& material,
                                       const BoundaryConditions& base, const GreensTableOptions& options) {
  const std::string path = "fixture-" + name + ".bemsgtbl";
  const GreensTableKey key = make_greens_table_key(mesh, material, base, options.gravity, options.quadrature);
  try {
    return load_greens_table(path, key, options.region);
  } catch (const IoError&) {
    // Missing, stale or corrupt: compute and replace it.
  }
  GreensTable table = GreensTable::compute(mesh, material, base, options);
  const std::string temporary = path + "." + std::to_string(::getpid());
  save_greens_table(temporary, table);
  if (std::rename(temporary.c_str(), path.c_str()) != 0) std::remove(temporary.c_str());
  return table;
}

}  // namespace bemsurg::testing
