// Implementation of bemsurg/cutting/table_update.hpp: the exact table after a cut step (docs/cutting.md,
// "The exact update"). The steps of the update, in the order it takes them, are the static members of
// detail::GreensTableParts, the one place outside presolution/ that reads and writes a table's parts.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <memory>
#include <utility>
#include <vector>

#include "bemsurg/cutting/table_update.hpp"
#include "bemsurg/dense_storage.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/solvers/low_rank_updated_lu.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

namespace detail {

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

  static Eigen::MatrixXd correction_coefficients_transposed(const GreensTable& g, const CutChange& change, const Eigen::MatrixXd& X) {
    // The old columns: T' = T + A'^-1 (B' - A' T) with T extended by zero rows. The residual is
    // E_D (dB_D - X T) - Y T_D + F (F: whole columns of reshaped region elements outside rows D),
    // so T' = T + Z_E (dB_D - X T) - Z_Y T_D + A'^-1 F, Z = A'^-1 U_s: T' = T + [Z_E, -Z_Y] CT with
    // CT = [dB_D - X T; T_D] (2d x 3|R0|). T holds the reactions in the rows of supported dofs
    // (g.columns_ keeps zeros there, g.reactions_ the values, g.reaction_dofs_ ascending); the cutter never
    // reshapes a supported element, but a delta may; new dofs have zero rows in T.
    // Held transposed (3|R0| x 2d): X T is then computed as T^T X^T, a GEMM with a long output and
    // a short inner side, which OpenBLAS runs faster than the d-row product (measured by
    // benchmarks/bench_cut, the table phase of the exact update).
    const Index n = g.num_dofs(), d = change.size(), R0 = static_cast<Index>(g.region_.size());
    Eigen::MatrixXd CTt(3 * R0, 2 * d);
    auto coef_t = CTt.leftCols(d);
    const Eigen::MatrixXd Xt = X.leftCols(n).transpose();
    coef_t.noalias() = -g.columns_.transpose() * Xt;
    if (!g.reaction_dofs_.empty()) {
      Eigen::MatrixXd Xr_t(static_cast<Index>(g.reaction_dofs_.size()), d);
      for (std::size_t i = 0; i < g.reaction_dofs_.size(); ++i) Xr_t.row(static_cast<Index>(i)) = Xt.row(g.reaction_dofs_[i]);
      coef_t.noalias() -= g.reactions_.transpose() * Xr_t;
    }
    for (Index s = 0; s < R0; ++s)
      for (int a = 0; a < 3; ++a) {
        const Index k = 3 * g.region_[static_cast<std::size_t>(s)] + a, col = 3 * s + a;
        coef_t.row(col) += change.rows_G.col(k).transpose();  // B'_D: the rows D of G' in column k
        if (k < n) coef_t.row(col).head(change.num_modified_dofs) -= change.old_rows_G.col(k).transpose();
      }
    for (Index j = 0; j < d; ++j) {  // T_D: a supported dof's row is its reactions
      const Index k = change.dofs[static_cast<std::size_t>(j)];
      const auto it = std::lower_bound(g.reaction_dofs_.begin(), g.reaction_dofs_.end(), k);
      if (k >= n)
        CTt.col(d + j).setZero();
      else if (it != g.reaction_dofs_.end() && *it == k)
        CTt.col(d + j) = g.reactions_.row(it - g.reaction_dofs_.begin()).transpose();
      else
        CTt.col(d + j) = g.columns_.row(k).transpose();
    }
    return CTt;
  }

