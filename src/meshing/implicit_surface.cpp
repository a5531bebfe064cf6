// Marching tetrahedra over a regular grid, one layer of cells at a time (bemsurg/meshing/implicit_surface.hpp).
#include "bemsurg/meshing/implicit_surface.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

namespace detail {

/// A crossing stays this fraction of a grid edge away from both of its nodes.
constexpr double kImplicitCrossingMargin = 1e-2;

/// The sweep's state: the grid, two layers of node values, and the vertex of each crossed grid
/// edge whose lower node lies in either layer (7 edge directions per node: the 3 axes, the 3 face
/// diagonals and the main diagonal of the Kuhn triangulation, all pointing up).
class ImplicitSweep {
 public:
  ImplicitSweep(const ImplicitFunction& f, const Vec3& lo, double h, std::array<Index, 3> cells)
      : f_(f), lo_(lo), h_(h), n_(cells), layer_nodes_((cells[0] + 1) * (cells[1] + 1)) {
    for (int l = 0; l < 2; ++l) {
      values_[l].resize(static_cast<std::size_t>(layer_nodes_));
      ids_[l].assign(static_cast<std::size_t>(7 * layer_nodes_), -1);
    }
  }

  void run(std::vector<double>& coords, std::vector<int>& faces) {
    coords_ = &coords;
    faces_ = &faces;
    fill_layer(0, 0);
    for (Index k = 0; k < n_[2]; ++k) {
      k_ = k;
      fill_layer(1, k + 1);
      for (Index j = 0; j < n_[1]; ++j)
        for (Index i = 0; i < n_[0]; ++i) march_cell(i, j);
      std::swap(values_[0], values_[1]);
      std::swap(ids_[0], ids_[1]);
      std::fill(ids_[1].begin(), ids_[1].end(), -1);
    }
  }

