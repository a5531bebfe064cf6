// Scene loading (bemsurg/io/scene.hpp, docs/scene-format.md): every class of malformed scene is a
// SceneError that names the key, the file line or the element; selectors pick exactly the
// elements their geometry says; rules apply in order with the CSV file last; generators load.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>

#include "bemsurg/io/element_selector.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/meshing/mesh_preparation.hpp"
#include "support/skip.hpp"
#include "support/temp_dir.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;
namespace fs = std::filesystem;

namespace {

/// A fresh directory per test case, removed at the end (tests/support/temp_dir.hpp).
struct TempDir : bemsurg_test::TempDir {
  TempDir() : bemsurg_test::TempDir("bemsurg_test_scene_") {}
};

/// The SceneError message of loading `json`, or a marker saying what happened instead.
std::string scene_error(const std::string& json, const std::string& dir = ".") {
  try {
    load_scene_from_string(json, dir, "test.json");
  } catch (const SceneError& e) { return e.what(); } catch (const std::exception& e) {
    return std::string("WRONG EXCEPTION TYPE: ") + e.what();
  }
  return "NO EXCEPTION";
}

// A 2x2x2-divided unit cube [0,1]^3: 4 (4 + 4 + 4) = 48 elements, 8 per face.
const std::string kCube = R"("mesh": {"generator": "box", "min": [0,0,0], "max": [1,1,1], "divisions": [2,2,2]})";
const std::string kMaterial = R"("material": {"young_modulus": 1000.0, "poisson_ratio": 0.3, "density": 1000.0})";
const std::string kFixBottom =
    R"("boundary_conditions": {"rules": [{"select": {"plane": {"point": [0,0,0], "normal": [0,0,1]}}, "displacement": [0,0,0]}]})";

std::string scene(const std::string& mesh, const std::string& material, const std::string& bc, const std::string& extra = "") {
  std::string s = "{" + mesh + ", " + material + ", " + bc;
  if (!extra.empty()) s += ", " + extra;
  return s + "}";
}

std::set<Index> as_set(const std::vector<Index>& v) { return {v.begin(), v.end()}; }

using bemsurg_test::kEps;

/// Elements whose normal is +-axis `c` with the given sign (the faces of an axis-aligned box).
std::set<Index> face_elements(const TriangleMesh& mesh, int c, double sign) {
  std::set<Index> out;
  for (Index e = 0; e < mesh.num_elements(); ++e)
    if (mesh.normal(e)(c) * sign > 0.999) out.insert(e);
  return out;
}

}  // namespace

TEST_CASE("a well-formed scene loads with the values it states", "[scene]") {
  const Scene s =
      load_scene_from_string(scene(kCube, kMaterial, kFixBottom,
                                   R"("gravity": [0, 0, -9.81], "solver": {"method": "gmres", "tolerance": 1e-8, "max_iterations": 77,
                "restart": 30, "preconditioner": "block_jacobi"},
                "interior_points": {"points": [[0.5, 0.5, 0.5], [0.25, 0.5, 0.75]]})"),
                             ".");
  CHECK(s.problem.mesh.num_elements() == 48);
  CHECK(s.problem.material.young_modulus == 1000.0);
  CHECK(s.problem.material.poisson_ratio == 0.3);
  CHECK(s.problem.material.density == 1000.0);
  // The parser and the compiler both round the decimal text to the nearest double (measured 0).
  CHECK(s.problem.gravity == Eigen::Vector3d(0, 0, -9.81));
  CHECK(s.solver.method == SolverMethod::Gmres);
  CHECK(s.solver.tolerance == 1e-8);
  CHECK(s.solver.max_iterations == 77);
  CHECK(s.solver.restart == 30);
  CHECK(s.solver.preconditioner == PreconditionerKind::BlockJacobi);
  REQUIRE(s.has_interior_points);
  REQUIRE(s.interior_points.rows() == 2);
  CHECK(s.interior_points(1, 2) == 0.75);
  CHECK(s.warnings.empty());

  // The bottom (8 elements, normal -z) is fixed; every other element is traction-free.
  const auto bottom = face_elements(s.problem.mesh, 2, -1.0);
  REQUIRE(bottom.size() == 8);
  const BoundaryConditions& bc = s.problem.boundary_conditions;
  for (Index e = 0; e < 48; ++e)
    for (int c = 0; c < 3; ++c) {
      CHECK(bc.kind(3 * e + c) == (bottom.count(e) ? BcKind::Displacement : BcKind::Traction));
      CHECK(bc.value(3 * e + c) == 0.0);
    }
}

TEST_CASE("defaults: traction-free elements, LU solver, no gravity, no interior points", "[scene]") {
  const Scene s = load_scene_from_string(scene(kCube, kMaterial, kFixBottom), ".");
  CHECK(s.solver.method == SolverMethod::Lu);
  CHECK(s.solver.preconditioner == PreconditionerKind::BlockJacobi);
  CHECK(s.problem.gravity.isZero(0.0));
  CHECK_FALSE(s.has_interior_points);
  CHECK(s.interior_points.rows() == 0);
  CHECK(s.problem.boundary_conditions.num_displacement_dofs() == 24);
}

