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

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/elastostatics/elastostatic_problem.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/quadrature/quadrature_cost.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bemsurg/solvers/explicit_inverse.hpp"
#include "bemsurg/solvers/lu_factors.hpp"
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

BEMSURG_INLINE GreensTable GreensTable::compute(const ElastostaticProblem& problem, const std::vector<Index>& region,
                                                double memory_limit_bytes, bool explicit_inverse) {
  return compute(std::make_shared<const TriangleMesh>(problem.mesh), problem, region, memory_limit_bytes, explicit_inverse);
}

BEMSURG_INLINE GreensTable GreensTable::compute(std::shared_ptr<const TriangleMesh> mesh, const ElastostaticProblem& problem,
                                                const std::vector<Index>& region, double memory_limit_bytes, bool explicit_inverse) {
  if (problem.elements != ElementType::Constant)
    throw InvalidArgumentError("GreensTable: pre-solution tables use constant elements; the problem has linear ones (docs/elements.md)");
  return compute_on(std::move(mesh), problem.material, problem.boundary_conditions, problem.gravity, problem.quadrature, region,
                    memory_limit_bytes, explicit_inverse);
}

BEMSURG_INLINE GreensTable GreensTable::compute(const TriangleMesh& mesh, const Material& material, const BoundaryConditions& base,
                                                const GreensTableOptions& options) {
  return compute(std::make_shared<const TriangleMesh>(mesh), material, base, options);
}

BEMSURG_INLINE GreensTable GreensTable::compute(std::shared_ptr<const TriangleMesh> mesh, const Material& material,
                                                const BoundaryConditions& base, const GreensTableOptions& options) {
  return compute_on(std::move(mesh), material, base, options.gravity, options.quadrature, options.region, options.memory_limit_bytes,
                    options.explicit_inverse);
}

BEMSURG_INLINE GreensTable GreensTable::compute_on(std::shared_ptr<const TriangleMesh> mesh_ptr, const Material& material,
                                                   const BoundaryConditions& base, const Eigen::Vector3d& gravity,
                                                   const QuadratureOptions& quadrature, const std::vector<Index>& region,
                                                   double memory_limit_bytes, bool explicit_inverse) {
  if (!mesh_ptr) throw InvalidArgumentError("GreensTable: no mesh");
  const TriangleMesh& mesh = *mesh_ptr;
  require_conditions_for(base, mesh);
  const Index E = mesh.num_elements();
  const Index n = 3 * E;

  GreensTable table;
  table.key_ = make_greens_table_key(mesh, material, base, gravity, quadrature);
  table.base_kinds_ = base.kinds();
  table.region_ = resolve_region(base, region);
  const Index R = static_cast<Index>(table.region_.size());

  // The problem's one check, as solve_elastostatic runs it (docs/design.md §5, §6).
  MemoryNeed memory;
  memory.bytes = estimate_bytes(E, R);
  memory.limit_bytes = memory_limit_bytes;
  memory.refusal = [E, n, R](double need, double limit) {
    return "the precomputation for " + std::to_string(E) + " elements (" + std::to_string(n) + " equations) with a region of " +
           std::to_string(R) + " elements needs about " + format_gib(need) +
           " (A* and G: " + format_gib(8.0 * 2.0 * double(n) * double(n)) + "; table: " + format_gib(8.0 * double(n) * 3.0 * double(R)) +
           "), more than the limit of " + format_gib(limit) + "; restrict the region to where tools act, or coarsen the mesh away from it";
  };
  table.warnings_ = check_before_solve(mesh, material, gravity, base, quadrature, memory, "GreensTable");

  auto t0 = std::chrono::steady_clock::now();
  Eigen::MatrixXd A, B;
  {
    const InfluenceAssembler assembler(mesh, material, quadrature);
    Eigen::VectorXd gvec;  // H, G and gravity in one pass (zero without gravity)
    InfluenceMatrices hg = assembler.assemble(gravity, gvec);
    B.resize(n, 3 * R + 1);
    for (Index s = 0; s < R; ++s) B.middleCols(3 * s, 3) = hg.G.middleCols(3 * table.region_[static_cast<std::size_t>(s)], 3);
    B.col(3 * R) = build_right_hand_side(hg, base, gvec);
    A = build_system_matrix_in_place(hg, base);
  }
  table.timings_.assembly_seconds = seconds_since(t0);
  table.rhs_ = B.col(3 * R);
  LuFactors lu = LuFactors::factor(std::move(A), &table.timings_.factorization_seconds);
  t0 = SteadyClock::now();
  lu.solve_in_place(B);  // dgetrs: the table's columns before the factors are inverted, which would not make them cheaper
  table.timings_.table_seconds = seconds_since(t0);
  if (explicit_inverse)
    table.solver_ = std::make_shared<const LowRankUpdatedLu>(
        std::make_shared<const ExplicitInverse>(ExplicitInverse::from(std::move(lu), &table.timings_.inversion_seconds)));
  else
    table.solver_ = std::make_shared<const LowRankUpdatedLu>(std::make_shared<const LuFactors>(std::move(lu)));
  table.mesh_ = std::move(mesh_ptr);
  table.quadrature_ = quadrature;
  table.base_values_ = base.values();

  table.set_base_state(base, B.col(3 * R));
  B.conservativeResize(n, 3 * R);
  if (!B.allFinite()) throw SolverError("GreensTable: the table has non-finite entries");
  table.set_columns_from_solution(std::move(B));
  table.build_slots();
  return table;
}

