// bench_cut_topology: latency of the topology half of a cut step (cutting/surface_cutter.hpp):
// open, extend and deepen on boxes of growing size, each against the cost of one full surface
// validation (validate_mesh + find_self_intersections) of the same mesh, measured in the same run.
// Every step rebuilds a snapshot and re-checks the whole surface (O(F log F)), so the ratio says
// how much the groove construction adds to the checks that make it safe.
//
// usage: bench_cut_topology [--quick] [--json PATH] [--sizes N1,N2,...]  (N: box cells per edge)
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bemsurg/cutting/surface_cutter.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bench_support.hpp"

using namespace bemsurg;

int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path;
  std::vector<int> sizes;
  cli::OptionParser parser =
      bench::command_line("bench_cut_topology",
                          "The cutter's topology steps (open, extend, deepen) against a validation of the same mesh.\n", quick, json_path);
  parser.value("--sizes", "N1,N2,...", sizes, "cubes of N cells per edge").at_least(4).default_text("8,16,32; --quick: 6,10");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (sizes.empty()) sizes = quick ? std::vector<int>{6, 10} : std::vector<int>{8, 16, 32};
  const int repeats = quick ? 3 : 9;
  nlohmann::json result;
  result["benchmark"] = "bench_cut_topology";
  result["quick"] = quick;
  std::cout << "elements  validate_ms  open_ms  extend_ms  deepen_ms  extend/validate\n";
  for (int n : sizes) {
    const auto mesh = std::make_shared<const TriangleMesh>(box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), n, n, n));
    std::vector<double> validate, open, extend, deepen;
    for (int r = 0; r < repeats; ++r) {
      auto clock = SteadyClock::now();
      const bool valid = validate_mesh(*mesh).valid() && find_self_intersections(*mesh).empty();
      validate.push_back(seconds_since(clock));
      if (!valid) {
        std::cerr << "bench_cut_topology: the generated box is not a clean surface\n";
        return 1;
      }
      SurfaceCutter cutter(mesh, {});
      const Vec3 from(0.15 + 0.002 * r, 0.5, 1.0), direction(1, 0.05, 0);
      clock = SteadyClock::now();
      if (!cutter.step(from, direction).accepted) {
        std::cerr << "bench_cut_topology: opening the cut was refused\n";
        return 1;
      }
      open.push_back(seconds_since(clock));
      for (int s = 0; s < 3; ++s) {
        clock = SteadyClock::now();
        if (!cutter.step(from, direction).accepted) {
          std::cerr << "bench_cut_topology: extending the cut was refused\n";
          return 1;
        }
        extend.push_back(seconds_since(clock));
      }
      clock = SteadyClock::now();
      if (!cutter.deepen().accepted) {
        std::cerr << "bench_cut_topology: deepening the cut was refused\n";
        return 1;
      }
      deepen.push_back(seconds_since(clock));
    }
    const double v = bench::median(validate), o = bench::median(open), e = bench::median(extend), d = bench::median(deepen);
    std::printf("%8lld  %11s  %7s  %9s  %9s  %15s\n", static_cast<long long>(mesh->num_elements()), fixed_text(1e3 * v, 2).c_str(),
                fixed_text(1e3 * o, 2).c_str(), fixed_text(1e3 * e, 2).c_str(), fixed_text(1e3 * d, 2).c_str(),
                fixed_text(e / v, 2).c_str());
    result["sizes"].push_back({{"elements", mesh->num_elements()},
                               {"validate_seconds", v},
                               {"open_seconds", o},
                               {"extend_seconds", e},
                               {"deepen_seconds", d},
                               {"extend_over_validate", e / v}});
  }
  return bench::write_json_file(json_path, result, "bench_cut_topology") ? 0 : 1;
}
