// bemsurg/cutting/cut_change.hpp: what a cut step changes in the BEM system, integrated anew only
// for the elements the step touched (docs/design.md §7 and §9; Wang et al. 2007 §5.3).
//
// A MeshDelta (mesh/mesh_delta.hpp) names the modified elements M (same id, new geometry) and
// the added ones N (appended). Unchanged elements keep their geometry, so H and G between them are
// unchanged (the diagonal blocks are evaluated directly, not from row sums: docs/design.md §4).
// Only the rows and columns of D = M + N change: integrate_cut_change() assembles them on the cut
// mesh (InfluenceAssembler::assemble_rows / assemble_columns) and, for M, on the mesh before the
// cut, so that the difference A* - A*_before is known exactly without keeping H and G. Gravity:
// the full right-hand side of the rows D, and the contributions of the changed elements to every
// row (before and after), which is all that changes in the other rows.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"
#include "bemsurg/timing.hpp"

namespace bemsurg {

/// Throws InvalidArgumentError unless `delta` describes the step from `before` to `after` as the
/// contract says: sizes match, modified ids ascending and < elements_before, added exactly
/// elements_before .. elements_after-1, no removed elements (updates refuse them rather than guess).
inline void check_mesh_delta(const MeshDelta& delta, const TriangleMesh& before, const TriangleMesh& after) {
  if (!delta.removed.empty())
    throw InvalidArgumentError("cut update: the delta removes " + std::to_string(delta.removed.size()) + " element(s) (first: " +
                               std::to_string(delta.removed.front()) + "); retiring element ids is not supported by the exact update");
  if (delta.elements_before != before.num_elements() || delta.elements_after != after.num_elements())
    throw InvalidArgumentError("cut update: the delta is for " + std::to_string(delta.elements_before) + " -> " +
                               std::to_string(delta.elements_after) + " elements, the meshes have " +
                               std::to_string(before.num_elements()) + " -> " + std::to_string(after.num_elements()));
  if (delta.elements_after - delta.elements_before != static_cast<Index>(delta.added.size()))
    throw InvalidArgumentError("cut update: the delta adds " + std::to_string(delta.added.size()) + " elements but the mesh grew by " +
                               std::to_string(delta.elements_after - delta.elements_before));
  for (std::size_t i = 0; i < delta.added.size(); ++i)
    if (delta.added[i] != delta.elements_before + static_cast<Index>(i))
      throw InvalidArgumentError("cut update: added element " + std::to_string(delta.added[i]) + " is not appended in order (expected " +
                                 std::to_string(delta.elements_before + static_cast<Index>(i)) + ")");
  for (std::size_t i = 0; i < delta.modified.size(); ++i) {
    const Index e = delta.modified[i];
    if (e < 0 || e >= delta.elements_before || (i > 0 && e <= delta.modified[i - 1]))
      throw InvalidArgumentError("cut update: modified element " + std::to_string(e) +
                                 " is out of range or out of order (ascending ids below " + std::to_string(delta.elements_before) + ")");
  }
}

/// The boundary conditions after a cut: old elements keep theirs (modified ones too), new cut
/// surface is traction-free (docs/design.md §7).
inline BoundaryConditions conditions_after_cut(const BoundaryConditions& before, const MeshDelta& delta) {
  BoundaryConditions after(delta.elements_after);
  for (Index k = 0; k < before.num_dofs(); ++k) after.prescribe_component(k / 3, static_cast<int>(k % 3), before.kind(k), before.value(k));
  return after;
}

/// The rows and columns of H, G and gravity for the elements a cut step changed (D = M + N), on the cut mesh and, for M,
/// on the mesh before the cut (integrate_cut_change): enough to know the change of A* and of the right-hand side exactly.
/// \ingroup cutting
struct CutChange {
  Index n_before = 0, n_after = 0;  // equations (3 per element)
  std::vector<Index> elements;      // D: modified (ascending), then added
  std::vector<Index> dofs;          // 3 per element of D, in that order (d = 3|D|)
  Index num_modified_dofs = 0;      // the first 3|M| of dofs
  // After the cut (the new mesh): rows and columns of D.
  Eigen::MatrixXd rows_H, rows_G;  // d x n_after
  Eigen::MatrixXd cols_H, cols_G;  // n_after x d
  Eigen::VectorXd rows_gravity;    // d: the gravity term of the rows D (all elements)
  Eigen::VectorXd cols_gravity;    // n_after: the gravity term from the elements D only, every row
  // Before the cut (the old mesh), for M only.
  Eigen::MatrixXd old_rows_H, old_rows_G;  // 3|M| x n_before
  Eigen::MatrixXd old_cols_H, old_cols_G;  // n_before x 3|M|
  Eigen::VectorXd old_cols_gravity;        // n_before: gravity from the elements M only (old geometry)
  double integration_seconds = 0.0;

