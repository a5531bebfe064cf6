// The `bemsurg` program (docs/cli.md): exit codes, the exact output headers, one row per element,
// a solved field that matches a closed form (a solid under uniform pressure, docs/design.md §8:
// sigma = -p I, u = -p (1 - 2 nu) x / E), and bad scenes that fail with the key named.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "support/cli_run.hpp"
#include "support/skip.hpp"
#include "support/temp_dir.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;
namespace fs = std::filesystem;

namespace {

/// A fresh directory per test case, removed at the end (tests/support/temp_dir.hpp).
struct TempDir : bemsurg_test::TempDir {
  TempDir() : bemsurg_test::TempDir("bemsurg_test_cli_") {}
};

using bemsurg_test::read_text;
using Run = bemsurg_test::CliRun;

/// Runs the built program with `args` (already quoted), capturing stdout and stderr.
Run run_cli(const std::string& args, const TempDir& dir) { return bemsurg_test::run_cli(args, dir); }

using bemsurg_test::column_differences;
using bemsurg_test::read_table;
using Table = bemsurg_test::CsvTable;

constexpr double kE = 3000.0, kNu = 0.3, kP = 100.0;
using bemsurg_test::kEps;

/// Errors of the uniform-pressure solve of the cube [-1/2, 1/2]^3 with `div` divisions per side.
struct PressureErrors {
  double displacement = 0.0;           // max |u - u_exact| over elements / max |u_exact|
  double support_traction = 0.0;       // max |t + p n| on the elements with u prescribed / p
  double interior_displacement = 0.0;  // max |u - u_exact| at the interior points / max |u_exact| on the surface
  double interior_stress = 0.0;        // max |sigma + p I| at the interior points / p
};

/// Every element carries the pressure p except one per face (the one nearest the face's centre),
/// where the exact displacement -p (1 - 2 nu) c / E at its centroid is prescribed instead; those
/// six pin the rigid-body motion to the exact solution's (none).
PressureErrors solve_cube_under_pressure(int div, const TempDir& dir) {
  const TriangleMesh mesh = box_mesh(Vec3::Constant(-0.5), Vec3::Constant(0.5), div, div, div);
  const double k = -kP * (1.0 - 2.0 * kNu) / kE;  // u = k x
  std::vector<Index> pinned;
  std::ostringstream bc;
  bc.precision(17);
  bc << "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n";
  for (int c = 0; c < 3; ++c)
    for (double side : {-0.5, 0.5}) {
      const Vec3 centre = side * Vec3::Unit(c);
      Index best = 0;
      for (Index e = 1; e < mesh.num_elements(); ++e)
        if ((mesh.centroid(e) - centre).norm() < (mesh.centroid(best) - centre).norm()) best = e;
      pinned.push_back(best);
      const Vec3 u = k * mesh.centroid(best);
      bc << best << ",u,u,u," << u.x() << "," << u.y() << "," << u.z() << "\n";
    }
  const std::string tag = "cube" + std::to_string(div);
  dir.write(tag + "_bc.csv", bc.str());
  dir.write(tag + "_points.csv", "x,y,z\n0,0,0\n0.2,-0.1,0.3\n-0.25,0.25,-0.25\n");
  std::ostringstream scene;
  scene << R"({"mesh": {"generator": "box", "min": [-0.5, -0.5, -0.5], "max": [0.5, 0.5, 0.5], "divisions": [)" << div << "," << div << ","
        << div << R"(]},
      "material": {"young_modulus": 3000, "poisson_ratio": 0.3, "density": 0},
      "boundary_conditions": {"rules": [{"select": {"all": true}, "pressure": 100}], "file": ")"
        << tag << R"(_bc.csv"},
      "interior_points": {"file": ")"
        << tag << R"(_points.csv"}})";
  const std::string scene_path = dir.write(tag + ".json", scene.str());
  const std::string out = dir.file(tag + "_out");
  const Run r = run_cli("solve '" + scene_path + "' -o '" + out + "'", dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);

  const Table elements = read_table(out + "/elements.csv");
  CHECK(elements.header == "element,cx,cy,cz,nx,ny,nz,area,ux,uy,uz,tx,ty,tz");
  REQUIRE(elements.rows.size() == static_cast<std::size_t>(mesh.num_elements()));
  PressureErrors err;
  double u_max = 0.0;
  for (std::size_t e = 0; e < elements.rows.size(); ++e) {
    const auto& row = elements.rows[e];
    REQUIRE(row.size() == 14);
    CHECK(row[0] == static_cast<double>(e));
    const Vec3 c(row[1], row[2], row[3]), n(row[4], row[5], row[6]), u(row[8], row[9], row[10]), t(row[11], row[12], row[13]);
    // The CSV holds round-trip text of the same computations: measured 0; bounds 4 eps.
    CHECK((c - mesh.centroid(static_cast<Index>(e))).norm() <= 4 * kEps);
    CHECK((n - mesh.normal(static_cast<Index>(e))).norm() <= 4 * kEps);
    CHECK(row[7] == Approx(mesh.area(static_cast<Index>(e))).epsilon(4 * kEps));
    err.displacement = std::max(err.displacement, (u - k * c).norm());
    u_max = std::max(u_max, (k * c).norm());
    const bool is_pinned = std::find(pinned.begin(), pinned.end(), static_cast<Index>(e)) != pinned.end();
    if (is_pinned) {
      CHECK((u - k * c).norm() <= 4 * kEps * (k * c).norm());  // prescribed values come back exactly (measured 0)
      err.support_traction = std::max(err.support_traction, (t + kP * n).norm() / kP);
    } else {
      CHECK((t + kP * n).norm() <= 4 * kEps * kP);  // prescribed: measured 0
    }
  }
  err.displacement /= u_max;

  const Table interior = read_table(out + "/interior.csv");
  CHECK(interior.header == "x,y,z,ux,uy,uz,sxx,syy,szz,sxy,syz,sxz");
  REQUIRE(interior.rows.size() == 3);
  for (const auto& row : interior.rows) {
    REQUIRE(row.size() == 12);
    const Vec3 x(row[0], row[1], row[2]), u(row[3], row[4], row[5]);
    err.interior_displacement = std::max(err.interior_displacement, (u - k * x).norm() / u_max);
    for (int i = 0; i < 6; ++i) err.interior_stress = std::max(err.interior_stress, std::abs(row[6 + i] + (i < 3 ? kP : 0.0)) / kP);
  }
  return err;
}

}  // namespace

