// Deprecated path, kept for one minor version (0.2): renamed to bemsurg/solvers/krylov_options.hpp with the
// option and result structs' names (*Options, *Result; docs/design.md, "Module order").
#pragma once
#pragma GCC warning "bemsurg/solvers/krylov_settings.hpp is deprecated: include bemsurg/solvers/krylov_options.hpp"
#include "bemsurg/solvers/krylov_options.hpp"
