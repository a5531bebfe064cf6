// Implementation of bemsurg/io/scene_table.hpp.
#include "bemsurg/io/scene_table.hpp"

#include <string>

namespace bemsurg {

GreensTable compute_scene_table(const Scene& scene) { return GreensTable::compute(scene.problem, scene.operating_elements); }

CachedGreensTable load_or_compute_scene_table(const Scene& scene, const std::string& table_file, const TableCacheOptions& options) {
  return load_or_compute_greens_table(scene.problem, scene.operating_elements, table_file, options);
}

}  // namespace bemsurg