TEST_CASE("the program answers --version and --help and rejects bad command lines with exit code 2", "[cli]") {
  TempDir dir;
  Run r = run_cli("--version", dir);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Catch::StartsWith("bemsurg 0."));
  r = run_cli("--help", dir);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Catch::Contains("solve SCENE.json -o OUTDIR"));
  r = run_cli("solve --help", dir);
  CHECK(r.exit_code == 0);
  CHECK_THAT(r.out, Catch::Contains("report.json"));

  r = run_cli("", dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::StartsWith("bemsurg: error: missing command"));
  r = run_cli("frobnicate", dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("unknown command 'frobnicate'"));
  r = run_cli("solve scene.json", dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("-o OUTDIR"));
  r = run_cli("solve scene.json -o out --fast", dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("unknown option '--fast'"));
}

TEST_CASE("solve: a cube under uniform pressure matches sigma = -p I, u = -p (1 - 2 nu) x / E", "[cli][closed-form]") {
  TempDir dir;
  // Constant elements on a cube converge at first order near its edges and corners. Measured (2 -> 4
  // divisions, max-norm errors): surface displacement 8.29 % -> 3.81 % (order 1.12), support
  // traction 5.90 % -> 4.07 % (0.54), interior displacement 5.72 % -> 1.11 % (2.37), interior
  // stress 6.41 % -> 1.65 % (1.96). Bounds: orders ~0.75x, errors ~1.3-1.45x the measured.
  const PressureErrors coarse = solve_cube_under_pressure(2, dir);
  const PressureErrors fine = solve_cube_under_pressure(4, dir);
  INFO("displacement " << coarse.displacement << " -> " << fine.displacement << ", support traction " << coarse.support_traction << " -> "
                       << fine.support_traction << ", interior u " << coarse.interior_displacement << " -> " << fine.interior_displacement
                       << ", interior stress " << coarse.interior_stress << " -> " << fine.interior_stress);
  CHECK(coarse.displacement < 0.12);
  CHECK(fine.displacement < 0.05);
  CHECK(fine.support_traction < 0.055);
  CHECK(fine.interior_displacement < 0.0144);
  CHECK(fine.interior_stress < 0.0214);
  CHECK(std::log2(coarse.displacement / fine.displacement) > 0.84);
  CHECK(std::log2(coarse.support_traction / fine.support_traction) > 0.4);
  CHECK(std::log2(coarse.interior_displacement / fine.interior_displacement) > 1.78);
  CHECK(std::log2(coarse.interior_stress / fine.interior_stress) > 1.47);
}

