// The `bemsurg` program's sub-commands (docs/cli.md). Each one is called like a program's main:
// argv[0] is the sub-command's name ("solve", "press") and argv[1..argc-1] are its arguments.
// A sub-command returns its exit status; it throws bemsurg::cli::UsageError for a command line it
// cannot understand (main prints it and exits with 2) and any other exception for a failure (main
// prints "bemsurg: error: <message>" and exits with 1).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "options/option_parser.hpp"

namespace bemsurg::cli {

/// "X,Y,Z" as a vector of three finite numbers, read by parse_number (the same in every locale);
/// `command` and `option` name the fault.
inline Eigen::Vector3d parse_vector3(const std::string& command, const std::string& option, const std::string& text) {
  const std::optional<std::vector<double>> v = parse_number_list<double>(text);
  if (!v || v->size() != 3 || !std::isfinite((*v)[0]) || !std::isfinite((*v)[1]) || !std::isfinite((*v)[2]))
    throw UsageError(command + ": " + option + ": expected three comma-separated finite numbers, got '" + text + "'");
  return {(*v)[0], (*v)[1], (*v)[2]};
}

/// Declares an "X,Y,Z" option of `parser` read into `target` by parse_vector3.
inline OptionParser& vector3_value(OptionParser& parser, const std::string& name, std::string value_name, Eigen::Vector3d& target,
                                   std::string help) {
  return parser.custom_value(
      name, std::move(value_name), std::move(help),
      [&target, program = parser.program(), name](const std::string& text) { target = parse_vector3(program, name, text); });
}

}  // namespace bemsurg::cli

/// bemsurg solve SCENE.json -o OUTDIR [--quiet]  (src/cli/solve_command.cpp)
int run_solve(int argc, char** argv);

/// bemsurg press ...  (src/cli/press_command.cpp)
int run_press(int argc, char** argv);

/// bemsurg table SCENE.json --table FILE -o OUTDIR  (src/cli/table_command.cpp)
int run_table(int argc, char** argv);

/// bemsurg session SCENE.json --script ACTIONS.json -o OUTDIR  (src/cli/session_command.cpp)
int run_session(int argc, char** argv);
/// bemsurg cut SCENE.json --from X,Y,Z --direction DX,DY,DZ --steps K ... (src/cli/cut_command.cpp)
int run_cut(int argc, char** argv);

/// bemsurg prepare IN -o OUT.obj ... (src/cli/prepare_command.cpp)
int run_prepare(int argc, char** argv);
/// bemsurg sample-segmentation liver|kidney -o OUT.stl ...  (src/cli/sample_segmentation_command.cpp)
int run_sample_segmentation(int argc, char** argv);
