// bemsurg/distributed.hpp: the distributed module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup distributed Distributed
/// \brief Beyond one machine (docs/distributed.md): the ranks of an MPI run, pre-solution tables whose columns the ranks share, and the dense solve split over them by ScaLAPACK. A compiled component, bemsurg::distributed; without MPI it runs one rank and refuses the rest.
///
/// Headers (each can be included on its own for faster builds):
/// - distributed_table.hpp
/// - mpi_runtime.hpp
/// - scalapack_solver.hpp

#include "bemsurg/distributed/distributed_table.hpp"
#include "bemsurg/distributed/mpi_runtime.hpp"
#include "bemsurg/distributed/scalapack_solver.hpp"
