// bemsurg/types.hpp: the small shared types every module uses. Element e owns the unknowns
// 3e, 3e+1, 3e+2 (x, y, z); per-vertex and per-element fields are row-major n x 3 matrices so
// that a row is one point or one element (docs/design.md).
#pragma once

#include <Eigen/Core>

namespace bemsurg {

using Index = Eigen::Index;
using Vec3 = Eigen::Vector3d;
/// One row per vertex or per element, columns x, y, z.
using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatrixX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

}  // namespace bemsurg
