// `bemsurg prepare` (src/cli/prepare_command.cpp, docs/cli.md, docs/organs.md): an STL in
// millimetres with a flipped patch becomes a valid OBJ in metres near the target element count,
// the same file byte for byte when run again, with a JSON report whose fields hold what was found
// and done; bad usage exits 2 naming the option, a missing file or an open sheet exits 1 naming
// the file or the hole limit. Skips (exit 77) in a build without mesh preparation.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/meshing/mesh_defects.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/meshing/mesh_preparation.hpp"
#include "support/cli_run.hpp"
#include "support/skip.hpp"
#include "support/temp_dir.hpp"

using namespace bemsurg;

namespace {

using bemsurg_test::read_text;
using Run = bemsurg_test::CliRun;

Run run_prepare_cli(const std::string& args, const bemsurg_test::TempDir& dir) { return bemsurg_test::run_cli(args, dir); }

const Vec3 kAxes(0.06, 0.045, 0.035);  // metres

/// The ellipsoid (5,120 faces) in millimetres with a patch of 10 faces flipped.
TriangleMesh flipped_ellipsoid_mm() { return scale_mesh(flip_face_patch(ellipsoid_mesh(Vec3::Zero(), kAxes, 4), 10, 3), 1000.0); }

}  // namespace

TEST_CASE("bemsurg prepare writes a valid OBJ in metres and a report of what it found, the same file twice", "[cli][prepare]") {
  testing::skip_unless(mesh_preparation_available(), "this build has no mesh preparation (BEMSURG_WITH_PREPARE: CGAL and Gmsh)");
  const bemsurg_test::TempDir dir("bemsurg_test_prepare_");
  write_stl(dir.file("in.stl"), flipped_ellipsoid_mm());
  const std::string args = "prepare '" + dir.file("in.stl") + "' --units mm --target-elements 500 --report '" + dir.file("r.json") + "'";
  Run r = run_prepare_cli(args + " -o '" + dir.file("a.obj") + "'", dir);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());
  const TriangleMesh out = read_mesh(dir.file("a.obj"));
  CHECK_NOTHROW(require_valid_mesh(out));
  CHECK(std::abs(double(out.num_elements()) / 500.0 - 1.0) < 0.15);
  const Vec3 size = out.bounding_box().col(1) - out.bounding_box().col(0);
  CHECK((size - 2.0 * kAxes).norm() < 0.02 * 2.0 * kAxes.norm());  // metres, not millimetres
  const double volume = 4.0 / 3.0 * 3.14159265358979323846 * kAxes.prod();
  CHECK(out.enclosed_volume() == Approx(volume).epsilon(0.03));  // 500 inscribed flat elements: ~2.5 % low

  const nlohmann::json j = nlohmann::json::parse(read_text(dir.file("r.json")));
  CHECK(j["input"]["faces"] == 5120);
  CHECK(j["input"]["scale"].get<double>() == 1e-3);
  for (const char* key : {"duplicate_vertices", "unreferenced_vertices", "degenerate_faces", "duplicate_faces", "boundary_edges", "holes",
                          "non_manifold_edges", "non_manifold_vertices", "self_intersections"}) {
    INFO(key);
    CHECK(j["defects"][key] == 0);  // the STL reader welds the soup back
  }
  CHECK(j["defects"]["flipped_faces"] == 10);
  CHECK(j["defects"]["shells"] == 1);
  CHECK(j["repairs"]["faces_flipped"] == 10);
  CHECK(j["repairs"]["holes_filled"] == 0);
  CHECK(j["repairs"]["rebuilt"] == false);
  CHECK(j["repairs"]["bodies"] == 1);
  CHECK(j["output"]["elements"] == out.num_elements());
  CHECK(j["output"]["vertices"] == out.num_vertices());
  CHECK(j["output"]["units"] == "m");
  // The distance of 500 inscribed flat elements, ~1-2 mm, under 2 % of the 0.17 m diagonal.
  CHECK(j["hausdorff_distance"].get<double>() > 0.0);
  CHECK(j["hausdorff_relative"].get<double>() < 0.02);
  CHECK(j["hausdorff_relative"].get<double>() == Approx(j["hausdorff_distance"].get<double>() / (2.0 * kAxes.norm())).epsilon(0.01));
  CHECK(j["volume"].get<double>() == Approx(out.enclosed_volume()).epsilon(1e-6));  // the OBJ keeps ~7 digits
  CHECK(std::abs(j["volume_change"].get<double>()) < 0.03);
  CHECK(j["estimate"]["memory_bytes"].get<double>() == Approx(estimate_elastostatic_bytes(out.num_elements())));
  CHECK(j["estimate"]["solve_seconds"].get<double>() > 0.0);
  // The hierarchical estimate where this bemsurg has that backend (docs/organs.md, "How big").
  if (hierarchical_backend_available())
    CHECK(j["estimate"]["hierarchical_memory_bytes"].get<double>() == Approx(estimate_hierarchical_bytes(out.num_elements())));
  else
    CHECK(j["estimate"]["hierarchical_memory_bytes"].is_null());
  double stages = 0.0;
  for (const char* stage : {"read", "clean", "orient_and_close", "self_intersection", "bodies", "remesh", "measure"}) {
    INFO(stage);
    REQUIRE(j["timings"].contains(stage));
    CHECK(j["timings"][stage].get<double>() >= 0.0);
    stages += j["timings"][stage].get<double>();
  }
  CHECK(stages <= j["seconds"].get<double>() + j["timings"]["read"].get<double>() + 1e-3);
  CHECK(j["warnings"].empty());

  r = run_prepare_cli(args + " --quiet -o '" + dir.file("b.obj") + "'", dir);
  REQUIRE(r.exit_code == 0);
  CHECK(read_text(dir.file("a.obj")) == read_text(dir.file("b.obj")));
}

