// The post module's definitions: interior points (Somigliana's identity) and their clearance check.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/post/interior_clearance.hpp"
#include "bemsurg/post/interior_evaluator.hpp"

#include "bemsurg/post/impl/interior_clearance_impl.hpp"
#include "bemsurg/post/impl/interior_evaluator_impl.hpp"
