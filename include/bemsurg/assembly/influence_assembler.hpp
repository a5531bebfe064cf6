// bemsurg/assembly/influence_assembler.hpp: the dense influence matrices of constant-element
// collocation BEM (docs/design.md, boundary integral equation and assembly; Wang et al. 2007 eq. 5):
//   H(3i.., 3e..) = 1/2 I delta_ie + int_e T(p_i, Q) dS   (acts on displacements u_e)
//   G(3i.., 3e..) =                  int_e U(p_i, Q) dS   (acts on tractions t_e)
//   g(3i..)       = sum_e int_e P(p_i, Q) dS               (gravity, body force b = rho * gravity)
// so that H u = G t + g. The diagonal H block is evaluated directly (1/2 I plus the principal
// value), never from row sums, so a change to a few elements (a cut) changes only their rows and
// columns, and the rigid-body identity (rows of H sum to zero) stays an honest test of quadrature.
//
// How the work is done (docs/assembly.md): assemble(), assemble_rows(), assemble_columns() and
// gravity_vector() all call one block routine, assemble_block(), for a list of rows x a list of
// columns. It splits the rows into tiles of kTileRows source points and, for one column element at
// a time, evaluates the far-field rule (Radon's 7 points, the quadrature policy's choice when
// distance / diameter >= far_ratio) for all the tile's source points at once: plain loops over
// structure-of-arrays data that the compiler vectorises at -O2/-O3 without -march=native. Pairs
// the policy does not call far (mid, near, self: a few per cent) go through element_pair(), the
// adaptive / polar path of ElementQuadrature, unchanged. The far-field points and weights are
// exactly those ElementQuadrature would use (precomputed once per element with the same
// expressions), so the result differs from a pair-by-pair evaluation only in the order of the
// arithmetic (tests/test_assembly_fast_vs_reference.cpp: 1e-12 relative).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bemsurg/error.hpp"
#include "bemsurg/kernels/kelvin_constants.hpp"
#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"

namespace bemsurg {

struct InfluenceMatrices {
  Eigen::MatrixXd H;  // 3E x 3E, includes the free term 1/2 I
  Eigen::MatrixXd G;  // 3E x 3E
};

class InfluenceAssembler {
 public:
  /// Validates the material and the quadrature options; precomputes the element geometry and the
  /// far-field quadrature points (about 300 bytes per element). The mesh must outlive the assembler.
  InfluenceAssembler(const TriangleMesh& mesh, const Material& material, const QuadratureOptions& options = {})
      : mesh_(mesh), material_(material), kernel_((material.validate(), material)), constants_(material), quadrature_(options) {
    precompute_geometry();
  }

  const TriangleMesh& mesh() const { return mesh_; }
  const Material& material() const { return material_; }
  const KelvinKernel& kernel() const { return kernel_; }
  const ElementQuadrature& quadrature() const { return quadrature_; }