  static Eigen::MatrixXd columns_after_cut(const GreensTable& g, const CutChange& change, const Eigen::MatrixXd& Z,
                                           const Eigen::MatrixXd& CTt, const Eigen::MatrixXd& F, const FreshColumns& fresh,
                                           Index region_after_size) {
    const Index n = g.num_dofs(), n1 = change.n_after, d = change.size();
    const Index R0 = static_cast<Index>(g.region_.size()), R1 = region_after_size;
    Eigen::MatrixXd ZZ(n1, 2 * d);
    ZZ.leftCols(d) = Z.leftCols(d);
    ZZ.rightCols(d) = -Z.rightCols(d);
    // The new n' x 3|R1| table. A fresh matrix per step (snapshots are immutable): advise huge pages
    // before the first touch, which otherwise costs one page fault per 4 KiB. Reaction rows are
    // gathered and scattered column by column: a row of a column-major matrix touches one page per
    // entry. (Panels of columns updated in cache were measured slower: narrow GEMMs cost more than
    // the passes over memory they save.)
    const Index S0 = static_cast<Index>(g.reaction_dofs_.size());
    Eigen::MatrixXd T = large_dense_matrix(n1, 3 * R1);
    T.topLeftCorner(n, 3 * R0) = g.columns_;
    for (Index c = 0; c < 3 * R0; ++c) {
      double* col = T.col(c).data();
      const double* r = g.reactions_.col(c).data();
      for (Index i = 0; i < S0; ++i) col[g.reaction_dofs_[static_cast<std::size_t>(i)]] = r[i];
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

  static std::shared_ptr<const GreensTable> updated(const GreensTable& g, std::shared_ptr<const TriangleMesh> after, const MeshDelta& delta,
                                                    const CutChange& change, const GreensTableUpdateOptions& options,
                                                    GreensTableUpdateResult* report) {
    const auto t_start = SteadyClock::now();
    check_update(g, after.get(), delta, change);
    const BoundaryConditions before = g.base_conditions();
    const BoundaryConditions bc = conditions_after_cut(before, delta);
    const auto t_system = SteadyClock::now();
    const SystemChange system = system_change(change, before, bc);
    // The region after the step and the table's columns to solve afresh come first: their LU solve
    // rides along with U_s's (one multi-right-hand-side dgetrs). Old elements keep their slots;
    // added elements near the region join at the end.
    std::vector<Index> region1 = region_after_cut(g, *after, delta, options);
    const FreshColumns fresh = fresh_columns(change, region1);
    const Index nf = static_cast<Index>(fresh.table_cols.size());
    Eigen::VectorXd rhs1 = rhs_after_cut(change, g.rhs_, before, bc);
    Eigen::MatrixXd F = fresh_right_hand_sides(g, change, fresh, rhs1);
    Eigen::MatrixXd Z;  // K^-1 U_s, then A*_after^-1 U_s (push-through: no further LU solve)
    auto solver = std::make_shared<const LowRankUpdatedLu>(g.solver_->updated(change.n_after, system.Us, system.Vs, &Z, &F));
    solver->finish_solve(Z);
    solver->finish_solve(F);  // K^-1 F came with U_s's solve

    auto out = std::make_shared<GreensTable>();
    GreensTable& t = *out;
    t.version_ = g.version_ + 1;
    t.mesh_ = std::move(after);
    t.solver_ = solver;
    t.quadrature_ = g.quadrature_;
    t.key_ = make_greens_table_key(*t.mesh_, g.key_.material, bc, g.key_.gravity, g.quadrature_);
    t.base_kinds_ = bc.kinds();
    t.base_values_ = bc.values();
    t.rhs_ = std::move(rhs1);
    t.set_base_state(bc, F.col(nf));
    const auto t_table = SteadyClock::now();

    const Index R1 = static_cast<Index>(region1.size());
    t.region_ = std::move(region1);
    const Eigen::MatrixXd CTt = correction_coefficients_transposed(g, change, system.X);
    Eigen::MatrixXd T = columns_after_cut(g, change, Z, CTt, F, fresh, R1);
    if (!T.allFinite()) throw SolverError("updated_table: the table has non-finite entries");
    t.set_columns_from_solution(std::move(T));
    t.build_slots();
    t.timings_ = g.timings_;

    if (report) {
      report->integration_seconds = change.integration_seconds;
      report->system_seconds = seconds_between(t_system, t_table);
      report->table_seconds = seconds_since(t_table);
      report->total_seconds = seconds_since(t_start);
      report->rank = solver->rank();
      report->added_region_elements = R1 - static_cast<Index>(g.region_.size());
    }
    return out;
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
    auto out = std::make_shared<GreensTable>(GreensTable::compute_on(
        std::move(after), g.material(), conditions_after_cut(g.base_conditions(), delta), g.gravity(), g.quadrature(), region, 0.0));
    out->version_ = g.version_ + 1;
    return out;
  }
};

}  // namespace detail

BEMSURG_INLINE std::vector<Index> region_after_cut(const GreensTable& g, const TriangleMesh& after, const MeshDelta& delta,
                                                   const GreensTableUpdateOptions& options) {
  std::vector<Index> region = g.region();
  Index free_count = 0;
  for (Index e = 0; e < g.num_elements(); ++e) free_count += g.is_free(e) ? 1 : 0;
  const bool all_free = free_count == static_cast<Index>(g.region().size());
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
    for (std::size_t s = 0; !join && s < g.region().size(); ++s)
      join = (after.centroid(e) - after.centroid(g.region()[s])).squaredNorm() <= reach * reach;
    if (join) region.push_back(e);
  }
  return region;
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> updated_table(const GreensTable& table, std::shared_ptr<const TriangleMesh> after,
                                                                const MeshDelta& delta, const GreensTableUpdateOptions& options,
                                                                GreensTableUpdateResult* report) {
  return detail::GreensTableParts::updated(table, std::move(after), delta, options, report);
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> updated_table(const GreensTable& table, std::shared_ptr<const TriangleMesh> after,
                                                                const MeshDelta& delta, const CutChange& change,
                                                                const GreensTableUpdateOptions& options, GreensTableUpdateResult* report) {
  return detail::GreensTableParts::updated(table, std::move(after), delta, change, options, report);
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> recomputed_table_after(const GreensTable& table,
                                                                         std::shared_ptr<const TriangleMesh> after, const MeshDelta& delta,
                                                                         const GreensTableUpdateOptions& options) {
  return detail::GreensTableParts::recomputed_after(table, std::move(after), delta, options);
}

}  // namespace bemsurg
