// Linear elements fed as users feed them (issue 37, docs/elements.md): `bemsurg solve` writes
// nodes.csv, the positions where the linear elements collocate; prescribed data sampled there and
// given in the node variant of bc.csv reach at most half the constant elements' error on the same
// mesh, errors taken over elements.csv's centroid values of what was solved for (the data
// prescribed are not measured) against the exact field there. Measured (constant -> linear, u / t):
// Lamé's hollow sphere at 640 elements 3.5 % / 5.4 % -> 0.74 % / 2.3 % (at 160 elements the
// traction ratio is 0.66: the halving needs the geometry resolved as well); the hanging bar at 112
// elements 1.6 % / 4.8 % -> 0.24 % / 0.10 %; the Kelvin box at 256 elements, mixed 2.9 % / 9.3 % ->
// 0.64 % / 1.1 %, displacement given everywhere t 8.5 % -> 2.4 %.
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bemsurg/verification/reference_solutions.hpp"
#include "support/cli_run.hpp"
#include "support/temp_dir.hpp"

using namespace bemsurg;
using Eigen::Vector3d;

namespace {

/// A CSV's rows of numbers, its header checked.
std::vector<std::vector<double>> read_rows(const std::string& path, const std::string& header) {
  bemsurg_test::CsvTable t = bemsurg_test::read_table(path);
  REQUIRE(t.header == header);
  return std::move(t.rows);
}

Vector3d at(const std::vector<double>& row, std::size_t first) { return {row[first], row[first + 1], row[first + 2]}; }

/// Relative L2 errors over elements.csv's centroid values of what was solved for: the displacement
/// of the elements held by traction (`inner` false), the traction of those held by displacement.
struct CentroidErrors {
  double displacement = 0.0, traction = 0.0;
};

/// A closed-form problem posed through a scene: its mesh section, gravity, exact field, and which
/// elements (by centroid) have their displacement given; the others have their traction given.
struct FedProblem {
  std::string mesh_json;
  std::string gravity_json;
  verification::ElasticField exact;
  std::function<bool(const Vector3d&)> displacement_given;
};

CentroidErrors centroid_errors(const std::string& elements_csv, const FedProblem& p) {
  const verification::ElasticField& exact = p.exact;
  double du = 0.0, u = 0.0, dt = 0.0, t = 0.0;
  for (const auto& r : read_rows(elements_csv, "element,cx,cy,cz,nx,ny,nz,area,ux,uy,uz,tx,ty,tz")) {
    const Vector3d x = at(r, 1), n = at(r, 4);
    if (p.displacement_given(x)) {  // traction solved
      const Vector3d te = exact.stress(x) * n;
      dt += (at(r, 11) - te).squaredNorm();
      t += te.squaredNorm();
    } else {
      const Vector3d ue = exact.displacement(x);
      du += (at(r, 8) - ue).squaredNorm();
      u += ue.squaredNorm();
    }
  }
  return {u > 0.0 ? std::sqrt(du / u) : 0.0, t > 0.0 ? std::sqrt(dt / t) : 0.0};
}

/// Solves `p` four times through `bemsurg solve` in `dir`: held everywhere, constant and linear, to
/// learn the centroids and nodes; then constant elements fed at their centroids (the element form of
/// bc.csv) and linear elements fed at their nodes (the node form). Returns {constant, linear}.
std::pair<CentroidErrors, CentroidErrors> fed_errors(const FedProblem& p, const bemsurg_test::TempDir& dir, std::size_t expected_elements) {
  const auto scene = [&](const std::string& name, const std::string& elements, const std::string& conditions, bool loaded) {
    std::ofstream(dir.file(name)) << R"({"mesh": )" << p.mesh_json
                                  << R"(, "material": {"young_modulus": 1, "poisson_ratio": 0.3, "density": 1}, "gravity": )"
                                  << (loaded ? p.gravity_json : "[0, 0, 0]") << R"(, "elements": ")" << elements
                                  << R"(", "boundary_conditions": )" << conditions << "}";
    return dir.file(name);
  };
  const auto solve = [&](const std::string& scene_file, const std::string& out) {
    const bemsurg_test::CliRun r = bemsurg_test::run_cli("solve '" + scene_file + "' -o '" + dir.file(out) + "' -q", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return dir.file(out);
  };
  const std::string held = R"({"rules": [{"select": {"all": true}, "displacement": [0, 0, 0]}]})";
  const auto elements = read_rows(solve(scene("c0.json", "constant", held, false), "c0") + "/elements.csv",
                                  "element,cx,cy,cz,nx,ny,nz,area,ux,uy,uz,tx,ty,tz");
  const std::string linear0 = solve(scene("l0.json", "linear", held, false), "l0");
  const auto nodes = read_rows(linear0 + "/nodes.csv", "element,node,x,y,z,ux,uy,uz,tx,ty,tz");
  const auto corners = read_rows(linear0 + "/corners.csv", "element,corner,x,y,z,ux,uy,uz,tx,ty,tz");
  REQUIRE(elements.size() == expected_elements);
  REQUIRE(nodes.size() == 3 * elements.size());
  REQUIRE(corners.size() == nodes.size());
  // nodes.csv against corners.csv: node k = 2/3 corner k + 1/6 the other two (docs/elements.md).
  for (std::size_t e = 0; e < elements.size(); ++e)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto& row = nodes[3 * e + k];
      CHECK((row[0] == double(e) && row[1] == double(k)));
      const Vector3d expected = (2.0 / 3.0) * at(corners[3 * e + k], 2) + (1.0 / 6.0) * at(corners[3 * e + (k + 1) % 3], 2) +
                                (1.0 / 6.0) * at(corners[3 * e + (k + 2) % 3], 2);
      CHECK((at(row, 2) - expected).norm() < 1e-12);
    }
  // The exact field at the centroids (constant) or at the nodes (linear); an element's kind follows
  // its centroid, so that both element types solve the same problem.
  const auto line = [&](const std::string& prefix, const Vector3d& centroid, const Vector3d& x, const Vector3d& n) {
    const bool u_given = p.displacement_given(centroid);
    const Vector3d v = u_given ? p.exact.displacement(x) : Vector3d(p.exact.stress(x) * n);
    std::ostringstream s;
    s.precision(17);
    s << prefix << (u_given ? "u,u,u," : "t,t,t,") << v(0) << ',' << v(1) << ',' << v(2) << '\n';
    return s.str();
  };
  {
    std::ofstream bc(dir.file("bc_elements.csv"));
    bc << "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n";
    for (std::size_t e = 0; e < elements.size(); ++e)
      bc << line(std::to_string(e) + ",", at(elements[e], 1), at(elements[e], 1), at(elements[e], 4));
    std::ofstream bn(dir.file("bc_nodes.csv"));
    bn << "element,node,kind_x,kind_y,kind_z,value_x,value_y,value_z\n";
    for (const auto& row : nodes) {
      const auto e = static_cast<std::size_t>(row[0]);
      bn << line(std::to_string(e) + "," + std::to_string(int(row[1])) + ",", at(elements[e], 1), at(row, 2), at(elements[e], 4));
    }
  }
  const CentroidErrors constant =
      centroid_errors(solve(scene("c.json", "constant", R"({"file": "bc_elements.csv"})", true), "c") + "/elements.csv", p);
  const CentroidErrors linear =
      centroid_errors(solve(scene("l.json", "linear", R"({"file": "bc_nodes.csv"})", true), "l") + "/elements.csv", p);
  return {constant, linear};
}

