// bemsurg/presolution/capacitance_contact.hpp: exact contact on any set of elements at once by the
// capacitance-matrix method (James & Pai, ArtDefo, SIGGRAPH 1999; docs/design.md §6), on top of the
// compliance table of greens_table.hpp. It replaces the paper's superposition of single-node
// tables (Wang et al. 2007 eq. 10), which is exact for one touched node only.
//
// A contact is a list of constraint rows a = (element e_a, unit direction w_a): the displacement
// component w_a . u(e_a) is prescribed, the traction in that direction is the unknown lambda_a
// and the traction perpendicular to the element's rows keeps its base value. A bonded (or pinched)
// element has three rows (x, y, z); a frictionless one has one row along the contact normal. With
// S_ab = w_a^T G_{e_a e_b} w_b (the small system G_CC restricted to the rows):
//     S lambda = target - W^T u_g,C,     u = u_g + G_{:,C} W lambda,     F_tool = -sum_c a_c t_c.
// The capacitance matrix P = S^{-1} is kept explicitly, as James & Pai do: the force path is then
// one k x k matrix-vector product, and when a few rows join or leave the set P is bordered or
// reduced (Schur complements, O(k^2 m)) instead of refactorised (O(k^3)).
//
// Real-time discipline: after construction nothing here allocates (every buffer is sized for
// `capacity` rows) and nothing locks; solve() and force() are the haptic path, O(k^2) and O(k).
//
// Ownership (docs/design.md §9): the mesh and the table are immutable snapshots held by
// std::shared_ptr<const ...>, so a cut that builds a new table never pulls them from under a live
// contact. One thread owns a CapacitanceContact at a time (the haptic thread while it computes
// forces); other threads do not read it while it changes: the graphics thread takes the published
// (contact elements, tractions) of contact_tractions() and computes the field from the read-only
// table with its own buffers (GreensTable::displacement_field).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/presolution/greens_table.hpp"

namespace bemsurg {

/// One constraint row of a contact: the displacement component direction . u(element) is prescribed and the traction
/// along `direction` is the unknown; `tag` says which tool owns the row.
/// \ingroup presolution
struct ContactRow {
  Index element = 0;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit vector
  int tag = 0;                                           // which tool owns the row (forces are reported per tag)
};

/// Exact contact on any set of elements at once by the capacitance-matrix method (James & Pai 1999; docs/design.md §6)
/// on the compliance table: keeps P = S^-1 explicitly and borders or reduces it as rows join or leave. Allocation-free after construction.
/// \ingroup presolution
class CapacitanceContact {
 public:
  /// `mesh` gives areas (the force) and must be the table's mesh; both are shared snapshots.
  /// `capacity`: the most constraint rows at once (bonded elements take 3, frictionless 1), held to
  /// 3 x the table's region (only region elements can be in contact: more rows could never be used,
  /// and the five capacity^2 buffers of a large organ would cost gigabytes). Throws ContactError for a
  /// null or empty table, a mesh that is not the table's, capacity < 1.
  CapacitanceContact(std::shared_ptr<const TriangleMesh> mesh, std::shared_ptr<const GreensTable> table, Index capacity = 300);

  Index capacity() const { return capacity_; }
  Index num_rows() const { return k_; }
  Index num_elements() const { return num_elements_; }
  const ContactRow& row(Index a) const { return rows_[static_cast<std::size_t>(a)]; }
  bool contains(Index element) const { return rows_of_[static_cast<std::size_t>(element)] > 0; }

  // ---- structure: which rows are constrained (allocation-free within capacity) ----------------
  void clear();
  /// Adds rows and borders P with their Schur complement: O(k^2 m + m^3). Throws for an element
  /// outside the table's region, an element already in the set, a full set, or rows that make
  /// S singular (then nothing changes).
  void add_rows(const ContactRow* rows, Index m);
  /// The haptic-thread form of add_rows for rows already known valid (in the table's region, not
  /// yet in the set, unit directions): never throws or allocates; returns false and changes
  /// nothing when the rows exceed the capacity or make S singular.
  bool try_add_rows(const ContactRow* rows, Index m) noexcept;
  void add_bonded(Index element, int tag = 0);
  void add_normal(Index element, const Eigen::Vector3d& direction, int tag = 0);
  /// Drops every row of `element` (no-op when absent): P' = P_KK - P_KJ P_JJ^{-1} P_JK.
  void remove_element(Index element) noexcept;
  /// Recomputes P from S from scratch (O(k^3)); resets the round-off of many incremental updates.
  /// Throws SolverError when S is singular.
  void refactor();
  /// Number of incremental updates since the last refactor().
  Index updates_since_refactor() const { return updates_; }

