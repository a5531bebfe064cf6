// The elastostatics module's definitions: the problem's one check and the one-call solve.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"

#include "bemsurg/elastostatics/impl/elastostatic_problem_impl.hpp"
#include "bemsurg/elastostatics/impl/elastostatic_solver_impl.hpp"
