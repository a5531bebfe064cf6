// bemsurg/presolution/greens_table.hpp: the compliance Green's-function table of a supported body
// (docs/design.md §6; Wang et al. 2007 §5.1, the pre-solutions that make BEM real-time).
//
// Base state: the scene's boundary conditions (typically supported elements S with u = 0 and free
// elements F with t = 0) plus gravity, solved once: u_g, t_g. With the one factorisation of A*
// that this needs, a unit traction on a free dof c is one more right-hand side (column c of G,
// eq. 6's R_bc), and its solution gives the displacement of every element: column c of the
// table. The table holds those columns for the free elements of a region where tools may act,
// so its memory is n x 3|region| (n = 3E): "model no more than a scene needs".
//
// Storage is column-major with one column per region dof: a contact lookup reads whole columns,
// which is contiguous (three rows of a column-major table would touch a new cache line, often a
// new page, per entry: about a hundred times slower when measured).
// Rows of displacement-prescribed dofs hold the prescribed change, zero. The columns live in a buffer
// the table shares with its copies (never written once the table is made), so that a cut's chain of
// snapshots can draw its tables' storage from the buffers the tables let go of leave behind
// (snapshot_buffers.hpp; docs/cutting.md, "Snapshot storage"); columns() views it.
//
// After a cut (docs/design.md §7, §9) the table is not recomputed: the cutting module's
// updated_table (bemsurg/cutting/table_update.hpp) returns a NEW table (an immutable snapshot,
// version() + 1) for the cut mesh whose base state and columns equal those computed from scratch,
// integrating only the rows and columns of the changed elements. For that a computed table keeps
// the factorisation of A* (the dense LU's factors and pivots, n^2 doubles, in estimate_bytes; or the
// hierarchical backend's H-LU, presolution/hierarchical_table.hpp), the right-hand side, the mesh
// snapshot and the reaction rows (see below); a table read from a file has none of these and
// cannot be updated (has_factorization() is false).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"
#include "bemsurg/snapshot_buffers.hpp"
#include "bemsurg/solvers/linear_solve.hpp"
#include "bemsurg/solvers/low_rank_updated_lu.hpp"
#include "bemsurg/solvers/system_factorization.hpp"

namespace bemsurg {

/// What GreensTable::compute is asked for: the region where tools may act, the gravity of the base state, the quadrature
/// and the memory limit.
/// \ingroup presolution
struct GreensTableOptions {
  /// Elements where tools may act (each must be free: traction prescribed on all three
  /// components). Empty: every free element.
  std::vector<Index> region;
  /// Gravity acceleration of the base state (body force = density * gravity).
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  QuadratureOptions quadrature;
  /// Refuse (ResourceError) when the estimate exceeds this many bytes; 0 = 80 % of physical memory.
  double memory_limit_bytes = 0.0;
  /// Keep A*^-1 itself (solvers/explicit_inverse.hpp) instead of its LU, for tables that will be cut:
  /// a cut's first response then reads rows of it (docs/cutting.md, "First response on the rows
  /// within reach"). Costs dgetri's 4/3 n^3 flops at precompute in the LU's storage (no more memory).
  bool explicit_inverse = false;
};

/// Wall-clock seconds of the three phases of the one-time precomputation.
/// \ingroup presolution
struct PrecomputeTimings {
  double assembly_seconds = 0.0;       // H, G, gravity, A* and the right-hand sides
  double factorization_seconds = 0.0;  // LU of A* (LAPACK dgetrf when BLAS is linked)
  double table_seconds = 0.0;          // multi-right-hand-side back-substitution (dgetrs)
  double inversion_seconds = 0.0;      // A*^-1 from the LU (dgetri), when the table keeps it (GreensTableOptions::explicit_inverse)
};

/// What a table was computed for, to identify its file: a saved table is used only when all of it matches. The
/// physics of a table is read through GreensTable::material() and gravity(), not from here.
/// \ingroup presolution
struct GreensTableKey {
  std::uint64_t mesh_hash = 0;        // vertices and faces, bit for bit
  std::uint64_t conditions_hash = 0;  // kinds and values of the base boundary conditions
  std::uint64_t quadrature_hash = 0;  // QuadratureOptions
  Index num_elements = 0;
  Material material;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  /// The backend that solved the columns: a compressed table (hierarchical, its ACA+ tolerance) is a
  /// different table from the dense one and never loads in its place (issue 40).
  SolverBackend backend = SolverBackend::Dense;
  double compression_tolerance = 0.0;  // 0 for the dense backend
};

/// 64-bit FNV-1a of raw bytes, chained through `seed` (used for keys and file checksums).
std::uint64_t fnv1a64(const void* data, std::size_t bytes, std::uint64_t seed = 0xcbf29ce484222325ULL);
std::uint64_t hash_mesh(const TriangleMesh& mesh);
std::uint64_t hash_conditions(const BoundaryConditions& bc);
std::uint64_t hash_quadrature(const QuadratureOptions& q);
GreensTableKey make_greens_table_key(const TriangleMesh& mesh, const Material& material, const BoundaryConditions& base,
                                     const Eigen::Vector3d& gravity, const QuadratureOptions& quadrature);

/// Base boundary conditions of docs/design.md §6: `supported` elements held (u = 0), the rest free.
BoundaryConditions supported_base_conditions(Index num_elements, const std::vector<Index>& supported);

class GreensTable;

/// How a table is computed again from scratch on a mesh (a background refactorisation after cuts, a
/// cut step recomputed): on the backend that computed it first. Empty: the dense LU (GreensTable::compute).
using TableRecompute =
    std::function<GreensTable(std::shared_ptr<const TriangleMesh> mesh, const Material& material, const BoundaryConditions& base,
                              const Eigen::Vector3d& gravity, const QuadratureOptions& quadrature, const std::vector<Index>& region)>;

/// What a table solved by another backend keeps for cuts (GreensTable::from_solution): its factorisation of A*
/// (the base of the cut's low-rank update), R_bc + R_G, and how to compute the table again on that backend.
/// \ingroup presolution
struct KeptFactorization {
  std::shared_ptr<const SystemFactorization> factors;  // null: nothing kept, the table cannot be cut
  Eigen::VectorXd rhs;
  TableRecompute recompute;
};

namespace detail {
struct GreensTableParts;  // the cutting module's access to a table's parts (cutting/impl/table_update_impl.hpp)
}  // namespace detail

/// The compliance Green's-function table of a supported body (docs/design.md §6; Wang et al. 2007 §5.1): the base state
/// and the displacement of every dof per unit traction on each region dof. Immutable: a cut step (updated_table, cutting/) returns a new table.
/// \ingroup presolution
class GreensTable {
 public:
  GreensTable() = default;

