// A command's body run on the ranks of an MPI run (docs/distributed.md): an error on any rank ends
// every rank (MPI_Abort) after printing it, because the others may be waiting in a collective that
// would never complete; with one rank the error goes to main's handler as usual.
#pragma once

#include <exception>
#include <iostream>
#include <string>

#include "bemsurg/distributed/mpi_runtime.hpp"

namespace bemsurg::cli {

/// body(), or: print the error ("bemsurg: error: ..." on rank 0, "bemsurg: error (rank R): ..."
/// elsewhere) and abort every rank with status 1, when the run has several ranks.
template <typename Body>
int run_on_ranks(const MpiRuntime& mpi, Body body) {
  if (mpi.size() == 1) return body();
  try {
    return body();
  } catch (const std::exception& e) {
    std::cerr << "bemsurg: error" << (mpi.root() ? std::string() : " (rank " + std::to_string(mpi.rank()) + ")") << ": " << e.what()
              << std::endl;
    mpi.abort(1);
  }
}

}  // namespace bemsurg::cli
