// The memory budget's definitions, compiled once here under BEMSURG_SEPARATE_COMPILATION
// (include/bemsurg/config.hpp); header-only programs (bemsurg::core) get them inline.
#include "bemsurg/memory_budget.hpp"

#include "bemsurg/impl/memory_budget_impl.hpp"
