// The solvers module's definitions: the one linear-solve entry point and the low-rank updated LU of cut steps.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/solvers/linear_solve.hpp"
#include "bemsurg/solvers/low_rank_updated_lu.hpp"

#include "bemsurg/solvers/impl/linear_solve_impl.hpp"
#include "bemsurg/solvers/impl/low_rank_updated_lu_impl.hpp"
