// bemsurg/types.hpp: the small shared types every module uses. Element e owns the unknowns
// 3e, 3e+1, 3e+2 (x, y, z); per-vertex and per-element fields are row-major n x 3 matrices so
// that a row is one point or one element (docs/design.md).
#pragma once

#include <Eigen/Core>

/// \defgroup core Core
/// \brief The top-level headers every module shares: small types (types.hpp), errors (error.hpp), the
/// material (material.hpp), mathematical constants (constants.hpp), numbers as text in every locale
/// (number_text.hpp), clocks (timing.hpp), the memory budget (memory_budget.hpp), large dense storage
/// (dense_storage.hpp) and how definitions are compiled (config.hpp). The other modules have a module
/// header each (bemsurg/mesh.hpp, ...); the core's headers are included one by one or through bemsurg/bemsurg.hpp.

namespace bemsurg {

using Index = Eigen::Index;
using Vec3 = Eigen::Vector3d;
/// One row per vertex or per element, columns x, y, z.
using RowMatrixX3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatrixX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

}  // namespace bemsurg
