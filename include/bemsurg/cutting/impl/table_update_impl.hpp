// Implementation of bemsurg/cutting/table_update.hpp: the exact table after a cut step (docs/cutting.md,
// "The exact update"). The steps of the update, in the order it takes them, are the static members of
// detail::GreensTableParts, the one place outside presolution/ that reads and writes a table's parts.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "bemsurg/cutting/table_update.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/solvers/low_rank_updated_lu.hpp"
#include "bemsurg/solvers/structured_products.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

namespace detail {

/// What every column of a cut step's new table needs, computed once (CutTableStep; docs/cutting.md,
/// "First response"): the system's low-rank update, the step's LU solves and the base state.
struct CutStepState {
  std::shared_ptr<const GreensTable> keep_before;  // CutTableStep holds the table before; updated_table borrows it
  const GreensTable* before = nullptr;
  std::shared_ptr<const CutChange> keep_change;
  const CutChange* change = nullptr;
  std::shared_ptr<const TriangleMesh> after;
  MeshDelta delta;
  BoundaryConditions bc;             // after the step
  Eigen::MatrixXd X;                 // the change of the rows D
  std::vector<Index> region;         // after the step (the complete table's slots)
  std::vector<Index> fresh_cols;     // FreshColumns::table_cols
  std::vector<Index> fresh_sources;  // FreshColumns::sources
  Eigen::MatrixXd Z;                 // A'^-1 U_s
  Eigen::MatrixXd Us, Vs;            // the step's change of A* (SystemChange), kept from a first response on rows for the completion
  Eigen::MatrixXd Qs;                // V_s^T K^-1 from a first response on rows (explicit inverse), which the completion reuses
  // The fresh columns' right-hand sides, then the base state's b' last; solved column by column as
  // the tables asked for need them (fresh_solved), the base state always with U_s.
  Eigen::MatrixXd F;
  std::vector<char> fresh_solved;
  std::shared_ptr<const LowRankUpdatedLu> solver;  // null until the step's system solve
  Eigen::VectorXd rhs;
  GreensTableUpdateResult timing;               // integration and the system phase with its profile (the solves so far)
  std::shared_ptr<const GreensTable> complete;  // CutTableStep::complete's table, once made
  GreensTableUpdateResult complete_report;
  std::shared_ptr<SnapshotBufferPool> buffers;  // GreensTableUpdateOptions::buffers: where the new tables' columns come from
};

/// The cut update's access to a GreensTable's parts (a friend of GreensTable).
struct GreensTableParts {
  /// A cut step's change of A* in low-rank form: A*_after = blockdiag(A*_before, I) + U_s V_s^T
  /// with U_s = [E_D, Y], V_s = [X^T, E_D]; X (the change of the rows D) also corrects the table.
  struct SystemChange {
    Eigen::MatrixXd X, Us, Vs;
  };
  /// The new table's columns solved afresh (reshaped or joining region elements): column
  /// table_cols[i] comes from column sources[i] of the step's change (an index into D).
  struct FreshColumns {
    std::vector<Index> table_cols, sources;
  };

  static void check_update(const GreensTable& g, const TriangleMesh* after, const MeshDelta& delta, const CutChange& change) {
    if (!g.has_factorization())
      throw InvalidArgumentError("updated_table: this table kept no factorisation (it was read from a file); recompute it");
    if (!after) throw InvalidArgumentError("updated_table: no mesh");
    check_mesh_delta(delta, *g.mesh_, *after);
    if (change.n_before != g.num_dofs() || change.n_after != after->num_dofs())
      throw InvalidArgumentError("updated_table: the integrated change is for another step");
  }

