// The assembly module's definitions: the column swap and the right-hand side.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/assembly/linear_system.hpp"

#include "bemsurg/assembly/impl/linear_system_impl.hpp"
