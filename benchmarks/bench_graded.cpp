// bench_graded: the saving of a graded mesh (Wang et al. 2007 §6: fine only where the surgery
// happens; docs/graded.md). The brain scene (mesh/brain_model.hpp) remeshed two ways by the same
// remesher (mesh/graded_remesher.hpp): graded (h_in in the operating region, growing by 1.25 per
// element to h_out) and uniformly fine (h_in everywhere: the reference, measured in the same
// process). Both get the same Green's table for the operating region and the same sphere tool
// pressed into it (tests/support/studies/graded_comparison.hpp). Reported: elements, precompute time
// (assembly + LU + table; median of the repetitions), peak memory of the precomputation and the
// table kept, the tool force and the displacement in the region, and the graded/fine ratios.
//
// usage: bench_graded [--quick] [--json PATH] [--inside H] [--outside H] [--repeat N]
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "support/studies/graded_comparison.hpp"

using namespace bemsurg;

namespace {

struct Run {
  GradedRemeshResult mesh;
  graded::PressResult press;
  double precompute_median = 0.0;
};

Run run(const TriangleMesh& input, const graded::PressCase& c, double h_in, double h_out, int repeat) {
  GradedRemeshOptions o;
  o.inside_edge_length = h_in;
  o.outside_edge_length = h_out;
  Run r;
  r.mesh = graded_remesh(input, OperatingRegion::sphere(c.region_center, c.region_radius), o);
  std::vector<double> t;
  for (int i = 0; i < repeat; ++i) {
    r.press = graded::press(r.mesh.mesh, c);
    t.push_back(r.press.precompute_seconds);
  }
  r.precompute_median = bench::median(t);
  return r;
}

nlohmann::json describe(const Run& r) {
  const auto& q = r.mesh.quality;
  const auto& p = r.press;
  return {{"elements", p.elements},
          {"equations", 3 * p.elements},
          {"region_elements", p.region_elements},
          {"contact_elements", p.contact_elements},
          {"remesh_seconds", r.mesh.seconds},
          {"precompute_seconds_median", r.precompute_median},
          {"assembly_seconds", p.timings.assembly_seconds},
          {"factorization_seconds", p.timings.factorization_seconds},
          {"table_seconds", p.timings.table_seconds},
          {"peak_bytes", p.peak_bytes},
          {"table_bytes", p.table_bytes},
          {"force", {p.force.x(), p.force.y(), p.force.z()}},
          {"min_angle_degrees", q.min_angle_degrees},
          {"max_neighbour_size_ratio", q.max_neighbour_size_ratio},
          {"p99_neighbour_size_ratio", q.p99_neighbour_size_ratio}};
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path;
  double h_in = 0.007, h_out = 0.02;
  int repeat = 3;
  cli::OptionParser parser =
      bench::command_line("bench_graded",
                          "The brain pressed by a sphere on a graded mesh against a uniformly fine one (docs/graded.md).\n"
                          "--quick uses h_in 0.012, h_out 0.03 and one repeat, whatever else is given.\n",
                          quick, json_path);
  parser.value("--inside", "H", h_in, "edge length inside the region (m)").above(0.0);
  parser.value("--outside", "H", h_out, "edge length outside it (m)").above(0.0);
  parser.value("--repeat", "N", repeat, "precomputations per mesh (median)").at_least(1);
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (!graded_remesher_available()) {
    std::cerr << "bench_graded: this build has no remesher (BEMSURG_WITH_REMESHER=OFF); nothing to measure\n";
    return 0;
  }
  if (quick) h_in = 0.012, h_out = 0.03, repeat = 1;

  BrainModelOptions brain;
  brain.subdivisions = 5;
  const TriangleMesh input = brain_mesh(brain);
  const graded::PressCase c = graded::brain_press_case(brain);

  const Run fine = run(input, c, h_in, h_in, quick ? 1 : std::max(1, repeat / 3));
  const Run grad = run(input, c, h_in, h_out, repeat);
  const double force_error = (grad.press.force - fine.press.force).norm() / fine.press.force.norm();
  const double disp_error = graded::region_displacement_difference(fine.mesh.mesh, fine.press, grad.mesh.mesh, grad.press, c);
  nlohmann::json out = {
      {"program", "bench_graded"},
      {"quick", quick},
      {"inside_edge_length", h_in},
      {"outside_edge_length", h_out},
      {"tool", {{"shape", "sphere"}, {"radius", c.tool_radius}, {"depth", c.depth}}},
      {"region", {{"center", {c.region_center.x(), c.region_center.y(), c.region_center.z()}}, {"radius", c.region_radius}}},
      {"fine", describe(fine)},
      {"graded", describe(grad)},
      {"ratios_graded_over_fine",
       {{"elements", double(grad.press.elements) / double(fine.press.elements)},
        {"peak_memory", grad.press.peak_bytes / fine.press.peak_bytes},
        {"table_memory", grad.press.table_bytes / fine.press.table_bytes},
        {"precompute_time", grad.precompute_median / fine.precompute_median}}},
      {"differences", {{"force_relative", force_error}, {"region_displacement_relative_l2", disp_error}}}};
  std::printf("bench_graded%s: brain, h_in %s m, h_out %s m, sphere tool R %s m pressed %s m\n", quick ? " --quick" : "",
              general_text(h_in, 4).c_str(), general_text(h_out, 4).c_str(), general_text(c.tool_radius, 3).c_str(),
              general_text(c.depth, 3).c_str());
  for (const auto* r : {&fine, &grad})
    std::printf(
        "  %-6s %5ld elements (region %ld, contact %ld)  precompute %s s  peak %s MB  table %s MB  "
        "Fz %s N  min angle %s  ratio max %s p99 %s\n",
        r == &fine ? "fine" : "graded", long(r->press.elements), long(r->press.region_elements), long(r->press.contact_elements),
        fixed_text(r->precompute_median, 3).c_str(), fixed_text(r->press.peak_bytes / 1e6, 1).c_str(),
        fixed_text(r->press.table_bytes / 1e6, 2).c_str(), fixed_text(r->press.force.z(), 5).c_str(),
        fixed_text(r->mesh.quality.min_angle_degrees, 1).c_str(), fixed_text(r->mesh.quality.max_neighbour_size_ratio, 2).c_str(),
        fixed_text(r->mesh.quality.p99_neighbour_size_ratio, 2).c_str());
  std::printf(
      "  graded/fine: elements %s, peak memory %s, precompute time %s; force differs by %s %%, "
      "region displacement by %s %% (L2)\n",
      fixed_text(out["ratios_graded_over_fine"]["elements"].get<double>(), 3).c_str(),
      fixed_text(out["ratios_graded_over_fine"]["peak_memory"].get<double>(), 3).c_str(),
      fixed_text(out["ratios_graded_over_fine"]["precompute_time"].get<double>(), 3).c_str(), fixed_text(100 * force_error, 2).c_str(),
      fixed_text(100 * disp_error, 2).c_str());
  return bench::write_json_file(json_path, out, "bench_graded") ? 0 : 1;
}
