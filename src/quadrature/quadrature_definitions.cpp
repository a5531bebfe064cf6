// The quadrature module's definitions: the cost estimate of the adaptive rule.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/quadrature/quadrature_cost.hpp"

#include "bemsurg/quadrature/impl/quadrature_cost_impl.hpp"
