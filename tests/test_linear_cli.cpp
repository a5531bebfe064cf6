// Linear elements fed as users feed them (issue 37, docs/elements.md): `bemsurg solve` writes
// nodes.csv, the positions where the linear elements collocate; prescribed data sampled there and
// given in the node variant of bc.csv reach at most half the constant elements' error on Lamé's
// hollow sphere (640 elements), errors taken over elements.csv's centroid values of what was solved
// for (the data prescribed are not measured) against the exact field there. Measured: constant
// u 3.5 %, t 5.4 %; linear fed at the nodes u 0.74 %, t 2.3 % (at 160 elements the traction ratio
// is 0.66: the halving needs the geometry resolved as well).
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
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

CentroidErrors centroid_errors(const std::string& elements_csv, const verification::ElasticField& exact) {
  double du = 0.0, u = 0.0, dt = 0.0, t = 0.0;
  for (const auto& r : read_rows(elements_csv, "element,cx,cy,cz,nx,ny,nz,area,ux,uy,uz,tx,ty,tz")) {
    const Vector3d x = at(r, 1), n = at(r, 4);
    if (x.norm() < 1.5) {  // the cavity: displacement given, traction solved
      const Vector3d te = exact.stress(x) * n;
      dt += (at(r, 11) - te).squaredNorm();
      t += te.squaredNorm();
    } else {
      const Vector3d ue = exact.displacement(x);
      du += (at(r, 8) - ue).squaredNorm();
      u += ue.squaredNorm();
    }
  }
  return {std::sqrt(du / u), std::sqrt(dt / t)};
}

}  // namespace

TEST_CASE("linear elements fed at their nodes through nodes.csv and bc.csv's node variant halve the constant elements' error",
          "[cli][linear]") {
  bemsurg_test::TempDir dir("bemsurg_test_linear_cli_");
  const Material m{1.0, 0.3, 0.0};
  const verification::ElasticField exact = verification::lame_field(m, Vector3d::Zero(), 1.0, 2.0, 1.0, 0.0);
  const auto scene = [&](const std::string& name, const std::string& elements, const std::string& conditions) {
    std::ofstream(dir.file(name)) << R"({"mesh": {"generator": "hollow_sphere", "inner_radius": 1, "outer_radius": 2, "subdivisions": 2},
      "material": {"young_modulus": 1, "poisson_ratio": 0.3}, "elements": ")"
                                  << elements << R"(", "boundary_conditions": )" << conditions << "}";
    return dir.file(name);
  };
  const auto solve = [&](const std::string& scene_file, const std::string& out) {
    const bemsurg_test::CliRun r = bemsurg_test::run_cli("solve '" + scene_file + "' -o '" + dir.file(out) + "' -q", dir);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return dir.file(out);
  };
  // First runs, held everywhere, give where the data are needed: centroids and normals, and nodes.
  const std::string held = R"({"rules": [{"select": {"all": true}, "displacement": [0, 0, 0]}]})";
  const auto elements =
      read_rows(solve(scene("c0.json", "constant", held), "c0") + "/elements.csv", "element,cx,cy,cz,nx,ny,nz,area,ux,uy,uz,tx,ty,tz");
  const std::string linear0 = solve(scene("l0.json", "linear", held), "l0");
  const auto nodes = read_rows(linear0 + "/nodes.csv", "element,node,x,y,z,ux,uy,uz,tx,ty,tz");
  const auto corners = read_rows(linear0 + "/corners.csv", "element,corner,x,y,z,ux,uy,uz,tx,ty,tz");
  REQUIRE(elements.size() == 640);
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

  // Lamé's sphere, pressure 1 inside: the cavity's displacement and the outer surface's (zero)
  // traction prescribed, from the exact field at the centroids (constant) or at the nodes (linear).
  const auto line = [&](const std::string& prefix, const Vector3d& x, const Vector3d& n) {
    const bool inner = x.norm() < 1.5;
    const Vector3d v = inner ? exact.displacement(x) : Vector3d(exact.stress(x) * n);
    std::ostringstream s;
    s.precision(17);
    s << prefix << (inner ? "u,u,u," : "t,t,t,") << v(0) << ',' << v(1) << ',' << v(2) << '\n';
    return s.str();
  };
  {
    std::ofstream bc(dir.file("bc_elements.csv"));
    bc << "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n";
    for (std::size_t e = 0; e < elements.size(); ++e) bc << line(std::to_string(e) + ",", at(elements[e], 1), at(elements[e], 4));
    std::ofstream bn(dir.file("bc_nodes.csv"));
    bn << "element,node,kind_x,kind_y,kind_z,value_x,value_y,value_z\n";
    for (const auto& row : nodes) {
      const auto e = static_cast<std::size_t>(row[0]);
      bn << line(std::to_string(e) + "," + std::to_string(int(row[1])) + ",", at(row, 2), at(elements[e], 4));
    }
  }
  const CentroidErrors constant =
      centroid_errors(solve(scene("c.json", "constant", R"({"file": "bc_elements.csv"})"), "c") + "/elements.csv", exact);
  const CentroidErrors linear =
      centroid_errors(solve(scene("l.json", "linear", R"({"file": "bc_nodes.csv"})"), "l") + "/elements.csv", exact);
  INFO("constant: u " << constant.displacement << ", t " << constant.traction << "; linear fed at the nodes: u " << linear.displacement
                      << ", t " << linear.traction);
  CHECK(linear.displacement <= 0.5 * constant.displacement);
  CHECK(linear.traction <= 0.5 * constant.traction);
}