  /// The 3x3 blocks for collocation element i and element e (H includes 1/2 I when i == e), one
  /// pair at a time through ElementQuadrature: the path for mid, near and self pairs.
  void element_pair(Index i, Index e, Eigen::Matrix3d& H, Eigen::Matrix3d& G) const {
    const Eigen::Vector3d p = mesh_.centroid(i);
    const auto c = mesh_.corners(e);
    const Eigen::Vector3d n = mesh_.normal(e);
    H.setZero();
    G.setZero();
    if (i == e) {
      // Polar about the centroid: int U dS = sum w (U r)(d) R; PV int T dS = sum w T_t(d) ln R
      // (the ln(eps) part vanishes because the directions d integrate to zero around the circle).
      quadrature_.polar(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& d, double R, double w) {
        G.noalias() += (w * R) * kernel_.displacement_times_r(d);
        H.noalias() += (w * std::log(R)) * kernel_.traction_tangential_part(d, n);
      });
      H.diagonal().array() += 0.5;
      return;
    }
    Eigen::Matrix3d u, t;
    quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double w) {
      kernel_.displacement_and_traction(x - p, n, u, t);
      G.noalias() += w * u;
      H.noalias() += w * t;
    });
  }

  /// Both full matrices (OpenMP over tiles of rows).
  InfluenceMatrices assemble() const {
    const Index E = mesh_.num_elements();
    InfluenceMatrices m{Eigen::MatrixXd(3 * E, 3 * E), Eigen::MatrixXd(3 * E, 3 * E)};
    assemble_block(nullptr, E, nullptr, E, m.H.data(), m.G.data(), nullptr, Eigen::Vector3d::Zero());
    return m;
  }

  /// H, G and the gravity vector g (body force density * gravity) in one pass over the pairs:
  /// the far-field points that H and G need give g's integrand almost for free. g is resized to 3E
  /// (zero when density or gravity is zero).
  InfluenceMatrices assemble(const Eigen::Vector3d& gravity, Eigen::VectorXd& g) const {
    const Index E = mesh_.num_elements();
    InfluenceMatrices m{Eigen::MatrixXd(3 * E, 3 * E), Eigen::MatrixXd(3 * E, 3 * E)};
    const Eigen::Vector3d body_force = material_.density * gravity;
    g.setZero(3 * E);
    const bool with_gravity = body_force.squaredNorm() != 0.0;
    assemble_block(nullptr, E, nullptr, E, m.H.data(), m.G.data(), with_gravity ? g.data() : nullptr, body_force);
    return m;
  }

  /// Rows (3 per listed element, in list order) of H and G over all columns: out_H, out_G are
  /// resized to 3|rows| x 3E. Used when elements are added or reshaped (cutting).
  void assemble_rows(const std::vector<Index>& rows, Eigen::MatrixXd& out_H, Eigen::MatrixXd& out_G) const {
    const Index E = mesh_.num_elements(), R = static_cast<Index>(rows.size());
    check_ids(rows, "assemble_rows");
    out_H.resize(3 * R, 3 * E);
    out_G.resize(3 * R, 3 * E);
    if (R == 0) return;
    assemble_block(rows.data(), R, nullptr, E, out_H.data(), out_G.data(), nullptr, Eigen::Vector3d::Zero());
  }

  /// Columns (3 per listed element) of H and G over all rows: 3E x 3|cols|.
  void assemble_columns(const std::vector<Index>& cols, Eigen::MatrixXd& out_H, Eigen::MatrixXd& out_G) const {
    const Index E = mesh_.num_elements(), C = static_cast<Index>(cols.size());
    check_ids(cols, "assemble_columns");
    out_H.resize(3 * E, 3 * C);
    out_G.resize(3 * E, 3 * C);
    if (C == 0) return;
    assemble_block(nullptr, E, cols.data(), C, out_H.data(), out_G.data(), nullptr, Eigen::Vector3d::Zero());
  }

  /// Gravity right-hand side for body force per volume b = density * gravity (m/s^2).
  Eigen::VectorXd gravity_vector(const Eigen::Vector3d& gravity) const {
    const Index E = mesh_.num_elements();
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * E);
    const Eigen::Vector3d body_force = material_.density * gravity;
    if (body_force.squaredNorm() == 0.0) return g;
    assemble_block(nullptr, E, nullptr, E, nullptr, nullptr, g.data(), body_force);
    return g;
  }

  /// Contribution of element e to the gravity term at a source point p (p may be any point;
  /// p equal to e's centroid uses the polar rule).
  Eigen::Vector3d gravity_element(const Eigen::Vector3d& p, Index e, const GravityKernel& kernel, bool self) const {
    const auto c = mesh_.corners(e);
    const Eigen::Vector3d n = mesh_.normal(e);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    if (self) {
      // P depends on the direction only when dr/dn = 0: int_0^R P r dr = P(d) R^2 / 2.
      quadrature_.polar(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& d, double R, double w) {
        sum += (0.5 * w * R * R) * kernel.tangential_part(d, n);
      });
    } else {
      quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double w) { sum += w * kernel(x - p, n); });
    }
    return sum;
  }

  /// The one block routine behind assemble(), assemble_rows(), assemble_columns() and
  /// gravity_vector(): rows x cols of H and G and/or the gravity of the rows.
  ///   rows, cols: element ids (nullptr: 0, 1, ..., R-1 or C-1);
  ///   H, G: column-major 3R x 3C outputs (leading dimension 3R), both or neither (nullptr);
  ///   g: 3R gravity output (nullptr: none), summed over the columns, which should then be all
  ///      elements; body_force is only read when g is given.
  /// Every output entry is written (no need to zero it first). Parallel over tiles (OpenMP); each
  /// tile owns its output entries, and a row's gravity is summed by one thread in column order, so
  /// the result does not depend on the number of threads.
  void assemble_block(const Index* rows, Index R, const Index* cols, Index C, double* H, double* G, double* g,
                      const Eigen::Vector3d& body_force) const {
    const bool hg = H != nullptr && G != nullptr;
    if (!hg && g == nullptr) return;
    const Index chunks = (R + kTileRows - 1) / kTileRows;
    Index ranges = 1;  // column ranges per row chunk; 1 when g is summed (one thread per row)
#ifdef _OPENMP
    const Index threads = omp_get_max_threads();
#else
    const Index threads = 1;
#endif
    if (g == nullptr && chunks < 4 * threads) ranges = std::min<Index>(C, (4 * threads + chunks - 1) / chunks);
    const Index tiles = chunks * ranges;
#pragma omp parallel for schedule(dynamic, 1)
    for (Index t = 0; t < tiles; ++t) {
      const Index chunk = t / ranges, range = t % ranges;
      const Index r0 = chunk * kTileRows, m = std::min<Index>(kTileRows, R - r0);
      const Index c0 = C * range / ranges, c1 = C * (range + 1) / ranges;
      if (hg && g) tile<true, true>(rows, R, r0, m, cols, c0, c1, H, G, g, body_force);
      else if (hg) tile<true, false>(rows, R, r0, m, cols, c0, c1, H, G, g, body_force);
      else tile<false, true>(rows, R, r0, m, cols, c0, c1, H, G, g, body_force);
    }
  }

 private:
  static constexpr int kTileRows = 64;   // source points evaluated together (fits L1 with the sums)
  static constexpr int kFarPoints = 7;   // Radon's rule
  // Per-pair sums of the far-field loop, one array each over the tile's source points.
  enum : int {
    kGxx, kGyy, kGzz, kGxy, kGxz, kGyz,                    // G is symmetric: 6
    kHxx, kHyy, kHzz, kHxy, kHyx, kHxz, kHzx, kHyz, kHzy,  // H: 9
    kPn, kPx, kPy, kPz,                                    // gravity: sum w dr/dn, sum w r,i
    kSums
  };

  // Element geometry in structure-of-arrays form, read in the order the loops need it.
  struct Geometry {
    std::vector<double> cx, cy, cz;  // centroid = collocation point
    std::vector<double> nx, ny, nz;  // unit normal
    std::vector<double> far2;        // (far_ratio * diameter)^2, raised by 1e-12 relative (see tile)
    std::vector<double> qx, qy, qz, qw;  // far-rule points and weights, kFarPoints per element
  };

  void check_ids(const std::vector<Index>& ids, const char* where) const {
    for (Index e : ids)
      if (e < 0 || e >= mesh_.num_elements())
        throw Error(std::string("InfluenceAssembler::") + where + ": element " + std::to_string(e) + " out of range [0, " +
                    std::to_string(mesh_.num_elements()) + ")");
  }

  void precompute_geometry() {
    const Index E = mesh_.num_elements();
    const TriangleRule& rule = radon7_rule();
    if (static_cast<int>(rule.weights.size()) != kFarPoints) throw Error("InfluenceAssembler: far rule has the wrong size");
    const double far_ratio = quadrature_.options().far_ratio;
    auto size = [&](std::vector<double>& v, Index per) { v.assign(static_cast<std::size_t>(E * per), 0.0); };
    for (auto* v : {&geo_.cx, &geo_.cy, &geo_.cz, &geo_.nx, &geo_.ny, &geo_.nz, &geo_.far2}) size(*v, 1);
    for (auto* v : {&geo_.qx, &geo_.qy, &geo_.qz, &geo_.qw}) size(*v, kFarPoints);
    for (Index e = 0; e < E; ++e) {
      const std::size_t s = static_cast<std::size_t>(e);
      const auto c = mesh_.corners(e);
      const Eigen::Vector3d &a = c[0], &b = c[1], &cc = c[2];
      // The same expressions as ElementQuadrature's top level, so that points, weights and the
      // far / not-far decision agree to the last bit.
      const double h = std::sqrt(std::max({(b - a).squaredNorm(), (cc - b).squaredNorm(), (a - cc).squaredNorm()}));
      const Eigen::Vector3d centre = (a + b + cc) / 3.0;
      const double area = 0.5 * (b - a).cross(cc - a).norm();
      const Eigen::Vector3d n = mesh_.normal(e);
      geo_.cx[s] = centre.x();
      geo_.cy[s] = centre.y();
      geo_.cz[s] = centre.z();
      geo_.nx[s] = n.x();
      geo_.ny[s] = n.y();
      geo_.nz[s] = n.z();
      const double limit = far_ratio * h;
      geo_.far2[s] = limit * limit * (1.0 + 1e-12);
      const Eigen::Vector3d e1 = b - a, e2 = cc - a;
      for (int k = 0; k < kFarPoints; ++k) {
        const std::size_t q = s * kFarPoints + static_cast<std::size_t>(k);
        const Eigen::Vector3d x = a + rule.points[static_cast<std::size_t>(k)].x() * e1 + rule.points[static_cast<std::size_t>(k)].y() * e2;
        geo_.qx[q] = x.x();
        geo_.qy[q] = x.y();
        geo_.qz[q] = x.z();
        geo_.qw[q] = area * rule.weights[static_cast<std::size_t>(k)];
      }
    }
  }

  /// One tile: source rows r0 .. r0+m-1 (positions in the row list) against columns c0 .. c1-1.
  template <bool HG, bool Gravity>
  void tile(const Index* rows, Index R, Index r0, Index m, const Index* cols, Index c0, Index c1, double* H, double* G,
            double* g, const Eigen::Vector3d& body_force) const {
    alignas(64) double px[kTileRows], py[kTileRows], pz[kTileRows];
    alignas(64) double rx[kTileRows], ry[kTileRows], rz[kTileRows], inv[kTileRows];
    alignas(64) double sum[kSums][kTileRows];
    alignas(64) double gsum[3][kTileRows];
    Index id[kTileRows];
    unsigned char far[kTileRows];
    for (Index j = 0; j < m; ++j) {
      id[j] = rows ? rows[r0 + j] : r0 + j;
      const std::size_t s = static_cast<std::size_t>(id[j]);
      px[j] = geo_.cx[s];
      py[j] = geo_.cy[s];
      pz[j] = geo_.cz[s];
      gsum[0][j] = gsum[1][j] = gsum[2][j] = 0.0;
    }
    const KelvinConstants& k = constants_;
    const GravityKernel gravity_kernel(k, body_force);
    const Index ld = 3 * R;
    Eigen::Matrix3d hb, gb;
    for (Index c = c0; c < c1; ++c) {
      const Index e = cols ? cols[c] : c;
      const std::size_t s = static_cast<std::size_t>(e);
      const double ex = geo_.cx[s], ey = geo_.cy[s], ez = geo_.cz[s], far2 = geo_.far2[s];
      const double nx = geo_.nx[s], ny = geo_.ny[s], nz = geo_.nz[s];
      // The policy's test, dist >= far_ratio * diameter, on squares. Pairs within 1e-12 of the
      // threshold go to element_pair, which decides exactly as ElementQuadrature does.
      int nfar = 0;
      for (Index j = 0; j < m; ++j) {
        const double dx = px[j] - ex, dy = py[j] - ey, dz = pz[j] - ez;
        far[j] = (dx * dx + dy * dy + dz * dz >= far2) ? 1 : 0;
        nfar += far[j];
      }
      if (nfar > 0) {
        for (int a = 0; a < kSums; ++a)
          for (Index j = 0; j < m; ++j) sum[a][j] = 0.0;
        for (int q = 0; q < kFarPoints; ++q) {
          const std::size_t qi = s * kFarPoints + static_cast<std::size_t>(q);
          const double xq = geo_.qx[qi], yq = geo_.qy[qi], zq = geo_.qz[qi], w = geo_.qw[qi];
          for (Index j = 0; j < m; ++j) {  // r = x_Q - p
            rx[j] = xq - px[j];
            ry[j] = yq - py[j];
            rz[j] = zq - pz[j];
            inv[j] = rx[j] * rx[j] + ry[j] * ry[j] + rz[j] * rz[j];
          }
          // 1/r through Eigen's packet sqrt: the plain loop would not vectorise while std::sqrt
          // may set errno (GCC without -fno-math-errno). Correctly rounded, as std::sqrt is.
          Eigen::Map<Eigen::ArrayXd> r2(inv, m);
          r2 = r2.sqrt().inverse();
          far_point<HG, Gravity>(m, w, nx, ny, nz, rx, ry, rz, inv, sum);
        }
      }
      if (HG) {
        // Column-major writes: the tile's 3m rows of columns 3c, 3c+1, 3c+2 are contiguous.
        static constexpr int gi[3][3] = {{kGxx, kGxy, kGxz}, {kGxy, kGyy, kGyz}, {kGxz, kGyz, kGzz}};
        static constexpr int hi[3][3] = {{kHxx, kHxy, kHxz}, {kHyx, kHyy, kHyz}, {kHzx, kHzy, kHzz}};
        for (int b = 0; b < 3; ++b) {
          double* hcol = H + (3 * c + b) * ld + 3 * r0;
          double* gcol = G + (3 * c + b) * ld + 3 * r0;
          if (nfar > 0)
            for (Index j = 0; j < m; ++j)
              for (int a = 0; a < 3; ++a) {
                hcol[3 * j + a] = sum[hi[a][b]][j];
                gcol[3 * j + a] = sum[gi[a][b]][j];
              }
        }
        if (nfar < m)
          for (Index j = 0; j < m; ++j) {
            if (far[j]) continue;
            element_pair(id[j], e, hb, gb);
            for (int b = 0; b < 3; ++b)
              for (int a = 0; a < 3; ++a) {
                H[(3 * c + b) * ld + 3 * (r0 + j) + a] = hb(a, b);
                G[(3 * c + b) * ld + 3 * (r0 + j) + a] = gb(a, b);
              }
          }
      }
      if (Gravity) {
        // P_i = p_scale [b_i dr/dn - n_i (b . r,) / (2 (1 - nu))] is linear in (dr/dn, r,):
        // integrate those and apply b once per pair.
        const double bx = body_force.x(), by = body_force.y(), bz = body_force.z();
        for (Index j = 0; j < m; ++j) {
          if (far[j]) {
            const double sn = sum[kPn][j];
            const double bd = k.p_half_inv * (bx * sum[kPx][j] + by * sum[kPy][j] + bz * sum[kPz][j]);
            gsum[0][j] += k.p_scale * (bx * sn - nx * bd);
            gsum[1][j] += k.p_scale * (by * sn - ny * bd);
            gsum[2][j] += k.p_scale * (bz * sn - nz * bd);
          } else {
            const Eigen::Vector3d v = gravity_element(mesh_.centroid(id[j]), e, gravity_kernel, id[j] == e);
            gsum[0][j] += v.x();
            gsum[1][j] += v.y();
            gsum[2][j] += v.z();
          }
        }
      }
    }
    if (Gravity)
      for (Index j = 0; j < m; ++j)
        for (int a = 0; a < 3; ++a) g[3 * (r0 + j) + a] = gsum[a][j];
  }

  /// One far-field point Q (weight w, normal n of its element) for the tile's source points, the
  /// Kelvin kernels written out (docs/design.md, kernels; Wang et al. 2007 eqs. 2-3):
  ///   U_ij = u_scale [(3 - 4 nu) delta_ij + r,i r,j] / r
  ///   T_ij = t_scale [dr/dn ((1 - 2 nu) delta_ij + 3 r,i r,j) - (1 - 2 nu)(r,i n_j - r,j n_i)] / r^2
  /// with r,i = r_i / r and t_scale = -1 / (8 pi (1 - nu)) carrying the sign; gravity collects
  /// w dr/dn and w r,i. A loop over plain arrays, no Eigen temporaries: the compiler vectorises it.
  template <bool HG, bool Gravity>
  void far_point(Index m, double w, double nx, double ny, double nz, const double* __restrict rx,
                 const double* __restrict ry, const double* __restrict rz, const double* __restrict inv,
                 double (*__restrict sum)[kTileRows]) const {
    const KelvinConstants& k = constants_;
    const double wu0 = w * k.u_scale, wt0 = w * k.t_scale, c34 = k.three_minus_4nu, a = k.one_minus_2nu;
    for (Index j = 0; j < m; ++j) {
      const double dx = rx[j] * inv[j], dy = ry[j] * inv[j], dz = rz[j] * inv[j];  // r,i
      const double drdn = dx * nx + dy * ny + dz * nz;
      if (HG) {
        const double wu = wu0 * inv[j];            // w u_scale / r
        const double wt = wt0 * inv[j] * inv[j];   // w t_scale / r^2
        sum[kGxx][j] += wu * (dx * dx + c34);
        sum[kGyy][j] += wu * (dy * dy + c34);
        sum[kGzz][j] += wu * (dz * dz + c34);
        sum[kGxy][j] += wu * (dx * dy);
        sum[kGxz][j] += wu * (dx * dz);
        sum[kGyz][j] += wu * (dy * dz);
        const double q = 3.0 * drdn * wt, diag = a * drdn * wt, aw = a * wt;
        const double sxy = dx * ny - dy * nx, sxz = dx * nz - dz * nx, syz = dy * nz - dz * ny;  // r,i n_j - r,j n_i
        sum[kHxx][j] += q * dx * dx + diag;
        sum[kHyy][j] += q * dy * dy + diag;
        sum[kHzz][j] += q * dz * dz + diag;
        sum[kHxy][j] += q * dx * dy - aw * sxy;
        sum[kHyx][j] += q * dx * dy + aw * sxy;
        sum[kHxz][j] += q * dx * dz - aw * sxz;
        sum[kHzx][j] += q * dx * dz + aw * sxz;
        sum[kHyz][j] += q * dy * dz - aw * syz;
        sum[kHzy][j] += q * dy * dz + aw * syz;
      }
      if (Gravity) {
        sum[kPn][j] += w * drdn;
        sum[kPx][j] += w * dx;
        sum[kPy][j] += w * dy;
        sum[kPz][j] += w * dz;
      }
    }
  }

  const TriangleMesh& mesh_;
  Material material_;
  KelvinKernel kernel_;
  KelvinConstants constants_;
  ElementQuadrature quadrature_;
  Geometry geo_;
};

}  // namespace bemsurg
