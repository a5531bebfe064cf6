// bemsurg/cutting.hpp: the cutting module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup cutting Cutting
/// \brief Surface cuts that open a gap along a path, and the exact update of the system and the table after each cut step (Wang et al. 2007 sec. 5.3, Table 1), behind one entry point (CutSystemUpdate) with one set of rules.
///
/// Headers (each can be included on its own for faster builds):
/// - cut_change.hpp
/// - cut_system_update.hpp
/// - gap_limit.hpp
/// - surface_cutter.hpp
/// - table_update.hpp

#include "bemsurg/cutting/cut_change.hpp"
#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/cutting/gap_limit.hpp"
#include "bemsurg/cutting/surface_cutter.hpp"
#include "bemsurg/cutting/table_update.hpp"
