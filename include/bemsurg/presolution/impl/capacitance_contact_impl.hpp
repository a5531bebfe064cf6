// Implementation of bemsurg/presolution/capacitance_contact.hpp: the capacitance matrix
// P = S^{-1} of James & Pai (1999) kept explicitly and bordered / reduced by Schur complements
// when the contact set changes (docs/design.md §6). All loops are written out over preallocated
// buffers so that nothing allocates after construction.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "bemsurg/error.hpp"

namespace bemsurg {

namespace detail {
// C(m x n) = alpha * A(m x k) B(k x n) + beta * C; column-major with leading dimensions.
BEMSURG_INLINE void gemm(Index m, Index n, Index k, double alpha, const double* A, Index lda, const double* B, Index ldb, double beta,
                         double* C, Index ldc) {
  for (Index j = 0; j < n; ++j) {
    double* c = C + j * ldc;
    if (beta == 0.0)
      for (Index i = 0; i < m; ++i) c[i] = 0.0;
    else if (beta != 1.0)
      for (Index i = 0; i < m; ++i) c[i] *= beta;
    for (Index p = 0; p < k; ++p) {
      const double f = alpha * B[p + j * ldb];
      if (f == 0.0) continue;
      const double* a = A + p * lda;
      for (Index i = 0; i < m; ++i) c[i] += f * a[i];
    }
  }
}
}  // namespace detail

BEMSURG_INLINE CapacitanceContact::CapacitanceContact(std::shared_ptr<const TriangleMesh> mesh_ptr,
                                                      std::shared_ptr<const GreensTable> table_ptr, Index capacity)
    : mesh_(std::move(mesh_ptr)), table_(std::move(table_ptr)), capacity_(capacity) {
  if (!mesh_ || !table_) throw ContactError("CapacitanceContact: the mesh or the Green's-function table is missing (null)");
  const TriangleMesh& mesh = *mesh_;
  const GreensTable& table = *table_;
  if (table.empty()) throw ContactError("CapacitanceContact: the Green's-function table is empty");
  if (mesh.num_elements() != table.num_elements() || hash_mesh(mesh) != table.key().mesh_hash)
    throw ContactError("CapacitanceContact: the mesh is not the one the table was computed for");
  if (capacity < 1) throw ContactError("CapacitanceContact: capacity must be at least 1 row");
  capacity_ = std::min<Index>(capacity, 3 * static_cast<Index>(table.region().size()));
  const auto cap = static_cast<std::size_t>(capacity_);
  rows_.resize(cap);
  rows_of_.assign(static_cast<std::size_t>(mesh.num_elements()), 0);
  P_.assign(cap * cap, 0.0);
  work_a_.assign(cap * cap, 0.0);
  work_b_.assign(cap * cap, 0.0);
  work_c_.assign(cap * cap, 0.0);
  work_d_.assign(cap * cap, 0.0);
  target_.assign(cap, 0.0);
  rhs_.assign(cap, 0.0);
  lambda_.assign(cap, 0.0);
  first_row_.assign(cap, 0);
  row_base_.assign(cap, 0.0);
  force_op_.assign(3 * cap, 0.0);
}

BEMSURG_INLINE void CapacitanceContact::clear() {
  for (Index a = 0; a < k_; ++a) rows_of_[static_cast<std::size_t>(rows_[static_cast<std::size_t>(a)].element)] = 0;
  k_ = 0;
  num_elements_ = 0;
  updates_ = 0;
  base_force_.setZero();
}

BEMSURG_INLINE double CapacitanceContact::s_entry(const ContactRow& a, const ContactRow& b) const {
  const Index ld = table_->columns().rows();
  const double* col = table_->column_data(b.element);
  const Index r = 3 * a.element;
  double s = 0.0;
  for (int j = 0; j < 3; ++j) {
    const double* c = col + j * ld + r;
    s += b.direction(j) * (a.direction(0) * c[0] + a.direction(1) * c[1] + a.direction(2) * c[2]);
  }
  return s;
}

BEMSURG_INLINE double CapacitanceContact::base_target(Index a) const {
  const ContactRow& r = rows_[static_cast<std::size_t>(a)];
  return r.direction.dot(table_->base_displacement().segment<3>(3 * r.element));
}

BEMSURG_INLINE bool CapacitanceContact::invert_into(double* M, double* inv, Index m) noexcept {
  const Index ld = capacity_;
  double scale = 0.0;
  for (Index j = 0; j < m; ++j)
    for (Index i = 0; i < m; ++i) scale = std::max(scale, std::abs(M[i + j * ld]));
  for (Index j = 0; j < m; ++j)
    for (Index i = 0; i < m; ++i) inv[i + j * ld] = i == j ? 1.0 : 0.0;
  for (Index c = 0; c < m; ++c) {
    Index p = c;
    for (Index r = c + 1; r < m; ++r)
      if (std::abs(M[r + c * ld]) > std::abs(M[p + c * ld])) p = r;
    const double pivot = M[p + c * ld];
    if (!(std::abs(pivot) > 1e-13 * scale) || !std::isfinite(pivot)) return false;
    if (p != c)
      for (Index j = 0; j < m; ++j) {
        std::swap(M[p + j * ld], M[c + j * ld]);
        std::swap(inv[p + j * ld], inv[c + j * ld]);
      }
    const double d = 1.0 / pivot;
    for (Index j = 0; j < m; ++j) {
      M[c + j * ld] *= d;
      inv[c + j * ld] *= d;
    }
    // Eliminate column c from every other row; column c itself last, since the others read it.
    for (Index j = 0; j < m; ++j) {
      if (j == c) continue;
      const double mc = M[c + j * ld], ic = inv[c + j * ld];
      if (mc == 0.0 && ic == 0.0) continue;
      for (Index r = 0; r < m; ++r) {
        if (r == c) continue;
        const double f = M[r + c * ld];
        M[r + j * ld] -= f * mc;
        inv[r + j * ld] -= f * ic;
      }
    }
    const double ic = inv[c + c * ld];
    for (Index r = 0; r < m; ++r) {
      if (r == c) continue;
      inv[r + c * ld] -= M[r + c * ld] * ic;
      M[r + c * ld] = 0.0;
    }
  }
  return true;
}

namespace detail {
[[noreturn]] BEMSURG_INLINE void throw_singular_contact() {
  throw SolverError(
      "CapacitanceContact: the contact rows are dependent (the same element and direction twice, or "
      "rows on supported elements): the small system G_CC is singular");
}
}  // namespace detail

BEMSURG_INLINE void CapacitanceContact::add_rows(const ContactRow* rows, Index m) {
  if (m <= 0) return;
  if (k_ + m > capacity_)
    throw CapacityError("CapacitanceContact: " + std::to_string(k_ + m) + " contact rows exceed the capacity of " +
                        std::to_string(capacity_) + " (construct with a larger capacity)");
  // Validate first: a throw must leave the set as it was.
  for (Index i = 0; i < m; ++i) {
    const Index e = rows[i].element;
    if (e < 0 || e >= mesh_->num_elements()) throw ContactError("CapacitanceContact: element " + std::to_string(e) + " is out of range");
    if (table_->region_slot(e) < 0)
      throw ContactError("CapacitanceContact: element " + std::to_string(e) +
                         " is outside the table's region (no column was precomputed for it)");
    if (rows_of_[static_cast<std::size_t>(e)] > 0)
      throw ContactError("CapacitanceContact: element " + std::to_string(e) + " is already in the contact set");
    for (Index j = 0; j < i; ++j)
      if (rows[j].element == e && std::abs(rows[j].direction.dot(rows[i].direction)) > 1.0 - 1e-12)
        throw ContactError("CapacitanceContact: element " + std::to_string(e) + " is given the same direction twice");
    const double len = rows[i].direction.norm();
    if (!(std::abs(len - 1.0) < 1e-9)) throw ContactError("CapacitanceContact: a row direction is not a unit vector");
  }
  if (!add_rows_unchecked(rows, m)) detail::throw_singular_contact();
}

BEMSURG_INLINE bool CapacitanceContact::try_add_rows(const ContactRow* rows, Index m) noexcept {
  if (m <= 0) return true;
  if (k_ + m > capacity_) return false;
  return add_rows_unchecked(rows, m);
}

BEMSURG_INLINE bool CapacitanceContact::add_rows_unchecked(const ContactRow* rows, Index m) noexcept {
  const Index k = k_, ld = capacity_;
  double* X = work_a_.data();  // P b      (k x m)
  double* Y = work_b_.data();  // c P      (m x k)
  double* Z = work_c_.data();  // Schur    (m x m)
  double* Zi = work_d_.data();
  // C = S(N, K) (m x k), c(i, p) = S(N_i, K_p), computed once into Zi's buffer: it is needed for
  // Y and Z only, both before the inversion overwrites the buffer with Zi.
  double* C = work_d_.data();
  for (Index p = 0; p < k; ++p)
    for (Index i = 0; i < m; ++i) C[i + p * ld] = s_entry(rows[i], rows_[static_cast<std::size_t>(p)]);
  // X = P b, b(p, j) = S(K_p, N_j)
  for (Index j = 0; j < m; ++j) {
    double* x = X + j * ld;
    for (Index i = 0; i < k; ++i) x[i] = 0.0;
    for (Index p = 0; p < k; ++p) {
      const double b = s_entry(rows_[static_cast<std::size_t>(p)], rows[j]);
      const double* pc = P_.data() + p * ld;
      for (Index i = 0; i < k; ++i) x[i] += b * pc[i];
    }
  }
  // Y = C P (m x k)
  detail::gemm(m, k, k, 1.0, C, ld, P_.data(), ld, 0.0, Y, ld);
  // Z = d - C X (m x m), d(i, j) = S(N_i, N_j)
  for (Index j = 0; j < m; ++j)
    for (Index i = 0; i < m; ++i) Z[i + j * ld] = s_entry(rows[i], rows[j]);
  detail::gemm(m, m, k, -1.0, C, ld, X, ld, 1.0, Z, ld);
  if (!invert_into(Z, Zi, m)) return false;  // overwrites C; nothing is committed yet
  // W = X Zi (k x m) into Z's buffer (Z no longer needed).
  double* W = Z;
  detail::gemm(k, m, m, 1.0, X, ld, Zi, ld, 0.0, W, ld);
  // P_KK += W Y;  P_KN = -W;  P_NK = -Zi Y;  P_NN = Zi.
  detail::gemm(k, k, m, 1.0, W, ld, Y, ld, 1.0, P_.data(), ld);
  for (Index j = 0; j < m; ++j)
    for (Index i = 0; i < k; ++i) P_[static_cast<std::size_t>(i + (k + j) * ld)] = -W[i + j * ld];
  detail::gemm(m, k, m, -1.0, Zi, ld, Y, ld, 0.0, P_.data() + k, ld);
  for (Index j = 0; j < m; ++j)
    for (Index i = 0; i < m; ++i) P_[static_cast<std::size_t>(k + i + (k + j) * ld)] = Zi[i + j * ld];
  for (Index i = 0; i < m; ++i) {
    rows_[static_cast<std::size_t>(k + i)] = rows[i];
    auto& count = rows_of_[static_cast<std::size_t>(rows[i].element)];
    first_row_[static_cast<std::size_t>(k + i)] = count == 0 ? 1 : 0;
    if (count == 0) ++num_elements_;
    ++count;
    target_[static_cast<std::size_t>(k + i)] = 0.0;
    lambda_[static_cast<std::size_t>(k + i)] = 0.0;
  }
  k_ = k + m;
  for (Index i = 0; i < m; ++i) {
    row_base_[static_cast<std::size_t>(k + i)] = base_target(k + i);
    target_[static_cast<std::size_t>(k + i)] = row_base_[static_cast<std::size_t>(k + i)];
  }
  ++updates_;
  update_force_operator();
  return true;
}

BEMSURG_INLINE void CapacitanceContact::add_bonded(Index element, int tag) {
  const ContactRow r[3] = {
      {element, Eigen::Vector3d::UnitX(), tag}, {element, Eigen::Vector3d::UnitY(), tag}, {element, Eigen::Vector3d::UnitZ(), tag}};
  add_rows(r, 3);
}

BEMSURG_INLINE void CapacitanceContact::add_normal(Index element, const Eigen::Vector3d& direction, int tag) {
  const double len = direction.allFinite() ? direction.stableNorm() : 0.0;  // stable for 1e-200 / 1e200
  if (!(len > 0.0) || !std::isfinite(len)) throw ContactError("CapacitanceContact: a contact normal must be a non-zero finite vector");
  const ContactRow r{element, direction / len, tag};
  add_rows(&r, 1);
}

BEMSURG_INLINE void CapacitanceContact::swap_rows(Index i, Index j) {
  if (i == j) return;
  const Index ld = capacity_;
  for (Index c = 0; c < k_; ++c) std::swap(P_[static_cast<std::size_t>(i + c * ld)], P_[static_cast<std::size_t>(j + c * ld)]);
  for (Index r = 0; r < k_; ++r) std::swap(P_[static_cast<std::size_t>(r + i * ld)], P_[static_cast<std::size_t>(r + j * ld)]);
  std::swap(rows_[static_cast<std::size_t>(i)], rows_[static_cast<std::size_t>(j)]);
  std::swap(target_[static_cast<std::size_t>(i)], target_[static_cast<std::size_t>(j)]);
  std::swap(lambda_[static_cast<std::size_t>(i)], lambda_[static_cast<std::size_t>(j)]);
  std::swap(first_row_[static_cast<std::size_t>(i)], first_row_[static_cast<std::size_t>(j)]);
  std::swap(row_base_[static_cast<std::size_t>(i)], row_base_[static_cast<std::size_t>(j)]);
}

BEMSURG_INLINE void CapacitanceContact::update_force_operator() {
  // K(c, b) = -sum_a area(e_a) w_a(c) P(a, b): O(k^2), once per structure change.
  const Index k = k_, ld = capacity_;
  const double* area = mesh_->areas().data();
  const double* tb = table_->base_traction().data();
  base_force_.setZero();
  for (Index b = 0; b < k; ++b) {
    const double* pc = P_.data() + b * ld;
    double kx = 0.0, ky = 0.0, kz = 0.0;
    for (Index a = 0; a < k; ++a) {
      const ContactRow& r = rows_[static_cast<std::size_t>(a)];
      const double f = area[r.element] * pc[a];
      kx -= f * r.direction(0);
      ky -= f * r.direction(1);
      kz -= f * r.direction(2);
    }
    force_op_[static_cast<std::size_t>(b)] = kx;
    force_op_[static_cast<std::size_t>(ld + b)] = ky;
    force_op_[static_cast<std::size_t>(2 * ld + b)] = kz;
    const ContactRow& r = rows_[static_cast<std::size_t>(b)];
    if (first_row_[static_cast<std::size_t>(b)])
      base_force_ -= area[r.element] * Eigen::Vector3d(tb[3 * r.element], tb[3 * r.element + 1], tb[3 * r.element + 2]);
  }
}

BEMSURG_INLINE Eigen::Vector3d CapacitanceContact::force_for_targets() const {
  const Index k = k_, ld = capacity_;
  const double* __restrict t = target_.data();
  const double* __restrict base = row_base_.data();
  const double* __restrict kx = force_op_.data();
  const double* __restrict ky = kx + ld;
  const double* __restrict kz = ky + ld;
  double fx = 0.0, fy = 0.0, fz = 0.0;
  for (Index b = 0; b < k; ++b) {
    const double r = t[b] - base[b];
    fx += kx[b] * r;
    fy += ky[b] * r;
    fz += kz[b] * r;
  }
  return base_force_ + Eigen::Vector3d(fx, fy, fz);
}

BEMSURG_INLINE void CapacitanceContact::remove_element(Index element) noexcept {
  if (element < 0 || element >= mesh_->num_elements() || rows_of_[static_cast<std::size_t>(element)] == 0) return;
  // Move the element's rows to the end (a symmetric permutation of S permutes P the same way).
  Index tail = k_;
  for (Index a = k_ - 1; a >= 0; --a)
    if (rows_[static_cast<std::size_t>(a)].element == element) swap_rows(a, --tail);
  const Index m = k_ - tail, k = tail, ld = capacity_;
  double* PJJ = work_c_.data();
  double* Qi = work_d_.data();
  for (Index j = 0; j < m; ++j)
    for (Index i = 0; i < m; ++i) PJJ[i + j * ld] = P_[static_cast<std::size_t>(k + i + (k + j) * ld)];
  if (!invert_into(PJJ, Qi, m)) {
    // P_JJ of a non-singular S cannot be singular; round-off after very many updates can make
    // it look so. Drop the rows and rebuild P from S (O(k^3)); if even that fails, empty the set
    // (the force falls to the base state's, and the owner sees the set change).
    rows_of_[static_cast<std::size_t>(element)] = 0;
    --num_elements_;
    k_ = k;
    if (!refactor_unchecked()) clear();
    return;
  }
  // W = P_KJ Qi (k x m); P_KK -= W P_JK.
  double* W = work_a_.data();
  detail::gemm(k, m, m, 1.0, P_.data() + k * ld, ld, Qi, ld, 0.0, W, ld);
  detail::gemm(k, k, m, -1.0, W, ld, P_.data() + k, ld, 1.0, P_.data(), ld);
  rows_of_[static_cast<std::size_t>(element)] = 0;
  --num_elements_;
  k_ = k;
  ++updates_;
  update_force_operator();
}

BEMSURG_INLINE void CapacitanceContact::refactor() {
  if (!refactor_unchecked()) detail::throw_singular_contact();
}

BEMSURG_INLINE bool CapacitanceContact::refactor_unchecked() noexcept {
  const Index k = k_, ld = capacity_;
  double* S = work_c_.data();
  for (Index j = 0; j < k; ++j)
    for (Index i = 0; i < k; ++i) S[i + j * ld] = s_entry(rows_[static_cast<std::size_t>(i)], rows_[static_cast<std::size_t>(j)]);
  double* inv = work_d_.data();
  if (!invert_into(S, inv, k)) return false;
  for (Index j = 0; j < k; ++j)
    for (Index i = 0; i < k; ++i) P_[static_cast<std::size_t>(i + j * ld)] = inv[i + j * ld];
  updates_ = 0;
  update_force_operator();
  return true;
}

BEMSURG_INLINE void CapacitanceContact::solve() {
  const Index k = k_, ld = capacity_;
  for (Index a = 0; a < k; ++a)
    rhs_[static_cast<std::size_t>(a)] = target_[static_cast<std::size_t>(a)] - row_base_[static_cast<std::size_t>(a)];
  // lambda = P rhs, four columns per sweep so lambda is loaded and stored a quarter as often.
  double* __restrict lam = lambda_.data();
  const double* __restrict r = rhs_.data();
  const double* P = P_.data();
  for (Index i = 0; i < k; ++i) lam[i] = 0.0;
  Index b = 0;
  for (; b + 4 <= k; b += 4) {
    const double f0 = r[b], f1 = r[b + 1], f2 = r[b + 2], f3 = r[b + 3];
    const double* __restrict p0 = P + b * ld;
    const double* __restrict p1 = p0 + ld;
    const double* __restrict p2 = p1 + ld;
    const double* __restrict p3 = p2 + ld;
    for (Index i = 0; i < k; ++i) lam[i] += f0 * p0[i] + f1 * p1[i] + f2 * p2[i] + f3 * p3[i];
  }
  for (; b < k; ++b) {
    const double f = r[b];
    const double* __restrict pc = P + b * ld;
    for (Index i = 0; i < k; ++i) lam[i] += f * pc[i];
  }
}

BEMSURG_INLINE Eigen::Vector3d CapacitanceContact::force_of_tag(int tag) const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  const double* tb = table_->base_traction().data();
  const double* area = mesh_->areas().data();
  for (Index a = 0; a < k_; ++a) {
    const ContactRow& r = rows_[static_cast<std::size_t>(a)];
    if (tag >= 0 && r.tag != tag) continue;
    const double ae = area[r.element];
    f -= (ae * lambda_[static_cast<std::size_t>(a)]) * r.direction;
    // The base traction of a contact element (zero on a traction-free surface) counts once.
    if (first_row_[static_cast<std::size_t>(a)]) {
      const double* t = tb + 3 * r.element;
      f(0) -= ae * t[0];
      f(1) -= ae * t[1];
      f(2) -= ae * t[2];
    }
  }
  return f;
}