TEST_CASE("bemsurg prepare names bad options, a missing file and an open sheet", "[cli][prepare]") {
  testing::skip_unless(mesh_preparation_available(), "this build has no mesh preparation (BEMSURG_WITH_PREPARE: CGAL and Gmsh)");
  const bemsurg_test::TempDir dir("bemsurg_test_prepare_");
  const std::string in = dir.file("in.stl"), out = " -o '" + dir.file("out.obj") + "'";
  write_stl(in, flipped_ellipsoid_mm());
  Run r = run_prepare_cli("prepare '" + in + "' --units inch" + out, dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("--units") && Catch::Contains("'inch'") && Catch::Contains("mm, cm or m"));
  r = run_prepare_cli("prepare '" + in + "' --units mm --scale 0.001" + out, dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("give --units or --scale, not both"));
  r = run_prepare_cli("prepare '" + in + "' --target-elements 500 --edge-length 0.01" + out, dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("--target-elements") && Catch::Contains("--edge-length"));
  r = run_prepare_cli("prepare '" + dir.file("missing.stl") + "'" + out, dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Catch::Contains("cannot read '" + dir.file("missing.stl") + "'"));

  // The upper half of the ellipsoid: an open sheet whose rim is longer than the hole limit.
  const TriangleMesh e = scale_mesh(ellipsoid_mesh(Vec3::Zero(), kAxes, 3), 1000.0);
  RowMatrixX3i upper(e.num_elements(), 3);
  Index n = 0;
  for (Index f = 0; f < e.num_elements(); ++f)
    if (e.centroid(f).z() > 0.0) upper.row(n++) = e.faces().row(f);
  write_stl(dir.file("sheet.stl"), TriangleMesh(e.vertices(), upper.topRows(n)));
  r = run_prepare_cli("prepare '" + dir.file("sheet.stl") + "' --units mm" + out, dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Catch::Contains("sheet.stl") && Catch::Contains("the surface is open") && Catch::Contains("more than the limit of") &&
                        Catch::Contains("--max-hole"));
}
