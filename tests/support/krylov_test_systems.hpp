// krylov_test_systems.hpp: real BEM systems A* x = b (Wang et al. 2007 eq. 6) for the Krylov solver
// tests: a brain-like soft block (E = 3 kPa, nu = 0.45, rho = 1000 kg/m^3) standing on its bottom
// face (u = 0 there) under its own weight, traction-free elsewhere, and the LU solution of each.
// "perturbed" moves one top vertex down a little and re-assembles: the rows and columns of the
// elements around it change, as after an incremental cut (§5.3), so the old solution is a warm start.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/solvers/dense_lu.hpp"

namespace bemsurg_test {

struct BemSystem {
  bemsurg::TriangleMesh mesh;
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  Eigen::VectorXd x_lu;       // reference: dense LU with partial pivoting
  double lu_condition = 0.0;  // 1 / rcond (1-norm estimate)
};

inline bemsurg::Material soft_tissue() {
  bemsurg::Material m;
  m.young_modulus = 3000.0;
  m.poisson_ratio = 0.45;
  m.density = 1000.0;
  return m;
}

/// Box [0, 0.08] x [0, 0.06] x [0, 0.05] m with nx, ny, nz cells per edge; `push` moves the top
/// vertex nearest the centre of the top face down by that fraction of the box height.
inline BemSystem make_bem_system(int nx, int ny, int nz, double push = 0.0) {
  using namespace bemsurg;
  const Vec3 lo(0.0, 0.0, 0.0), hi(0.08, 0.06, 0.05);
  TriangleMesh mesh = box_mesh(lo, hi, nx, ny, nz);
  if (push != 0.0) {
    RowMatrixX3d v = mesh.vertices();
    const Vec3 target(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), hi.z());
    Index best = 0;
    for (Index i = 0; i < v.rows(); ++i)
      if ((v.row(i).transpose() - target).norm() < (v.row(best).transpose() - target).norm()) best = i;
    v(best, 2) -= push * (hi.z() - lo.z());
    mesh = TriangleMesh(v, mesh.faces());
  }
  const Material material = soft_tissue();
  BoundaryConditions bc(mesh.num_elements());
  for (Index e = 0; e < mesh.num_elements(); ++e)
    if (mesh.normal(e).z() < -0.9) bc.prescribe_displacement(e, Vec3::Zero());
  const InfluenceAssembler assembler(mesh, material);
  const InfluenceMatrices hg = assembler.assemble();
  BemSystem s{mesh, build_system_matrix(hg, bc), build_right_hand_side(hg, bc, assembler.gravity_vector(Vec3(0.0, 0.0, -9.81))), {}, 0.0};
  const DenseLu lu(s.A);
  s.x_lu = lu.solve(s.b);
  s.lu_condition = 1.0 / lu.rcond();
  return s;
}

}  // namespace bemsurg_test
