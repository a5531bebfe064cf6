// bemsurg/bemsurg.hpp: every module of the library bemsurg::bemsurg in one include. Each module
// has its own header (bemsurg/mesh.hpp, bemsurg/solvers.hpp, ...) and every header can be included
// on its own for faster builds. Left out: bemsurg/haptics.hpp, because the haptics adapter is a
// library of its own (bemsurg::haptics) that only device programs link. A module whose code needs
// an optional dependency still compiles without it: the graded remesher (Gmsh) throws and says so,
// and the near-field preconditioner (SuiteSparse) needs bemsurg::bemsurg rather than the
// header-only bemsurg::core (docs/design.md, "Module order").
#pragma once

#include "bemsurg/blas_threads.hpp"
#include "bemsurg/config.hpp"
#include "bemsurg/constants.hpp"
#include "bemsurg/dense_storage.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/snapshot_buffers.hpp"
#include "bemsurg/timing.hpp"
#include "bemsurg/types.hpp"
#include "bemsurg/version.hpp"

#include "bemsurg/assembly.hpp"
#include "bemsurg/cutting.hpp"
#include "bemsurg/elastostatics.hpp"
#include "bemsurg/io.hpp"
#include "bemsurg/kernels.hpp"
#include "bemsurg/mesh.hpp"
#include "bemsurg/meshing.hpp"
#include "bemsurg/post.hpp"
#include "bemsurg/presolution.hpp"
#include "bemsurg/quadrature.hpp"
#include "bemsurg/solvers.hpp"
#include "bemsurg/verification.hpp"
