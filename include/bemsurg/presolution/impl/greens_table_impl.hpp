// Implementation of bemsurg/presolution/greens_table.hpp: the one-time precomputation of the
// compliance table (docs/design.md §6; Wang et al. 2007 §5.1). One LU of A*, then the base state and
// the region's unit-traction columns as one multi-right-hand-side back-substitution.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/quadrature/quadrature_cost.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bemsurg/solvers/lu_in_place.hpp"
#include "bemsurg/timing.hpp"


namespace bemsurg {

inline std::uint64_t fnv1a64(const void* data, std::size_t bytes, std::uint64_t seed) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = seed;
  for (std::size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

inline std::uint64_t hash_mesh(const TriangleMesh& mesh) {
  std::uint64_t h = fnv1a64(mesh.vertices().data(), static_cast<std::size_t>(mesh.vertices().size()) * sizeof(double));
  return fnv1a64(mesh.faces().data(), static_cast<std::size_t>(mesh.faces().size()) * sizeof(int), h);
}

inline std::uint64_t hash_conditions(const BoundaryConditions& bc) {
  std::vector<unsigned char> kinds(bc.kinds().size());
  for (std::size_t i = 0; i < kinds.size(); ++i) kinds[i] = static_cast<unsigned char>(bc.kinds()[i]);
  std::uint64_t h = fnv1a64(kinds.data(), kinds.size());
  return fnv1a64(bc.values().data(), static_cast<std::size_t>(bc.values().size()) * sizeof(double), h);
}

inline std::uint64_t hash_quadrature(const QuadratureOptions& q) {
  const double v[6] = {q.far_ratio, q.mid_ratio, double(q.mid_order), double(q.max_depth), double(q.polar_order),
                       q.polar_max_angle};
  return fnv1a64(v, sizeof(v));
}

inline GreensTableKey make_greens_table_key(const TriangleMesh& mesh, const Material& material, const BoundaryConditions& base,
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

inline BoundaryConditions supported_base_conditions(Index num_elements, const std::vector<Index>& supported) {
  BoundaryConditions bc(num_elements);
  for (Index e : supported) bc.prescribe_displacement(e, Eigen::Vector3d::Zero());
  return bc;
}

inline double GreensTable::estimate_bytes(Index num_elements, Index region_elements) {
  const double n = 3.0 * double(num_elements);
  // Peak: H and G (assembly) and A* live together briefly; then A* and the right-hand sides.
  return 8.0 * (3.0 * n * n + n * (3.0 * double(region_elements) + 1.0) + 4.0 * n);
}

inline double GreensTable::default_memory_limit_bytes() { return bemsurg::default_memory_limit_bytes(); }

inline GreensTable GreensTable::compute(const TriangleMesh& mesh, const Material& material, const BoundaryConditions& base,
                                 const GreensTableOptions& options) {
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
                        " (A*, H and G: " + format_gib(8.0 * 3.0 * double(n) * double(n)) + "; table: " +
                        format_gib(8.0 * double(n) * 3.0 * double(R)) + "), more than the limit of " + format_gib(limit) +
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
  lu_factor_and_solve_in_place(A, B, &table.timings_.factorization_seconds, &table.timings_.table_seconds);
  A.resize(0, 0);

  // Unknown x_k is u_k on traction dofs and t_k on displacement dofs: split into the two fields.
  table.base_displacement_.resize(n);
  table.base_traction_.resize(n);
  for (Index k = 0; k < n; ++k) {
    const bool t_known = base.kind(k) == BcKind::Traction;
    table.base_displacement_(k) = t_known ? B(k, 3 * R) : base.value(k);
    table.base_traction_(k) = t_known ? base.value(k) : B(k, 3 * R);
  }
  B.conservativeResize(n, 3 * R);
  for (Index k = 0; k < n; ++k)
    if (base.kind(k) == BcKind::Displacement) B.row(k).setZero();  // prescribed u does not change
  if (!B.allFinite()) throw SolverError("GreensTable: the table has non-finite entries");
  table.columns_.swap(B);
  table.build_slots();
  return table;
}

inline GreensTable::GreensTable(GreensTableKey key, std::vector<Index> region, Eigen::VectorXd base_displacement,
                         Eigen::VectorXd base_traction, std::vector<BcKind> base_kinds, Eigen::MatrixXd columns)
    : key_(key),
      region_(std::move(region)),
      base_displacement_(std::move(base_displacement)),
      base_traction_(std::move(base_traction)),
      base_kinds_(std::move(base_kinds)),
      columns_(std::move(columns)) {
  const Index n = 3 * key_.num_elements;
  if (base_displacement_.size() != n || base_traction_.size() != n || static_cast<Index>(base_kinds_.size()) != n ||
      columns_.rows() != n || columns_.cols() != 3 * static_cast<Index>(region_.size()))
    throw ResourceError("GreensTable: stored parts have inconsistent sizes");
  for (Index e : region_)
    if (e < 0 || e >= key_.num_elements) throw ResourceError("GreensTable: stored region element out of range");
  build_slots();
}

inline void GreensTable::build_slots() {
  slot_.assign(static_cast<std::size_t>(key_.num_elements), -1);
  for (std::size_t s = 0; s < region_.size(); ++s) {
    if (slot_[static_cast<std::size_t>(region_[s])] != -1)
      throw ResourceError("GreensTable: region element " + std::to_string(region_[s]) + " is listed twice");
    slot_[static_cast<std::size_t>(region_[s])] = static_cast<Index>(s);
  }
}

inline void GreensTable::displacement_field(const Index* elements, const double* tractions, Index count, Eigen::VectorXd& u) const {
  const Index n = num_dofs();
  if (u.size() != n) throw InvalidArgumentError("GreensTable::displacement_field: u must have " + std::to_string(n) + " entries");
  u = base_displacement_;
  // One thread, on purpose: the work streams contiguous columns (memory bound, ~0.4 ms for 50
  // elements at n = 15,000), and an OpenMP team here would wait for cores that the BLAS threads
  // and the haptic thread may be spinning on (measured: 8 ms stalls on 2 cores).
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
