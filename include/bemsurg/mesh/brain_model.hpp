// bemsurg/mesh/brain_model.hpp: a procedural, deterministic brain-like surface (docs/graded.md):
// two hemispheres separated by a midline (longitudinal) fissure, gyri-like folds, and a flat
// underside at z = 0 on which it rests (the support of the brain scene).
//
// Why written here rather than taken from a library or a scan: the default model must ship with
// the code, be reproducible bit for bit on every machine (tests compare against it), and be small;
// no Debian package provides an anatomical surface, and a scanned brain would be a large data file
// with its own licence. The shape is a *radial graph* over the unit sphere: every point is
// base + R(d) d for a unit direction d and a positive R. A positive radial function always gives
// an embedded (self-intersection-free), closed surface of sphere topology, and mapping an
// icosphere through it keeps the icosphere's outward orientation, so the result passes
// validate_mesh by construction. Only the smooth function R is "anatomy":
//
//   R(d) = R_ellipsoid(d) * (1 - fissure(d)) * (1 + folds(d)), then clipped to the plane z = 0.
//
// The mesh it returns follows the icosphere and is meant as the *input* of the graded remesher
// (mesh/graded_remesher.hpp), which resamples it at the sizes a scene asks for; it is fine enough
// (subdivisions 4-5) to carry the folds.
#pragma once

#include <Eigen/Core>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Shape and resolution of the procedural brain surface (brain_mesh, brain_surface_point): overall size, midline
/// fissure, gyri-like folds and the icosphere subdivisions of the returned mesh.
/// \ingroup mesh
struct BrainModelOptions {
  /// Overall extent along x (front to back), y (left to right) and z (height above the support);
  /// an adult human brain is about 167 x 140 x 93 mm.
  Vec3 size = Vec3(0.16, 0.13, 0.085);
  /// Depth of the midline fissure as a fraction of the local radius, and its half-width (m): a
  /// groove about 1.5 cm deep, smooth enough that a 2-3 mm input mesh resolves it.
  double fissure_depth = 0.22;
  double fissure_half_width = 0.01;
  /// Amplitude of the gyri-like folds as a fraction of the local radius, and their wavelength (m).
  double fold_amplitude = 0.025;
  double fold_wavelength = 0.03;
  /// Icosphere subdivisions of the returned mesh: 20 * 4^s faces (0..7). 5 (20480 faces, ~2.3 mm)
  /// is what the remesher needs: at 4 the rim of the underside, which cuts across the icosphere's
  /// triangles, is too jagged for Gmsh's crease detection at 40 degrees (docs/graded.md).
  int subdivisions = 5;
};

/// The closed, outward-oriented brain surface; its underside is the disc-like flat part on the
/// plane z = 0, the midline fissure lies along the plane y = 0, the top is at about z = size.z().
/// Throws InvalidMeshError for non-positive or non-finite sizes, a fissure depth outside [0, 0.8),
/// a fold amplitude outside [0, 0.2), a non-positive width or wavelength, or subdivisions outside 0..7.
TriangleMesh brain_mesh(const BrainModelOptions& options = {});

/// The point of the brain surface in unit direction `direction` from the shape's centre (the same
/// radial function as brain_mesh, without the mesh): where to put an operating region on top.
Vec3 brain_surface_point(const BrainModelOptions& options, const Vec3& direction);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/brain_model_impl.hpp"
#endif
