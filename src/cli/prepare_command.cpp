// `bemsurg prepare IN -o OUT.obj`: a segmentation's surface, in any of the formats mesh/mesh_io.hpp
// reads and any unit, repaired and remeshed into a closed, outward surface in metres that the
// other commands can solve (mesh/mesh_preparation.hpp; docs/organs.md). Prints what was found and
// done, and with --report writes it as JSON.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/meshing/mesh_preparation.hpp"
#include "bemsurg/version.hpp"
#include "commands.hpp"

namespace {

using bemsurg::cli::UsageError;

constexpr const char* kPrepareUsage =
    "usage: bemsurg prepare IN -o OUT.obj [--units mm|cm|m | --scale S]\n"
    "                       [--target-elements N | --edge-length L | --region X,Y,Z --radius R\n"
    "                        --inside-edge-length H1 --outside-edge-length H2] [--report PATH]\n"
    "                       [--max-hole F] [--wrap-alpha F] [--wrap-offset F] [--rebuild] [--keep-all] [--quiet]\n"
    "\n"
    "Reads IN (.stl binary or ASCII, .obj, .off, .ply, .vtk), scales it to metres, repairs it\n"
    "(duplicate vertices, degenerate faces, orientation, holes; a surface that crosses itself, is\n"
    "not manifold or has overlapping shells is rebuilt by alpha wrapping), keeps the largest body\n"
    "(with its cavities) and remeshes it: graded to an operating region, uniform to N elements or\n"
    "edge length L (metres), or by default to 3000 elements, 6000 where this bemsurg has the\n"
    "hierarchical backend (fewer: kept as repaired). Writes\n"
    "OUT.obj in metres; the same input and options give the same file. docs/organs.md.\n";

struct PrepareCommandOptions {
  std::string input, output, report, units;
  double scale = 0.0, edge_length = 0.0, radius = 0.0, inside = 0.0, outside = 0.0;
  double max_hole = bemsurg::kDefaultMaxHoleFraction, alpha = bemsurg::kDefaultWrapAlphaFraction;
  double offset = bemsurg::kDefaultWrapOffsetFraction;
  int target_elements = 0;
  Eigen::Vector3d region = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  bool rebuild = false, keep_all = false, quiet = false;
};

std::optional<PrepareCommandOptions> parse_prepare_options(int argc, char** argv) {
  PrepareCommandOptions o;
  bemsurg::cli::OptionParser p("prepare", kPrepareUsage);
  p.positional("IN", o.input, "one input mesh per run").required();
  p.value("-o, --output", "OUT.obj", o.output, "the prepared mesh (Wavefront OBJ, metres)").required();
  p.value("--units", "mm|cm|m", o.units, "the input's length unit");
  p.value("--scale", "S", o.scale, "multiply the input's coordinates by S to get metres (instead of --units)").above(0.0);
  p.value("--target-elements", "N", o.target_elements, "remesh uniformly to about N elements")
      .between(1, double(bemsurg::kMaxPreparedElements));
  p.value("--edge-length", "L", o.edge_length, "remesh uniformly to edge length L (metres)").above(0.0);
  bemsurg::cli::vector3_value(p, "--region", "X,Y,Z", o.region, "graded remesh: the operating region's centre (metres)");
  p.value("--radius", "R", o.radius, "graded remesh: the operating region's radius").above(0.0);
  p.value("--inside-edge-length", "H1", o.inside, "graded remesh: edge length in the region").above(0.0);
  p.value("--outside-edge-length", "H2", o.outside, "graded remesh: edge length far from it").above(0.0);
  p.value("--report", "PATH", o.report, "write what was found and done as JSON");
  p.value("--max-hole", "F", o.max_hole, "fill holes whose boundary is shorter than F x the bounding-box diagonal").above(0.0);
  p.value("--wrap-alpha", "F", o.alpha, "rebuild: close details narrower than F x the diagonal").above(0.0);
  p.value("--wrap-offset", "F", o.offset, "rebuild: lie F x alpha outside the input").above(0.0);
  p.flag("--rebuild", o.rebuild, "rebuild by alpha wrapping even if the surface is already a body");
  p.flag("--keep-all", o.keep_all, "keep every disjoint body, not only the largest");
  p.flag("-q, --quiet", o.quiet, "print nothing but errors and warnings");
  if (!p.parse(argc, argv)) {
    std::cout << p.help();
    return std::nullopt;
  }
  if (!o.units.empty() && o.scale > 0.0) throw UsageError("prepare: give --units or --scale, not both");
  const bool graded = o.region.allFinite() || o.radius > 0.0 || o.inside > 0.0 || o.outside > 0.0;
  if (graded && !(o.region.allFinite() && o.radius > 0.0 && o.inside > 0.0 && o.outside > 0.0))
    throw UsageError("prepare: a graded remesh needs --region, --radius, --inside-edge-length and --outside-edge-length");
  if (int(graded) + int(o.target_elements > 0) + int(o.edge_length > 0.0) > 1)
    throw UsageError("prepare: give at most one of --target-elements, --edge-length and a graded region");
  return o;
}

bemsurg::MeshPreparationOptions preparation_options(const PrepareCommandOptions& c) {
  bemsurg::MeshPreparationOptions o;
  if (!c.units.empty()) {
    try {
      o.scale = bemsurg::length_unit_to_metres(c.units);
    } catch (const bemsurg::InvalidArgumentError& e) { throw UsageError(std::string("prepare: --units: ") + e.what()); }
    o.scale_given = true;
  } else if (c.scale > 0.0) {
    o.scale = c.scale;
    o.scale_given = true;
  }
  o.target_elements = c.target_elements;
  // Built with hmat-oss, the default organ is the one the hierarchical backend solves with its
  // table in about a minute, as 3,000 is for dense LU (docs/organs.md, "How big").
  if (bemsurg::hierarchical_backend_available()) o.default_elements = bemsurg::kDefaultPreparedElementsHierarchical;
  o.edge_length = c.edge_length;
  if (c.region.allFinite()) {
    o.region = bemsurg::OperatingRegion::sphere(c.region, c.radius);
    o.graded_options.inside_edge_length = c.inside;
    o.graded_options.outside_edge_length = c.outside;
  }
  o.max_hole_fraction = c.max_hole;
  o.wrap_alpha_fraction = c.alpha;
  o.wrap_offset_fraction = c.offset;
  o.force_wrap = c.rebuild;
  o.keep_all = c.keep_all;
  return o;
}

nlohmann::json report_json(const bemsurg::MeshPreparationReport& r, const PrepareCommandOptions& c) {
  const bemsurg::MeshDefectCounts& d = r.defects;
  nlohmann::json j;
  j["input"] = {{"file", c.input},
                {"faces", r.input_faces},
                {"vertices", r.input_vertices},
                {"scale", r.scale},
                {"size", {r.input_size(0), r.input_size(1), r.input_size(2)}}};
  j["defects"] = {{"duplicate_vertices", d.duplicate_vertices}, {"unreferenced_vertices", d.unreferenced_vertices},
                  {"degenerate_faces", d.degenerate_faces},     {"slivers", d.slivers},
                  {"duplicate_faces", d.duplicate_faces},       {"flipped_faces", d.flipped_faces},
                  {"boundary_edges", d.boundary_edges},         {"holes", d.holes},
                  {"non_manifold_edges", d.non_manifold_edges}, {"non_manifold_vertices", d.non_manifold_vertices},
                  {"self_intersections", d.self_intersections}, {"shells", d.shells}};
  j["repairs"] = {{"vertices_merged", d.duplicate_vertices},
                  {"faces_dropped", d.degenerate_faces + d.duplicate_faces},
                  {"faces_flipped", d.flipped_faces},
                  {"holes_filled", r.holes_filled},
                  {"rebuilt", r.rebuilt},
                  {"rebuild_reason", r.rebuild_reason},
                  {"wrap_alpha", r.wrap_alpha},
                  {"wrap_offset", r.wrap_offset},
                  {"bodies", r.bodies},
                  {"bodies_dropped", r.bodies_dropped},
                  {"dropped_volume", r.dropped_volume},
                  {"cavities", r.cavities},
                  {"repaired_elements", r.repaired_elements}};
  j["remesh"] = {{"kind", r.remesh}, {"target_elements", r.target_elements}, {"edge_length", r.target_edge_length}};
  j["output"] = {{"file", c.output}, {"elements", r.elements}, {"vertices", r.vertices}, {"units", "m"}};
  j["hausdorff_distance"] = r.hausdorff;
  j["hausdorff_relative"] = r.hausdorff_relative;
  j["input_volume"] = r.input_volume;
  j["volume"] = r.volume;
  j["volume_change"] = r.volume_change;
  j["estimate"] = {{"memory_bytes", r.estimated_bytes}, {"solve_seconds", r.estimated_seconds}};
  j["estimate"]["hierarchical_memory_bytes"] =
      r.hierarchical_estimated_bytes > 0.0 ? nlohmann::json(r.hierarchical_estimated_bytes) : nlohmann::json(nullptr);
  j["steps"] = r.steps;
  j["warnings"] = r.warnings;
  j["seconds"] = r.seconds;
  for (const auto& [stage, seconds] : r.timings) j["timings"][stage] = seconds;
  j["bemsurg_version"] = bemsurg::version_string();
  return j;
}

}  // namespace