TEST_CASE("slivers are warned about once by solve and by press, before their work", "[cli][errors]") {
  // A 1 x 1 x 0.0105 slab in 2 x 2 x 1 divisions: its 16 side faces have aspect ratio 41.3, above
  // kSliverWarningAspectRatio (40): the scene warns at load, and solve's own check does not repeat it.
  TempDir dir;
  const std::string scene = dir.write("slab.json", R"({
    "mesh": {"generator": "box", "min": [0, 0, 0], "max": [1, 1, 0.0105], "divisions": [2, 2, 1]},
    "material": {"young_modulus": 3000, "poisson_ratio": 0.45, "density": 0},
    "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]}})");
  const auto count = [](const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  };
  const Run solve = run_cli("solve '" + scene + "' -o '" + dir.file("solve") + "' -q", dir);
  INFO(solve.err);
  REQUIRE(solve.exit_code == 0);
  CHECK(count(solve.err, "has aspect ratio 41.3") == 1);
  const auto report = nlohmann::json::parse(read_text(dir.file("solve/report.json")));
  std::size_t in_report = 0;
  for (const auto& w : report.at("warnings")) in_report += count(w.get<std::string>(), "has aspect ratio 41.3");
  CHECK(in_report == 1);
  const Run press = run_cli(
      "press '" + scene + "' --tool point --at 0.25,0.25,0.0105 --direction 0,0,-1 --depth 0.0001 -o '" + dir.file("press") + "'", dir);
  INFO(press.err);
  REQUIRE(press.exit_code == 0);
  CHECK(count(press.err, "has aspect ratio 41.3") == 1);
}

TEST_CASE("README's demo runs its command-line part without a warning", "[cli]") {
  // The `"$BEMSURG" ...` commands of scripts/run-demo.sh (continuation lines joined), on the source
  // tree's examples/ with out/demo/ redirected here: a newcomer's first run prints no warning (issue 37).
  TempDir dir;
  const fs::path root = fs::path(__FILE__).parent_path().parent_path();
  std::ifstream script(root / "scripts" / "run-demo.sh");
  REQUIRE(script);
  std::vector<std::string> commands;
  std::string line, command;
  while (std::getline(script, line)) {
    if (command.empty() && line.rfind("\"$BEMSURG\" ", 0) != 0) continue;
    const bool continued = !line.empty() && line.back() == '\\';
    command += continued ? line.substr(0, line.size() - 1) : line;
    if (!continued) commands.push_back(std::exchange(command, std::string()));
  }
  REQUIRE(commands.size() == 2);  // solve, press
  for (std::string c : commands) {
    c = c.substr(std::string("\"$BEMSURG\" ").size());
    const auto replace_all = [&c](const std::string& from, const std::string& to) {
      for (std::size_t at = c.find(from); at != std::string::npos; at = c.find(from, at + to.size())) c.replace(at, from.size(), to);
    };
    replace_all("out/demo", dir.file("demo"));
    replace_all("examples/", (root / "examples").string() + "/");
    const Run r = run_cli(c, dir);
    INFO(c << "\n" << r.err);
    CHECK(r.exit_code == 0);
    CHECK(r.err.find("warning") == std::string::npos);
  }
}

