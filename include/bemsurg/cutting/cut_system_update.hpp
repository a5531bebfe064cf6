// bemsurg/cutting/cut_system_update.hpp: the one entry point for cutting a body whose Green's table
// is in use (docs/cutting.md; docs/design.md §7, §9; Wang et al. 2007 §5.3 and Table 1). The command
// line (`bemsurg cut`), sessions (haptics/surface_cut_hook.hpp) and the viewer all cut through it, so
// they meet the same rules, stated here once:
//   locking   a cut never reshapes an element that is held or loaded in the base state
//             (cut_locked_elements): it keeps its condition, and a pressure would no longer be normal;
//   surface   SurfaceCutter opens and extends the groove and refuses what it cannot do cleanly,
//             narrow gaps included (cutting/gap_limit.hpp);
//   conditions old elements keep theirs, new cut surface is traction-free (conditions_after_cut);
//   region    the table's region keeps its elements and takes in the new walls near it
//             (region_after_cut, cutting/table_update.hpp);
//   refactor  past the refactor rank the table is factorised afresh (default_refactor_rank).
// The system and the table are updated step by step in one of three ways that must agree:
//   Exact     bordering by partitioning for the new rows and columns plus a low-rank (Woodbury)
//             correction for the reshaped elements, on top of the LU kept from the precompute
//             (GreensTable::updated, solvers/low_rank_updated_lu.hpp);
//   Gmres, BiCgStab, BiCg
//             the new system re-solved iteratively, warm-started from the previous solution with
//             the scene's preconditioner (the paper's Table 1); the explicit A* is kept for it and
//             updated by the changed rows and columns only;
//   Refactor  the reference: full re-assembly and a new factorisation.
// The table is updated exactly after every step in every mode (Refactor: recomputed), so prodding
// anywhere after a cut feels it. When the accumulated correction rank passes refactor_rank, the
// table is refactorised from scratch on a background thread and swapped in atomically if no cut
// happened meanwhile: readers (the force path) call table(), an atomic load of an immutable
// snapshot, and never wait for, or see, a half-updated table.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/cutting/cut_change.hpp"
#include "bemsurg/cutting/surface_cutter.hpp"
#include "bemsurg/cutting/table_update.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/snapshot_buffers.hpp"
#include "bemsurg/solvers/linear_solve.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

/// How CutSystemUpdate brings the system and the table to a cut mesh (see the top of this header).
/// \ingroup cutting
enum class CutUpdateMethod { Exact, Gmres, BiCgStab, BiCg, Refactor };

/// The default refactor rank, max(96, n / 10): past it the table is refactorised. Not an accuracy
/// limit: bench_stability's updates study (docs/stability.md (f)) finds the updated solution
/// within round-off (about 1e-14) of a fresh LU of the same system far past it, for random
/// splits, cuts and the same elements reshaped over and over; it bounds the cost an update adds to
/// every solve (4 n r flops on top of the LU's 2 n^2) and the memory of V and W (2 n r doubles).
inline Index default_refactor_rank(Index n) { return std::max<Index>(96, n / 10); }

/// Names as `bemsurg cut --update` and report.json write them.
inline const char* to_string(CutUpdateMethod m) {
  switch (m) {
    case CutUpdateMethod::Exact: return "exact";
    case CutUpdateMethod::Gmres: return "gmres";
    case CutUpdateMethod::BiCgStab: return "bicgstab";
    case CutUpdateMethod::BiCg: return "bicg";
    case CutUpdateMethod::Refactor: return "refactor";
  }
  return "unknown";
}
inline CutUpdateMethod parse_cut_update_method(const std::string& name) {
  for (CutUpdateMethod m :
       {CutUpdateMethod::Exact, CutUpdateMethod::Gmres, CutUpdateMethod::BiCgStab, CutUpdateMethod::BiCg, CutUpdateMethod::Refactor})
    if (name == to_string(m)) return m;
  throw InvalidArgumentError("unknown update method '" + name + "' (expected exact, gmres, bicgstab, bicg or refactor)");
}

