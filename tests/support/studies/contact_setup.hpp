// contact_setup.hpp: the runs of stability studies (g) and (h) (docs/stability.md), shared by
// benchmarks/stability/contact_studies.cpp and tests/test_stability_contact.cpp. Each builds a mesh, precomputes the
// Green's table on the tool's region and presses a tool through ToolContactSolver, the library's
// contact path (no CLI check in between: the depth check is the caller's, contact_validity.hpp).
//   thin slab   a slab 2L x 2L x t on rollers (bottom and sides: normal displacement held, no
//               shear), its whole top pressed by a frictionless flat punch wider than the slab:
//               the exact answer is uniaxial strain, F = M d (2L)^2 / t with M = E (1 - nu) /
//               ((1 + nu)(1 - 2 nu)); the mesh has spacing h on the top and bottom faces.
//   bent plate  the plate [-Lx, Lx] x [-W, W] x [-t/2, t/2] in Saint-Venant's pure bending (exact:
//               u = kappa (x z, -nu y z, -(x^2 + nu (z^2 - y^2)) / 2), sigma_xx = E kappa z), the exact
//               displacement prescribed on its ends x = +-Lx, the rest free: the ends' reaction
//               (the bending moment) and the deflection of the faces against the exact field. A
//               field that varies along the faces: the thin-part failure shows here, not in the slab.
//   tool size   the truncated half-space block of bench_contact_accuracy (graded top face of
//               spacing h near the axis) under a flat punch of radius a or a sphere whose Hertz
//               contact radius is a: against Boussinesq's F = 2 a E* d and Hertz's (4/3) E* R^0.5 d^1.5.
//   depth       the same block under a sphere of radius R or a punch of radius R, pressed from
//               depth / R = 0.01 to 2 on one table.
#pragma once

#include <cmath>
#include <memory>
#include <vector>

#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "contact_accuracy_setup.hpp"

