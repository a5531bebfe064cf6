// bench_organ_gravity: an organ-like body with no closed-form solution, hung under its own weight,
// for the finite-element peer of the benchmark report (issues 24 and 38, scripts/report/parts/peer.py;
// docs/benchmarks.md). The body is bemsurg's procedural brain (mesh/brain_model.hpp) turned upside
// down: z -> -z, so its flat face lies on the plane z = 0 with the body below it, glued to a
// ceiling by that face (the clamped patch; by default all of it) while gravity pulls along -z.
//
// The patch, which scripts/report/calculix_peer.py applies to its finite-element nodes in the same
// way: the points of the plane z = 0 with x^2 + y^2 <= R^2 (the flat face is centred on the z axis);
// here, the elements whose centroid lies on the plane (|z| <= 0.1 um, as the FE nodes) and
// within R of the axis. The default R = 1 m reaches past the face's rim: the whole flat face is
// clamped. Displacement zero there, traction zero elsewhere, gravity on the volume.
//
//   bench_organ_gravity [--quick] [--json PATH] [--subdivisions S] [--patch-radius R]
//                       [--edge-length H [--rim-area-loss L] [--old-clamp]] [--hung-volume V]
//                       [--points-out CSV] [--clamped-out CSV]
//   bench_organ_gravity --write-surface PATH.obj [--surface-subdivisions S] [--json PATH]
//                       [--organ liver --held-sphere DX,DY,DZ,R --tool-sphere DX,DY,DZ,R]
//
// --edge-length H: the BEM mesh is the fine surface (--surface-subdivisions) remeshed by Gmsh with
// edges of about H, the flat face kept (graded_remesher.hpp; --rim-area-loss L meshes its rim so
// that the chords lose about L of it); --old-clamp remeshes without keeping it, as releases before
// issue 38 did (the face's rim rounded off: the control of the report's peer). Without
// --edge-length, the icosphere mesh of --subdivisions, whose triangles straddle the rim.
// --hung-volume V scales the density so that the weight is density * g * V (the finite-element
// side's volume: both sides then hang the same weight, issue 38 item 5).
//
// --write-surface writes the finite-element mesher's input, the same body finer (the geometry every
// finite-element level shares), as OBJ with its faces in groups: "held" (the patch), "tool" and
// "free"; calculix_peer.py meshes each group as a surface of its own, so that their rims are mesh
// curves and both sides hold the same area. With --organ liver the body is the procedural liver
// (mesh/liver_model.hpp) split along two spheres (mesh/conforming_split.hpp), centred on the surface
// point in direction (DX, DY, DZ) from its origin: the held region and the tool's footprint.
// `--organ liver --edge-length H` writes (--json) the element count and volume of the liver as a
// scene remeshes it at edges H, without solving: `bemsurg solve` solves the liver's scenes.

#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/mesh/brain_model.hpp"
#include "bemsurg/mesh/conforming_split.hpp"
#include "bemsurg/mesh/liver_model.hpp"
#include "bemsurg/mesh/operating_region.hpp"
#include "bemsurg/meshing/graded_remesher.hpp"
#include "bench_support.hpp"

using namespace bemsurg;

