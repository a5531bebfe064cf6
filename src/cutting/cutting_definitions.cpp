// The cutting module's definitions: SurfaceCutter, the groove topology of a cut (Wang et al. 2007 §5.3).
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/cutting/surface_cutter.hpp"
#include "bemsurg/cutting/table_update.hpp"

#include "bemsurg/cutting/impl/cut_checks_impl.hpp"
#include "bemsurg/cutting/impl/cut_groove_impl.hpp"
#include "bemsurg/cutting/impl/cut_table_step_impl.hpp"
#include "bemsurg/cutting/impl/cut_work_impl.hpp"
#include "bemsurg/cutting/impl/surface_cutter_impl.hpp"
#include "bemsurg/cutting/impl/table_update_impl.hpp"
