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
// the policy does not call far (mid and near, a few per cent) keep ElementQuadrature's rules and
// points (collapsed Gauss, adaptive subdivision); their points are evaluated in batches by the same
// kernel loop. The self pair keeps the polar rule. The far-field points and weights are exactly
// those ElementQuadrature would use (precomputed once per element with the same expressions), so
// the result differs from a pair-by-pair evaluation only in the order of the arithmetic
// (tests/test_assembly_fast_vs_reference.cpp: 1e-12 relative; measured: below 1e-15).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bemsurg/dense_storage.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/kernels/kelvin_constants.hpp"
#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"

namespace bemsurg {

/// The dense influence matrices of H u = G t + g (Wang et al. 2007 eq. 5), 3E x 3E each; H includes the free term 1/2 I.
/// \ingroup assembly
struct InfluenceMatrices {
  Eigen::MatrixXd H;  // 3E x 3E, includes the free term 1/2 I
  Eigen::MatrixXd G;  // 3E x 3E
};

/// Assembles the influence matrices H and G of constant-element collocation on one mesh, the gravity vector g, or
/// only the rows and columns of listed elements (docs/assembly.md).
/// \ingroup assembly
class InfluenceAssembler {
 public:
  /// Validates the material and the quadrature options; precomputes the element geometry and the
  /// far-field quadrature points (about 300 bytes per element). The mesh must outlive the assembler.
  InfluenceAssembler(const TriangleMesh& mesh, const Material& material, const QuadratureOptions& options = {})
      : mesh_(mesh), material_(material), kernel_(material.validated()), constants_(material), quadrature_(options) {
    precompute_geometry();
  }

  const TriangleMesh& mesh() const { return mesh_; }
  const Material& material() const { return material_; }
  const KelvinKernel& kernel() const { return kernel_; }
  const ElementQuadrature& quadrature() const { return quadrature_; }

  /// The 3x3 blocks for collocation element i and element e (H includes 1/2 I when i == e), one
  /// pair at a time: the path assemble_block() takes for the pairs the policy does not call far.
  /// Bit for bit the blocks that assemble() writes for such pairs.
  void element_pair(Index i, Index e, Eigen::Matrix3d& H, Eigen::Matrix3d& G) const {
    if (i == e) return self_pair(e, H, G);
    double total[kSums];
    regular_pair<true, false>(mesh_.centroid(i), e, total);
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) {
        H(a, b) = total[kHIndex[a][b]];
        G(a, b) = total[kGIndex[a][b]];
      }
  }

  /// Both full matrices (OpenMP over tiles of rows).
  InfluenceMatrices assemble() const {
    const Index E = mesh_.num_elements();
    InfluenceMatrices m{large_dense_matrix(3 * E, 3 * E), large_dense_matrix(3 * E, 3 * E)};
    assemble_block(nullptr, E, nullptr, E, m.H.data(), m.G.data(), nullptr, Eigen::Vector3d::Zero());
    return m;
  }

  /// H, G and the gravity vector g (body force density * gravity) in one pass over the pairs:
  /// the far-field points that H and G need give g's integrand almost for free. g is resized to 3E
  /// (zero when density or gravity is zero).
  InfluenceMatrices assemble(const Eigen::Vector3d& gravity, Eigen::VectorXd& g) const {
    const Index E = mesh_.num_elements();
    InfluenceMatrices m{large_dense_matrix(3 * E, 3 * E), large_dense_matrix(3 * E, 3 * E)};
    assemble_block(nullptr, E, nullptr, E, m.H.data(), m.G.data(), gravity_output(&g, 3 * E, gravity), material_.density * gravity);
    return m;
  }

