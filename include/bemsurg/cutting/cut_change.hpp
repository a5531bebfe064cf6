// Deprecated path, kept for one minor version (0.2): the header moved to bemsurg/assembly/cut_change.hpp so that
// the module graph has no cycle (docs/design.md, "Module order"). Include the new path.
#pragma once
#pragma GCC warning "bemsurg/cutting/cut_change.hpp is deprecated: include bemsurg/assembly/cut_change.hpp"
#include "bemsurg/assembly/cut_change.hpp"
