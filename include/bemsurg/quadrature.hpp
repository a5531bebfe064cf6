// bemsurg/quadrature.hpp: the quadrature module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup quadrature Quadrature
/// \brief Triangle quadrature rules and the element integration policy: far-field rules, collapsed Gauss for near pairs, the polar rule for the singular self pair, and their cost.
///
/// Headers (each can be included on its own for faster builds):
/// - element_quadrature.hpp
/// - quadrature_cost.hpp
/// - triangle_rules.hpp

#include "bemsurg/quadrature/element_quadrature.hpp"
#include "bemsurg/quadrature/quadrature_cost.hpp"
#include "bemsurg/quadrature/triangle_rules.hpp"
