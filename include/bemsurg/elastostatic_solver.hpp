// Deprecated path, kept for one minor version (0.2): the elastostatics module has its own folder now
// (docs/design.md, "Module order"). Include bemsurg/elastostatics.hpp or the new path.
#pragma once
#pragma GCC warning "bemsurg/elastostatic_solver.hpp is deprecated: include bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"
