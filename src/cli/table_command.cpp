// bemsurg table: the scene's pre-solution table computed and written to a file that `press` and
// `session` read with --table (docs/cli.md "bemsurg table"; issue 41, item 1). The
// same region (the scene's operating_region, else every free element), backend (the scene's method;
// "auto" chooses per mesh) and file format, key and checksum as theirs: src/cli/scene_table.hpp.
// OUTDIR/report.json says what was computed and what it cost. Under mpirun the ranks share the
// table's columns (issue 41, item 2; docs/distributed.md): each holds the factorisation, rank 0
// gathers the columns and writes the same file a single process writes.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "backend_choice.hpp"
#include "bemsurg/distributed/distributed_table.hpp"
#include "bemsurg/distributed/mpi_runtime.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/timing.hpp"
#include "commands.hpp"
#include "on_ranks.hpp"
#include "scene_table.hpp"

namespace {

constexpr const char* kTableUsage =
    "usage: bemsurg table SCENE.json --table FILE -o OUTDIR [--quiet]\n"
    "\n"
    "Computes the scene's pre-solution table (region: its operating_region, else every free\n"
    "element; backend: its solver method) and writes FILE, which bemsurg press and session read\n"
    "with --table (same format, key and checksum; an existing FILE is replaced).\n"
    "Writes OUTDIR/report.json: elements, equations, region_elements, columns, backend,\n"
    "compression_tolerance, the phases' seconds, seconds (the whole command), ranks,\n"
    "peak_memory_mb_per_rank, table_file, table_bytes, warnings; under mpirun also\n"
    "columns_per_rank, factorization, slowest_rank_seconds, gather_seconds.\n"
    "\n"
    "Under mpirun -np K the K ranks share the columns; rank 0 writes FILE and OUTDIR\n"
    "(docs/distributed.md).\n";

struct TableOptions {
  std::string scene, table_file, output;
  bool quiet = false;
};

std::optional<TableOptions> parse_table(int argc, char** argv) {
  TableOptions o;
  bemsurg::cli::OptionParser parser("table", kTableUsage);
  parser.positional("SCENE.json", o.scene, "one scene file only").required();
  parser.value("--table", "FILE", o.table_file, "where the table is written").required();
  parser.value("-o, --output", "OUTDIR", o.output, "output directory (report.json)").required();
  parser.flag("-q, --quiet", o.quiet, "print nothing but errors");
  if (!parser.parse(argc, argv)) {
    std::cout << parser.help();
    return std::nullopt;
  }
  return o;
}

int table_on_ranks(const TableOptions& o, const bemsurg::MpiRuntime& mpi, bemsurg::SteadyClock::time_point t_start);

}  // namespace

int run_table(int argc, char** argv) {
  using namespace bemsurg;
  const std::optional<TableOptions> parsed = parse_table(argc, argv);
  if (!parsed) return 0;
  TableOptions o = *parsed;
  if (launcher_rank() != 0) o.quiet = true;  // rank 0 alone speaks
  const auto t_start = SteadyClock::now();
  const MpiRuntime mpi;  // several ranks when mpirun started this process
  if (!mpi.root()) o.quiet = true;
  return cli::run_on_ranks(mpi, [&] { return table_on_ranks(o, mpi, t_start); });
}

namespace {

int table_on_ranks(const TableOptions& o, const bemsurg::MpiRuntime& mpi, bemsurg::SteadyClock::time_point t_start) {
  using namespace bemsurg;
  const Scene scene = cli::with_chosen_backend(require_constant_elements(load_scene(o.scene), "bemsurg table"), o.quiet, "bemsurg table");
  if (!o.quiet)
    for (const auto& w : scene.warnings) std::cerr << "bemsurg: warning: " << w << "\n";
  std::error_code ec;
  if (mpi.root()) {
    std::filesystem::create_directories(o.output, ec);
    if (ec || !std::filesystem::is_directory(o.output))
      throw IoError("cannot create the output directory '" + o.output +
                    "': " + (ec ? ec.message() : std::string("a file of that name exists")));
  }
  DistributedTableReport shared;
  CachedGreensTable cached;
  if (mpi.size() == 1) {
    cached = cli::scene_table(scene, o.table_file, o.quiet, false, true);
  } else {
    // A scalapack scene's table: the dense LU on every rank (the same table; docs/distributed.md).
    LinearSolverOptions solver = scene.solver;
    if (solver.backend == SolverBackend::ScaLapack) solver.backend = SolverBackend::Dense;
    GreensTable computed = compute_greens_table_across_ranks(mpi, scene.problem, scene.operating_elements, solver, &shared);
    if (mpi.root()) {
      // Written as a single process writes it (same key, checksum and atomic rename).
      TableCacheOptions options;
      options.recompute = true;
      options.backend = solver.backend;
      options.compression_tolerance = solver.compression_tolerance;
      options.compute = [&computed](const ElastostaticProblem&, const std::vector<Index>&, bool) { return std::move(computed); };
      cached = load_or_compute_scene_table(scene, o.table_file, options);
    }
  }
  const std::vector<double> peaks = mpi.gather(peak_memory_mb());
  if (!mpi.root()) return 0;
  const GreensTable& table = cached.table;
  const PrecomputeTimings& t = table.timings();
  const double total = seconds_since(t_start);
  const double peak = peaks[0];
  nlohmann::json j;
  j["elements"] = table.num_elements();
  j["equations"] = table.num_dofs();
  j["region_elements"] = table.region().size();
  j["columns"] = table.columns().cols();
  j["backend"] = to_string(table.key().backend);
  j["compression_tolerance"] = table.key().compression_tolerance;
  j["assembly_seconds"] = t.assembly_seconds;
  j["factorization_seconds"] = t.factorization_seconds;
  j["table_seconds"] = t.table_seconds;
  j["seconds"] = total;  // the whole command
  j["ranks"] = mpi.size();
  j["peak_memory_mb_per_rank"] = peaks;
  if (mpi.size() > 1) {
    j["columns_per_rank"] = shared.columns_per_rank;
    j["factorization"] = shared.factorization;
    j["slowest_rank_seconds"] = shared.slowest_rank_seconds;
    j["gather_seconds"] = shared.gather_seconds;
  }
  j["table_file"] = o.table_file;
  j["table_bytes"] = std::filesystem::file_size(o.table_file, ec);
  j["warnings"] = table.warnings();
  const std::string json_path = (std::filesystem::path(o.output) / "report.json").string();
  std::ofstream js(json_path);
  js << j.dump(2) << "\n";
  if (!js) throw IoError("cannot write " + json_path);
  if (!o.quiet)
    std::cout << "table: " << table.num_elements() << " elements, " << table.columns().cols() << " columns (" << table.region().size()
              << " region elements" << (mpi.size() > 1 ? ", " + std::to_string(mpi.size()) + " ranks" : std::string()) << "), backend "
              << to_string(table.key().backend) << "; " << fixed_text(total, 2) << " s, peak memory " << fixed_text(peak, 0)
              << " MiB; wrote " << o.table_file << " and " << json_path << "\n";
  return 0;
}

}  // namespace
