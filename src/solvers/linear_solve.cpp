// solve_linear_system's definitions: LU or a Krylov method with its preconditioner.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/solvers/linear_solve.hpp"

#include "bemsurg/solvers/impl/linear_solve_impl.hpp"
