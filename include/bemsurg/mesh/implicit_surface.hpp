// Deprecated path, kept for one minor version (0.2): the compiled meshing part left the header-only
// mesh module for its own, bemsurg::meshing (docs/design.md, "Module order"). Include the new path.
#pragma once
#pragma GCC warning "bemsurg/mesh/implicit_surface.hpp is deprecated: include bemsurg/meshing/implicit_surface.hpp"
#include "bemsurg/meshing/implicit_surface.hpp"
