// Defects of segmented surfaces, one kind per function (bemsurg/meshing/mesh_defects.hpp).
#include "bemsurg/meshing/mesh_defects.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <limits>
#include <queue>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

namespace detail::defects {

/// A mesh as growable lists, for edits that add and remove vertices and faces.
struct Soup {
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;

  explicit Soup(const TriangleMesh& mesh) {
    v.reserve(static_cast<std::size_t>(mesh.num_vertices()));
    for (Index i = 0; i < mesh.num_vertices(); ++i) v.push_back(mesh.vertex(i));
    f.reserve(static_cast<std::size_t>(mesh.num_elements()));
    for (Index e = 0; e < mesh.num_elements(); ++e) f.push_back({mesh.faces()(e, 0), mesh.faces()(e, 1), mesh.faces()(e, 2)});
  }
  int add_vertex(const Vec3& p) {
    v.push_back(p);
    return static_cast<int>(v.size() - 1);
  }
  /// Appends another mesh's faces and vertices as a shell of their own.
  void append(const TriangleMesh& other) {
    const int base = static_cast<int>(v.size());
    for (Index i = 0; i < other.num_vertices(); ++i) v.push_back(other.vertex(i));
    for (Index e = 0; e < other.num_elements(); ++e)
      f.push_back({base + other.faces()(e, 0), base + other.faces()(e, 1), base + other.faces()(e, 2)});
  }
  TriangleMesh mesh() const { return detail::to_mesh(v, f); }
};

/// The k-th pick in [0, n): the generator's raw output (fixed by the standard) modulo n.
Index pick(std::mt19937_64& rng, Index n) { return static_cast<Index>(rng() % static_cast<std::uint64_t>(n)); }

void require_faces(const TriangleMesh& mesh, const char* what, Index at_least = 4) {
  if (mesh.num_elements() < at_least)
    throw InvalidArgumentError(std::string(what) + ": the mesh needs at least " + std::to_string(at_least) + " faces");
}

/// Area-weighted normal at vertex v (unit) and the mean diameter of its faces.
std::pair<Vec3, double> vertex_normal_and_size(const TriangleMesh& mesh, const MeshTopology& topo, Index v) {
  Vec3 n = Vec3::Zero();
  double size = 0.0;
  for (Index f : topo.vertex_faces(v)) {
    n += mesh.area(f) * mesh.normal(f);
    size += mesh.diameter(f);
  }
  const auto count = static_cast<double>(std::max<std::size_t>(1, topo.vertex_faces(v).size()));
  return {n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3(Vec3::UnitZ()), size / count};
}

/// Distance along the ray o + t d (t > 0) to triangle (a, b, c), or infinity (Moller-Trumbore).
double ray_triangle(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = d.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-300) return std::numeric_limits<double>::infinity();
  const Vec3 s = o - a;
  const double u = s.dot(p) / det;
  if (u < 0.0 || u > 1.0) return std::numeric_limits<double>::infinity();
  const Vec3 q = s.cross(e1);
  const double w = d.dot(q) / det;
  if (w < 0.0 || u + w > 1.0) return std::numeric_limits<double>::infinity();
  const double t = e2.dot(q) / det;
  return t > 0.0 ? t : std::numeric_limits<double>::infinity();
}

/// The three faces of the collinear split of face f (see add_degenerate_faces), in place.
void split_with_flat_face(Soup& s, std::size_t f) {
  const auto [a, b, c] = s.f[f];
  const int m = s.add_vertex(0.5 * (s.v[static_cast<std::size_t>(a)] + s.v[static_cast<std::size_t>(b)]));
  s.f[f] = {a, m, c};
  s.f.push_back({m, b, c});
  s.f.push_back({b, m, a});
}

}  // namespace detail::defects

TriangleMesh unweld_mesh(const TriangleMesh& mesh) {
  RowMatrixX3d V(3 * mesh.num_elements(), 3);
  RowMatrixX3i F(mesh.num_elements(), 3);
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (int k = 0; k < 3; ++k) {
      V.row(3 * e + k) = mesh.vertices().row(mesh.faces()(e, k));
      F(e, k) = static_cast<int>(3 * e + k);
    }
  return TriangleMesh(std::move(V), std::move(F));
}

