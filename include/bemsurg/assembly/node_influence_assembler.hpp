// bemsurg/assembly/node_influence_assembler.hpp: the dense influence matrices of collocation BEM for
// an element type with several nodes per element (element_types.hpp; docs/elements.md). Node i
// (global index kNodes e + k) sits at x_i inside element e; node k' of element e' carries the
// unknowns u, t of the field N_k'(Q) u_(e',k'):
//   H(3i.., 3j..) = 1/2 I delta_ij + int_e' T(x_i, Q) N_k'(Q) dS,   j = kNodes e' + k'
//   G(3i.., 3j..) =                  int_e' U(x_i, Q) N_k'(Q) dS
//   g(3i..)       = sum_e int_e P(x_i, Q) dS
// so that H u = G t + g with 3 kNodes E unknowns of each kind. Templated on the element trait: the
// loops do not branch on the element type.
//
// Quadrature (docs/elements.md):
//   - far pairs (distance node-centroid / diameter >= far_ratio): Radon's 7 points, precomputed
//     per element with the shape values there, evaluated for 64 nodes at once (the constant
//     assembler's fast path, docs/assembly.md);
//   - mid and near pairs: ElementQuadrature's rules, i.e. adaptive subdivision of the element
//     (coordinate splitting, not more Gauss points) until each child is at 1.5 diameters;
//   - self pairs (the node lies inside the element, not at its centroid): the element is split at
//     the node into three sub-triangles (one per edge) and each is integrated in polar
//     coordinates about the node (ElementQuadrature::polar). On a flat element dr/dn = 0 and a
//     shape function is N(x + r d) = N(x) + r (grad N . d), so the radial integrals are exact:
//       int U N dS   = sum_theta w (U r)(d) [N(x) R + (grad N . d) R^2 / 2]
//       PV int T N dS = sum_theta w T_t(d) [N(x) ln R + (grad N . d) R]
//     (the principal value's ln(eps) term vanishes because T_t(d) integrates to zero around the
//     circle). The diagonal blocks are evaluated directly, with the free term 1/2 I N_k(x_i); the
//     rigid-body identity (rows of H sum to zero) stays a test of the whole quadrature.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "bemsurg/assembly/element_types.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/dense_storage.hpp"
#include "bemsurg/kernels/kelvin_constants.hpp"
#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"

