// Generators for boxes (uniform and graded), icospheres, ellipsoids and hollow spheres.
#pragma once

#include "bemsurg/config.hpp"
#include "bemsurg/number_text.hpp"

#include "bemsurg/mesh/mesh_generators.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>

namespace bemsurg {

namespace detail {

BEMSURG_INLINE std::string str(double x) { return fixed_text(x, 6); }  // as "%f" printed it, without the locale

BEMSURG_INLINE void check_grid(const std::vector<double>& g, const char* name) {
  if (g.size() < 2)
    throw InvalidMeshError(std::string("box_mesh_from_grid: ") + name + " needs at least two coordinates, got " + std::to_string(g.size()));
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (!std::isfinite(g[i]))
      throw InvalidMeshError(std::string("box_mesh_from_grid: ") + name + "[" + std::to_string(i) + "] is not finite");
    if (i > 0 && !(g[i] > g[i - 1]))
      throw InvalidMeshError(std::string("box_mesh_from_grid: ") + name + " must be strictly increasing, but " + name + "[" +
                             std::to_string(i) + "] = " + str(g[i]) + " <= " + name + "[" + std::to_string(i - 1) + "] = " + str(g[i - 1]));
  }
}

/// Grid lines per side beyond which graded_coordinates refuses: such a grid is a mistake (h_min
/// in the wrong unit, say), and the dense BEM could never use it.
BEMSURG_INLINE constexpr int kMaxLines = 10000000;

[[noreturn]] BEMSURG_INLINE void too_many_lines(double h_min) {
  throw InvalidMeshError("graded_coordinates: h_min = " + str(h_min) + " would need more than " + std::to_string(kMaxLines) +
                         " grid lines");
}

/// Sum of m graded steps min(h_min q^k, h_max), k = k0 .. k0 + m - 1.
BEMSURG_INLINE double graded_sum(int m, int k0, double h_min, double h_max, double q) {
  double sum = 0.0, h = h_min * std::pow(q, k0);
  for (int k = 0; k < m; ++k, h *= q) sum += std::min(h, h_max);
  return sum;
}

/// Offsets (increasing, the last exactly L) of the grid lines on one side of the focus.
BEMSURG_INLINE std::vector<double> side_offsets(double L, double h_min, double h_max, double growth, double plateau) {
  std::vector<double> out;
  if (!(L > 0.0)) return out;
  auto uniform = [&](long n) {
    if (n > kMaxLines) too_many_lines(h_min);
    for (long i = 1; i <= n; ++i) out.push_back(i == n ? L : L * static_cast<double>(i) / static_cast<double>(n));
  };
  const long n_plateau = static_cast<long>(std::floor(std::min(std::max(0.0, plateau), L) / h_min + 1e-9));
  const double P = static_cast<double>(n_plateau) * h_min;
  if (P >= L * (1.0 - 1e-12)) {
    uniform(std::max(1L, std::lround(L / h_min)));
    return out;
  }
  const double R = L - P;
  // The first graded step is h_min itself when there is no plateau (the spacing at the focus),
  // otherwise one growth step beyond the plateau.
  const int k0 = n_plateau > 0 ? 1 : 0;
  // Smallest number of graded steps that reaches R at full growth (summed incrementally: a
  // uniform grid, growth = 1, can need many steps).
  int m = 0;
  for (double sum = 0.0, h = h_min * std::pow(growth, k0); sum < R; h *= growth, ++m) {
    if (m >= kMaxLines) too_many_lines(h_min);
    sum += std::min(h, h_max);
  }
  if (static_cast<double>(m) * h_min > R) {
    // Too short to grade with spacings >= h_min and ratios <= growth: uniform, slightly below h_min.
    out.clear();
    uniform(n_plateau + m);
    return out;
  }
  // sum_m(q) increases with q from m h_min <= R to sum_m(growth) >= R: bisect for the ratio that
  // ends exactly at L.
  double qa = 1.0, qb = growth;
  for (int it = 0; it < 100 && qb - qa > 1e-15; ++it) {
    const double q = 0.5 * (qa + qb);
    (graded_sum(m, k0, h_min, h_max, q) < R ? qa : qb) = q;
  }
  const double q = qb;
  std::vector<double> steps;
  double h = h_min * std::pow(q, k0), sum = 0.0;
  for (int k = 0; k < m; ++k, h *= q) {
    steps.push_back(std::min(h, h_max));
    sum += steps.back();
  }
  double x = 0.0;
  for (long i = 0; i < n_plateau; ++i) out.push_back(x += h_min);
  for (double s : steps) out.push_back(x += s * (R / sum));  // R / sum = 1 to rounding
  out.back() = L;
  return out;
}

/// Twelve vertices of the unit icosahedron and its twenty faces, counter-clockwise from outside.
BEMSURG_INLINE void icosahedron(std::vector<Vec3>& v, std::vector<std::array<int, 3>>& f) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
       {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : v) p.normalize();
  f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
       {3, 9, 4},  {3, 4, 2}, {3, 2, 6}, {3, 6, 8},  {3, 8, 9},   {4, 9, 5}, {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  // Belt and braces: orient each face outward by its own geometry rather than trust the table.
  for (auto& face : f)
    if ((v[static_cast<std::size_t>(face[1])] - v[static_cast<std::size_t>(face[0])])
            .cross(v[static_cast<std::size_t>(face[2])] - v[static_cast<std::size_t>(face[0])])
            .dot(v[static_cast<std::size_t>(face[0])]) < 0.0)
      std::swap(face[1], face[2]);
}

BEMSURG_INLINE TriangleMesh to_mesh(const std::vector<Vec3>& v, const std::vector<std::array<int, 3>>& f) {
  RowMatrixX3d V(static_cast<Index>(v.size()), 3);
  RowMatrixX3i F(static_cast<Index>(f.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) V.row(static_cast<Index>(i)) = v[i].transpose();
  for (std::size_t i = 0; i < f.size(); ++i)
    for (int k = 0; k < 3; ++k) F(static_cast<Index>(i), k) = f[i][static_cast<std::size_t>(k)];
  return TriangleMesh(std::move(V), std::move(F));
}

/// Unit icosphere (vertices on the unit sphere, centred at the origin).
BEMSURG_INLINE void unit_icosphere(int subdivisions, std::vector<Vec3>& v, std::vector<std::array<int, 3>>& f) {
  if (subdivisions < 0 || subdivisions > 10)
    throw InvalidMeshError("icosphere: subdivisions must be in [0, 10] (20 * 4^s faces), got " + std::to_string(subdivisions));
  icosahedron(v, f);
  for (int s = 0; s < subdivisions; ++s) {
    // One midpoint per edge, shared by the edge's two faces, so the result stays welded.
    std::unordered_map<std::uint64_t, int> midpoint;
    midpoint.reserve(f.size() * 2);
    auto mid = [&](int a, int b) {
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | static_cast<std::uint32_t>(std::max(a, b));
      const auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back((v[static_cast<std::size_t>(a)] + v[static_cast<std::size_t>(b)]).normalized());
      const int id = static_cast<int>(v.size() - 1);
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(4 * f.size());
    for (const auto& t : f) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    f.swap(next);
  }
}

}  // namespace detail

BEMSURG_INLINE TriangleMesh box_mesh(const Vec3& lo, const Vec3& hi, int nx, int ny, int nz) {
  const std::array<int, 3> n{{nx, ny, nz}};
  std::array<std::vector<double>, 3> grid;
  for (int a = 0; a < 3; ++a) {
    if (n[static_cast<std::size_t>(a)] < 1)
      throw InvalidMeshError("box_mesh: the number of divisions along " + std::string(1, "xyz"[a]) + " must be at least 1, got " +
                             std::to_string(n[static_cast<std::size_t>(a)]));
    if (!(lo(a) < hi(a)))
      throw InvalidMeshError("box_mesh: lo must be below hi in every coordinate, but lo." + std::string(1, "xyz"[a]) + " = " +
                             detail::str(lo(a)) + " >= hi." + std::string(1, "xyz"[a]) + " = " + detail::str(hi(a)));
    const int m = n[static_cast<std::size_t>(a)];
    for (int i = 0; i <= m; ++i) grid[static_cast<std::size_t>(a)].push_back(i == m ? hi(a) : lo(a) + (hi(a) - lo(a)) * i / m);
  }
  return box_mesh_from_grid(grid[0], grid[1], grid[2]);
}

BEMSURG_INLINE TriangleMesh box_mesh_from_grid(const std::vector<double>& xs, const std::vector<double>& ys,
                                               const std::vector<double>& zs) {
  detail::check_grid(xs, "xs");
  detail::check_grid(ys, "ys");
  detail::check_grid(zs, "zs");
  const std::array<const std::vector<double>*, 3> g{{&xs, &ys, &zs}};
  const std::array<int, 3> n{{static_cast<int>(xs.size()) - 1, static_cast<int>(ys.size()) - 1, static_cast<int>(zs.size()) - 1}};

  // Surface grid points are numbered on first use; the map makes points on box edges and
  // corners shared between the faces that meet there.
  std::unordered_map<std::int64_t, int> id;
  std::vector<Vec3> vertices;
  auto vertex = [&](const std::array<int, 3>& ijk) {
    const std::int64_t key = (static_cast<std::int64_t>(ijk[0]) * (n[1] + 1) + ijk[1]) * static_cast<std::int64_t>(n[2] + 1) + ijk[2];
    const auto it = id.find(key);
    if (it != id.end()) return it->second;
    vertices.emplace_back((*g[0])[static_cast<std::size_t>(ijk[0])], (*g[1])[static_cast<std::size_t>(ijk[1])],
                          (*g[2])[static_cast<std::size_t>(ijk[2])]);
    const int v = static_cast<int>(vertices.size() - 1);
    id.emplace(key, v);
    return v;
  };

  std::vector<std::array<int, 3>> faces;
  for (int a = 0; a < 3; ++a) {
    // (b, c) is the cyclic successor pair of a, so e_b x e_c = +e_a: quads listed in (b, c) order
    // face +a; on the low side they are reversed to face -a.
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const int ia = side == 0 ? 0 : n[static_cast<std::size_t>(a)];
      for (int ib = 0; ib < n[static_cast<std::size_t>(b)]; ++ib)
        for (int ic = 0; ic < n[static_cast<std::size_t>(c)]; ++ic) {
          auto at = [&](int db, int dc) {
            std::array<int, 3> ijk{};
            ijk[static_cast<std::size_t>(a)] = ia;
            ijk[static_cast<std::size_t>(b)] = ib + db;
            ijk[static_cast<std::size_t>(c)] = ic + dc;
            return vertex(ijk);
          };
          const int q00 = at(0, 0), q10 = at(1, 0), q11 = at(1, 1), q01 = at(0, 1);
          std::array<std::array<int, 3>, 2> tri;
          if ((ib + ic) % 2 == 0)
            tri = {{{q00, q10, q11}, {q00, q11, q01}}};
          else
            tri = {{{q00, q10, q01}, {q10, q11, q01}}};
          for (auto t : tri) {
            if (side == 0) std::swap(t[1], t[2]);
            faces.push_back(t);
          }
        }
    }
  }
  return detail::to_mesh(vertices, faces);
}

BEMSURG_INLINE std::vector<double> graded_coordinates(double lo, double hi, double focus, double h_min, double h_max, double growth,
                                                      double fine_half_width) {
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo < hi))
    throw InvalidMeshError("graded_coordinates: need finite lo < hi, got lo = " + detail::str(lo) + ", hi = " + detail::str(hi));
  if (!(h_min > 0.0 && h_min <= h_max && std::isfinite(h_max)))
    throw InvalidMeshError("graded_coordinates: need 0 < h_min <= h_max, got h_min = " + detail::str(h_min) +
                           ", h_max = " + detail::str(h_max));
  if (!(growth >= 1.0 && std::isfinite(growth)))
    throw InvalidMeshError("graded_coordinates: growth must be >= 1, got " + detail::str(growth));
  if (std::isnan(focus)) throw InvalidMeshError("graded_coordinates: focus is NaN");
  focus = std::min(std::max(focus, lo), hi);

  const std::vector<double> left = detail::side_offsets(focus - lo, h_min, h_max, growth, fine_half_width);
  const std::vector<double> right = detail::side_offsets(hi - focus, h_min, h_max, growth, fine_half_width);
  std::vector<double> out;
  out.reserve(left.size() + right.size() + 1);
  for (auto it = left.rbegin(); it != left.rend(); ++it) out.push_back(focus - *it);
  if (!left.empty()) out.front() = lo;
  out.push_back(focus);
  for (double d : right) out.push_back(focus + d);
  out.back() = hi;
  return out;
}

