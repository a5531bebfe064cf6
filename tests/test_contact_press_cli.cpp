// Tests for `bemsurg press` (src/cli/press_command.cpp, docs/design.md §6): the outputs' format and the
// physics they carry (force against the tractions in elements.csv), and clear refusals.
#include <catch2/catch.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/temp_dir.hpp"

namespace fs = std::filesystem;

namespace {
int run_press_cli(const std::string& args) {
  const std::string cmd = std::string(BEMSURG_CLI_PATH) + " " + args + " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
}  // namespace

TEST_CASE("bemsurg press writes elements.csv and force.json consistent with each other", "[contact][cli]") {
  const bemsurg_test::TempDir temp("bemsurg_test_press_");
  const fs::path& dir = temp.path;
  {
    std::ofstream scene(dir / "scene.json");
    scene << R"({"mesh": {"generator": "box", "min": [-0.05, -0.05, 0], "max": [0.05, 0.05, 0.05], "divisions": [6, 6, 3]},
                 "material": {"young_modulus": 3000, "poisson_ratio": 0.45, "density": 1000},
                 "gravity": [0, 0, -9.81],
                 "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}},
                                                    "displacement": [0, 0, 0]}]}})";
  }
  const std::string scene = (dir / "scene.json").string(), out = (dir / "out").string();
  const auto started = std::chrono::steady_clock::now();
  REQUIRE(run_press_cli("press " + scene + " --tool flat:0.02 --at 0,0,0.05 --direction 0,0,-1 --depth 0.002 --frictionless -o " + out) ==
          0);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  std::ifstream fj(dir / "out" / "force.json");
  const nlohmann::json j = nlohmann::json::parse(fj);
  const std::vector<double> force = j.at("force").get<std::vector<double>>();
  REQUIRE(force.size() == 3);
  CHECK(force[2] > 0.0);  // the tissue pushes the tool back up
  CHECK(j.at("contact_elements").get<int>() > 0);
  // Timings, checked for consistency only (the speed is bench_contact's subject: its
  // "force_only_update_us" median, beside "bare_force_product_us" in the same run, is the path
  // force_update_us times; these tests also run under sanitizers): the run's total lies within the
  // wall time measured here, the force update is reported, and the table's phases add up to at
  // most the total. Measured: update 0.03 us, total 0.14 s, wall 0.25 s.
  const double total = j.at("total_seconds").get<double>(), update_us = j.at("force_update_us").get<double>();
  INFO("force update " << update_us << " us, total " << total << " s, wall " << wall << " s");
  CHECK(total <= wall);
  CHECK(update_us > 0.0);
  const auto& table = j.at("table");
  CHECK(table.at("loaded_from_file") == false);
  CHECK(table.at("assembly_seconds").get<double>() > 0.0);
  CHECK(table.at("factorization_seconds").get<double>() > 0.0);
  CHECK(table.at("assembly_seconds").get<double>() + table.at("factorization_seconds").get<double>() +
            table.at("table_seconds").get<double>() <=
        total);
  // The force is minus the sum of area x traction over the elements in contact (the rest of the
  // free top face carries no traction), and the top elements under the disc moved down 2 mm more.
  std::ifstream csv(dir / "out" / "elements.csv");
  std::string line;
  std::getline(csv, line);
  CHECK(line == "element,cx,cy,cz,nx,ny,nz,area,ux,uy,uz,tx,ty,tz");
  double fz = 0.0;
  int loaded = 0;
  while (std::getline(csv, line)) {
    std::stringstream ss(line);
    std::vector<double> v;
    std::string cell;
    while (std::getline(ss, cell, ',')) v.push_back(std::stod(cell));
    REQUIRE(v.size() == 14);
    if (v[6] > 0.99 && std::abs(v[13]) > 0.0) {
      fz -= v[7] * v[13];
      ++loaded;
    }
  }
  CHECK(loaded == j.at("contact_elements").get<int>());
  // The same `loaded` terms of one sign summed in another order, read back exactly (shortest
  // round-trip text): 2 loaded eps (measured 0, 8 elements).
  CHECK(fz == Approx(force[2]).epsilon(2.0 * loaded * std::numeric_limits<double>::epsilon()));
  // Refusals: unknown tool (usage, 2), a line that misses the body (error, 1).
  CHECK(run_press_cli("press " + scene + " --tool cone --at 0,0,1 --direction 0,0,-1 --depth 0.001 -o " + out) == 2);
  CHECK(run_press_cli("press " + scene + " --tool point --at 5,5,1 --direction 0,0,-1 --depth 0.001 -o " + out) == 1);
  CHECK(run_press_cli("press " + scene + " --tool point --at 0,0,1 --direction 0,0,0 --depth 0.001 -o " + out) == 2);
}