TriangleMesh add_degenerate_faces(const TriangleMesh& mesh, int count, std::uint64_t seed) {
  detail::defects::require_faces(mesh, "add_degenerate_faces", 4 * std::max(count, 1));
  if (count < 0) throw InvalidArgumentError("add_degenerate_faces: count must not be negative");
  const MeshTopology topo(mesh);
  std::mt19937_64 rng(seed);
  detail::defects::Soup s(mesh);
  std::vector<char> touched(static_cast<std::size_t>(mesh.num_vertices()), 0);
  const auto untouched = [&](std::initializer_list<Index> vs) {
    for (Index x : vs)
      if (touched[static_cast<std::size_t>(x)]) return false;
    for (Index x : vs) touched[static_cast<std::size_t>(x)] = 1;
    return true;
  };
  for (int added = 0, tries = 0; added < count; ++tries) {
    if (tries > 100 * count + 100) throw InvalidArgumentError("add_degenerate_faces: found no place for another face");
    const Index f = detail::defects::pick(rng, mesh.num_elements());
    const auto& F = mesh.faces();
    if (added % 2 == 0) {  // three collinear points
      if (!untouched({F(f, 0), F(f, 1), F(f, 2)})) continue;
      detail::defects::split_with_flat_face(s, static_cast<std::size_t>(f));
    } else {  // a repeated index between a and the far vertex b of the face across a's opposite edge
      const Index across = topo.neighbour(f, 1);
      if (across < 0) continue;
      Index b = -1;
      for (int k = 0; k < 3; ++k)
        if (F(across, k) != F(f, 1) && F(across, k) != F(f, 2)) b = F(across, k);
      if (b < 0 || topo.find_edge(F(f, 0), b) >= 0 || !untouched({F(f, 0), b})) continue;
      s.f.push_back({F(f, 0), F(f, 0), static_cast<int>(b)});
    }
    ++added;
  }
  return s.mesh();
}

TriangleMesh add_slivers(const TriangleMesh& mesh, int count, double aspect_ratio, std::uint64_t seed) {
  if (count < 0) throw InvalidArgumentError("add_slivers: count must not be negative");
  if (!(aspect_ratio >= 10.0 && std::isfinite(aspect_ratio)))
    throw InvalidArgumentError("add_slivers: aspect_ratio must be a finite number of at least 10, got " + number_text(aspect_ratio));
  detail::defects::require_faces(mesh, "add_slivers", 2 * std::max(count, 1));
  std::mt19937_64 rng(seed);
  detail::defects::Soup s(mesh);
  std::vector<char> split(static_cast<std::size_t>(mesh.num_elements()), 0);
  for (int added = 0, tries = 0; added < count; ++tries) {
    if (tries > 100 * count + 100) throw InvalidArgumentError("add_slivers: found no face left to split");
    const Index f = detail::defects::pick(rng, mesh.num_elements());
    if (split[static_cast<std::size_t>(f)]) continue;
    split[static_cast<std::size_t>(f)] = 1;
    const auto [a, b, c] = s.f[static_cast<std::size_t>(f)];
    const Vec3 A = s.v[static_cast<std::size_t>(a)], B = s.v[static_cast<std::size_t>(b)], C = s.v[static_cast<std::size_t>(c)];
    const Vec3 m = 0.5 * (A + B);
    // The altitude of p over ab is s times c's, h_c; ab is the sliver's longest edge, so its
    // aspect ratio (sqrt(3)/2 longest edge / shortest altitude) is sqrt(3)/2 |ab| / (s h_c).
    const double h_c = (B - A).cross(C - A).norm() / (B - A).norm();
    const double fraction = 0.5 * std::sqrt(3.0) * (B - A).norm() / (aspect_ratio * h_c);
    if (!(fraction > 0.0 && fraction <= 0.1)) continue;  // a face too flat already for this ratio
    const int p = s.add_vertex(m + fraction * (C - m));
    s.f[static_cast<std::size_t>(f)] = {a, b, p};
    s.f.push_back({b, c, p});
    s.f.push_back({c, a, p});
    ++added;
  }
  return s.mesh();
}

