// bemsurg/io/scene_table.hpp: a scene's pre-solution table, for every program that presses, pinches or
// cuts (`bemsurg press`, `session`, `cut`, the viewer; docs/cli.md "--table"). One rule for the region
// (the scene's operating_region, where tools may act; empty: every free element, docs/graded.md) and
// one load-or-compute (presolution/table_file.hpp), so the doors cannot drift apart.
#pragma once

#include <string>

#include "bemsurg/io/scene.hpp"
#include "bemsurg/presolution/table_file.hpp"

namespace bemsurg {

/// The scene's table computed (never read from a file): what a cut updates, which needs the factorisation.
GreensTable compute_scene_table(const Scene& scene);

/// The scene's table, read from `table_file` when it matches the scene (key and region) and `options.for_cuts` is
/// off, else computed (and saved there when `table_file` is named): load_or_compute_greens_table on the scene's
/// problem and operating region.
CachedGreensTable load_or_compute_scene_table(const Scene& scene, const std::string& table_file, const TableCacheOptions& options = {});

}  // namespace bemsurg
