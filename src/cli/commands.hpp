// The `bemsurg` program's sub-commands (docs/cli.md). Each one is called like a program's main:
// argv[0] is the sub-command's name ("solve", "press") and argv[1..argc-1] are its arguments.
// A sub-command returns its exit status; it throws bemsurg::cli::UsageError for a command line it
// cannot understand (main prints it and exits with 2) and any other exception for a failure (main
// prints "bemsurg: error: <message>" and exits with 1).
#pragma once

#include "bemsurg/error.hpp"

namespace bemsurg::cli {

/// A command line that cannot be understood: unknown option, missing or extra argument.
class UsageError : public Error {
 public:
  using Error::Error;
};

}  // namespace bemsurg::cli

/// bemsurg solve SCENE.json -o OUTDIR [--quiet]  (src/cli/solve_command.cpp)
int run_solve(int argc, char** argv);

/// bemsurg press ...  (src/cli/press_command.cpp)
int run_press(int argc, char** argv);

/// bemsurg session SCENE.json --script ACTIONS.json -o OUTDIR  (src/cli/session_command.cpp)
int run_session(int argc, char** argv);