TEST_CASE("missing keys are named with their path", "[scene][errors]") {
  CHECK_THAT(scene_error("{" + kMaterial + ", " + kFixBottom + "}"), Catch::Contains("mesh: missing"));
  CHECK_THAT(scene_error("{" + kCube + ", " + kFixBottom + "}"), Catch::Contains("material: missing"));
  CHECK_THAT(scene_error("{" + kCube + ", " + kMaterial + "}"), Catch::Contains("boundary_conditions: missing"));
  CHECK_THAT(scene_error(scene(kCube, R"("material": {"poisson_ratio": 0.3})", kFixBottom)),
             Catch::Contains("material.young_modulus: missing"));
  CHECK_THAT(scene_error(scene(R"("mesh": {"generator": "box", "max": [1,1,1], "divisions": [2,2,2]})", kMaterial, kFixBottom)),
             Catch::Contains("mesh.min: missing"));
  CHECK_THAT(
      scene_error(scene(kCube, R"("material": {"young_modulus": 1, "poisson_ratio": 0.3})", kFixBottom, R"("gravity": [0, 0, -9.81])")),
      Catch::Contains("material.density: missing"));
  CHECK_THAT(scene_error(scene(R"("mesh": {})", kMaterial, kFixBottom)), Catch::Contains("mesh: expected a \"file\" or a \"generator\""));
  CHECK_THAT(scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"rules": [{"displacement": [0,0,0]}]})")),
             Catch::Contains("boundary_conditions.rules[0].select: missing"));
}

TEST_CASE("values of the wrong type are named with their path", "[scene][errors]") {
  CHECK_THAT(scene_error(scene(kCube, R"("material": {"young_modulus": 1, "poisson_ratio": "0.3", "density": 0})", kFixBottom)),
             Catch::Contains("material.poisson_ratio: expected a number, got a string"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, R"("gravity": [0, -9.81])")),
             Catch::Contains("gravity: expected an array of 3 numbers"));
  CHECK_THAT(scene_error(
                 scene(R"("mesh": {"generator": "box", "min": [0,0,0], "max": [1,1,1], "divisions": [2, 2.5, 2]})", kMaterial, kFixBottom)),
             Catch::Contains("mesh.divisions[1]: expected an integer"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"rules": {"select": {}}})")),
             Catch::Contains("boundary_conditions.rules: expected an array"));
  CHECK_THAT(
      scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"rules": [{"select": {"all": true}, "displacement": [0, "x", 0]}]})")),
      Catch::Contains("boundary_conditions.rules[0].displacement[1]: expected a number"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, R"("solver": {"max_iterations": "many"})")),
             Catch::Contains("solver.max_iterations: expected an integer"));
  CHECK_THAT(scene_error("[1, 2]"), Catch::Contains("expected a JSON object"));
  CHECK_THAT(scene_error("{\"mesh\": "), Catch::Contains("test.json: not valid JSON"));
}

TEST_CASE("solver limits: near_field_radius above 0 and at most 100, max_iterations at most a million", "[scene][errors]") {
  for (const char* bad : {"0", "-1", "100.5", "1e300"})
    CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, std::string(R"("solver": {"near_field_radius": )") + bad + "}")),
               Catch::Contains("solver.near_field_radius: must lie in (0, 100]"));
  for (const char* good : {"1e-3", "2", "100"}) {
    const Scene s = load_scene_from_string(
        scene(kCube, kMaterial, kFixBottom, std::string(R"("solver": {"near_field_radius": )") + good + "}"), ".", "test.json");
    CHECK(s.solver.near_field_radius == std::stod(good));  // the same text, the same double (measured 0)
  }
  CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, R"("solver": {"max_iterations": 100000000})")),
             Catch::Contains("solver.max_iterations: must lie in [1, 1000000]"));
  CHECK(load_scene_from_string(scene(kCube, kMaterial, kFixBottom, R"("solver": {"max_iterations": 1000000})"), ".", "test.json")
            .solver.max_iterations == 1000000);
}

TEST_CASE("unknown kinds, methods and generators are named", "[scene][errors]") {
  TempDir dir;
  dir.write("bc.csv", "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n0,u,u,u,0,0,0\n1,u,q,t,0,0,0\n");
  CHECK_THAT(scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"file": "bc.csv"})"), dir.path.string()),
             Catch::Contains("boundary_conditions.file line 3: kind_y: unknown kind 'q'"));
  CHECK_THAT(
      scene_error(scene(kCube, kMaterial,
                        R"("boundary_conditions": {"rules": [{"select": {"all": true}, "kind": ["u", "x", "t"], "value": [0,0,0]}]})")),
      Catch::Contains("boundary_conditions.rules[0].kind[1]: unknown kind 'x'"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, R"("solver": {"method": "cg"})")),
             Catch::Contains("solver.method: unknown method 'cg'"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, R"("solver": {"preconditioner": "ilu"})")),
             Catch::Contains("solver.preconditioner: unknown preconditioner 'ilu'"));
  CHECK_THAT(scene_error(scene(R"("mesh": {"generator": "torus"})", kMaterial, kFixBottom)),
             Catch::Contains("mesh.generator: unknown generator 'torus'"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial,
                               R"("boundary_conditions": {"rules": [{"select": {"all": true}, "displacement": [0,0,0], "pressure": 1}]})")),
             Catch::Contains("boundary_conditions.rules[0]: give only one of"));
}