/// The check of the issue's done line: each solved quantity at most half the constant elements' error.
void check_halved(const CentroidErrors& constant, const CentroidErrors& linear) {
  INFO("constant: u " << constant.displacement << ", t " << constant.traction << "; linear fed at the nodes: u " << linear.displacement
                      << ", t " << linear.traction);
  CHECK(linear.displacement <= 0.5 * constant.displacement);
  CHECK(linear.traction <= 0.5 * constant.traction);
}

const Material kFedMaterial{1.0, 0.3, 1.0};

}  // namespace

TEST_CASE("linear elements fed at their nodes through nodes.csv and bc.csv's node variant halve the constant elements' error",
          "[cli][linear]") {
  bemsurg_test::TempDir dir("bemsurg_test_linear_cli_");
  // Lamé's sphere, pressure 1 inside: the cavity's displacement and the outer surface's (zero)
  // traction prescribed.
  const FedProblem lame{R"({"generator": "hollow_sphere", "inner_radius": 1, "outer_radius": 2, "subdivisions": 2})", "[0, 0, 0]",
                        verification::lame_field(kFedMaterial, Vector3d::Zero(), 1.0, 2.0, 1.0, 0.0),
                        [](const Vector3d& x) { return x.norm() < 1.5; }};
  const auto [constant, linear] = fed_errors(lame, dir, 640);
  check_halved(constant, linear);
}

TEST_CASE("linear elements fed at their nodes halve the constant elements' error on the hanging bar", "[cli][linear]") {
  bemsurg_test::TempDir dir("bemsurg_test_linear_bar_");
  // A bar hanging under its own weight, its top face's displacement given, the rest traction-free.
  const FedProblem bar{R"({"generator": "box", "min": [-0.5, -0.5, 0], "max": [0.5, 0.5, 3], "divisions": [2, 2, 6]})", "[0, 0, -1]",
                       verification::hanging_bar_field(kFedMaterial, 1.0, 3.0), [](const Vector3d& x) { return x.z() > 3.0 - 1e-9; }};
  const auto [constant, linear] = fed_errors(bar, dir, 112);
  check_halved(constant, linear);
}

TEST_CASE("linear elements fed at their nodes halve the constant elements' error on the Kelvin box, mixed and displacement-only",
          "[cli][linear]") {
  // Kelvin's point force outside a 2 x 1.2 x 1.2 box (the accuracy benchmark's problem).
  const std::string box = R"({"generator": "box", "min": [-1, -0.6, -0.6], "max": [1, 0.6, 0.6], "divisions": [6, 4, 4]})";
  const verification::ElasticField kelvin = verification::kelvin_field(kFedMaterial, Vector3d(0.3, 0.2, 1.4), Vector3d(0.4, -0.3, 1.0));
  {
    bemsurg_test::TempDir dir("bemsurg_test_linear_kelvin_");
    const auto [constant, linear] = fed_errors({box, "[0, 0, 0]", kelvin, [](const Vector3d& x) { return x.z() < 0.0; }}, dir, 256);
    check_halved(constant, linear);
  }
  {
    bemsurg_test::TempDir dir("bemsurg_test_linear_kelvin_u_");
    const auto [constant, linear] = fed_errors({box, "[0, 0, 0]", kelvin, [](const Vector3d&) { return true; }}, dir, 256);
    CHECK(constant.displacement == 0.0);  // nothing solved for: every element's displacement is given
    check_halved(constant, linear);
  }
}
