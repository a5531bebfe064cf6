// contact_accuracy_setup.hpp: the configurations of bench_contact_accuracy (problem, study, level,
// mesh), the truncated half-space block each one meshes, and one configuration run: precompute,
// contact solve, errors against the closed forms (contact_accuracy_closed_forms.hpp). The error
// definitions are at the top of benchmarks/bench_contact_accuracy.cpp; shared with the contact
// studies (contact_setup.hpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bemsurg/io/results_io.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/timing.hpp"
#include "contact_accuracy_closed_forms.hpp"

namespace bemsurg::bench::contact_accuracy {

/// Contact-zone spacing h / a per level.
inline const std::vector<double>& level_spacings() {
  static const std::vector<double> h = {1.0 / 2.0, 1.0 / 3.0, 1.0 / 4.0, 1.0 / 6.0};
  return h;
}

struct Config {
  Problem problem = Problem::Punch;
  std::string study = "levels";  // levels | mesh
  int level = 0;
  std::string mesh = "graded";  // graded | uniform (the top face)
};

inline std::string problem_name(Problem p) { return p == Problem::Punch ? "punch" : "sphere"; }

/// The block's half-width L / a: 800 for the refinement levels (the truncation floor,
/// bench_contact_accuracy.cpp: at L / a = 100 it held the sphere's error_u at 1.1-1.5 % at every
/// level; the graded top face and the coarse other faces make a large block cheap: 3,270 -> 4,278
/// elements at h = a / 6), 6 for uniform against graded (a uniform top face at L / a = 20 and
/// h = a / 2 would already have 12,800 elements).
inline double block_half_width(const Config& c) { return c.study == "mesh" ? 6.0 : 800.0; }

/// The runs of --list: the refinement levels of both problems on graded meshes, then graded
/// against uniform at the two coarsest levels. Quick: the two coarsest levels, and the coarsest
/// graded against uniform.
inline std::vector<Config> configurations(bool quick) {
  std::vector<Config> out;
  const int levels = quick ? 2 : 4, mesh_levels = quick ? 1 : 2;
  for (Problem p : {Problem::Punch, Problem::Sphere}) {
    for (int l = 0; l < levels; ++l) out.push_back({p, "levels", l, "graded"});
    // Quick: the punch alone is compared (the smoke list's budget is seconds).
    for (int l = 0; l < (quick && p == Problem::Sphere ? 0 : mesh_levels); ++l)
      for (const char* m : {"graded", "uniform"}) out.push_back({p, "mesh", l, m});
  }
  return out;
}

/// Triangles with welded vertices (coordinates equal to 1e-9), each turned to face `outward`.
struct WeldingBuilder {
  std::map<std::array<long long, 3>, int> index;
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> faces;
  int vertex(const Vec3& p) {
    const std::array<long long, 3> key = {std::llround(p.x() * 1e9), std::llround(p.y() * 1e9), std::llround(p.z() * 1e9)};
    const auto [it, added] = index.emplace(key, static_cast<int>(vertices.size()));
    if (added) vertices.push_back(p);
    return it->second;
  }
  void triangle(const Vec3& p, Vec3 q, Vec3 r, const Vec3& outward) {
    if ((q - p).cross(r - p).dot(outward) < 0.0) std::swap(q, r);
    faces.push_back({vertex(p), vertex(q), vertex(r)});
  }
  void add(const TriangleMesh& m, Index e) {
    const auto c = m.corners(e);
    triangle(c[0], c[1], c[2], m.normal(e));
  }
  TriangleMesh mesh() const {
    RowMatrixX3d v(static_cast<Index>(vertices.size()), 3);
    RowMatrixX3i f(static_cast<Index>(faces.size()), 3);
    for (std::size_t i = 0; i < vertices.size(); ++i) v.row(static_cast<Index>(i)) = vertices[i].transpose();
    for (std::size_t i = 0; i < faces.size(); ++i) f.row(static_cast<Index>(i)) << faces[i][0], faces[i][1], faces[i][2];
    return TriangleMesh(std::move(v), std::move(f));
  }
};

/// The strip z in [-depth, 0] of the side face x = side L (axis 0) or y = side L (axis 1), joining
/// the top face's grid lines `upper` at z = 0 to the coarse lines `lower` at z = -depth: the two
/// sorted point rows zipped into triangles, so the mesh stays conforming.
inline void side_strip(WeldingBuilder& b, int axis, double side, double L, double depth, const std::vector<double>& upper,
                       const std::vector<double>& lower) {
  auto at = [&](double s, double z) { return axis == 0 ? Vec3(side * L, s, z) : Vec3(s, side * L, z); };
  const Vec3 outward = axis == 0 ? Vec3(side, 0, 0) : Vec3(0, side, 0);
  std::size_t i = 0, j = 0;
  while (i + 1 < upper.size() || j + 1 < lower.size()) {
    if (j + 1 == lower.size() || (i + 1 < upper.size() && upper[i + 1] <= lower[j + 1])) {
      b.triangle(at(upper[i], 0.0), at(upper[i + 1], 0.0), at(lower[j], -depth), outward);
      ++i;
    } else {
      b.triangle(at(upper[i], 0.0), at(lower[j + 1], -depth), at(lower[j], -depth), outward);
      ++j;
    }
  }
}

/// The block [-L, L]^2 x [-L, 0]: its top face on the grid xs_top x xs_top; the other five faces
/// coarse (spacing 2L / 5, z graded from L / 10), joined to the top face by a strip L / 10 deep
/// round the sides whose triangles zip the top's grid lines to the coarse ones. A plain
/// box_mesh_from_grid would repeat the fine top grid on the bottom and more than double the
/// elements. Conforming and welded (one closed shell: the enclosed volume is checked).
inline TriangleMesh block_mesh(const std::vector<double>& xs_top, double L) {
  const double depth = 0.1 * L;
  std::vector<double> xs_coarse;
  for (int i = 0; i <= 5; ++i) xs_coarse.push_back(-L + 2.0 * L * i / 5.0);
  const std::vector<double> zs = graded_coordinates(-L, -depth, -depth, depth, 0.4 * L, 2.0);
  const TriangleMesh top = box_mesh_from_grid(xs_top, xs_top, {-L, 0.0});
  const TriangleMesh rest = box_mesh_from_grid(xs_coarse, xs_coarse, zs);
  WeldingBuilder b;
  for (Index e = 0; e < top.num_elements(); ++e)
    if (top.normal(e).z() > 0.99) b.add(top, e);
  for (Index e = 0; e < rest.num_elements(); ++e)
    if (rest.normal(e).z() <= 0.99) b.add(rest, e);
  for (int axis : {0, 1})
    for (double side : {-1.0, 1.0}) side_strip(b, axis, side, L, depth, xs_top, xs_coarse);
  return b.mesh();
}

/// The top face's grid lines for a configuration: spacing h within 1.5 a of the axis (the
/// sphere's initial overlap reaches sqrt(2) a), growing by at most 2 up to L / 5 (graded), or
/// spacing h everywhere (uniform).
inline std::vector<double> top_grid(const Config& c, double a, double h, double L) {
  if (c.mesh == "graded") return graded_coordinates(-L, L, 0.0, h * a, L / 5.0, 2.0, 1.5 * a);
  const int n = static_cast<int>(std::lround(2.0 * L / (h * a)));
  std::vector<double> xs;
  for (int i = 0; i <= n; ++i) xs.push_back(-L + 2.0 * L * i / n);
  return xs;
}

/// What a run measures against the closed form (the definitions: bench_contact_accuracy.cpp).
struct Errors {
  double error_u = 0.0, error_t = 0.0, mean_h = 0.0, reference_force = 0.0;
  Index zone_elements = 0, outer_elements = 0;
};

/// error_t over the contact zone Z (top elements the closed-form contact disc overlaps, and the
/// elements in contact), error_u over the top elements outside Z within 3 a of the axis.
inline Errors measure_errors(const TriangleMesh& mesh, const ToolContactSolver& solver, int tool, const ClosedForm& cf) {
  std::vector<Index> list;
  solver.contact_element_list(tool, list);
  std::vector<char> in_contact(static_cast<std::size_t>(mesh.num_elements()), 0);
  for (Index e : list) in_contact[static_cast<std::size_t>(e)] = 1;
  Eigen::VectorXd u(mesh.num_dofs());
  solver.displacement_field(u);
  Errors r;
  double t_diff = 0.0, t_ref = 0.0, u_diff = 0.0, u_ref = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    if (mesh.normal(e).z() < 0.99) continue;
    const double rc = mesh.centroid(e).head<2>().norm(), A = mesh.area(e);
    const bool contact = in_contact[static_cast<std::size_t>(e)] != 0;
    double integral = 0.0;
    if (rc < cf.a + mesh.diameter(e)) {
      const auto c = mesh.corners(e);
      integral = pressure_integral(cf, {c[0].head<2>(), c[1].head<2>(), c[2].head<2>()});
    }
    if (contact || integral > 0.0) {  // in Z
      const double p = contact ? -solver.contact().traction(e).z() : 0.0, p_bar = integral / A;
      t_diff += A * (p - p_bar) * (p - p_bar);
      t_ref += A * p_bar * p_bar;
      r.reference_force += integral;
      r.mean_h += mesh.diameter(e);
      ++r.zone_elements;
    } else if (rc <= 3.0 * cf.a) {
      const double uz = -u(3 * e + 2), ref = cf.displacement(rc);
      u_diff += A * (uz - ref) * (uz - ref);
      u_ref += A * ref * ref;
      ++r.outer_elements;
    }
  }
  r.error_t = std::sqrt(t_diff / t_ref);
  r.error_u = std::sqrt(u_diff / u_ref);
  r.mean_h /= static_cast<double>(std::max<Index>(1, r.zone_elements));
  return r;
}

