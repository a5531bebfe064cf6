// bemsurg/verification/reference_solutions.hpp: closed-form elasticity fields (docs/design.md §8) that
// the tests and benchmarks/bench_accuracy compare the BEM against, and the helpers that turn a
// field into boundary conditions ("exact traces": u at centroids, sigma(centroid) . n_facet) so
// that only the BEM discretisation error is measured.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/element_types.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/kernels/kelvin_kernel.hpp"
#include "bemsurg/kernels/kernel_gradients.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/post/interior_evaluator.hpp"

namespace bemsurg::verification {

/// A displacement field with its stress, both as functions of position.
/// \ingroup verification
struct ElasticField {
  std::function<Eigen::Vector3d(const Eigen::Vector3d&)> displacement;
  std::function<Eigen::Matrix3d(const Eigen::Vector3d&)> stress;
};

/// Kelvin's point force f at x0 in an infinite body: u_j(x) = f_i U_ij(x - x0).
inline ElasticField kelvin_field(const Material& m, const Eigen::Vector3d& x0, const Eigen::Vector3d& f) {
  const KelvinKernel k(m);
  const KelvinKernelGradients g(m);
  return {[=](const Eigen::Vector3d& x) { return Eigen::Vector3d(k.displacement(x - x0).transpose() * f); },
          [=](const Eigen::Vector3d& x) {
            const KernelGradient gU = g.displacement(x - x0);  // d U_ij / d x0_b = -d U_ij / d x_b
            Eigen::Matrix3d grad;                              // grad(j, b) = d u_j / d x_b
            for (int b = 0; b < 3; ++b) grad.col(b) = -(gU[static_cast<std::size_t>(b)].transpose() * f);
            return m.stress(grad);
          }};
}

/// Lamé's thick hollow sphere (radii a < b, pressures pa inside, pb outside), centred at c:
/// u = (C1 + C2 / r^3) (x - c), C1 = (pa a^3 - pb b^3)(1 - 2nu) / (E (b^3 - a^3)),
/// C2 = (pa - pb) a^3 b^3 (1 + nu) / (2 E (b^3 - a^3)).
inline ElasticField lame_field(const Material& m, const Eigen::Vector3d& c, double a, double b, double pa, double pb) {
  const double E = m.young_modulus, nu = m.poisson_ratio, d = b * b * b - a * a * a;
  const double C1 = (pa * a * a * a - pb * b * b * b) * (1.0 - 2.0 * nu) / (E * d);
  const double C2 = (pa - pb) * a * a * a * b * b * b * (1.0 + nu) / (2.0 * E * d);
  return {[=](const Eigen::Vector3d& x) {
            const Eigen::Vector3d y = x - c;
            return Eigen::Vector3d((C1 + C2 / std::pow(y.norm(), 3)) * y);
          },
          [=](const Eigen::Vector3d& x) {
            const Eigen::Vector3d y = x - c;
            const double r = y.norm();
            Eigen::Matrix3d grad = (-3.0 * C2 / std::pow(r, 5)) * (y * y.transpose());
            grad.diagonal().array() += C1 + C2 / (r * r * r);
            return m.stress(grad);
          }};
}

/// A body under uniform pressure p on all faces: sigma = -p I, u = -p (1 - 2nu) x / E.
inline ElasticField uniform_pressure_field(const Material& m, double p) {
  const double s = -p * (1.0 - 2.0 * m.poisson_ratio) / m.young_modulus;
  return {[=](const Eigen::Vector3d& x) { return Eigen::Vector3d(s * x); },
          [=](const Eigen::Vector3d&) { return Eigen::Matrix3d(-p * Eigen::Matrix3d::Identity()); }};
}

/// A bar hanging under its own weight, held at z = L, gravity g (> 0) along -z: sigma_zz = rho g z,
/// u = (-nu rho g x z, -nu rho g y z, rho g (z^2 - L^2 + nu (x^2 + y^2)) / 2) / E.
inline ElasticField hanging_bar_field(const Material& m, double g, double L) {
  const double k = m.density * g / m.young_modulus, nu = m.poisson_ratio;
  return {[=](const Eigen::Vector3d& x) {
            return Eigen::Vector3d(-nu * k * x(0) * x(2), -nu * k * x(1) * x(2),
                                   0.5 * k * (x(2) * x(2) - L * L + nu * (x(0) * x(0) + x(1) * x(1))));
          },
          [=](const Eigen::Vector3d& x) {
            Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
            s(2, 2) = m.density * g * x(2);
            return s;
          }};
}

/// Exact traces: displacement at the centroid where `displacement_prescribed(e)` is true, traction
/// sigma(centroid) n_e elsewhere.
inline BoundaryConditions exact_trace_conditions(const TriangleMesh& mesh, const ElasticField& field,
                                                 const std::function<bool(Index)>& displacement_prescribed) {
  BoundaryConditions bc(mesh.num_elements());
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const Eigen::Vector3d x = mesh.centroid(e);
    if (displacement_prescribed(e))
      bc.prescribe_displacement(e, field.displacement(x));
    else
      bc.prescribe_traction(e, field.stress(x) * mesh.normal(e));
  }
  return bc;
}

