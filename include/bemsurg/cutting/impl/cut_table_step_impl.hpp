// Implementation of bemsurg/cutting/table_update.hpp, continued: the region and reach rules, CutTableStep's
// phases and the entry points (docs/cutting.md, "First response"), on top of detail::GreensTableParts
// (table_update_impl.hpp).
#pragma once

#include "bemsurg/config.hpp"

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "bemsurg/cutting/impl/table_update_impl.hpp"
#include "bemsurg/cutting/table_update.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

BEMSURG_INLINE std::vector<Index> region_after_cut(const GreensTable& g, const TriangleMesh& after, const MeshDelta& delta,
                                                   const GreensTableUpdateOptions& options) {
  std::vector<Index> region = g.region();
  Index free_count = 0;
  for (Index e = 0; e < g.num_elements(); ++e) free_count += g.is_free(e) ? 1 : 0;
  const bool all_free = free_count == static_cast<Index>(g.region().size());
  double reach = options.join_distance;
  if (!(reach > 0.0)) {
    double largest = 0.0;
    for (Index e : delta.changed())
      if (e >= 0 && e < after.num_elements()) largest = std::max(largest, after.diameter(e));
    reach = 3.0 * largest;
  }
  for (Index e : delta.added) {  // new cut surface: traction-free, so a tool may act on it
    if (e < 0 || e >= after.num_elements()) continue;
    bool join = all_free;
    for (std::size_t s = 0; !join && s < g.region().size(); ++s)
      join = (after.centroid(e) - after.centroid(g.region()[s])).squaredNorm() <= reach * reach;
    if (join) region.push_back(e);
  }
  return region;
}

BEMSURG_INLINE std::vector<Index> elements_within_reach(const TriangleMesh& mesh, const std::vector<Index>& region,
                                                        const std::vector<Eigen::Vector3d>& tools, double reach) {
  std::vector<Index> out;
  if (!(reach >= 0.0) || !std::isfinite(reach))
    throw InvalidArgumentError("elements_within_reach: the reach must be finite and not negative, got " + number_text(reach));
  for (const Eigen::Vector3d& p : tools)
    if (!p.allFinite()) throw InvalidArgumentError("elements_within_reach: a tool position is not finite");
  for (Index e : region) {
    if (e < 0 || e >= mesh.num_elements())
      throw InvalidArgumentError("elements_within_reach: region element " + std::to_string(e) + " is not on the mesh");
    for (const Eigen::Vector3d& p : tools)
      if ((mesh.centroid(e) - p).squaredNorm() <= reach * reach) {
        out.push_back(e);
        break;
      }
  }
  return out;
}

BEMSURG_INLINE CutTableStep::CutTableStep(std::shared_ptr<const GreensTable> table, std::shared_ptr<const TriangleMesh> after,
                                          const MeshDelta& delta, CutChange change, const GreensTableUpdateOptions& options) {
  if (!table) throw InvalidArgumentError("CutTableStep: no table");
  detail::GreensTableParts::check_update(*table, after.get(), delta, change);
  auto s = std::make_shared<detail::CutStepState>();
  s->keep_before = std::move(table);
  s->before = s->keep_before.get();
  s->keep_change = std::make_shared<const CutChange>(std::move(change));
  s->change = s->keep_change.get();
  s->after = std::move(after);
  s->delta = delta;
  detail::GreensTableParts::prepare(*s, options);
  state_ = std::move(s);
}

BEMSURG_INLINE const std::vector<Index>& CutTableStep::region() const { return state_->region; }

BEMSURG_INLINE const GreensTableUpdateResult& CutTableStep::result() const { return state_->timing; }

BEMSURG_INLINE std::shared_ptr<const GreensTable> CutTableStep::first_response(const std::vector<Index>& reach,
                                                                               GreensTableUpdateResult* report) const {
  std::vector<char> wanted(static_cast<std::size_t>(state_->after->num_elements()), 0);
  for (Index e : reach) {
    if (e < 0 || e >= state_->after->num_elements())
      throw InvalidArgumentError("CutTableStep::first_response: element " + std::to_string(e) + " is not on the cut mesh");
    wanted[static_cast<std::size_t>(e)] = 1;
  }
  std::vector<Index> slots;
  for (std::size_t s = 0; s < state_->region.size(); ++s)
    if (wanted[static_cast<std::size_t>(state_->region[s])]) slots.push_back(static_cast<Index>(s));
  // Over an explicit inverse, and before the completion has solved: exact on the rows within reach
  // only (docs/cutting.md, "First response on the rows within reach"), even when the reach covers
  // the whole region (its rows are still fewer than the body's).
  if (state_->before->solver()->has_rows() && !state_->solver) return detail::GreensTableParts::rows_table_of(*state_, slots, report);
  if (slots.size() < state_->region.size()) return detail::GreensTableParts::table_of(*state_, &slots, report);
  // Over the LU, a reach that covers the whole region (a small operating region, a large tool) asks
  // for the complete table: made once, and complete() hands out the same snapshot.
  return complete(report);
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> CutTableStep::complete(GreensTableUpdateResult* report) const {
  if (!state_->complete) state_->complete = detail::GreensTableParts::table_of(*state_, nullptr, &state_->complete_report);
  if (report) *report = state_->complete_report;
  return state_->complete;
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> updated_table(const GreensTable& table, std::shared_ptr<const TriangleMesh> after,
                                                                const MeshDelta& delta, const GreensTableUpdateOptions& options,
                                                                GreensTableUpdateResult* report) {
  return detail::GreensTableParts::updated(table, std::move(after), delta, options, report);
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> updated_table(const GreensTable& table, std::shared_ptr<const TriangleMesh> after,
                                                                const MeshDelta& delta, const CutChange& change,
                                                                const GreensTableUpdateOptions& options, GreensTableUpdateResult* report) {
  return detail::GreensTableParts::updated(table, std::move(after), delta, change, options, report);
}

BEMSURG_INLINE std::shared_ptr<const GreensTable> recomputed_table_after(const GreensTable& table,
                                                                         std::shared_ptr<const TriangleMesh> after, const MeshDelta& delta,
                                                                         const GreensTableUpdateOptions& options) {
  return detail::GreensTableParts::recomputed_after(table, std::move(after), delta, options);
}

}  // namespace bemsurg
