// bemsurg/solvers.hpp: the solvers module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup solvers Solvers
/// \brief Dense LU (in place, low-rank updated, partitioned inverse), the Krylov methods GMRES, BiCGStab and BiCG with their preconditioners, and one entry point solve_linear_system. The near-field preconditioner needs SuiteSparse and is compiled into bemsurg::numerics (part of bemsurg::bemsurg) only.
///
/// Headers (each can be included on its own for faster builds):
/// - bicg.hpp
/// - bicgstab.hpp
/// - block_jacobi_preconditioner.hpp
/// - dense_lu.hpp
/// - explicit_inverse.hpp
/// - gmres.hpp
/// - identity_preconditioner.hpp
/// - krylov_options.hpp
/// - krylov_result.hpp
/// - krylov_solver_base.hpp
/// - linear_operator.hpp
/// - linear_solve.hpp
/// - low_rank_updated_lu.hpp
/// - lu_factors.hpp
/// - lu_in_place.hpp
/// - near_field_preconditioner.hpp
/// - partitioned_inverse.hpp
/// - structured_products.hpp
/// - system_factorization.hpp

#include "bemsurg/solvers/bicg.hpp"
#include "bemsurg/solvers/bicgstab.hpp"
#include "bemsurg/solvers/block_jacobi_preconditioner.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bemsurg/solvers/explicit_inverse.hpp"
#include "bemsurg/solvers/gmres.hpp"
#include "bemsurg/solvers/identity_preconditioner.hpp"
#include "bemsurg/solvers/krylov_options.hpp"
#include "bemsurg/solvers/krylov_result.hpp"
#include "bemsurg/solvers/krylov_solver_base.hpp"
#include "bemsurg/solvers/linear_operator.hpp"
#include "bemsurg/solvers/linear_solve.hpp"
#include "bemsurg/solvers/low_rank_updated_lu.hpp"
#include "bemsurg/solvers/lu_factors.hpp"
#include "bemsurg/solvers/lu_in_place.hpp"
#include "bemsurg/solvers/near_field_preconditioner.hpp"
#include "bemsurg/solvers/partitioned_inverse.hpp"
#include "bemsurg/solvers/structured_products.hpp"
#include "bemsurg/solvers/system_factorization.hpp"