/// The locking rule of every cut (docs/design.md §7): one entry per element of the table's mesh, non-zero
/// for an element that is not free (some displacement prescribed) or that carries a non-zero prescribed
/// value (a load) in the table's base state. A cut never reshapes such an element.
inline std::vector<char> cut_locked_elements(const GreensTable& table) {
  const BoundaryConditions bc = table.base_conditions();
  std::vector<char> locked(static_cast<std::size_t>(table.num_elements()), 0);
  for (Index e = 0; e < table.num_elements(); ++e) {
    const bool loaded = bc.value(3 * e) != 0.0 || bc.value(3 * e + 1) != 0.0 || bc.value(3 * e + 2) != 0.0;
    locked[static_cast<std::size_t>(e)] = (!bc.is_free(e) || loaded) ? 1 : 0;
  }
  return locked;
}

/// Settings of CutSystemUpdate: the Krylov settings of the iterative modes, when and where the table is
/// refactorised, whether the explicit A* is built at once, and the table's update options.
/// \ingroup cutting
struct CutSystemOptions {
  /// Krylov settings of the iterative modes (method set per step). Full GMRES, block-Jacobi.
  LinearSolverOptions krylov = [] {
    LinearSolverOptions s;
    s.tolerance = 1e-12;
    s.max_iterations = 2000;
    return s;
  }();
  /// Refactorise when the accumulated correction rank exceeds this; 0 = default_refactor_rank(n) = max(96, n / 10).
  Index refactor_rank = 0;
  /// Refactorise on a background thread (else at once, inside apply()).
  bool background_refactor = true;
  /// Build the explicit A* at once (the iterative modes need it; built on first use otherwise).
  bool keep_matrix = false;
  /// The table updates' options. Without `table.buffers` the update makes its own pool, so that each
  /// step's tables reuse the storage of the tables the program let go of (docs/cutting.md, "Snapshot storage").
  GreensTableUpdateOptions table;
};

/// What one CutSystemUpdate step did: whether it was accepted (else why not), the method, Krylov iterations and
/// residual, seconds per phase, the accumulated correction rank, and whether a refactorisation was started.
/// \ingroup cutting
struct CutStepResult {
  bool accepted = true;  // false: refused (by the cutter or a singular cut system), nothing changed
  std::string reason;    // why a step was refused
  MeshDelta delta;       // what the accepted step changed
  CutUpdateMethod method = CutUpdateMethod::Exact;
  int iterations = 0;                // Krylov iterations (0 for exact and refactor)
  double relative_residual = 0.0;    // Krylov: ||b - A x|| / ||b||
  double integration_seconds = 0.0;  // rows and columns of the changed elements (refactor: full assembly)
  double system_seconds = 0.0;       // the system's update and solve (Krylov: the iterations)
  double table_seconds = 0.0;        // the table's update (refactor: factorisation and table)
  double total_seconds = 0.0;
  Index rank = 0;                 // accumulated correction rank after the step
  bool refactor_started = false;  // a refactorisation was started (or done, if not in background)
};
/// Deprecated name (before 0.2), kept one minor version: use CutStepResult.
using CutStepReport [[deprecated("renamed to CutStepResult in bemsurg 0.2")]] = CutStepResult;

/// The surface of a cut step before the system follows it (CutSystemUpdate::cut_surface): the new mesh and its
/// delta, or a refusal with its reason.
/// \ingroup cutting
struct CutSurfaceStep {
  bool accepted = false;
  std::string reason;
  std::shared_ptr<const TriangleMesh> mesh;  // the cut surface (null when refused)
  MeshDelta delta;
};

/// The one entry point for cutting a body in use: the surface step under the cut rules, then the BEM system and the
/// Green's table updated (exactly, iteratively or by refactorisation; docs/cutting.md); readers get an immutable table
/// snapshot and never see a half-updated one.
/// \ingroup cutting
class CutSystemUpdate {
 public:
  /// `table` must have been computed (has_factorization()): its base state is the system solved.
  explicit CutSystemUpdate(std::shared_ptr<const GreensTable> table, CutSystemOptions options = {})
      : options_(std::move(options)), table_(std::move(table)) {
    if (!table_ || !table_->has_factorization())
      throw InvalidArgumentError("CutSystemUpdate: the table must be computed (with its factorisation), not read from a file");
    x_ = solution_of(*table_);
    // Three buffers: a step's two tables, and the next step's first response while the loop still
    // blends from this step's (docs/cutting.md, "Snapshot storage").
    if (!options_.table.buffers) options_.table.buffers = std::make_shared<SnapshotBufferPool>(3);
    if (options_.keep_matrix) build_matrix();
  }
  CutSystemUpdate(const CutSystemUpdate&) = delete;
  CutSystemUpdate& operator=(const CutSystemUpdate&) = delete;
  ~CutSystemUpdate() { wait_for_refactor(); }