int run_prepare(int argc, char** argv) {
  const std::optional<PrepareCommandOptions> c = parse_prepare_options(argc, argv);
  if (!c) return 0;
  const bemsurg::MeshPreparationOptions options = preparation_options(*c);
  bemsurg::TriangleMesh input;
  const auto read_start = std::chrono::steady_clock::now();
  try {
    input = bemsurg::read_mesh(c->input);
  } catch (const bemsurg::Error& e) { throw bemsurg::Error("prepare: cannot read '" + c->input + "': " + e.what()); }
  const double read_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
  bemsurg::PreparedMesh prepared;
  try {
    prepared = bemsurg::prepare_mesh(input, options);
  } catch (const bemsurg::InvalidMeshError& e) { throw bemsurg::Error("prepare: " + c->input + ": " + e.what()); }
  prepared.report.timings.insert(prepared.report.timings.begin(), {"read", read_seconds});
  prepared.report.estimated_bytes = bemsurg::estimate_elastostatic_bytes(prepared.report.elements);
  prepared.report.estimated_seconds = bemsurg::estimate_elastostatic_seconds(prepared.report.elements);
  if (bemsurg::hierarchical_backend_available())
    prepared.report.hierarchical_estimated_bytes = bemsurg::estimate_hierarchical_bytes(prepared.report.elements);
  bemsurg::write_obj(c->output, prepared.mesh);
  if (!c->report.empty()) {
    std::ofstream out(c->report);
    out << report_json(prepared.report, *c).dump(2) << "\n";
    if (!out) throw bemsurg::Error("prepare: cannot write the report '" + c->report + "'");
  }
  const std::string summary = bemsurg::describe_preparation(prepared.report);
  if (!c->quiet)
    std::cout << summary << "wrote " << c->output << "\n";
  else
    for (const std::string& w : prepared.report.warnings) std::cerr << "bemsurg: warning: " << w << "\n";
  return 0;
}
