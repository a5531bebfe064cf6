// bemsurg/assembly.hpp: the assembly module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup assembly Assembly
/// \brief Boundary conditions, the influence matrices H and G, the mixed linear system A* x = b, and the rows and columns a mesh change touches (cut_change.hpp).
///
/// Headers (each can be included on its own for faster builds):
/// - boundary_conditions.hpp
/// - cut_change.hpp
/// - element_types.hpp
/// - influence_assembler.hpp
/// - linear_system.hpp
/// - node_influence_assembler.hpp

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/cut_change.hpp"
#include "bemsurg/assembly/element_types.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/assembly/node_influence_assembler.hpp"
