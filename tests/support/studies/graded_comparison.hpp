// tests/support/studies/graded_comparison.hpp: the brain scene pressed by a tool, graded mesh against a
// uniformly fine reference (docs/graded.md). Shared by benchmarks/bench_graded.cpp (figures) and
// tests/test_graded_mesh.cpp (tolerances), so both measure the same thing.
//
// Set-up (the brain scene, examples/scenes/brain.json, at a chosen size): the brain's flat underside
// (z = 0) held, the rest free; the Green's table (docs/design.md §6) for the free elements in the
// operating region only; a rigid sphere tool (frictionless, unilateral: an active set) approaching
// from above the region's centre and pressed `depth`. Compared: the force on the tool, and the
// displacement of the surface in the operating region after the press.
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

#include "bemsurg/mesh/brain_model.hpp"
#include "bemsurg/meshing/graded_remesher.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "bemsurg/presolution/greens_table.hpp"

namespace bemsurg::graded {

struct PressCase {
  Vec3 region_center;  // on the surface, top of the left hemisphere
  double region_radius = 0.025;
  double tool_radius = 0.02;
  double depth = 0.004;
  Material material{3000.0, 0.45, 1040.0};
};

inline PressCase brain_press_case(const BrainModelOptions& brain) {
  PressCase c;
  c.region_center = brain_surface_point(brain, Vec3(0.1, 0.45, 1.0));
  return c;
}

struct PressResult {
  Index elements = 0;
  Index region_elements = 0;
  Vec3 force = Vec3::Zero();
  Eigen::VectorXd displacement;  // every element, after the press
  PrecomputeTimings timings;
  double precompute_seconds = 0.0;  // assembly + factorisation + table
  double peak_bytes = 0.0;          // GreensTable::estimate_bytes: the precomputation's peak
  double table_bytes = 0.0;         // what stays for the simulation
  Index contact_elements = 0;
};

inline PressResult press(const TriangleMesh& mesh, const PressCase& c) {
  PressResult r;
  r.elements = mesh.num_elements();
  std::vector<Index> supported;
  for (Index e = 0; e < mesh.num_elements(); ++e)
    if (std::abs(mesh.centroid(e).z()) < 1e-9 && mesh.normal(e).z() < -0.999) supported.push_back(e);
  const BoundaryConditions base = supported_base_conditions(mesh.num_elements(), supported);
  GreensTableOptions options;
  const OperatingRegion region = OperatingRegion::sphere(c.region_center, c.region_radius);
  for (Index e : region.elements_of(mesh))
    if (base.is_free(e)) options.region.push_back(e);
  r.region_elements = static_cast<Index>(options.region.size());
  // Shared snapshots, as the contact solver takes them (docs/design.md §9).
  auto snapshot = std::make_shared<const TriangleMesh>(mesh);
  auto table_ptr = std::make_shared<const GreensTable>(GreensTable::compute(mesh, c.material, base, options));
  const GreensTable& table = *table_ptr;
  r.timings = table.timings();
  r.precompute_seconds = r.timings.assembly_seconds + r.timings.factorization_seconds + r.timings.table_seconds;
  r.peak_bytes = GreensTable::estimate_bytes(mesh.num_elements(), r.region_elements);
  r.table_bytes = static_cast<double>(table.bytes());
  ToolContactSolver solver(snapshot, table_ptr);
  const int tool = solver.add_tool(ToolSpec::sphere(c.tool_radius));
  if (!solver.engage(tool, c.region_center + Vec3(0, 0, 0.05), Vec3(0, 0, -1)))
    throw ContactError("graded comparison: the tool missed the brain");
  solver.set_depth(tool, c.depth);
  solver.update();
  r.force = solver.force(tool);
  r.contact_elements = solver.contact_elements(tool);
  r.displacement = Eigen::VectorXd::Zero(mesh.num_dofs());
  solver.displacement_field(r.displacement);
  return r;
}

/// Relative L2 difference of the displacement over the reference's elements in the operating
/// region. Both fields are first made continuous the same way (vertex values: area-weighted means
/// of the adjacent elements, docs/design.md §2) and read by linear interpolation: on the reference
/// at its element's centroid, on the test mesh at the closest point of its surface. (Comparing raw
/// element values at different centroids would measure the meshes' offset, O(h grad u), not the
/// models' difference.)
inline double region_displacement_difference(const TriangleMesh& reference, const PressResult& ref, const TriangleMesh& test,
                                             const PressResult& res, const PressCase& c) {
  const auto vertex_field = [](const TriangleMesh& m, const Eigen::VectorXd& u) {
    RowMatrixX3d per_element(m.num_elements(), 3);
    for (Index e = 0; e < m.num_elements(); ++e) per_element.row(e) = u.segment<3>(3 * e).transpose();
    return m.element_to_vertex(per_element);
  };
  const RowMatrixX3d uf = vertex_field(reference, ref.displacement), ut = vertex_field(test, res.displacement);
  const OperatingRegion region = OperatingRegion::sphere(c.region_center, c.region_radius);
  double num = 0.0, den = 0.0;
  for (Index e : region.elements_of(reference)) {
    const Vec3 x = reference.centroid(e);
    Vec3 u_ref = Vec3::Zero();
    for (int k = 0; k < 3; ++k) u_ref += uf.row(reference.faces()(e, k)).transpose() / 3.0;
    double best = 1e300;
    Vec3 u = Vec3::Zero();
    for (Index f = 0; f < test.num_elements(); ++f) {
      const auto t = test.corners(f);
      const Vec3 q = closest_point_on_triangle(x, t[0], t[1], t[2]);
      const double d = (q - x).squaredNorm();
      if (d >= best) continue;
      best = d;
      // Barycentric coordinates of q in triangle f.
      const Vec3 v0 = t[1] - t[0], v1 = t[2] - t[0], v2 = q - t[0];
      const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
      const double den_b = d00 * d11 - d01 * d01;
      const double b1 = (d11 * d20 - d01 * d21) / den_b, b2 = (d00 * d21 - d01 * d20) / den_b;
      u = (1.0 - b1 - b2) * ut.row(test.faces()(f, 0)).transpose() + b1 * ut.row(test.faces()(f, 1)).transpose() +
          b2 * ut.row(test.faces()(f, 2)).transpose();
    }
    num += reference.area(e) * (u - u_ref).squaredNorm();
    den += reference.area(e) * u_ref.squaredNorm();
  }
  return den > 0.0 ? std::sqrt(num / den) : 0.0;
}

}  // namespace bemsurg::graded