TEST_CASE("element indices out of range are named with the element and the line", "[scene][errors]") {
  TempDir dir;
  std::string csv = "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n";
  for (int e = 0; e < 15; ++e) csv += std::to_string(e) + ",u,u,u,0,0,0\n";
  csv += "999,u,u,u,0,0,0\n";  // line 17
  dir.write("bc.csv", csv);
  CHECK_THAT(scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"file": "bc.csv"})"), dir.path.string()),
             Catch::Contains("boundary_conditions.file line 17: element 999 out of range (mesh has 48 elements)"));
  dir.write("neg.csv", "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n-1,u,u,u,0,0,0\n");
  CHECK_THAT(scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"file": "neg.csv"})"), dir.path.string()),
             Catch::Contains("line 2: element -1 out of range"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial,
                               R"("boundary_conditions": {"rules": [{"select": {"elements": [0, 48]}, "displacement": [0,0,0]}]})")),
             Catch::Contains("boundary_conditions.rules[0].select.elements[1]: element 48 out of range (mesh has 48 elements)"));
  CHECK_THAT(
      scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"rules": [{"select": {"shell": 1}, "displacement": [0,0,0]}]})")),
      Catch::Contains("boundary_conditions.rules[0].select: shell: index 1 out of range (mesh has 1 shells)"));
}

TEST_CASE("malformed CSV rows are named by line and column", "[scene][errors]") {
  TempDir dir;
  dir.write("short.csv", "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n0,u,u,u,0,0,0\n\n1,u,u,u,0,0\n");
  CHECK_THAT(scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"file": "short.csv"})"), dir.path.string()),
             Catch::Contains("boundary_conditions.file line 4: expected 7 fields, got 6"));
  dir.write("value.csv", "element,kind_x,kind_y,kind_z,value_x,value_y,value_z\n0,u,u,u,0,abc,0\n");
  CHECK_THAT(scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"file": "value.csv"})"), dir.path.string()),
             Catch::Contains("boundary_conditions.file line 2: value_y: expected a finite number, got 'abc'"));
  dir.write("header.csv", "element,kx,ky,kz,vx,vy,vz\n0,u,u,u,0,0,0\n");
  CHECK_THAT(scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"file": "header.csv"})"), dir.path.string()),
             Catch::Contains("boundary_conditions.file line 1: expected the header"));
  dir.write("points.csv", "x,y,z\n0.5,0.5,0.5\n0.5,0.5\n");
  CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, R"("interior_points": {"file": "points.csv"})"), dir.path.string()),
             Catch::Contains("interior_points.file line 3: expected 3 fields"));
}

TEST_CASE("unreadable files are named with the key and the path", "[scene][errors]") {
  TempDir dir;
  CHECK_THAT(scene_error(scene(R"("mesh": {"file": "nowhere.obj"})", kMaterial, kFixBottom), dir.path.string()),
             Catch::Contains("mesh.file: cannot read") && Catch::Contains("nowhere.obj"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial, R"("boundary_conditions": {"file": "missing.csv"})"), dir.path.string()),
             Catch::Contains("boundary_conditions.file: cannot read") && Catch::Contains("missing.csv"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, R"("interior_points": {"file": "none.csv"})"), dir.path.string()),
             Catch::Contains("interior_points.file: cannot read"));
  CHECK_THROWS_AS(load_scene((dir.path / "no_scene.json").string()), SceneError);
  CHECK_THROWS_WITH(load_scene((dir.path / "no_scene.json").string()), Catch::Contains("no_scene.json"));
  dir.write("garbage.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
  CHECK_THAT(scene_error(scene(R"("mesh": {"file": "garbage.obj"})", kMaterial, kFixBottom), dir.path.string()),
             Catch::Contains("mesh.file: cannot load"));
}

TEST_CASE("an invalid mesh is reported with the validator's finding", "[scene][errors]") {
  TempDir dir;
  // A tetrahedron with one face missing: open along three edges.
  dir.write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n");
  const std::string message = scene_error(scene(R"("mesh": {"file": "open.obj"})", kMaterial, kFixBottom), dir.path.string());
  CHECK_THAT(message, Catch::Contains("mesh.file: invalid mesh"));
  CHECK_THAT(message, Catch::Contains("open.obj"));
  // The same tetrahedron closed but inside out.
  dir.write("flipped.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 2 4 3\nf 1 3 4\n");
  CHECK_THAT(scene_error(scene(R"("mesh": {"file": "flipped.obj"})", kMaterial, kFixBottom), dir.path.string()),
             Catch::Contains("mesh.file: invalid mesh"));
  // Closed and outward: loads.
  dir.write("tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n");
  const Scene s = load_scene_from_string(scene(R"("mesh": {"file": "tet.obj"})", kMaterial,
                                               R"("boundary_conditions": {"rules": [{"select": {"all": true}, "displacement": [0,0,0]}]})"),
                                         dir.path.string());
  CHECK(s.problem.mesh.num_elements() == 4);
}