  Index size() const { return static_cast<Index>(dofs.size()); }
};

/// Integrates the rows and columns of the changed elements on both meshes (checks the delta first).
inline CutChange integrate_cut_change(const TriangleMesh& before, const TriangleMesh& after, const MeshDelta& delta,
                                      const Material& material, const QuadratureOptions& quadrature, const Eigen::Vector3d& gravity) {
  check_mesh_delta(delta, before, after);
  const auto t0 = SteadyClock::now();
  CutChange c;
  c.n_before = before.num_dofs();
  c.n_after = after.num_dofs();
  c.elements = delta.changed();
  for (Index e : c.elements)
    for (int a = 0; a < 3; ++a) c.dofs.push_back(3 * e + a);
  c.num_modified_dofs = 3 * static_cast<Index>(delta.modified.size());
  // H, G and the gravity term in one pass per block: the gravity integrand comes from the pairs'
  // quadrature points (InfluenceAssembler::assemble_rows / assemble_columns).
  {
    const InfluenceAssembler assembler(after, material, quadrature);
    assembler.assemble_rows(c.elements, c.rows_H, c.rows_G, &c.rows_gravity, gravity);
    assembler.assemble_columns(c.elements, c.cols_H, c.cols_G, &c.cols_gravity, gravity);
  }
  {
    const InfluenceAssembler assembler(before, material, quadrature);
    assembler.assemble_rows(delta.modified, c.old_rows_H, c.old_rows_G);
    assembler.assemble_columns(delta.modified, c.old_cols_H, c.old_cols_G, &c.old_cols_gravity, gravity);
  }
  c.integration_seconds = seconds_since(t0);
  return c;
}

/// Rows D of A* after the cut (d x n_after): column k is H's for a traction dof, -G's otherwise.
inline Eigen::MatrixXd system_rows_after(const CutChange& c, const BoundaryConditions& after) {
  Eigen::MatrixXd X(c.size(), c.n_after);
  for (Index k = 0; k < c.n_after; ++k) X.col(k) = after.kind(k) == BcKind::Traction ? c.rows_H.col(k) : Eigen::VectorXd(-c.rows_G.col(k));
  return X;
}

/// Columns D of A* after the cut (n_after x d).
inline Eigen::MatrixXd system_columns_after(const CutChange& c, const BoundaryConditions& after) {
  Eigen::MatrixXd Y(c.n_after, c.size());
  for (Index j = 0; j < c.size(); ++j) {
    const Index k = c.dofs[static_cast<std::size_t>(j)];
    Y.col(j) = after.kind(k) == BcKind::Traction ? c.cols_H.col(j) : Eigen::VectorXd(-c.cols_G.col(j));
  }
  return Y;
}

/// Rows D of blockdiag(A*_before, I) (d x n_after): the old rows of M, unit rows for N.
inline Eigen::MatrixXd system_rows_before(const CutChange& c, const BoundaryConditions& before) {
  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(c.size(), c.n_after);
  for (Index k = 0; k < c.n_before; ++k)
    X.col(k).head(c.num_modified_dofs) = before.kind(k) == BcKind::Traction ? c.old_rows_H.col(k) : Eigen::VectorXd(-c.old_rows_G.col(k));
  for (Index j = c.num_modified_dofs; j < c.size(); ++j) X(j, c.dofs[static_cast<std::size_t>(j)]) = 1.0;
  return X;
}

/// Columns D of blockdiag(A*_before, I) (n_after x d).
inline Eigen::MatrixXd system_columns_before(const CutChange& c, const BoundaryConditions& before) {
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(c.n_after, c.size());
  for (Index j = 0; j < c.num_modified_dofs; ++j) {
    const Index k = c.dofs[static_cast<std::size_t>(j)];
    Y.col(j).head(c.n_before) = before.kind(k) == BcKind::Traction ? c.old_cols_H.col(j) : Eigen::VectorXd(-c.old_cols_G.col(j));
  }
  for (Index j = c.num_modified_dofs; j < c.size(); ++j) Y(c.dofs[static_cast<std::size_t>(j)], j) = 1.0;
  return Y;
}

/// The right-hand side R_bc + R_G after the cut from the one before (`rhs_before`, n_before):
/// rows D anew; every other row changes by the changed columns' prescribed-value terms and the
/// changed elements' gravity.
inline Eigen::VectorXd rhs_after_cut(const CutChange& c, const Eigen::VectorXd& rhs_before, const BoundaryConditions& before,
                                     const BoundaryConditions& after) {
  if (rhs_before.size() != c.n_before) throw InvalidArgumentError("rhs_after_cut: the right-hand side has the wrong size");
  Eigen::VectorXd b = Eigen::VectorXd::Zero(c.n_after);
  b.head(c.n_before) = rhs_before;
  b += c.cols_gravity;
  b.head(c.n_before) -= c.old_cols_gravity;
  auto term = [](BcKind kind, double value, const auto& Hcol, const auto& Gcol) -> Eigen::VectorXd {
    return kind == BcKind::Traction ? Eigen::VectorXd(value * Gcol) : Eigen::VectorXd(-value * Hcol);
  };
  for (Index j = 0; j < c.size(); ++j) {
    const Index k = c.dofs[static_cast<std::size_t>(j)];
    if (after.value(k) != 0.0) b += term(after.kind(k), after.value(k), c.cols_H.col(j), c.cols_G.col(j));
    if (j < c.num_modified_dofs && before.value(k) != 0.0)
      b.head(c.n_before) -= term(before.kind(k), before.value(k), c.old_cols_H.col(j), c.old_cols_G.col(j));
  }
  // Rows D anew, from the full rows.
  Eigen::VectorXd known_t = Eigen::VectorXd::Zero(c.n_after), known_u = Eigen::VectorXd::Zero(c.n_after);
  for (Index k = 0; k < c.n_after; ++k) (after.kind(k) == BcKind::Traction ? known_t : known_u)(k) = after.value(k);
  const Eigen::VectorXd rows = c.rows_gravity + c.rows_G * known_t - c.rows_H * known_u;
  for (Index j = 0; j < c.size(); ++j) b(c.dofs[static_cast<std::size_t>(j)]) = rows(j);
  return b;
}

}  // namespace bemsurg