BEMSURG_INLINE void GreensTable::require_conditions_for(const BoundaryConditions& base, const TriangleMesh& mesh) {
  if (base.num_elements() != mesh.num_elements())
    throw BoundaryConditionError("GreensTable: the boundary conditions are for " + std::to_string(base.num_elements()) +
                                 " elements, the mesh has " + std::to_string(mesh.num_elements()));
}

BEMSURG_INLINE std::vector<Index> GreensTable::resolve_region(const BoundaryConditions& base, const std::vector<Index>& region) {
  const Index E = base.num_elements();
  std::vector<Index> out;
  if (region.empty()) {
    for (Index e = 0; e < E; ++e)
      if (base.is_free(e)) out.push_back(e);
  } else {
    std::vector<char> seen(static_cast<std::size_t>(E), 0);
    for (Index e : region) {
      if (e < 0 || e >= E)
        throw BoundaryConditionError("GreensTable: region element " + std::to_string(e) + " is out of range (the mesh has " +
                                     std::to_string(E) + " elements)");
      if (!base.is_free(e))
        throw BoundaryConditionError("GreensTable: region element " + std::to_string(e) +
                                     " is not free (a displacement is prescribed on it); tools act on free elements only");
      if (seen[static_cast<std::size_t>(e)]) continue;
      seen[static_cast<std::size_t>(e)] = 1;
      out.push_back(e);
    }
  }
  if (out.empty()) throw BoundaryConditionError("GreensTable: no free element for the table's region");
  return out;
}

