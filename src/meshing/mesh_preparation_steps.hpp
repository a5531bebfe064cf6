// Steps of mesh preparation that need no CGAL (src/meshing/mesh_preparation.cpp runs them in order;
// mesh/mesh_preparation.hpp says why each exists). Internal to bemsurg.
#pragma once

#include <vector>

#include "bemsurg/meshing/mesh_preparation.hpp"

namespace bemsurg::detail {

/// A soup after step 2's first half: coincident vertices merged, degenerate and repeated faces and
/// unused vertices dropped. Counts go into `defects`.
struct CleanSoup {
  RowMatrixX3d vertices;
  RowMatrixX3i faces;
};
CleanSoup clean_soup(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, double diagonal, MeshDefectCounts& defects);

/// Non-manifold edges (more than two faces) and vertices (separate fans of faces meeting there).
void count_non_manifold(const TriangleMesh& mesh, MeshDefectCounts& defects);

/// Step 5 on a closed, 2-manifold surface: shells oriented by nesting depth (outer outward, a shell
/// inside it inward as a cavity, and so on), and unless keep_all only the largest body by volume
/// with what nests in it. `dropped` receives the faces of what was dropped (for distances).
TriangleMesh select_bodies(const TriangleMesh& mesh, bool keep_all, MeshPreparationReport& report, TriangleMesh& dropped);

/// Points on a surface for distance measurements: vertices, face centroids and (when
/// `edge_midpoints`) edge midpoints.
RowMatrixX3d surface_samples(const TriangleMesh& mesh, bool edge_midpoints = true);

}  // namespace bemsurg::detail