TEST_CASE("solve writes surface.vtk and a complete report.json", "[cli]") {
  TempDir dir;
  const std::string scene = dir.write("s.json", R"({
    "mesh": {"generator": "box", "min": [0, 0, 0], "max": [0.1, 0.1, 0.05], "divisions": [2, 2, 2]},
    "material": {"young_modulus": 3000, "poisson_ratio": 0.45, "density": 1000},
    "gravity": [0, 0, -9.81],
    "boundary_conditions": {"rules": [{"select": {"normal": {"direction": [0, 0, -1]}}, "displacement": [0, 0, 0]},
                                      {"select": {"box": {"min": [-1, -1, 0.0499], "max": [1, 1, 1]}}, "traction": [0, 0, 0]}]},
    "solver": {"method": "gmres", "tolerance": 1e-10, "preconditioner": "block_jacobi"}})");
  const auto started = std::chrono::steady_clock::now();
  const Run r = run_cli("solve '" + scene + "' -o '" + dir.file("out") + "'", dir);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_FALSE(fs::exists(dir.file("out/interior.csv")));  // not asked for
  CHECK_THAT(read_text(dir.file("out/surface.vtk")), Catch::StartsWith("# vtk DataFile Version") && Catch::Contains("traction"));

  const auto report = nlohmann::json::parse(read_text(dir.file("out/report.json")));
  CHECK(report.at("elements") == 48);
  CHECK(report.at("equations") == 144);
  // Timings in seconds: each phase took some time, the phases happen one after another inside the
  // run (so they add up to at most the total), and the total lies inside the wall time of the
  // process as this test measured it (a report in milliseconds, or a phase timed twice, fails).
  const auto& timings = report.at("timings");
  double phases = 0.0;
  for (const char* phase : {"load", "assembly", "system", "solve", "post"}) {
    INFO(phase << ": " << timings.at(phase).get<double>() << " s");
    CHECK(timings.at(phase).get<double>() > 0.0);
    phases += timings.at(phase).get<double>();
  }
  const double total = timings.at("total").get<double>();
  INFO("phases " << phases << " s, total " << total << " s, wall time of the run " << wall << " s");
  CHECK(phases <= total * (1.0 + 4 * kEps));  // a sum of 5 (measured: 2.1 % below the total)
  CHECK(total <= wall);
  CHECK(report.at("peak_memory_mb").get<double>() > 1.0);
  const auto& solver = report.at("solver");
  CHECK(solver.at("method") == "gmres");
  CHECK(solver.at("preconditioner") == "block_jacobi");
  CHECK(solver.at("status") == "converged");
  CHECK(solver.at("iterations").get<int>() >= 1);
  // Converged means a true residual at most the scene's tolerance 1e-10 (measured 6.2e-11).
  CHECK(solver.at("relative_residual").get<double>() <= 1e-10);
  CHECK(report.at("backend") == nlohmann::json({{"name", "dense"}, {"chosen_by", "scene"}}));
  CHECK(report.at("bemsurg_version").is_string());
  // What each rule held (issue 38): the bottom face (a normal selector: no region), the top face
  // (a box region, which also holds 0.1 mm of each side: 0.01 + 4 x 0.1 x 1e-4 m^2 of surface).
  const auto& rules = report.at("boundary_rules");
  REQUIRE(rules.size() == 2);
  CHECK(rules[0].at("rule") == "boundary_conditions.rules[0]");
  CHECK(rules[0].at("area").get<double>() == Approx(0.01).epsilon(1e-12));
  CHECK_FALSE(rules[0].contains("region_area"));
  CHECK(rules[1].at("area").get<double>() == Approx(0.01).epsilon(1e-12));
  CHECK(rules[1].at("region_area").get<double>() == Approx(0.01004).epsilon(1e-9));
  CHECK(rules[1].at("conform") == false);
  CHECK(rules[1].at("refine_rim") == 0);
  CHECK_THAT(r.out, Catch::Contains("boundary_conditions.rules[0] holds 0.01 m^2"));  // a displacement rule's held area is printed

  // Gravity pulls the free top down; the fixed bottom stays put.
  const Table elements = read_table(dir.file("out/elements.csv"));
  REQUIRE(elements.rows.size() == 48);
  for (const auto& row : elements.rows) {
    if (row[6] < -0.999) CHECK(Vec3(row[8], row[9], row[10]).norm() == 0.0);
    if (row[6] > 0.999) CHECK(row[10] < 0.0);
  }
}

TEST_CASE("solve: a bad scene exits with 1 and names the key, line or element", "[cli][errors]") {
  TempDir dir;
  const std::string mesh = R"("mesh": {"generator": "box", "min": [0,0,0], "max": [1,1,1], "divisions": [1,1,1]})";
  const auto solve = [&](const std::string& scene_text) {
    const std::string scene = dir.write("bad.json", scene_text);
    return run_cli("solve '" + scene + "' -o '" + dir.file("out") + "'", dir);
  };

  Run r = solve("{" + mesh + R"(, "material": {"poisson_ratio": 0.3}, "boundary_conditions": {}})");
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Catch::StartsWith("bemsurg: error:") && Catch::Contains("material.young_modulus: missing"));

  r = solve("{" + mesh + R"(, "material": {"young_modulus": 1, "poisson_ratio": 0.7}, "boundary_conditions": {}})");
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Catch::Contains("material.poisson_ratio"));

  dir.write("bc.csv", "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n0,u,u,u,0,0,0\n12,u,u,u,0,0,0\n");
  r = solve("{" + mesh + R"(, "material": {"young_modulus": 1, "poisson_ratio": 0.3}, "boundary_conditions": {"file": "bc.csv"}})");
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Catch::Contains("boundary_conditions.file line 3: element 12 out of range (mesh has 12 elements)"));

  // Loads, but nothing holds the body: the solver refuses instead of returning garbage.
  r = solve("{" + mesh + R"(, "material": {"young_modulus": 1, "poisson_ratio": 0.3}, "boundary_conditions": {}})");
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Catch::Contains("support"));
  CHECK_FALSE(fs::exists(dir.file("out/elements.csv")));

  r = run_cli("solve '" + dir.file("missing.json") + "' -o '" + dir.file("out") + "'", dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Catch::Contains("missing.json"));
}