TEST_CASE("an invalid material is named by its key", "[scene][errors]") {
  const auto with = [](const std::string& material) { return scene_error(scene(kCube, material, kFixBottom)); };
  CHECK_THAT(with(R"("material": {"young_modulus": 1000, "poisson_ratio": 0.5, "density": 0})"),
             Catch::Contains("material.poisson_ratio: must lie in the open interval (-1, 0.5)"));
  CHECK_THAT(with(R"("material": {"young_modulus": 1000, "poisson_ratio": -1.0, "density": 0})"),
             Catch::Contains("material.poisson_ratio"));
  CHECK_THAT(with(R"("material": {"young_modulus": -3000, "poisson_ratio": 0.3, "density": 0})"),
             Catch::Contains("material.young_modulus: must be positive"));
  CHECK_THAT(with(R"("material": {"young_modulus": 0, "poisson_ratio": 0.3, "density": 0})"),
             Catch::Contains("material.young_modulus: must be positive"));
  CHECK_THAT(with(R"("material": {"young_modulus": 1000, "poisson_ratio": 0.3, "density": -1})"),
             Catch::Contains("material.density: must not be negative"));
  CHECK_THAT(with(R"("material": 5)"), Catch::Contains("material: expected an object, got a number"));
}

TEST_CASE("interior points outside the body or on its surface are refused", "[scene][errors]") {
  TempDir dir;
  dir.write("points.csv", "x,y,z\n0.5,0.5,0.5\n1.5,0.5,0.5\n");
  CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, R"("interior_points": {"file": "points.csv"})"), dir.path.string()),
             Catch::Contains("interior_points.file line 3: point (1.5, 0.5, 0.5) is not inside the body"));
  CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, R"("interior_points": [[0.5, 0.5, 0.5], [0.5, 0.5, 1.0]])")),
             Catch::Contains("interior_points[1]: point") && Catch::Contains("on the surface"));
  // Inside the cavity of a hollow sphere is outside the material.
  CHECK_THAT(scene_error(scene(R"("mesh": {"generator": "hollow_sphere", "inner_radius": 0.5, "outer_radius": 1, "subdivisions": 1})",
                               kMaterial, R"("boundary_conditions": {})", R"("interior_points": [[0.75, 0, 0], [0.1, 0, 0]])")),
             Catch::Contains("interior_points[1]: point (0.1, 0.0, 0.0) is not inside the body"));
  // Closer to the surface than the stress that solve writes for every point is accurate (0.25 x the
  // 0.707 edge = 0.177, docs/stability.md (b)): refused at load, before the solve, naming the point,
  // the element, the distance and the limit; no quadrature setting lifts it. Just outside, it loads.
  const std::string close = R"("interior_points": [[0.5, 0.5, 0.5], [0.3, 0.4, 0.85]])";
  for (const std::string& extra : {std::string(), std::string(R"(, "quadrature": {"max_depth": 12})")})
    CHECK_THAT(scene_error(scene(kCube, kMaterial, kFixBottom, close + extra)),
               Catch::Contains("interior_points[1]: point (0.3, 0.4, 0.85) is 0.15 from element") &&
                   Catch::Contains("closer than 0.25 x 0.707 = 0.177") && Catch::Contains("stress"));
  CHECK(load_scene_from_string(scene(kCube, kMaterial, kFixBottom, R"("interior_points": [[0.5, 0.5, 0.5], [0.3, 0.4, 0.8]])"), ".")
            .interior_points.rows() == 2);
}

