// The steps of mesh preparation that need no CGAL (src/meshing/mesh_preparation_steps.hpp).
#include "mesh_preparation_steps.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_set>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"

namespace bemsurg::detail {
namespace {

struct TripleHash {
  std::size_t operator()(const std::array<Index, 3>& t) const {
    std::size_t h = std::hash<Index>()(t[0]);
    h = h * 1000003u ^ std::hash<Index>()(t[1]);
    return h * 1000003u ^ std::hash<Index>()(t[2]);
  }
};

double triangle_area(const RowMatrixX3d& v, Index a, Index b, Index c) {
  return 0.5 * (v.row(b) - v.row(a)).cross(v.row(c) - v.row(a)).norm();
}

/// The corners of a collinear triangle ordered (end, end, middle): the middle one lies between.
std::array<Index, 3> middle_last(const RowMatrixX3d& v, const std::array<Index, 3>& t) {
  int middle = 0;
  double longest = -1.0;
  for (int k = 0; k < 3; ++k) {  // the middle vertex is the one opposite the longest edge
    const double length = (v.row(t[std::size_t((k + 1) % 3)]) - v.row(t[std::size_t((k + 2) % 3)])).squaredNorm();
    if (length > longest) longest = length, middle = k;
  }
  return {t[std::size_t((middle + 1) % 3)], t[std::size_t((middle + 2) % 3)], t[std::size_t(middle)]};
}

}  // namespace

CleanSoup clean_soup(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, double diagonal, MeshDefectCounts& d) {
  const Index V = vertices.rows(), F = faces.rows();
  std::vector<char> used(static_cast<std::size_t>(V), 0);
  for (Index e = 0; e < F; ++e)
    for (int c = 0; c < 3; ++c) used[std::size_t(faces(e, c))] = 1;
  d.unreferenced_vertices = static_cast<Index>(std::count(used.begin(), used.end(), 0));
  // Coincident within 1e-9 of the diagonal: bit-identical copies and the round-off of a writer.
  const std::vector<Index> rep = coincident_vertex_representatives(vertices, 1e-9 * diagonal);
  for (Index v = 0; v < V; ++v) d.duplicate_vertices += used[std::size_t(v)] && rep[std::size_t(v)] != v;
  double mean_area = 0.0;
  for (Index e = 0; e < F; ++e) mean_area += triangle_area(vertices, faces(e, 0), faces(e, 1), faces(e, 2));
  mean_area /= std::max<Index>(F, 1);
  std::unordered_set<std::array<Index, 3>, TripleHash> seen;
  seen.reserve(static_cast<std::size_t>(F));
  std::vector<std::array<Index, 3>> kept, t_junctions;  // t_junctions: (end, middle, end)
  kept.reserve(static_cast<std::size_t>(F));
  for (Index e = 0; e < F; ++e) {
    const std::array<Index, 3> t{rep[std::size_t(faces(e, 0))], rep[std::size_t(faces(e, 1))], rep[std::size_t(faces(e, 2))]};
    // Zero area: a repeated corner, or three collinear corners (below validate_mesh's tolerance).
    const bool repeated = t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    if (repeated || triangle_area(vertices, t[0], t[1], t[2]) <= 1e-10 * mean_area) {
      ++d.degenerate_faces;
      if (!repeated) t_junctions.push_back(middle_last(vertices, t));
      continue;
    }
    std::array<Index, 3> key = t;
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) {  // the same triangle again, either way round
      ++d.duplicate_faces;
      continue;
    }
    // A sliver (aspect ratio above the solver's limit, mesh_quality.hpp) is kept for now: it closes
    // the surface, and the remesh that follows replaces it (docs/organs.md).
    if (aspect_ratio(vertices.row(t[0]).transpose(), vertices.row(t[1]).transpose(), vertices.row(t[2]).transpose()) > kMaxAspectRatio)
      ++d.slivers;
    kept.push_back(t);
  }
  // A flat face (a, m, b) with m between a and b closes a T-junction: the faces on its other sides
  // use a-m and m-b, while a face across it uses a-b. Dropped, it would leave a hole of zero area
  // that no triangulation closes; instead each kept face on the edge a-b is split at m.
  for (const auto& [a, b, m] : t_junctions)
    for (std::size_t f = 0, n = kept.size(); f < n; ++f)
      for (int k = 0; k < 3; ++k) {
        const Index u = kept[f][std::size_t(k)], w = kept[f][std::size_t((k + 1) % 3)], x = kept[f][std::size_t((k + 2) % 3)];
        if (!((u == a && w == b) || (u == b && w == a))) continue;
        kept[f] = {u, m, x};
        kept.push_back({m, w, x});
        break;
      }
  // Vertices renumbered in order of first use, so the result does not depend on unused ones.
  std::vector<Index> index(static_cast<std::size_t>(V), -1);
  CleanSoup out;
  out.faces.resize(static_cast<Index>(kept.size()), 3);
  Index n = 0;
  for (std::size_t e = 0; e < kept.size(); ++e)
    for (int c = 0; c < 3; ++c) {
      Index& i = index[std::size_t(kept[e][std::size_t(c)])];
      if (i < 0) i = n++;
      out.faces(Index(e), c) = i;
    }
  out.vertices.resize(n, 3);
  for (Index v = 0; v < V; ++v)
    if (index[std::size_t(v)] >= 0) out.vertices.row(index[std::size_t(v)]) = vertices.row(v);
  return out;
}