TriangleMesh flip_face_patch(const TriangleMesh& mesh, Index faces, std::uint64_t seed) {
  detail::defects::require_faces(mesh, "flip_face_patch", 4 * faces);
  const MeshTopology topo(mesh);
  std::mt19937_64 rng(seed);
  std::vector<char> in(static_cast<std::size_t>(mesh.num_elements()), 0);
  std::queue<Index> queue;
  const Index start = detail::defects::pick(rng, mesh.num_elements());
  queue.push(start);
  in[static_cast<std::size_t>(start)] = 1;
  RowMatrixX3i F = mesh.faces();
  for (Index taken = 0; taken < faces && !queue.empty(); ++taken) {
    const Index f = queue.front();
    queue.pop();
    std::swap(F(f, 1), F(f, 2));
    for (Index g : topo.neighbours(f))
      if (g >= 0 && !in[static_cast<std::size_t>(g)]) {
        in[static_cast<std::size_t>(g)] = 1;
        queue.push(g);
      }
  }
  return TriangleMesh(mesh.vertices(), std::move(F));
}

TriangleMesh punch_hole(const TriangleMesh& mesh, Index boundary_edges, std::uint64_t seed) {
  if (boundary_edges < 3) throw InvalidArgumentError("punch_hole: a hole's rim needs at least 3 edges");
  detail::defects::require_faces(mesh, "punch_hole", 8 * boundary_edges);
  const MeshTopology topo(mesh);
  std::mt19937_64 rng(seed);
  const Index start = detail::defects::pick(rng, mesh.num_elements());
  const Vec3 centre = mesh.centroid(start);
  std::vector<char> seen(static_cast<std::size_t>(mesh.num_elements()), 0), removed(seen.size(), 0);
  using Item = std::pair<double, Index>;  // (distance, face): nearest first, ties by face index
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> front;
  front.push({0.0, start});
  seen[static_cast<std::size_t>(start)] = 1;
  Index rim = 0, taken = 0;
  while (rim < boundary_edges) {
    if (front.empty() || 4 * ++taken > mesh.num_elements())
      throw InvalidArgumentError("punch_hole: a hole with a rim of " + std::to_string(boundary_edges) +
                                 " edges would take too much of the mesh");
    const Index f = front.top().second;
    front.pop();
    removed[static_cast<std::size_t>(f)] = 1;
    for (int k = 0; k < 3; ++k) {
      const Index g = topo.neighbour(f, k);
      rim += g >= 0 && removed[static_cast<std::size_t>(g)] ? -1 : 1;
      if (g >= 0 && !seen[static_cast<std::size_t>(g)]) {
        seen[static_cast<std::size_t>(g)] = 1;
        front.push({(mesh.centroid(g) - centre).norm(), g});
      }
    }
  }
  detail::defects::Soup s(mesh);
  std::vector<std::array<int, 3>> kept;
  for (std::size_t f = 0; f < s.f.size(); ++f)
    if (!removed[f]) kept.push_back(s.f[f]);
  // Drop the vertices no face uses any more, keeping the others' order.
  std::vector<int> renumber(s.v.size(), -1);
  std::vector<Vec3> used;
  for (auto& face : kept)
    for (int& x : face) {
      if (renumber[static_cast<std::size_t>(x)] < 0) renumber[static_cast<std::size_t>(x)] = 0;
    }
  for (std::size_t i = 0; i < s.v.size(); ++i)
    if (renumber[i] == 0) {
      renumber[i] = static_cast<int>(used.size());
      used.push_back(s.v[i]);
    }
  for (auto& face : kept)
    for (int& x : face) x = renumber[static_cast<std::size_t>(x)];
  return detail::to_mesh(used, kept);
}

