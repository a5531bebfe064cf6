// bemsurg/meshing/mesh_preparation.hpp: from a segmentation's surface, as exported, to a mesh the BEM
// can solve on a small machine (issue 28; docs/organs.md).
//
// A surface exported by 3D Slicer, ITK-SNAP or a marching-cubes run is in millimetres, has 10^4 to
// 10^6 triangles and often defects: duplicate vertices, zero-area faces, flipped patches, small
// holes, and worse, faces that cross each other, edges shared by three faces, overlapping shells.
// prepare_mesh runs the same steps whatever the input:
//   1. units: coordinates times `scale` (1e-3 for mm), so the output is in metres;
//   2. clean: merge coincident vertices, drop degenerate and repeated faces, then orient each
//      connected part consistently (CGAL's orient_polygon_soup);
//   3. close: fill holes whose boundary is shorter than max_hole_fraction of the bounding-box
//      diagonal (CGAL's triangulate_and_refine_hole); a longer one is an open sheet, refused;
//   4. rebuild when the surface still is not a body (it crosses itself, has non-manifold edges or
//      vertices, or shells that overlap): CGAL's 3-D alpha wrapping, which returns a watertight,
//      2-manifold surface at distance `offset` outside the input, following it up to details
//      smaller than `alpha` (both fractions of the bounding-box diagonal, stated below);
//   5. bodies: nested shells are oriented as a body with cavities (outer outward, inner inward);
//      of several disjoint bodies the largest by volume is kept unless keep_all;
//   6. remesh with Gmsh (mesh/graded_remesher.hpp): graded to an operating region, or uniform to
//      a target element count or edge length, and by default to default_elements (3,000, or
//      6,000 for the hierarchical backend; a repaired surface with fewer faces is kept as it is);
//   7. check: require_valid_mesh on the result, the two-sided Hausdorff distance and the volume
//      change against the (scaled) input.
// Same input and options give the same mesh, vertex for vertex: every step is deterministic and
// single-threaded, so table caches keyed on the mesh stay valid.
//
// Compiled in src/meshing/mesh_preparation.cpp and src/meshing/cgal_repair.cpp (the one file that
// includes CGAL), only with BEMSURG_WITH_PREPARE (on when CMake finds CGAL and Gmsh):
// mesh_preparation_available() says whether this build has it; without it prepare_mesh throws.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/mesh/operating_region.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/meshing/graded_remesher.hpp"