namespace bemsurg {

namespace detail {

/// Indices of the weighted kernel terms one quadrature point contributes (G symmetric: 6, H: 9,
/// gravity: w dr/dn and w r,i).
enum NodeTerm : int {
  kNGxx,
  kNGyy,
  kNGzz,
  kNGxy,
  kNGxz,
  kNGyz,
  kNHxx,
  kNHyy,
  kNHzz,
  kNHxy,
  kNHyx,
  kNHxz,
  kNHzx,
  kNHyz,
  kNHzy,
  kNPn,
  kNPx,
  kNPy,
  kNPz,
  kNTerms
};
inline constexpr int kNodeTile = 64;
inline constexpr int kNodeG[3][3] = {{kNGxx, kNGxy, kNGxz}, {kNGxy, kNGyy, kNGyz}, {kNGxz, kNGyz, kNGzz}};
inline constexpr int kNodeH[3][3] = {{kNHxx, kNHxy, kNHxz}, {kNHyx, kNHyy, kNHyz}, {kNHzx, kNHzy, kNHzz}};

/// The Kelvin kernels at m points times their weights (docs/design.md §3; Wang et al. 2007 eqs. 2-3),
/// r = x_Q - p, written into out[term][j] (not accumulated):
///   U_ij = u_scale [(3 - 4 nu) delta_ij + r,i r,j] / r
///   T_ij = t_scale [dr/dn ((1 - 2 nu) delta_ij + 3 r,i r,j) - (1 - 2 nu)(r,i n_j - r,j n_i)] / r^2
/// Plain loops over arrays so that the compiler vectorises them.
inline void node_kernel_terms(const KelvinConstants& k, int m, const double* __restrict w, double nx, double ny, double nz,
                              const double* __restrict rx, const double* __restrict ry, const double* __restrict rz, double* __restrict inv,
                              double (*__restrict out)[kNodeTile]) {
  for (int j = 0; j < m; ++j) inv[j] = rx[j] * rx[j] + ry[j] * ry[j] + rz[j] * rz[j];
  Eigen::Map<Eigen::ArrayXd> r2(inv, m);
  r2 = r2.sqrt().inverse();
  const double c34 = k.three_minus_4nu, a = k.one_minus_2nu;
  for (int j = 0; j < m; ++j) {
    const double dx = rx[j] * inv[j], dy = ry[j] * inv[j], dz = rz[j] * inv[j];
    const double drdn = dx * nx + dy * ny + dz * nz;
    const double wu = w[j] * k.u_scale * inv[j], wt = w[j] * k.t_scale * inv[j] * inv[j];
    out[kNGxx][j] = wu * (dx * dx + c34);
    out[kNGyy][j] = wu * (dy * dy + c34);
    out[kNGzz][j] = wu * (dz * dz + c34);
    out[kNGxy][j] = wu * (dx * dy);
    out[kNGxz][j] = wu * (dx * dz);
    out[kNGyz][j] = wu * (dy * dz);
    const double q = 3.0 * drdn * wt, diag = a * drdn * wt, aw = a * wt;
    const double sxy = dx * ny - dy * nx, sxz = dx * nz - dz * nx, syz = dy * nz - dz * ny;
    out[kNHxx][j] = q * dx * dx + diag;
    out[kNHyy][j] = q * dy * dy + diag;
    out[kNHzz][j] = q * dz * dz + diag;
    out[kNHxy][j] = q * dx * dy - aw * sxy;
    out[kNHyx][j] = q * dx * dy + aw * sxy;
    out[kNHxz][j] = q * dx * dz - aw * sxz;
    out[kNHzx][j] = q * dx * dz + aw * sxz;
    out[kNHyz][j] = q * dy * dz - aw * syz;
    out[kNHzy][j] = q * dy * dz + aw * syz;
    out[kNPn][j] = w[j] * drdn;
    out[kNPx][j] = w[j] * dx;
    out[kNPy][j] = w[j] * dy;
    out[kNPz][j] = w[j] * dz;
  }
}

}  // namespace detail

/// Assembles H, G (3 kNodes E square) and the gravity vector of collocation BEM for the element
/// trait Element (element_types.hpp): far pairs by the blocked 7-point path, near pairs by
/// adaptive subdivision, self pairs by polar integration about the node (docs/elements.md).
/// \ingroup assembly
template <class Element>
class NodeInfluenceAssembler {
 public:
  static constexpr int kNodes = Element::kNodes;
  /// The blocks node i x element e: 3 x 3 kNodes (the columns of e's nodes side by side).
  using PairBlock = Eigen::Matrix<double, 3, 3 * kNodes>;

  /// Validates the material and the options; precomputes nodes, shape functions and far points.
  /// The mesh must outlive the assembler.
  NodeInfluenceAssembler(const TriangleMesh& mesh, const Material& material, const QuadratureOptions& options = {})
      : mesh_(mesh), kernel_(material.validated()), constants_(material), density_(material.density), quadrature_(options) {
    precompute();
  }

  Index num_nodes() const { return kNodes * mesh_.num_elements(); }
  /// Collocation node i = kNodes e + k (node k of element e).
  Eigen::Vector3d node(Index i) const { return nodes_.row(i).transpose(); }
  const RowMatrixX3d& nodes() const { return nodes_; }

  /// N_k(x) for a point x in the plane of element e.
  double shape(Index e, int k, const Eigen::Vector3d& x) const {
    const std::size_t s = std::size_t(e) * kNodes + std::size_t(k);
    return shape_at_centroid_[k] + grad_[s].dot(x - mesh_.centroid(e));
  }

  /// Both matrices without gravity.
  InfluenceMatrices assemble() const {
    Eigen::VectorXd unused;
    return assemble_impl(Eigen::Vector3d::Zero(), unused, false);
  }
  /// H, G and the gravity vector g (3 kNodes E; body force = density * gravity) in one pass.
  InfluenceMatrices assemble(const Eigen::Vector3d& gravity, Eigen::VectorXd& g) const { return assemble_impl(gravity, g, true); }