TriangleMesh poke_through(const TriangleMesh& mesh, std::uint64_t seed) {
  detail::defects::require_faces(mesh, "poke_through", 20);
  const MeshTopology topo(mesh);
  std::mt19937_64 rng(seed);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const Index v = detail::defects::pick(rng, mesh.num_vertices());
    if (topo.vertex_faces(v).empty()) continue;
    const auto [normal, size] = detail::defects::vertex_normal_and_size(mesh, topo, v);
    const Vec3 origin = mesh.vertex(v), d = -normal;
    double exit = std::numeric_limits<double>::infinity();
    for (Index f = 0; f < mesh.num_elements(); ++f) {
      const auto& F = mesh.faces();
      if (F(f, 0) == v || F(f, 1) == v || F(f, 2) == v) continue;
      const auto c = mesh.corners(f);
      exit = std::min(exit, detail::defects::ray_triangle(origin, d, c[0], c[1], c[2]));
    }
    // Through a body several edges thick, so the spike's faces meet only faces far from its base.
    if (!std::isfinite(exit) || exit < 6.0 * size) continue;
    RowMatrixX3d V = mesh.vertices();
    V.row(v) = (origin + (exit + 0.3 * size) * d).transpose();
    TriangleMesh poked(std::move(V), mesh.faces());
    if (find_self_intersections(poked, topo.vertex_faces(v)).empty()) continue;
    return poked;
  }
  throw InvalidArgumentError("poke_through: found no vertex whose inward normal crosses the body (is the mesh closed and outward?)");
}

TriangleMesh add_fin(const TriangleMesh& mesh, std::uint64_t seed) {
  detail::defects::require_faces(mesh, "add_fin");
  const MeshTopology topo(mesh);
  std::mt19937_64 rng(seed);
  const Index f = detail::defects::pick(rng, mesh.num_elements());
  const Index g = topo.neighbour(f, 0);
  const Vec3 a = mesh.vertex(mesh.faces()(f, 0)), b = mesh.vertex(mesh.faces()(f, 1));
  Vec3 n = mesh.normal(f) + (g >= 0 ? mesh.normal(g) : Vec3(Vec3::Zero()));
  n = n.norm() > 0.0 ? Vec3(n.normalized()) : mesh.normal(f);
  detail::defects::Soup s(mesh);
  const int apex = s.add_vertex(0.5 * (a + b) + (b - a).norm() * n);
  s.f.push_back({mesh.faces()(f, 0), mesh.faces()(f, 1), apex});
  return s.mesh();
}

TriangleMesh add_touching_cone(const TriangleMesh& mesh, std::uint64_t seed) {
  detail::defects::require_faces(mesh, "add_touching_cone");
  const MeshTopology topo(mesh);
  std::mt19937_64 rng(seed);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const Index v = detail::defects::pick(rng, mesh.num_vertices());
    if (topo.vertex_faces(v).empty()) continue;
    const auto [n, size] = detail::defects::vertex_normal_and_size(mesh, topo, v);
    const Vec3 t1 = n.unitOrthogonal(), t2 = n.cross(t1), p = mesh.vertex(v);
    detail::defects::Soup s(mesh);
    std::array<int, 3> base{};
    for (int k = 0; k < 3; ++k) {
      const double angle = 2.0943951023931957 * k;  // 2 pi k / 3
      base[static_cast<std::size_t>(k)] = s.add_vertex(p + 2.0 * size * n + size * (std::cos(angle) * t1 + std::sin(angle) * t2));
    }
    const int apex = static_cast<int>(v);
    // (t1, t2, n) is right-handed and the base runs counter-clockwise about n: the sides
    // (apex, b[k+1], b[k]) and the base (b0, b1, b2) face out of the cone.
    for (int k = 0; k < 3; ++k) s.f.push_back({apex, base[static_cast<std::size_t>((k + 1) % 3)], base[static_cast<std::size_t>(k)]});
    s.f.push_back({base[0], base[1], base[2]});
    TriangleMesh out = s.mesh();
    const std::vector<Index> cone = {mesh.num_elements(), mesh.num_elements() + 1, mesh.num_elements() + 2, mesh.num_elements() + 3};
    if (find_self_intersections(out, cone).empty()) return out;
  }
  throw InvalidArgumentError("add_touching_cone: found no vertex where a cone stays clear of the surface");
}

