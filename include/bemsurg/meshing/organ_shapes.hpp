// bemsurg/meshing/organ_shapes.hpp: organ-like bodies as signed functions, in metres, to be sampled
// by mesh/implicit_surface.hpp into what a segmentation tool would export (docs/organs.md).
//
// Coordinates follow the liver model (mesh/liver_model.hpp, examples/scenes/liver.json): x to
// the patient's left-right (+x: the liver's right lobe), y from front (-y, anterior) to back (+y,
// posterior), z up (superior). Each shape comes with where such an organ is held and where a
// surgeon works on it, as plain points and radii, so a scene can select a support region (the
// elements within support_radius of support_center) and an operating region.
//
//   liver:  the procedural liver's surface (liver_surface_point: a smooth union of a rounded right
//           lobe and a flatter left lobe, about 0.2 x 0.15 x 0.1 m), held at its top-back surface
//           (the bare area, where the coronary ligaments and the vena cava attach it to the
//           diaphragm), worked on at the anterior surface of the right lobe;
//   kidney: a bean about 0.06 x 0.04 x 0.11 m (long axis along z): an ellipsoid with a smooth
//           concave indentation, the hilum, on its medial side (-x), held at the hilum and the
//           posterior surface behind it (vessels, ureter, the fat and fascia on the back wall),
//           worked on at its anterior surface.
#pragma once

#include <string>

#include "bemsurg/meshing/implicit_surface.hpp"

namespace bemsurg {

/// An organ as a signed function with a box that contains it, where it is held and where it is
/// operated on (all in metres).
/// \ingroup meshing
struct OrganShape {
  /// Negative inside the organ, positive outside (not a distance, but Lipschitz and smooth).
  ImplicitFunction signed_function;
  /// Lower corner of a box containing the organ with a margin on every side: the box to sample it
  /// in (sample_implicit_surface).
  Vec3 box_lo;
  /// Upper corner of that box.
  Vec3 box_hi;
  /// A point on the surface where the organ is held (its ligaments, vessels or fascia).
  Vec3 support_center;
  /// Radius of the support region around support_center.
  double support_radius = 0.0;
  /// A point on the anterior surface where tools work.
  Vec3 operating_center;
  /// Radius of the operating region around operating_center.
  double operating_radius = 0.0;
};

/// Options of liver_shape: the overall size (as LiverModelOptions::size).
/// \ingroup meshing
struct LiverShapeOptions {
  /// Extent along x, y and z: an adult liver measures about 0.2 x 0.15 x 0.1 m.
  Vec3 size = Vec3(0.2, 0.15, 0.1);
};

/// The liver-like organ: f(x) = |x| - R(x / |x|), where R is the radius of the procedural liver
/// (liver_surface_point), so its surface is exactly liver_mesh's limit surface. Supported at the
/// top-back surface (the surface point in direction (0, 1, 1), radius 0.3 size.y); operated on at
/// the anterior surface of the right lobe (direction (0.5, -1, 0.3), radius 0.15 size.y). Throws
/// InvalidMeshError for non-positive or non-finite sizes.
OrganShape liver_shape(const LiverShapeOptions& options = {});

/// Options of kidney_shape.
/// \ingroup meshing
struct KidneyShapeOptions {
  /// Extent of the ellipsoid along x (medial-lateral width), y (thickness, front to back) and z
  /// (length): an adult kidney measures about 0.06 x 0.04 x 0.11 m.
  Vec3 size = Vec3(0.06, 0.04, 0.11);
  /// How deep the hilum cuts into the medial side (-x), as a fraction of size.x.
  double hilum_depth = 0.25;
  /// Radius of the sphere carved out at the hilum, as a fraction of size.z.
  double hilum_radius = 0.22;
  /// Blend radius of the smooth difference (metres): the hilum's rim is rounded over about this.
  double blend = 0.006;
};

/// The kidney-like organ: an ellipsoid minus (a smooth maximum with blend radius `blend`) a sphere
/// at its medial side. Supported at the hilum and the posterior surface behind it (the surface
/// point in direction (-1, 1, 0) from the inside point (0.2 size.x, 0, 0), radius 0.35 size.z);
/// operated on at the anterior surface (direction (0, -1, 0.2) from the same point, radius
/// 0.15 size.z). Throws InvalidMeshError for non-positive sizes or fractions outside (0, 1).
OrganShape kidney_shape(const KidneyShapeOptions& options = {});

/// The shape by name ("liver" or "kidney", default options); throws InvalidArgumentError naming
/// the known names otherwise.
OrganShape organ_shape(const std::string& name);

/// Smooth minimum of a and b with blend radius k > 0 (polynomial: min(a, b) - k s^2 / 4 with
/// s = max(k - |a - b|, 0) / k): equal to min(a, b) where they differ by more than k. The union
/// of two bodies given by signed functions.
double smooth_min(double a, double b, double k);
/// Smooth maximum, -smooth_min(-a, -b, k): the intersection of two bodies; max(a, -b) is a minus b.
double smooth_max(double a, double b, double k);

}  // namespace bemsurg
