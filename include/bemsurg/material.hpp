// bemsurg/material.hpp: isotropic linear elastic material (small strain), SI units throughout:
// Young's modulus E in Pa, Poisson's ratio nu (dimensionless), density rho in kg/m^3.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

/// Poisson's ratio from which solve_elastostatic warns (ElastostaticResult::warnings) when a closed
/// surface component has its displacement prescribed on every element: at nu = 0.5 the tractions of
/// such a component are determined only up to a pressure p n (the Kelvin displacement kernel's flux
/// through a closed surface vanishes), so A* is singular there and the discretisation error of that
/// pressure mode grows as 1 / (1 - 2 nu) while every solver still converges to a small residual.
/// Measured (docs/stability.md (a), report.md "(a) Poisson's ratio towards 0.5"): the error of a
/// Kelvin Dirichlet box and of Lamé's sphere with its cavity displaced roughly doubles from 0.45 to
/// 0.49 and cond(A*) grows as 1 / (0.5 - nu); mixed problems without such a component do not change.
/// Warned from 0.48, where that growth has begun (issue 37).
inline constexpr double kPoissonRatioWarning = 0.48;
/// Poisson's ratio at and above which check_before_solve refuses (InvalidMaterialError) a problem
/// with such a component, in solve_elastostatic and GreensTable::compute alike: study (a) measured
/// errors above 100 % from about 0.493 on a displacement-only closed surface (docs/stability.md (a)),
/// so the refusal sits just past that, at 0.495 (issue 37). Problems without one are solved up to nu < 0.5.
inline constexpr double kPoissonRatioLimit = 0.495;

/// Isotropic linear elastic material (small strain) in SI units: Young's modulus E in Pa, Poisson's ratio nu and
/// density rho in kg/m^3, with the derived shear modulus and Lame constant and Hooke's law for stresses.
/// \ingroup core
struct Material {
  double young_modulus = 1.0;
  double poisson_ratio = 0.3;
  double density = 0.0;

  /// Throws InvalidMaterialError unless E > 0, -1 < nu < 0.5 (strictly: nu = 0.5 makes the
  /// Kelvin kernels' (1 - 2 nu) terms vanish and the traction kernel singular in 1/(1 - 2 nu)
  /// quantities downstream) and rho >= 0, all finite.
  void validate() const {
    if (!std::isfinite(young_modulus) || young_modulus <= 0.0)
      throw InvalidMaterialError("material: young_modulus must be a finite positive number, got " + number_text(young_modulus));
    if (!std::isfinite(poisson_ratio) || poisson_ratio <= -1.0 || poisson_ratio >= 0.5)
      throw InvalidMaterialError("material: poisson_ratio must lie in the open interval (-1, 0.5), got " + number_text(poisson_ratio));
    if (!std::isfinite(density) || density < 0.0)
      throw InvalidMaterialError("material: density must be finite and non-negative, got " + number_text(density));
  }

  /// This material after validate(): for constructors that must check it before a member that
  /// divides by its constants is built (InfluenceAssembler, the Kelvin kernels).
  const Material& validated() const {
    validate();
    return *this;
  }

  double shear_modulus() const { return young_modulus / (2.0 * (1.0 + poisson_ratio)); }
  double lame_lambda() const { return young_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio)); }

  /// Hooke's law from the displacement gradient du(a, b) = d u_a / d x_b:
  /// sigma = 2 mu eps + lambda tr(eps) I with eps = (du + du^T) / 2 (small strain).
  Eigen::Matrix3d stress(const Eigen::Matrix3d& displacement_gradient) const {
    const Eigen::Matrix3d strain = 0.5 * (displacement_gradient + displacement_gradient.transpose());
    Eigen::Matrix3d sigma = 2.0 * shear_modulus() * strain;
    sigma.diagonal().array() += lame_lambda() * strain.trace();
    return sigma;
  }
};

}  // namespace bemsurg
