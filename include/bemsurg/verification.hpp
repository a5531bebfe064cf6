// bemsurg/verification.hpp: the verification module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup verification Verification
/// \brief Closed-form solutions of linear elasticity (Kelvin, Lame's hollow sphere, Boussinesq, Hertz, ...) that the tests compare against.
///
/// Headers (each can be included on its own for faster builds):
/// - reference_solutions.hpp

#include "bemsurg/verification/reference_solutions.hpp"