 private:
  Vec3 node_position(Index i, Index j, Index k) const {
    return lo_ + h_ * Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k));
  }

  void fill_layer(int l, Index k) {
    for (Index j = 0; j <= n_[1]; ++j)
      for (Index i = 0; i <= n_[0]; ++i) {
        const Vec3 p = node_position(i, j, k);
        const double v = f_(p);
        if (!std::isfinite(v))
          throw InvalidArgumentError("sample_implicit_surface: the function is not finite at (" + number_text(p.x()) + ", " +
                                     number_text(p.y()) + ", " + number_text(p.z()) + ")");
        const bool boundary = i == 0 || j == 0 || k == 0 || i == n_[0] || j == n_[1] || k == n_[2];
        if (boundary && v < 0.0)
          throw InvalidArgumentError("sample_implicit_surface: grid node (" + number_text(p.x()) + ", " + number_text(p.y()) + ", " +
                                     number_text(p.z()) +
                                     ") on the boundary of the box is inside the surface: enlarge the box so the surface lies within it");
        values_[l][static_cast<std::size_t>(j * (n_[0] + 1) + i)] = v;
      }
  }

  /// Value at cell corner `c` (bit 0: +x, bit 1: +y, bit 2: +z) of cell (i, j) of the current layer.
  double corner_value(Index i, Index j, int c) const {
    const Index node = (j + ((c >> 1) & 1)) * (n_[0] + 1) + i + (c & 1);
    return values_[(c >> 2) & 1][static_cast<std::size_t>(node)];
  }

  /// The vertex on the grid edge from corner a to corner b (b = a plus some unit offsets).
  int edge_vertex(Index i, Index j, int a, int b, double fa, double fb) {
    const Index node = (j + ((a >> 1) & 1)) * (n_[0] + 1) + i + (a & 1);
    int& id = ids_[(a >> 2) & 1][static_cast<std::size_t>(7 * node + (b - a) - 1)];
    if (id >= 0) return id;
    const double t = std::clamp(fa / (fa - fb), kImplicitCrossingMargin, 1.0 - kImplicitCrossingMargin);
    const Vec3 pa = node_position(i + (a & 1), j + ((a >> 1) & 1), k_ + ((a >> 2) & 1));
    const Vec3 pb = node_position(i + (b & 1), j + ((b >> 1) & 1), k_ + ((b >> 2) & 1));
    const Vec3 p = pa + t * (pb - pa);
    id = static_cast<int>(coords_->size() / 3);
    coords_->insert(coords_->end(), {p.x(), p.y(), p.z()});
    return id;
  }

  void march_cell(Index i, Index j) {
    std::array<double, 8> v;
    int inside = 0;
    for (int c = 0; c < 8; ++c) {
      v[static_cast<std::size_t>(c)] = corner_value(i, j, c);
      inside += v[static_cast<std::size_t>(c)] < 0.0;
    }
    if (inside == 0 || inside == 8) return;
    // The six tetrahedra: from corner 0 to corner 7 adding the axes in each order.
    static constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& order : kOrders) {
      const int c1 = 1 << order[0], c2 = c1 | (1 << order[1]);
      march_tetrahedron(i, j, {0, c1, c2, 7}, v);
    }
  }

  /// Orientation of the tetrahedron of cell corners (a, b, c, d): the sign of det(b - a, c - a, d - a), exact in integers.
  static int orientation(int a, int b, int c, int d) {
    const auto vec = [a](int x) {
      return std::array<int, 3>{(x & 1) - (a & 1), ((x >> 1) & 1) - ((a >> 1) & 1), ((x >> 2) & 1) - ((a >> 2) & 1)};
    };
    const auto u = vec(b), w = vec(c), z = vec(d);
    const int det = u[0] * (w[1] * z[2] - w[2] * z[1]) - u[1] * (w[0] * z[2] - w[2] * z[0]) + u[2] * (w[0] * z[1] - w[1] * z[0]);
    return det > 0 ? 1 : -1;
  }

  int vertex_between(Index i, Index j, int a, int b, const std::array<double, 8>& v) {
    // Grid edges are keyed by their lower corner; the tetrahedra's corners are ordered so one of
    // the two is below the other in every coordinate.
    if (a > b) std::swap(a, b);
    return edge_vertex(i, j, a, b, v[static_cast<std::size_t>(a)], v[static_cast<std::size_t>(b)]);
  }

  void add_triangle(int p, int q, int r) { faces_->insert(faces_->end(), {p, q, r}); }

  void march_tetrahedron(Index i, Index j, std::array<int, 4> t, const std::array<double, 8>& v) {
    std::array<int, 4> in{}, out{};
    int ni = 0, no = 0;
    for (int c : t) (v[static_cast<std::size_t>(c)] < 0.0 ? in[static_cast<std::size_t>(ni++)] : out[static_cast<std::size_t>(no++)]) = c;
    if (ni == 0 || ni == 4) return;
    if (ni == 1 || ni == 3) {
      // One corner a apart from the other three: the triangle across its three edges faces away
      // from a when a is inside (and towards it when a is outside), with det(b - a, c - a, d - a) > 0.
      const int a = ni == 1 ? in[0] : out[0];
      const std::array<int, 3> o = ni == 1 ? std::array<int, 3>{out[0], out[1], out[2]} : std::array<int, 3>{in[0], in[1], in[2]};
      const int p = vertex_between(i, j, a, o[0], v), q = vertex_between(i, j, a, o[1], v), r = vertex_between(i, j, a, o[2], v);
      const bool away = orientation(a, o[0], o[1], o[2]) > 0;
      if (away == (ni == 1))
        add_triangle(p, q, r);
      else
        add_triangle(p, r, q);
      return;
    }
    // Two inside (a, b), two outside (c, d): the quadrilateral (ac, ad, bd, bc) faces c and d when
    // det(b - a, c - a, d - a) > 0. Split along its shorter diagonal.
    const int a = in[0], b = in[1], c = out[0], d = out[1];
    std::array<int, 4> quad = {vertex_between(i, j, a, c, v), vertex_between(i, j, a, d, v), vertex_between(i, j, b, d, v),
                               vertex_between(i, j, b, c, v)};
    if (orientation(a, b, c, d) < 0) std::swap(quad[1], quad[3]);
    const auto point = [this](int id) {
      return Vec3((*coords_)[3 * static_cast<std::size_t>(id)], (*coords_)[3 * static_cast<std::size_t>(id) + 1],
                  (*coords_)[3 * static_cast<std::size_t>(id) + 2]);
    };
    if ((point(quad[0]) - point(quad[2])).squaredNorm() <= (point(quad[1]) - point(quad[3])).squaredNorm()) {
      add_triangle(quad[0], quad[1], quad[2]);
      add_triangle(quad[0], quad[2], quad[3]);
    } else {
      add_triangle(quad[1], quad[2], quad[3]);
      add_triangle(quad[1], quad[3], quad[0]);
    }
  }

  const ImplicitFunction& f_;
  Vec3 lo_;
  double h_;
  std::array<Index, 3> n_;
  Index layer_nodes_;
  Index k_ = 0;
  std::array<std::vector<double>, 2> values_;
  std::array<std::vector<int>, 2> ids_;
  std::vector<double>* coords_ = nullptr;
  std::vector<int>* faces_ = nullptr;
};

}  // namespace detail

