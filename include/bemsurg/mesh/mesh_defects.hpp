// Deprecated path, kept for one minor version (0.2): the compiled meshing part left the header-only
// mesh module for its own, bemsurg::meshing (docs/design.md, "Module order"). Include the new path.
#pragma once
#pragma GCC warning "bemsurg/mesh/mesh_defects.hpp is deprecated: include bemsurg/meshing/mesh_defects.hpp"
#include "bemsurg/meshing/mesh_defects.hpp"
