// Text in a comma-decimal locale (bemsurg/number_text.hpp): an application that embeds bemsurg may
// switch the C and C++ locales at start-up, as every Qt application does with setlocale(LC_ALL,
// ""). In de_DE, strtod and std::stod read "0.45" as 0 and streams write "0,45" and "12.000.000";
// bemsurg's files and messages must not change with it. Each case switches both locales the way
// such an application does, reads and writes through the library, and asserts the exact values
// and the decimal point. Where no comma-decimal locale is installed the case is skipped (exit
// code 77, tests/support/skip.hpp); scripts/setup-deps.sh installs de_DE.UTF-8.
#include <catch2/catch.hpp>

#include <clocale>
#include <cstdlib>
#include <fstream>
#include <locale>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/haptics/recording_device.hpp"
#include "bemsurg/haptics/scripted_device.hpp"
#include "bemsurg/io/action_script.hpp"
#include "bemsurg/io/element_selector.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/meshing/graded_remesher.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/number_text.hpp"
#include "support/skip.hpp"
#include "support/temp_dir.hpp"

using namespace bemsurg;

namespace {

struct LocaleTempDir : bemsurg_test::TempDir {
  LocaleTempDir() : bemsurg_test::TempDir("bemsurg_test_locale_") {}
};

/// Switches the C locale (setlocale) and the C++ global locale to a comma-decimal one for its
/// lifetime and restores both on destruction, also when a check throws. Skips the test case
/// when no such locale is installed.
class CommaDecimalLocale {
 public:
  CommaDecimalLocale() {
    const char* c_name = std::setlocale(LC_ALL, nullptr);
    old_c_ = c_name != nullptr ? c_name : "C";
    for (const char* name : {"de_DE.UTF-8", "de_DE.utf8", "fr_FR.UTF-8"}) {
      try {
        std::locale::global(std::locale(name));  // as an application that uses C++ streams does
      } catch (const std::runtime_error&) { continue; }
      if (std::setlocale(LC_ALL, name) != nullptr) {  // as Qt does with setlocale(LC_ALL, "")
        active_ = name;
        break;
      }
      std::locale::global(old_cpp_);
    }
    if (active_.empty()) restore();
    testing::skip_unless(!active_.empty(), "no comma-decimal locale (de_DE.UTF-8) is installed");
  }
  ~CommaDecimalLocale() { restore(); }
  CommaDecimalLocale(const CommaDecimalLocale&) = delete;
  CommaDecimalLocale& operator=(const CommaDecimalLocale&) = delete;

  const std::string& name() const { return active_; }

 private:
  void restore() {
    std::locale::global(old_cpp_);
    std::setlocale(LC_ALL, old_c_.c_str());
  }
  std::string old_c_;
  std::locale old_cpp_;  // the global locale at construction
  std::string active_;
};

/// The locale really is comma-decimal for both the C library and new streams: otherwise a case
/// would pass without testing anything.
void require_comma_decimal() {
  REQUIRE(std::strtod("0.45", nullptr) == 0.0);  // strtod stops at the '.'
  std::ostringstream s;
  s << 0.45;
  REQUIRE(s.str() == "0,45");
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Every number in `text` written with a point: "0.45" appears, "0,45" does not.
void check_point_decimal(const std::string& text, const std::string& what) {
  INFO(what << ":\n" << text.substr(0, 600));
  CHECK(text.find("0.45") != std::string::npos);
  CHECK(text.find("0,45") == std::string::npos);
}

/// A closed box [0, 0.45] x [0, 1.25] x [0, 0.75]: coordinates with decimals.
TriangleMesh decimal_box() { return box_mesh(Vec3(0.0, 0.0, 0.0), Vec3(0.45, 1.25, 0.75), 2, 2, 2); }

}  // namespace

TEST_CASE("a scene and its CSV files read the same numbers in a comma-decimal locale", "[io][locale]") {
  const LocaleTempDir dir;
  dir.write("conditions.csv",
            "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n"
            "0,t,t,u,0.25,-1.5e-3,0.125\n");
  dir.write("points.csv", "x,y,z\n0.5,0.25,0.75\n");
  const std::string path = dir.write("scene.json", R"({
    "mesh": {"generator": "box", "min": [0, 0, 0], "max": [1, 1, 1], "divisions": [2, 2, 2]},
    "material": {"young_modulus": 4500.5, "poisson_ratio": 0.45, "density": 1040.25},
    "gravity": [0, 0, -9.81],
    "solver": {"method": "gmres", "tolerance": 1.5e-9},
    "boundary_conditions": {
      "rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0.0125]}],
      "file": "conditions.csv"},
    "interior_points": {"file": "points.csv", "points": [[0.75, 0.5, 0.375]]}
  })");
  const CommaDecimalLocale locale;
  require_comma_decimal();
  INFO("locale " << locale.name());

