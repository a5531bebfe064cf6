// solve_elastostatic, the one-call facade, compiled once here under BEMSURG_SEPARATE_COMPILATION
// (include/bemsurg/config.hpp). It sits above assembly and solvers in the module order
// (docs/design.md, "Module order"), so it has a file of its own rather than sharing core's.
#include "bemsurg/elastostatic_solver.hpp"

#include "bemsurg/impl/elastostatic_solver_impl.hpp"