TriangleMesh add_overlapping_ellipsoid(const TriangleMesh& mesh, std::uint64_t seed) {
  detail::defects::require_faces(mesh, "add_overlapping_ellipsoid");
  std::mt19937_64 rng(seed);
  const Vec3 centre = mesh.vertex(detail::defects::pick(rng, mesh.num_vertices()));
  const Eigen::Matrix<double, 3, 2> box = mesh.bounding_box();
  detail::defects::Soup s(mesh);
  s.append(ellipsoid_mesh(centre, 0.15 * (box.col(1) - box.col(0)), 3));
  return s.mesh();
}

TriangleMesh add_speck(const TriangleMesh& mesh, double volume_fraction) {
  detail::defects::require_faces(mesh, "add_speck");
  const double volume = mesh.enclosed_volume();
  if (!(volume_fraction > 0.0 && std::isfinite(volume_fraction) && volume > 0.0))
    throw InvalidArgumentError("add_speck: needs a positive volume fraction and a mesh enclosing a positive volume");
  // The icosphere of 80 faces encloses less than its sphere: scale its radius to hit the volume.
  const TriangleMesh unit = icosphere_mesh(Vec3::Zero(), 1.0, 1);
  const double radius = std::cbrt(volume_fraction * volume / unit.enclosed_volume());
  const Eigen::Matrix<double, 3, 2> box = mesh.bounding_box();
  const Vec3 diagonal = box.col(1) - box.col(0);
  detail::defects::Soup s(mesh);
  s.append(icosphere_mesh(Vec3(box.col(1)) + (0.2 + radius / diagonal.norm()) * diagonal, radius, 1));
  return s.mesh();
}

TriangleMesh add_cavity(const TriangleMesh& mesh, const Vec3& center, double radius, bool outward_by_mistake) {
  if (!(center.allFinite() && std::isfinite(radius) && radius > 0.0))
    throw InvalidArgumentError("add_cavity: needs a finite centre and a positive radius");
  const TriangleMesh sphere = icosphere_mesh(center, radius, 2);
  detail::defects::Soup s(mesh);
  s.append(outward_by_mistake ? sphere : flip_orientation(sphere));
  return s.mesh();
}

TriangleMesh scale_mesh(const TriangleMesh& mesh, double factor) {
  if (!(std::isfinite(factor) && factor > 0.0)) throw InvalidArgumentError("scale_mesh: the factor must be a positive number");
  return TriangleMesh(factor * mesh.vertices(), mesh.faces());
}

TriangleMesh segmentation_like(const TriangleMesh& mesh, std::uint64_t seed, const SegmentationDefects& defects) {
  // Each kind its own stream of picks, so leaving one out does not move the others.
  const auto stream = [seed](std::uint64_t k) { return seed * 0x9E3779B97F4A7C15ULL + k; };
  TriangleMesh m = mesh;
  if (defects.self_intersection) m = poke_through(m, stream(1));
  if (defects.non_manifold_edge) m = add_fin(m, stream(2));
  if (defects.hole_boundary_edges > 0) m = punch_hole(m, defects.hole_boundary_edges, stream(3));
  if (defects.flipped_faces > 0) m = flip_face_patch(m, defects.flipped_faces, stream(4));
  if (defects.degenerate_faces > 0) m = add_degenerate_faces(m, defects.degenerate_faces, stream(5));
  if (defects.speck_volume_fraction > 0.0) m = add_speck(m, defects.speck_volume_fraction);
  return defects.scale == 1.0 ? m : scale_mesh(m, defects.scale);
}

}  // namespace bemsurg