  /// Bytes the precomputation needs at its peak: A* (built in H's storage) and G during assembly
  /// (2 n^2 doubles, as solve_elastostatic), the right-hand sides n x (3|region| + 1), O(n)
  /// vectors and the pivots; what is kept afterwards (the LU factors, n^2, and the table) fits in
  /// that peak.
  static double estimate_bytes(Index num_elements, Index region_elements);
  /// The default limit: 80 % of this machine's physical memory (bemsurg/memory_budget.hpp).
  static double default_memory_limit_bytes();

  /// The table of `problem` (constant elements) on `region` (elements where tools may act, each free:
  /// traction prescribed on all three components; empty: every free element). Runs the problem's one
  /// check (check_before_solve, as solve_elastostatic does; its warnings are kept in warnings()),
  /// assembles, factorises A* once, solves the base state and the region's columns. Throws
  /// ResourceError (with the estimate) when it would not fit within `memory_limit_bytes` (0: 80 % of
  /// physical memory), BoundaryConditionError for an unsupported body or a region element that is
  /// not free, InvalidMaterialError, InvalidArgumentError for linear elements, SolverError for a
  /// singular A*.
  /// `explicit_inverse`: as GreensTableOptions::explicit_inverse.
  static GreensTable compute(const ElastostaticProblem& problem, const std::vector<Index>& region = {}, double memory_limit_bytes = 0.0,
                             bool explicit_inverse = false);
  /// The same for a mesh snapshot shared with its other users (no copy of the mesh kept;
  /// problem.mesh is not read).
  static GreensTable compute(std::shared_ptr<const TriangleMesh> mesh, const ElastostaticProblem& problem,
                             const std::vector<Index>& region = {}, double memory_limit_bytes = 0.0, bool explicit_inverse = false);
  /// The same from its parts (GreensTableOptions carries region, gravity, quadrature and the limit).
  static GreensTable compute(const TriangleMesh& mesh, const Material& material, const BoundaryConditions& base,
                             const GreensTableOptions& options = {});
  /// The same for a mesh snapshot shared with its other users (no copy of the mesh kept).
  static GreensTable compute(std::shared_ptr<const TriangleMesh> mesh, const Material& material, const BoundaryConditions& base,
                             const GreensTableOptions& options = {});

