// bemsurg/assembly.hpp: the assembly module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup assembly Assembly
/// \brief Boundary conditions, the influence matrices H and G, the mixed linear system A* x = b. The rows and columns a cut changes are the cutting module's (cutting/cut_change.hpp), built on InfluenceAssembler::assemble_rows / assemble_columns.
///
/// Headers (each can be included on its own for faster builds):
/// - boundary_conditions.hpp
/// - element_types.hpp
/// - influence_assembler.hpp
/// - linear_system.hpp
/// - node_influence_assembler.hpp

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/element_types.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/assembly/node_influence_assembler.hpp"