  const Scene s = load_scene(path);
  const ElastostaticProblem& p = s.problem;
  CHECK(p.material.young_modulus == 4500.5);
  CHECK(p.material.poisson_ratio == 0.45);
  CHECK(p.material.density == 1040.25);
  CHECK(p.gravity.z() == -9.81);
  CHECK(s.solver.tolerance == 1.5e-9);
  const BoundaryConditions& bc = p.boundary_conditions;
  CHECK(bc.kind(0) == BcKind::Traction);
  CHECK(bc.kind(1) == BcKind::Traction);
  CHECK(bc.kind(2) == BcKind::Displacement);
  CHECK(bc.value(0) == 0.25);
  CHECK(bc.value(1) == -1.5e-3);
  CHECK(bc.value(2) == 0.125);
  bool rule_value_seen = false;  // the bottom face's rule: u_z = 0.0125
  for (Index k = 5; k < bc.num_dofs(); k += 3) rule_value_seen = rule_value_seen || bc.value(k) == 0.0125;
  CHECK(rule_value_seen);
  REQUIRE(s.interior_points.rows() == 2);
  CHECK(s.interior_points(0, 0) == 0.75);  // inline points come before the file's
  CHECK(s.interior_points(0, 2) == 0.375);
  CHECK(s.interior_points(1, 0) == 0.5);
  CHECK(s.interior_points(1, 1) == 0.25);
  CHECK(s.interior_points(1, 2) == 0.75);
}

TEST_CASE("a scene reads a mesh file written in a comma-decimal locale", "[io][locale]") {
  const LocaleTempDir dir;
  const CommaDecimalLocale locale;
  require_comma_decimal();
  const TriangleMesh box = decimal_box();
  write_obj(dir.file("box.obj"), box);
  check_point_decimal(read_text(dir.file("box.obj")), "box.obj");
  const std::string path = dir.write("scene.json", R"({
    "mesh": {"file": "box.obj", "scale": 2.5, "translate": [0.5, 0, 0]},
    "material": {"young_modulus": 3000, "poisson_ratio": 0.45},
    "boundary_conditions": {}
  })");
  const Scene s = load_scene(path);
  REQUIRE(s.problem.mesh.num_elements() == box.num_elements());
  const auto bounds = s.problem.mesh.bounding_box();
  CHECK(bounds(0, 1) == 0.45 * 2.5 + 0.5);
  CHECK(bounds(1, 1) == 1.25 * 2.5);
  CHECK(s.problem.material.poisson_ratio == 0.45);
}

TEST_CASE("an action script reads the same numbers in a comma-decimal locale", "[io][locale]") {
  const CommaDecimalLocale locale;
  require_comma_decimal();
  const ActionScript a = load_action_script_from_string(R"({
    "format": "bemsurg-actions", "version": 1, "rate_hz": 1250.5,
    "tools": [{"name": "probe", "shape": "sphere", "radius": 0.0045}],
    "actions": [{"time": 0.25, "tool": "probe", "type": "press", "at": [0.45, 0.5, 1.125], "depth": 0.0035, "duration": 0.75}]
  })");
  CHECK(a.rate_hz == 1250.5);
  CHECK(a.tools.at(0).radius == 0.0045);
  REQUIRE(a.actions.size() == 1);
  CHECK(a.actions[0].time == 0.25);
  CHECK(a.actions[0].at.x() == 0.45);
  CHECK(a.actions[0].at.z() == 1.125);
  CHECK(a.actions[0].depth == 0.0035);
  CHECK(a.actions[0].duration == 0.75);
  CHECK(a.duration == 0.25 + 0.75 + 0.1);
}