  /// The table's region as compute() resolves and checks `region` on `base` (empty: every free
  /// element, in order; repeats dropped): BoundaryConditionError for an element out of range, not
  /// free, or no free element at all.
  static std::vector<Index> resolve_region(const BoundaryConditions& base, const std::vector<Index>& region);
  /// BoundaryConditionError unless `base` has one condition per element of `mesh` (every backend's
  /// table checks this first).
  static void require_conditions_for(const BoundaryConditions& base, const TriangleMesh& mesh);
  /// A table from the solution of A* X = [G columns of the region's elements, R_bc + R_G] solved by
  /// another backend (presolution/hierarchical_table.hpp): `solution` is n x (3|region| + 1), the
  /// base state last; `region` as resolve_region returns it. The key records `backend` and
  /// `compression_tolerance`. With `kept.factors` the table keeps that factorisation for cuts
  /// (has_factorization(); the cut's update runs on it, docs/cutting.md "On either backend") and
  /// `kept.recompute` for refactorisations; without, it cannot be cut.
  static GreensTable from_solution(std::shared_ptr<const TriangleMesh> mesh, const ElastostaticProblem& problem, std::vector<Index> region,
                                   Eigen::MatrixXd solution, SolverBackend backend, double compression_tolerance,
                                   std::vector<std::string> warnings, const PrecomputeTimings& timings, KeptFactorization kept = {});

  /// This table computed again from scratch on its own mesh (same region, conditions, version, and
  /// backend): what a background refactorisation publishes in place of a table whose correction rank grew.
  std::shared_ptr<const GreensTable> refactored() const;
  /// The table of this body's material, gravity and quadrature on `mesh` with `base` and `region`,
  /// computed from scratch on the backend that computed this one (dense LU unless another backend
  /// set its TableRecompute); no memory limit (the caller's table already fits).
  GreensTable recomputed_on(std::shared_ptr<const TriangleMesh> mesh, const BoundaryConditions& base,
                            const std::vector<Index>& region) const;
  /// The same body with Young's modulus `young_modulus` and gravity scaled by `gravity_factor`: exact without
  /// recomputing, because with zero prescribed displacements every displacement (the table's columns and the
  /// base state) scales as 1/E and the reactions do not, and with zero prescribed tractions the base state is
  /// linear in gravity (docs/viewer.md). A new snapshot (same version) that keeps the mesh but no factorisation
  /// (A* changes with E), so cut a table before rescaling it. Throws InvalidArgumentError when the base state
  /// prescribes a non-zero displacement (and E changes) or a non-zero traction (and gravity changes), or for
  /// E <= 0 or a non-finite factor.
  std::shared_ptr<const GreensTable> with_young_modulus(double young_modulus, double gravity_factor = 1.0) const;

  /// Snapshot number: 0 from compute() or a file, +1 per cut step (updated_table).
  std::uint64_t version() const { return version_; }
  /// True when the table kept what a cut update (updated_table) needs (computed, not read from a file).
  bool has_factorization() const { return solver_ != nullptr && mesh_ != nullptr; }
  /// True for a cut's first response on the rows within reach (cutting/table_update.hpp): exact on
  /// its region's elements (their rows of its columns and of the base state), the table before the
  /// step elsewhere, until the complete table follows. False for every complete table.
  bool stale_outside_region() const { return stale_outside_region_; }
  /// The mesh the table was computed for (null for a table read from a file).
  const std::shared_ptr<const TriangleMesh>& mesh() const { return mesh_; }
  /// The solver of A* (the kept LU plus the low-rank correction of the cuts since); null when none.
  const std::shared_ptr<const LowRankUpdatedLu>& solver() const { return solver_; }
  /// The base boundary conditions (kinds and values).
  BoundaryConditions base_conditions() const;
  /// R_bc + R_G of the base state (n).
  const Eigen::VectorXd& rhs() const { return rhs_; }
  /// The quadrature the table was integrated with.
  const QuadratureOptions& quadrature() const { return quadrature_; }
  /// The material of the body the table describes.
  const Material& material() const { return key_.material; }
  /// The gravity acceleration of the base state.
  const Eigen::Vector3d& gravity() const { return key_.gravity; }
  /// What check_before_solve warned of when the table was computed (slivers, a nearly incompressible held surface).
  const std::vector<std::string>& warnings() const { return warnings_; }

  /// From stored parts (the table file reader); checks that the sizes agree.
  GreensTable(GreensTableKey key, std::vector<Index> region, Eigen::VectorXd base_displacement, Eigen::VectorXd base_traction,
              std::vector<BcKind> base_kinds, Eigen::MatrixXd columns);

  bool empty() const { return key_.num_elements == 0; }
  Index num_elements() const { return key_.num_elements; }
  Index num_dofs() const { return 3 * key_.num_elements; }
  const GreensTableKey& key() const { return key_; }

  /// Elements with a column in the table, in column order: element region()[s] owns columns
  /// 3s..3s+2 (unit traction along x, y, z).
  const std::vector<Index>& region() const { return region_; }
  /// Column block of element e, or -1 when e is not in the region.
  Index region_slot(Index element) const { return slot_[static_cast<std::size_t>(element)]; }
  /// True when all three dofs of e are traction-prescribed in the base state.
  bool is_free(Index element) const { return BoundaryConditions::is_free_element(base_kinds_, element); }
  const std::vector<BcKind>& base_kinds() const { return base_kinds_; }