TEST_CASE("selectors pick exactly the elements their geometry says", "[scene][selectors]") {
  const TriangleMesh mesh = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), 2, 2, 2);
  REQUIRE(mesh.num_elements() == 48);
  const auto top = face_elements(mesh, 2, 1.0), bottom = face_elements(mesh, 2, -1.0), right = face_elements(mesh, 0, 1.0);
  REQUIRE(top.size() == 8);

  CHECK(as_set(select_elements(mesh, ElementSelector::plane(Vec3(0, 0, 1), Vec3(0, 0, 2), 1e-9))) == top);
  // A plane through the middle of the cube touches no centroid (they sit at 1/6, 1/3, ... of a side).
  CHECK(select_elements(mesh, ElementSelector::plane(Vec3(0, 0, 0.5), Vec3(0, 0, 1), 1e-9)).empty());
  CHECK(as_set(select_elements(mesh, ElementSelector::normal_direction(Vec3(1, 0, 0), 0.9))) == right);
  // min_cos = 0.5 still takes only the +x face: every other face is at 90 degrees or more.
  CHECK(as_set(select_elements(mesh, ElementSelector::normal_direction(Vec3(1, 0, 0), 0.5))) == right);
  CHECK(select_elements(mesh, ElementSelector::normal_direction(Vec3(1, 0, 0), -1.0)).size() == 48);
  CHECK(as_set(select_elements(mesh, ElementSelector::box(Vec3(-1, -1, -1), Vec3(2, 2, 0.01)))) == bottom);
  CHECK(select_elements(mesh, ElementSelector::all()).size() == 48);
  CHECK(select_elements(mesh, ElementSelector::element_list({5, 3, 5})) == std::vector<Index>{3, 5});
  CHECK_THROWS_AS(select_elements(mesh, ElementSelector::plane(Vec3::Zero(), Vec3::Zero(), 0.1)), SceneError);
  CHECK_THROWS_AS(select_elements(mesh, ElementSelector::box(Vec3(1, 0, 0), Vec3(0, 1, 1))), SceneError);

  // Shells of a hollow sphere: 0 is the outer (normals away from the centre), 1 the cavity.
  const TriangleMesh hollow = hollow_sphere_mesh(Vec3::Zero(), 0.5, 1.0, 1, 1);
  const auto inner = select_elements(hollow, ElementSelector::shell_index(1));
  CHECK(inner.size() == 80);
  for (Index e : inner) {
    CHECK(hollow.centroid(e).norm() < 0.51);
    CHECK(hollow.normal(e).dot(hollow.centroid(e)) < 0.0);
  }
  CHECK(select_elements(hollow, ElementSelector::shell_index(0)).size() == 80);
}

TEST_CASE("scene rules: selectors combine by intersection, rules apply in order, the file last", "[scene][selectors]") {
  TempDir dir;
  // Element 0's row in the file overrides what the rules set on it.
  dir.write("bc.csv", "# element 0: roller\nelement,kind_x,kind_y,kind_z,value_x,value_y,value_z\n0, t, t, u, 1.5, 0, -0.25\n");
  const std::string bc = R"("boundary_conditions": {"file": "bc.csv", "rules": [
      {"select": {"all": true}, "displacement": [0.1, 0.2, 0.3]},
      {"select": {"plane": {"point": [0,0,1], "normal": [0,0,1]}, "box": {"min": [0,0,0], "max": [0.5,1,1]}}, "pressure": 2.0},
      {"select": {"normal": {"direction": [1,0,0]}}, "kind": ["u", "t", "t"], "value": [0.01, 4, 5]}]})";
  const Scene s = load_scene_from_string(scene(kCube, kMaterial, bc), dir.path.string());
  const TriangleMesh& mesh = s.problem.mesh;
  const BoundaryConditions& b = s.problem.boundary_conditions;
  const auto right = face_elements(mesh, 0, 1.0);
  std::set<Index> top_left;
  for (Index e : face_elements(mesh, 2, 1.0))
    if (mesh.centroid(e).x() <= 0.5) top_left.insert(e);
  REQUIRE(top_left.size() == 4);
  REQUIRE(right.count(0) == 0);
  REQUIRE(top_left.count(0) == 0);

  for (Index e = 0; e < mesh.num_elements(); ++e) {
    if (e == 0) {
      CHECK(b.kind(0) == BcKind::Traction);
      CHECK(b.kind(2) == BcKind::Displacement);
      CHECK(b.value(0) == 1.5);
      CHECK(b.value(2) == -0.25);
    } else if (top_left.count(e)) {
      for (int c = 0; c < 3; ++c) {
        CHECK(b.kind(3 * e + c) == BcKind::Traction);
        CHECK(b.value(3 * e + c) == Approx(-2.0 * mesh.normal(e)(c)).margin(4 * kEps));  // t = -p n: measured 0
      }
    } else if (right.count(e)) {
      CHECK(b.kind(3 * e) == BcKind::Displacement);
      CHECK(b.kind(3 * e + 1) == BcKind::Traction);
      CHECK(b.value(3 * e) == 0.01);
      CHECK(b.value(3 * e + 2) == 5.0);
    } else {
      for (int c = 0; c < 3; ++c) {
        CHECK(b.kind(3 * e + c) == BcKind::Displacement);
        CHECK(b.value(3 * e + c) == Approx(0.1 * (c + 1)).epsilon(2 * kEps));  // one rounding of 0.1 (c + 1): measured <= 5.6e-17
      }
    }
  }
}

TEST_CASE("a rule that selects nothing is an error, an unknown key a warning", "[scene][selectors]") {
  CHECK_THAT(
      scene_error(scene(
          kCube, kMaterial,
          R"("boundary_conditions": {"rules": [{"select": {"plane": {"point": [0,0,2], "normal": [0,0,1]}}, "displacement": [0,0,0]}]})")),
      Catch::Contains("boundary_conditions.rules[0].select: selects no elements"));
  const Scene s = load_scene_from_string(scene(kCube, kMaterial, kFixBottom, R"("gravty": [0,0,-1], "description": "x")"), ".");
  REQUIRE(s.warnings.size() == 1);
  CHECK_THAT(s.warnings[0], Catch::Contains("gravty: unknown key"));
}

