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
// which is contiguous (measured here: three columns ~1 us, three rows of a column-major
// n = 4752 table ~100 us).
// Rows of displacement-prescribed dofs hold the prescribed change, zero.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"
#include "bemsurg/solvers/lu_in_place.hpp"

namespace bemsurg {

struct GreensTableOptions {
  /// Elements where tools may act (each must be free: traction prescribed on all three
  /// components). Empty: every free element.
  std::vector<Index> region;
  /// Gravity acceleration of the base state (body force = density * gravity).
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  QuadratureOptions quadrature;
  /// Refuse (ResourceError) when the estimate exceeds this many bytes; 0 = 80 % of physical memory.
  double memory_limit_bytes = 0.0;
};

/// Wall-clock seconds of the three phases of the one-time precomputation.
struct PrecomputeTimings {
  double assembly_seconds = 0.0;       // H, G, gravity, A* and the right-hand sides
  double factorization_seconds = 0.0;  // LU of A* (LAPACK dgetrf when BLAS is linked)
  double table_seconds = 0.0;          // multi-right-hand-side back-substitution (dgetrs)
};

/// What a table was computed for; a saved table is used only when all of it matches.
struct GreensTableKey {
  std::uint64_t mesh_hash = 0;        // vertices and faces, bit for bit
  std::uint64_t conditions_hash = 0;  // kinds and values of the base boundary conditions
  std::uint64_t quadrature_hash = 0;  // QuadratureOptions
  Index num_elements = 0;
  Material material;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
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

class GreensTable {
 public:
  GreensTable() = default;

  /// Bytes the precomputation needs at its peak: H and G during assembly plus A* (3 n^2 doubles
  /// at most at once), and the table n x 3|region| with the base state.
  static double estimate_bytes(Index num_elements, Index region_elements);
  /// The default limit: 80 % of this machine's physical memory (bemsurg/memory_budget.hpp).
  static double default_memory_limit_bytes();

  /// Assembles, factorises A* once, solves the base state and the region's columns. Throws
  /// ResourceError (with the estimate) when it would not fit, BoundaryConditionError for an
  /// unsupported body or a region element that is not free, SolverError for a singular A*.
  static GreensTable compute(const TriangleMesh& mesh, const Material& material, const BoundaryConditions& base,
                             const GreensTableOptions& options = {});

  /// From stored parts (the table file reader); checks that the sizes agree.
  GreensTable(GreensTableKey key, std::vector<Index> region, Eigen::VectorXd base_displacement,
              Eigen::VectorXd base_traction, std::vector<BcKind> base_kinds, Eigen::MatrixXd columns);

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
  /// n x 3|region|: displacement of every dof per unit traction on each region dof.
  const Eigen::MatrixXd& columns() const { return columns_; }
  /// Displacement of element `row` (3) per unit traction on element `col` (3): G_{row,col}.
  Eigen::Matrix3d block(Index row, Index col) const {
    return columns_.block<3, 3>(3 * row, 3 * region_slot(col));
  }
  /// Pointer to the first of the three columns of region element `col` (contiguous, length n each).
  const double* column_data(Index col) const { return columns_.data() + 3 * region_slot(col) * columns_.rows(); }

  const PrecomputeTimings& timings() const { return timings_; }
  std::size_t bytes() const {
    return static_cast<std::size_t>(columns_.size() + 2 * base_displacement_.size()) * sizeof(double);
  }

  /// u = u_g + sum_c G_{:,c} t_c for extra tractions `tractions` (k x 3 rows) on region elements
  /// `elements`: the full field after contact, O(n k). `u` must have n entries (not resized).
  void displacement_field(const Index* elements, const double* tractions, Index count, Eigen::VectorXd& u) const;

 private:
  void build_slots();

  GreensTableKey key_;
  std::vector<Index> region_;
  std::vector<Index> slot_;
  Eigen::VectorXd base_displacement_;
  Eigen::VectorXd base_traction_;
  std::vector<BcKind> base_kinds_;
  Eigen::MatrixXd columns_;
  PrecomputeTimings timings_;
};


}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#include "bemsurg/presolution/impl/greens_table_impl.hpp"