namespace bemsurg::bench::stability {

inline Material contact_material() { return Material{1.0, 0.3, 0.0}; }
inline double contact_e_star() { return 1.0 / (1.0 - 0.3 * 0.3); }

/// The thin slab: force over the uniaxial-strain force, and the mesh's elements.
struct ThinSlabResult {
  double force_ratio = 0.0;
  Index elements = 0;
};

/// The slab [-L, L]^2 x [-t, 0], L = half_cells * h, top and bottom on the grid of spacing h,
/// max(1, round(t / h)) layers through the thickness; pressed d = 1e-3 t.
inline ThinSlabResult thin_slab_press(double t, double h, int half_cells) {
  const double L = half_cells * h, d = 1e-3 * t;
  std::vector<double> xs, zs;
  for (int i = -half_cells; i <= half_cells; ++i) xs.push_back(i * h);
  const int nz = std::max(1, static_cast<int>(std::lround(t / h)));
  for (int k = 0; k <= nz; ++k) zs.push_back(-t + t * k / nz);
  const auto mesh = std::make_shared<const TriangleMesh>(box_mesh_from_grid(xs, xs, zs));
  BoundaryConditions bc(mesh->num_elements());
  std::vector<Index> top;
  for (Index e = 0; e < mesh->num_elements(); ++e) {
    const Eigen::Vector3d n = mesh->normal(e);
    int axis = 2;
    n.cwiseAbs().maxCoeff(&axis);
    if (axis == 2 && n.z() > 0.0) {
      top.push_back(e);  // free: the tool's region
      continue;
    }
    bc.prescribe_component(e, axis, BcKind::Displacement, 0.0);  // roller: normal held, shear free
  }
  GreensTableOptions options;
  options.region = top;
  const auto table = std::make_shared<const GreensTable>(GreensTable::compute(mesh, contact_material(), bc, options));
  ToolContactSolver solver(mesh, table, static_cast<Index>(top.size()) + 8);
  const int tool = solver.add_tool(ToolSpec::flat(2.0 * L));  // covers the whole top face
  solver.place(tool, Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, -1));
  solver.set_depth(tool, d);
  solver.update();
  const double nu = 0.3, M = (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
  return {solver.force(tool).z() / (M * d * 4.0 * L * L / t), mesh->num_elements()};
}

/// The bent plate: Lx = 6 h, W = 2 h, top and bottom faces on the grid of spacing h,
/// max(1, round(t / h)) layers through the thickness. moment_ratio: sum over the end x = +Lx of
/// area * t_x * z (BEM traction) over the same sum with the exact traction E kappa z;
/// deflection_error: the relative L2 error of u_z over the top and bottom faces.
struct BentPlateResult {
  double moment_ratio = 0.0;
  double deflection_error = 0.0;
  Index elements = 0;
  std::size_t thin_elements = 0;  // find_thin_elements(mesh).count
};

inline BentPlateResult bent_plate(double t, double h, int half_cells = 6, int half_width_cells = 2) {
  std::vector<double> xs, ys, zs;
  for (int i = -half_cells; i <= half_cells; ++i) xs.push_back(i * h);
  for (int i = -half_width_cells; i <= half_width_cells; ++i) ys.push_back(i * h);
  const int nz = std::max(1, static_cast<int>(std::lround(t / h)));
  for (int k = 0; k <= nz; ++k) zs.push_back(-0.5 * t + t * k / nz);
  ElastostaticProblem p;
  p.mesh = box_mesh_from_grid(xs, ys, zs);
  p.material = contact_material();
  const double kappa = 1e-3, nu = p.material.poisson_ratio, Lx = half_cells * h;
  const auto exact = [&](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(kappa * x.x() * x.z(), -nu * kappa * x.y() * x.z(),
                           -0.5 * kappa * (x.x() * x.x() + nu * (x.z() * x.z() - x.y() * x.y())));
  };
  p.boundary_conditions = BoundaryConditions(p.mesh.num_elements());
  for (Index e = 0; e < p.mesh.num_elements(); ++e)
    if (std::abs(p.mesh.normal(e).x()) > 0.99) p.boundary_conditions.prescribe_displacement(e, exact(p.mesh.centroid(e)));
  const ElastostaticSolution s = solve_elastostatic(p);
  BentPlateResult r;
  r.elements = p.mesh.num_elements();
  r.thin_elements = find_thin_elements(p.mesh).count;
  double m = 0.0, m_exact = 0.0, du = 0.0, u2 = 0.0;
  for (Index e = 0; e < p.mesh.num_elements(); ++e) {
    const Eigen::Vector3d c = p.mesh.centroid(e), n = p.mesh.normal(e);
    const double A = p.mesh.area(e);
    if (n.x() > 0.99 && c.x() > Lx - 1e-9 * h) {
      m += A * s.boundary.traction(e, 0) * c.z();
      m_exact += A * p.material.young_modulus * kappa * c.z() * c.z();
    } else if (std::abs(n.z()) > 0.99) {
      const double ref = exact(c).z();
      du += A * (s.boundary.displacement(e, 2) - ref) * (s.boundary.displacement(e, 2) - ref);
      u2 += A * ref * ref;
    }
  }
  r.moment_ratio = m / m_exact;
  r.deflection_error = std::sqrt(du / u2);
  return r;
}

/// The truncated half-space block of bench_contact_accuracy, top spacing h near the axis (fine
/// within 1.5 `fine` of it), half-width L; its top elements within `reach` of the axis are the region.
struct ContactBlock {
  std::shared_ptr<const TriangleMesh> mesh;
  std::shared_ptr<const GreensTable> table;
  std::vector<Index> region;
};

inline ContactBlock contact_block(double h, double fine, double L, double reach) {
  using namespace contact_accuracy;
  const std::vector<double> xs = graded_coordinates(-L, L, 0.0, h, L / 5.0, 2.0, 1.5 * fine);
  ContactBlock b;
  b.mesh = std::make_shared<const TriangleMesh>(block_mesh(xs, L));
  std::vector<Index> bottom;
  for (Index e = 0; e < b.mesh->num_elements(); ++e) {
    if (b.mesh->normal(e).z() < -0.99) bottom.push_back(e);
    if (b.mesh->normal(e).z() > 0.99 && b.mesh->centroid(e).head<2>().norm() < reach) b.region.push_back(e);
  }
  GreensTableOptions options;
  options.region = b.region;
  b.table = std::make_shared<const GreensTable>(
      GreensTable::compute(b.mesh, contact_material(), supported_base_conditions(b.mesh->num_elements(), bottom), options));
  return b;
}

/// A tool engaged on the block's axis from above (as `bemsurg press` does) and pressed `depth`:
/// the force along the push (positive) and the elements in contact.
struct PressResult {
  double force = 0.0;
  Index contact_elements = 0;
  std::vector<Index> elements;
};

inline PressResult press_block(const ContactBlock& b, const ToolSpec& spec, double depth) {
  ToolContactSolver solver(b.mesh, b.table, static_cast<Index>(b.region.size()) + 8);
  const int tool = solver.add_tool(spec);
  PressResult r;
  if (!solver.engage(tool, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1))) return r;
  solver.set_depth(tool, depth);
  solver.update();
  r.force = solver.force(tool).z();  // the body pushes the tool back up (+z)
  r.contact_elements = solver.contact_elements(tool);
  solver.contact_element_list(tool, r.elements);
  return r;
}

/// Sneddon's spherical punch in linear elasticity (the exact sphere, not Hertz's parabola;
/// Sneddon 1965, Int. J. Eng. Sci. 3, 47-57, the spherical punch): contact radius a < R at depth
/// d = (a / 2) ln((R + a) / (R - a)), force F = (E* / 2) [(a^2 + R^2) ln((R + a) / (R - a)) - 2 a R].
/// Returns the force at depth d (a found by bisection; d grows without bound as a -> R).
inline double sneddon_sphere_force(double E_star, double R, double d, double* contact_radius = nullptr) {
  double lo = 0.0, hi = R;
  for (int i = 0; i < 200; ++i) {
    const double a = 0.5 * (lo + hi);
    (0.5 * a * std::log((R + a) / (R - a)) < d ? lo : hi) = a;
  }
  const double a = 0.5 * (lo + hi), l = std::log((R + a) / (R - a));
  if (contact_radius) *contact_radius = a;
  return 0.5 * E_star * ((a * a + R * R) * l - 2.0 * a * R);
}

}  // namespace bemsurg::bench::stability
