// tests/support/half_space_table.hpp: a stand-in compliance table for exercising the haptic path
// at scale (benchmarks/bench_haptic_loop, the continuity test): the Boussinesq-Cerruti half-space
// surface compliance between element centroids, written straight into GreensTable's column layout
// (docs/contact.md §1), for a block whose top face is finely meshed under the tools. The loop's
// cost and the contact model's behaviour depend on n, the contact set and the table's layout, not
// on how the table was computed; the BEM precomputation of thousands of elements takes minutes and
// gigabytes and is measured by bench_contact. Not a substitute for GreensTable::compute anywhere
// physics is asserted against the BEM.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"

namespace bemsurg::haptics {

struct HalfSpaceBlock {
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const GreensTable> table;
  double fine_edge = 0.0;
};

/// A 100 x 100 x 50 mm block (top face at z = 0, centred on the z axis), element edge h on the top
/// face within `fine` of the centre, graded (ratio 1.5) to h_max elsewhere; the bottom held; table
/// columns for the top elements within `region` of the centre. Surface point force F on a
/// half-space, displacement at distance r (Boussinesq, Cerruti): u_z = (1 - nu^2) F_z / (pi E r),
/// u_t = (1 + nu) / (pi E r) [(1 - nu) F_t + nu (F . r^)(r^)_t]; the tangential-normal coupling
/// (proportional to 1 - 2 nu) is left out so the table is symmetric. An element's own column uses
/// the mean of 1/r over a disc of its area, 2/c with c = sqrt(area / pi).
inline HalfSpaceBlock half_space_block(double h, double h_max, double fine, double region, const Material& material) {
  using Vec3 = Eigen::Vector3d;
  const double L = 0.05;
  const auto xs = graded_coordinates(-L, L, 0.0, h, h_max, 1.5, fine);
  const auto zs = graded_coordinates(-L, 0.0, 0.0, std::max(2.0 * h, 0.002), h_max, 1.5, 0.0);
  auto mesh = std::make_shared<TriangleMesh>(box_mesh_from_grid(xs, xs, zs));
  const Index E = mesh->num_elements();
  std::vector<Index> bottom, top;
  for (Index e = 0; e < E; ++e) {
    if (mesh->normal(e).z() < -0.99) bottom.push_back(e);
    if (mesh->normal(e).z() > 0.99 && mesh->centroid(e).head<2>().norm() < region) top.push_back(e);
  }
  const BoundaryConditions bc = supported_base_conditions(E, bottom);
  const GreensTableKey key = make_greens_table_key(*mesh, material, bc, Vec3::Zero(), QuadratureOptions{});
  const double nu = material.poisson_ratio, Y = material.young_modulus;
  Eigen::MatrixXd columns = Eigen::MatrixXd::Zero(3 * E, 3 * static_cast<Index>(top.size()));
  std::vector<char> held(static_cast<std::size_t>(E), 0);
  for (Index e : bottom) held[static_cast<std::size_t>(e)] = 1;
  for (std::size_t s = 0; s < top.size(); ++s) {
    const Index j = top[s];
    const Vec3 xj = mesh->centroid(j);
    const double aj = mesh->area(j), cj = std::sqrt(aj / numbers::pi);
    for (Index i = 0; i < E; ++i) {
      if (held[static_cast<std::size_t>(i)]) continue;  // displacement prescribed: no change
      const Vec3 d = mesh->centroid(i) - xj;
      const double r = d.norm();
      const double inv = i == j ? 2.0 / cj : 1.0 / std::max(r, 0.5 * cj);
      const double dx = i == j ? 0.0 : d.x() / r, dy = i == j ? 0.0 : d.y() / r;
      const double f = aj * (1.0 + nu) / (numbers::pi * Y) * inv;  // per unit traction on j (force a_j t_j)
      Eigen::Matrix3d G;
      G << f * ((1.0 - nu) + nu * dx * dx), f * nu * dx * dy, 0.0,  //
          f * nu * dx * dy, f * ((1.0 - nu) + nu * dy * dy), 0.0,   //
          0.0, 0.0, f * (1.0 - nu);
      columns.block<3, 3>(3 * i, 3 * static_cast<Index>(s)) = G;
    }
  }
  HalfSpaceBlock b;
  b.fine_edge = h;
  b.table = std::make_shared<const GreensTable>(key, top, Eigen::VectorXd::Zero(3 * E), Eigen::VectorXd::Zero(3 * E), bc.kinds(),
                                                std::move(columns));
  b.mesh = std::move(mesh);
  return b;
}

}  // namespace bemsurg::haptics
