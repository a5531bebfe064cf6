// Issue 41 (docs/distributed.md): `bemsurg table` and `bemsurg solve` ("method": "scalapack") on two
// MPI ranks of this machine, against the single-process results of the same scene: the table's
// columns and base state to 1e-10 (and a file press reads without recomputing), the distributed
// solve to dense LU's answer to 1e-10, each rank holding only its share of A*. Skipped in a build
// without MPI (BEMSURG_WITH_MPI off: the sanitizer trees).
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "bemsurg/distributed/mpi_runtime.hpp"
#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/presolution/table_file.hpp"
#include "support/cli_run.hpp"
#include "support/skip.hpp"
#include "support/temp_dir.hpp"

namespace {

void skip_without_mpi() {
  bemsurg::testing::skip_unless(bemsurg::distributed_backend_available() && bemsurg_test::can_run_on_ranks(),
                                "this build has no MPI and ScaLAPACK (BEMSURG_WITH_MPI off), or not Open MPI's launcher");
}

/// A 0.1 x 0.1 x 0.05 m block held on its base, one side pushed down by a prescribed 1 mm and hung
/// under gravity (so both the known-value columns and the gravity term enter the right-hand side).
/// `solver`: the scene's solver section; `divisions`: "6, 6, 3" gives 288 elements (864 equations,
/// 9 blocks of 96), "5, 5, 3" 220 elements (660 equations: a last block of 84 rows).
std::string write_block_scene(const bemsurg_test::TempDir& dir, const std::string& name, const std::string& solver,
                              const std::string& divisions = "6, 6, 3") {
  std::ofstream scene(dir.path / name);
  scene << R"({"mesh": {"generator": "box", "min": [-0.05, -0.05, 0], "max": [0.05, 0.05, 0.05], "divisions": [)" << divisions << R"(]},
               "material": {"young_modulus": 3000, "poisson_ratio": 0.45, "density": 1000}, "gravity": [0, 0, -9.81],
               "boundary_conditions": {"rules": [
                 {"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]},
                 {"select": {"plane": {"point": [0.05, 0, 0], "normal": [1, 0, 0]}}, "displacement": [0, 0, -0.001]}]},
               "operating_region": {"sphere": {"center": [0, 0, 0.05], "radius": 0.03}},
               "solver": )"
        << solver << "}";
  return (dir.path / name).string();
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

/// max |a - b| / max |b| over two matrices of one shape.
double relative_difference(const Eigen::Ref<const Eigen::MatrixXd>& a, const Eigen::Ref<const Eigen::MatrixXd>& b) {
  REQUIRE(a.rows() == b.rows());
  REQUIRE(a.cols() == b.cols());
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

/// The largest relative column difference of two elements.csv files' displacement and traction columns.
double elements_difference(const std::string& a, const std::string& b) {
  const bemsurg_test::CsvTable ta = bemsurg_test::read_table(a), tb = bemsurg_test::read_table(b);
  const std::vector<double> d = bemsurg_test::column_differences(ta, tb);
  REQUIRE(d.size() == 14);  // element, centroid, normal, area, u, t
  double worst = 0.0;
  for (std::size_t k = 8; k < 14; ++k) worst = std::max(worst, d[k]);
  return worst;
}

}  // namespace

TEST_CASE("bemsurg table on two MPI ranks writes the single-process table, which press reads", "[distributed][cli]") {
  skip_without_mpi();
  const bemsurg_test::TempDir dir("bemsurg_test_mpi_table_");
  for (const std::string solver : {R"({"method": "lu"})", R"({"method": "hmatrix", "compression_tolerance": 1e-6})"}) {
    CAPTURE(solver);
    if (solver.find("hmatrix") != std::string::npos && !bemsurg::hierarchical_backend_available()) continue;  // built without hmat-oss
    const std::string scene = write_block_scene(dir, "scene.json", solver);
    const std::string two = dir.file("two.tbl"), one = dir.file("one.tbl");
    const bemsurg_test::CliRun shared =
        bemsurg_test::run_cli_on_ranks(2, "table '" + scene + "' --table '" + two + "' -o '" + dir.file("t2") + "'", dir);
    INFO(shared.err);
    REQUIRE(shared.exit_code == 0);
    REQUIRE(bemsurg_test::run_cli("table '" + scene + "' --table '" + one + "' -o '" + dir.file("t1") + "'", dir).exit_code == 0);

    const nlohmann::json r = read_json(dir.file("t2") + "/report.json");
    CHECK(r.at("ranks") == 2);
    REQUIRE(r.at("peak_memory_mb_per_rank").size() == 2);
    CHECK(r.at("peak_memory_mb_per_rank")[1].get<double>() > 0.0);
    const std::vector<int> per_rank = r.at("columns_per_rank").get<std::vector<int>>();
    REQUIRE(per_rank.size() == 2);
    CHECK(per_rank[0] + per_rank[1] == r.at("columns").get<int>());
    CHECK(std::abs(per_rank[0] - per_rank[1]) <= 3);  // equal shares of elements
    CHECK(r.at("factorization") == (solver.find("hmatrix") != std::string::npos ? "H-LU on every rank" : "dense LU on every rank"));
    CHECK(r.at("backend") == read_json(dir.file("t1") + "/report.json").at("backend"));

    // The two files hold the same table (the file's key check passes for both) to 1e-10.
    const bemsurg::Scene s = bemsurg::load_scene(scene);
    bemsurg::GreensTableKey key = bemsurg::make_greens_table_key(s.problem.mesh, s.problem.material, s.problem.boundary_conditions,
                                                                 s.problem.gravity, s.problem.quadrature);
    key.backend = s.solver.backend;
    key.compression_tolerance = s.solver.backend == bemsurg::SolverBackend::Dense ? 0.0 : s.solver.compression_tolerance;
    const bemsurg::GreensTable a = bemsurg::load_greens_table(two, key), b = bemsurg::load_greens_table(one, key);
    CHECK(a.region() == b.region());
    CHECK(relative_difference(a.columns(), b.columns()) < 1e-10);
    CHECK(relative_difference(a.base_displacement(), b.base_displacement()) < 1e-10);
    CHECK(relative_difference(a.base_traction(), b.base_traction()) < 1e-10);

    // press reads the ranks' file without recomputing, and its force is the single-process table's.
    const std::string press = "press '" + scene + "' --tool flat:0.02 --at 0,0,0.05 --direction 0,0,-1 --depth 0.002 --table ";
    REQUIRE(bemsurg_test::run_cli(press + "'" + two + "' -o '" + dir.file("p2") + "'", dir).exit_code == 0);
    REQUIRE(bemsurg_test::run_cli(press + "'" + one + "' -o '" + dir.file("p1") + "'", dir).exit_code == 0);
    const nlohmann::json f2 = read_json(dir.file("p2") + "/force.json"), f1 = read_json(dir.file("p1") + "/force.json");
    CHECK(f2.at("table").at("loaded_from_file") == true);
    const std::vector<double> g2 = f2.at("force").get<std::vector<double>>(), g1 = f1.at("force").get<std::vector<double>>();
    REQUIRE(g1.size() == 3);
    for (int k = 0; k < 3; ++k) CHECK(std::abs(g2[k] - g1[k]) <= 1e-10 * std::abs(g1[2]));
  }
}

TEST_CASE("bemsurg solve with method scalapack equals dense LU on two ranks and on one, each rank holding its share",
          "[distributed][cli]") {
  skip_without_mpi();
  const bemsurg_test::TempDir dir("bemsurg_test_scalapack_");
  const std::string split = write_block_scene(dir, "split.json", R"({"method": "scalapack"})");
  const std::string dense = write_block_scene(dir, "dense.json", R"({"method": "lu"})");
  REQUIRE(bemsurg_test::run_cli("solve '" + dense + "' -o '" + dir.file("dense") + "' --quiet", dir).exit_code == 0);
  const bemsurg_test::CliRun two = bemsurg_test::run_cli_on_ranks(2, "solve '" + split + "' -o '" + dir.file("two") + "'", dir);
  INFO(two.err);
  REQUIRE(two.exit_code == 0);
  CHECK_THAT(two.out, Catch::Contains("scalapack: 2 rank(s) on a 1 x 2 grid"));
  // Outside mpirun the method runs as one rank (a single-rank MPI job).
  REQUIRE(bemsurg_test::run_cli("solve '" + split + "' -o '" + dir.file("one") + "' --quiet", dir).exit_code == 0);

  CHECK(elements_difference(dir.file("two") + "/elements.csv", dir.file("dense") + "/elements.csv") < 1e-10);
  CHECK(elements_difference(dir.file("one") + "/elements.csv", dir.file("dense") + "/elements.csv") < 1e-10);
  const nlohmann::json r2 = read_json(dir.file("two") + "/report.json"), r1 = read_json(dir.file("one") + "/report.json");
  CHECK(r2.at("ranks") == 2);
  CHECK(r1.at("ranks") == 1);
  CHECK(r2.at("solver").at("method") == "scalapack");
  CHECK(r2.at("solver").at("relative_residual").get<double>() < 1e-12);
  const nlohmann::json& b = r2.at("backend");
  CHECK(b.at("name") == "scalapack");
  CHECK(b.at("process_grid") == nlohmann::json::array({1, 2}));
  CHECK(r1.at("backend").at("process_grid") == nlohmann::json::array({1, 1}));
  // Each rank holds all rows and about half the columns of A*, never the whole.
  const int n = r2.at("equations").get<int>();
  CHECK(b.at("local_rows").get<int>() == n);
  CHECK(b.at("local_columns").get<int>() < n / 2 + b.at("block_size").get<int>());
  REQUIRE(r2.at("peak_memory_mb_per_rank").size() == 2);
}

TEST_CASE("bemsurg solve on two ranks refuses a method that is not scalapack, and a build without MPI refuses scalapack by name",
          "[distributed][cli]") {
  const bemsurg_test::TempDir dir("bemsurg_test_mpi_refusal_");
  const std::string split = write_block_scene(dir, "split.json", R"({"method": "scalapack", "tolerance": 1e-8})");
  if (!bemsurg::distributed_backend_available()) {
    const bemsurg_test::CliRun r = bemsurg_test::run_cli("solve '" + split + "' -o '" + dir.file("out") + "'", dir);
    CHECK(r.exit_code == 1);
    CHECK_THAT(r.err, Catch::Contains("BEMSURG_WITH_MPI"));
    return;
  }
  skip_without_mpi();
  const std::string lu = write_block_scene(dir, "lu.json", R"({"method": "lu"})");
  const bemsurg_test::CliRun r = bemsurg_test::run_cli_on_ranks(2, "solve '" + lu + "' -o '" + dir.file("out") + "'", dir);
  CHECK(r.exit_code != 0);
  CHECK_THAT(r.err, Catch::Contains("only with \"method\": \"scalapack\""));
  // The commands that do not share work refuse to run K times under mpirun.
  const bemsurg_test::CliRun p = bemsurg_test::run_cli_on_ranks(
      2, "press '" + lu + "' --tool flat:0.02 --at 0,0,0.05 --direction 0,0,-1 --depth 0.002 -o '" + dir.file("press") + "'", dir);
  CHECK(p.exit_code != 0);
  CHECK_THAT(p.err, Catch::Contains("bemsurg press runs as one process"));
  // A linear-element scalapack scene is refused with the reason.
  std::ofstream linear(dir.path / "linear.json");
  linear << R"({"mesh": {"generator": "box", "min": [0, 0, 0], "max": [0.1, 0.1, 0.1], "divisions": [2, 2, 2]}, "elements": "linear",
               "material": {"young_modulus": 3000, "poisson_ratio": 0.3},
               "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]},
                                                 {"select": {"plane": {"point": [0, 0, 0.1], "normal": [0, 0, 1]}}, "traction": [0, 0, -100]}]},
               "solver": {"method": "scalapack"}})";
  linear.close();
  const bemsurg_test::CliRun l = bemsurg_test::run_cli("solve '" + dir.file("linear.json") + "' -o '" + dir.file("lin") + "'", dir);
  CHECK(l.exit_code == 1);
  CHECK_THAT(l.err, Catch::Contains("constant elements only"));
}