namespace {

// Material of soft brain tissue in the range the literature quotes (a few kPa, nearly incompressible).
constexpr double kYoung = 3000.0;         // Pa
constexpr double kPoisson = 0.45;         // -
constexpr double kDensity = 1000.0;       // kg/m^3
constexpr double kGravity = 9.81;         // m/s^2, along -z
constexpr double kPlaneTolerance = 1e-7;  // m, as calculix_peer.py: the remeshed face lies within ~1e-17 of the plane

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

// The fine surface remeshed by Gmsh with uniform edges; `keep_face` keeps flat faces up to their
// rims (graded_remesher.hpp). bemsurg's scenes remesh in the same way (operating_region with equal
// inside and outside edge lengths).
TriangleMesh uniform_remesh(const TriangleMesh& fine, double edge_length, bool keep_face, double rim_area_loss) {
  GradedRemeshOptions o;
  o.inside_edge_length = o.outside_edge_length = edge_length;  // uniform: the region only has to meet the surface
  o.keep_planar_regions = keep_face;
  o.planar_rim_area_loss = keep_face ? rim_area_loss : 0.0;
  return graded_remesh(fine, OperatingRegion::sphere(fine.vertex(0), edge_length), o).mesh;
}

// The BEM mesh of the brain: the icosphere brain itself, or (edge_length > 0) the fine surface remeshed.
TriangleMesh bem_mesh(int subdivisions, int surface_subdivisions, double edge_length, bool keep_face, double rim_area_loss) {
  if (edge_length <= 0.0) return hanging_brain(subdivisions);
  return uniform_remesh(hanging_brain(surface_subdivisions), edge_length, keep_face, rim_area_loss);
}

// The liver remeshed as a scene with "mesh": {"generator": "liver", "subdivisions": S} and an
// operating region of equal edge lengths H remeshes it: its element count and volume (the peer
// scales the scene's density by the finite-element volume over this one).
int liver_mesh_summary(int surface_subdivisions, double edge_length, const std::string& json_path) {
  LiverModelOptions o;
  o.subdivisions = surface_subdivisions;
  const TriangleMesh mesh = uniform_remesh(liver_mesh(o), edge_length, true, 0.0);
  nlohmann::json j;
  j["benchmark"] = "bench_organ_gravity";
  j["organ"] = "liver";
  j["edge_length_m"] = edge_length;
  j["elements"] = mesh.num_elements();
  j["volume_m3"] = mesh.enclosed_volume();
  return bench::write_json_file(json_path, j, "bench_organ_gravity") ? 0 : 1;
}

bool on_patch(const Vec3& c, double radius) {
  return std::abs(c.z()) <= kPlaneTolerance && c.x() * c.x() + c.y() * c.y() <= radius * radius;
}

enum Label : int { kFree = 0, kHeld = 1, kTool = 2 };

// OBJ with the faces in groups by label (calculix_peer.py reads the groups).
bool write_labelled_obj(const std::string& path, const TriangleMesh& mesh, const std::vector<int>& label) {
  std::ofstream out(path);
  use_classic_locale(out);
  out << "# bemsurg bench_organ_gravity: the finite-element peer's surface, faces grouped held / tool / free\n";
  for (Index v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3 p = mesh.vertex(v);
    out << "v " << number_text(p.x()) << " " << number_text(p.y()) << " " << number_text(p.z()) << "\n";
  }
  const char* names[] = {"free", "held", "tool"};
  for (int l : {kFree, kHeld, kTool}) {
    out << "g " << names[l] << "\n";
    for (Index e = 0; e < mesh.num_elements(); ++e)
      if (label[static_cast<std::size_t>(e)] == l)
        out << "f " << mesh.faces()(e, 0) + 1 << " " << mesh.faces()(e, 1) + 1 << " " << mesh.faces()(e, 2) + 1 << "\n";
  }
  return static_cast<bool>(out);
}

// One of the liver's spheres: centred on the surface in direction (dx, dy, dz), radius r.
struct SurfaceSphere {
  Vec3 center;
  double radius;
};

SurfaceSphere surface_sphere(const LiverModelOptions& o, const std::vector<double>& spec, const char* option) {
  if (spec.size() != 4 || !(spec[3] > 0.0) || Vec3(spec[0], spec[1], spec[2]).norm() == 0.0)
    throw Error(std::string("bench_organ_gravity: ") + option + " takes DX,DY,DZ,R: a non-zero direction and a radius > 0");
  return {liver_surface_point(o, Vec3(spec[0], spec[1], spec[2]).normalized()), spec[3]};
}

// The liver split along the held sphere and the tool's, labelled; `j` gets the spheres, the exact
// areas inside them and the areas the split holds.
TriangleMesh labelled_liver(int subdivisions, const std::vector<double>& held_spec, const std::vector<double>& tool_spec,
                            std::vector<int>& label, nlohmann::json& j) {
  LiverModelOptions o;
  o.subdivisions = subdivisions;
  TriangleMesh mesh = liver_mesh(o);
  label.assign(static_cast<std::size_t>(mesh.num_elements()), kFree);
  const std::pair<const std::vector<double>*, Label> parts[] = {{&held_spec, kHeld}, {&tool_spec, kTool}};
  for (const auto& [spec, which] : parts) {
    const SurfaceSphere s = surface_sphere(o, *spec, which == kHeld ? "--held-sphere" : "--tool-sphere");
    ElementSplit split = conform_to_region(mesh, SpaceRegion::ball(s.center, s.radius));
    std::vector<int> next(static_cast<std::size_t>(split.mesh.num_elements()));
    for (std::size_t e = 0; e < next.size(); ++e) {
      next[e] = label[static_cast<std::size_t>(split.parent[e])];
      if (split.inside[e]) {
        if (next[e] != kFree) throw Error("bench_organ_gravity: the held sphere and the tool's overlap on the surface");
        next[e] = which;
      }
    }
    mesh = std::move(split.mesh);
    label = std::move(next);
    j[which == kHeld ? "held_sphere" : "tool_sphere"] = {{"center", {s.center.x(), s.center.y(), s.center.z()}},
                                                         {"radius", s.radius},
                                                         {"region_area_m2", split.region_area},
                                                         {"split_area_m2", split.held_area}};
  }
  return mesh;
}

// --write-surface: the finite-element mesher's surface, written as a labelled OBJ.
int write_surface(const std::string& organ, int subdivisions, const std::vector<double>& held, const std::vector<double>& tool,
                  const std::string& path, const std::string& json_path) {
  nlohmann::json j;
  j["benchmark"] = "bench_organ_gravity";
  j["organ"] = organ;
  std::vector<int> label;
  TriangleMesh mesh;
  if (organ == "liver") {
    mesh = labelled_liver(subdivisions, held, tool, label, j);
  } else {
    mesh = hanging_brain(subdivisions);
    for (Index e = 0; e < mesh.num_elements(); ++e) label.push_back(on_patch(mesh.centroid(e), 1.0) ? kHeld : kFree);
  }
  double area[3] = {0.0, 0.0, 0.0};
  for (Index e = 0; e < mesh.num_elements(); ++e) area[label[static_cast<std::size_t>(e)]] += mesh.area(e);
  j["held_area_m2"] = area[kHeld];
  j["tool_area_m2"] = area[kTool];
  if (!write_labelled_obj(path, mesh, label)) {
    std::cerr << "bench_organ_gravity: cannot write " << path << "\n";
    return 1;
  }
  j["triangles"] = mesh.num_elements();
  j["volume_m3"] = mesh.enclosed_volume();
  std::cerr << "wrote " << path << ": " << mesh.num_elements() << " triangles, volume " << mesh.enclosed_volume() << " m^3\n";
  return bench::write_json_file(json_path, j, "bench_organ_gravity") ? 0 : 1;
}

}  // namespace