namespace bemsurg {

/// Element count of a prepared mesh when no target is given: a dense solve of 3,000 constant
/// elements (9,000 equations, ~1.3 GiB) takes about a minute on a 2-core machine with its Green's
/// table (docs/organs.md, "How big"). Never more than the repaired surface itself has.
inline constexpr Index kDefaultPreparedElements = 3000;
/// The same for the hierarchical backend (`bemsurg prepare` built with hmat-oss, a scene whose
/// solver says "hmatrix"): a 6,028-element prepared liver's table (438 columns) took 41 s and
/// 555 MiB on a 2-core machine, where its dense solve alone was estimated at 4.87 GiB and 171 s.
inline constexpr Index kDefaultPreparedElementsHierarchical = 6000;
/// Upper bound of target_elements: the graded remesher's own limit (a dense system of 1.8e5
/// equations, 2 x 240 GiB: for machines far larger than the 2-core default's).
inline constexpr Index kMaxPreparedElements = 60000;
/// Default hole limit: holes whose boundary loop is shorter than this fraction of the bounding-box
/// diagonal are filled; a longer one means an open sheet, not a body, and is refused.
inline constexpr double kDefaultMaxHoleFraction = 0.2;
/// Default alpha of the rebuild, as a fraction of the bounding-box diagonal: details narrower than
/// about this (1/150: ~1.7 mm on a 250 mm liver) are closed over.
inline constexpr double kDefaultWrapAlphaFraction = 1.0 / 150.0;
/// Default offset of the rebuild, as a fraction of alpha: the wrap lies this far outside the input.
inline constexpr double kDefaultWrapOffsetFraction = 1.0 / 20.0;
/// An input whose bounding box is larger than this (m) with no unit given is almost surely in mm.
inline constexpr double kLargestBodyMetres = 2.0;

/// Length unit names understood by prepare_mesh's callers: "mm", "cm", "m". Returns the factor to
/// metres, or throws InvalidArgumentError naming the unit and the accepted ones.
double length_unit_to_metres(const std::string& unit);

/// What prepare_mesh does: units, repair tolerances and the remesh target.
/// \ingroup meshing
struct MeshPreparationOptions {
  /// Factor to metres (e.g. 1e-3 for millimetres). `scale_given` false means the caller gave no
  /// unit: an input larger than kLargestBodyMetres is then warned about.
  double scale = 1.0;
  bool scale_given = false;
  /// Rebuild parameters, fractions of the (scaled) input's bounding-box diagonal / of alpha.
  double wrap_alpha_fraction = kDefaultWrapAlphaFraction;
  double wrap_offset_fraction = kDefaultWrapOffsetFraction;
  /// Rebuild by alpha wrapping even if the cleaned surface is already a body.
  bool force_wrap = false;
  /// Fill holes whose boundary is shorter than this fraction of the bounding-box diagonal.
  double max_hole_fraction = kDefaultMaxHoleFraction;
  /// Keep every disjoint body instead of the largest by volume.
  bool keep_all = false;
  /// Remesh target: at most one of target_elements (> 0), edge_length (> 0, metres) and region.
  /// With none, a uniform remesh to default_elements, or none at all when the repaired surface has
  /// no more faces than that.
  Index target_elements = 0;
  /// The target when none is given: kDefaultPreparedElements, or kDefaultPreparedElementsHierarchical
  /// for a mesh the hierarchical backend will solve.
  Index default_elements = kDefaultPreparedElements;
  double edge_length = 0.0;
  /// A graded remesh to this operating region with graded_options (mesh/graded_remesher.hpp).
  std::optional<OperatingRegion> region;
  GradedRemeshOptions graded_options;
  /// Skip step 6: return the repaired surface (a scene that grades it later). With
  /// graded_options.inside_edge_length > 0 a very fine surface is still coarsened for that remesh.
  bool no_remesh = false;
};

/// Counts of each kind of defect found in the input (after scaling, before any repair).
/// \ingroup meshing
struct MeshDefectCounts {
  Index duplicate_vertices = 0;     // vertices merged into an earlier coincident one
  Index unreferenced_vertices = 0;  // vertices no face uses
  Index degenerate_faces = 0;       // zero-area faces (a repeated corner or collinear corners)
  Index slivers = 0;                // faces of non-zero area above kMaxAspectRatio (1e4): remeshed away, never kept
  Index duplicate_faces = 0;        // faces with the same three vertices as an earlier face
  Index flipped_faces = 0;          // faces whose orientation was reversed to agree with their neighbours
  Index boundary_edges = 0;         // edges with one face
  Index holes = 0;                  // boundary loops
  Index non_manifold_edges = 0;     // edges with more than two faces
  Index non_manifold_vertices = 0;  // vertices where separate fans of faces meet
  Index self_intersections = 0;     // pairs of faces that cross (after cleaning)
  Index shells = 0;                 // connected parts (sharing edges)
  Index total() const {
    return duplicate_vertices + degenerate_faces + slivers + duplicate_faces + flipped_faces + boundary_edges + non_manifold_edges +
           non_manifold_vertices + self_intersections;
  }
};

/// What prepare_mesh did and measured, for the printed summary and the JSON report (docs/organs.md).
/// \ingroup meshing
struct MeshPreparationReport {
  Index input_vertices = 0, input_faces = 0;
  double scale = 1.0;
  Vec3 input_size = Vec3::Zero();  // bounding-box extent after scaling (m)
  MeshDefectCounts defects;
  Index holes_filled = 0;
  bool rebuilt = false;  // alpha wrapping was used
  std::string rebuild_reason;
  double wrap_alpha = 0.0, wrap_offset = 0.0;  // metres, when rebuilt
  Index bodies = 0, cavities = 0;              // of the repaired surface
  Index bodies_dropped = 0;
  double dropped_volume = 0.0;       // m^3
  Index repaired_elements = 0;       // after repair, before remeshing
  std::string remesh;                // "graded", "uniform" or "none"
  Index target_elements = 0;         // uniform remesh to a count: the count aimed at (0 otherwise)
  double target_edge_length = 0.0;   // uniform remesh: the edge length used (m)
  Index elements = 0, vertices = 0;  // final
  double hausdorff = 0.0;            // two-sided, input vs final (m)
  double hausdorff_relative = 0.0;   // over the bounding-box diagonal
  /// Input sample points left out of the distance: on dropped bodies, or walls inside the result
  /// farther than 1 % of the diagonal from its surface (the inner parts of overlapping shells).
  Index hausdorff_excluded_samples = 0;
  double input_volume = 0.0, volume = 0.0;    // m^3; input: the cleaned surface's, holes filled
  double volume_change = 0.0;                 // (volume - input_volume) / input_volume
  double estimated_bytes = 0.0;               // dense solve of the final mesh (estimate_elastostatic_bytes)
  double estimated_seconds = 0.0;             // dense solve, calibrated on this machine (docs/organs.md)
  double hierarchical_estimated_bytes = 0.0;  // hierarchical solve (estimate_hierarchical_bytes), where set
  std::vector<std::string> warnings;
  std::vector<std::string> steps;  // one line per step done, in order
  /// Seconds per stage, in order: read (set by callers that read), clean, orient_and_close,
  /// self_intersection, wrap, bodies, remesh, measure.
  std::vector<std::pair<std::string, double>> timings;
  double seconds = 0.0;
};

/// The prepared surface (metres, closed, 2-manifold, outward, validated) and the report.
/// \ingroup meshing
struct PreparedMesh {
  TriangleMesh mesh;
  MeshPreparationReport report;
};

/// Whether this build includes prepare_mesh (BEMSURG_WITH_PREPARE: CGAL and Gmsh).
bool mesh_preparation_available();

/// Steps 1-7 above on a surface as read (mesh/mesh_io.hpp's readers keep every defect). Throws
/// InvalidArgumentError for options out of range (naming the option), InvalidMeshError for an
/// input that cannot be made a body (an empty or non-finite input, a hole longer than the limit,
/// no closed region after repair) with the figures and the option to change, and bemsurg::Error
/// when this build has no preparation.
PreparedMesh prepare_mesh(const TriangleMesh& input, const MeshPreparationOptions& options);

/// A multi-line, human-readable summary of the report (what `bemsurg prepare` prints).
std::string describe_preparation(const MeshPreparationReport& report);

}  // namespace bemsurg