/// The exact per-element traces of a field.
inline BoundarySolution exact_traces(const TriangleMesh& mesh, const ElasticField& field) {
  BoundarySolution s{RowMatrixX3d(mesh.num_elements(), 3), RowMatrixX3d(mesh.num_elements(), 3)};
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const Eigen::Vector3d x = mesh.centroid(e);
    s.displacement.row(e) = field.displacement(x).transpose();
    s.traction.row(e) = (field.stress(x) * mesh.normal(e)).transpose();
  }
  return s;
}

/// Area-weighted relative L2 error of the solved (not prescribed) components:
/// sqrt(sum a_e |x_e - x*_e|^2 / sum a_e |x*_e|^2) over the dofs where the quantity was unknown.
/// \ingroup verification
struct RelativeErrors {
  double displacement = 0.0;
  double traction = 0.0;
};

inline RelativeErrors relative_l2_errors(const TriangleMesh& mesh, const BoundaryConditions& bc, const BoundarySolution& computed,
                                         const BoundarySolution& exact, const std::function<bool(Index)>& include);

inline RelativeErrors relative_l2_errors(const TriangleMesh& mesh, const BoundaryConditions& bc, const BoundarySolution& computed,
                                         const BoundarySolution& exact) {
  return relative_l2_errors(mesh, bc, computed, exact, [](Index) { return true; });
}

/// The same errors over the elements where `include(e)` is true only (e.g. away from a box's
/// edges, whose row of elements converges more slowly and would hide the rest's order).
inline RelativeErrors relative_l2_errors(const TriangleMesh& mesh, const BoundaryConditions& bc, const BoundarySolution& computed,
                                         const BoundarySolution& exact, const std::function<bool(Index)>& include) {
  double du = 0.0, nu = 0.0, dt = 0.0, nt = 0.0;
  for (Index k = 0; k < bc.num_dofs(); ++k) {
    const Index e = k / 3;
    if (!include(e)) continue;
    const int c = static_cast<int>(k % 3);
    const double a = mesh.area(e);
    if (bc.kind(k) == BcKind::Traction) {
      du += a * std::pow(computed.displacement(e, c) - exact.displacement(e, c), 2);
      nu += a * std::pow(exact.displacement(e, c), 2);
    } else {
      dt += a * std::pow(computed.traction(e, c) - exact.traction(e, c), 2);
      nt += a * std::pow(exact.traction(e, c), 2);
    }
  }
  return {nu > 0.0 ? std::sqrt(du / nu) : 0.0, nt > 0.0 ? std::sqrt(dt / nt) : 0.0};
}

/// Solves the problem whose boundary values are the exact traces of `field` (displacement where
/// `displacement_prescribed`, traction elsewhere) and returns the relative errors of what was solved.
inline RelativeErrors solve_exact_trace_problem(const TriangleMesh& mesh, const Material& m, const ElasticField& field,
                                                const std::function<bool(Index)>& displacement_prescribed,
                                                const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero(),
                                                BoundarySolution* solution = nullptr) {
  ElastostaticProblem p{mesh, m, gravity, exact_trace_conditions(mesh, field, displacement_prescribed), QuadratureOptions()};
  const ElastostaticSolution s = solve_elastostatic(p);
  if (solution) *solution = s.boundary;
  return relative_l2_errors(mesh, p.boundary_conditions, s.boundary, exact_traces(mesh, field));
}

/// Exact traces at the collocation nodes of linear elements (3E rows, row 3e + k; docs/elements.md):
/// u(x_k) and sigma(x_k) n_e.
inline BoundarySolution exact_node_traces(const TriangleMesh& mesh, const ElasticField& field) {
  const Index E = mesh.num_elements();
  BoundarySolution s{RowMatrixX3d(3 * E, 3), RowMatrixX3d(3 * E, 3)};
  for (Index e = 0; e < E; ++e)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d x = collocation_node<LinearElement>(mesh.corners(e), k);
      s.displacement.row(3 * e + k) = field.displacement(x).transpose();
      s.traction.row(3 * e + k) = (field.stress(x) * mesh.normal(e)).transpose();
    }
  return s;
}

