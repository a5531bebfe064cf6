// bemsurg/post/interior_clearance.hpp: how close to the surface an interior point may be for the
// adaptive quadrature to integrate Somigliana's identity accurately there (docs/design.md §4, §10).
//
// The near-singular integrals of an element seen from a point at distance d are resolved by
// splitting the element until a child's distance is mid_ratio times its size (ElementQuadrature);
// splitting stops at max_depth, where children are 2^-max_depth of the element's longest edge h.
// Below d ≈ mid_ratio 2^-max_depth h the deepest children are still too close and the rule is
// wrong: under a rigid translation (exact stress 0) a point 1e-3 h from a face of a cube had
// stresses of 3e-3 E|u| and 1e-4 h gave 4e3 E|u| (defaults: mid_ratio 1.5, max_depth 10). With a
// factor 2 of margin, points closer than
//     min_clearance_fraction(options) x h = 2 mid_ratio 2^-max_depth h   (2.9e-3 h by default)
// to any element are refused; just outside that distance the same test gives stresses of 2-3e-5
// E|u| and u to 3e-9 (tests/test_bem_interior.cpp).
// Raising max_depth halves the distance per level (max_depth 20: 2.9e-6 h).
//
// Stress has a second, larger limit that no quadrature lifts (docs/stability.md, study (b)): the
// boundary data are constant per element, and the jumps of u and t between neighbouring elements
// make the stress of Somigliana's identity grow like h / d next to element edges and vertices,
// with exact integration too (max_depth 20 gives the same figures). On the Kelvin box of
// bench_stability --study interior the stress error near a mesh vertex was about 0.04-0.07 h / d
// (20 % at d ~ 0.2-0.3 h, 1500 % at the 2.9e-3 h displacement limit) while u stayed within a few
// per cent; so stress is refused closer than kMinStressClearanceFraction x h.
#pragma once

#include <Eigen/Core>

#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"

namespace bemsurg {

/// The smallest distance to an element, as a fraction of its longest edge, at which an interior
/// point is evaluated: 2 mid_ratio 2^-max_depth.
double min_clearance_fraction(const QuadratureOptions& options);

/// Stress is evaluated no closer to an element than this fraction of its longest edge: there the
/// stress error of constant elements, about 0.05 h / d near element vertices, reaches ~20 %
/// (docs/stability.md, study (b); bench_stability --study interior measures it).
inline constexpr double kMinStressClearanceFraction = 0.25;

/// The stress limit: the larger of kMinStressClearanceFraction and min_clearance_fraction(options).
double min_stress_clearance_fraction(const QuadratureOptions& options);

/// Which quantity a clearance check is for: displacement (the quadrature's limit) or stress (also
/// the constant elements' limit, kMinStressClearanceFraction).
/// \ingroup post
enum class ClearanceQuantity { Displacement, Stress };

/// The first point closer to some element than min_clearance_fraction x that element's longest
/// edge: point = -1 when every point is clear. element, distance, element_size and required
/// describe the violation (the element with the smallest distance / required ratio).
/// \ingroup post
struct ClearanceViolation {
  Index point = -1;
  Index element = -1;
  double distance = 0.0;
  double element_size = 0.0;
  double required = 0.0;
  ClearanceQuantity quantity = ClearanceQuantity::Displacement;
};
ClearanceViolation find_point_too_close(const TriangleMesh& mesh, const RowMatrixX3d& points, const QuadratureOptions& options,
                                        ClearanceQuantity quantity = ClearanceQuantity::Displacement);

/// "is 1e-05 from element 12 (longest edge 0.354), closer than 0.00293 x 0.354 = 0.00104 ..."
/// for messages: what is wrong and what to do.
std::string describe_clearance_violation(const ClearanceViolation& v, const QuadratureOptions& options);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/post/impl/interior_clearance_impl.hpp"
#endif
