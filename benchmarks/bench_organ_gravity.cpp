// bench_organ_gravity: an organ-like body with no closed-form solution, hung under its own weight,
// for the finite-element peer of the benchmark report (issue 24, scripts/report/parts/peer.py;
// docs/benchmarks.md). The body is bemsurg's procedural brain (mesh/brain_model.hpp) turned upside
// down: z -> -z, so its flat face lies on the plane z = 0 with the body below it, glued to a
// ceiling by that face (the clamped patch; by default all of it) while gravity pulls along -z.
//
// The patch, which scripts/report/calculix_peer.py applies to its finite-element nodes in the same
// way: the points of the plane z = 0 with x^2 + y^2 <= R^2 (the flat face is centred on the z axis);
// here, the elements whose centroid lies on the plane (|z| <= 0.1 um, as the FE nodes) and
// within R of the axis. The default R = 1 m reaches past the face's rim: the whole flat face is
// clamped, which a volume mesher reproduces exactly (the rim is a crease), where a disc inside the
// face zig-zags between finite-element nodes. Displacement zero there, traction zero elsewhere,
// gravity on the volume.
//
//   bench_organ_gravity [--quick] [--json PATH] [--subdivisions S] [--patch-radius R]
//                       [--edge-length H] [--points-out CSV] [--write-surface PATH.stl [--surface-subdivisions S]]
//
// --edge-length H: the BEM mesh is the fine surface (--surface-subdivisions) remeshed by Gmsh with
// edges of about H, rim kept; without it, the icosphere mesh of --subdivisions, whose triangles
// straddle the rim (only 62-74 % of the face clamped at S = 2-3).
//
// --write-surface writes the finite-element mesher's input (the same body, finer: the geometry
// every finite-element level shares) as ASCII STL and exits without solving.

#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/mesh/brain_model.hpp"
#include "bemsurg/mesh/operating_region.hpp"
#include "bemsurg/meshing/graded_remesher.hpp"
#include "bench_support.hpp"

using namespace bemsurg;

namespace {

// Material of soft brain tissue in the range the literature quotes (a few kPa, nearly incompressible).
constexpr double kYoung = 3000.0;    // Pa
constexpr double kPoisson = 0.45;    // -
constexpr double kDensity = 1000.0;  // kg/m^3
constexpr double kGravity = 9.81;    // m/s^2, along -z

// The brain of brain_mesh mirrored through the plane z = 0 (faces reversed to stay outward).
TriangleMesh hanging_brain(int subdivisions) {
  BrainModelOptions o;
  o.subdivisions = subdivisions;
  const TriangleMesh up = brain_mesh(o);
  RowMatrixX3d v = up.vertices();
  RowMatrixX3i f = up.faces();
  v.col(2) = -v.col(2);
  f.col(1).swap(f.col(2));
  return TriangleMesh(v, f);
}

// The BEM mesh: the icosphere brain itself, or (edge_length > 0) the fine surface remeshed by Gmsh
// with uniform edges, which keeps the rim of the flat face as a crease (graded_remesher.hpp), so
// that the clamped face is the whole face at every size, as in the finite-element meshes.
TriangleMesh bem_mesh(int subdivisions, int surface_subdivisions, double edge_length) {
  if (edge_length <= 0.0) return hanging_brain(subdivisions);
  const TriangleMesh fine = hanging_brain(surface_subdivisions);
  GradedRemeshOptions o;
  o.inside_edge_length = o.outside_edge_length = edge_length;  // uniform: the region only has to meet the surface
  return graded_remesh(fine, OperatingRegion::sphere(fine.vertex(0), edge_length), o).mesh;
}

bool on_patch(const Vec3& c, double radius, double tolerance) {
  return std::abs(c.z()) <= tolerance && c.x() * c.x() + c.y() * c.y() <= radius * radius;
}

bool write_stl(const std::string& path, const TriangleMesh& mesh) {
  std::ofstream out(path);
  use_classic_locale(out);
  out << "solid bemsurg_hanging_brain\n";
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const Vec3 n = mesh.normal(e);
    out << "facet normal " << number_text(n.x()) << " " << number_text(n.y()) << " " << number_text(n.z()) << "\nouter loop\n";
    for (const Vec3& p : mesh.corners(e))
      out << "vertex " << number_text(p.x()) << " " << number_text(p.y()) << " " << number_text(p.z()) << "\n";
    out << "endloop\nendfacet\n";
  }
  out << "endsolid bemsurg_hanging_brain\n";
  return static_cast<bool>(out);
}

}  // namespace