  /// The current table: an immutable snapshot, safe to read from any thread while cuts go on.
  std::shared_ptr<const GreensTable> table() const { return std::atomic_load(&table_); }
  /// The unknowns x of the current system A* x = b (the method of the last step's solution).
  const Eigen::VectorXd& solution() const { return x_; }
  /// Displacement and traction of every element of the current mesh.
  BoundarySolution boundary_solution() const { return recover_boundary_solution(table()->base_conditions(), x_); }
  /// The explicit A* of the current system (kept for the iterative modes, or with keep_matrix;
  /// empty otherwise): what a fresh factorisation of the current system would factorise.
  const Eigen::MatrixXd& matrix() const { return A_; }
  /// Touches now the storage of the next steps' tables (three buffers of the current table's size, with
  /// the pool's room to spare: SnapshotBufferPool::reserve), for a caller that knows cuts will come
  /// and has time before them (a session before its clock starts): the first steps then cost what
  /// later ones do, whose tables reuse the storage of the tables let go of (docs/cutting.md, "Snapshot storage").
  void reserve_snapshot_buffers() { options_.table.buffers->reserve(table()->columns().size(), 3); }
  /// What the steps' table storage has done so far: buffers allocated, reused and held now.
  SnapshotBufferPool::Counts snapshot_buffer_counts() const { return options_.table.buffers->counts(); }
  /// True when a background refactorisation is running.
  bool refactor_running() const { return busy_.load(); }
  /// Blocks until a running background refactorisation has finished (and published, if still current).
  void wait_for_refactor() {
    if (worker_.joinable()) worker_.join();
  }

  /// Starts a new cut with `options` (gap width, the cutter's limits): the next step opens a new groove on
  /// the current mesh.
  void begin_cut(const CutOptions& options = {}) {
    cutter_.reset();
    pending_before_.reset();
    cut_options_ = options;
  }

  /// One step of the current cut (a new one after begin_cut, or on the first call): the surface step, then the
  /// system and the table. A step the cutter refuses, or whose system cannot be updated (an exception of the
  /// update), is returned with accepted false and the reason, and changes nothing.
  CutStepResult cut(const Eigen::Vector3d& from, const Eigen::Vector3d& direction, CutUpdateMethod method = CutUpdateMethod::Exact) {
    const auto t0 = SteadyClock::now();
    const CutSurfaceStep surface = cut_surface(from, direction);
    CutStepResult r = surface.accepted ? apply(surface, method) : refused(method, surface.reason);
    r.total_seconds = seconds_since(t0);
    return r;
  }

  /// One exact step in two phases (docs/cutting.md, "First response"): the surface step, then what every
  /// column needs (the system's update, the step's solves, the base state) and the table over the region
  /// elements within `reach` of the `tools` positions (elements_within_reach), returned in `first` and
  /// not published: table() stays the table before the step until complete_step() publishes the
  /// complete one, which must come before the next step. A refused step is returned with accepted false
  /// and changes nothing. Exact only: a CutSystemUpdate that keeps the explicit A* (keep_matrix, the
  /// iterative modes) refuses it.
  CutStepResult cut_first(const Eigen::Vector3d& from, const Eigen::Vector3d& direction, const std::vector<Eigen::Vector3d>& tools,
                          double reach, std::shared_ptr<const GreensTable>& first) {
    const auto t0 = SteadyClock::now();
    first.reset();
    if (A_.size() > 0) throw InvalidArgumentError("CutSystemUpdate::cut_first: two-phase steps are exact only (this update keeps A*)");
    if (pending_step_) throw InvalidArgumentError("CutSystemUpdate::cut_first: the previous step was not completed (complete_step)");
    const CutSurfaceStep surface = cut_surface(from, direction);
    if (!surface.accepted) return refused(CutUpdateMethod::Exact, surface.reason);
    return apply_first(surface, tools, reach, first, t0);
  }

