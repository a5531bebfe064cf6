// bemsurg table: the scene's pre-solution table computed and written to a file that `press` and
// `session` read with --table (docs/cli.md "bemsurg table"; issue 41, item 1). The
// same region (the scene's operating_region, else every free element), backend (the scene's method;
// "auto" chooses per mesh) and file format, key and checksum as theirs: src/cli/scene_table.hpp.
// OUTDIR/report.json says what was computed and what it cost.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "backend_choice.hpp"
#include "bemsurg/io/results_io.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/timing.hpp"
#include "commands.hpp"
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
    "peak_memory_mb_per_rank, table_file, table_bytes, warnings.\n";

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

}  // namespace

int run_table(int argc, char** argv) {
  using namespace bemsurg;
  const std::optional<TableOptions> parsed = parse_table(argc, argv);
  if (!parsed) return 0;
  const TableOptions& o = *parsed;
  const auto t_start = SteadyClock::now();
  const Scene scene = cli::with_chosen_backend(require_constant_elements(load_scene(o.scene), "bemsurg table"), o.quiet, "bemsurg table");
  if (!o.quiet)
    for (const auto& w : scene.warnings) std::cerr << "bemsurg: warning: " << w << "\n";
  std::error_code ec;
  std::filesystem::create_directories(o.output, ec);
  if (ec || !std::filesystem::is_directory(o.output))
    throw IoError("cannot create the output directory '" + o.output +
                  "': " + (ec ? ec.message() : std::string("a file of that name exists")));
  const CachedGreensTable cached = cli::scene_table(scene, o.table_file, o.quiet, false, true);
  const GreensTable& table = cached.table;
  const PrecomputeTimings& t = table.timings();
  const double total = seconds_since(t_start);
  const double peak = peak_memory_mb();
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
  j["ranks"] = 1;
  j["peak_memory_mb_per_rank"] = nlohmann::json::array({peak});
  j["table_file"] = o.table_file;
  j["table_bytes"] = std::filesystem::file_size(o.table_file, ec);
  j["warnings"] = table.warnings();
  const std::string json_path = (std::filesystem::path(o.output) / "report.json").string();
  std::ofstream js(json_path);
  js << j.dump(2) << "\n";
  if (!js) throw IoError("cannot write " + json_path);
  if (!o.quiet)
    std::cout << "table: " << table.num_elements() << " elements, " << table.columns().cols() << " columns (" << table.region().size()
              << " region elements), backend " << to_string(table.key().backend) << "; " << fixed_text(total, 2) << " s, peak memory "
              << fixed_text(peak, 0) << " MiB; wrote " << o.table_file << " and " << json_path << "\n";
  return 0;
}