TEST_CASE("a mesh file too large for the dense solve is refused at load with the estimate and the command that prepares it",
          "[cli][errors]") {
  // A raw 'segmentation' in millimetres: an icosphere of 81,920 triangles (radius 50 mm). Its dense
  // solve (245,760 unknowns) needs about 900 GiB: more than any test machine's 80 %.
  TempDir dir;
  const TriangleMesh organ = icosphere_mesh(Vec3::Zero(), 50.0, 6);
  REQUIRE(organ.num_elements() == 81920);
  const double need = estimate_elastostatic_bytes(organ.num_elements());
  if (need <= default_memory_limit_bytes()) {
    WARN("this machine has more than 1.1 TB of memory; the refusal is not exercised");
    return;
  }
  write_obj(dir.file("organ.obj"), organ);
  const std::string scene = dir.write("organ.json", R"({"mesh": {"file": "organ.obj", "scale": 0.001},
    "material": {"young_modulus": 3000, "poisson_ratio": 0.45},
    "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, -0.04], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]}})");
  const std::string path = fs::path(dir.file("organ.obj")).lexically_normal().string();
  const auto refused = [&](const Run& r) {
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Catch::StartsWith("bemsurg: error: ") && Catch::Contains("mesh.file: the mesh '" + path + "' has 81920 elements") &&
                          Catch::Contains("(245760 unknowns); the dense solve needs about " + format_gib(need)) &&
                          Catch::Contains("to make it solvable, remesh it: bemsurg prepare '" + path +
                                          "' -o prepared.obj --scale 0.001 --target-elements 3000, then set mesh.file to prepared.obj "
                                          "and remove mesh.scale") &&
                          Catch::Contains("docs/organs.md") &&
                          Catch::Contains(R"(or add "prepare": {"scale": 0.001} to the scene's mesh section and remove mesh.scale)"));
  };
  // Refused before any matrix: the message is the pre-solve check's (check_before_solve), which runs
  // on the mesh alone, and no output exists. (No wall-clock bound: CI's machines and the sanitizer
  // trees vary in speed by far more than a bound could allow for.)
  refused(run_cli("solve '" + scene + "' -o '" + dir.file("solve") + "'", dir));
  CHECK_FALSE(fs::exists(dir.file("solve/elements.csv")));
  refused(run_cli("press '" + scene + "' --tool point --at 0,0,0.05 --direction 0,0,-1 --depth 0.001 -o '" + dir.file("press") + "'", dir));
  CHECK_FALSE(fs::exists(dir.file("press/force.json")));
}