  static SystemChange system_change(const CutChange& change, const BoundaryConditions& before, const BoundaryConditions& after) {
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

  static FreshColumns fresh_columns(const CutChange& change, const std::vector<Index>& region_after) {
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

  static Eigen::MatrixXd fresh_right_hand_sides(const GreensTable& g, const CutChange& change, const FreshColumns& fresh,
                                                const Eigen::VectorXd& rhs_after) {
    // Right-hand sides that ride along with U_s's LU solve (one multi-right-hand-side dgetrs, which
    // streams the n^2 factors once): F, the fresh table columns, and last the base state's b'.
    const Index n = g.num_dofs(), d = change.size(), R0 = static_cast<Index>(g.region_.size());
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

  static Eigen::MatrixXd correction_coefficients_transposed(const GreensTable& g, const CutChange& change, const Eigen::MatrixXd& X,
                                                            const std::vector<Index>* columns) {
    // The old columns: T' = T + A'^-1 (B' - A' T) with T extended by zero rows. The residual is
    // E_D (dB_D - X T) - Y T_D + F (F: whole columns of reshaped region elements outside rows D),
    // so T' = T + Z_E (dB_D - X T) - Z_Y T_D + A'^-1 F, Z = A'^-1 U_s: T' = T + [Z_E, -Z_Y] CT with
    // CT = [dB_D - X T; T_D] (2d x 3|R0|). T holds the reactions in the rows of supported dofs
    // (g.columns_ keeps zeros there, g.reactions_ the values, g.reaction_dofs_ ascending); the cutter never
    // reshapes a supported element, but a delta may; new dofs have zero rows in T.
    // Held transposed (3|R0| x 2d): X T is then computed as T^T X^T, a GEMM with a long output and
    // a short inner side, which OpenBLAS runs faster than the d-row product (measured by
    // benchmarks/bench_cut, the table phase of the exact update).
    // `columns` (ascending table columns of g, or null for all): the rows of CT^T for those only (a
    // first response's columns, CutTableStep).
    const Index n = g.num_dofs(), d = change.size(), R0 = static_cast<Index>(g.region_.size());
    const Index m = columns ? static_cast<Index>(columns->size()) : 3 * R0;
    auto column = [&](Index i) { return columns ? (*columns)[static_cast<std::size_t>(i)] : i; };
    Eigen::MatrixXd CTt(m, 2 * d);
    auto coef_t = CTt.leftCols(d);
    const Eigen::MatrixXd Xt = X.leftCols(n).transpose();
    Eigen::MatrixXd Xr_t(static_cast<Index>(g.reaction_dofs_.size()), d);
    for (std::size_t i = 0; i < g.reaction_dofs_.size(); ++i) Xr_t.row(static_cast<Index>(i)) = Xt.row(g.reaction_dofs_[i]);
    if (!columns) {
      coef_t.noalias() = -g.columns().transpose() * Xt;
      if (!g.reaction_dofs_.empty()) coef_t.noalias() -= g.reactions_.transpose() * Xr_t;
    } else {
      // The chosen columns where they lie: a copy of them would be a fresh n x m matrix (first touches).
      selected_columns_transposed_times(g.columns(), *columns, Xt, coef_t);
      coef_t = -coef_t;
      if (!g.reaction_dofs_.empty()) {
        Eigen::MatrixXd r(m, d);
        selected_columns_transposed_times(g.reactions_, *columns, Xr_t, r);
        coef_t -= r;
      }
    }
    for (Index i = 0; i < m; ++i) {
      const Index col = column(i), k = 3 * g.region_[static_cast<std::size_t>(col / 3)] + col % 3;
      coef_t.row(i) += change.rows_G.col(k).transpose();  // B'_D: the rows D of G' in column k
      if (k < n) coef_t.row(i).head(change.num_modified_dofs) -= change.old_rows_G.col(k).transpose();
    }
    for (Index j = 0; j < d; ++j) {  // T_D: a supported dof's row is its reactions
      const Index k = change.dofs[static_cast<std::size_t>(j)];
      const auto it = std::lower_bound(g.reaction_dofs_.begin(), g.reaction_dofs_.end(), k);
      const bool reaction = it != g.reaction_dofs_.end() && *it == k;
      for (Index i = 0; i < m; ++i)
        CTt(i, d + j) = k >= n ? 0.0 : reaction ? g.reactions_(it - g.reaction_dofs_.begin(), column(i)) : g.columns()(k, column(i));
    }
    return CTt;
  }

  /// Where the table phase's time went (GreensTableUpdateResult's profile).
  struct TableProfile {
    double snapshot_seconds = 0.0, gemm_seconds = 0.0, finish_seconds = 0.0;
  };

  /// Which region slots after the step a table keeps, and where: out_slot[s] is slot s's place in
  /// the output (-1: not kept); the kept old slots (s < |R0|) come first.
  struct SlotMap {
    std::vector<Index> out_slot;
    Index kept = 0, kept_old = 0;
  };
  static SlotMap slot_map(Index R0, Index R1, const std::vector<Index>* slots) {
    SlotMap m;
    m.out_slot.assign(static_cast<std::size_t>(R1), -1);
    for (Index s = 0; s < R1; ++s)
      if (!slots || std::binary_search(slots->begin(), slots->end(), s)) {
        m.out_slot[static_cast<std::size_t>(s)] = m.kept++;
        m.kept_old += s < R0 ? 1 : 0;
      }
    return m;
  }

  /// A new table's columns: rows x cols in a buffer of the step's pool (GreensTableUpdateOptions::buffers)
  /// or a fresh one.
  struct SnapshotColumns {
    std::shared_ptr<double> data;
    Index rows = 0, cols = 0;
    Eigen::Map<Eigen::MatrixXd> view() const { return {data.get(), rows, cols}; }
  };
  static SnapshotColumns snapshot_columns(const std::shared_ptr<SnapshotBufferPool>& buffers, Index rows, Index cols) {
    return {buffers ? buffers->acquire(rows * cols) : SnapshotBufferPool::fresh(rows * cols), rows, cols};
  }

  /// The new n' x 3|kept| table before the step's correction: the kept old columns with their
  /// reactions in the rows of supported dofs, zeros in the added rows and the new slots' columns.
  /// Snapshots are immutable, so each step writes a new one: into a buffer a table let go of when the
  /// step has a pool (its pages already touched), else into fresh memory advised for huge pages (whose
  /// first touch otherwise costs one page fault per 4 KiB). Reaction rows are gathered and scattered
  /// column by column: a row of a column-major matrix touches one page per entry. (Panels of columns
  /// updated in cache were measured slower: narrow GEMMs cost more than the passes over memory they save.)
  static SnapshotColumns old_columns_snapshot(const GreensTable& g, Index n1, const SlotMap& map,
                                              const std::shared_ptr<SnapshotBufferPool>& buffers) {
    const Index n = g.num_dofs(), R0 = static_cast<Index>(g.region_.size());
    const Index S0 = static_cast<Index>(g.reaction_dofs_.size());
    SnapshotColumns out = snapshot_columns(buffers, n1, 3 * map.kept);
    Eigen::Map<Eigen::MatrixXd> T = out.view();
    const Eigen::Map<const Eigen::MatrixXd> before = g.columns();
    for (Index s = 0; s < R0; ++s) {
      const Index o = map.out_slot[static_cast<std::size_t>(s)];
      if (o < 0) continue;
      T.block(0, 3 * o, n, 3) = before.middleCols(3 * s, 3);
      for (int a = 0; a < 3; ++a) {
        double* col = T.col(3 * o + a).data();
        const double* r = g.reactions_.col(3 * s + a).data();
        for (Index i = 0; i < S0; ++i) col[g.reaction_dofs_[static_cast<std::size_t>(i)]] = r[i];
      }
    }
    T.bottomLeftCorner(n1 - n, 3 * map.kept_old).setZero();
    T.rightCols(3 * (map.kept - map.kept_old)).setZero();
    return out;
  }

  /// The columns of the new table for the region slots `slots` (ascending indices into the region
  /// after the step; null: all of them, the complete table), in that order.
  static SnapshotColumns columns_after_cut(const GreensTable& g, const CutChange& change, const Eigen::MatrixXd& Z,
                                           const Eigen::MatrixXd& CTt, const Eigen::MatrixXd& F, const FreshColumns& fresh,
                                           Index region_after_size, const std::vector<Index>* slots,
                                           const std::shared_ptr<SnapshotBufferPool>& buffers, TableProfile* profile) {
    const auto t0 = SteadyClock::now();
    const Index n1 = change.n_after, d = change.size();
    const Index R0 = static_cast<Index>(g.region_.size());
    const SlotMap map = slot_map(R0, region_after_size, slots);
    const std::vector<Index>& out_slot = map.out_slot;
    const Index kept_old = map.kept_old;
    Eigen::MatrixXd ZZ(n1, 2 * d);
    ZZ.leftCols(d) = Z.leftCols(d);
    ZZ.rightCols(d) = -Z.rightCols(d);
    const SnapshotColumns out = old_columns_snapshot(g, n1, map, buffers);
    Eigen::Map<Eigen::MatrixXd> T = out.view();
    const auto t1 = SteadyClock::now();
    // One GEMM, both halves of Z: the kept old slots come first and in CTt's order.
    if (d > 0 && kept_old > 0) T.leftCols(3 * kept_old).noalias() += ZZ * CTt.transpose();
    const auto t2 = SteadyClock::now();
    for (std::size_t i = 0; i < fresh.table_cols.size(); ++i) {
      const Index col = fresh.table_cols[i], o = out_slot[static_cast<std::size_t>(col / 3)];
      if (o < 0) continue;
      if (col < 3 * R0)
        T.col(3 * o + col % 3) += F.col(static_cast<Index>(i));
      else
        T.col(3 * o + col % 3) = F.col(static_cast<Index>(i));
    }
    if (profile) {
      profile->snapshot_seconds += seconds_between(t0, t1);  // includes ZZ's copy, small beside the table's
      profile->gemm_seconds += seconds_between(t1, t2);
      profile->finish_seconds += seconds_since(t2);
    }
    return out;
  }

  /// The step's cheap parts, before any solve (CutTableStep's construction): the conditions, region,
  /// fresh columns and right-hand sides after the step.
  static void prepare(CutStepState& s, const GreensTableUpdateOptions& options) {
    const GreensTable& g = *s.before;
    const CutChange& change = *s.change;
    const auto t_change = SteadyClock::now();
    const BoundaryConditions before = g.base_conditions();
    s.bc = conditions_after_cut(before, s.delta);
    // Old elements keep their slots; added elements near the region join at the end.
    s.region = region_after_cut(g, *s.after, s.delta, options);
    const FreshColumns fresh = fresh_columns(change, s.region);
    s.fresh_cols = fresh.table_cols;
    s.fresh_sources = fresh.sources;
    s.fresh_solved.assign(fresh.table_cols.size(), 0);
    s.rhs = rhs_after_cut(change, g.rhs_, before, s.bc);
    s.F = fresh_right_hand_sides(g, change, fresh, s.rhs);
    s.timing.integration_seconds = change.integration_seconds;
    s.buffers = options.buffers;
    s.timing.change_seconds = seconds_since(t_change);
    s.timing.system_seconds = s.timing.change_seconds;
  }

  /// The step's change of A* in low-rank form (system_change), once per step.
  static void system_change_of(CutStepState& s) {
    if (s.Us.size() > 0) return;
    SystemChange system = system_change(*s.change, s.before->base_conditions(), s.bc);
    s.X = std::move(system.X);
    s.Us = std::move(system.Us);
    s.Vs = std::move(system.Vs);
  }

  /// The fresh columns that a table over `slots` (null: all) needs and that are not solved yet.
  static std::vector<Index> fresh_wanted(const CutStepState& s, const std::vector<Index>* slots) {
    std::vector<char> in(s.region.size(), slots ? 0 : 1);
    if (slots)
      for (Index slot : *slots) in[static_cast<std::size_t>(slot)] = 1;
    std::vector<Index> out;
    for (std::size_t i = 0; i < s.fresh_cols.size(); ++i)
      if (!s.fresh_solved[i] && in[static_cast<std::size_t>(s.fresh_cols[i] / 3)]) out.push_back(static_cast<Index>(i));
    return out;
  }

  /// Solves what a table over `slots` (null: all) needs (docs/cutting.md, "First response"). The first
  /// call takes the system's low-rank update: the LU solves of U_s, with the base state and the wanted
  /// fresh columns riding along (one multi-right-hand-side dgetrs streams the n^2 factors once); later
  /// calls solve only the fresh columns not solved yet. A first response therefore leaves the fresh
  /// columns outside its reach to the completion. Adds to `s.timing`.
  static void solve_for(CutStepState& s, const std::vector<Index>* slots) {
    const std::vector<Index> wanted = fresh_wanted(s, slots);
    if (s.solver && wanted.empty()) return;
    const auto t_system = SteadyClock::now();
    const Index n1 = s.change->n_after, nf = static_cast<Index>(s.fresh_cols.size()), k = static_cast<Index>(wanted.size());
    const bool first = !s.solver;
    Eigen::MatrixXd B(n1, k + (first ? 1 : 0));
    for (Index c = 0; c < k; ++c) B.col(c) = s.F.col(wanted[static_cast<std::size_t>(c)]);
    if (first) B.col(k) = s.F.col(nf);
    LowRankUpdateProfile lu_profile;
    double finish_s = 0.0;
    if (first) {
      system_change_of(s);
      s.timing.change_seconds += seconds_since(t_system);
      // Z: K^-1 U_s, then A*_after^-1 U_s (push-through: no further LU solve). A first response on
      // rows computed V_s^T K^-1 already: the new solver keeps it (Q) without a second GEMM.
      s.solver = std::make_shared<const LowRankUpdatedLu>(
          s.before->solver_->updated(n1, s.Us, s.Vs, &s.Z, &B, &lu_profile, s.Qs.size() > 0 ? &s.Qs : nullptr));
      const auto t_finish = SteadyClock::now();
      s.solver->finish_solve(s.Z);
      s.solver->finish_solve(B);  // K^-1 B came with U_s's solve
      finish_s = seconds_since(t_finish);
      s.Us.resize(0, 0);
      s.Vs.resize(0, 0);
      s.Qs.resize(0, 0);
      s.F.col(nf) = B.col(k);
    } else {
      const auto t_solve = SteadyClock::now();
      lu_profile.base_solve_columns = s.solver->apply_base_inverse(B);
      lu_profile.base_solve_seconds = seconds_since(t_solve);
      const auto t_finish = SteadyClock::now();
      s.solver->finish_solve(B);
      finish_s = seconds_since(t_finish);
    }
    for (Index c = 0; c < k; ++c) {
      const Index i = wanted[static_cast<std::size_t>(c)];
      s.F.col(i) = B.col(c);
      s.fresh_solved[static_cast<std::size_t>(i)] = 1;
    }
    GreensTableUpdateResult& r = s.timing;
    r.solve_seconds += lu_profile.base_solve_seconds;
    r.solve_columns += lu_profile.base_solve_columns;
    r.correction_seconds += lu_profile.correction_seconds + finish_s;
    r.rank = s.solver->rank();
    r.added_region_elements = static_cast<Index>(s.region.size() - s.before->region_.size());
    r.system_seconds += seconds_since(t_system);
  }

  /// The new table over the region slots `slots` (ascending; null: all, the complete table) from a
  /// prepared step. `report` gets the table phase and its profile (the system phase as prepared).
  /// A new table's parts that do not depend on its columns: version, mesh, key, conditions, and its
  /// region (the slots listed, or all), with `old_columns` the table columns of the step's table
  /// behind the kept old slots.
  static std::shared_ptr<GreensTable> table_shell(const CutStepState& s, const std::vector<Index>* slots, std::vector<Index>& old_columns) {
    const GreensTable& g = *s.before;
    auto out = std::make_shared<GreensTable>();
    GreensTable& t = *out;
    t.version_ = g.version_ + 1;
    t.mesh_ = s.after;
    t.solver_ = s.solver;
    t.quadrature_ = g.quadrature_;
    t.key_ = make_greens_table_key(*t.mesh_, g.key_.material, s.bc, g.key_.gravity, g.quadrature_);
    t.key_.backend = g.key_.backend;  // the update is exact on the base's backend: a compressed table stays one
    t.key_.compression_tolerance = g.key_.compression_tolerance;
    t.recompute_ = g.recompute_;
    t.base_kinds_ = s.bc.kinds();
    t.base_values_ = s.bc.values();
    t.rhs_ = s.rhs;
    old_columns.clear();
    if (slots) {
      t.region_.clear();
      for (Index slot : *slots) {
        t.region_.push_back(s.region[static_cast<std::size_t>(slot)]);
        if (slot < static_cast<Index>(g.region_.size()))
          for (int a = 0; a < 3; ++a) old_columns.push_back(3 * slot + a);
      }
    } else {
      t.region_ = s.region;
    }
    return out;
  }

  static std::shared_ptr<const GreensTable> table_of(CutStepState& s, const std::vector<Index>* slots, GreensTableUpdateResult* report) {
    solve_for(s, slots);
    const auto t_table = SteadyClock::now();
    const GreensTable& g = *s.before;
    const CutChange& change = *s.change;
    const Index nf = static_cast<Index>(s.fresh_cols.size());
    const FreshColumns fresh{s.fresh_cols, s.fresh_sources};
    std::vector<Index> old_columns;  // the table columns of g behind the kept old slots
    std::shared_ptr<GreensTable> out = table_shell(s, slots, old_columns);
    GreensTable& t = *out;
    t.set_base_state(s.bc, s.F.col(nf));
    TableProfile profile;
    const auto t_coefficients = SteadyClock::now();
    const Eigen::MatrixXd CTt = correction_coefficients_transposed(g, change, s.X, slots ? &old_columns : nullptr);
    profile.gemm_seconds = seconds_since(t_coefficients);  // X T is most of it
    SnapshotColumns T = columns_after_cut(g, change, s.Z, CTt, s.F, fresh, static_cast<Index>(s.region.size()), slots, s.buffers, &profile);
    const auto t_checks = SteadyClock::now();
    if (!T.view().allFinite()) throw SolverError("updated_table: the table has non-finite entries");
    t.set_columns_from_solution(std::move(T.data), T.rows, T.cols);
    t.build_slots();
    t.timings_ = g.timings_;
    profile.finish_seconds += seconds_since(t_checks);
    if (report) {
      *report = s.timing;
      report->table_seconds = seconds_since(t_table);
      report->total_seconds = report->system_seconds + report->table_seconds;  // integration: the caller's (updated_table adds it)
      report->snapshot_seconds = profile.snapshot_seconds;
      report->gemm_seconds = profile.gemm_seconds;
      report->finish_seconds = profile.finish_seconds;
      const double n0 = static_cast<double>(g.num_dofs()), n1 = static_cast<double>(change.n_after);
      const double d = static_cast<double>(change.size()), cols0 = static_cast<double>(slots ? old_columns.size() : 3 * g.region_.size());
      report->table_gemm_flops = d > 0 ? 2.0 * n0 * cols0 * d + 2.0 * n1 * 2.0 * d * cols0 : 0.0;
      report->snapshot_bytes = static_cast<std::size_t>(t.columns().size() + t.reactions_.size()) * sizeof(double);
    }
    return out;
  }

  /// A first response exact on the rows of the elements in `slots` (ascending region slots after the
  /// step, not all of them) and on their columns (docs/cutting.md, "First response on the rows within
  /// reach"): over an explicit inverse (LowRankUpdatedLu::has_rows) the rows R of Z = A'^-1 U_s, of
  /// the fresh columns and of the base state cost one GEMM (V_s^T A0^-1, which the completion keeps)
  /// and products with |R| or the rank rows; the table's rows R are then T_R + Z_R CT (+ the fresh
  /// columns' rows), and its other rows, and the base state's, are the table's before the step
  /// (stale_outside_region()). Nothing is solved for the completion but V_s^T A0^-1; the step's
  /// state is otherwise unchanged. `report`: the step's integration and change, this call's work as
  /// its system and table phases, and the rank after the step.
  static std::shared_ptr<const GreensTable> rows_table_of(CutStepState& s, const std::vector<Index>& slots,
                                                          GreensTableUpdateResult* report) {
    const auto t_system = SteadyClock::now();
    const GreensTable& g = *s.before;
    const CutChange& change = *s.change;
    system_change_of(s);
    const double change_s = seconds_since(t_system);
    const Index n = g.num_dofs(), n1 = change.n_after, d = change.size(), nf = static_cast<Index>(s.fresh_cols.size());
    const Index R0 = static_cast<Index>(g.region_.size());
    std::vector<Index> rows;  // the dofs of the kept elements, in slot order
    for (Index slot : slots)
      for (int a = 0; a < 3; ++a) rows.push_back(3 * s.region[static_cast<std::size_t>(slot)] + a);
    const SlotMap map = slot_map(R0, static_cast<Index>(s.region.size()), &slots);
    std::vector<Index> wanted;  // fresh columns of kept slots
    for (std::size_t i = 0; i < s.fresh_cols.size(); ++i)
      if (map.out_slot[static_cast<std::size_t>(s.fresh_cols[i] / 3)] >= 0) wanted.push_back(static_cast<Index>(i));
    const Index k = static_cast<Index>(wanted.size());
    Eigen::MatrixXd also(n1, k + 1);
    for (Index c = 0; c < k; ++c) also.col(c) = s.F.col(wanted[static_cast<std::size_t>(c)]);
    also.col(k) = s.F.col(nf);
    LowRankUpdateProfile lu_profile;
    LowRankUpdatedLu::RowsOfUpdate r = g.solver_->rows_after_update(n1, s.Us, s.Vs, rows, also, &lu_profile);
    s.Qs = std::move(r.Qs);
    const double system_s = seconds_since(t_system);

    const auto t_table = SteadyClock::now();
    std::vector<Index> old_columns;
    std::shared_ptr<GreensTable> out = table_shell(s, &slots, old_columns);
    GreensTable& t = *out;
    t.stale_outside_region_ = true;
    // The base state: the solution before the step (added dofs 0), exact on the rows R.
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n1);
    for (Index q = 0; q < n; ++q)
      x(q) = g.base_kinds_[static_cast<std::size_t>(q)] == BcKind::Traction ? g.base_displacement_(q) : g.base_traction_(q);
    for (std::size_t i = 0; i < rows.size(); ++i) x(rows[i]) = r.also_rows(static_cast<Index>(i), k);
    t.set_base_state(s.bc, x);
    TableProfile profile;
    const auto t_coefficients = SteadyClock::now();
    const Eigen::MatrixXd CTt = correction_coefficients_transposed(g, change, s.X, &old_columns);
    profile.gemm_seconds = seconds_since(t_coefficients);
    const auto t_snapshot = SteadyClock::now();
    SnapshotColumns snapshot = old_columns_snapshot(g, n1, map, s.buffers);
    Eigen::Map<Eigen::MatrixXd> T = snapshot.view();
    profile.snapshot_seconds = seconds_since(t_snapshot);
    const auto t_rows = SteadyClock::now();
    // The change of the rows R (the new slots' columns are zero in T, so adding sets them), made in
    // panels of columns and added column by column: one reused |R| x 64 panel stays in cache for
    // its scatter, where a whole |R| x 3|kept| change would be a fresh matrix (first touches), and a
    // row of the column-major table touches one cache line per entry.
    const Index m = static_cast<Index>(rows.size()), cols = T.cols(), width = 64;
    Eigen::MatrixXd ZZ(m, 2 * d);
    ZZ.leftCols(d) = r.z_rows.leftCols(d);
    ZZ.rightCols(d) = -r.z_rows.rightCols(d);
    std::vector<Index> fresh_of(static_cast<std::size_t>(cols), -1);  // a table column's fresh column in also_rows
    for (Index c = 0; c < k; ++c) {
      const Index col = s.fresh_cols[static_cast<std::size_t>(wanted[static_cast<std::size_t>(c)])];
      fresh_of[static_cast<std::size_t>(3 * map.out_slot[static_cast<std::size_t>(col / 3)] + col % 3)] = c;
    }
    Eigen::MatrixXd dR(m, std::min(width, cols));
    bool finite = true;
    for (Index c0 = 0; c0 < cols; c0 += width) {
      const Index w = std::min(width, cols - c0), old = std::max<Index>(0, std::min(w, 3 * map.kept_old - c0));
      auto panel = dR.leftCols(w);
      panel.setZero();
      if (d > 0 && old > 0) panel.leftCols(old).noalias() = ZZ * CTt.middleRows(c0, old).transpose();
      for (Index c = 0; c < w; ++c)
        if (fresh_of[static_cast<std::size_t>(c0 + c)] >= 0) panel.col(c) += r.also_rows.col(fresh_of[static_cast<std::size_t>(c0 + c)]);
      finite = finite && panel.allFinite();
      for (Index c = 0; c < w; ++c) {
        double* to = T.col(c0 + c).data();
        const double* from = panel.col(c).data();
        for (Index i = 0; i < m; ++i) to[rows[static_cast<std::size_t>(i)]] += from[i];
      }
    }
    profile.gemm_seconds += seconds_since(t_rows);
    const auto t_checks = SteadyClock::now();
    if (!finite || !x.allFinite()) throw SolverError("updated_table: the table has non-finite entries");
    t.set_columns_from_solution(std::move(snapshot.data), snapshot.rows, snapshot.cols);
    t.build_slots();
    t.timings_ = g.timings_;
    profile.finish_seconds = seconds_since(t_checks);
    if (report) {
      *report = s.timing;
      report->change_seconds += change_s;
      report->solve_seconds = lu_profile.base_solve_seconds;  // the GEMM V_s^T A0^-1
      report->solve_columns = 0;
      report->correction_seconds = lu_profile.correction_seconds;
      report->system_seconds += system_s;
      report->table_seconds = seconds_since(t_table);
      report->total_seconds = report->system_seconds + report->table_seconds;
      report->snapshot_seconds = profile.snapshot_seconds;
      report->gemm_seconds = profile.gemm_seconds;
      report->finish_seconds = profile.finish_seconds;
      report->table_gemm_flops = 2.0 * double(m) * double(old_columns.size()) * 2.0 * double(d);
      report->snapshot_bytes = static_cast<std::size_t>(t.columns().size() + t.reactions_.size()) * sizeof(double);
      report->rank = g.solver_->rank() + s.Us.cols();
      report->added_region_elements = static_cast<Index>(s.region.size() - g.region_.size());
    }
    return out;
  }

  static std::shared_ptr<const GreensTable> updated(const GreensTable& g, std::shared_ptr<const TriangleMesh> after, const MeshDelta& delta,
                                                    const CutChange& change, const GreensTableUpdateOptions& options,
                                                    GreensTableUpdateResult* report) {
    check_update(g, after.get(), delta, change);
    CutStepState s;
    s.before = &g;
    s.change = &change;
    s.after = std::move(after);
    s.delta = delta;
    prepare(s, options);
    return table_of(s, nullptr, report);
  }

  static std::shared_ptr<const GreensTable> updated(const GreensTable& g, std::shared_ptr<const TriangleMesh> after, const MeshDelta& delta,
                                                    const GreensTableUpdateOptions& options, GreensTableUpdateResult* report) {
    const auto t_start = SteadyClock::now();
    if (!g.has_factorization())
      throw InvalidArgumentError("updated_table: this table kept no factorisation (it was read from a file); recompute it");
    if (!after) throw InvalidArgumentError("updated_table: no mesh");
    const CutChange change = integrate_cut_change(*g.mesh_, *after, delta, g.material(), g.quadrature(), g.gravity());
    auto out = updated(g, std::move(after), delta, change, options, report);
    if (report) report->total_seconds = seconds_since(t_start);  // integration included
    return out;
  }

  static std::shared_ptr<const GreensTable> recomputed_after(const GreensTable& g, std::shared_ptr<const TriangleMesh> after,
                                                             const MeshDelta& delta, const GreensTableUpdateOptions& options) {
    if (!g.mesh_) throw InvalidArgumentError("recomputed_table_after: this table has no mesh (read from a file)");
    if (!after) throw InvalidArgumentError("recomputed_table_after: no mesh");
    check_mesh_delta(delta, *g.mesh_, *after);
    const std::vector<Index> region = region_after_cut(g, *after, delta, options);  // before `after` moves
    auto out = std::make_shared<GreensTable>(g.recomputed_on(std::move(after), conditions_after_cut(g.base_conditions(), delta), region));
    out->version_ = g.version_ + 1;
    return out;
  }
};

}  // namespace detail

}  // namespace bemsurg
