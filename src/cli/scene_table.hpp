// The pre-solution table of a scene for the commands that press and pinch (`press`, `session`;
// docs/cli.md "--table"): loaded from a file when it matches the scene, else computed and saved.
#pragma once

#include <filesystem>
#include <iostream>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/presolution/table_file.hpp"

namespace bemsurg::cli {

struct SceneTable {
  GreensTable table;
  bool loaded_from_file = false;
};

/// The table on the scene's operating_region (where tools may act; empty: every free element,
/// docs/graded.md). With `table_file` named and present, it is loaded when its key and region
/// match the scene; a stale or corrupt file is recomputed with a warning that says why (unless
/// `quiet`) and rewritten. With `table_file` named and absent, the computed table is saved there.
/// `for_cuts`: the table will be updated after cuts (GreensTable::updated needs the factorisation,
/// which a file does not keep): it is computed even when a matching file exists, with a note.
inline SceneTable scene_table(const Scene& scene, const std::string& table_file, bool quiet, bool for_cuts = false) {
  const ElastostaticProblem& p = scene.problem;
  GreensTableOptions options;
  options.gravity = p.gravity;
  options.quadrature = p.quadrature;
  options.region = scene.operating_elements;
  SceneTable out;
  if (for_cuts && !table_file.empty() && std::filesystem::exists(table_file) && !quiet)
    std::cerr << "bemsurg: note: the script cuts, so the table is computed rather than read from " << table_file
              << " (a table read from a file keeps no factorisation for the exact updates after a cut)\n";
  if (!for_cuts && !table_file.empty() && std::filesystem::exists(table_file)) {
    try {
      const GreensTableKey key = make_greens_table_key(p.mesh, p.material, p.boundary_conditions, p.gravity, p.quadrature);
      out.table = load_greens_table(table_file, key, options.region);
      out.loaded_from_file = true;
      return out;
    } catch (const IoError& e) {  // stale or corrupt: recompute
      if (!quiet) std::cerr << "bemsurg: warning: " << e.what() << "; recomputing\n";
    }
  }
  out.table = GreensTable::compute(p.mesh, p.material, p.boundary_conditions, options);
  if (!table_file.empty()) save_greens_table(table_file, out.table);
  return out;
}

}  // namespace bemsurg::cli
