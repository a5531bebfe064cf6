// bemsurg/distributed/mpi_runtime.hpp: the ranks a command runs on (issue 41; docs/distributed.md).
//
// A program started by mpirun (or any MPI launcher) runs as one of K ranks of MPI_COMM_WORLD; the
// same program started on its own runs as one rank, without initialising MPI unless a method needs
// it (ScaLAPACK's solve, which then runs as a single-rank MPI job). MpiRuntime owns that decision
// and MPI's lifetime (MPI_Init_thread at construction, MPI_Finalize at destruction when it
// initialised), and offers the few collectives the commands need that carry no numerics: a barrier,
// a gather of one number per rank (peak memory), and an abort that ends every rank after an error on
// one, so that no rank waits forever in a collective.
//
// MPI's types stay out of this header: a program that includes it needs no mpi.h, and the library
// and every command build without MPI (CMake option BEMSURG_WITH_MPI; the component bemsurg::distributed
// then holds the refusals).
#pragma once

#include <string>
#include <vector>

namespace bemsurg {

/// True when this build has MPI and ScaLAPACK (BEMSURG_WITH_MPI): tables across ranks and the
/// "scalapack" solve.
bool distributed_backend_available();

/// True when this process was started by an MPI launcher (mpirun, mpiexec, srun with PMI): the
/// environment it sets (OMPI_COMM_WORLD_SIZE, PMIX_RANK, PMI_SIZE, ...) is present.
bool launched_by_mpi_launcher();

/// The number of ranks the launcher started, as its environment says before MPI starts
/// (OMPI_COMM_WORLD_SIZE, PMI_SIZE, MV2_COMM_WORLD_SIZE); 0 when it does not say (no launcher).
long launcher_rank_count();

/// This process's rank as the launcher's environment says before MPI starts; 0 without a launcher.
long launcher_rank();

/// The ranks of this run: MPI_COMM_WORLD when MPI is in use, else one rank (docs/distributed.md).
/// One per process: MPI is initialised once; a second MpiRuntime while one lives shares it.
/// \ingroup distributed
class MpiRuntime {
 public:
  /// Initialises MPI (thread level funneled: OpenMP and OpenBLAS threads inside a rank never call
  /// MPI) when the process was launched by an MPI launcher or when `required` (a method that only
  /// runs on MPI: then a single-rank job outside mpirun). Otherwise one rank, no MPI. Throws
  /// SolverError when MPI is asked for (`required`, or a launcher with more than one rank) and this
  /// build has none, when MPI_Init_thread fails, and when MPI was finalised already (it cannot start again).
  explicit MpiRuntime(bool required = false);
  ~MpiRuntime();
  MpiRuntime(const MpiRuntime&) = delete;
  MpiRuntime& operator=(const MpiRuntime&) = delete;

  /// True when MPI is initialised and in use (possibly with one rank).
  bool active() const { return active_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  /// Ranks of this run on this node (MPI_COMM_TYPE_SHARED; 1 without MPI): they share its memory,
  /// so each checks its need against its share of the node's limit.
  int ranks_on_node() const { return ranks_on_node_; }
  /// The memory limit of one rank: 80 % of the node's physical memory shared by its ranks.
  double memory_limit_bytes() const;
  /// The MPI library's version string, or "none".
  std::string library_version() const;

  /// Waits for every rank (nothing without MPI).
  void barrier() const;
  /// One value per rank, in rank order, on every rank (MPI_Allgather; {value} with one rank).
  std::vector<double> gather(double value) const;
  /// The largest of every rank's value, on every rank.
  double max(double value) const;
  /// Ends every rank with exit status `code` (MPI_Abort; std::exit without MPI): after an error on one
  /// rank the others may be waiting in a collective that would never complete.
  [[noreturn]] void abort(int code) const;

 private:
  bool active_ = false;
  bool owns_ = false;  // this object initialised MPI, so it finalises it
  int rank_ = 0, size_ = 1, ranks_on_node_ = 1;
};

}  // namespace bemsurg
