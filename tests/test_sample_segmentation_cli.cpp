// `bemsurg sample-segmentation` (src/cli/sample_segmentation_command.cpp, docs/cli.md,
// docs/organ-samples.md): the file has about the requested number of triangles, in millimetres
// with the defects or in metres and valid with --clean, is the same byte for byte for the same
// arguments, and a bad organ, unit or extension is a usage error (exit status 2) that names it.
#include <catch2/catch.hpp>

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "support/cli_run.hpp"
#include "support/temp_dir.hpp"

using namespace bemsurg;

namespace {

using bemsurg_test::read_text;
using Run = bemsurg_test::CliRun;

Run run_sample_cli(const std::string& args, const bemsurg_test::TempDir& dir) { return bemsurg_test::run_cli(args, dir); }

}  // namespace

TEST_CASE("sample-segmentation writes a defective liver of about 100000 triangles in millimetres", "[cli][organ_samples]") {
  const bemsurg_test::TempDir dir("bemsurg_test_sample_");
  const std::string path = dir.file("liver.stl");
  REQUIRE(run_sample_cli("sample-segmentation liver -o '" + path + "'", dir).exit_code == 0);
  const TriangleMesh m = read_stl(path);
  CHECK(std::abs(static_cast<double>(m.num_elements()) - 100000.0) < 20000.0);
  const Vec3 extent = m.bounding_box().col(1) - m.bounding_box().col(0);
  CHECK(extent.x() > 150.0);  // millimetres: the liver is about 200 mm wide (the speck adds to the box)
  const MeshValidationResult r = validate_mesh(m);
  CHECK(r.count(MeshIssueKind::DegenerateFace) > 0);
  CHECK(r.count(MeshIssueKind::BoundaryEdge) > 0);
  CHECK(r.count(MeshIssueKind::NonManifoldEdge) > 0);
}

TEST_CASE("sample-segmentation --clean --units m writes a valid kidney, the same for the same arguments", "[cli][organ_samples]") {
  const bemsurg_test::TempDir dir("bemsurg_test_sample_");
  for (const char* name : {"a.obj", "b.obj"})
    REQUIRE(run_sample_cli("sample-segmentation kidney --clean --units m --triangles 5000 -o '" + dir.file(name) + "'", dir).exit_code ==
            0);
  CHECK(read_text(dir.file("a.obj")) == read_text(dir.file("b.obj")));
  const TriangleMesh m = read_mesh(dir.file("a.obj"));
  require_valid_mesh(m);
  CHECK(std::abs(static_cast<double>(m.num_elements()) - 5000.0) < 1000.0);
  const Vec3 extent = m.bounding_box().col(1) - m.bounding_box().col(0);
  CHECK(extent.z() == Approx(0.11).epsilon(0.05));  // metres
  // Defects move with the seed.
  REQUIRE(run_sample_cli("sample-segmentation kidney --triangles 5000 --seed 2 -o '" + dir.file("c.ply") + "'", dir).exit_code == 0);
  REQUIRE(run_sample_cli("sample-segmentation kidney --triangles 5000 --seed 3 -o '" + dir.file("d.ply") + "'", dir).exit_code == 0);
  CHECK(read_text(dir.file("c.ply")) != read_text(dir.file("d.ply")));
}

TEST_CASE("sample-segmentation names a bad organ, unit or extension with exit status 2", "[cli][organ_samples]") {
  const bemsurg_test::TempDir dir("bemsurg_test_sample_");
  Run r = run_sample_cli("sample-segmentation spleen -o '" + dir.file("x.stl") + "'", dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("unknown organ 'spleen' (known: liver, kidney)"));
  r = run_sample_cli("sample-segmentation liver --units cm -o '" + dir.file("x.stl") + "'", dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("--units: expected mm or m, got 'cm'"));
  r = run_sample_cli("sample-segmentation liver -o '" + dir.file("x.xyz") + "'", dir);
  CHECK(r.exit_code == 2);
  CHECK_THAT(r.err, Catch::Contains("unknown mesh file extension '.xyz'"));
  CHECK(run_sample_cli("sample-segmentation liver --triangles 10 -o '" + dir.file("x.stl") + "'", dir).exit_code == 2);
}