/// Runs one configuration: E = 1, nu = 0.3, a = 1; punch pressed d = 0.01, sphere R = 20 pressed
/// d = a^2 / R = 0.05 (a / R = 0.05: the sphere's gap differs from Hertz's parabola by
/// (a / 2R)^2 = 6e-4 relative at the contact edge).
inline nlohmann::json run_configuration(const Config& c, double tolerance) {
  const auto t_total = SteadyClock::now();
  const Material material{1.0, 0.3, 0.0};
  const double E_star = 1.0 / (1.0 - 0.3 * 0.3), a = 1.0, R = 20.0;
  const double h = level_spacings().at(static_cast<std::size_t>(c.level)), L = block_half_width(c);
  const ClosedForm cf = c.problem == Problem::Punch ? ClosedForm::punch(E_star, a, 0.01) : ClosedForm::sphere(E_star, R, a);
  nlohmann::json j = {{"problem", problem_name(c.problem)},
                      {"study", c.study},
                      {"level", c.level},
                      {"quadrature", "baseline"},
                      {"solver", "lu"},
                      {"tolerance", tolerance},
                      {"mesh", c.mesh},
                      {"h_over_a", h},
                      {"block_half_width_over_a", L}};
  const auto mesh = std::make_shared<const TriangleMesh>(block_mesh(top_grid(c, a, h, L), L));
  std::vector<Index> bottom, region;
  // The tool's reach: the punch's elements have centroids within a; the sphere's first overlap
  // reaches sqrt(2) a, less than 1.5 a.
  const double reach = (c.problem == Problem::Punch ? 1.0 : 1.5) * a + h * a;
  for (Index e = 0; e < mesh->num_elements(); ++e) {
    if (mesh->normal(e).z() < -0.99) bottom.push_back(e);
    if (mesh->normal(e).z() > 0.99 && mesh->centroid(e).head<2>().norm() < reach) region.push_back(e);
  }
  j["elements"] = mesh->num_elements();
  j["equations"] = mesh->num_dofs();
  j["region_elements"] = region.size();
  // Every metric present in every record: null where the run failed before measuring it.
  for (const char* key : {"assembly_s", "factor_s", "table_s", "solve_s", "iterations", "contact_elements", "error_u", "error_t", "mean_h",
                          "zone_elements", "outer_elements", "force_ratio"})
    j[key] = nullptr;
  std::string status = "ok";
  if (!check_closed_forms(cf)) status = "closed_form_check_failed";
  const MeshTopology topology(*mesh);
  if (topology.num_shells() != 1 || !topology.is_closed_and_oriented() ||
      std::abs(mesh->enclosed_volume() / (4.0 * L * L * L) - 1.0) > 1e-9)
    status = "mesh_not_closed";
  try {
    GreensTableOptions options;
    options.region = region;  // columns only where the tool acts: n x 3|region| memory
    const auto table = std::make_shared<const GreensTable>(
        GreensTable::compute(mesh, material, supported_base_conditions(mesh->num_elements(), bottom), options));
    const PrecomputeTimings& pt = table->timings();
    j["assembly_s"] = pt.assembly_seconds + pt.table_seconds;
    j["factor_s"] = pt.factorization_seconds;
    j["table_s"] = pt.table_seconds;  // the back-substitution part of assembly_s
    const auto t_solve = SteadyClock::now();
    ToolContactSolver solver(mesh, table, static_cast<Index>(region.size()) + 8);
    const int tool = solver.add_tool(c.problem == Problem::Punch ? ToolSpec::flat(a) : ToolSpec::sphere(R));
    solver.place(tool, Vec3(0, 0, c.problem == Problem::Punch ? 0.0 : R), Vec3(0, 0, -1));
    solver.set_depth(tool, cf.d);
    const ContactUpdateResult result = solver.update();
    j["solve_s"] = seconds_since(t_solve);
    j["iterations"] = result.active_set_iterations;
    j["contact_elements"] = solver.contact_elements(tool);
    if (!result.consistent && status == "ok") status = "unsettled";
    const Errors err = measure_errors(*mesh, solver, tool, cf);
    // The reference pressure integrated over Z must give the closed-form force: Z covers the disc.
    if (std::abs(err.reference_force / cf.force - 1.0) > 1e-8 && status == "ok") status = "reference_quadrature_failed";
    j["error_u"] = err.error_u;
    j["error_t"] = err.error_t;
    j["mean_h"] = err.mean_h;
    j["zone_elements"] = err.zone_elements;
    j["outer_elements"] = err.outer_elements;
    j["force_ratio"] = solver.force(tool).z() / cf.force;
  } catch (const std::exception& e) { status = std::string("error: ") + e.what(); }
  j["status"] = status;
  j["total_s"] = seconds_since(t_total);
  j["peak_hwm_bytes"] = peak_memory_mb() * 1048576.0;  // this process's own peak (VmHWM)
  return j;
}

}  // namespace bemsurg::bench::contact_accuracy