BEMSURG_INLINE TriangleMesh icosphere_mesh(const Vec3& center, double radius, int subdivisions) {
  if (!(radius > 0.0 && std::isfinite(radius)))
    throw InvalidMeshError("icosphere_mesh: radius must be positive, got " + detail::str(radius));
  return ellipsoid_mesh(center, Vec3::Constant(radius), subdivisions);
}

BEMSURG_INLINE TriangleMesh ellipsoid_mesh(const Vec3& center, const Vec3& semi_axes, int subdivisions) {
  if (!((semi_axes.array() > 0.0).all() && semi_axes.allFinite()))
    throw InvalidMeshError("ellipsoid_mesh: semi-axes must be positive, got (" + detail::str(semi_axes.x()) + ", " +
                           detail::str(semi_axes.y()) + ", " + detail::str(semi_axes.z()) + ")");
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;
  detail::unit_icosphere(subdivisions, v, f);
  for (Vec3& p : v) p = center + semi_axes.cwiseProduct(p);
  return detail::to_mesh(v, f);
}

BEMSURG_INLINE TriangleMesh hollow_sphere_mesh(const Vec3& center, double inner_radius, double outer_radius, int subdivisions_inner,
                                               int subdivisions_outer) {
  if (!(inner_radius > 0.0 && inner_radius < outer_radius))
    throw InvalidMeshError("hollow_sphere_mesh: need 0 < inner_radius < outer_radius, got " + detail::str(inner_radius) + " and " +
                           detail::str(outer_radius));
  return merge_meshes(icosphere_mesh(center, outer_radius, subdivisions_outer),
                      flip_orientation(icosphere_mesh(center, inner_radius, subdivisions_inner)));
}

BEMSURG_INLINE TriangleMesh merge_meshes(const TriangleMesh& a, const TriangleMesh& b) {
  RowMatrixX3d V(a.num_vertices() + b.num_vertices(), 3);
  V << a.vertices(), b.vertices();
  RowMatrixX3i F(a.num_elements() + b.num_elements(), 3);
  F << a.faces(), (b.faces().array() + static_cast<int>(a.num_vertices())).matrix();
  return TriangleMesh(std::move(V), std::move(F));
}

BEMSURG_INLINE TriangleMesh flip_orientation(const TriangleMesh& mesh) {
  RowMatrixX3i F = mesh.faces();
  F.col(1).swap(F.col(2));
  return TriangleMesh(mesh.vertices(), std::move(F));
}

}  // namespace bemsurg
