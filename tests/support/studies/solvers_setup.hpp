// solvers_setup.hpp: the systems the solver studies of issue 25 sweep (docs/stability.md (a), (e)):
// closed-form problems whose exact boundary traces are known for any Poisson's ratio (Kelvin's point
// force outside a box, Lamé's hollow sphere), assembled into A* x = b, and the 2-norm condition number
// of A* by SVD. The systems are built here, below solve_elastostatic, so the sweep passes its refusal
// at kPoissonRatioLimit (bemsurg/material.hpp) on purpose.
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <string>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/solvers/linear_solve.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

namespace bemsurg::stability_setup {

/// Which closed-form problem: which field, on which mesh, held where.
enum class PoissonCase {
  KelvinDirichlet,  // Kelvin field outside a box, displacement prescribed everywhere (tractions solved)
  KelvinMixed,      // the same, displacement on the half x < 0, traction on the rest
  LameMixed         // Lamé's hollow sphere (1, 2), inner surface displaced, outer loaded by its traction
};

inline const char* to_string(PoissonCase c) {
  switch (c) {
    case PoissonCase::KelvinDirichlet: return "kelvin_dirichlet";
    case PoissonCase::KelvinMixed: return "kelvin_mixed";
    case PoissonCase::LameMixed: return "lame_mixed";
  }
  return "unknown";
}

/// One assembled closed-form problem: mesh, conditions, A* and b, and the exact traces.
struct ClosedFormSystem {
  TriangleMesh mesh;
  BoundaryConditions bc;
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  BoundarySolution exact;
};

/// `level` 1 or 2: the box has 3l x 2l x 2l cells per edge (64 or 256 elements), the sphere's
/// shells l subdivisions (160 or 640 elements).
inline ClosedFormSystem closed_form_system(PoissonCase c, double nu, int level) {
  using namespace verification;
  const Material m{1.0, nu, 0.0};
  ClosedFormSystem s;
  ElasticField field;
  std::function<bool(Index)> held;
  if (c == PoissonCase::LameMixed) {
    s.mesh = hollow_sphere_mesh(Eigen::Vector3d::Zero(), 1.0, 2.0, level, level);
    field = lame_field(m, Eigen::Vector3d::Zero(), 1.0, 2.0, 1.0, 0.0);
    held = [&s](Index e) { return s.mesh.centroid(e).norm() < 1.5; };
  } else {
    s.mesh = box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 3 * level, 2 * level, 2 * level);
    field = kelvin_field(m, Eigen::Vector3d(0.3, 0.2, 1.4), Eigen::Vector3d(0.4, -0.3, 1.0));
    if (c == PoissonCase::KelvinDirichlet)
      held = [](Index) { return true; };
    else
      held = [&s](Index e) { return s.mesh.centroid(e).x() < 0.0; };
  }
  s.bc = exact_trace_conditions(s.mesh, field, held);
  s.exact = exact_traces(s.mesh, field);
  const InfluenceMatrices hg = InfluenceAssembler(s.mesh, m).assemble();
  s.A = build_system_matrix(hg, s.bc);
  s.b = build_right_hand_side(hg, s.bc);
  return s;
}

/// Relative error of a solution x of s.A x = s.b against the closed form: the larger of the
/// displacement and traction errors over the solved components (reference_solutions.hpp).
inline double closed_form_error(const ClosedFormSystem& s, const Eigen::VectorXd& x) {
  const verification::RelativeErrors e = verification::relative_l2_errors(s.mesh, s.bc, recover_boundary_solution(s.bc, x), s.exact);
  return std::max(e.displacement, e.traction);
}

/// sigma_max / sigma_min of A (2-norm condition number, by divide-and-conquer SVD).
inline double condition_2norm(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd sv = Eigen::BDCSVD<Eigen::MatrixXd>(A).singularValues();
  return sv(0) / sv(sv.size() - 1);
}

}  // namespace bemsurg::stability_setup
