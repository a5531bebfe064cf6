// bemsurg/kernels.hpp: the kernels module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup kernels Kernels
/// \brief Kelvin's fundamental solutions U and T of linear elastostatics and their gradients, with the sign conventions of docs/design.md (Wang et al. 2007 eqs. 2-4).
///
/// Headers (each can be included on its own for faster builds):
/// - kelvin_constants.hpp
/// - kelvin_kernel.hpp
/// - kernel_gradients.hpp

#include "bemsurg/kernels/kelvin_constants.hpp"
#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/kernels/kernel_gradients.hpp"
