// The depth range in which a tool pressed into the body is within the model: linear elasticity
// (small strain) and the contact geometry of contact_tools.hpp (docs/design.md §6, §10).
#pragma once

#include <Eigen/Core>
#include <limits>
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
/// \ingroup presolution
struct ContactDepthLimits {
  double warn_body_strain = 0.05;
  double max_body_strain = 0.2;
  double warn_tool_strain = 0.1;
  // 0.5: there Hertz's force departs 5 % from the linear-elastic force of the exact sphere
  // (Sneddon), and the contact radius is 0.65 R (docs/stability.md (h), report.md "(h) Press
  // depth against tool radius").
  double max_tool_strain = 0.5;

  /// For studies only (bench_stability (h), docs/stability.md): nothing is refused (the max_*
  /// are infinite), the warnings stay; check_contact_depth then only measures the strains.
  static ContactDepthLimits for_studies() {
    ContactDepthLimits l;
    l.max_body_strain = l.max_tool_strain = std::numeric_limits<double>::infinity();
    return l;
  }
};

/// What check_contact_depth found: the two strains (tool_strain is 0 for a point tool) and a
/// warning (empty when the depth is inside the small-strain range).
/// \ingroup presolution
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

/// Contact radius over element size below which the tool's force is unreliable (more than 10 %
/// off Boussinesq's punch or Hertz's sphere on a resolved half-space; docs/stability.md (g),
/// report.md "(g) Thin parts and tool size against element size"): the punch's force wanders by
/// more than 10 % from about 1.2 radii per element, the sphere's from 2.5 (its pressure
/// vanishes at the footprint's edge, so fewer elements carry it).
constexpr double kMinPunchRadiusPerElement = 1.5;
constexpr double kMinSphereContactRadiusPerElement = 2.5;

/// What check_tool_resolution found: the contact radius (the punch's radius, or the sphere's
/// Hertz footprint sqrt(R depth), at most R), the element size sqrt(2 area) under the tool's
/// axis, the limit that applies, and a warning naming the three (empty when resolved).
/// \ingroup presolution
struct ToolResolutionCheck {
  double contact_radius = 0.0;
  double element_size = 0.0;
  double limit = 0.0;
  std::string warning;
};

/// Checks a flat punch (sphere = false) of radius `tool_radius`, or a sphere of that radius pressed
/// `depth` beyond first contact, landing on `element` of `mesh`. Warns (never throws: the force is
/// a coarse estimate, not a wrong state) when contact radius / element size is below the limit.
ToolResolutionCheck check_tool_resolution(const TriangleMesh& mesh, Index element, bool sphere, double tool_radius, double depth);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/presolution/impl/contact_validity_impl.hpp"
#endif
