// bench_stability: the stability studies of issue 25 (docs/stability.md). Each study sweeps one
// parameter of a method until it breaks (Poisson's ratio towards 0.5, interior points towards the
// surface, slivers, narrow cut gaps, Krylov breakdowns, accumulated cut updates, thin parts and
// small tools, press depth past the tool radius, non-uniform meshes), writes the sweep as CSV into
// --csv-dir and prints the threshold it found with the behaviour bemsurg chooses there. The report
// (scripts/report/parts/stability_*.py) runs one study per section and charts it.
#include <exception>
#include <iostream>
#include <optional>
#include <string>

#include "bench_support.hpp"
#include "stability/stability_study.hpp"

int main(int argc, char** argv) {
  using namespace bemsurg;
  namespace st = bench::stability;
  bool quick = false, list = false;
  std::string json_path, study = "all", csv_dir = ".";
  cli::OptionParser parser =
      bench::command_line("bench_stability", "Sweeps each method to its breaking point (issue 25, docs/stability.md).\n", quick, json_path);
  parser.value("--study", "NAME", study, "one study by name (--list shows them) or all").default_text("all");
  parser.value("--csv-dir", "DIR", csv_dir, "where each study writes its CSV files (created)").default_text(".");
  parser.flag("--list", list, "print the studies (letter, name, what it sweeps) and exit");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (list) {
    for (const st::StudyEntry& s : st::all_studies()) std::cout << s.letter << "\t" << s.name << "\t" << s.title << "\n";
    return 0;
  }
  bool known = study == "all";
  for (const st::StudyEntry& s : st::all_studies()) known = known || study == s.name;
  if (!known) {
    std::cerr << "bench_stability: --study " << study << ": no such study (--list shows them)\n";
    return 2;
  }
  st::StudyContext ctx{quick, csv_dir};
  std::filesystem::create_directories(ctx.csv_dir);
  nlohmann::json report = {{"benchmark", "bench_stability"}, {"mode", quick ? "quick" : "full"}, {"studies", nlohmann::json::object()}};
  for (const st::StudyEntry& s : st::all_studies()) {
    if (study != "all" && study != s.name) continue;
    std::cout << "bench_stability: (" << s.letter << ") " << s.title << "\n" << std::flush;
    try {
      report["studies"][s.name] = s.run(ctx);
    } catch (const std::exception& e) {
      std::cerr << "bench_stability: study " << s.name << " failed: " << e.what() << "\n";
      return 1;
    }
  }
  return bench::write_json_file(json_path, report, "bench_stability") ? 0 : 1;
}