TEST_CASE("generator scenes load with the element counts of their generators", "[scene][generators]") {
  const auto count = [](const std::string& mesh) {
    return load_scene_from_string(scene(mesh, kMaterial, R"("boundary_conditions": {})"), ".").problem.mesh.num_elements();
  };
  CHECK(count(R"("mesh": {"generator": "box", "min": [0,0,0], "max": [2,1,1], "divisions": [4,2,3]})") == 4 * (8 + 6 + 12));
  CHECK(count(R"("mesh": {"generator": "box_grid", "x": [0, 0.1, 1], "y": [0, 1], "z": [0, 0.5, 1]})") == 4 * (2 + 2 + 4));
  CHECK(count(R"("mesh": {"generator": "icosphere", "radius": 2, "subdivisions": 1})") == 80);
  CHECK(count(R"("mesh": {"generator": "icosphere", "center": [1,2,3], "radius": 0.5})") == 320);
  CHECK(count(R"("mesh": {"generator": "ellipsoid", "semi_axes": [1, 2, 0.5], "subdivisions": 1})") == 80);
  CHECK(
      count(
          R"("mesh": {"generator": "hollow_sphere", "inner_radius": 0.5, "outer_radius": 1, "subdivisions_inner": 1, "subdivisions_outer": 2})") ==
      80 + 320);

  const Scene e = load_scene_from_string(
      scene(R"("mesh": {"generator": "ellipsoid", "center": [0, 0, 1], "semi_axes": [1, 2, 0.5], "subdivisions": 2})", kMaterial,
            R"("boundary_conditions": {})"),
      ".");
  const auto box = e.problem.mesh.bounding_box();
  CHECK(box(1, 1) == Approx(2.0).epsilon(4 * kEps));  // measured 0
  CHECK(box(2, 0) == Approx(0.5).epsilon(4 * kEps));  // measured 0

  CHECK_THAT(scene_error(scene(R"("mesh": {"generator": "hollow_sphere", "inner_radius": 1, "outer_radius": 0.5})", kMaterial, kFixBottom)),
             Catch::Contains("mesh.outer_radius: must exceed mesh.inner_radius"));
  CHECK_THAT(scene_error(scene(R"("mesh": {"generator": "icosphere", "radius": 1, "subdivisions": 12})", kMaterial, kFixBottom)),
             Catch::Contains("mesh.subdivisions: must lie in [0, 7]"));
  CHECK_THAT(
      scene_error(scene(R"("mesh": {"generator": "box", "min": [0,0,0], "max": [1,0,1], "divisions": [1,1,1]})", kMaterial, kFixBottom)),
      Catch::Contains("mesh.max: must exceed mesh.min"));
}

TEST_CASE("mesh files resolve against the scene's directory and can be scaled", "[scene]") {
  TempDir dir;
  fs::create_directories(dir.path / "meshes");
  write_obj((dir.path / "meshes" / "cube.obj").string(), box_mesh(Vec3(0, 0, 0), Vec3(10, 10, 10), 1, 1, 1));
  const std::string path = dir.write("scene.json", scene(R"("mesh": {"file": "meshes/cube.obj", "scale": 0.1, "translate": [1, 0, 0]})",
                                                         kMaterial, R"("boundary_conditions": {})"));
  const Scene s = load_scene(path);
  CHECK(s.problem.mesh.num_elements() == 12);
  CHECK(s.problem.mesh.bounding_box()(0, 0) == Approx(1.0).epsilon(4 * kEps));  // 10 x 0.1 + 1: measured 0
  CHECK(s.problem.mesh.bounding_box()(0, 1) == Approx(2.0).epsilon(4 * kEps));  // measured 0
  CHECK(s.problem.mesh.enclosed_volume() == Approx(1.0).epsilon(12 * kEps));    // a sum over 12 faces: measured 2.2e-16
  CHECK_THAT(s.mesh_source, Catch::Contains("cube.obj"));
}

TEST_CASE("generators too large for the dense solve are refused with the estimate before generating", "[scene][generators]") {
  // Before: the box at its maximum divisions generated and validated 12 M elements (> 4 GB)
  // before the solve refused the size; now the element count is predicted from the parameters.
  const auto resource_error = [](const std::string& mesh) -> std::string {
    try {
      load_scene_from_string(scene(mesh, kMaterial, kFixBottom), ".");
    } catch (const ResourceError& e) { return e.what(); } catch (const std::exception& e) {
      return std::string("WRONG EXCEPTION TYPE: ") + e.what();
    }
    return "NO EXCEPTION";
  };
  CHECK_THAT(resource_error(R"("mesh": {"generator": "box", "min": [0,0,0], "max": [1,1,1], "divisions": [1000,1000,1000]})"),
             Catch::Contains("mesh.divisions: a 1000x1000x1000 box has 12000000 elements") && Catch::Contains("GiB") &&
                 Catch::Contains("refused before generating it"));
  // 20 x 4^7 = 327680 elements: about 14 TB for H and G, beyond any machine this runs on.
  CHECK_THAT(resource_error(R"("mesh": {"generator": "icosphere", "radius": 1, "subdivisions": 7})"),
             Catch::Contains("mesh.subdivisions: the icosphere has 327680 elements"));
  CHECK_THAT(
      resource_error(
          R"("mesh": {"generator": "hollow_sphere", "inner_radius": 0.5, "outer_radius": 1, "subdivisions_inner": 1, "subdivisions_outer": 7})"),
      Catch::Contains("the hollow sphere has 327760 elements"));
}