void count_non_manifold(const TriangleMesh& mesh, MeshDefectCounts& d) {
  const MeshTopology topo(mesh);
  d.non_manifold_edges = static_cast<Index>(topo.non_manifold_edges().size());
  d.boundary_edges = static_cast<Index>(topo.boundary_edges().size());
  d.shells = topo.num_shells();
  // A vertex is manifold when its faces form one fan: connected through the edges at the vertex.
  std::vector<Index> parent;
  for (Index v = 0; v < topo.num_vertices(); ++v) {
    const std::vector<Index>& around = topo.vertex_faces(v);
    if (around.size() < 2) continue;
    parent.resize(around.size());
    std::iota(parent.begin(), parent.end(), Index(0));
    const auto root = [&parent](Index i) {
      while (parent[std::size_t(i)] != i) i = parent[std::size_t(i)] = parent[std::size_t(parent[std::size_t(i)])];
      return i;
    };
    const auto local = [&around](Index f) { return Index(std::lower_bound(around.begin(), around.end(), f) - around.begin()); };
    for (std::size_t i = 0; i < around.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        const MeshEdge& edge = topo.edge(topo.face_edge(around[i], k));
        if (edge.vertices[0] != v && edge.vertices[1] != v) continue;
        for (const EdgeFace& ef : edge.faces) parent[std::size_t(root(local(ef.face)))] = root(Index(i));
      }
    Index fans = 0;
    for (std::size_t i = 0; i < around.size(); ++i) fans += root(Index(i)) == Index(i);
    d.non_manifold_vertices += fans > 1;
  }
}

TriangleMesh select_bodies(const TriangleMesh& mesh, bool keep_all, MeshPreparationReport& report, TriangleMesh& dropped) {
  const MeshTopology topo(mesh);
  const Index S = topo.num_shells();
  const std::size_t ns = static_cast<std::size_t>(std::max<Index>(S, 0));
  for (Index s = 0; s < S; ++s)
    if (!topo.shell_is_closed_and_oriented(s))
      throw InvalidMeshError("after repair, shell " + std::to_string(s) + " is still not closed (please report this input)");
  // The shell containing each shell: the smallest larger one around one of its vertices.
  std::vector<double> volume(ns);
  for (Index s = 0; s < S; ++s) volume[std::size_t(s)] = std::abs(topo.shell_volume(s));
  std::vector<Index> parent(ns, -1);
  for (Index s = 0; s < S; ++s) {
    const Vec3 probe = mesh.vertices().row(mesh.faces()(topo.shell(s).front(), 0)).transpose();
    for (Index t = 0; t < S; ++t) {
      if (t == s || volume[std::size_t(t)] <= volume[std::size_t(s)]) continue;
      if (parent[std::size_t(s)] >= 0 && volume[std::size_t(t)] >= volume[std::size_t(parent[std::size_t(s)])]) continue;
      if (std::abs(winding_number(mesh, topo.shell(t), probe)) > 0.5) parent[std::size_t(s)] = t;
    }
  }
  std::vector<Index> depth(ns, 0), root(ns);
  for (Index s = 0; s < S; ++s) {
    Index r = s;
    while (parent[std::size_t(r)] >= 0) r = parent[std::size_t(r)], ++depth[std::size_t(s)];
    root[std::size_t(s)] = r;
  }
  Index largest = -1;
  for (Index s = 0; s < S; ++s)
    if (root[std::size_t(s)] == s) {
      ++report.bodies;
      if (largest < 0 || volume[std::size_t(s)] > volume[std::size_t(largest)]) largest = s;
    }
  if (largest < 0) throw InvalidMeshError("after repair, no closed region is left: the input bounds no volume");
  RowMatrixX3i kept(mesh.num_elements(), 3), lost(mesh.num_elements(), 3);
  Index nk = 0, nl = 0;
  for (Index s = 0; s < S; ++s) {
    const bool keep = keep_all || root[std::size_t(s)] == largest;
    const bool cavity = depth[std::size_t(s)] % 2 == 1;
    const bool flip = (topo.shell_volume(s) > 0.0) == cavity;  // outward bodies, inward cavities
    if (keep) report.cavities += cavity;
    if (!keep && root[std::size_t(s)] == s) {
      ++report.bodies_dropped;
      report.dropped_volume += volume[std::size_t(s)];
    }
    for (const Index f : topo.shell(s)) {
      Eigen::RowVector3i face = mesh.faces().row(f);
      if (flip) std::swap(face(1), face(2));
      (keep ? kept.row(nk++) : lost.row(nl++)) = face;
    }
  }
  dropped = TriangleMesh(mesh.vertices(), lost.topRows(nl));
  return TriangleMesh(mesh.vertices(), kept.topRows(nk));
}

RowMatrixX3d surface_samples(const TriangleMesh& mesh, bool edge_midpoints) {
  const RowMatrixX3d& v = mesh.vertices();
  const RowMatrixX3i& f = mesh.faces();
  const Index per_face = edge_midpoints ? 4 : 1;
  RowMatrixX3d out(v.rows() + per_face * f.rows(), 3);
  out.topRows(v.rows()) = v;
  for (Index e = 0; e < f.rows(); ++e) {
    const Index base = v.rows() + per_face * e;
    out.row(base) = (v.row(f(e, 0)) + v.row(f(e, 1)) + v.row(f(e, 2))) / 3.0;
    if (edge_midpoints)
      for (int k = 0; k < 3; ++k) out.row(base + 1 + k) = 0.5 * (v.row(f(e, k)) + v.row(f(e, (k + 1) % 3)));
  }
  return out;
}

}  // namespace bemsurg::detail
