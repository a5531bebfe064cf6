// Implementation of bemsurg/distributed/mpi_runtime.hpp: MPI's lifetime and the commands' few
// collectives; without MPI (BEMSURG_WITH_MPI off) one rank and the refusals.
#include "bemsurg/distributed/mpi_runtime.hpp"

#include <cstdlib>
#include <string>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"

#if BEMSURG_HAVE_MPI
#include <mpi.h>
#endif

namespace bemsurg {

bool launched_by_mpi_launcher() {
  // Open MPI's mpirun, PMIx launchers (Open MPI 4/5, Slurm), PMI-1/2 launchers (MPICH's hydra, Slurm), MVAPICH.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE", "PMI_RANK", "MV2_COMM_WORLD_SIZE"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

long launcher_rank_count() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "MV2_COMM_WORLD_SIZE"})
    if (const char* v = std::getenv(name)) return std::strtol(v, nullptr, 10);
  return 0;
}

long launcher_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "MV2_COMM_WORLD_RANK"})
    if (const char* v = std::getenv(name)) return std::strtol(v, nullptr, 10);
  return 0;
}

double MpiRuntime::memory_limit_bytes() const { return default_memory_limit_bytes() / double(ranks_on_node_); }

#if BEMSURG_HAVE_MPI

bool distributed_backend_available() { return true; }

MpiRuntime::MpiRuntime(bool required) {
  if (!required && !launched_by_mpi_launcher()) return;
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (finalised) throw SolverError("MpiRuntime: MPI was finalised already in this process and cannot start again");
  if (!initialised) {
    int provided = 0;
    if (MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
      throw SolverError("MPI_Init_thread failed: MPI cannot start in this environment (docs/distributed.md)");
    owns_ = true;
  }
  active_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &ranks_on_node_);
  MPI_Comm_free(&node);
}

MpiRuntime::~MpiRuntime() {
  if (!owns_) return;
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (!finalised) MPI_Finalize();
}

std::string MpiRuntime::library_version() const {
  char text[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(text, &length);
  std::string out(text, static_cast<std::size_t>(length));
  const std::size_t line = out.find_first_of("\n,");
  return line == std::string::npos ? out : out.substr(0, line);
}

void MpiRuntime::barrier() const {
  if (active_) MPI_Barrier(MPI_COMM_WORLD);
}

std::vector<double> MpiRuntime::gather(double value) const {
  std::vector<double> out(static_cast<std::size_t>(size_), value);
  if (active_) MPI_Allgather(&value, 1, MPI_DOUBLE, out.data(), 1, MPI_DOUBLE, MPI_COMM_WORLD);
  return out;
}

double MpiRuntime::max(double value) const {
  double out = value;
  if (active_) MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return out;
}

void MpiRuntime::abort(int code) const {
  if (active_) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else

bool distributed_backend_available() { return false; }

MpiRuntime::MpiRuntime(bool required) {
  // Started as one of several ranks by a build that cannot talk to the others: every copy would do
  // the whole work and write the same files, so refuse rather than run K times.
  if (required || launcher_rank_count() > 1)
    throw SolverError(
        std::string(required ? "this method needs MPI and ScaLAPACK" : "this program was started by mpirun with several ranks") +
        ", and this build of bemsurg has neither (configure with -DBEMSURG_WITH_MPI=ON; Debian: libopenmpi-dev, "
        "openmpi-bin, libscalapack-openmpi-dev; scripts/setup-deps.sh installs them)");
}

MpiRuntime::~MpiRuntime() = default;
std::string MpiRuntime::library_version() const { return "none"; }
void MpiRuntime::barrier() const {}
std::vector<double> MpiRuntime::gather(double value) const { return {value}; }
double MpiRuntime::max(double value) const { return value; }
void MpiRuntime::abort(int code) const { std::exit(code); }

#endif

}  // namespace bemsurg
