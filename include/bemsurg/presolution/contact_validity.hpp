// The depth range in which a tool pressed into the body is within the model: linear elasticity
// (small strain) and the contact geometry of contact_tools.hpp (docs/design.md §6, §10).
#pragma once

#include <Eigen/Core>
#include <string>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Thresholds on the two strain measures of a press (docs/design.md §6):
/// - body strain  depth / T, T = the body's extent along the push direction: the nominal strain
///   of the whole body between the tool and the far side;
/// - tool strain  depth / radius (flat punch and sphere): the indentation strain under the tool
///   (Boussinesq d/a for a punch; Hertz a/R = sqrt(d/R) for a sphere, so d/R = 0.1 is a/R = 0.32).
///   It is also the geometry's limit: a sphere's contact set is gathered within one radius of its
///   axis and its footprint sqrt(R d) reaches that radius at d = R, where the contact breaks down.
/// Up to warn_* the answer is the model's; between warn_* and max_* it is returned with a warning
/// (the model is increasingly approximate); beyond max_* it is refused.
struct ContactDepthLimits {
  double warn_body_strain = 0.05;
  double max_body_strain = 0.2;
  double warn_tool_strain = 0.1;
  double max_tool_strain = 0.5;
};

/// What check_contact_depth found: the two strains (tool_strain is 0 for a point tool) and a
/// warning (empty when the depth is inside the small-strain range).
struct ContactDepthCheck {
  double body_extent = 0.0;
  double body_strain = 0.0;
  double tool_strain = 0.0;
  std::string warning;
};

/// Checks a press of `depth` (>= 0, beyond first contact) along `direction` (any nonzero length)
/// by a tool of `tool_radius` (0 for a point tool; the punch's or sphere's radius otherwise)
/// against `limits`. Throws ContactError naming the depth, the strain and the limit when the depth
/// is beyond max_* (or not finite, or negative); returns the strains and a warning otherwise.
ContactDepthCheck check_contact_depth(const TriangleMesh& mesh, const Eigen::Vector3d& direction, double depth, double tool_radius,
                                      const ContactDepthLimits& limits = ContactDepthLimits());

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/presolution/impl/contact_validity_impl.hpp"
#endif