  /// One node x element pair block by the pair-by-pair rules (the reference the blocked path is
  /// tested against): self when node i belongs to e, else ElementQuadrature's regular rule.
  void node_element_pair(Index i, Index e, PairBlock& H, PairBlock& G) const {
    if (i / kNodes == e) return self_pair(i, H, G);
    double sums[kNodes][detail::kNTerms];
    regular_pair(node(i), e, sums);
    unpack(sums, H, G);
  }

  /// The rows of `R` nodes against the columns of `C` elements, pair by pair (node_element_pair:
  /// far pairs take the same 7 points as assemble(), so the entries agree with it): H and G are
  /// column-major 3R x 3 kNodes C (leading dimension 3R), node rows and element columns in list
  /// order. What a hierarchical matrix asks for a block, a row or a column at a time
  /// (elastostatics/hierarchical_solver.hpp); assemble() stays the fast path for whole matrices.
  void assemble_block(const Index* nodes, Index R, const Index* elements, Index C, double* H, double* G) const {
    const Index ld = 3 * R;
    PairBlock hb, gb;
    for (Index c = 0; c < C; ++c)
      for (Index r = 0; r < R; ++r) {
        node_element_pair(nodes[r], elements[c], hb, gb);
        for (int col = 0; col < 3 * kNodes; ++col)
          for (int a = 0; a < 3; ++a) {
            const Index at = (3 * kNodes * c + col) * ld + 3 * r + a;
            H[at] = hb(a, col);
            G[at] = gb(a, col);
          }
      }
  }

  /// The gravity vector g alone (3 kNodes E; body force = density * gravity), node by node over
  /// every element: far pairs by the 7 points' dr/dn and r,i sums, near pairs by
  /// ElementQuadrature, self pairs by the polar rule, as assemble(gravity, g) does without H and G.
  Eigen::VectorXd gravity_vector(const Eigen::Vector3d& gravity) const {
    const Index N = num_nodes();
    Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * N);
    const Eigen::Vector3d body_force = density_ * gravity;
    if (body_force.squaredNorm() == 0.0) return g;
    const GravityKernel gk(constants_, body_force);
#pragma omp parallel for schedule(dynamic, 16)
    for (Index i = 0; i < N; ++i) {
      const Eigen::Vector3d p = node(i);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      double sums[kNodes][detail::kNTerms];
      for (Index e = 0; e < mesh_.num_elements(); ++e) {
        const Eigen::Vector3d n = mesh_.normal(e);
        if (i / kNodes == e) {
          sum += self_gravity(p, e, gk);
        } else if ((p - mesh_.centroid(e)).squaredNorm() >= far2_[std::size_t(e)]) {
          const FarRule& f = far_[std::size_t(e)];
          double s_n = 0.0;
          Eigen::Vector3d s_d = Eigen::Vector3d::Zero();
          for (int q = 0; q < 7; ++q) {
            const Eigen::Vector3d r(f.x[0][q] - p.x(), f.x[1][q] - p.y(), f.x[2][q] - p.z());
            const Eigen::Vector3d d = r / r.norm();
            s_n += f.w[q] * d.dot(n);
            s_d += f.w[q] * d;
          }
          sum += gk.from_integrals(s_n, s_d, n);
        } else {
          regular_pair(p, e, sums);
          sum += gk.from_integrals(sums[0][detail::kNPn],
                                   Eigen::Vector3d(sums[0][detail::kNPx], sums[0][detail::kNPy], sums[0][detail::kNPz]), n);
        }
      }
      g.template segment<3>(3 * i) = sum;
    }
    return g;
  }

 private:
  InfluenceMatrices assemble_impl(const Eigen::Vector3d& gravity, Eigen::VectorXd& g, bool want_g) const {
    const Index n = 3 * num_nodes();
    InfluenceMatrices m{large_dense_matrix(n, n), large_dense_matrix(n, n)};
    const Eigen::Vector3d body_force = density_ * gravity;
    const bool with_gravity = want_g && body_force.squaredNorm() != 0.0;
    if (want_g) g.setZero(n);
    const Index tiles = (num_nodes() + detail::kNodeTile - 1) / detail::kNodeTile;
#pragma omp parallel for schedule(dynamic, 1)
    for (Index t = 0; t < tiles; ++t) {
      if (with_gravity)
        tile<true>(t, m.H.data(), m.G.data(), g.data(), body_force);
      else
        tile<false>(t, m.H.data(), m.G.data(), nullptr, body_force);
    }
    return m;
  }

