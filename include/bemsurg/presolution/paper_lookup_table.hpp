// bemsurg/presolution/paper_lookup_table.hpp: the paper's look-up tables [Up] and [Tp] (Wang et
// al. 2007 §5.1, eq. 10), kept as the explicitly named "paper" mode for comparison.
//
// The paper applies a unit displacement along x, y, z at each surface node j in turn (all other
// free nodes traction-free, no gravity) and stores the displacement of every node [Up] and the
// traction at the node [Tp]. A tool on node j pushing it by d beyond the self-weight state gives
//     u = u_g + Up_j d,   t_j = t_g,j + Tp_j d,   F = -a_j t_j.
// In terms of the compliance table: Up_j = G_{:,J} G_JJ^{-1}, Tp_j = G_JJ^{-1} (J = j's three
// dofs), which is exactly single-element bonded capacitance contact. It is exact for one touched
// node only; several nodes superposed from it are not (use CapacitanceContact). The force of a
// point tool depends on the element's size and does not converge under refinement.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/presolution/greens_table.hpp"

namespace bemsurg {

/// The paper's look-up tables [Up] and [Tp] (Wang et al. 2007 §5.1, eq. 10), built from the compliance table and kept as
/// the "paper" mode for comparison: exact for one touched element only (use CapacitanceContact for several).
/// \ingroup presolution
class PaperLookupTable {
 public:
  /// Builds Up and Tp for every element of the table's region (same memory as the table).
  PaperLookupTable(const TriangleMesh& mesh, const GreensTable& table);

  /// Tool on element j, pushing it by `push` beyond the base (self-weight) state.
  /// Displacement field (n entries; u must be sized): u = u_g + Up_j push. O(n).
  void displacement_field(Index element, const Eigen::Vector3d& push, Eigen::VectorXd& u) const;
  /// Traction on element j: t_g,j + Tp_j push. O(1).
  Eigen::Vector3d traction(Index element, const Eigen::Vector3d& push) const;
  /// Force on the tool: -a_j t_j. O(1) (the paper reports < 1e-7 s).
  Eigen::Vector3d force(Index element, const Eigen::Vector3d& push) const { return -area_(element) * traction(element, push); }

  /// n x 3 block of Up for element j; Tp_j.
  Eigen::Ref<const Eigen::MatrixXd> up(Index element) const { return up_.middleCols(3 * slot(element), 3); }
  Eigen::Matrix3d tp(Index element) const { return tp_.block<3, 3>(0, 3 * slot(element)); }

 private:
  Index slot(Index element) const;

  const GreensTable& table_;
  Eigen::VectorXd area_;
  Eigen::MatrixXd up_;  // n x 3|region|
  Eigen::MatrixXd tp_;  // 3 x 3|region|
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/presolution/impl/paper_lookup_table_impl.hpp"
#endif
