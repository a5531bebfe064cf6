// bemsurg/cutting/table_update.hpp: the exact Green's table of a cut body, from the table before the
// cut and the rows and columns the step changed (docs/cutting.md; docs/design.md §7, §9; Wang et al.
// 2007 §5.3, eqs. 11-13).
//
// updated_table returns a NEW table (an immutable snapshot, version() + 1) for the cut mesh whose
// base state and columns equal those computed from scratch (recomputed_table_after, the reference),
// integrating only the rows and columns of the changed elements: bordering by partitioning for the
// added elements and a low-rank (Woodbury) correction for the reshaped ones, on top of the LU the
// table kept. The rules of a cut — the conditions after it (conditions_after_cut) and the region
// after it (region_after_cut) — are stated here once; CutSystemUpdate (cut_system_update.hpp) is the
// one entry point that the command line, sessions and the viewer use.
#pragma once

#include <memory>
#include <vector>

#include "bemsurg/cutting/cut_change.hpp"
#include "bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/snapshot_buffers.hpp"

namespace bemsurg {

/// How a cut step's table update treats the region where tools may act.
/// \ingroup cutting
struct GreensTableUpdateOptions {
  /// New (cut-wall) elements join the region when the region holds every free element, or when
  /// their centroid lies within this distance of a region element's centroid. 0: three times the
  /// largest diameter among the step's changed elements.
  double join_distance = 0.0;
  /// Where the new tables' columns are stored: buffers that earlier tables of the chain let go of
  /// (snapshot_buffers.hpp; their pages already touched, docs/cutting.md "Snapshot storage"). Null:
  /// fresh memory for every table. CutSystemUpdate gives its steps one pool.
  std::shared_ptr<SnapshotBufferPool> buffers;
};

/// Wall-clock seconds of one table update after a cut step, by phase, and what it left. The profile
/// below splits the system and table phases by the kind of work (docs/cutting.md, "Where a step's time
/// goes"). total_seconds: system + table, and integration too when updated_table integrated the change
/// itself. A CutTableStep's reports repeat the system phase, which its construction took once.
/// \ingroup cutting
struct GreensTableUpdateResult {
  double integration_seconds = 0.0;  // rows and columns of the changed elements, both meshes
  double system_seconds = 0.0;       // low-rank update of the factorisation and the base state
  double table_seconds = 0.0;        // the table's columns (old ones corrected, new ones solved)
  double total_seconds = 0.0;
  // The profile of the system and table phases.
  double change_seconds = 0.0;      // the step's terms X, U_s, V_s, the new right-hand side and the fresh columns' right-hand sides
  double solve_seconds = 0.0;       // LU triangular solves (one multi-right-hand-side dgetrs)
  Index solve_columns = 0;          // right-hand sides that went through the LU
  double correction_seconds = 0.0;  // the accumulated rank: V, W and the capacitance grown, Woodbury finish of the solves
  double snapshot_seconds = 0.0;    // the new table's matrix allocated and the old columns copied in (first touches)
  double gemm_seconds = 0.0;        // the table's products: X T and the Woodbury term (one GEMM each)
  double finish_seconds = 0.0;      // fresh columns placed, finiteness check, reaction rows and slots
  double table_gemm_flops = 0.0;    // flops of those two products, 2 n (3|R0|) d + 2 n' (2d) (3|R0|)
  std::size_t snapshot_bytes = 0;   // the new table's columns
  Index rank = 0;                   // accumulated rank of the correction after the step
  Index added_region_elements = 0;  // new elements that joined the region
};
/// Deprecated name (before 0.2), kept one minor version: use GreensTableUpdateResult.
using GreensTableUpdateReport [[deprecated("renamed to GreensTableUpdateResult in bemsurg 0.2")]] = GreensTableUpdateResult;

/// The region after a cut step: `table`'s region in its slots, then the added elements that join it
/// (GreensTableUpdateOptions::join_distance).
std::vector<Index> region_after_cut(const GreensTable& table, const TriangleMesh& after, const MeshDelta& delta,
                                    const GreensTableUpdateOptions& options = {});

/// The exact table of the cut mesh `after` (a new snapshot, version() + 1): `delta` says what changed
/// (mesh/mesh_delta.hpp). Modified elements keep their boundary condition, added ones are traction-free
/// (conditions_after_cut); the region keeps its elements in their slots and appends the added elements
/// near it (region_after_cut). Cost: the rows and columns of the changed elements are integrated anew,
/// 2 n^2 (2|M| + |N|) x 3 flops of LU solves plus GEMMs of the table against the step's rank
/// (docs/cutting.md). Throws InvalidArgumentError for a delta that does not fit (or removes elements) or
/// a table without factorisation, SolverError when the cut system is singular. `table` is not changed.
std::shared_ptr<const GreensTable> updated_table(const GreensTable& table, std::shared_ptr<const TriangleMesh> after,
                                                 const MeshDelta& delta, const GreensTableUpdateOptions& options = {},
                                                 GreensTableUpdateResult* report = nullptr);

/// The same step taken with the rows and columns already integrated (integrate_cut_change on the
/// table's mesh, `after`, its material, quadrature and gravity), e.g. shared with an iterative
/// re-solve of the same step.
std::shared_ptr<const GreensTable> updated_table(const GreensTable& table, std::shared_ptr<const TriangleMesh> after,
                                                 const MeshDelta& delta, const CutChange& change,
                                                 const GreensTableUpdateOptions& options = {}, GreensTableUpdateResult* report = nullptr);

namespace detail {
struct CutStepState;
}

/// One exact table update after a cut step, taken in two phases (docs/cutting.md, "First response";
/// issue 39). The constructor takes the step's cheap parts (conditions, region, right-hand sides).
/// first_response(reach) then makes exact only the columns of the region elements listed (a table whose
/// region is those elements, in the complete table's order), for the tools' neighbourhood: it takes the
/// system's low-rank update (the LU solves of U_s, Z = A'^-1 U_s, and of the base state) and solves
/// only the fresh columns (reshaped or joining elements) within the reach. complete() solves the fresh
/// columns left and makes the whole table, equal to updated_table's. Both are new immutable snapshots
/// (version() + 1) sharing the step's solver; either may be called any number of times, from one
/// thread at a time (a call solves what earlier calls left). The step holds the table before it, the
/// change and the solves (about n' x (2d + fresh columns) doubles) until it is destroyed.
/// \ingroup cutting
class CutTableStep {
 public:
  /// `change`: integrate_cut_change on the table's mesh, `after`, its material, quadrature and gravity.
  /// Throws as updated_table does.
  CutTableStep(std::shared_ptr<const GreensTable> table, std::shared_ptr<const TriangleMesh> after, const MeshDelta& delta,
               CutChange change, const GreensTableUpdateOptions& options = {});
  /// The region after the step: the complete table's elements, in its slots.
  const std::vector<Index>& region() const;
  /// Integration (as the change says) and the system phase with its profile: the solves taken so far.
  const GreensTableUpdateResult& result() const;
  /// A table over the region elements in `reach` (others ignored; any order): exact for them. `report`
  /// gets the system phase as result() after this call's solves, and this table's phase.
  std::shared_ptr<const GreensTable> first_response(const std::vector<Index>& reach, GreensTableUpdateResult* report = nullptr) const;
  /// The complete table (updated_table's result), made once: a later call, or a first response whose
  /// reach covers the whole region, returns the same snapshot (and the report of its making).
  std::shared_ptr<const GreensTable> complete(GreensTableUpdateResult* report = nullptr) const;

 private:
  std::shared_ptr<detail::CutStepState> state_;  // its solves grow as the phases ask for them
};

/// The reach rule of a first response: the elements of `region` whose centroid lies within `reach` of
/// any of the `tools` positions (e.g. the tool's radius plus the distance it can travel before the
/// step completes). Throws InvalidArgumentError for a negative or non-finite reach or position.
std::vector<Index> elements_within_reach(const TriangleMesh& mesh, const std::vector<Index>& region,
                                         const std::vector<Eigen::Vector3d>& tools, double reach);

/// The reference for updated_table: the same step by full re-assembly and a new factorisation (same
/// rules, version() + 1).
std::shared_ptr<const GreensTable> recomputed_table_after(const GreensTable& table, std::shared_ptr<const TriangleMesh> after,
                                                          const MeshDelta& delta, const GreensTableUpdateOptions& options = {});

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/cutting/impl/cut_table_step_impl.hpp"
#include "bemsurg/cutting/impl/table_update_impl.hpp"
#endif
