// The pre-solution table of a scene for the commands that press and pinch (`press`, `session`;
// docs/cli.md "--table"): the library's one load-or-compute (bemsurg/io/scene_table.hpp), with its
// warnings and notes printed as the command line prints them.
#pragma once

#include <iostream>
#include <string>

#include "bemsurg/io/scene_table.hpp"

namespace bemsurg::cli {

/// load_or_compute_scene_table, printing its warnings and notes (unless `quiet`). `for_cuts`: the table will be
/// updated after cuts, so it is computed even when a matching file exists.
inline CachedGreensTable scene_table(const Scene& scene, const std::string& table_file, bool quiet, bool for_cuts = false) {
  TableCacheOptions options;
  options.for_cuts = for_cuts;
  CachedGreensTable out = load_or_compute_scene_table(scene, table_file, options);
  if (!quiet) {
    for (const std::string& w : out.warnings) std::cerr << "bemsurg: warning: " << w << "\n";
    for (const std::string& n : out.notes) std::cerr << "bemsurg: note: " << n << "\n";
  }
  return out;
}

}  // namespace bemsurg::cli
