// tests/support/haptic_block.hpp: the small model the haptics tests drive (test_haptic_loop.cpp,
// test_haptic_continuity.cpp): a 1 x 1 x 0.5 block held at the bottom, soft (E = 2 kPa) so
// millimetre presses give newtons, with its table computed once and read from a file after that
// (cached_greens_table.hpp), and the same table scaled: what a cut's new table is to the loop.
#pragma once

#include <memory>
#include <vector>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "cached_greens_table.hpp"

namespace bemsurg::testing {

struct HapticBlock {
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const GreensTable> table;
  HapticBlock() {
    auto m = std::make_shared<TriangleMesh>(box_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 0.5), 6, 6, 3));
    std::vector<Index> bottom;
    for (Index e = 0; e < m->num_elements(); ++e)
      if (m->normal(e).z() < -0.99) bottom.push_back(e);
    const Material material{2000.0, 0.3, 1000.0};
    // Shared by many cases, each its own process under ctest: computed once, then read from its file.
    table = std::make_shared<const GreensTable>(
        cached_greens_table("haptic-loop-block", *m, material, supported_base_conditions(m->num_elements(), bottom), {}));
    mesh = m;
  }
};

inline HapticBlock& haptic_block() {
  static HapticBlock b;
  return b;
}

/// The same table with every compliance column scaled: a stiffer or softer body on the same mesh.
inline std::shared_ptr<const GreensTable> scaled_table(const GreensTable& t, double factor) {
  return std::make_shared<const GreensTable>(t.key(), t.region(), t.base_displacement(), t.base_traction(), t.base_kinds(),
                                             Eigen::MatrixXd(factor * t.columns()));
}

}  // namespace bemsurg::testing