TEST_CASE("results and meshes written in a comma-decimal locale read back exactly, with a decimal point", "[io][locale]") {
  const LocaleTempDir dir;
  const CommaDecimalLocale locale;
  require_comma_decimal();
  const TriangleMesh mesh = decimal_box();
  BoundarySolution solution;
  solution.displacement = RowMatrixX3d::Constant(mesh.num_elements(), 3, 0.45);
  solution.traction = RowMatrixX3d::Constant(mesh.num_elements(), 3, -1.0 / 3.0);

  write_elements_csv(dir.file("elements.csv"), mesh, solution);
  const std::string elements = read_text(dir.file("elements.csv"));
  check_point_decimal(elements, "elements.csv");
  {
    std::istringstream lines(elements);
    std::string line;
    std::getline(lines, line);
    CHECK(line == kElementsCsvHeader);
    std::getline(lines, line);
    std::vector<std::string> fields;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) fields.push_back(cell);
    REQUIRE(fields.size() == 14);
    CHECK(parse_number<double>(fields[8]) == 0.45);
    CHECK(parse_number<double>(fields[11]) == -1.0 / 3.0);  // the shortest text reads back exactly
    CHECK(parse_number<double>(fields[1]) == mesh.centroids()(0, 0));
  }

  RowMatrixX3d points(1, 3);
  points << 0.45, 0.5, 0.25;
  StressRows stress = StressRows::Constant(1, 6, 1234567.5);
  write_interior_csv(dir.file("interior.csv"), points, solution.displacement.topRows(1), stress);
  const std::string interior = read_text(dir.file("interior.csv"));
  check_point_decimal(interior, "interior.csv");
  CHECK(interior.find("1234567.5") != std::string::npos);  // no digit grouping either

  RunResult report;
  report.elements = mesh.num_elements();
  report.timings.load = 0.45;
  report.peak_memory_mb = 1234.5;
  write_report_json(dir.file("report.json"), report);
  const std::string json = read_text(dir.file("report.json"));
  check_point_decimal(json, "report.json");
  CHECK(json.find("1234.5") != std::string::npos);

  write_solution_vtk(dir.file("surface.vtk"), mesh, solution);
  check_point_decimal(read_text(dir.file("surface.vtk")), "surface.vtk");
  const TriangleMesh back = read_vtk(dir.file("surface.vtk"));
  CHECK(back.vertices() == mesh.vertices());

  write_obj(dir.file("box.obj"), mesh);
  check_point_decimal(read_text(dir.file("box.obj")), "box.obj");
  CHECK(read_obj(dir.file("box.obj")).vertices() == mesh.vertices());
}