  // ---- force path (haptic rate) ----------------------------------------------------------------
  /// Prescribed displacement component w_a . u(e_a) of row a, measured from the undeformed mesh
  /// (so "no change from the base state" is w_a . u_g(e_a)). Set every row before solve().
  void set_target(Index a, double value) { target_[static_cast<std::size_t>(a)] = value; }
  double target(Index a) const { return target_[static_cast<std::size_t>(a)]; }
  /// w_a . u_g(e_a): the target that leaves row a where the base state has it.
  double base_target(Index a) const;
  /// lambda = P (target - W^T u_g): O(k^2), allocation-free.
  void solve();
  /// Traction multiplier of row a after solve() (traction along w_a added to the base traction).
  double multiplier(Index a) const { return lambda_[static_cast<std::size_t>(a)]; }
  /// Force on the tool(s): -sum over contact elements of area * (base + contact traction). O(k).
  Eigen::Vector3d force() const { return force_of_tag(-1); }
  /// The same force straight from the targets, without the tractions: F = F_base + K (target -
  /// W^T u_g) with the 3 x k force operator K = -(A W)^T P kept up to date on every structure
  /// change. O(k): the haptic path when only the force is needed at a fixed contact set (the
  /// active set of unilateral tools needs solve()).
  Eigen::Vector3d force_for_targets() const;
  /// The same over the rows of one tool (tag >= 0): each hand's share when several act.
  Eigen::Vector3d force_of_tag(int tag) const;

  // ---- field (graphics rate) -----------------------------------------------------------------
  /// Total traction (base + contact) on a contact element after solve().
  Eigen::Vector3d traction(Index element) const;
  /// Displacement of any element after solve(): u_g,e + sum_a G_{e,e_a} w_a lambda_a, O(k).
  Eigen::Vector3d displacement_of(Index element) const;
  /// The full field (n entries, u must be sized): u_g + G_{:,C} t_C, O(n k). Allocates its own
  /// small buffers per call (graphics rate; it writes nothing shared). Another thread must not
  /// call it while the owner changes this object: publish contact_tractions() instead.
  void displacement_field(Eigen::VectorXd& u) const;
  /// Extra (contact) tractions per distinct contact element: elements and 3 values each; returns
  /// the count. Buffers must hold num_elements() entries. Allocation-free: this is what the
  /// haptic thread publishes for the graphics thread.
  Index contact_tractions(Index* elements, double* tractions) const noexcept;

  const TriangleMesh& mesh() const { return *mesh_; }
  const GreensTable& table() const { return *table_; }
  const std::shared_ptr<const TriangleMesh>& mesh_ptr() const { return mesh_; }
  const std::shared_ptr<const GreensTable>& table_ptr() const { return table_; }

 private:
  double s_entry(const ContactRow& a, const ContactRow& b) const;
  bool invert_into(double* m, double* inv, Index size) noexcept;  // Gauss-Jordan, m destroyed; false: singular
  bool add_rows_unchecked(const ContactRow* rows, Index m) noexcept;
  bool refactor_unchecked() noexcept;
  void swap_rows(Index i, Index j);
  void update_force_operator();

  std::shared_ptr<const TriangleMesh> mesh_;
  std::shared_ptr<const GreensTable> table_;
  Index capacity_;
  Index k_ = 0;
  Index num_elements_ = 0;
  Index updates_ = 0;
  std::vector<ContactRow> rows_;
  std::vector<char> first_row_;                            // per row: the first row of its element (counts base traction)
  std::vector<int> rows_of_;                               // per mesh element: number of rows it has in the set
  std::vector<double> P_;                                  // capacity x capacity, column-major, leading dimension capacity
  std::vector<double> work_a_, work_b_, work_c_, work_d_;  // capacity x capacity each
  std::vector<double> target_, rhs_, lambda_;
  std::vector<double> row_base_;                          // per row: w_a . u_g(e_a)
  std::vector<double> force_op_;                          // 3 x capacity (component-major): K = -(A W)^T P
  Eigen::Vector3d base_force_ = Eigen::Vector3d::Zero();  // -sum a_c t_base,c over contact elements
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/presolution/impl/capacitance_contact_impl.hpp"
#endif