TEST_CASE("press: --direction is any finite nonzero vector, however large or small", "[cli]") {
  TempDir dir;
  {
    std::ofstream scene(dir.file("scene.json"));
    scene << R"({"mesh": {"generator": "box", "min": [-0.05, -0.05, 0], "max": [0.05, 0.05, 0.05], "divisions": [2, 2, 1]},
                 "material": {"young_modulus": 3000, "poisson_ratio": 0.45, "density": 0},
                 "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}},
                                                    "displacement": [0, 0, 0]}]}})";
  }
  std::vector<std::string> forces;
  std::vector<Vec3> F;
  int k = 0;
  for (const char* direction : {"0,0,-1", "0,0,-1e200", "0,0,-1e-200", "1e-200,0,-1e-200", "1,0,-1", "-1,0,-1"}) {
    INFO(direction);
    const std::string out = dir.file("out" + std::to_string(k++));
    const Run r = run_cli("press '" + dir.file("scene.json") + "' --tool point --at 0.01,0.01,0.05 --direction " + direction +
                              " --depth 0.001 --quiet -o '" + out + "'",
                          dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    const auto force = nlohmann::json::parse(read_text(out + "/force.json")).at("force");
    forces.push_back(force.dump());
    F.emplace_back(force.at(0).get<double>(), force.at(1).get<double>(), force.at(2).get<double>());
  }
  CHECK(forces[1] == forces[0]);  // the same unit direction
  CHECK(forces[2] == forces[0]);
  // 1e-200,0,-1e-200 is the unit direction (1, 0, -1)/sqrt(2) (its norm() underflows to 0): the
  // force equals that of 1,0,-1 (measured: identical; bound 16 eps, the normalisation's 2 eps per
  // component through a bonded point's 3 rows) and differs from straight down (measured
  // |F3 - F0| = 0.51 |F0|).
  INFO("F(0,0,-1) = " << F[0].transpose() << ", F(1e-200,0,-1e-200) = " << F[3].transpose() << ", F(1,0,-1) = " << F[4].transpose()
                      << ", F(-1,0,-1) = " << F[5].transpose() << "; |F3 - F4|/|F4| = " << (F[3] - F[4]).norm() / F[4].norm()
                      << ", |F3 + F5 - sqrt2 F0|/|F0| = " << (F[3] + F[5] - std::sqrt(2.0) * F[0]).norm() / F[0].norm());
  CHECK((F[3] - F[4]).norm() <= 16 * kEps * F[4].norm());
  CHECK((F[3] - F[0]).norm() > 0.1 * F[0].norm());
  // A bonded point tool is linear in its displacement, depth x unit direction, and the body (no
  // weight) is in its reference state, so the two oblique presses add up to sqrt(2) times the
  // straight one: F(1,0,-1)/sqrt(2) + F(-1,0,-1)/sqrt(2) = 2 F(0,0,-1)/sqrt(2). Measured 2.1e-16
  // relative; bound 16 eps on each of the three forces (a press that ignored the direction's x
  // part, or a wrong sign, is O(1)).
  CHECK((F[3] + F[5] - std::sqrt(2.0) * F[0]).norm() <= 16 * kEps * (F[3].norm() + F[5].norm() + std::sqrt(2.0) * F[0].norm()));
  for (const char* direction : {"0,0,0", "0,0,1e400"}) {
    const Run r = run_cli("press '" + dir.file("scene.json") + "' --tool point --at 0,0,0.05 --direction " + direction +
                              " --depth 0.001 -o '" + dir.file("bad") + "'",
                          dir);
    CHECK(r.exit_code == 2);
  }
}

