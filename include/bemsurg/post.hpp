// bemsurg/post.hpp: the post module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup post Post-processing
/// \brief Interior displacements and stresses from the boundary solution (Somigliana's identity) and the clearance needed for them.
///
/// Headers (each can be included on its own for faster builds):
/// - interior_clearance.hpp
/// - interior_evaluator.hpp

#include "bemsurg/post/interior_clearance.hpp"
#include "bemsurg/post/interior_evaluator.hpp"