// long: one straight sequence of options, solve and outputs, clearer unsplit
int main(int argc, char** argv) {
  bool quick = false, old_clamp = false;
  std::string json_path, points_path, clamped_path, surface_path, organ = "brain";
  int subdivisions = 3, surface_subdivisions = 5;
  double patch_radius = 1.0, edge_length = 0.0, rim_area_loss = 0.0, hung_volume = 0.0;  // radius past the flat face: all of it
  double hmatrix_tolerance = 0.0;  // > 0: the hierarchical backend at this compression tolerance
  std::vector<double> held_sphere, tool_sphere;
  cli::OptionParser parser = bench::command_line(
      "bench_organ_gravity", "The upside-down brain hung from a disc of its flat face under gravity (the CalculiX peer's BEM side).\n",
      quick, json_path);
  parser.value("--subdivisions", "S", subdivisions, "icosphere subdivisions of the BEM mesh: 20 * 4^S elements").at_least(0);
  parser.value("--edge-length", "H", edge_length, "remesh the fine surface with edges of about H (m) instead (Gmsh)").above(0.0);
  parser.value("--rim-area-loss", "L", rim_area_loss, "with --edge-length: mesh the flat face's rim so that it loses about L of it")
      .between(0.0, 0.1);
  parser.flag("--old-clamp", old_clamp, "with --edge-length: do not keep the flat face through the remesh (releases before issue 38)");
  parser.value("--hung-volume", "V", hung_volume, "scale the density so that the weight is density * g * V (m^3)").above(0.0);
  parser.value("--patch-radius", "R", patch_radius, "radius of the clamped disc on the flat face (m); 1 (default): the whole face")
      .above(0.0);
  parser.value("--hmatrix", "T", hmatrix_tolerance, "solve on the hierarchical backend at compression tolerance T (default: dense LU)")
      .between(1e-12, 0.1);
  parser.value("--points-out", "CSV", points_path, "write element centroids, areas and displacements to CSV");
  parser.value("--clamped-out", "CSV", clamped_path, "write the corners of the clamped elements to CSV (x0,y0,z0,...,z2)");
  parser.value("--write-surface", "PATH", surface_path, "write the finite-element mesher's surface as grouped OBJ and exit");
  parser.value("--surface-subdivisions", "S", surface_subdivisions, "subdivisions of the surface --write-surface writes").at_least(0);
  parser.value("--organ", "NAME", organ, "with --write-surface: brain (default) or liver");
  parser.value("--held-sphere", "DX,DY,DZ,R", held_sphere, "liver: the held region, a sphere on the surface in that direction");
  parser.value("--tool-sphere", "DX,DY,DZ,R", tool_sphere, "liver: the tool's footprint, a sphere on the surface in that direction");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (quick) subdivisions = 2;  // 320 elements: under a second
  if (organ != "brain" && organ != "liver") {
    std::cerr << "bench_organ_gravity: --organ takes brain or liver, not '" << organ << "'\n";
    return 2;
  }
  if (!surface_path.empty()) {
    try {
      return write_surface(organ, surface_subdivisions, held_sphere, tool_sphere, surface_path, json_path);
    } catch (const std::exception& e) {
      std::cerr << e.what() << "\n";
      return 1;
    }
  }
  if (organ != "brain") {
    if (edge_length > 0.0) return liver_mesh_summary(surface_subdivisions, edge_length, json_path);
    std::cerr << "bench_organ_gravity: the liver is solved by `bemsurg solve` (scripts/report/parts/peer.py); here only "
                 "--write-surface, or --edge-length for its remeshed volume\n";
    return 2;
  }

  const bench::Clock::time_point start = bench::Clock::now();
  const TriangleMesh mesh = bem_mesh(subdivisions, surface_subdivisions, edge_length, !old_clamp, rim_area_loss);
  const double volume = mesh.enclosed_volume();
  // The weight both sides hang: the density scaled to the given volume (issue 38 item 5), or this mesh's own.
  const double density = hung_volume > 0.0 ? kDensity * hung_volume / volume : kDensity;
  const Material material{kYoung, kPoisson, density};
  BoundaryConditions bc(mesh.num_elements());  // traction-free by default
  Index clamped = 0;
  for (Index e = 0; e < mesh.num_elements(); ++e)
    if (on_patch(mesh.centroid(e), patch_radius)) {
      bc.prescribe_displacement(e, Vec3::Zero());
      ++clamped;
    }
  if (clamped == 0) {
    std::cerr << "bench_organ_gravity: no element centroid lies on the patch; use a larger --patch-radius\n";
    return 1;
  }
  const ElastostaticProblem problem{mesh, material, Eigen::Vector3d(0.0, 0.0, -kGravity), bc, QuadratureOptions()};
  LinearSolverOptions solver;
  if (hmatrix_tolerance > 0.0) {  // the hierarchical front of the report's peer (issue 40)
    solver.backend = SolverBackend::HMatrix;
    solver.compression_tolerance = hmatrix_tolerance;
  }
  const ElastostaticSolution s =
      hmatrix_tolerance > 0.0 ? solve_elastostatic_hierarchical(problem, solver) : solve_elastostatic(problem, solver);
  const double total_s = seconds_since(start);

  // The support's reaction on the body must balance the weight: sum of t * area over the patch.
  Vec3 reaction = Vec3::Zero();
  double patch_area = 0.0, max_u = 0.0;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    max_u = std::max(max_u, s.boundary.displacement.row(e).norm());
    if (!on_patch(mesh.centroid(e), patch_radius)) continue;
    reaction += mesh.area(e) * s.boundary.traction.row(e).transpose();
    patch_area += mesh.area(e);
  }
  const double weight = density * kGravity * volume;
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
          << (on_patch(c, patch_radius) ? 1 : 0);
      for (int k = 0; k < 3; ++k) csv << "," << number_text(s.boundary.displacement(e, k));
      csv << "\n";
    }
    if (!csv) {
      std::cerr << "bench_organ_gravity: cannot write " << points_path << "\n";
      return 1;
    }
  }
  if (!clamped_path.empty()) {
    std::ofstream csv(clamped_path);
    use_classic_locale(csv);
    csv << "x0,y0,z0,x1,y1,z1,x2,y2,z2\n";
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      if (!on_patch(mesh.centroid(e), patch_radius)) continue;
      const std::array<Vec3, 3> c = mesh.corners(e);
      for (int k = 0; k < 9; ++k) csv << (k ? "," : "") << number_text(c[static_cast<std::size_t>(k / 3)](k % 3));
      csv << "\n";
    }
    if (!csv) {
      std::cerr << "bench_organ_gravity: cannot write " << clamped_path << "\n";
      return 1;
    }
  }
  nlohmann::json j;
  j["benchmark"] = "bench_organ_gravity";
  j["quick"] = quick;
  j["flat_face_kept"] = edge_length > 0.0 && !old_clamp;
  j["rim_area_loss"] = rim_area_loss;
  j["density_kg_m3"] = density;  // kDensity, or scaled by --hung-volume
  j["subdivisions"] = subdivisions;
  j["edge_length_m"] = edge_length;  // 0: the icosphere mesh of `subdivisions`
  j["elements"] = mesh.num_elements();
  j["clamped_elements"] = clamped;
  j["equations"] = s.report.equations;
  j["backend"] = hmatrix_tolerance > 0.0 ? "hmatrix" : "dense";
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
  j["material"] = {{"young_modulus_pa", kYoung}, {"poisson_ratio", kPoisson}, {"density_kg_m3", density}};
  j["gravity_m_s2"] = {0.0, 0.0, -kGravity};
  j["patch"] = {{"kind", "disc on the plane z = 0: x^2 + y^2 <= radius^2"},
                {"plane_z", 0.0},
                {"centre", {0.0, 0.0, 0.0}},
                {"radius_m", patch_radius},
                {"bem_rule", "element centroid on the plane and within the radius"}};
  return bench::write_json_file(json_path, j, "bench_organ_gravity") ? 0 : 1;
}