TEST_CASE("overlapping shells are refused at load, a body thinner than its elements is warned about", "[scene][errors]") {
  TempDir dir;
  // Two overlapping spheres in one OBJ: before, this scene loaded and solved.
  const TriangleMesh a = icosphere_mesh(Vec3::Zero(), 1.0, 1), b = icosphere_mesh(Vec3(1.2, 0.0, 0.0), 1.0, 1);
  RowMatrixX3d V(a.num_vertices() + b.num_vertices(), 3);
  V << a.vertices(), b.vertices();
  RowMatrixX3i F(a.num_elements() + b.num_elements(), 3);
  F << a.faces(), (b.faces().array() + static_cast<int>(a.num_vertices())).matrix();
  write_obj((dir.path / "two.obj").string(), TriangleMesh(V, F));
  CHECK_THAT(scene_error(scene(R"("mesh": {"file": "two.obj"})", kMaterial, R"("boundary_conditions": {})"), dir.path.string()),
             Catch::Contains("mesh.file: invalid mesh") && Catch::Contains("faces ") && Catch::Contains("intersect"));

  // A plate 1 x 1 x 0.001 in 2 x 2 x 1 divisions: loads, with a warning naming an element.
  const Scene plate = load_scene_from_string(
      scene(R"("mesh": {"generator": "box", "min": [0,0,0], "max": [1,1,0.001], "divisions": [2,2,1]})", kMaterial, kFixBottom), ".");
  // Its 16 side faces (right triangles of legs 0.5 and 0.001) are slivers of aspect ratio
  // (sqrt(3)/2)(0.25 + 1e-6)/(0.5 x 0.001) = 433 as well.
  REQUIRE(plate.warnings.size() == 2);
  CHECK_THAT(plate.warnings[0], Catch::Contains("mesh: 16 elements are larger than the body is thick under them") &&
                                    Catch::Contains("size 0.5, thickness 0.001"));
  CHECK(plate.warnings[0].find("solved mesh") == std::string::npos);  // the elements are the generator's
  CHECK_THAT(plate.warnings[1],
             Catch::StartsWith("mesh: element ") && Catch::Contains("has aspect ratio 433") && Catch::Contains("above 40 (16 elements)"));
}

TEST_CASE("slivers are warned about at scene load from aspect ratio 40", "[scene]") {
  // A 1 x 1 x h slab in 2 x 2 x 1 divisions: 16 side faces, right triangles of legs 0.5 and h, of
  // aspect ratio (sqrt(3)/2)(0.25 + h^2)/(0.5 h): 37.7 at h = 0.0115 (below), 41.3 at h = 0.0105 (above).
  const auto slab = [](const char* h) {
    return scene(std::string(R"("mesh": {"generator": "box", "min": [0,0,0], "max": [1,1,)") + h + R"(], "divisions": [2,2,1]})", kMaterial,
                 kFixBottom);
  };
  const auto sliver_warnings = [](const Scene& s) {
    std::vector<std::string> out;
    for (const std::string& w : s.warnings)
      if (w.find("aspect ratio") != std::string::npos) out.push_back(w);
    return out;
  };
  CHECK(sliver_warnings(load_scene_from_string(slab("0.0115"), ".")).empty());
  const std::vector<std::string> above = sliver_warnings(load_scene_from_string(slab("0.0105"), "."));
  REQUIRE(above.size() == 1);
  CHECK_THAT(above[0], Catch::StartsWith("mesh: element ") && Catch::Contains("has aspect ratio 41.3") &&
                           Catch::Contains("above 40 (16 elements)") && Catch::Contains("remesh them"));
}