  /// Rows (3 per listed element, in list order) of H and G over all columns: out_H, out_G are
  /// resized to 3|rows| x 3E. Used when elements are added or reshaped (cutting). `out_gravity`
  /// (optional) is resized to 3|rows| and gets those rows of the gravity vector for acceleration
  /// `gravity` (every element's share; zero when density or gravity is zero) from the same pass
  /// over the pairs, whose quadrature points give its integrand almost for free.
  void assemble_rows(const std::vector<Index>& rows, Eigen::MatrixXd& out_H, Eigen::MatrixXd& out_G, Eigen::VectorXd* out_gravity = nullptr,
                     const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero()) const {
    const Index E = mesh_.num_elements(), R = static_cast<Index>(rows.size());
    check_ids(rows, "assemble_rows");
    if (out_H.rows() != 3 * R || out_H.cols() != 3 * E) out_H = large_dense_matrix(3 * R, 3 * E);
    if (out_G.rows() != 3 * R || out_G.cols() != 3 * E) out_G = large_dense_matrix(3 * R, 3 * E);
    double* g = gravity_output(out_gravity, 3 * R, gravity);
    if (R == 0) return;
    assemble_block(rows.data(), R, nullptr, E, out_H.data(), out_G.data(), g, material_.density * gravity);
  }

  /// Columns (3 per listed element) of H and G over all rows: 3E x 3|cols|. `out_gravity`
  /// (optional) is resized to 3E and gets the gravity term at every row from the listed elements
  /// only, from the same pass (as assemble_rows).
  void assemble_columns(const std::vector<Index>& cols, Eigen::MatrixXd& out_H, Eigen::MatrixXd& out_G,
                        Eigen::VectorXd* out_gravity = nullptr, const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero()) const {
    const Index E = mesh_.num_elements(), C = static_cast<Index>(cols.size());
    check_ids(cols, "assemble_columns");
    if (out_H.rows() != 3 * E || out_H.cols() != 3 * C) out_H = large_dense_matrix(3 * E, 3 * C);
    if (out_G.rows() != 3 * E || out_G.cols() != 3 * C) out_G = large_dense_matrix(3 * E, 3 * C);
    double* g = gravity_output(out_gravity, 3 * E, gravity);
    if (C == 0) return;
    assemble_block(nullptr, E, cols.data(), C, out_H.data(), out_G.data(), g, material_.density * gravity);
  }

  /// Gravity right-hand side for body force per volume b = density * gravity (m/s^2).
  Eigen::VectorXd gravity_vector(const Eigen::Vector3d& gravity) const {
    const Index E = mesh_.num_elements();
    Eigen::VectorXd g;
    assemble_block(nullptr, E, nullptr, E, nullptr, nullptr, gravity_output(&g, 3 * E, gravity), material_.density * gravity);
    return g;
  }

  /// Contribution of element e to the gravity term at a source point p (p may be any point;
  /// p equal to e's centroid uses the polar rule).
  Eigen::Vector3d gravity_element(const Eigen::Vector3d& p, Index e, const GravityKernel& kernel, bool self) const {
    const Eigen::Vector3d n = mesh_.normal(e);
    if (self) {
      const auto c = mesh_.corners(e);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      // P depends on the direction only when dr/dn = 0: int_0^R P r dr = P(d) R^2 / 2.
      quadrature_.polar(p, c[0], c[1], c[2],
                        [&](const Eigen::Vector3d& d, double R, double w) { sum += (0.5 * w * R * R) * kernel.tangential_part(d, n); });
      return sum;
    }
    double total[kSums];
    regular_pair<false, true>(p, e, total);
    return kernel.from_integrals(total[kPn], Eigen::Vector3d(total[kPx], total[kPy], total[kPz]), n);
  }

