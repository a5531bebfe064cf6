// Deprecated path, kept for one minor version (0.2): the compiled meshing part left the header-only
// mesh module for its own, bemsurg::meshing (docs/design.md, "Module order"). Include the new path.
#pragma once
#pragma GCC warning "bemsurg/mesh/organ_shapes.hpp is deprecated: include bemsurg/meshing/organ_shapes.hpp"
#include "bemsurg/meshing/organ_shapes.hpp"