  /// Base state (gravity and the base conditions): displacement and traction of every dof.
  const Eigen::VectorXd& base_displacement() const { return base_displacement_; }
  const Eigen::VectorXd& base_traction() const { return base_traction_; }
  /// n x 3|region|: displacement of every dof per unit traction on each region dof. A view of the
  /// table's storage (column-major, leading dimension n), valid while the table lives.
  Eigen::Map<const Eigen::MatrixXd> columns() const { return {columns_data_.get(), columns_rows_, columns_cols_}; }
  /// Displacement of element `row` (3) per unit traction on element `col` (3): G_{row,col}.
  Eigen::Matrix3d block(Index row, Index col) const { return columns().block<3, 3>(3 * row, 3 * region_slot(col)); }
  /// Pointer to the first of the three columns of region element `col` (contiguous, length n each).
  const double* column_data(Index col) const { return columns_data_.get() + 3 * region_slot(col) * columns_rows_; }

  const PrecomputeTimings& timings() const { return timings_; }
  /// Bytes held: the table, the base state, the reaction rows and, when kept, the solver (the LU
  /// factors are shared between a table and the tables updated from it).
  std::size_t bytes() const {
    return static_cast<std::size_t>(columns_rows_ * columns_cols_ + reactions_.size() + 4 * base_displacement_.size()) * sizeof(double) +
           (solver_ ? solver_->bytes() + solver_->base()->bytes() : 0);
  }
  /// Traction on the displacement-prescribed dofs (reaction_dofs(), in order) per unit traction on
  /// each region dof: the rows that columns() holds as zero (|reaction_dofs| x 3|region|).
  const Eigen::MatrixXd& reactions() const { return reactions_; }
  const std::vector<Index>& reaction_dofs() const { return reaction_dofs_; }

  /// u = u_g + sum_c G_{:,c} t_c for extra tractions `tractions` (k x 3 rows) on region elements
  /// `elements`: the full field after contact, O(n k). `u` must have n entries (not resized).
  void displacement_field(const Index* elements, const double* tractions, Index count, Eigen::VectorXd& u) const;

 private:
  friend struct detail::GreensTableParts;
  static GreensTable compute_on(std::shared_ptr<const TriangleMesh> mesh, const Material& material, const BoundaryConditions& base,
                                const Eigen::Vector3d& gravity, const QuadratureOptions& quadrature, const std::vector<Index>& region,
                                double memory_limit_bytes, bool explicit_inverse = false);
  void build_slots();
  /// Base displacement and traction from the solution x of A* x = b (u on traction dofs, t on
  /// displacement dofs) and the prescribed values of `bc`.
  void set_base_state(const BoundaryConditions& bc, const Eigen::Ref<const Eigen::VectorXd>& x);
  /// The table's columns from the solution X of A* X = [region columns of G] (n x 3|region|): the rows
  /// of displacement-prescribed dofs move to reactions_ and become zero. The first takes X's storage.
  void set_columns_from_solution(Eigen::MatrixXd&& X);
  /// The same for a solution held in `data` (rows x cols, column-major; a buffer of a
  /// SnapshotBufferPool), which the table keeps.
  void set_columns_from_solution(std::shared_ptr<double> data, Index rows, Index cols);
  Eigen::Map<Eigen::MatrixXd> writable_columns() { return {columns_data_.get(), columns_rows_, columns_cols_}; }

  GreensTableKey key_;
  std::vector<Index> region_;
  std::vector<Index> slot_;
  Eigen::VectorXd base_displacement_;
  Eigen::VectorXd base_traction_;
  std::vector<BcKind> base_kinds_;
  std::shared_ptr<double> columns_data_;  // n x 3|region|, column-major; shared with the table's copies
  Index columns_rows_ = 0, columns_cols_ = 0;
  PrecomputeTimings timings_;
  // Kept for the cut updates (cutting/table_update.hpp) (empty for a table read from a file).
  std::uint64_t version_ = 0;
  bool stale_outside_region_ = false;
  std::shared_ptr<const TriangleMesh> mesh_;
  std::shared_ptr<const LowRankUpdatedLu> solver_;
  TableRecompute recompute_;  // empty: the dense LU
  QuadratureOptions quadrature_;
  Eigen::VectorXd base_values_;
  Eigen::VectorXd rhs_;
  std::vector<Index> reaction_dofs_;
  Eigen::MatrixXd reactions_;
  std::vector<std::string> warnings_;
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/presolution/impl/greens_table_impl.hpp"
#endif
