// bemsurg/elastostatics.hpp: the elastostatics module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup elastostatics Elastostatics
/// \brief The boundary value problem as one object (mesh, material, gravity, conditions, quadrature), the one check made before every solve and table, and the one-call solve.
///
/// Headers (each can be included on its own for faster builds):
/// - elastostatic_problem.hpp
/// - elastostatic_solver.hpp
/// - hierarchical_solver.hpp

#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