  void precompute() {
    const Index E = mesh_.num_elements();
    const TriangleRule& rule = radon7_rule();
    const Eigen::Matrix<double, kNodes, 3> S = Element::shape_matrix();
    for (int k = 0; k < kNodes; ++k) shape_at_centroid_[k] = S.row(k).sum() / 3.0;
    nodes_.resize(kNodes * E, 3);
    grad_.resize(std::size_t(kNodes * E));
    far2_.resize(std::size_t(E));
    far_.resize(std::size_t(E));
    const double far_ratio = quadrature_.options().far_ratio;
    for (Index e = 0; e < E; ++e) {
      const auto c = mesh_.corners(e);
      const Eigen::Vector3d n = mesh_.normal(e);
      const double area = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]).norm();
      // grad lambda_c = n x (v_(c+2) - v_(c+1)) / (2 A): zero along the opposite edge, 1 at v_c.
      Eigen::Vector3d gl[3];
      for (int v = 0; v < 3; ++v) gl[v] = n.cross(c[(v + 2) % 3] - c[(v + 1) % 3]) / (2.0 * area);
      for (int k = 0; k < kNodes; ++k) {
        nodes_.row(kNodes * e + k) = collocation_node<Element>(c, k).transpose();
        grad_[std::size_t(kNodes * e + k)] = S(k, 0) * gl[0] + S(k, 1) * gl[1] + S(k, 2) * gl[2];
      }
      const double limit = far_ratio * element_diameter(c[0], c[1], c[2]);
      far2_[std::size_t(e)] = limit * limit * (1.0 + 1e-12);  // pairs at the threshold: regular_pair decides
      FarRule& f = far_[std::size_t(e)];
      for (int q = 0; q < 7; ++q) {
        const Eigen::Vector2d& xi = rule.points[std::size_t(q)];
        const Eigen::Vector3d lambda(1.0 - xi.x() - xi.y(), xi.x(), xi.y());
        const Eigen::Vector3d x = c[0] + xi.x() * (c[1] - c[0]) + xi.y() * (c[2] - c[0]);
        for (int d = 0; d < 3; ++d) f.x[d][q] = x(d);
        f.w[q] = area * rule.weights[std::size_t(q)];
        for (int k = 0; k < kNodes; ++k) f.shape[k][q] = S.row(k).dot(lambda);
      }
    }
  }

  /// The self pair: node i inside its own element, polar about the node (see the file comment).
  void self_pair(Index i, PairBlock& H, PairBlock& G) const {
    const Index e = i / kNodes;
    const Eigen::Vector3d p = node(i);
    const auto c = mesh_.corners(e);
    const Eigen::Vector3d n = mesh_.normal(e);
    double value[kNodes];
    for (int k = 0; k < kNodes; ++k) value[k] = shape(e, k, p);
    H.setZero();
    G.setZero();
    quadrature_.polar(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& d, double R, double w) {
      const Eigen::Matrix3d ur = kernel_.displacement_times_r(d), tt = kernel_.traction_tangential_part(d, n);
      const double lnR = std::log(R);
      for (int k = 0; k < kNodes; ++k) {
        const double slope = grad_[std::size_t(kNodes * e + k)].dot(d);
        G.template block<3, 3>(0, 3 * k).noalias() += (w * (value[k] * R + 0.5 * slope * R * R)) * ur;
        H.template block<3, 3>(0, 3 * k).noalias() += (w * (value[k] * lnR + slope * R)) * tt;
      }
    });
    for (int k = 0; k < kNodes; ++k) H.template block<3, 3>(0, 3 * k).diagonal().array() += 0.5 * value[k];
  }

  /// Gravity of element e at its own node p (dr/dn = 0): int_0^R P r dr = P(d) R^2 / 2.
  Eigen::Vector3d self_gravity(const Eigen::Vector3d& p, Index e, const GravityKernel& kernel) const {
    const auto c = mesh_.corners(e);
    const Eigen::Vector3d n = mesh_.normal(e);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    quadrature_.polar(p, c[0], c[1], c[2],
                      [&](const Eigen::Vector3d& d, double R, double w) { sum += (0.5 * w * R * R) * kernel.tangential_part(d, n); });
    return sum;
  }

  /// A pair that is not a self pair, by ElementQuadrature's regular rule (far, mid or adaptive
  /// near): sums[k][term] = sum over the points of N_k(Q) w K_term (gravity terms in sums[0] unweighted by N).
  void regular_pair(const Eigen::Vector3d& p, Index e, double (&sums)[kNodes][detail::kNTerms]) const {
    alignas(64) double rx[detail::kNodeTile], ry[detail::kNodeTile], rz[detail::kNodeTile], inv[detail::kNodeTile], w[detail::kNodeTile];
    alignas(64) double nshape[kNodes][detail::kNodeTile];
    alignas(64) double terms[detail::kNTerms][detail::kNodeTile];
    for (auto& row : sums)
      for (double& v : row) v = 0.0;
    const Eigen::Vector3d n = mesh_.normal(e), centre = mesh_.centroid(e);
    int count = 0;
    auto flush = [&] {
      detail::node_kernel_terms(constants_, count, w, n.x(), n.y(), n.z(), rx, ry, rz, inv, terms);
      // Points outermost: the kNodes x kNTerms sums are independent chains (an inner loop over the
      // points would make each sum one long chain of dependent additions).
      for (int j = 0; j < count; ++j) {
        for (int k = 0; k < kNodes; ++k)
          for (int a = 0; a < detail::kNPn; ++a) sums[k][a] += nshape[k][j] * terms[a][j];
        for (int a = detail::kNPn; a < detail::kNTerms; ++a) sums[0][a] += terms[a][j];
      }
      count = 0;
    };
    const auto c = mesh_.corners(e);
    quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double weight) {
      rx[count] = x.x() - p.x();
      ry[count] = x.y() - p.y();
      rz[count] = x.z() - p.z();
      w[count] = weight;
      for (int k = 0; k < kNodes; ++k) nshape[k][count] = shape_at_centroid_[k] + grad_[std::size_t(kNodes * e + k)].dot(x - centre);
      if (++count == detail::kNodeTile) flush();
    });
    if (count > 0) flush();
  }

  static void unpack(const double (&sums)[kNodes][detail::kNTerms], PairBlock& H, PairBlock& G) {
    for (int k = 0; k < kNodes; ++k)
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) {
          H(a, 3 * k + b) = sums[k][detail::kNodeH[a][b]];
          G(a, 3 * k + b) = sums[k][detail::kNodeG[a][b]];
        }
  }

  /// Rows of the nodes kNodeTile t .. kNodeTile t + m - 1 against every element.
  // long: the assembly's innermost loop; its far, near and gravity passes share the tile's stack arrays
  template <bool Gravity>
  void tile(Index t, double* H, double* G, double* g, const Eigen::Vector3d& body_force) const {
    using namespace detail;
    const Index r0 = t * kNodeTile, m = std::min<Index>(kNodeTile, num_nodes() - r0);
    const int mi = static_cast<int>(m);
    alignas(64) double px[kNodeTile], py[kNodeTile], pz[kNodeTile], rx[kNodeTile], ry[kNodeTile], rz[kNodeTile];
    alignas(64) double inv[kNodeTile], wq[kNodeTile], gsum[3][kNodeTile];
    alignas(64) double terms[kNTerms][kNodeTile];
    alignas(64) double acc[kNodes][kNPn][kNodeTile];
    alignas(64) double pacc[4][kNodeTile];
    unsigned char far[kNodeTile];
    for (int j = 0; j < mi; ++j) {
      px[j] = nodes_(r0 + j, 0);
      py[j] = nodes_(r0 + j, 1);
      pz[j] = nodes_(r0 + j, 2);
      gsum[0][j] = gsum[1][j] = gsum[2][j] = 0.0;
    }
    const GravityKernel gk(constants_, body_force);
    const Index ld = 3 * num_nodes();
    PairBlock hb, gb;
    double sums[kNodes][kNTerms];
    for (Index e = 0; e < mesh_.num_elements(); ++e) {
      const std::size_t s = std::size_t(e);
      const Eigen::Vector3d centre = mesh_.centroid(e), n = mesh_.normal(e);
      int nfar = 0;
      for (int j = 0; j < mi; ++j) {
        const double dx = px[j] - centre.x(), dy = py[j] - centre.y(), dz = pz[j] - centre.z();
        far[j] = (dx * dx + dy * dy + dz * dz >= far2_[s]) ? 1 : 0;
        nfar += far[j];
      }
      if (nfar > 0) {
        for (auto& block : acc)
          for (auto& row : block) std::fill(row, row + mi, 0.0);
        for (auto& row : pacc) std::fill(row, row + mi, 0.0);
        const FarRule& f = far_[s];
        for (int q = 0; q < 7; ++q) {
          for (int j = 0; j < mi; ++j) {
            rx[j] = f.x[0][q] - px[j];
            ry[j] = f.x[1][q] - py[j];
            rz[j] = f.x[2][q] - pz[j];
            wq[j] = f.w[q];
          }
          node_kernel_terms(constants_, mi, wq, n.x(), n.y(), n.z(), rx, ry, rz, inv, terms);
          for (int k = 0; k < kNodes; ++k) {
            const double nk = f.shape[k][q];
            for (int a = 0; a < kNPn; ++a)
              for (int j = 0; j < mi; ++j) acc[k][a][j] += nk * terms[a][j];
          }
          if (Gravity)
            for (int a = 0; a < 4; ++a)
              for (int j = 0; j < mi; ++j) pacc[a][j] += terms[kNPn + a][j];
        }
        for (int k = 0; k < kNodes; ++k)
          for (int b = 0; b < 3; ++b) {
            double* hcol = H + (3 * (kNodes * e + k) + b) * ld + 3 * r0;
            double* gcol = G + (3 * (kNodes * e + k) + b) * ld + 3 * r0;
            for (int j = 0; j < mi; ++j)
              for (int a = 0; a < 3; ++a) {
                hcol[3 * j + a] = acc[k][kNodeH[a][b]][j];
                gcol[3 * j + a] = acc[k][kNodeG[a][b]][j];
              }
          }
        if (Gravity)
          for (int j = 0; j < mi; ++j)
            if (far[j]) {
              const Eigen::Vector3d v = gk.from_integrals(pacc[0][j], Eigen::Vector3d(pacc[1][j], pacc[2][j], pacc[3][j]), n);
              for (int a = 0; a < 3; ++a) gsum[a][j] += v(a);
            }
      }
      if (nfar == mi) continue;
      for (int j = 0; j < mi; ++j) {
        if (far[j]) continue;
        const Index i = r0 + j;
        const Eigen::Vector3d p = node(i);
        Eigen::Vector3d v;
        if (i / kNodes == e) {
          self_pair(i, hb, gb);
          if (Gravity) v = self_gravity(p, e, gk);
        } else {
          regular_pair(p, e, sums);
          unpack(sums, hb, gb);
          if (Gravity) v = gk.from_integrals(sums[0][kNPn], Eigen::Vector3d(sums[0][kNPx], sums[0][kNPy], sums[0][kNPz]), n);
        }
        if (Gravity)
          for (int a = 0; a < 3; ++a) gsum[a][j] += v(a);
        for (int col = 0; col < 3 * kNodes; ++col)
          for (int a = 0; a < 3; ++a) {
            H[(3 * kNodes * e + col) * ld + 3 * i + a] = hb(a, col);
            G[(3 * kNodes * e + col) * ld + 3 * i + a] = gb(a, col);
          }
      }
    }
    if (Gravity)
      for (int j = 0; j < mi; ++j)
        for (int a = 0; a < 3; ++a) g[3 * (r0 + j) + a] = gsum[a][j];
  }

  /// Radon's 7 points of one element with their weights and the shape values there.
  struct FarRule {
    double x[3][7];
    double w[7];
    double shape[kNodes][7];
  };

  const TriangleMesh& mesh_;
  KelvinKernel kernel_;
  KelvinConstants constants_;
  double density_;
  ElementQuadrature quadrature_;
  RowMatrixX3d nodes_;
  double shape_at_centroid_[kNodes];
  std::vector<Eigen::Vector3d> grad_;  // in-plane gradient of N_k, kNodes per element
  std::vector<double> far2_;           // (far_ratio * diameter)^2, raised by 1e-12 relative
  std::vector<FarRule> far_;
};

/// The linear discontinuous element's assembler (docs/elements.md).
using LinearInfluenceAssembler = NodeInfluenceAssembler<LinearElement>;

}  // namespace bemsurg
