// Definitions for contact_validity.hpp (inline; docs/design.md §6 depth range).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

namespace detail {
BEMSURG_INLINE std::string short_number(double x) {
  return std::isfinite(x) ? general_text(x, 3) : std::string("more than 1e308");  // depth 1e308 over a 0.05 body
}
}  // namespace detail

BEMSURG_INLINE ContactDepthCheck check_contact_depth(const TriangleMesh& mesh, const Eigen::Vector3d& direction, double depth,
                                                     double tool_radius, const ContactDepthLimits& limits) {
  using detail::short_number;
  if (!std::isfinite(depth) || depth < 0.0) throw ContactError("contact depth " + short_number(depth) + " must be finite and non-negative");
  const double dn = direction.stableNorm();
  if (!(dn > 0.0) || !std::isfinite(dn)) throw ContactError("contact depth check: the push direction must be finite and nonzero");
  const Eigen::Vector3d d = direction / dn;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    const double s = mesh.vertices().row(v).dot(d.transpose());
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  ContactDepthCheck c;
  c.body_extent = hi - lo;
  if (!(c.body_extent > 0.0) || !std::isfinite(c.body_extent))
    throw ContactError("contact depth check: the body has no finite extent along the push direction");
  c.body_strain = depth / c.body_extent;
  c.tool_strain = tool_radius > 0.0 ? depth / tool_radius : 0.0;
  const std::string pushed = "the tool pushes " + short_number(depth) + " beyond first contact";
  if (c.body_strain > limits.max_body_strain)
    throw ContactError(pushed + ", " + short_number(100.0 * c.body_strain) + " % of the body's extent along the push (" +
                       short_number(c.body_extent) + "): beyond the small-strain range of linear elasticity (at most " +
                       short_number(100.0 * limits.max_body_strain) +
                       " %, depth <= " + short_number(limits.max_body_strain * c.body_extent) + "); docs/design.md §6");
  if (c.tool_strain > limits.max_tool_strain)
    throw ContactError(pushed + ", " + short_number(c.tool_strain) + " times the tool radius " + short_number(tool_radius) +
                       ": beyond the contact model's range (at most " + short_number(limits.max_tool_strain) +
                       " radius, depth <= " + short_number(limits.max_tool_strain * tool_radius) +
                       "; deeper, the footprint outgrows the tool and the strain is not small); docs/design.md §6");
  if (c.body_strain > limits.warn_body_strain)
    c.warning = pushed + ", " + short_number(100.0 * c.body_strain) + " % of the body's extent along the push (" +
                short_number(c.body_extent) + "): above " + short_number(100.0 * limits.warn_body_strain) +
                " % strain linear elasticity is only approximate";
  else if (c.tool_strain > limits.warn_tool_strain)
    c.warning = pushed + ", " + short_number(c.tool_strain) + " times the tool radius " + short_number(tool_radius) + ": above " +
                short_number(limits.warn_tool_strain) + " radius the small-strain contact is only approximate";
  return c;
}

BEMSURG_INLINE ToolResolutionCheck check_tool_resolution(const TriangleMesh& mesh, Index element, bool sphere, double tool_radius,
                                                         double depth) {
  using detail::short_number;
  ToolResolutionCheck c;
  if (element < 0 || element >= mesh.num_elements() || !(tool_radius > 0.0) || (sphere && !(depth > 0.0)))
    return c;  // a punch's resolution does not depend on the depth; a sphere's footprint does
  c.contact_radius = sphere ? std::min(tool_radius, std::sqrt(tool_radius * depth)) : tool_radius;
  c.element_size = std::sqrt(2.0 * mesh.area(element));
  c.limit = sphere ? kMinSphereContactRadiusPerElement : kMinPunchRadiusPerElement;
  if (c.contact_radius < c.limit * c.element_size)
    c.warning = std::string(sphere ? "the sphere's contact radius " : "the punch radius ") + short_number(c.contact_radius) + " is " +
                short_number(c.contact_radius / c.element_size) + " element sizes (" + short_number(c.element_size) +
                " under the tool): below " + short_number(c.limit) +
                " the force can be more than 10 % off; refine the mesh there or use a larger tool (docs/stability.md)";
  return c;
}

}  // namespace bemsurg