  /// The one block routine behind assemble(), assemble_rows(), assemble_columns() and
  /// gravity_vector(): rows x cols of H and G and/or the gravity of the rows.
  ///   rows, cols: element ids, in range (not checked here; assemble_rows / assemble_columns
  ///      check them), or nullptr for 0, 1, ..., R-1 or C-1;
  ///   H, G: column-major 3R x 3C outputs (leading dimension 3R), both or neither (nullptr);
  ///   g: 3R gravity output (nullptr: none), summed over the columns (all elements for the gravity
  ///      vector, the listed ones for their share); body_force is only read when g is given.
  /// Every output entry is written (no need to zero it first). Parallel over tiles (OpenMP); each
  /// tile owns its output entries. A row's gravity is summed in column order by one tile, except
  /// for rows that fit one tile (a cut's changed ones): their columns are split into
  /// min(C, kGravityRanges) ranges, each summed into a part of its own and the parts added in range
  /// order. Either way the result does not depend on the number of threads, and the gravity vector
  /// of a body of more than kTileRows elements is summed as it always was. The split allocates its
  /// parts (at most kGravityRanges x 3 x kTileRows doubles); nothing else here allocates.
  void assemble_block(const Index* rows, Index R, const Index* cols, Index C, double* H, double* G, double* g,
                      const Eigen::Vector3d& body_force) const {
    const bool hg = H != nullptr && G != nullptr;
    if ((!hg && g == nullptr) || R == 0) return;
    const Index chunks = (R + kTileRows - 1) / kTileRows;
    Index ranges = 1;  // column ranges per row chunk
#ifdef _OPENMP
    const Index threads = omp_get_max_threads();
#else
    const Index threads = 1;
#endif
    if (g != nullptr && chunks == 1)
      ranges = std::max<Index>(1, std::min<Index>(C, kGravityRanges));
    else if (g == nullptr && chunks < 4 * threads)
      ranges = std::min<Index>(C, (4 * threads + chunks - 1) / chunks);
    // Split gravity sums: each range's part of g (3R each), added up after the tiles.
    std::vector<double> parts(g != nullptr && ranges > 1 ? static_cast<std::size_t>(ranges * 3 * R) : 0);
    const Index tiles = chunks * ranges;
#pragma omp parallel for schedule(dynamic, 1)
    for (Index t = 0; t < tiles; ++t) {
      const Index chunk = t / ranges, range = t % ranges;
      const Index r0 = chunk * kTileRows, m = std::min<Index>(kTileRows, R - r0);
      const Index c0 = C * range / ranges, c1 = C * (range + 1) / ranges;
      double* gt = parts.empty() ? g : parts.data() + range * 3 * R;
      if (hg && g)
        tile<true, true>(rows, R, r0, m, cols, c0, c1, H, G, gt, body_force);
      else if (hg)
        tile<true, false>(rows, R, r0, m, cols, c0, c1, H, G, gt, body_force);
      else
        tile<false, true>(rows, R, r0, m, cols, c0, c1, H, G, gt, body_force);
    }
    if (!parts.empty())
      for (Index i = 0; i < 3 * R; ++i) {
        double sum = parts[static_cast<std::size_t>(i)];
        for (Index range = 1; range < ranges; ++range) sum += parts[static_cast<std::size_t>(range * 3 * R + i)];
        g[i] = sum;
      }
  }

 private:
  static constexpr int kTileRows = 64;  // source points evaluated together (fits L1 with the sums)
  static constexpr int kBatch = 64;     // quadrature points of one mid / near pair evaluated together
  static constexpr int kFarPoints = 7;  // Radon's rule
  // Column ranges that sum the gravity of rows fitting one tile: fixed, so that the sums do not
  // depend on the thread count, and enough for the cores of a large machine.
  static constexpr int kGravityRanges = 64;
  // Per-pair sums of the kernel loop, one array each over the source points (far field) or the
  // quadrature points (mid / near pairs).
  enum : int {
    kGxx,
    kGyy,
    kGzz,
    kGxy,
    kGxz,
    kGyz,  // G is symmetric: 6
    kHxx,
    kHyy,
    kHzz,
    kHxy,
    kHyx,
    kHxz,
    kHzx,
    kHyz,
    kHzy,  // H: 9
    kPn,
    kPx,
    kPy,
    kPz,  // gravity: sum w dr/dn, sum w r,i
    kSums
  };
  static constexpr int kGIndex[3][3] = {{kGxx, kGxy, kGxz}, {kGxy, kGyy, kGyz}, {kGxz, kGyz, kGzz}};
  static constexpr int kHIndex[3][3] = {{kHxx, kHxy, kHxz}, {kHyx, kHyy, kHyz}, {kHzx, kHzy, kHzz}};

  // Element geometry in structure-of-arrays form, read in the order the loops need it.
  struct Geometry {
    std::vector<double> cx, cy, cz;      // centroid = collocation point
    std::vector<double> nx, ny, nz;      // unit normal
    std::vector<double> far2;            // (far_ratio * diameter)^2, raised by 1e-12 relative (see tile)
    std::vector<double> qx, qy, qz, qw;  // far-rule points and weights, kFarPoints per element
  };

