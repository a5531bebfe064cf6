// The pre-solution table of a scene for the commands that press and pinch (`press`, `session`;
// docs/cli.md "--table"): the library's one load-or-compute (bemsurg/io/scene_table.hpp), with its
// warnings and notes printed as the command line prints them.
#pragma once

#include <iostream>
#include <string>

#include "bemsurg/io/scene_table.hpp"
#include "bemsurg/presolution/hierarchical_table.hpp"

namespace bemsurg::cli {

/// load_or_compute_scene_table, printing its warnings and notes (unless `quiet`). `for_cuts`: the table will be
/// updated after cuts, so it is computed even when a matching file exists, with its factorisation kept. A
/// scene whose solver method is "hmatrix" computes (and keys) its table on the hierarchical backend
/// (bemsurg::hmatrix); its cuts update the kept H-LU.
/// `recompute`: compute and replace the file even when it matches (`bemsurg table`). `explicit_inverse`: a
/// dense table for cuts keeps A*^-1 (cuts in two phases: sessions; docs/cutting.md).
inline CachedGreensTable scene_table(const Scene& scene, const std::string& table_file, bool quiet, bool for_cuts = false,
                                     bool recompute = false, bool explicit_inverse = false) {
  TableCacheOptions options;
  options.for_cuts = for_cuts;
  options.explicit_inverse = explicit_inverse;
  options.recompute = recompute;
  if (scene.solver.backend == SolverBackend::HMatrix) {
    options.backend = SolverBackend::HMatrix;
    options.compression_tolerance = scene.solver.compression_tolerance;
    const LinearSolverOptions solver = scene.solver;
    options.compute = [solver](const ElastostaticProblem& problem, const std::vector<Index>& region, bool cuts) {
      return compute_greens_table_hierarchical(problem, region, solver, nullptr, cuts);
    };
  }
  CachedGreensTable out = load_or_compute_scene_table(scene, table_file, options);
  if (!quiet) {
    for (const std::string& w : out.warnings) std::cerr << "bemsurg: warning: " << w << "\n";
    for (const std::string& n : out.notes) std::cerr << "bemsurg: note: " << n << "\n";
  }
  return out;
}

}  // namespace bemsurg::cli