TEST_CASE("the thin-part warning judges the refined mesh solved and names its elements", "[scene]") {
  // A plate 1 x 1 x 0.1 in 2 x 2 x 1 divisions: 32 elements of size 0.5 over a 0.1 thickness.
  const std::string plate = R"("mesh": {"generator": "box", "min": [0,0,0], "max": [1,1,0.1], "divisions": [2,2,1], "refine": )";
  // Refined 3 levels everywhere (size 0.5 / 8 = 0.0625 < 0.1): no warning.
  const Scene fixed =
      load_scene_from_string(scene(plate + R"({"box": {"min": [-1,-1,-1], "max": [2,2,2]}, "levels": 3}})", kMaterial, kFixBottom), ".");
  REQUIRE(fixed.problem.mesh.num_elements() == 32 * 64);
  for (const std::string& x : fixed.warnings) CHECK(x.find("thick under them") == std::string::npos);
  // Only the top face refined: the bottom's elements (up to 0.5 over 0.1) stay thin, and they are
  // numbered in the refined mesh, which the warning says.
  const Scene half =
      load_scene_from_string(scene(plate + R"({"box": {"min": [-1,-1,0.09], "max": [2,2,2]}, "levels": 3}})", kMaterial, kFixBottom), ".");
  const Index E = half.problem.mesh.num_elements();
  REQUIRE(E > 32 + 8 * 63);  // the 8 top elements became 64 each
  std::string w;
  for (const std::string& x : half.warnings)
    if (x.find("thick under them") != std::string::npos) w = x;
  CHECK_THAT(w, Catch::StartsWith("mesh: ") && Catch::Contains("elements are larger than the body is thick under them (element ") &&
                    Catch::Contains(", thickness 0.1 ") &&
                    Catch::EndsWith("(element numbers refer to the solved mesh, " + std::to_string(E) +
                                    " elements after the red-green refinement, not to the input; bemsurg solve, press, cut and session "
                                    "write it to OUTDIR/solved_mesh.obj)"));
  // The element named is a bottom element of the refined mesh, larger than the plate is thick.
  const std::size_t at = w.find("(element ") + 9;
  REQUIRE(at > 9);
  const Index named = std::stoll(w.substr(at));
  REQUIRE(named < E);
  CHECK(half.problem.mesh.normal(named).z() == Approx(-1.0).epsilon(1e-12));
  CHECK(std::sqrt(2.0 * half.problem.mesh.area(named)) > 0.1);
}

TEST_CASE("mesh.prepare repairs a raw file at load: units, the mesh.scale on top, the sphere selector, bad keys named",
          "[scene][prepare]") {
  testing::skip_unless(mesh_preparation_available(), "this build has no mesh preparation (BEMSURG_WITH_PREPARE: CGAL and Gmsh)");
  ::setenv("BEMSURG_CACHE_DIR", "off", 1);  // every load prepares; nothing written outside the test
  TempDir dir;
  // An icosphere of radius 50 mm in millimetres with its first 30 faces turned inside out.
  TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 50.0, 3);
  RowMatrixX3i f = sphere.faces();
  for (Index e = 0; e < 30; ++e) std::swap(f(e, 1), f(e, 2));
  write_obj(dir.file("raw.obj"), TriangleMesh(sphere.vertices(), f));
  const std::string fix_cap = R"("boundary_conditions": {"rules": [{"select": {"sphere": {"center": [0, 0, -0.05], "radius": 0.02}},
                                                                   "displacement": [0, 0, 0]}]})";
  const Scene s = load_scene_from_string(scene(R"("mesh": {"file": "raw.obj", "prepare": {"units": "mm"}})", kMaterial, fix_cap),
                                         dir.path.string(), "test.json");
  CHECK(s.warnings.empty());
  CHECK_THAT(s.mesh_source, Catch::Contains(", prepared (30 defects"));
  CHECK(s.problem.mesh.num_elements() == 1280);  // no more faces than the default target: kept as repaired
  CHECK(s.problem.mesh.enclosed_volume() == Approx(sphere.enclosed_volume() * 1e-9).epsilon(1e-12));
  // The sphere selector holds exactly the elements whose centroid lies within 20 mm of the pole.
  Index near_pole = 0;
  for (Index e = 0; e < s.problem.mesh.num_elements(); ++e) {
    const bool inside = (s.problem.mesh.centroid(e) - Vec3(0, 0, -0.05)).norm() <= 0.02;
    near_pole += inside;
    CHECK(s.problem.boundary_conditions.is_free(e) == !inside);
  }
  CHECK(near_pole > 10);
  // mesh.scale after preparing: the file's unit is said there, so no millimetre warning.
  const Scene t = load_scene_from_string(scene(R"("mesh": {"file": "raw.obj", "scale": 0.001, "prepare": {}})", kMaterial, fix_cap),
                                         dir.path.string(), "test.json");
  CHECK(t.warnings.empty());
  CHECK(t.problem.mesh.vertices().isApprox(s.problem.mesh.vertices(), 1e-12));
  // Without either, the input (100 m across) is warned about, naming the key to add.
  const Scene u = load_scene_from_string(scene(R"("mesh": {"file": "raw.obj", "prepare": {}})", kMaterial, R"("boundary_conditions": {})"),
                                         dir.path.string(), "test.json");
  REQUIRE(u.warnings.size() == 1);
  CHECK_THAT(u.warnings[0], Catch::Contains("mesh.prepare") && Catch::Contains(R"("units": "mm")"));
  CHECK_THAT(scene_error(scene(R"("mesh": {"file": "raw.obj", "prepare": {"units": "inch"}})", kMaterial, kFixBottom), dir.path.string()),
             Catch::Contains("mesh.prepare.units: expected \"mm\", \"cm\" or \"m\", got \"inch\""));
  CHECK_THAT(scene_error(scene(R"("mesh": {"generator": "icosphere", "radius": 1, "prepare": {}})", kMaterial, kFixBottom)),
             Catch::Contains("mesh.prepare: \"prepare\" repairs a mesh file"));
  ::unsetenv("BEMSURG_CACHE_DIR");
}