TEST_CASE("bemsurg solve with method scalapack on 1 x 3 and 2 x 2 grids with a ragged last block, and bemsurg table on 3 ranks",
          "[distributed][cli]") {
  // 660 equations: blocks of 96 leave a last block of 84, so the row and column maps and the ragged
  // block are exercised on a grid with two process rows (4 ranks) as well as one (3 ranks); the
  // table's 3 ranks get unequal shares.
  skip_without_mpi();
  const bemsurg_test::TempDir dir("bemsurg_test_scalapack_grids_");
  const std::string split = write_block_scene(dir, "split.json", R"({"method": "scalapack"})", "5, 5, 3");
  const std::string dense = write_block_scene(dir, "dense.json", R"({"method": "lu"})", "5, 5, 3");
  REQUIRE(bemsurg_test::run_cli("solve '" + dense + "' -o '" + dir.file("dense") + "' --quiet", dir).exit_code == 0);
  for (const int ranks : {3, 4}) {
    CAPTURE(ranks);
    const std::string out = dir.file("split" + std::to_string(ranks));
    const bemsurg_test::CliRun run = bemsurg_test::run_cli_on_ranks(ranks, "solve '" + split + "' -o '" + out + "' --quiet", dir);
    INFO(run.err);
    REQUIRE(run.exit_code == 0);
    CHECK(elements_difference(out + "/elements.csv", dir.file("dense") + "/elements.csv") < 1e-10);
    const nlohmann::json r = read_json(out + "/report.json");
    CHECK(r.at("equations") == 660);
    CHECK(r.at("backend").at("process_grid") == (ranks == 3 ? nlohmann::json::array({1, 3}) : nlohmann::json::array({2, 2})));
    CHECK(r.at("peak_memory_mb_per_rank").size() == static_cast<std::size_t>(ranks));
    CHECK(r.at("solver").at("relative_residual").get<double>() < 1e-12);
  }
  const std::string two = dir.file("three.tbl"), one = dir.file("one.tbl");
  REQUIRE(
      bemsurg_test::run_cli_on_ranks(3, "table '" + dense + "' --table '" + two + "' -o '" + dir.file("t3") + "' --quiet", dir).exit_code ==
      0);
  REQUIRE(bemsurg_test::run_cli("table '" + dense + "' --table '" + one + "' -o '" + dir.file("t1") + "' --quiet", dir).exit_code == 0);
  const std::vector<int> per_rank = read_json(dir.file("t3") + "/report.json").at("columns_per_rank").get<std::vector<int>>();
  REQUIRE(per_rank.size() == 3);
  const bemsurg::Scene s = bemsurg::load_scene(dense);
  const bemsurg::GreensTableKey key = bemsurg::make_greens_table_key(s.problem.mesh, s.problem.material, s.problem.boundary_conditions,
                                                                     s.problem.gravity, s.problem.quadrature);
  const bemsurg::GreensTable a = bemsurg::load_greens_table(two, key), b = bemsurg::load_greens_table(one, key);
  CHECK(per_rank[0] + per_rank[1] + per_rank[2] == static_cast<int>(b.columns().cols()));
  CHECK(relative_difference(a.columns(), b.columns()) < 1e-10);
  CHECK(relative_difference(a.base_displacement(), b.base_displacement()) < 1e-10);
}
