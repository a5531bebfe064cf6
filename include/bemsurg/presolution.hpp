// bemsurg/presolution.hpp: the presolution module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup presolution Pre-solution and contact
/// \brief Green's tables (pre-solutions for unit displacements of the elements tools can touch), their exact update after a mesh change, and contact of several tools at haptic rates by capacitance matrices (Wang et al. 2007 sec. 5.1-5.2).
///
/// Headers (each can be included on its own for faster builds):
/// - capacitance_contact.hpp
/// - contact_tools.hpp
/// - contact_validity.hpp
/// - greens_table.hpp
/// - hierarchical_table.hpp
/// - paper_lookup_table.hpp
/// - table_file.hpp

#include "bemsurg/presolution/capacitance_contact.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "bemsurg/presolution/contact_validity.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/presolution/hierarchical_table.hpp"
#include "bemsurg/presolution/paper_lookup_table.hpp"
#include "bemsurg/presolution/table_file.hpp"