// long: one straight sequence of options, solve and outputs, clearer unsplit
int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path, points_path, surface_path;
  int subdivisions = 3, surface_subdivisions = 5;
  double patch_radius = 1.0, edge_length = 0.0;  // past the flat face: all of it
  cli::OptionParser parser = bench::command_line(
      "bench_organ_gravity", "The upside-down brain hung from a disc of its flat face under gravity (the CalculiX peer's BEM side).\n",
      quick, json_path);
  parser.value("--subdivisions", "S", subdivisions, "icosphere subdivisions of the BEM mesh: 20 * 4^S elements").at_least(0);
  parser.value("--edge-length", "H", edge_length, "remesh the fine surface with edges of about H (m) instead (Gmsh)").above(0.0);
  parser.value("--patch-radius", "R", patch_radius, "radius of the clamped disc on the flat face (m); 1 (default): the whole face")
      .above(0.0);
  parser.value("--points-out", "CSV", points_path, "write element centroids, areas and displacements to CSV");
  parser.value("--write-surface", "PATH", surface_path, "write the finite-element mesher's surface as ASCII STL and exit");
  parser.value("--surface-subdivisions", "S", surface_subdivisions, "subdivisions of the surface --write-surface writes").at_least(0);
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (quick) subdivisions = 2;  // 320 elements: under a second

  if (!surface_path.empty()) {
    const TriangleMesh fine = hanging_brain(surface_subdivisions);
    if (!write_stl(surface_path, fine)) {
      std::cerr << "bench_organ_gravity: cannot write " << surface_path << "\n";
      return 1;
    }
    std::cerr << "wrote " << surface_path << ": " << fine.num_elements() << " triangles, volume " << fine.enclosed_volume() << " m^3\n";
    return 0;
  }

  const bench::Clock::time_point start = bench::Clock::now();
  const TriangleMesh mesh = bem_mesh(subdivisions, surface_subdivisions, edge_length);
  const Material material{kYoung, kPoisson, kDensity};
  const double tolerance = 1e-7;               // m, as calculix_peer.py: Gmsh puts the remeshed face within ~1e-17 of the plane
  BoundaryConditions bc(mesh.num_elements());  // traction-free by default
  Index clamped = 0;
  for (Index e = 0; e < mesh.num_elements(); ++e)
    if (on_patch(mesh.centroid(e), patch_radius, tolerance)) {
      bc.prescribe_displacement(e, Vec3::Zero());
      ++clamped;
    }
  if (clamped == 0) {
    std::cerr << "bench_organ_gravity: no element centroid lies on the patch; use a larger --patch-radius\n";
    return 1;
  }
  const ElastostaticProblem problem{mesh, material, Eigen::Vector3d(0.0, 0.0, -kGravity), bc, QuadratureOptions()};
  const ElastostaticSolution s = solve_elastostatic(problem);
  const double total_s = seconds_since(start);

  // The support's reaction on the body must balance the weight: sum of t * area over the patch.
  Vec3 reaction = Vec3::Zero();
  double patch_area = 0.0, max_u = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    max_u = std::max(max_u, s.boundary.displacement.row(e).norm());
    if (!on_patch(mesh.centroid(e), patch_radius, tolerance)) continue;
    reaction += mesh.area(e) * s.boundary.traction.row(e).transpose();
    patch_area += mesh.area(e);
  }
  const double volume = mesh.enclosed_volume();
  const double weight = kDensity * kGravity * volume;
  const double solve_s = s.report.system_seconds + s.report.solver.setup_seconds + s.report.solver.solve_seconds;
  std::cerr << "subdivisions " << subdivisions << ": " << mesh.num_elements() << " elements (" << clamped << " clamped), assembly "
            << s.report.assembly_seconds << " s, solve " << solve_s << " s, reaction z / weight " << reaction.z() / weight << ", max |u| "
            << max_u << " m\n";

  if (!points_path.empty()) {
    std::ofstream csv(points_path);
    use_classic_locale(csv);
    csv << "x,y,z,area,clamped,ux,uy,uz\n";
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      const Vec3 c = mesh.centroid(e);
      csv << number_text(c.x()) << "," << number_text(c.y()) << "," << number_text(c.z()) << "," << number_text(mesh.area(e)) << ","
          << (on_patch(c, patch_radius, tolerance) ? 1 : 0);
      for (int k = 0; k < 3; ++k) csv << "," << number_text(s.boundary.displacement(e, k));
      csv << "\n";
    }
    if (!csv) {
      std::cerr << "bench_organ_gravity: cannot write " << points_path << "\n";
      return 1;
    }
  }
  nlohmann::json j;
  j["benchmark"] = "bench_organ_gravity";
  j["quick"] = quick;
  j["subdivisions"] = subdivisions;
  j["edge_length_m"] = edge_length;  // 0: the icosphere mesh of `subdivisions`
  j["elements"] = mesh.num_elements();
  j["clamped_elements"] = clamped;
  j["equations"] = s.report.equations;
  j["assembly_s"] = s.report.assembly_seconds;
  j["solve_s"] = solve_s;
  j["total_s"] = total_s;
  j["peak_rss_bytes"] = peak_memory_mb() * 1048576.0;  // this process's own peak (VmHWM)
  j["volume_m3"] = volume;
  j["weight_n"] = weight;
  j["reaction_n"] = {reaction.x(), reaction.y(), reaction.z()};
  j["reaction_over_weight"] = reaction.z() / weight;  // the support pulls up (+z) on a body pulled down (-z)
  j["patch_area_m2"] = patch_area;
  j["max_displacement_m"] = max_u;
  j["material"] = {{"young_modulus_pa", kYoung}, {"poisson_ratio", kPoisson}, {"density_kg_m3", kDensity}};
  j["gravity_m_s2"] = {0.0, 0.0, -kGravity};
  j["patch"] = {{"kind", "disc on the plane z = 0: x^2 + y^2 <= radius^2"},
                {"plane_z", 0.0},
                {"centre", {0.0, 0.0, 0.0}},
                {"radius_m", patch_radius},
                {"bem_rule", "element centroid on the plane and within the radius"}};
  return bench::write_json_file(json_path, j, "bench_organ_gravity") ? 0 : 1;
}