namespace {
// Runs bemsurg with `args`; returns the exit status and puts stdout + stderr in `output`.
int run_capture(const std::string& args, const fs::path& log, std::string& output) {
  const std::string cmd = std::string(BEMSURG_CLI_PATH) + " " + args + " > '" + log.string() + "' 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream ss;
  ss << in.rdbuf();
  output = ss.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

double force_z(const fs::path& out) {
  std::ifstream fj(out / "force.json");
  return nlohmann::json::parse(fj).at("force").get<std::vector<double>>().at(2);
}
}  // namespace

TEST_CASE("bemsurg press refuses depths beyond the small-strain range and stays continuous inside it", "[contact][cli]") {
  const bemsurg_test::TempDir temp("bemsurg_test_press_range_");
  const fs::path& dir = temp.path;
  auto write_scene = [&](const std::string& name, double height, int nz) {
    std::ofstream scene(dir / name);
    scene << R"({"mesh": {"generator": "box", "min": [-0.05, -0.05, 0], "max": [0.05, 0.05, )" << height << R"(], "divisions": [6, 6, )"
          << nz << R"(]},
                 "material": {"young_modulus": 3000, "poisson_ratio": 0.45, "density": 1000},
                 "gravity": [0, 0, -9.81],
                 "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}},
                                                    "displacement": [0, 0, 0]}]}})";
    return (dir / name).string();
  };
  const std::string flat_block = write_scene("block.json", 0.05, 3), tall = write_scene("tall.json", 0.2, 6);
  const std::string out = (dir / "out").string(), table = (dir / "table.bin").string();
  const fs::path log = dir / "log.txt";
  std::string text;

  // Before: a sphere pushed deeper than its radius gave zero force on zero elements with exit 0;
  // a flat tool pushed 1.7e308 gave NaN forces; 1 m into a 5 cm body gave a force without a word.
  CHECK(run_capture("press " + tall + " --tool sphere:0.02 --at 0,0,0.3 --direction 0,0,-1 --depth 0.025 -o " + out, log, text) == 1);
  CHECK_THAT(text, Catch::Contains("1.25 times the tool radius 0.02") && Catch::Contains("depth <= 0.01"));
  CHECK(run_capture("press " + flat_block + " --tool flat:0.02 --at 0,0,0.1 --direction 0,0,-1 --depth 1.7e308 -o " + out, log, text) == 1);
  CHECK_THAT(text, Catch::Contains("small-strain range") && Catch::Contains("depth <= 0.01"));
  CHECK(run_capture("press " + flat_block + " --tool point --at 0,0,0.1 --direction 0,0,-1 --depth 1 -o " + out, log, text) == 1);
  CHECK_THAT(text, Catch::Contains("2e+03 % of the body's extent along the push (0.05)"));
  CHECK_FALSE(fs::exists(dir / "out" / "force.json"));  // refused before any work

  // Inside the range the force grows continuously with the depth up to the limit (20 % of the
  // 0.05 body = 0.01; the sphere's own limit 0.5 R = 0.02 is further): a frictionless sphere on a
  // fixed contact set is linear in the depth, and the set grows from 8 to 16 elements at 0.009.
  // Measured F/d relative to the shallowest: 1.000 up to 0.008, then 1.015, 1.082; bound 12 % (1.5x).
  // Above 5 % strain (0.0025) a warning says the model is approximate.
  const std::vector<double> depths = {0.001, 0.003, 0.005, 0.007, 0.009, 0.01};
  double stiffness0 = 0.0, previous = 0.0;
  for (double d : depths) {
    INFO("depth " << d);
    REQUIRE(run_capture("press " + flat_block + " --tool sphere:0.04 --frictionless --at 0,0,0.1 --direction 0,0,-1 --depth " +
                            std::to_string(d) + " --table " + table + " -o " + out,
                        log, text) == 0);
    CHECK((text.find("warning: press: the tool pushes") != std::string::npos) == (d > 0.0025));
    const double f = force_z(dir / "out");
    CHECK(f > previous);
    if (stiffness0 == 0.0) stiffness0 = f / d;
    CHECK(std::abs(f / d / stiffness0 - 1.0) < 0.12);
    previous = f;
  }
  // Just beyond the limit: refused, not a jump.
  CHECK(run_capture("press " + flat_block + " --tool sphere:0.04 --frictionless --at 0,0,0.1 --direction 0,0,-1 --depth 0.0101 --table " +
                        table + " -o " + out,
                    log, text) == 1);
  CHECK_THAT(text, Catch::Contains("beyond the small-strain range"));
}