  /// Zeroes `out` at `size` and returns where assemble_block sums the gravity term, or nullptr when
  /// none is asked for or the body force is zero.
  double* gravity_output(Eigen::VectorXd* out, Index size, const Eigen::Vector3d& gravity) const {
    if (!out) return nullptr;
    out->setZero(size);
    return (material_.density * gravity).squaredNorm() != 0.0 ? out->data() : nullptr;
  }

  void check_ids(const std::vector<Index>& ids, const char* where) const {
    for (Index e : ids)
      if (e < 0 || e >= mesh_.num_elements())
        throw InvalidArgumentError(std::string("InfluenceAssembler::") + where + ": element " + std::to_string(e) + " out of range [0, " +
                                   std::to_string(mesh_.num_elements()) + ")");
  }

  void precompute_geometry() {
    const Index E = mesh_.num_elements();
    const TriangleRule& rule = radon7_rule();
    if (static_cast<int>(rule.weights.size()) != kFarPoints) throw InvalidArgumentError("InfluenceAssembler: far rule has the wrong size");
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
      const double h = element_diameter(a, b, cc);
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

  /// The self pair (source = e's own centroid): polar coordinates about the centroid.
  /// int U dS = sum w (U r)(d) R; PV int T dS = sum w T_t(d) ln R (the ln(eps) part vanishes
  /// because the directions d integrate to zero around the circle); H gets the free term 1/2 I.
  void self_pair(Index e, Eigen::Matrix3d& H, Eigen::Matrix3d& G) const {
    const Eigen::Vector3d p = mesh_.centroid(e);
    const auto c = mesh_.corners(e);
    const Eigen::Vector3d n = mesh_.normal(e);
    H.setZero();
    G.setZero();
    quadrature_.polar(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& d, double R, double w) {
      G.noalias() += (w * R) * kernel_.displacement_times_r(d);
      H.noalias() += (w * std::log(R)) * kernel_.traction_tangential_part(d, n);
    });
    H.diagonal().array() += 0.5;
  }