TEST_CASE("solve with method hmatrix answers as lu does and says what the hierarchical backend did", "[cli][hmatrix]") {
  // docs/solvers.md, "Hierarchical matrices": the same scene by "lu" and by "hmatrix" (320 elements,
  // compressed at 1e-6), elements.csv compared, and report.json's "backend" for each.
  TempDir dir;
  const std::string body = R"({"mesh": {"generator": "brain", "size": [0.16, 0.13, 0.085], "subdivisions": 2},
    "material": {"young_modulus": 3000.0, "poisson_ratio": 0.45, "density": 1040.0}, "gravity": [0, 0, -9.81],
    "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1], "tolerance": 1e-6}},
                                       "displacement": [0, 0, 0]}]}, "solver": )";
  const std::string dense = dir.write("dense.json", body + R"({"method": "lu"}})");
  const std::string hmatrix = dir.write("hmatrix.json", body + R"({"method": "hmatrix", "compression_tolerance": 1e-6}})");
  const Run h = run_cli("solve '" + hmatrix + "' -o '" + dir.file("h") + "'", dir);
  if (!hierarchical_backend_available()) {
    CHECK(h.exit_code != 0);
    CHECK_THAT(h.err, Catch::Contains("without hmat-oss"));
    bemsurg::testing::skip_unless(false, "built without hmat-oss (libhmat-oss-dev): solve refuses the method, as checked");
  }
  INFO(h.err);
  REQUIRE(h.exit_code == 0);
  CHECK_THAT(h.out, Catch::Contains("solver hmatrix (compression tolerance 1e-06)") && Catch::Contains("of dense storage"));
  REQUIRE(run_cli("solve '" + dense + "' -o '" + dir.file("d") + "'", dir).exit_code == 0);
  const Table a = read_table(dir.file("h/elements.csv")), b = read_table(dir.file("d/elements.csv"));
  REQUIRE(a.header == b.header);
  REQUIRE(a.rows.size() == 320);
  REQUIRE(b.rows.size() == 320);
  // Each column (element, centroid, displacement, traction) against its own largest entry: measured
  // at most 2e-6 (tolerance 1e-6; the bound leaves room for ACA+'s sampling).
  const std::vector<double> differences = column_differences(a, b);
  REQUIRE(differences.size() == a.rows.front().size());
  for (std::size_t k = 0; k < differences.size(); ++k) {
    INFO("column " << k);
    CHECK(differences[k] <= 1e-4);
  }
  const auto report = nlohmann::json::parse(read_text(dir.file("h/report.json")));
  const auto& backend = report.at("backend");
  CHECK(backend.at("name") == "hmatrix");
  CHECK(report.at("solver").at("method") == "hmatrix");
  CHECK(backend.at("compression_tolerance").get<double>() == 1e-6);
  CHECK(backend.at("dense_entries").get<double>() == 960.0 * 960.0);
  CHECK(backend.at("stored_entries").get<double>() <= backend.at("dense_entries").get<double>());
  CHECK(backend.at("compression_ratio").get<double>() ==
        Approx(backend.at("stored_entries").get<double>() / backend.at("dense_entries").get<double>()));
  CHECK(backend.at("largest_rank").get<int>() >= 0);
  CHECK(backend.at("factorization_seconds").get<double>() > 0.0);
  CHECK(report.at("solver").at("relative_residual").get<double>() <= 1e-4);
  const auto dense_report = nlohmann::json::parse(read_text(dir.file("d/report.json")));
  CHECK(dense_report.at("backend").at("name") == "dense");
  CHECK(dense_report.at("backend").at("chosen_by") == "scene");
  // "auto" on these 320 elements: dense LU, said on stderr and in the report.
  const std::string automatic = dir.write("auto.json", body + R"({"method": "auto"}})");
  const Run a_run = run_cli("solve '" + automatic + "' -o '" + dir.file("a") + "'", dir);
  REQUIRE(a_run.exit_code == 0);
  CHECK_THAT(a_run.err, Catch::Contains("solver method auto: dense LU"));
  const auto auto_report = nlohmann::json::parse(read_text(dir.file("a/report.json")));
  CHECK(auto_report.at("backend").at("name") == "dense");
  CHECK(auto_report.at("backend").at("chosen_by") == "auto");
  // Linear elements on both backends (80 elements, 720 unknowns at the nodes): nodes.csv compared.
  std::string linear_body = body;
  linear_body.replace(linear_body.find(R"("subdivisions": 2)"), 17, R"("subdivisions": 1)");
  linear_body.insert(linear_body.rfind(R"("solver")"), R"("elements": "linear", )");
  const std::string lh = dir.write("linear_h.json", linear_body + R"({"method": "hmatrix", "compression_tolerance": 1e-6}})");
  const std::string ld = dir.write("linear_d.json", linear_body + R"({"method": "lu"}})");
  const Run lh_run = run_cli("solve '" + lh + "' -o '" + dir.file("lh") + "'", dir);
  INFO(lh_run.err);
  REQUIRE(lh_run.exit_code == 0);
  REQUIRE(run_cli("solve '" + ld + "' -o '" + dir.file("ld") + "'", dir).exit_code == 0);
  const Table ln = read_table(dir.file("lh/nodes.csv")), lnd = read_table(dir.file("ld/nodes.csv"));
  REQUIRE(ln.header == lnd.header);
  REQUIRE(ln.rows.size() == 240);
  const std::vector<double> node_differences = column_differences(ln, lnd);
  for (std::size_t k = 0; k < node_differences.size(); ++k) {
    INFO("nodes.csv column " << k);
    CHECK(node_differences[k] <= 1e-4);
  }
  const auto linear_report = nlohmann::json::parse(read_text(dir.file("lh/report.json")));
  CHECK(linear_report.at("backend").at("name") == "hmatrix");
  CHECK(linear_report.at("element_type") == "linear");
  CHECK(linear_report.at("backend").at("dense_entries").get<double>() == 720.0 * 720.0);
}