BEMSURG_INLINE Eigen::Vector3d CapacitanceContact::traction(Index element) const {
  Eigen::Vector3d t = table_->base_traction().segment<3>(3 * element);
  for (Index a = 0; a < k_; ++a) {
    const ContactRow& r = rows_[static_cast<std::size_t>(a)];
    if (r.element == element) t += lambda_[static_cast<std::size_t>(a)] * r.direction;
  }
  return t;
}

BEMSURG_INLINE Eigen::Vector3d CapacitanceContact::displacement_of(Index element) const {
  Eigen::Vector3d u = table_->base_displacement().segment<3>(3 * element);
  const Index ld = table_->columns().rows();
  for (Index a = 0; a < k_; ++a) {
    const ContactRow& r = rows_[static_cast<std::size_t>(a)];
    const double* col = table_->column_data(r.element) + 3 * element;
    const double l = lambda_[static_cast<std::size_t>(a)];
    for (int j = 0; j < 3; ++j) {
      const double f = l * r.direction(j);
      if (f == 0.0) continue;
      const double* c = col + j * ld;
      u(0) += f * c[0];
      u(1) += f * c[1];
      u(2) += f * c[2];
    }
  }
  return u;
}

BEMSURG_INLINE Index CapacitanceContact::contact_tractions(Index* elements, double* tractions) const noexcept {
  Index count = 0;
  for (Index a = 0; a < k_; ++a) {
    const ContactRow& r = rows_[static_cast<std::size_t>(a)];
    Index slot = -1;
    for (Index c = count - 1; c >= 0 && c >= count - 3; --c)  // an element's rows are adjacent
      if (elements[c] == r.element) slot = c;
    if (slot < 0) {
      for (Index c = 0; c < count; ++c)
        if (elements[c] == r.element) slot = c;
    }
    if (slot < 0) {
      slot = count++;
      elements[slot] = r.element;
      tractions[3 * slot] = tractions[3 * slot + 1] = tractions[3 * slot + 2] = 0.0;
    }
    for (int j = 0; j < 3; ++j) tractions[3 * slot + j] += lambda_[static_cast<std::size_t>(a)] * r.direction(j);
  }
  return count;
}

BEMSURG_INLINE void CapacitanceContact::displacement_field(Eigen::VectorXd& u) const {
  // Local buffers: a const method that wrote member scratch would race with any other reader.
  std::vector<Index> elements(static_cast<std::size_t>(std::max<Index>(num_elements_, 1)));
  std::vector<double> tractions(3 * elements.size());
  const Index count = contact_tractions(elements.data(), tractions.data());
  table_->displacement_field(elements.data(), tractions.data(), count, u);
}

}  // namespace bemsurg
