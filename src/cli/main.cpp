// The `bemsurg` command-line program: entry point and sub-command dispatch (docs/cli.md).
// Errors are caught here, at the program's edge, and printed as "bemsurg: error: ..." with exit
// status 1; a command line that cannot be understood exits with 2.
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include "bemsurg/distributed/mpi_runtime.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/version.hpp"
#include "commands.hpp"

namespace {

constexpr const char* kUsage =
    "usage: bemsurg <command> [arguments]\n"
    "       bemsurg --help | --version\n"
    "\n"
    "commands:\n"
    "  solve SCENE.json -o OUTDIR   solve a scene; write elements.csv, interior.csv, surface.vtk, report.json\n"
    "  press ...                    press a tool into a scene and report the force (bemsurg press --help)\n"
    "  table SCENE.json --table FILE -o OUTDIR\n"
    "                               compute a scene's pre-solution table into FILE (for --table)\n"
    "  session SCENE.json --script ACTIONS.json -o OUTDIR\n"
    "                               run an action script through the haptic loop (bemsurg session --help)\n"
    "  cut ...                      cut a scene step by step, updating system and tables (bemsurg cut --help)\n"
    "  prepare IN -o OUT.obj        repair and remesh a segmentation's surface for the other commands\n"
    "                               (bemsurg prepare --help; docs/organs.md)\n"
    "  sample-segmentation liver|kidney -o OUT.stl\n"
    "                               write an organ-like, deliberately defective segmentation surface (mm)\n"
    "\n"
    "Run 'bemsurg <command> --help' for a command's options. Scene format: docs/scene-format.md.\n";

int usage_error(const std::string& message) {
  std::cerr << "bemsurg: error: " << message << "\n"
            << "Run 'bemsurg --help' for usage.\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  // What the commands print (times, forces, residuals) has a decimal point whatever the global
  // C++ locale: this program never sets one, but the streams say so themselves (number_text.hpp).
  bemsurg::use_classic_locale(std::cout);
  bemsurg::use_classic_locale(std::cerr);
  if (argc < 2) return usage_error("missing command");
  const std::string command = argv[1];
  if (command == "--version" || command == "-V") {
    std::cout << "bemsurg " << bemsurg::version_string() << "\n";
    return 0;
  }
  if (command == "--help" || command == "-h" || command == "help") {
    std::cout << kUsage;
    return 0;
  }
  try {
    // The sub-command sees itself as argv[0], like a program's main.
    // Cut steps replace whole table snapshots: reuse their memory (bemsurg/memory_budget.hpp).
    if (command == "cut" || command == "session") bemsurg::reuse_freed_memory();
    // Under mpirun only table and solve share the work (docs/distributed.md); K copies of another
    // command would each do all of it and write the same files.
    if (command != "solve" && command != "table" && bemsurg::launcher_rank_count() > 1)
      throw bemsurg::SolverError("bemsurg " + command + " runs as one process; under mpirun (" +
                                 std::to_string(bemsurg::launcher_rank_count()) +
                                 " ranks) only table and solve share the work (docs/distributed.md): run it without mpirun");
    if (command == "solve") return run_solve(argc - 1, argv + 1);
    if (command == "press") return run_press(argc - 1, argv + 1);
    if (command == "table") return run_table(argc - 1, argv + 1);
    if (command == "session") return run_session(argc - 1, argv + 1);
    if (command == "cut") return run_cut(argc - 1, argv + 1);
    if (command == "prepare") return run_prepare(argc - 1, argv + 1);
    if (command == "sample-segmentation") return run_sample_segmentation(argc - 1, argv + 1);
    return usage_error("unknown command '" + command + "'");
  } catch (const bemsurg::cli::UsageError& e) { return usage_error(e.what()); } catch (const std::bad_alloc&) {
    std::cerr << "bemsurg: error: out of memory (the dense BEM system grows as the square of the number of elements: use a coarser mesh)\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "bemsurg: error: " << e.what() << "\n";
    return 1;
  }
}
