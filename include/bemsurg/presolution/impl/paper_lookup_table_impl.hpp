// Implementation of bemsurg/presolution/paper_lookup_table.hpp: the paper's Up/Tp tables
// (Wang et al. 2007 eq. 10) derived from the compliance table, Up_j = G_{:,J} G_JJ^{-1}.
#pragma once

#include "bemsurg/config.hpp"

#include <Eigen/LU>
#include <string>

#include "bemsurg/error.hpp"

namespace bemsurg {

BEMSURG_INLINE PaperLookupTable::PaperLookupTable(const TriangleMesh& mesh, const GreensTable& table) : table_(table), area_(mesh.areas()) {
  if (table.empty() || mesh.num_elements() != table.num_elements())
    throw ContactError("PaperLookupTable: the table is empty or was computed for another mesh");
  const Index R = static_cast<Index>(table.region().size());
  up_.resize(table.num_dofs(), 3 * R);
  tp_.resize(3, 3 * R);
  for (Index s = 0; s < R; ++s) {
    const Index j = table.region()[static_cast<std::size_t>(s)];
    const Eigen::Matrix3d gjj = table.block(j, j);
    Eigen::FullPivLU<Eigen::Matrix3d> lu(gjj);
    if (!lu.isInvertible()) throw SolverError("PaperLookupTable: G_JJ of element " + std::to_string(j) + " is singular");
    const Eigen::Matrix3d inv = lu.inverse();
    tp_.block<3, 3>(0, 3 * s) = inv;
    up_.middleCols(3 * s, 3).noalias() = table.columns().middleCols(3 * s, 3) * inv;
  }
}

BEMSURG_INLINE Index PaperLookupTable::slot(Index element) const {
  if (element < 0 || element >= table_.num_elements() || table_.region_slot(element) < 0)
    throw ContactError("PaperLookupTable: element " + std::to_string(element) + " has no table entry (outside the region)");
  return table_.region_slot(element);
}

BEMSURG_INLINE void PaperLookupTable::displacement_field(Index element, const Eigen::Vector3d& push, Eigen::VectorXd& u) const {
  if (u.size() != table_.num_dofs()) throw ContactError("PaperLookupTable::displacement_field: u has the wrong size");
  u = table_.base_displacement();
  u.noalias() += up_.middleCols(3 * slot(element), 3) * push;
}

BEMSURG_INLINE Eigen::Vector3d PaperLookupTable::traction(Index element, const Eigen::Vector3d& push) const {
  return table_.base_traction().segment<3>(3 * element) + tp_.block<3, 3>(0, 3 * slot(element)) * push;
}

}  // namespace bemsurg
