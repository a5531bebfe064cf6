// bemsurg/kernels/kelvin_constants.hpp: the material constants of the Kelvin kernels U, T, the
// gravity kernel P and their derivatives, computed in one place (docs/design.md, kernels; Wang et
// al. 2007 eqs. 2-3). KelvinKernel, GravityKernel, KelvinKernelGradients and the assembler's far
// field loop all read them from here, so a change of convention cannot leave one of them behind.
#pragma once

#include <cmath>

#include "bemsurg/constants.hpp"
#include "bemsurg/material.hpp"

namespace bemsurg {

/// The material constants of the Kelvin kernels U, T, the gravity kernel P and their derivatives (Wang et al. 2007
/// eqs. 2-3), computed in one place from a Material so that every kernel and the assembler use the same convention.
/// \ingroup kernels
struct KelvinConstants {
  double mu;               // shear modulus
  double nu;               // Poisson's ratio
  double u_scale;          // 1 / (16 pi mu (1 - nu)): U_ij = u_scale [(3 - 4 nu) delta_ij + r,i r,j] / r
  double t_scale;          // -1 / (8 pi (1 - nu)):     T_ij = t_scale [...] / r^2
  double p_scale;          // 1 / (8 pi mu):            P_i  = p_scale [b_i dr/dn - n_i (b . r,) p_half_inv]
  double p_half_inv;       // 1 / (2 (1 - nu))
  double three_minus_4nu;  // 3 - 4 nu
  double one_minus_2nu;    // 1 - 2 nu

  explicit KelvinConstants(const Material& m)
      : mu(m.shear_modulus()),
        nu(m.poisson_ratio),
        u_scale(1.0 / (16.0 * numbers::pi * mu * (1.0 - nu))),
        t_scale(-1.0 / (8.0 * numbers::pi * (1.0 - nu))),
        p_scale(1.0 / (8.0 * numbers::pi * mu)),
        p_half_inv(1.0 / (2.0 * (1.0 - nu))),
        three_minus_4nu(3.0 - 4.0 * nu),
        one_minus_2nu(1.0 - 2.0 * nu) {}
};

}  // namespace bemsurg
