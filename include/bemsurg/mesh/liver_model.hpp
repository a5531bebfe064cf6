// bemsurg/mesh/liver_model.hpp: a procedural, deterministic liver-like surface (docs/haptics.md,
// "Feeling through a cut"; examples/scenes/liver.json): a large rounded right lobe and a thinner,
// flatter left lobe, joined smoothly. Like the brain model (brain_model.hpp) it is a radial graph
// over the unit sphere, base + R(d) d with R > 0, so it is closed, embedded and outward-oriented by
// construction; R is the smooth maximum (R1^p + R2^p)^(1/p), p = 6, of the two lobes' ellipsoids
// seen from a point inside both (a union of two sets star-shaped about one point is star-shaped
// about it). It is written here rather than taken from a scan for the same reasons as the brain:
// shipped with the code, reproducible bit for bit, no third-party data or licence. It is meant as
// the input of the graded remesher (mesh/graded_remesher.hpp).
#pragma once

#include <Eigen/Core>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Size and resolution of the procedural liver surface (liver_mesh, liver_surface_point).
/// \ingroup mesh
struct LiverModelOptions {
  /// Overall extent along x (right lobe at +x, left lobe at -x), y (front to back) and z (height);
  /// an adult liver measures about 200 x 150 x 100 mm. The lobes are scaled from it.
  Vec3 size = Vec3(0.2, 0.15, 0.1);
  /// Icosphere subdivisions of the returned mesh: 20 * 4^s faces (0..7).
  int subdivisions = 4;
};

/// The closed, outward-oriented liver surface, centred on the origin of its radial function
/// (inside both lobes); the right lobe's top lies near (0.15 size.x, 0, 0.45 size.z). Throws
/// InvalidMeshError for non-positive or non-finite sizes or subdivisions outside 0..7.
TriangleMesh liver_mesh(const LiverModelOptions& options = {});

/// The point of the liver surface in unit direction `direction` from the origin (where to put a
/// tool, an operating region or a support).
Vec3 liver_surface_point(const LiverModelOptions& options, const Vec3& direction);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/liver_model_impl.hpp"
#endif
