// bemsurg/io.hpp: the io module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup io Input and output
/// \brief Scenes (JSON), boundary-condition and point files (CSV), action scripts, element selectors, results files; every number read and written independently of the locale.
///
/// Headers (each can be included on its own for faster builds):
/// - action_script.hpp
/// - boundary_rule_area.hpp
/// - element_selector.hpp
/// - results_io.hpp
/// - scene.hpp
/// - scene_table.hpp

#include "bemsurg/io/action_script.hpp"
#include "bemsurg/io/boundary_rule_area.hpp"
#include "bemsurg/io/element_selector.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/io/scene_table.hpp"