TEST_CASE("a device trajectory CSV and its recording keep the decimal point in a comma-decimal locale", "[io][locale]") {
  const LocaleTempDir dir;
  const std::string path = dir.write("trajectory.csv",
                                     "time,x,y,z,dx,dy,dz,buttons\n"
                                     "0,0.45,0.5,0.125,0,0,-1,0\n"
                                     "0.25,0.5,0.45,1.5e-3,0,0.6,-0.8,1\n");
  const CommaDecimalLocale locale;
  require_comma_decimal();
  const std::vector<haptics::Keyframe> k = haptics::ScriptedDevice::read_csv(path);
  REQUIRE(k.size() == 2);
  CHECK(k[0].position.x() == 0.45);
  CHECK(k[0].position.z() == 0.125);
  CHECK(k[1].time == 0.25);
  CHECK(k[1].position.z() == 1.5e-3);
  CHECK(k[1].buttons == 1U);

  haptics::RecordingDevice recorder(std::make_unique<haptics::ScriptedDevice>(k), 16);
  recorder.read(0.0);
  recorder.write_force(Eigen::Vector3d(0.45, 0.0, -1.25));
  recorder.read(0.25);
  recorder.write_csv(dir.file("recording.csv"));
  const std::string text = read_text(dir.file("recording.csv"));
  check_point_decimal(text, "recording.csv");
  const std::vector<haptics::Keyframe> again = haptics::ScriptedDevice::read_csv(dir.file("recording.csv"));
  REQUIRE(again.size() == 2);
  CHECK(again[0].position.x() == 0.45);
  CHECK(again[1].position.z() == 1.5e-3);
}

TEST_CASE("messages quote numbers with a decimal point and no digit grouping in a comma-decimal locale", "[io][locale]") {
  const CommaDecimalLocale locale;
  require_comma_decimal();
  const TriangleMesh mesh = decimal_box();
  const auto message = [](const auto& action) -> std::string {
    try {
      action();
    } catch (const std::exception& e) { return e.what(); }
    return "NO EXCEPTION";
  };
  CHECK_THAT(message([&] { select_elements(mesh, ElementSelector::plane(Vec3::Zero(), Vec3::UnitZ(), -0.45)); }),
             Catch::Contains("got -0.45") && !Catch::Contains("0,45"));
  GradedRemeshOptions options;
  options.inside_edge_length = 0.45;
  options.outside_edge_length = 0.125;
  CHECK_THAT(message([&] { graded_remesh(mesh, OperatingRegion::sphere(Vec3::Zero(), 0.25), options); }),
             Catch::Contains("inside_edge_length (0.45) is larger than outside_edge_length (0.125)"));
  const std::string refused = message([] {
    load_scene_from_string(R"({"mesh": {"generator": "box", "min": [0,0,0], "max": [1,1,1], "divisions": [1000,1000,1000]},
                               "material": {"young_modulus": 1000, "poisson_ratio": 0.45}, "boundary_conditions": {}})",
                           ".");
  });
  CHECK_THAT(refused, Catch::Contains("has 12000000 elements"));
}

// number_text.hpp itself, in whatever locale the process has: what every text input and output
// of bemsurg goes through. Written out against the C library's "C"-locale behaviour it replaces.
TEST_CASE("parse_number reads exactly one number and the writers print it as the C locale would", "[locale]") {
  using bemsurg::parse_number;
  CHECK(parse_number<double>("0.45") == 0.45);
  CHECK(parse_number<double>("+1e-3") == 1e-3);
  CHECK(parse_number<double>("-2.5E2") == -250.0);
  CHECK(parse_number<int>("+12") == 12);
  CHECK(parse_number<long long>("-9000000000") == -9000000000LL);
  for (const char* bad : {"", "+", "++1", "+-1", "0,45", " 1", "1 ", "1.5x", "0x10", "--1"}) {
    INFO("text '" << bad << "'");
    CHECK_FALSE(parse_number<double>(bad).has_value());
  }
  CHECK_FALSE(parse_number<int>("1.5").has_value());
  CHECK_FALSE(parse_number<int>("99999999999").has_value());  // out of int's range
  CHECK_FALSE(parse_number<unsigned>("-1").has_value());
  // Writers: shortest round trip, and the printf forms "%.*f", "%.*g", "%.*e" without a locale.
  CHECK(bemsurg::number_text(0.1) == "0.1");
  CHECK(parse_number<double>(bemsurg::number_text(1.0 / 3.0)) == 1.0 / 3.0);
  CHECK(bemsurg::fixed_text(1234.5, 3) == "1234.500");
  CHECK(bemsurg::general_text(1e-9, 3) == "1e-09");
  CHECK(bemsurg::scientific_text(12345.678, 2) == "1.23e+04");
}
