// The core module's definitions: the memory budget, the BLAS thread caps, the snapshot buffers.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/blas_threads.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/snapshot_buffers.hpp"

#include "bemsurg/impl/blas_threads_impl.hpp"
#include "bemsurg/impl/memory_budget_impl.hpp"
#include "bemsurg/impl/snapshot_buffers_impl.hpp"
