// Synthetic mesh changes with exact MeshDeltas (mesh/mesh_delta.hpp), for testing the cut
// algebra without the cut topology: split an edge shared by two triangles at a point (2 modified
// + 2 added, the surface stays closed and conforming), or move a vertex (its faces modified).
#pragma once

#include <algorithm>
#include <memory>
#include <random>
#include <utility>

#include "bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg::testing {

struct SyntheticStep {
  std::shared_ptr<const TriangleMesh> mesh;
  MeshDelta delta;
};

/// Splits edge `k` (from corner k to k+1) of face `f` and of the face across it at the edge's
/// midpoint moved by `offset` (e.g. a small dent along the inward normal).
inline SyntheticStep split_edge(const TriangleMesh& mesh, Index f, int k, const Vec3& offset = Vec3::Zero()) {
  const auto& F = mesh.faces();
  const int a = F(f, k), b = F(f, (k + 1) % 3);
  Index g = -1;
  int kg = -1;
  for (Index h = 0; h < mesh.num_elements() && g < 0; ++h)
    for (int j = 0; j < 3; ++j)
      if (F(h, j) == b && F(h, (j + 1) % 3) == a) {
        g = h;
        kg = j;
      }
  if (g < 0) throw InvalidMeshError("split_edge: the edge has no opposite face");
  RowMatrixX3d V(mesh.num_vertices() + 1, 3);
  V.topRows(mesh.num_vertices()) = mesh.vertices();
  V.row(mesh.num_vertices()) = (0.5 * (mesh.vertex(a) + mesh.vertex(b)) + offset).transpose();
  const int m = static_cast<int>(mesh.num_vertices());
  const Index E = mesh.num_elements();
  RowMatrixX3i Fn(E + 2, 3);
  Fn.topRows(E) = F;
  const int c = F(f, (k + 2) % 3), dd = F(g, (kg + 2) % 3);
  Fn.row(f) << a, m, c;
  Fn.row(E) << m, b, c;
  Fn.row(g) << b, m, dd;
  Fn.row(E + 1) << m, a, dd;
  SyntheticStep s;
  s.mesh = std::make_shared<const TriangleMesh>(std::move(V), std::move(Fn));
  s.delta.elements_before = E;
  s.delta.elements_after = E + 2;
  s.delta.modified = {std::min(f, g), std::max(f, g)};
  s.delta.added = {E, E + 1};
  return s;
}

/// Moves vertex v by `displacement`; every face using it is modified.
inline SyntheticStep move_vertex(const TriangleMesh& mesh, Index v, const Vec3& displacement) {
  RowMatrixX3d V = mesh.vertices();
  V.row(v) += displacement.transpose();
  SyntheticStep s;
  s.mesh = std::make_shared<const TriangleMesh>(std::move(V), mesh.faces());
  s.delta.elements_before = s.delta.elements_after = mesh.num_elements();
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (int j = 0; j < 3; ++j)
      if (mesh.faces()(e, j) == v) {
        s.delta.modified.push_back(e);
        break;
      }
  return s;
}

/// A random split of an edge of an element in `candidates`, its midpoint dented inwards by
/// `dent` x the edge length (so the geometry really changes).
inline SyntheticStep random_split(const TriangleMesh& mesh, const std::vector<Index>& candidates, double dent, std::mt19937& rng) {
  std::uniform_int_distribution<std::size_t> pick(0, candidates.size() - 1);
  std::uniform_int_distribution<int> edge(0, 2);
  const Index f = candidates[pick(rng)];
  const int k = edge(rng);
  const Vec3 a = mesh.vertex(mesh.faces()(f, k)), b = mesh.vertex(mesh.faces()(f, (k + 1) % 3));
  return split_edge(mesh, f, k, -dent * (b - a).norm() * mesh.normal(f));
}

}  // namespace bemsurg::testing
