// The presolution module's definitions: Green's tables and their keys, capacitance contact, tools,
// the depth range and the paper's lookup table.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/presolution/capacitance_contact.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "bemsurg/presolution/contact_validity.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/presolution/paper_lookup_table.hpp"

#include "bemsurg/presolution/impl/capacitance_contact_impl.hpp"
#include "bemsurg/presolution/impl/contact_tools_impl.hpp"
#include "bemsurg/presolution/impl/contact_validity_impl.hpp"
#include "bemsurg/presolution/impl/greens_table_impl.hpp"
#include "bemsurg/presolution/impl/paper_lookup_table_impl.hpp"