  /// The system half of cut_first() for the surface step cut_surface returned (the viewer shows the new
  /// surface before the tables follow); complete_step() must come next. `started`: when the step was
  /// asked for (complete_step's total_seconds count from it).
  CutStepResult apply_first(const CutSurfaceStep& surface, const std::vector<Eigen::Vector3d>& tools, double reach,
                            std::shared_ptr<const GreensTable>& first, SteadyClock::time_point started = SteadyClock::now()) {
    const auto t0 = started;
    first.reset();
    if (!surface.accepted || !pending_before_ || surface.mesh != cutter_->mesh())
      throw InvalidArgumentError("CutSystemUpdate::apply_first: not the surface step just taken");
    if (A_.size() > 0) {
      undo_surface();
      throw InvalidArgumentError("CutSystemUpdate::apply_first: two-phase steps are exact only (this update keeps A*)");
    }
    CutStepResult r;
    r.delta = surface.delta;
    try {
      const std::shared_ptr<const GreensTable> current = table();
      CutChange change = integrate_cut_change(*current->mesh(), *surface.mesh, surface.delta, current->material(), current->quadrature(),
                                              current->gravity());
      r.integration_seconds = change.integration_seconds;
      auto step = std::make_unique<CutTableStep>(current, surface.mesh, surface.delta, std::move(change), options_.table);
      GreensTableUpdateResult tr;
      first = step->first_response(elements_within_reach(*surface.mesh, step->region(), tools, reach), &tr);
      r.system_seconds = tr.system_seconds;
      r.table_seconds = tr.table_seconds;
      r.rank = tr.rank;
      pending_step_ = std::move(step);
      pending_started_ = t0;
      pending_delta_ = surface.delta;
      pending_before_.reset();  // the surface step stands
    } catch (const Error& e) {
      undo_surface();
      first.reset();
      return refused(CutUpdateMethod::Exact, e.what());
    } catch (...) {
      undo_surface();
      throw;
    }
    r.total_seconds = seconds_since(t0);
    return r;
  }

  /// True between cut_first() and complete_step().
  bool completion_pending() const { return pending_step_ != nullptr; }

  /// The second phase of cut_first(): the complete table, published (table(), solution()) as apply()
  /// publishes, and the refactorisation policy applied. Its total_seconds count from cut_first's start;
  /// its integration and system seconds are cut_first's again (computed once). On an exception nothing
  /// is published and the step stays pending: complete_step may be called again.
  CutStepResult complete_step() {
    if (!pending_step_) throw InvalidArgumentError("CutSystemUpdate::complete_step: no step is waiting (cut_first)");
    CutStepResult r;
    r.delta = pending_delta_;
    GreensTableUpdateResult tr;
    const std::shared_ptr<const GreensTable> next = pending_step_->complete(&tr);
    pending_step_.reset();  // from here on nothing throws
    r.integration_seconds = tr.integration_seconds;
    r.system_seconds = tr.system_seconds;
    r.table_seconds = tr.table_seconds;
    Eigen::VectorXd x = solution_of(*next);
    r.rank = next->solver()->rank();
    {
      std::lock_guard<std::mutex> lock(publish_);
      std::atomic_store(&table_, next);
    }
    x_.swap(x);
    const Index limit = options_.refactor_rank > 0 ? options_.refactor_rank : default_refactor_rank(next->num_dofs());
    if (r.rank > limit) r.refactor_started = start_refactor(next, r.rank > 2 * limit || !options_.background_refactor);
    r.total_seconds = seconds_since(pending_started_);
    return r;
  }

  /// The surface half of cut(), for a caller that shows the new surface before the tables follow (the
  /// viewer): the next increment of the current cut, with the elements of cut_locked_elements locked. Only
  /// the surface advances; apply(step) brings the system and the table to it and must come next.
  CutSurfaceStep cut_surface(const Eigen::Vector3d& from, const Eigen::Vector3d& direction) {
    if (pending_before_) throw InvalidArgumentError("CutSystemUpdate::cut_surface: the previous surface step was not applied");
    if (pending_step_) throw InvalidArgumentError("CutSystemUpdate::cut_surface: the previous step was not completed (complete_step)");
    if (cutter_ && cutter_->mesh() != table()->mesh()) cutter_.reset();  // the system was stepped elsewhere
    if (!cutter_) {
      const std::shared_ptr<const GreensTable> t = table();
      cutter_ = std::make_unique<SurfaceCutter>(t->mesh(), cut_locked_elements(*t), cut_options_);
    }
    SurfaceCutter before = *cutter_;
    CutSurfaceStep s;
    const CutStep step = cutter_->step(from, direction);
    s.accepted = step.accepted;
    s.reason = step.reason;
    if (!step.accepted) return s;
    s.mesh = cutter_->mesh();
    s.delta = step.delta;
    pending_before_ = std::make_unique<SurfaceCutter>(std::move(before));
    return s;
  }