TriangleMesh sample_implicit_surface(const ImplicitFunction& f, const Vec3& lo, const Vec3& hi, double cell_size) {
  if (!f) throw InvalidArgumentError("sample_implicit_surface: no function given");
  if (!(std::isfinite(cell_size) && cell_size > 0.0))
    throw InvalidArgumentError("sample_implicit_surface: the cell size must be a positive number, got " + number_text(cell_size));
  if (!(lo.allFinite() && hi.allFinite() && (hi.array() > lo.array()).all()))
    throw InvalidArgumentError("sample_implicit_surface: the box needs lo < hi in every coordinate, with finite corners");
  std::array<Index, 3> cells{};
  double nodes = 1.0;
  for (int c = 0; c < 3; ++c) {
    const double n = std::ceil((hi(c) - lo(c)) / cell_size);
    nodes *= n + 1.0;
    if (nodes > 2147483648.0)
      throw InvalidArgumentError("sample_implicit_surface: a cell size of " + number_text(cell_size) +
                                 " makes a grid of more than 2^31 nodes over the box: use a larger cell");
    cells[static_cast<std::size_t>(c)] = std::max<Index>(1, static_cast<Index>(n));
  }
  std::vector<double> coords;
  std::vector<int> faces;
  detail::ImplicitSweep(f, lo, cell_size, cells).run(coords, faces);
  RowMatrixX3d V(static_cast<Index>(coords.size() / 3), 3);
  RowMatrixX3i F(static_cast<Index>(faces.size() / 3), 3);
  std::copy(coords.begin(), coords.end(), V.data());
  std::copy(faces.begin(), faces.end(), F.data());
  return TriangleMesh(std::move(V), std::move(F));
}

double cell_size_for_triangle_count(const ImplicitFunction& f, const Vec3& lo, const Vec3& hi, Index triangles) {
  if (triangles < 100)
    throw InvalidArgumentError("cell_size_for_triangle_count: ask for at least 100 triangles, got " + std::to_string(triangles));
  // A first guess from the box (a surface about as large as the box's), then a pilot at 4 times
  // that cell fixes the constant of count ~ 1 / h^2; a second pilot if the first was too coarse
  // to see the shape (fewer than 400 triangles).
  const Vec3 e = hi - lo;
  const double box_area = 2.0 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
  double h = std::sqrt(box_area / static_cast<double>(triangles));
  for (int attempt = 0; attempt < 4; ++attempt) {
    const double pilot_h = 4.0 * h;
    const Index pilot = sample_implicit_surface(f, lo, hi, pilot_h).num_elements();
    if (pilot == 0) throw InvalidArgumentError("cell_size_for_triangle_count: the function has no surface inside the box");
    h = pilot_h * std::sqrt(static_cast<double>(pilot) / static_cast<double>(triangles));
    if (pilot >= 400) return h;
  }
  return h;
}

Vec3 implicit_ray_crossing(const ImplicitFunction& f, const Vec3& origin, const Vec3& direction, double max_distance) {
  if (!(direction.allFinite() && direction.norm() > 0.0 && std::isfinite(max_distance) && max_distance > 0.0))
    throw InvalidArgumentError("implicit_ray_crossing: needs a non-zero finite direction and a positive distance");
  if (!(f(origin) < 0.0)) throw InvalidArgumentError("implicit_ray_crossing: the ray's origin is not inside the surface");
  const Vec3 d = direction.normalized();
  const double step = max_distance / 256.0;
  for (int s = 1; s <= 256; ++s) {
    if (f(origin + s * step * d) < 0.0) continue;
    double a = (s - 1) * step, b = s * step;  // f < 0 at a, >= 0 at b
    for (int it = 0; it < 200 && b - a > 0.0; ++it) {
      const double m = 0.5 * (a + b);
      if (m <= a || m >= b) break;
      (f(origin + m * d) < 0.0 ? a : b) = m;
    }
    return origin + b * d;
  }
  throw InvalidArgumentError("implicit_ray_crossing: the function stays negative along the ray up to the given distance");
}

}  // namespace bemsurg
