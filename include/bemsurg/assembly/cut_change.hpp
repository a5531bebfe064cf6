// Deprecated path, kept for one minor version (0.2): the rows and columns a cut changes are the cutting
// module's, beside the update that uses them (docs/design.md, "Module order"). Include the new path.
#pragma once
#pragma GCC warning "bemsurg/assembly/cut_change.hpp is deprecated: include bemsurg/cutting/cut_change.hpp"
#include "bemsurg/cutting/cut_change.hpp"
