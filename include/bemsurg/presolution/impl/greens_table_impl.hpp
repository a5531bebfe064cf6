// Implementation of bemsurg/presolution/greens_table.hpp: the one-time precomputation of the
// compliance table (docs/design.md §6; Wang et al. 2007 §5.1). One LU of A*, then the base state and
// the region's unit-traction columns as one multi-right-hand-side back-substitution.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>

#include "bemsurg/assembly/cut_change.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/quadrature/quadrature_cost.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bemsurg/solvers/lu_in_place.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

BEMSURG_INLINE std::uint64_t fnv1a64(const void* data, std::size_t bytes, std::uint64_t seed) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = seed;
  for (std::size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

BEMSURG_INLINE std::uint64_t hash_mesh(const TriangleMesh& mesh) {
  std::uint64_t h = fnv1a64(mesh.vertices().data(), static_cast<std::size_t>(mesh.vertices().size()) * sizeof(double));
  return fnv1a64(mesh.faces().data(), static_cast<std::size_t>(mesh.faces().size()) * sizeof(int), h);
}

BEMSURG_INLINE std::uint64_t hash_conditions(const BoundaryConditions& bc) {
  std::vector<unsigned char> kinds(bc.kinds().size());
  for (std::size_t i = 0; i < kinds.size(); ++i) kinds[i] = static_cast<unsigned char>(bc.kinds()[i]);
  std::uint64_t h = fnv1a64(kinds.data(), kinds.size());
  return fnv1a64(bc.values().data(), static_cast<std::size_t>(bc.values().size()) * sizeof(double), h);
}

BEMSURG_INLINE std::uint64_t hash_quadrature(const QuadratureOptions& q) {
  const double v[6] = {q.far_ratio, q.mid_ratio, double(q.mid_order), double(q.max_depth), double(q.polar_order), q.polar_max_angle};
  return fnv1a64(v, sizeof(v));
}

BEMSURG_INLINE GreensTableKey make_greens_table_key(const TriangleMesh& mesh, const Material& material, const BoundaryConditions& base,
                                                    const Eigen::Vector3d& gravity, const QuadratureOptions& quadrature) {
  GreensTableKey key;
  key.mesh_hash = hash_mesh(mesh);
  key.conditions_hash = hash_conditions(base);
  key.quadrature_hash = hash_quadrature(quadrature);
  key.num_elements = mesh.num_elements();
  key.material = material;
  key.gravity = gravity;
  return key;
}

BEMSURG_INLINE BoundaryConditions supported_base_conditions(Index num_elements, const std::vector<Index>& supported) {
  BoundaryConditions bc(num_elements);
  for (Index e : supported) bc.prescribe_displacement(e, Eigen::Vector3d::Zero());
  return bc;
}

BEMSURG_INLINE double GreensTable::estimate_bytes(Index num_elements, Index region_elements) {
  const double n = 3.0 * double(num_elements);
  // Peak: A* (built in H's storage) and G during assembly, with the right-hand sides (region
  // columns and the base state) and O(n) vectors; G is released before the factorisation, whose
  // factors (kept, n^2) take A*'s storage. Pivots: one int per equation.
  return 8.0 * (2.0 * n * n + n * (3.0 * double(region_elements) + 1.0) + 8.0 * n) + 4.0 * n;
}

BEMSURG_INLINE double GreensTable::default_memory_limit_bytes() { return bemsurg::default_memory_limit_bytes(); }

BEMSURG_INLINE GreensTable GreensTable::compute(const TriangleMesh& mesh, const Material& material, const BoundaryConditions& base,
                                                const GreensTableOptions& options) {
  return compute(std::make_shared<const TriangleMesh>(mesh), material, base, options);
}

BEMSURG_INLINE GreensTable GreensTable::compute(std::shared_ptr<const TriangleMesh> mesh_ptr, const Material& material,
                                                const BoundaryConditions& base, const GreensTableOptions& options) {
  if (!mesh_ptr) throw InvalidArgumentError("GreensTable: no mesh");
  const TriangleMesh& mesh = *mesh_ptr;
  material.validate();
  if (mesh.num_elements() == 0) throw InvalidMeshError("GreensTable: the mesh has no elements");
  if (!options.gravity.allFinite()) throw BoundaryConditionError("GreensTable: gravity is not finite");
  base.require_supported(mesh);
  const Index E = mesh.num_elements();
  const Index n = 3 * E;

  GreensTable table;
  table.key_ = make_greens_table_key(mesh, material, base, options.gravity, options.quadrature);
  table.base_kinds_ = base.kinds();
  if (options.region.empty()) {
    for (Index e = 0; e < E; ++e)
      if (base.is_free(e)) table.region_.push_back(e);
  } else {
    std::vector<char> seen(static_cast<std::size_t>(E), 0);
    for (Index e : options.region) {
      if (e < 0 || e >= E)
        throw BoundaryConditionError("GreensTable: region element " + std::to_string(e) + " is out of range (the mesh has " +
                                     std::to_string(E) + " elements)");
      if (!base.is_free(e))
        throw BoundaryConditionError("GreensTable: region element " + std::to_string(e) +
                                     " is not free (a displacement is prescribed on it); tools act on free elements only");
      if (seen[static_cast<std::size_t>(e)]) continue;
      seen[static_cast<std::size_t>(e)] = 1;
      table.region_.push_back(e);
    }
  }
  if (table.region_.empty()) throw BoundaryConditionError("GreensTable: no free element for the table's region");
  const Index R = static_cast<Index>(table.region_.size());

  const double need = estimate_bytes(E, R);
  const double limit = options.memory_limit_bytes > 0.0 ? options.memory_limit_bytes : default_memory_limit_bytes();
  if (need > limit)
    throw ResourceError("GreensTable: the precomputation for " + std::to_string(E) + " elements (" + std::to_string(n) +
                        " equations) with a region of " + std::to_string(R) + " elements needs about " + format_gib(need) +
                        " (A* and G: " + format_gib(8.0 * 2.0 * double(n) * double(n)) +
                        "; table: " + format_gib(8.0 * double(n) * 3.0 * double(R)) + "), more than the limit of " + format_gib(limit) +
                        "; restrict the region to where tools act, or coarsen the mesh away from it");
  require_assembly_quadrature_within(mesh, options.quadrature, "GreensTable");  // docs/design.md §4, §10

  auto t0 = std::chrono::steady_clock::now();
  Eigen::MatrixXd A, B;
  {
    const InfluenceAssembler assembler(mesh, material, options.quadrature);
    Eigen::VectorXd gvec;  // H, G and gravity in one pass (zero without gravity)
    InfluenceMatrices hg = assembler.assemble(options.gravity, gvec);
    B.resize(n, 3 * R + 1);
    for (Index s = 0; s < R; ++s) B.middleCols(3 * s, 3) = hg.G.middleCols(3 * table.region_[static_cast<std::size_t>(s)], 3);
    B.col(3 * R) = build_right_hand_side(hg, base, gvec);
    A = build_system_matrix_in_place(hg, base);
  }
  table.timings_.assembly_seconds = seconds_since(t0);
  table.rhs_ = B.col(3 * R);
  auto lu = std::make_shared<const LuFactors>(LuFactors::factor(std::move(A), &table.timings_.factorization_seconds));
  t0 = SteadyClock::now();
  lu->solve_in_place(B);
  table.timings_.table_seconds = seconds_since(t0);
  table.solver_ = std::make_shared<const LowRankUpdatedLu>(lu);
  table.mesh_ = std::move(mesh_ptr);
  table.quadrature_ = options.quadrature;
  table.base_values_ = base.values();

  table.set_base_state(base, B.col(3 * R));
  B.conservativeResize(n, 3 * R);
  if (!B.allFinite()) throw SolverError("GreensTable: the table has non-finite entries");
  table.set_columns_from_solution(std::move(B));
  table.build_slots();
  return table;
}

BEMSURG_INLINE void GreensTable::set_base_state(const BoundaryConditions& bc, const Eigen::Ref<const Eigen::VectorXd>& x) {
  // Unknown x_k is u_k on traction dofs and t_k on displacement dofs: split into the two fields.
  const Index n = x.size();
  base_displacement_.resize(n);
  base_traction_.resize(n);
  for (Index k = 0; k < n; ++k) {
    const bool t_known = bc.kind(k) == BcKind::Traction;
    base_displacement_(k) = t_known ? x(k) : bc.value(k);
    base_traction_(k) = t_known ? bc.value(k) : x(k);
  }
}

BEMSURG_INLINE void GreensTable::set_columns_from_solution(Eigen::MatrixXd&& X) {
  // Rows of displacement-prescribed dofs: the solution there is a traction (kept as reactions_,
  // which updated() needs); the table holds the change of the prescribed displacement, zero.
  const Index n = X.rows();
  reaction_dofs_.clear();
  for (Index k = 0; k < n; ++k)
    if (base_kinds_[static_cast<std::size_t>(k)] == BcKind::Displacement) reaction_dofs_.push_back(k);
  const Index S = static_cast<Index>(reaction_dofs_.size());
  reactions_ = large_dense_matrix(S, X.cols());  // first touched below: advise huge pages
  for (Index c = 0; c < X.cols(); ++c)           // column by column: both matrices are column-major
    for (Index i = 0; i < S; ++i) {
      double& x = X(reaction_dofs_[static_cast<std::size_t>(i)], c);
      reactions_(i, c) = x;
      x = 0.0;
    }
  columns_.swap(X);
}

BEMSURG_INLINE BoundaryConditions GreensTable::base_conditions() const {
  BoundaryConditions bc(key_.num_elements);
  for (Index k = 0; k < num_dofs(); ++k)
    bc.prescribe_component(k / 3, static_cast<int>(k % 3), base_kinds_[static_cast<std::size_t>(k)],
                           base_values_.size() == num_dofs() ? base_values_(k) : 0.0);
  return bc;
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> GreensTable::updated(std::shared_ptr<const TriangleMesh> after, const MeshDelta& delta,
                                                                       const GreensTableUpdateOptions& options,
                                                                       GreensTableUpdateResult* report) const {
  const auto t_start = SteadyClock::now();
  if (!has_factorization())
    throw InvalidArgumentError("GreensTable::updated: this table kept no factorisation (it was read from a file); recompute it");
  if (!after) throw InvalidArgumentError("GreensTable::updated: no mesh");
  const CutChange change = integrate_cut_change(*mesh_, *after, delta, key_.material, quadrature_, key_.gravity);
  auto out = updated(std::move(after), delta, change, options, report);
  if (report) report->total_seconds = seconds_since(t_start);  // integration included
  return out;
}

BEMSURG_INLINE std::vector<Index> GreensTable::region_after_cut(const TriangleMesh& after, const MeshDelta& delta,
                                                                const GreensTableUpdateOptions& options) const {
  std::vector<Index> region = region_;
  Index free_count = 0;
  for (Index e = 0; e < key_.num_elements; ++e) free_count += is_free(e) ? 1 : 0;
  const bool all_free = free_count == static_cast<Index>(region_.size());
  double reach = options.join_distance;
  if (!(reach > 0.0)) {
    double largest = 0.0;
    for (Index e : delta.changed())
      if (e >= 0 && e < after.num_elements()) largest = std::max(largest, after.diameter(e));
    reach = 3.0 * largest;
  }
  for (Index e : delta.added) {  // new cut surface: traction-free, so a tool may act on it
    if (e < 0 || e >= after.num_elements()) continue;
    bool join = all_free;
    for (std::size_t s = 0; !join && s < region_.size(); ++s)
      join = (after.centroid(e) - after.centroid(region_[s])).squaredNorm() <= reach * reach;
    if (join) region.push_back(e);
  }
  return region;
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> GreensTable::recomputed_after(std::shared_ptr<const TriangleMesh> after,
                                                                                const MeshDelta& delta,
                                                                                const GreensTableUpdateOptions& options) const {
  if (!mesh_) throw InvalidArgumentError("GreensTable::recomputed_after: this table has no mesh (read from a file)");
  if (!after) throw InvalidArgumentError("GreensTable::recomputed_after: no mesh");
  check_mesh_delta(delta, *mesh_, *after);
  GreensTableOptions o;
  o.region = region_after_cut(*after, delta, options);
  o.gravity = key_.gravity;
  o.quadrature = quadrature_;
  auto out = std::make_shared<GreensTable>(compute(std::move(after), key_.material, conditions_after_cut(base_conditions(), delta), o));
  out->version_ = version_ + 1;
  return out;
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> GreensTable::refactored() const {
  if (!mesh_) throw InvalidArgumentError("GreensTable::refactored: this table has no mesh (read from a file)");
  GreensTableOptions o;
  o.region = region_;
  o.gravity = key_.gravity;
  o.quadrature = quadrature_;
  auto out = std::make_shared<GreensTable>(compute(mesh_, key_.material, base_conditions(), o));
  out->version_ = version_;
  return out;
}

BEMSURG_INLINE void GreensTable::check_update(const TriangleMesh* after, const MeshDelta& delta, const CutChange& change) const {
  if (!has_factorization())
    throw InvalidArgumentError("GreensTable::updated: this table kept no factorisation (it was read from a file); recompute it");
  if (!after) throw InvalidArgumentError("GreensTable::updated: no mesh");
  check_mesh_delta(delta, *mesh_, *after);
  if (change.n_before != num_dofs() || change.n_after != after->num_dofs())
    throw InvalidArgumentError("GreensTable::updated: the integrated change is for another step");
}

BEMSURG_INLINE GreensTable::SystemChange GreensTable::system_change(const CutChange& change, const BoundaryConditions& before,
                                                                    const BoundaryConditions& after) {
  // A*_after = blockdiag(A*_before, I) + U_s V_s^T with U_s = [E_D, Y], V_s = [X^T, E_D]:
  // X = the change of the rows D, Y = the change of the columns D outside the rows D.
  const Index n1 = change.n_after, d = change.size();
  SystemChange c;
  c.X = system_rows_after(change, after) - system_rows_before(change, before);
  Eigen::MatrixXd Y = system_columns_after(change, after) - system_columns_before(change, before);
  for (Index j = 0; j < d; ++j) Y.row(change.dofs[static_cast<std::size_t>(j)]).setZero();
  c.Us = Eigen::MatrixXd::Zero(n1, 2 * d);
  c.Vs = Eigen::MatrixXd::Zero(n1, 2 * d);
  for (Index j = 0; j < d; ++j) {
    c.Us(change.dofs[static_cast<std::size_t>(j)], j) = 1.0;
    c.Vs(change.dofs[static_cast<std::size_t>(j)], d + j) = 1.0;
  }
  c.Us.rightCols(d) = Y;
  c.Vs.leftCols(d) = c.X.transpose();
  return c;
}

BEMSURG_INLINE GreensTable::FreshColumns GreensTable::fresh_columns(const CutChange& change, const std::vector<Index>& region_after) {
  // Columns to solve afresh: F for reshaped region elements, G' columns for joining elements.
  const Index d = change.size(), R1 = static_cast<Index>(region_after.size());
  std::vector<Index> position(static_cast<std::size_t>(change.n_after), -1);  // dof -> index in D
  for (Index j = 0; j < d; ++j) position[static_cast<std::size_t>(change.dofs[static_cast<std::size_t>(j)])] = j;
  FreshColumns fresh;
  for (Index s = 0; s < R1; ++s)
    for (int a = 0; a < 3; ++a) {
      const Index k = 3 * region_after[static_cast<std::size_t>(s)] + a, p = position[static_cast<std::size_t>(k)];
      if (p >= 0) {
        fresh.table_cols.push_back(3 * s + a);
        fresh.sources.push_back(p);
      }
    }
  return fresh;
}

BEMSURG_INLINE Eigen::MatrixXd GreensTable::fresh_right_hand_sides(const CutChange& change, const FreshColumns& fresh,
                                                                   const Eigen::VectorXd& rhs_after) const {
  // Right-hand sides that ride along with U_s's LU solve (one multi-right-hand-side dgetrs, which
  // streams the n^2 factors once): F, the fresh table columns, and last the base state's b'.
  const Index n = num_dofs(), d = change.size(), R0 = static_cast<Index>(region_.size());
  const Index nf = static_cast<Index>(fresh.table_cols.size());
  Eigen::MatrixXd F = Eigen::MatrixXd::Zero(change.n_after, nf + 1);
  for (Index i = 0; i < nf; ++i) {
    const Index j = fresh.sources[static_cast<std::size_t>(i)];
    F.col(i) = change.cols_G.col(j);
    if (fresh.table_cols[static_cast<std::size_t>(i)] < 3 * R0) {  // an old column whose element was reshaped: its change only
      F.col(i).head(n) -= change.old_cols_G.col(j);
      for (Index q = 0; q < d; ++q) F(change.dofs[static_cast<std::size_t>(q)], i) = 0.0;  // in coef already
    }
  }
  F.col(nf) = rhs_after;
  return F;
}

BEMSURG_INLINE Eigen::MatrixXd GreensTable::correction_coefficients_transposed(const CutChange& change, const Eigen::MatrixXd& X) const {
  // The old columns: T' = T + A'^-1 (B' - A' T) with T extended by zero rows. The residual is
  // E_D (dB_D - X T) - Y T_D + F (F: whole columns of reshaped region elements outside rows D),
  // so T' = T + Z_E (dB_D - X T) - Z_Y T_D + A'^-1 F, Z = A'^-1 U_s: T' = T + [Z_E, -Z_Y] CT with
  // CT = [dB_D - X T; T_D] (2d x 3|R0|). T holds the reactions in the rows of supported dofs
  // (columns_ keeps zeros there, reactions_ the values, reaction_dofs_ ascending); the cutter never
  // reshapes a supported element, but a delta may; new dofs have zero rows in T.
  // Held transposed (3|R0| x 2d): X T is then computed as T^T X^T, a GEMM with a long output and
  // a short inner side, which OpenBLAS runs faster than the d-row product (measured by
  // benchmarks/bench_cut, the table phase of the exact update).
  const Index n = num_dofs(), d = change.size(), R0 = static_cast<Index>(region_.size());
  Eigen::MatrixXd CTt(3 * R0, 2 * d);
  auto coef_t = CTt.leftCols(d);
  const Eigen::MatrixXd Xt = X.leftCols(n).transpose();
  coef_t.noalias() = -columns_.transpose() * Xt;
  if (!reaction_dofs_.empty()) {
    Eigen::MatrixXd Xr_t(static_cast<Index>(reaction_dofs_.size()), d);
    for (std::size_t i = 0; i < reaction_dofs_.size(); ++i) Xr_t.row(static_cast<Index>(i)) = Xt.row(reaction_dofs_[i]);
    coef_t.noalias() -= reactions_.transpose() * Xr_t;
  }
  for (Index s = 0; s < R0; ++s)
    for (int a = 0; a < 3; ++a) {
      const Index k = 3 * region_[static_cast<std::size_t>(s)] + a, col = 3 * s + a;
      coef_t.row(col) += change.rows_G.col(k).transpose();  // B'_D: the rows D of G' in column k
      if (k < n) coef_t.row(col).head(change.num_modified_dofs) -= change.old_rows_G.col(k).transpose();
    }
  for (Index j = 0; j < d; ++j) {  // T_D: a supported dof's row is its reactions
    const Index k = change.dofs[static_cast<std::size_t>(j)];
    const auto it = std::lower_bound(reaction_dofs_.begin(), reaction_dofs_.end(), k);
    if (k >= n)
      CTt.col(d + j).setZero();
    else if (it != reaction_dofs_.end() && *it == k)
      CTt.col(d + j) = reactions_.row(it - reaction_dofs_.begin()).transpose();
    else
      CTt.col(d + j) = columns_.row(k).transpose();
  }
  return CTt;
}

BEMSURG_INLINE Eigen::MatrixXd GreensTable::columns_after_cut(const CutChange& change, const Eigen::MatrixXd& Z, const Eigen::MatrixXd& CTt,
                                                              const Eigen::MatrixXd& F, const FreshColumns& fresh,
                                                              Index region_after_size) const {
  const Index n = num_dofs(), n1 = change.n_after, d = change.size();
  const Index R0 = static_cast<Index>(region_.size()), R1 = region_after_size;
  Eigen::MatrixXd ZZ(n1, 2 * d);
  ZZ.leftCols(d) = Z.leftCols(d);
  ZZ.rightCols(d) = -Z.rightCols(d);
  // The new n' x 3|R1| table. A fresh matrix per step (snapshots are immutable): advise huge pages
  // before the first touch, which otherwise costs one page fault per 4 KiB. Reaction rows are
  // gathered and scattered column by column: a row of a column-major matrix touches one page per
  // entry. (Panels of columns updated in cache were measured slower: narrow GEMMs cost more than
  // the passes over memory they save.)
  const Index S0 = static_cast<Index>(reaction_dofs_.size());
  Eigen::MatrixXd T = large_dense_matrix(n1, 3 * R1);
  T.topLeftCorner(n, 3 * R0) = columns_;
  for (Index c = 0; c < 3 * R0; ++c) {
    double* col = T.col(c).data();
    const double* r = reactions_.col(c).data();
    for (Index i = 0; i < S0; ++i) col[reaction_dofs_[static_cast<std::size_t>(i)]] = r[i];
  }
  T.bottomLeftCorner(n1 - n, 3 * R0).setZero();
  T.rightCols(3 * (R1 - R0)).setZero();
  if (d > 0) T.leftCols(3 * R0).noalias() += ZZ * CTt.transpose();  // one GEMM: both halves of Z
  for (std::size_t i = 0; i < fresh.table_cols.size(); ++i) {
    if (fresh.table_cols[i] < 3 * R0)
      T.col(fresh.table_cols[i]) += F.col(static_cast<Index>(i));
    else
      T.col(fresh.table_cols[i]) = F.col(static_cast<Index>(i));
  }
  return T;
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> GreensTable::updated(std::shared_ptr<const TriangleMesh> after, const MeshDelta& delta,
                                                                       const CutChange& change, const GreensTableUpdateOptions& options,
                                                                       GreensTableUpdateResult* report) const {
  const auto t_start = SteadyClock::now();
  check_update(after.get(), delta, change);
  const BoundaryConditions before = base_conditions();
  const BoundaryConditions bc = conditions_after_cut(before, delta);
  const auto t_system = SteadyClock::now();
  const SystemChange system = system_change(change, before, bc);
  // The region after the step and the table's columns to solve afresh come first: their LU solve
  // rides along with U_s's (one multi-right-hand-side dgetrs). Old elements keep their slots;
  // added elements near the region join at the end.
  std::vector<Index> region1 = region_after_cut(*after, delta, options);
  const FreshColumns fresh = fresh_columns(change, region1);
  const Index nf = static_cast<Index>(fresh.table_cols.size());
  Eigen::VectorXd rhs1 = rhs_after_cut(change, rhs_, before, bc);
  Eigen::MatrixXd F = fresh_right_hand_sides(change, fresh, rhs1);
  Eigen::MatrixXd Z;  // K^-1 U_s, then A*_after^-1 U_s (push-through: no further LU solve)
  auto solver = std::make_shared<const LowRankUpdatedLu>(solver_->updated(change.n_after, system.Us, system.Vs, &Z, &F));
  solver->finish_solve(Z);
  solver->finish_solve(F);  // K^-1 F came with U_s's solve

  auto out = std::make_shared<GreensTable>();
  GreensTable& t = *out;
  t.version_ = version_ + 1;
  t.mesh_ = std::move(after);
  t.solver_ = solver;
  t.quadrature_ = quadrature_;
  t.key_ = make_greens_table_key(*t.mesh_, key_.material, bc, key_.gravity, quadrature_);
  t.base_kinds_ = bc.kinds();
  t.base_values_ = bc.values();
  t.rhs_ = std::move(rhs1);
  t.set_base_state(bc, F.col(nf));
  const auto t_table = SteadyClock::now();

  const Index R1 = static_cast<Index>(region1.size());
  t.region_ = std::move(region1);
  const Eigen::MatrixXd CTt = correction_coefficients_transposed(change, system.X);
  Eigen::MatrixXd T = columns_after_cut(change, Z, CTt, F, fresh, R1);
  if (!T.allFinite()) throw SolverError("GreensTable::updated: the table has non-finite entries");
  t.set_columns_from_solution(std::move(T));
  t.build_slots();
  t.timings_ = timings_;

  if (report) {
    report->integration_seconds = change.integration_seconds;
    report->system_seconds = seconds_between(t_system, t_table);
    report->table_seconds = seconds_since(t_table);
    report->total_seconds = seconds_since(t_start);
    report->rank = solver->rank();
    report->added_region_elements = R1 - static_cast<Index>(region_.size());
  }
  return out;
}

BEMSURG_INLINE GreensTable::GreensTable(GreensTableKey key, std::vector<Index> region, Eigen::VectorXd base_displacement,
                                        Eigen::VectorXd base_traction, std::vector<BcKind> base_kinds, Eigen::MatrixXd columns)
    : key_(key),
      region_(std::move(region)),
      base_displacement_(std::move(base_displacement)),
      base_traction_(std::move(base_traction)),
      base_kinds_(std::move(base_kinds)),
      columns_(std::move(columns)) {
  const Index n = 3 * key_.num_elements;
  if (base_displacement_.size() != n || base_traction_.size() != n || static_cast<Index>(base_kinds_.size()) != n || columns_.rows() != n ||
      columns_.cols() != 3 * static_cast<Index>(region_.size()))
    throw ResourceError("GreensTable: stored parts have inconsistent sizes");
  base_values_.resize(n);
  for (Index k = 0; k < n; ++k)
    base_values_(k) = base_kinds_[static_cast<std::size_t>(k)] == BcKind::Traction ? base_traction_(k) : base_displacement_(k);
  for (Index e : region_)
    if (e < 0 || e >= key_.num_elements) throw ResourceError("GreensTable: stored region element out of range");
  build_slots();
}

BEMSURG_INLINE void GreensTable::build_slots() {
  slot_.assign(static_cast<std::size_t>(key_.num_elements), -1);
  for (std::size_t s = 0; s < region_.size(); ++s) {
    if (slot_[static_cast<std::size_t>(region_[s])] != -1)
      throw ResourceError("GreensTable: region element " + std::to_string(region_[s]) + " is listed twice");
    slot_[static_cast<std::size_t>(region_[s])] = static_cast<Index>(s);
  }
}

BEMSURG_INLINE void GreensTable::displacement_field(const Index* elements, const double* tractions, Index count, Eigen::VectorXd& u) const {
  const Index n = num_dofs();
  if (u.size() != n) throw InvalidArgumentError("GreensTable::displacement_field: u must have " + std::to_string(n) + " entries");
  u = base_displacement_;
  // One thread, on purpose: the work streams contiguous columns (memory bound; its time is
  // benchmarks/bench_contact's "full field"), and an OpenMP team here would wait for cores that
  // the BLAS threads and the haptic thread may be spinning on (on 2 cores that was measured to
  // stall for far longer than the work itself).
  double* out = u.data();
  const Index ld = columns_.rows();
  for (Index c = 0; c < count; ++c) {
    const double* c0 = column_data(elements[c]);
    const double* c1 = c0 + ld;
    const double* c2 = c1 + ld;
    const double tx = tractions[3 * c], ty = tractions[3 * c + 1], tz = tractions[3 * c + 2];
    for (Index i = 0; i < n; ++i) out[i] += tx * c0[i] + ty * c1[i] + tz * c2[i];
  }
}

}  // namespace bemsurg