  /// The system half of cut() for the surface step cut_surface returned. On a failure the surface step is
  /// undone too and the result says why (accepted false).
  CutStepResult apply(const CutSurfaceStep& surface, CutUpdateMethod method = CutUpdateMethod::Exact) {
    if (!surface.accepted || !pending_before_ || surface.mesh != cutter_->mesh())
      throw InvalidArgumentError("CutSystemUpdate::apply: not the surface step just taken");
    try {
      CutStepResult r = apply(surface.mesh, surface.delta, method);
      pending_before_.reset();
      return r;
    } catch (const Error& e) {
      undo_surface();
      return refused(method, e.what());
    } catch (...) {
      undo_surface();
      throw;
    }
  }

  /// One system step for a surface cut elsewhere: `after` is the cut mesh, `delta` what changed from the
  /// current mesh (the conditions and region rules apply; the locking rule is the caller's).
  /// On an exception nothing has changed (the current table and solution stay as they were).
  CutStepResult apply(std::shared_ptr<const TriangleMesh> after, const MeshDelta& delta, CutUpdateMethod method) {
    if (pending_step_) throw InvalidArgumentError("CutSystemUpdate::apply: the previous step was not completed (complete_step)");
    const auto t0 = SteadyClock::now();
    CutStepResult r;
    r.method = method;
    r.delta = delta;
    const std::shared_ptr<const GreensTable> current = table();
    std::shared_ptr<const GreensTable> next;
    Eigen::VectorXd x;
    Eigen::MatrixXd A;
    if (method == CutUpdateMethod::Refactor) {
      const auto ta = SteadyClock::now();
      next = recomputed_table_after(*current, after, delta, options_.table);
      r.integration_seconds = next->timings().assembly_seconds;
      r.table_seconds = seconds_since(ta) - r.integration_seconds;
      x = solution_of(*next);
      if (A_.size() > 0) A = updated_matrix(*current, *after, delta, nullptr, r);
    } else {
      const CutChange change =
          integrate_cut_change(*current->mesh(), *after, delta, current->material(), current->quadrature(), current->gravity());
      r.integration_seconds = change.integration_seconds;
      GreensTableUpdateResult tr;
      next = updated_table(*current, after, delta, change, options_.table, &tr);
      r.table_seconds = tr.table_seconds;
      r.system_seconds = tr.system_seconds;
      x = solution_of(*next);
      if (method != CutUpdateMethod::Exact || A_.size() > 0) {
        if (A_.size() == 0) {  // first iterative step: the explicit A* of the mesh before the cut
          const auto tb = SteadyClock::now();
          build_matrix();
          r.integration_seconds += seconds_since(tb);
        }
        A = updated_matrix(*current, *after, delta, &change, r);
      }
      if (method != CutUpdateMethod::Exact) {
        LinearSolverOptions s = options_.krylov;
        s.method = method == CutUpdateMethod::Gmres      ? SolverMethod::Gmres
                   : method == CutUpdateMethod::BiCgStab ? SolverMethod::BiCgStab
                                                         : SolverMethod::BiCg;
        Eigen::VectorXd x0 = Eigen::VectorXd::Zero(A.rows());
        x0.head(x_.size()) = x_;
        LinearSolveResult summary;
        const auto ts = SteadyClock::now();
        x = solve_linear_system(A, next->rhs(), s, summary, after.get(), x0);
        r.system_seconds = seconds_since(ts);
        r.iterations = summary.iterations;
        r.relative_residual = summary.relative_residual;
      }
    }
    r.rank = next->solver()->rank();
    // Publish: from here on nothing throws.
    {
      std::lock_guard<std::mutex> lock(publish_);
      std::atomic_store(&table_, std::shared_ptr<const GreensTable>(next));
    }
    x_.swap(x);
    if (A.size() > 0) A_.swap(A);
    const Index limit = options_.refactor_rank > 0 ? options_.refactor_rank : default_refactor_rank(next->num_dofs());
    if (r.rank > limit) r.refactor_started = start_refactor(next, r.rank > 2 * limit || !options_.background_refactor);
    r.total_seconds = seconds_since(t0);
    return r;
  }

