// bemsurg/meshing/mesh_defects.hpp: turning a clean surface into the broken ones that segmentation
// tools export (docs/organs.md), one kind of defect per function, to test a mesh repair.
//
// Surfaces from 3D Slicer, ITK-SNAP or a marching-cubes script arrive as triangle soups in
// millimetres, with zero-area faces, patches facing the wrong way, small holes, faces crossing
// each other, fins and pinches where two parts touch, loose specks of noise and overlapping
// pieces. Each function below adds exactly one such kind to a clean, closed, outward mesh and says
// what validate_mesh (mesh/mesh_validation.hpp), MeshTopology or find_self_intersections then
// reports; where a defect cannot come alone (a fin has a free rim) the companion is named too.
// Every function is deterministic: the places it picks come from `seed` (std::mt19937_64, whose
// sequence the C++ standard fixes, reduced modulo the count), so a test or a benchmark rebuilds
// the same input byte for byte. None needs more than a clean closed mesh with faces of similar
// size; picks are made far from earlier defects only by chance (on 10^5 faces, a safe one).
#pragma once

#include <cstdint>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Every face gets its own three vertices, as an STL triangle soup read without welding: each
/// vertex of the input is repeated once per face that uses it. validate_mesh: DuplicateVertex
/// (and every edge a BoundaryEdge); weld_vertices (mesh/vertex_welding.hpp) undoes it exactly.
TriangleMesh unweld_mesh(const TriangleMesh& mesh);

/// Adds `count` zero-area faces, alternately: (1) three collinear points: a face (a, b, c) is
/// split at the midpoint m of its edge ab into (a, m, c) and (m, b, c), and the flat face (b, m, a)
/// closes the gap, so the surface stays closed, manifold and oriented; (2) a repeated vertex index:
/// a face (a, a, b) between two existing vertices that share no edge (its edge ab is used twice,
/// once each way, so it too leaves every edge manifold). validate_mesh: `count` DegenerateFace
/// errors and nothing else (its self-intersection check is skipped on degenerate meshes).
TriangleMesh add_degenerate_faces(const TriangleMesh& mesh, int count, std::uint64_t seed);

/// Splits `count` distinct faces (a, b, c) at a point p inside each, near the midpoint m of its
/// edge ab: p = m + s (c - m), with s chosen so that the face (a, b, p) has the given aspect ratio
/// (longest edge / shortest altitude, mesh_quality.hpp); (b, c, p) and (c, a, p) are ordinary.
/// The surface stays closed, manifold and oriented, and its volume is unchanged. validate_mesh:
/// `count` DegenerateFace errors ("a sliver") when aspect_ratio is above kMaxAspectRatio, and
/// nothing else. aspect_ratio must be at least 10 (p stays within the face's middle tenth).
TriangleMesh add_slivers(const TriangleMesh& mesh, int count, double aspect_ratio, std::uint64_t seed);

/// Reverses the vertex order of a connected patch of `faces` faces (grown breadth-first from a
/// random face). validate_mesh: InconsistentOrientation on each edge of the patch's rim, nothing else.
TriangleMesh flip_face_patch(const TriangleMesh& mesh, Index faces, std::uint64_t seed);

/// Removes a disk of faces around a random face, grown nearest first (by centroid distance, across
/// edges), until its rim has at least `boundary_edges` edges (it stops at the first size that
/// does: the rim is one loop of boundary_edges edges or a few more); vertices left unused are
/// dropped. validate_mesh: BoundaryEdge on the rim, nothing else. Throws InvalidArgumentError for
/// boundary_edges < 3 or a hole that would take more than a quarter of the faces.
TriangleMesh punch_hole(const TriangleMesh& mesh, Index boundary_edges, std::uint64_t seed);

/// Makes the surface cut through itself within its one shell: a random vertex is pushed inward
/// along its normal, through the body and out of the far side by 0.3 local edge lengths, so its
/// fan of faces (a thin spike) crosses the faces around the exit point, which share no vertex with
/// it. find_self_intersections: a few pairs, each with one face of the moved vertex;
/// validate_mesh: SelfIntersection only.
TriangleMesh poke_through(const TriangleMesh& mesh, std::uint64_t seed);

/// A fin: one triangle standing on an existing edge (a, b), its apex one edge length out along the
/// edge's mean normal. validate_mesh: one NonManifoldEdge (three faces on ab) and the fin's two
/// free edges as BoundaryEdge; no self-intersection.
TriangleMesh add_fin(const TriangleMesh& mesh, std::uint64_t seed);

/// A non-manifold vertex: a small closed, outward tetrahedron (a cone) standing on a random vertex
/// of the surface and sharing only that vertex, so two shells touch at one point. validate_mesh
/// reports nothing (it checks edges, not vertices): MeshTopology shows two shells whose faces meet
/// at the vertex.
TriangleMesh add_touching_cone(const TriangleMesh& mesh, std::uint64_t seed);

/// A second closed, outward shell overlapping the body: an ellipsoid (1,280 faces) centred on a
/// random vertex with semi-axes 0.15 times the bounding box's extents, so about half of it lies
/// inside. validate_mesh: SelfIntersection (its faces cross the body's).
TriangleMesh add_overlapping_ellipsoid(const TriangleMesh& mesh, std::uint64_t seed);

/// A disjoint speck of noise: a closed, outward icosphere (80 faces) whose volume is
/// `volume_fraction` of the mesh's, placed beyond the bounding box's upper corner (0.2 times the
/// diagonal away). validate_mesh reports nothing: it is a second body (shell_bodies).
TriangleMesh add_speck(const TriangleMesh& mesh, double volume_fraction);

/// A nested cavity: a sphere (320 faces) of `radius` around `center` (the caller says where the
/// material is: it must lie inside the body, clear of its surface). Oriented as a cavity (normals
/// into the hole) unless `outward_by_mistake`, the exporter's error of orienting it like an outer
/// surface. validate_mesh: nothing for a cavity; InwardShell for the mistake.
TriangleMesh add_cavity(const TriangleMesh& mesh, const Vec3& center, double radius, bool outward_by_mistake);

/// Every coordinate times `factor` (1000: metres to millimetres, as segmentation tools write).
TriangleMesh scale_mesh(const TriangleMesh& mesh, double factor);

/// What segmentation_like adds (the defaults: the "deliberately defective" input of docs/organs.md).
/// \ingroup meshing
struct SegmentationDefects {
  /// Coordinates times this (1000: metres in, millimetres out).
  double scale = 1000.0;
  /// Zero-area faces (add_degenerate_faces); 0 leaves them out.
  int degenerate_faces = 4;
  /// Faces of the flipped patch (flip_face_patch); 0 leaves it out.
  Index flipped_faces = 12;
  /// Edges of the hole's rim (punch_hole); 0 leaves it out.
  Index hole_boundary_edges = 12;
  /// Whether one vertex is pushed through the body (poke_through).
  bool self_intersection = true;
  /// Whether a fin stands on one edge (add_fin).
  bool non_manifold_edge = true;
  /// Volume of the disjoint speck as a fraction of the body's (add_speck); 0 leaves it out.
  double speck_volume_fraction = 1e-3;
};

/// A realistic mix of defects on a clean, closed, outward mesh in metres: a self-intersection, a
/// fin, a hole, a flipped patch and zero-area faces, then a disjoint speck, then the scale (by
/// default to millimetres), each placed from `seed`. The input a mesh repair must take.
TriangleMesh segmentation_like(const TriangleMesh& mesh, std::uint64_t seed, const SegmentationDefects& defects = {});

}  // namespace bemsurg