/// Relative L2 errors at the linear elements' nodes (weight area / 3 each) of the components that
/// were solved for (the kinds of the per-element `bc`), over the elements where include(e) is true.
inline RelativeErrors node_relative_l2_errors(const TriangleMesh& mesh, const BoundaryConditions& bc, const BoundarySolution& computed,
                                              const BoundarySolution& exact, const std::function<bool(Index)>& include) {
  double du = 0.0, nu = 0.0, dt = 0.0, nt = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    if (!include(e)) continue;
    const double a = mesh.area(e) / 3.0;
    for (Index row = 3 * e; row < 3 * e + 3; ++row)
      for (int c = 0; c < 3; ++c) {
        if (bc.kind(3 * e + c) == BcKind::Traction) {
          du += a * std::pow(computed.displacement(row, c) - exact.displacement(row, c), 2);
          nu += a * std::pow(exact.displacement(row, c), 2);
        } else {
          dt += a * std::pow(computed.traction(row, c) - exact.traction(row, c), 2);
          nt += a * std::pow(exact.traction(row, c), 2);
        }
      }
  }
  return {nu > 0.0 ? std::sqrt(du / nu) : 0.0, nt > 0.0 ? std::sqrt(dt / nt) : 0.0};
}

/// The linear-element counterpart of solve_exact_trace_problem: exact values at the nodes (kinds
/// per element as there), errors at the nodes over the elements where include(e) is true; the
/// per-node solution is returned through `nodes` when given.
inline RelativeErrors solve_linear_exact_trace_problem(
    const TriangleMesh& mesh, const Material& m, const ElasticField& field, const std::function<bool(Index)>& displacement_prescribed,
    const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero(), BoundarySolution* nodes = nullptr,
    const std::function<bool(Index)>& include = [](Index) { return true; }) {
  const BoundarySolution exact = exact_node_traces(mesh, field);
  ElastostaticProblem p{mesh, m, gravity, exact_trace_conditions(mesh, field, displacement_prescribed), QuadratureOptions()};
  p.elements = ElementType::Linear;
  p.node_values.resize(3 * mesh.num_elements(), 3);
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (Index row = 3 * e; row < 3 * e + 3; ++row)
      for (int c = 0; c < 3; ++c)
        p.node_values(row, c) =
            p.boundary_conditions.kind(3 * e + c) == BcKind::Displacement ? exact.displacement(row, c) : exact.traction(row, c);
  const ElastostaticSolution s = solve_elastostatic(p);
  if (nodes) *nodes = s.nodes;
  return node_relative_l2_errors(mesh, p.boundary_conditions, s.nodes, exact, include);
}

/// Relative L2 errors over a set of interior points of the displacement u and of the six stress
/// components (sxx, syy, szz, sxy, syz, sxz) that InteriorEvaluator gives from a boundary solution:
/// sqrt(sum_k |x_k - x*_k|^2 / sum_k |x*_k|^2), with x* from the closed-form `field`.
/// \ingroup verification
struct InteriorErrors {
  double displacement = 0.0;
  double stress = 0.0;
};

inline InteriorErrors interior_relative_errors(const TriangleMesh& mesh, const Material& m, const ElasticField& field,
                                               const BoundarySolution& solution, const RowMatrixX3d& points,
                                               const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero()) {
  const InteriorEvaluator ev(mesh, m, gravity);
  const RowMatrixX3d u = ev.displacement(points, solution);
  const StressRows sigma = ev.stress(points, solution);
  double du = 0.0, nu = 0.0, ds = 0.0, ns = 0.0;
  for (Index k = 0; k < points.rows(); ++k) {
    const Eigen::Vector3d x = points.row(k).transpose();
    du += (u.row(k).transpose() - field.displacement(x)).squaredNorm();
    nu += field.displacement(x).squaredNorm();
    const Eigen::Matrix3d S = field.stress(x);
    Eigen::Matrix<double, 6, 1> exact;
    exact << S(0, 0), S(1, 1), S(2, 2), S(0, 1), S(1, 2), S(0, 2);
    ds += (sigma.row(k).transpose() - exact).squaredNorm();
    ns += exact.squaredNorm();
  }
  return {std::sqrt(du / nu), std::sqrt(ds / ns)};
}

/// Rigid-body identity residual (docs/design.md §4): a rigid translation gives zero traction, so the
/// 3x3 blocks of every block row of H sum to zero. Returns max_i |sum_e H_ie| / |H_ii| (Frobenius).
inline double rigid_body_row_sum_ratio(const InfluenceMatrices& hg) {
  const Index n = hg.H.rows() / 3;
  double worst = 0.0;
  for (Index i = 0; i < n; ++i) {
    Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
    for (Index e = 0; e < n; ++e) sum += hg.H.block<3, 3>(3 * i, 3 * e);
    worst = std::max(worst, sum.norm() / hg.H.block<3, 3>(3 * i, 3 * i).norm());
  }
  return worst;
}

/// A few well-spread elements (four, evenly spaced in index order) on which a traction-loaded
/// body gets its exact displacement: enough to fix the six rigid modes without changing the problem.
inline std::function<bool(Index)> a_few_elements(const TriangleMesh& mesh) {
  const Index E = mesh.num_elements();
  std::vector<Index> pick;
  for (Index k = 0; k < 4; ++k) pick.push_back((k * E) / 4 + E / 8);
  return [pick](Index e) { return std::find(pick.begin(), pick.end(), e) != pick.end(); };
}

}  // namespace bemsurg::verification
