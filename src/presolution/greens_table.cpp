// GreensTable's definitions: the pre-solution table, its file key and its exact cut updates.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/presolution/greens_table.hpp"

#include "bemsurg/presolution/impl/greens_table_impl.hpp"
