// The `bemsurg` program's sub-commands (docs/cli.md). Each one is called like a program's main:
// argv[0] is the sub-command's name ("solve", "press") and argv[1..argc-1] are its arguments.
// A sub-command returns its exit status; it throws bemsurg::cli::UsageError for a command line it
// cannot understand (main prints it and exits with 2) and any other exception for a failure (main
// prints "bemsurg: error: <message>" and exits with 1).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "bemsurg/error.hpp"

namespace bemsurg::cli {

/// A command line that cannot be understood: unknown option, missing or extra argument.
class UsageError : public Error {
 public:
  using Error::Error;
};

/// "X,Y,Z" as a vector of three finite numbers; `command` and `option` name the fault.
inline Eigen::Vector3d parse_vector3(const std::string& command, const std::string& option, const std::string& text) {
  std::stringstream ss(text);
  std::string item;
  std::vector<double> v;
  while (std::getline(ss, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw UsageError(command + ": " + option + " expects three comma-separated numbers, got '" + text + "'");
    }
  }
  if (v.size() != 3 || !std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
    throw UsageError(command + ": " + option + " expects three comma-separated finite numbers, got '" + text + "'");
  return {v[0], v[1], v[2]};
}

}  // namespace bemsurg::cli

/// bemsurg solve SCENE.json -o OUTDIR [--quiet]  (src/cli/solve_command.cpp)
int run_solve(int argc, char** argv);

/// bemsurg press ...  (src/cli/press_command.cpp)
int run_press(int argc, char** argv);

/// bemsurg session SCENE.json --script ACTIONS.json -o OUTDIR  (src/cli/session_command.cpp)
int run_session(int argc, char** argv);
/// bemsurg cut SCENE.json --from X,Y,Z --direction DX,DY,DZ --steps K ... (src/cli/cut_command.cpp)
int run_cut(int argc, char** argv);