BEMSURG_INLINE GreensTable GreensTable::from_solution(std::shared_ptr<const TriangleMesh> mesh, const ElastostaticProblem& problem,
                                                      std::vector<Index> region, Eigen::MatrixXd solution, SolverBackend backend,
                                                      double compression_tolerance, std::vector<std::string> warnings,
                                                      const PrecomputeTimings& timings, KeptFactorization kept) {
  if (!mesh) throw InvalidArgumentError("GreensTable::from_solution: no mesh");
  const BoundaryConditions& base = problem.boundary_conditions;
  const Index n = 3 * mesh->num_elements(), R = static_cast<Index>(region.size());
  if (base.num_elements() != mesh->num_elements() || solution.rows() != n || solution.cols() != 3 * R + 1)
    throw InvalidArgumentError("GreensTable::from_solution: the solution is " + std::to_string(solution.rows()) + " x " +
                               std::to_string(solution.cols()) + ", expected " + std::to_string(n) + " x " + std::to_string(3 * R + 1));
  if (!solution.allFinite()) throw SolverError("GreensTable: the table has non-finite entries");
  GreensTable table;
  table.key_ = make_greens_table_key(*mesh, problem.material, base, problem.gravity, problem.quadrature);
  table.key_.backend = backend;
  table.key_.compression_tolerance = backend == SolverBackend::Dense ? 0.0 : compression_tolerance;
  table.base_kinds_ = base.kinds();
  table.region_ = std::move(region);
  table.warnings_ = std::move(warnings);
  table.timings_ = timings;
  table.quadrature_ = problem.quadrature;
  table.base_values_ = base.values();
  table.mesh_ = std::move(mesh);
  table.set_base_state(base, solution.col(3 * R));
  solution.conservativeResize(n, 3 * R);
  table.set_columns_from_solution(std::move(solution));
  table.build_slots();
  if (kept.factors) {
    if (kept.factors->size() != n || kept.rhs.size() != n)
      throw InvalidArgumentError("GreensTable::from_solution: the kept factorisation is of order " + std::to_string(kept.factors->size()) +
                                 " with a right-hand side of " + std::to_string(kept.rhs.size()) + ", expected " + std::to_string(n));
    table.solver_ = std::make_shared<const LowRankUpdatedLu>(std::move(kept.factors));
    table.rhs_ = std::move(kept.rhs);
    table.recompute_ = std::move(kept.recompute);
  }
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

namespace detail {
/// A matrix's storage as a table's column buffer: the matrix moves into the buffer's owner (no copy).
inline std::shared_ptr<double> storage_of(Eigen::MatrixXd&& m) {
  auto owner = std::make_shared<Eigen::MatrixXd>(std::move(m));
  return std::shared_ptr<double>(owner, owner->data());
}
}  // namespace detail

BEMSURG_INLINE void GreensTable::set_columns_from_solution(Eigen::MatrixXd&& X) {
  const Index rows = X.rows(), cols = X.cols();
  set_columns_from_solution(detail::storage_of(std::move(X)), rows, cols);
}

BEMSURG_INLINE void GreensTable::set_columns_from_solution(std::shared_ptr<double> data, Index rows, Index cols) {
  // Rows of displacement-prescribed dofs: the solution there is a traction (kept as reactions_,
  // which the cut updates need); the table holds the change of the prescribed displacement, zero.
  columns_data_ = std::move(data);
  columns_rows_ = rows;
  columns_cols_ = cols;
  Eigen::Map<Eigen::MatrixXd> X = writable_columns();
  const Index n = rows;
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
}

BEMSURG_INLINE BoundaryConditions GreensTable::base_conditions() const {
  BoundaryConditions bc(key_.num_elements);
  for (Index k = 0; k < num_dofs(); ++k)
    bc.prescribe_component(k / 3, static_cast<int>(k % 3), base_kinds_[static_cast<std::size_t>(k)],
                           base_values_.size() == num_dofs() ? base_values_(k) : 0.0);
  return bc;
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> GreensTable::refactored() const {
  if (!mesh_) throw InvalidArgumentError("GreensTable::refactored: this table has no mesh (read from a file)");
  auto out = std::make_shared<GreensTable>(recomputed_on(mesh_, base_conditions(), region_));
  out->version_ = version_;
  return out;
}

BEMSURG_INLINE GreensTable GreensTable::recomputed_on(std::shared_ptr<const TriangleMesh> mesh, const BoundaryConditions& base,
                                                      const std::vector<Index>& region) const {
  if (recompute_) return recompute_(std::move(mesh), key_.material, base, key_.gravity, quadrature_, region);
  return compute_on(std::move(mesh), key_.material, base, key_.gravity, quadrature_, region, 0.0, solver_ && solver_->has_rows());
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> GreensTable::with_young_modulus(double young_modulus, double gravity_factor) const {
  if (!(young_modulus > 0.0) || !std::isfinite(young_modulus))
    throw InvalidArgumentError("GreensTable::with_young_modulus: Young's modulus must be a finite positive number");
  if (!std::isfinite(gravity_factor)) throw InvalidArgumentError("GreensTable::with_young_modulus: the gravity factor must be finite");
  const double scale = key_.material.young_modulus / young_modulus;  // displacements scale as 1/E
  for (Index k = 0; k < num_dofs(); ++k) {
    const bool displacement = base_kinds_[static_cast<std::size_t>(k)] == BcKind::Displacement;
    const double value = base_values_.size() == num_dofs() ? base_values_(k) : 0.0;
    if (value == 0.0) continue;
    if (displacement && scale != 1.0)
      throw InvalidArgumentError("GreensTable::with_young_modulus: element " + std::to_string(k / 3) +
                                 " has a prescribed non-zero displacement, so a new E does not scale the table; recompute it");
    if (gravity_factor != 1.0)
      throw InvalidArgumentError("GreensTable::with_young_modulus: element " + std::to_string(k / 3) +
                                 " has a prescribed non-zero value, so scaling gravity does not scale the base state; recompute it");
  }
  auto out = std::make_shared<GreensTable>(*this);
  GreensTable& t = *out;
  t.key_.material.young_modulus = young_modulus;
  t.key_.gravity = gravity_factor * key_.gravity;
  // The displacement of traction dofs scales as 1/E (and with gravity); the reactions on displacement
  // dofs only with gravity; prescribed values stay (zero wherever a factor applies, checked above).
  for (Index k = 0; k < num_dofs(); ++k) {
    if (base_kinds_[static_cast<std::size_t>(k)] == BcKind::Traction)
      t.base_displacement_(k) *= scale * gravity_factor;
    else
      t.base_traction_(k) *= gravity_factor;
  }
  // The copy shares this table's storage (immutable once published); scaled columns get their own.
  // The same E keeps the columns: a viewer that republishes every cut step's table at the user's E
  // and gravity then copies no table (docs/viewer.md).
  if (scale != 1.0) {
    t.columns_data_ = SnapshotBufferPool::fresh(columns_rows_ * columns_cols_);
    t.writable_columns() = scale * columns();
  }
  t.solver_.reset();  // A* changes with E: no cut update from a rescaled table
  t.rhs_.resize(0);
  return out;
}

BEMSURG_INLINE GreensTable::GreensTable(GreensTableKey key, std::vector<Index> region, Eigen::VectorXd base_displacement,
                                        Eigen::VectorXd base_traction, std::vector<BcKind> base_kinds, Eigen::MatrixXd columns)
    : key_(key),
      region_(std::move(region)),
      base_displacement_(std::move(base_displacement)),
      base_traction_(std::move(base_traction)),
      base_kinds_(std::move(base_kinds)) {
  const Index n = 3 * key_.num_elements;
  if (base_displacement_.size() != n || base_traction_.size() != n || static_cast<Index>(base_kinds_.size()) != n || columns.rows() != n ||
      columns.cols() != 3 * static_cast<Index>(region_.size()))
    throw ResourceError("GreensTable: stored parts have inconsistent sizes");
  base_values_.resize(n);
  for (Index k = 0; k < n; ++k)
    base_values_(k) = base_kinds_[static_cast<std::size_t>(k)] == BcKind::Traction ? base_traction_(k) : base_displacement_(k);
  for (Index e : region_)
    if (e < 0 || e >= key_.num_elements) throw ResourceError("GreensTable: stored region element out of range");
  build_slots();
  columns_rows_ = columns.rows();
  columns_cols_ = columns.cols();
  columns_data_ = detail::storage_of(std::move(columns));
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
  const Index ld = columns_rows_;
  for (Index c = 0; c < count; ++c) {
    const double* c0 = column_data(elements[c]);
    const double* c1 = c0 + ld;
    const double* c2 = c1 + ld;
    const double tx = tractions[3 * c], ty = tractions[3 * c + 1], tz = tractions[3 * c + 2];
    for (Index i = 0; i < n; ++i) out[i] += tx * c0[i] + ty * c1[i] + tz * c2[i];
  }
}

}  // namespace bemsurg
