// The core module's definitions: the memory budget.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/memory_budget.hpp"

#include "bemsurg/impl/memory_budget_impl.hpp"
