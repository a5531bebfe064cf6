// Deprecated path, kept for one minor version (0.2): the header moved to bemsurg/mesh/mesh_delta.hpp so that
// the module graph has no cycle (docs/design.md, "Module order"). Include the new path.
#pragma once
#pragma GCC warning "bemsurg/cutting/mesh_delta.hpp is deprecated: include bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/mesh/mesh_delta.hpp"