 private:
  /// Takes back the surface step cut_surface took (the cutter as it was before it).
  void undo_surface() {
    *cutter_ = std::move(*pending_before_);
    pending_before_.reset();
  }

  static CutStepResult refused(CutUpdateMethod method, std::string reason) {
    CutStepResult r;
    r.method = method;
    r.accepted = false;
    r.reason = std::move(reason);
    return r;
  }

  static Eigen::VectorXd solution_of(const GreensTable& t) {
    Eigen::VectorXd x(t.num_dofs());
    for (Index k = 0; k < t.num_dofs(); ++k)
      x(k) = t.base_kinds()[static_cast<std::size_t>(k)] == BcKind::Traction ? t.base_displacement()(k) : t.base_traction()(k);
    return x;
  }

  void build_matrix() {
    const std::shared_ptr<const GreensTable> t = table();
    const InfluenceAssembler assembler(*t->mesh(), t->material(), t->quadrature());
    InfluenceMatrices hg = assembler.assemble();
    A_ = build_system_matrix_in_place(hg, t->base_conditions());
  }

  /// The explicit A* after the step: blockdiag(A*, I) with the rows and columns D replaced.
  Eigen::MatrixXd updated_matrix(const GreensTable& current, const TriangleMesh& after, const MeshDelta& delta, const CutChange* known,
                                 CutStepResult& r) const {
    CutChange local;
    if (!known) {
      local = integrate_cut_change(*current.mesh(), after, delta, current.material(), current.quadrature(), current.gravity());
      r.integration_seconds += local.integration_seconds;
      known = &local;
    }
    const BoundaryConditions bc = conditions_after_cut(current.base_conditions(), delta);
    const Index n = A_.rows(), n1 = known->n_after;
    Eigen::MatrixXd A = Eigen::MatrixXd::Identity(n1, n1);
    A.topLeftCorner(n, n) = A_;
    const Eigen::MatrixXd rows = system_rows_after(*known, bc), cols = system_columns_after(*known, bc);
    for (Index j = 0; j < known->size(); ++j) {
      const Index k = known->dofs[static_cast<std::size_t>(j)];
      A.col(k) = cols.col(j);
      A.row(k) = rows.row(j);
    }
    return A;
  }

  /// Starts (or, when `now`, runs here) a refactorisation of `snapshot`; true when one was started.
  bool start_refactor(const std::shared_ptr<const GreensTable>& snapshot, bool now) {
    if (busy_.load()) {
      if (!now) return false;
      wait_for_refactor();
      if (table().get() != snapshot.get()) return false;  // the finished one was for this snapshot and published
    }
    wait_for_refactor();  // a finished worker: join it
    busy_.store(true);
    auto work = [this, snapshot]() {
      try {
        std::shared_ptr<const GreensTable> fresh = snapshot->refactored();
        std::lock_guard<std::mutex> lock(publish_);
        if (std::atomic_load(&table_).get() == snapshot.get()) std::atomic_store(&table_, fresh);
      } catch (...) {
        // The current table stays valid (only more expensive to update); the next step retries.
      }
      busy_.store(false);
    };
    if (now)
      work();
    else
      worker_ = std::thread(work);
    return true;
  }

  CutSystemOptions options_;
  CutOptions cut_options_;
  std::unique_ptr<SurfaceCutter> cutter_;          // the current cut (null: the next step opens one)
  std::unique_ptr<SurfaceCutter> pending_before_;  // the cutter before a surface step not yet applied
  std::unique_ptr<CutTableStep> pending_step_;     // cut_first's step, until complete_step
  SteadyClock::time_point pending_started_{};
  MeshDelta pending_delta_;
  std::shared_ptr<const GreensTable> table_;  // read and written with std::atomic_load / atomic_store
  Eigen::VectorXd x_;
  Eigen::MatrixXd A_;  // explicit A* (iterative modes only)
  std::mutex publish_;
  std::atomic<bool> busy_{false};
  std::thread worker_;
};

}  // namespace bemsurg