  /// A pair that is not the self pair, by ElementQuadrature's regular rule (far, mid or adaptive
  /// near): its points are collected kBatch at a time and evaluated by kelvin_terms, each batch
  /// slot accumulating its own partial sums, which are added up once at the end (four chains, so
  /// the additions do not wait on each other). total[] gets the H, G (HG) and gravity (Gravity)
  /// sums of the enum above.
  template <bool HG, bool Gravity>
  void regular_pair(const Eigen::Vector3d& p, Index e, double* total) const {
    alignas(64) double rx[kBatch], ry[kBatch], rz[kBatch], inv[kBatch], w[kBatch];
    alignas(64) double terms[kSums][kBatch];
    const int first = HG ? 0 : kPn, last = Gravity ? kSums : kPn;
    const std::size_t s = static_cast<std::size_t>(e);
    const double nx = geo_.nx[s], ny = geo_.ny[s], nz = geo_.nz[s];
    Index count = 0, used = 0;  // points in the batch; slots holding partial sums
    auto flush = [&] {
      for (int a = first; a < last; ++a)
        for (Index j = used; j < count; ++j) terms[a][j] = 0.0;
      used = std::max(used, count);
      kelvin_terms<HG, Gravity, true>(count, w, nx, ny, nz, rx, ry, rz, inv, terms);
      count = 0;
    };
    const auto c = mesh_.corners(e);
    quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double weight) {
      rx[count] = x.x() - p.x();  // r = x_Q - p
      ry[count] = x.y() - p.y();
      rz[count] = x.z() - p.z();
      w[count] = weight;
      if (++count == kBatch) flush();
    });
    if (count > 0) flush();
    for (int a = 0; a < kSums; ++a) total[a] = 0.0;
    for (int a = first; a < last; ++a) {
      double part[4] = {0.0, 0.0, 0.0, 0.0};
      Index j = 0;
      for (; j + 4 <= used; j += 4)
        for (int l = 0; l < 4; ++l) part[l] += terms[a][j + l];
      for (; j < used; ++j) part[0] += terms[a][j];
      total[a] = (part[0] + part[1]) + (part[2] + part[3]);
    }
  }

  /// One tile: source rows r0 .. r0+m-1 (positions in the row list) against columns c0 .. c1-1.
  // long: the assembly's innermost loop; its far, near and gravity passes share the tile's stack arrays
  template <bool HG, bool Gravity>
  void tile(const Index* rows, Index R, Index r0, Index m, const Index* cols, Index c0, Index c1, double* H, double* G, double* g,
            const Eigen::Vector3d& body_force) const {
    alignas(64) double px[kTileRows], py[kTileRows], pz[kTileRows];
    alignas(64) double rx[kTileRows], ry[kTileRows], rz[kTileRows], inv[kTileRows], wq[kTileRows];
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
    const GravityKernel gravity_kernel(constants_, body_force);
    const Index ld = 3 * R;
    Eigen::Matrix3d hb, gb;
    double total[kSums];
    for (Index c = c0; c < c1; ++c) {
      const Index e = cols ? cols[c] : c;
      const std::size_t s = static_cast<std::size_t>(e);
      const double ex = geo_.cx[s], ey = geo_.cy[s], ez = geo_.cz[s], far2 = geo_.far2[s];
      const double nx = geo_.nx[s], ny = geo_.ny[s], nz = geo_.nz[s];
      const Eigen::Vector3d n(nx, ny, nz);
      // The policy's test, dist >= far_ratio * diameter, on squares. Pairs within 1e-12 of the
      // threshold take regular_pair, where ElementQuadrature decides exactly as it always does.
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
            wq[j] = w;
          }
          kelvin_terms<HG, Gravity, true>(m, wq, nx, ny, nz, rx, ry, rz, inv, sum);
        }
      }
      if (HG && nfar > 0) {
        // Column-major writes: the tile's 3m rows of columns 3c, 3c+1, 3c+2 are contiguous.
        for (int b = 0; b < 3; ++b) {
          double* hcol = H + (3 * c + b) * ld + 3 * r0;
          double* gcol = G + (3 * c + b) * ld + 3 * r0;
          for (Index j = 0; j < m; ++j)
            for (int a = 0; a < 3; ++a) {
              hcol[3 * j + a] = sum[kHIndex[a][b]][j];
              gcol[3 * j + a] = sum[kGIndex[a][b]][j];
            }
        }
      }
      if (Gravity && nfar > 0)
        for (Index j = 0; j < m; ++j) {
          if (!far[j]) continue;
          const Eigen::Vector3d v = gravity_kernel.from_integrals(sum[kPn][j], Eigen::Vector3d(sum[kPx][j], sum[kPy][j], sum[kPz][j]), n);
          for (int a = 0; a < 3; ++a) gsum[a][j] += v(a);
        }
      if (nfar == m) continue;
      // Mid, near and self pairs (a few per cent): one at a time, overwriting the far-rule values.
      for (Index j = 0; j < m; ++j) {
        if (far[j]) continue;
        const Eigen::Vector3d p = mesh_.centroid(id[j]);
        if (id[j] == e) {
          if (HG) self_pair(e, hb, gb);
          if (Gravity) {
            const Eigen::Vector3d v = gravity_element(p, e, gravity_kernel, true);
            for (int a = 0; a < 3; ++a) gsum[a][j] += v(a);
          }
        } else {
          regular_pair<HG, Gravity>(p, e, total);
          if (HG)
            for (int b = 0; b < 3; ++b)
              for (int a = 0; a < 3; ++a) {
                hb(a, b) = total[kHIndex[a][b]];
                gb(a, b) = total[kGIndex[a][b]];
              }
          if (Gravity) {
            const Eigen::Vector3d v = gravity_kernel.from_integrals(total[kPn], Eigen::Vector3d(total[kPx], total[kPy], total[kPz]), n);
            for (int a = 0; a < 3; ++a) gsum[a][j] += v(a);
          }
        }
        if (HG)
          for (int b = 0; b < 3; ++b)
            for (int a = 0; a < 3; ++a) {
              H[(3 * c + b) * ld + 3 * (r0 + j) + a] = hb(a, b);
              G[(3 * c + b) * ld + 3 * (r0 + j) + a] = gb(a, b);
            }
      }
    }
    if (Gravity)
      for (Index j = 0; j < m; ++j)
        for (int a = 0; a < 3; ++a) g[3 * (r0 + j) + a] = gsum[a][j];
  }

  /// The Kelvin kernels at m points, written out (docs/design.md, kernels; Wang et al. 2007
  /// eqs. 2-3), with r = x_Q - p, r = |r|, r,i = r_i / r and n the element's unit normal:
  ///   U_ij = u_scale [(3 - 4 nu) delta_ij + r,i r,j] / r
  ///   T_ij = t_scale [dr/dn ((1 - 2 nu) delta_ij + 3 r,i r,j) - (1 - 2 nu)(r,i n_j - r,j n_i)] / r^2
  /// (t_scale = -1 / (8 pi (1 - nu)) carries the sign), times the weight w[j]; gravity takes
  /// w dr/dn and w r,i (P is linear in them: GravityKernel::from_integrals). Accumulate: add to
  /// out[][j] (far field: j runs over source points) or store (mid / near: j runs over the
  /// quadrature points, summed by the caller). Plain loops over arrays, no Eigen temporaries: the
  /// compiler vectorises them. inv is workspace (1/r).
  template <bool HG, bool Gravity, bool Accumulate>
  void kelvin_terms(Index m, const double* __restrict w, double nx, double ny, double nz, const double* __restrict rx,
                    const double* __restrict ry, const double* __restrict rz, double* __restrict inv,
                    double (*__restrict out)[kTileRows]) const {
    static_assert(kBatch == kTileRows, "kelvin_terms serves both with one row length");
    for (Index j = 0; j < m; ++j) inv[j] = rx[j] * rx[j] + ry[j] * ry[j] + rz[j] * rz[j];
    // 1/r through Eigen's packet sqrt: the plain loop would not vectorise while std::sqrt may set
    // errno (GCC without -fno-math-errno). Correctly rounded, as std::sqrt is.
    Eigen::Map<Eigen::ArrayXd> r2(inv, m);
    r2 = r2.sqrt().inverse();
    const KelvinConstants& k = constants_;
    const double c34 = k.three_minus_4nu, a = k.one_minus_2nu;
    auto put = [](double& o, double v) {
      if (Accumulate)
        o += v;
      else
        o = v;
    };
    for (Index j = 0; j < m; ++j) {
      const double dx = rx[j] * inv[j], dy = ry[j] * inv[j], dz = rz[j] * inv[j];  // r,i
      const double drdn = dx * nx + dy * ny + dz * nz;
      if (HG) {
        const double wu = w[j] * k.u_scale * inv[j];           // w u_scale / r
        const double wt = w[j] * k.t_scale * inv[j] * inv[j];  // w t_scale / r^2
        put(out[kGxx][j], wu * (dx * dx + c34));
        put(out[kGyy][j], wu * (dy * dy + c34));
        put(out[kGzz][j], wu * (dz * dz + c34));
        put(out[kGxy][j], wu * (dx * dy));
        put(out[kGxz][j], wu * (dx * dz));
        put(out[kGyz][j], wu * (dy * dz));
        const double q = 3.0 * drdn * wt, diag = a * drdn * wt, aw = a * wt;
        const double sxy = dx * ny - dy * nx, sxz = dx * nz - dz * nx, syz = dy * nz - dz * ny;  // r,i n_j - r,j n_i
        put(out[kHxx][j], q * dx * dx + diag);
        put(out[kHyy][j], q * dy * dy + diag);
        put(out[kHzz][j], q * dz * dz + diag);
        put(out[kHxy][j], q * dx * dy - aw * sxy);
        put(out[kHyx][j], q * dx * dy + aw * sxy);
        put(out[kHxz][j], q * dx * dz - aw * sxz);
        put(out[kHzx][j], q * dx * dz + aw * sxz);
        put(out[kHyz][j], q * dy * dz - aw * syz);
        put(out[kHzy][j], q * dy * dz + aw * syz);
      }
      if (Gravity) {
        put(out[kPn][j], w[j] * drdn);
        put(out[kPx][j], w[j] * dx);
        put(out[kPy][j], w[j] * dy);
        put(out[kPz][j], w[j] * dz);
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
