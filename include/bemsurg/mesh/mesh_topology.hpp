// bemsurg/mesh/mesh_topology.hpp: who touches whom in a triangle mesh.
//
// Edges with the faces that use them (and in which direction), the face across each edge, the
// faces around each vertex, and the connected shells with their signed enclosed volumes.
// Validation reads it to find open, non-manifold, mis-oriented or inside-out surfaces; cutting
// reads it to walk along edges and to re-triangulate around a vertex. It is a plain value: built
// once from a mesh, copied freely, and rebuilt (O(F log F)) after a topology change.
#pragma once

#include <array>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// One use of an edge by a face. Local edge k of face f runs from corner k to corner (k+1) % 3,
/// i.e. from faces(f, k) to faces(f, (k+1) % 3).
/// \ingroup mesh
struct EdgeFace {
  Index face = -1;
  int local = 0;
  /// True if the face runs from vertices[0] to vertices[1] of the edge (the lower index first).
  /// On a consistently oriented manifold, the two faces of an edge have opposite values.
  bool forward = true;
};

/// An undirected edge. vertices[0] <= vertices[1]; they are equal only for an edge of a
/// collapsed face that repeats a vertex.
/// \ingroup mesh
struct MeshEdge {
  std::array<Index, 2> vertices{{-1, -1}};
  std::vector<EdgeFace> faces;  // in increasing face index

  /// Exactly two faces traversing the edge in opposite directions: the one healthy state.
  bool is_manifold_oriented() const { return faces.size() == 2 && faces[0].forward != faces[1].forward; }
  bool is_boundary() const { return faces.size() == 1; }
  bool is_non_manifold() const { return faces.size() > 2; }
};

/// Who touches whom in a triangle mesh: edges with the faces that use them, the face across each edge, the faces
/// around each vertex, and the connected shells with their signed volumes. A plain value, rebuilt after a topology change.
/// \ingroup mesh
class MeshTopology {
 public:
  MeshTopology() = default;
  explicit MeshTopology(const TriangleMesh& mesh);

  Index num_vertices() const { return static_cast<Index>(vertex_faces_.size()); }
  Index num_faces() const { return static_cast<Index>(shell_of_face_.size()); }
  Index num_edges() const { return static_cast<Index>(edges_.size()); }

  /// Edges sorted by (vertices[0], vertices[1]), so the numbering is deterministic.
  const std::vector<MeshEdge>& edges() const { return edges_; }
  const MeshEdge& edge(Index e) const { return edges_[static_cast<std::size_t>(e)]; }
  /// The edge joining vertices a and b (either order), or -1 if there is none. O(log E).
  Index find_edge(Index a, Index b) const;
  /// Edge index of local edge k (corner k to corner k+1) of face f.
  Index face_edge(Index f, int k) const { return face_edges_[static_cast<std::size_t>(3 * f + k)]; }

  /// The face across local edge k of face f, or -1 where the edge is a boundary edge or is
  /// shared by more than two faces (there is no single neighbour then).
  Index neighbour(Index f, int k) const;
  std::array<Index, 3> neighbours(Index f) const { return {neighbour(f, 0), neighbour(f, 1), neighbour(f, 2)}; }

  /// Faces that use vertex v, in increasing order (empty for an unreferenced vertex).
  const std::vector<Index>& vertex_faces(Index v) const { return vertex_faces_[static_cast<std::size_t>(v)]; }

  /// Edges with one face (the mesh is open there) and with more than two (not 2-manifold).
  std::vector<Index> boundary_edges() const;
  std::vector<Index> non_manifold_edges() const;
  /// Every edge has two faces traversing it in opposite directions.
  bool is_closed_and_oriented() const;

  /// Shells: the connected components of faces, two faces being connected when they share an
  /// edge (faces meeting only at a vertex belong to different shells). Numbered in order of
  /// their lowest face; each lists its faces in increasing order.
  Index num_shells() const { return static_cast<Index>(shells_.size()); }
  const std::vector<Index>& shell(Index s) const { return shells_[static_cast<std::size_t>(s)]; }
  Index shell_of_face(Index f) const { return shell_of_face_[static_cast<std::size_t>(f)]; }
  /// Signed volume enclosed by shell s (positive when its normals point away from the enclosed
  /// region). Meaningful only for a shell that is closed; see shell_is_closed_and_oriented.
  double shell_volume(Index s) const { return shell_volumes_[static_cast<std::size_t>(s)]; }
  /// Every edge of shell s has exactly two faces with opposite directions.
  bool shell_is_closed_and_oriented(Index s) const { return shell_closed_[static_cast<std::size_t>(s)]; }

 private:
  std::vector<MeshEdge> edges_;
  std::vector<Index> face_edges_;  // 3 per face
  std::vector<std::vector<Index>> vertex_faces_;
  std::vector<std::vector<Index>> shells_;
  std::vector<Index> shell_of_face_;
  std::vector<double> shell_volumes_;
  std::vector<bool> shell_closed_;
};

/// Whether point p lies inside the closed surface formed by `faces` of `mesh` (for instance one
/// shell), by the solid-angle winding number: |w| > 1/2 is inside. Unlike ray parity it has no
/// trouble with rays through vertices or edges, and it works for either orientation. Returns the
/// winding number (about +1 inside an outward shell, -1 inside an inward one, 0 outside).
/// `on_surface` (optional) is set when p lies on one of the triangles, where w is not defined.
double winding_number(const TriangleMesh& mesh, const std::vector<Index>& faces, const Vec3& p, bool* on_surface = nullptr);
/// The same over every face of the mesh: 1 inside the material of a closed outward body, 0
/// outside and inside a cavity (whose shell faces the other way).
double winding_number(const TriangleMesh& mesh, const Vec3& p, bool* on_surface = nullptr);

/// Bodies: the shells grouped into connected solids (docs/design.md §2). A closed shell that lies
/// inside an odd number of other closed shells is a cavity and belongs to the body of the
/// smallest closed shell containing it; every other shell (closed at even depth: an outer
/// surface, or an island inside a cavity; or open) bounds a body of its own. Returns the body of
/// each shell, bodies numbered 0, 1, ... in the order of their outer shells.
std::vector<Index> shell_bodies(const TriangleMesh& mesh, const MeshTopology& topo);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/mesh/impl/mesh_topology_impl.hpp"
#endif