TEST_CASE("press on a hierarchical scene computes, keys and reloads its table on that backend", "[cli][hmatrix]") {
  // docs/solvers.md, "Hierarchical matrices": the same press on "lu" and "hmatrix" scenes (320
  // elements, region the top within 4 cm) gives the same force; the hierarchical table's file is
  // read back by its own scene and is stale for the dense one (the key records the backend).
  TempDir dir;
  const std::string body = R"({"mesh": {"generator": "brain", "size": [0.16, 0.13, 0.085], "subdivisions": 2},
    "material": {"young_modulus": 3000.0, "poisson_ratio": 0.45, "density": 1040.0}, "gravity": [0, 0, -9.81],
    "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1], "tolerance": 1e-6}},
                                       "displacement": [0, 0, 0]}]},
    "operating_region": {"sphere": {"center": [0, 0, 0.085], "radius": 0.04}}, "solver": )";
  const std::string dense = dir.write("dense.json", body + R"({"method": "lu"}})");
  const std::string hmatrix = dir.write("hmatrix.json", body + R"({"method": "hmatrix", "compression_tolerance": 1e-6}})");
  const std::string press = " --tool sphere:0.01 --at 0,0,0.09 --direction 0,0,-1 --depth 0.001 --table '" + dir.file("h.tbl") + "' -o '";
  const Run h = run_cli("press '" + hmatrix + "'" + press + dir.file("h") + "'", dir);
  if (!hierarchical_backend_available()) {
    CHECK(h.exit_code != 0);
    CHECK_THAT(h.err, Catch::Contains("without hmat-oss"));
    bemsurg::testing::skip_unless(false, "built without hmat-oss (libhmat-oss-dev): press refuses the method, as checked");
  }
  INFO(h.err);
  REQUIRE(h.exit_code == 0);
  const Run again = run_cli("press '" + hmatrix + "'" + press + dir.file("h2") + "'", dir);
  REQUIRE(again.exit_code == 0);
  const Run d = run_cli("press '" + dense + "'" + press + dir.file("d") + "'", dir);
  REQUIRE(d.exit_code == 0);
  CHECK_THAT(d.err, Catch::Contains("stale") && Catch::Contains("hierarchical backend") && Catch::Contains("recomputing"));
  const auto fh = nlohmann::json::parse(read_text(dir.file("h/force.json")));
  const auto fh2 = nlohmann::json::parse(read_text(dir.file("h2/force.json")));
  const auto fd = nlohmann::json::parse(read_text(dir.file("d/force.json")));
  CHECK(fh.at("table").at("backend") == "hmatrix");
  CHECK(fh.at("table").at("compression_tolerance").get<double>() == 1e-6);
  CHECK_FALSE(fh.at("table").at("loaded_from_file").get<bool>());
  CHECK(fh2.at("table").at("loaded_from_file").get<bool>());
  CHECK(fd.at("table").at("backend") == "dense");
  const auto a = fh.at("force").get<std::vector<double>>(), b = fd.at("force").get<std::vector<double>>();
  const double norm = std::hypot(b[0], b[1], b[2]);
  REQUIRE(norm > 0.0);
  CHECK(std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) <= 1e-5 * norm);
  CHECK(fh2.at("force") == fh.at("force"));
  // A cut updates the kept H-LU as it updates the dense LU (docs/cutting.md, "On either backend"): the
  // same two steps on both scenes leave the same mesh and, to the compression's accuracy, the same
  // fields (each column of elements.csv against its largest entry).
  const std::string cut = " --from -0.02,0,0.09 --direction 1,0,0 --steps 2 -o '";
  const Run ch = run_cli("cut '" + hmatrix + "'" + cut + dir.file("ch") + "'", dir);
  INFO(ch.err);
  REQUIRE(ch.exit_code == 0);
  REQUIRE(run_cli("cut '" + dense + "'" + cut + dir.file("cd") + "'", dir).exit_code == 0);
  const auto rh = nlohmann::json::parse(read_text(dir.file("ch/report.json")));
  const auto rd = nlohmann::json::parse(read_text(dir.file("cd/report.json")));
  CHECK(rh.at("table_backend") == "hmatrix");
  CHECK(rd.at("table_backend") == "dense");
  REQUIRE(rh.at("steps").size() == 2);
  REQUIRE(rh.at("elements") == rd.at("elements"));
  CHECK(rh.at("elements").get<int>() > 320);
  const Table ta = read_table(dir.file("ch/elements.csv")), tc = read_table(dir.file("cd/elements.csv"));
  REQUIRE(ta.rows.size() == tc.rows.size());
  const std::vector<double> cut_differences = column_differences(ta, tc);
  REQUIRE(cut_differences.size() == ta.rows.front().size());
  for (std::size_t k = 0; k < cut_differences.size(); ++k) {
    INFO("column " << k);
    CHECK(cut_differences[k] <= 1e-4);
  }
}
