// bemsurg/mesh/mesh_validation.hpp: is this surface a usable BEM boundary (docs/design.md §2)?
//
// The BEM needs closed, 2-manifold, consistently oriented shells with normals out of the
// material and no degenerate elements; anything else gives a singular or silently wrong
// system. validate_mesh collects every problem it finds (so a user can fix a file in one go);
// require_valid_mesh throws InvalidMeshError naming the first offending face, edge or vertex.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// What a MeshIssue is about: one value per check validate_mesh makes (kNumMeshIssueKinds of them).
/// \ingroup mesh
enum class MeshIssueKind {
  EmptyMesh,                // no faces (or no vertices)
  NonFiniteVertex,          // NaN or infinite coordinate
  DegenerateFace,           // area below the tolerance, or a face repeating a vertex
  DuplicateVertex,          // two used vertices at the same place: usually an unwelded mesh
  BoundaryEdge,             // an edge with one face: the surface is not closed
  NonManifoldEdge,          // an edge with more than two faces
  InconsistentOrientation,  // two faces traverse their shared edge in the same direction
  InwardShell,              // a closed shell whose normals point into the material
  UnreferencedVertex,       // a vertex no face uses (harmless: a warning)
  SelfIntersection,         // two faces cross or touch where the connectivity says they should not
};
inline constexpr std::size_t kNumMeshIssueKinds = 10;

/// How bad a MeshIssue is: an Error makes the mesh unusable (MeshValidationResult::valid), a Warning does not.
/// \ingroup mesh
enum class MeshIssueSeverity { Warning, Error };

/// One problem validate_mesh found: its kind and severity, the offending face, vertex, edge or shell, and a message.
/// \ingroup mesh
struct MeshIssue {
  MeshIssueKind kind;
  MeshIssueSeverity severity;
  /// The offending face, vertex, edge (as in MeshTopology) or shell, by kind; -1 for EmptyMesh.
  Index index;
  std::string message;
};

/// Tolerances and switches of validate_mesh and require_valid_mesh: which checks run and how many issues of each
/// kind are stored.
/// \ingroup mesh
struct MeshValidationOptions {
  /// A face is degenerate if its area is below this fraction of the mean face area.
  double degenerate_area_tolerance = 1e-10;
  /// A face is degenerate if its aspect ratio (mesh_quality.hpp) exceeds this: kMaxAspectRatio
  /// (1e4; docs/stability.md, study (c)). Infinity switches the check off (stability studies).
  double max_aspect_ratio = kMaxAspectRatio;
  /// Two vertices coincide if closer than this fraction of the bounding-box diagonal.
  double duplicate_vertex_tolerance = 1e-10;
  /// Whether each closed shell must face out of the material (outer shells outward, cavities
  /// inward, by nesting depth). Switch off for surfaces that are not solid boundaries.
  bool check_shell_orientation = true;
  /// Whether unreferenced vertices are reported (always as warnings).
  bool warn_unreferenced_vertices = true;
  /// Whether faces that cross each other are reported (find_self_intersections, O(F log F)): a
  /// surface that cuts through itself, or two overlapping shells, bounds no body. Checked only
  /// when the vertices are finite, no face is degenerate and no used vertices coincide. A caller that has checked the faces
  /// it changed (the cutter) may switch it off.
  bool check_self_intersection = true;
  /// At most this many issues of one kind are stored in full; the rest are only counted, so a
  /// triangle soup of a million faces does not produce a million strings.
  std::size_t max_issues_per_kind = 20;
};

/// The result of validate_mesh: the stored issues in check order and the number found of each kind, including
/// those not stored.
/// \ingroup mesh
struct MeshValidationResult {
  std::vector<MeshIssue> issues;  // stored issues, errors and warnings, in check order
  /// Number of issues found per kind, including those beyond max_issues_per_kind.
  std::vector<std::size_t> counts = std::vector<std::size_t>(kNumMeshIssueKinds, 0);

  std::size_t count(MeshIssueKind kind) const { return counts[static_cast<std::size_t>(kind)]; }
  std::size_t num_errors() const;
  std::size_t num_warnings() const;
  /// No errors (warnings allowed).
  bool valid() const { return num_errors() == 0; }
  /// One line per stored issue, errors first, and a line for the issues counted but not stored.
  std::string summary() const;
};
/// Deprecated name (before 0.2), kept one minor version: use MeshValidationResult.
using MeshValidationReport [[deprecated("renamed to MeshValidationResult in bemsurg 0.2")]] = MeshValidationResult;

MeshValidationResult validate_mesh(const TriangleMesh& mesh, const MeshValidationOptions& options = {});

/// Throws InvalidMeshError if validate_mesh finds an error. The message starts with the first
/// error (e.g. "face 1042: edge (17, 88) is shared by 3 faces: the mesh is not 2-manifold") and
/// says how many more problems there are.
void require_valid_mesh(const TriangleMesh& mesh, const MeshValidationOptions& options = {});

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/mesh_validation_impl.hpp"
#endif