TEST_CASE("bemsurg table writes the table that press then reads without recomputing", "[contact][cli]") {
  // docs/cli.md "bemsurg table": the scene's table (its operating region) computed into FILE and
  // report.json; `press --table FILE` reads it (loaded_from_file) and its force equals the force of a
  // press that computes its own table: the same columns, so the same numbers bit for bit.
  const bemsurg_test::TempDir temp("bemsurg_test_table_");
  const fs::path& dir = temp.path;
  {
    std::ofstream scene(dir / "scene.json");
    scene << R"({"mesh": {"generator": "box", "min": [-0.05, -0.05, 0], "max": [0.05, 0.05, 0.05], "divisions": [6, 6, 3]},
                 "material": {"young_modulus": 3000, "poisson_ratio": 0.45, "density": 1000}, "gravity": [0, 0, -9.81],
                 "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}},
                                                    "displacement": [0, 0, 0]}]},
                 "operating_region": {"sphere": {"center": [0, 0, 0.05], "radius": 0.03}}})";
  }
  const std::string scene = (dir / "scene.json").string(), file = (dir / "t.tbl").string();
  REQUIRE(run_press_cli("table " + scene + " --table " + file + " -o " + (dir / "t").string()) == 0);
  std::ifstream fr(dir / "t" / "report.json");
  const nlohmann::json r = nlohmann::json::parse(fr);
  CHECK(r.at("ranks") == 1);
  CHECK(r.at("backend") == "dense");
  CHECK(r.at("columns").get<int>() == 3 * r.at("region_elements").get<int>());
  CHECK(r.at("region_elements").get<int>() > 0);
  CHECK(r.at("region_elements").get<int>() < r.at("elements").get<int>());  // the operating region, not every free element
  CHECK(r.at("equations").get<int>() == 3 * r.at("elements").get<int>());
  CHECK(r.at("peak_memory_mb_per_rank").size() == 1);
  CHECK(r.at("peak_memory_mb_per_rank")[0].get<double>() > 0.0);
  CHECK(r.at("seconds").get<double>() >= r.at("factorization_seconds").get<double>());
  CHECK(r.at("table_bytes").get<std::uintmax_t>() == fs::file_size(file));
  const std::string press = "press " + scene + " --tool flat:0.02 --at 0,0,0.05 --direction 0,0,-1 --depth 0.002 -o ";
  REQUIRE(run_press_cli(press + (dir / "read").string() + " --table " + file) == 0);
  REQUIRE(run_press_cli(press + (dir / "fresh").string()) == 0);
  std::ifstream fa(dir / "read" / "force.json"), fb(dir / "fresh" / "force.json");
  const nlohmann::json a = nlohmann::json::parse(fa), b = nlohmann::json::parse(fb);
  CHECK(a.at("table").at("loaded_from_file") == true);
  CHECK(b.at("table").at("loaded_from_file") == false);
  CHECK(a.at("force") == b.at("force"));
  // Run again, it replaces the file (the table is its product), and a bad scene path is an error.
  const auto written = fs::last_write_time(file);
  REQUIRE(run_press_cli("table " + scene + " --table " + file + " -o " + (dir / "t2").string() + " --quiet") == 0);
  CHECK(fs::last_write_time(file) >= written);
  std::ifstream fr2(dir / "t2" / "report.json");
  CHECK(nlohmann::json::parse(fr2).at("factorization_seconds").get<double>() > 0.0);  // computed, not read
  CHECK(run_press_cli("table " + (dir / "missing.json").string() + " --table " + file + " -o " + (dir / "t3").string()) == 1);
  CHECK(run_press_cli("table " + scene + " -o " + (dir / "t4").string()) == 2);  // --table is required
}
