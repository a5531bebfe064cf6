// Implementation of bemsurg/presolution/contact_tools.hpp: tool geometry -> contact rows ->
// capacitance solve, with the unilateral active set (docs/design.md §6; Hertz / Boussinesq checks).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "bemsurg/error.hpp"

namespace bemsurg {

namespace detail {
BEMSURG_INLINE Eigen::Vector3d unit_or_throw(const Eigen::Vector3d& v, const char* what) {
  // stableNorm: components like 1e-200 or 1e200 would underflow / overflow in norm().
  if (!v.allFinite()) throw ContactError(std::string("contact tool: ") + what + " must be a non-zero finite vector");
  const double n = v.stableNorm();
  if (!(n > 0.0) || !std::isfinite(n)) throw ContactError(std::string("contact tool: ") + what + " must be a non-zero finite vector");
  return v / n;
}

// Point in polygon (projected onto the plane with normal m) by the winding/crossing rule.
BEMSURG_INLINE bool inside_polygon(const std::vector<Eigen::Vector3d>& poly, const Eigen::Vector3d& m, const Eigen::Vector3d& x) {
  Eigen::Vector3d e1 = (std::abs(m.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY()).cross(m).normalized();
  const Eigen::Vector3d e2 = m.cross(e1);
  const double px = x.dot(e1), py = x.dot(e2);
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const double xi = poly[i].dot(e1), yi = poly[i].dot(e2), xj = poly[j].dot(e1), yj = poly[j].dot(e2);
    if ((yi > py) != (yj > py) && px < (xj - xi) * (py - yi) / (yj - yi) + xi) in = !in;
  }
  return in;
}
}  // namespace detail

BEMSURG_INLINE const char* to_string(ContactStatus status) noexcept {
  switch (status) {
    case ContactStatus::Ok: return "ok";
    case ContactStatus::Unsettled: return "active set unsettled";
    case ContactStatus::CapacityExceeded: return "contact capacity exceeded";
    case ContactStatus::Singular: return "singular contact system";
    case ContactStatus::NonFinitePose: return "non-finite pose";
  }
  return "?";
}

BEMSURG_INLINE ToolContactSolver::ToolContactSolver(std::shared_ptr<const TriangleMesh> mesh, std::shared_ptr<const GreensTable> table,
                                                    Index capacity_rows)
    : mesh_(mesh),
      table_(table),
      contact_(std::move(mesh), std::move(table), capacity_rows),  // throws for null / mismatched snapshots
      bvh_(deformed_vertices(*mesh_, table_->base_displacement()), mesh_->faces()),
      owner_(static_cast<std::size_t>(mesh_->num_elements()), -1) {
  add_buffer_.reserve(static_cast<std::size_t>(capacity_rows));
}

BEMSURG_INLINE int ToolContactSolver::add_tool(const ToolSpec& spec) {
  if ((spec.shape == ToolShape::FlatPunch || spec.shape == ToolShape::Sphere) && !(spec.radius > 0.0 && std::isfinite(spec.radius)))
    throw ContactError("contact tool: a flat punch or sphere needs a finite positive radius");
  if (spec.shape == ToolShape::Pinch && !(spec.radius >= 0.0 && std::isfinite(spec.radius)))
    throw ContactError("contact tool: the pinch jaw radius must be finite and non-negative");
  if (spec.shape == ToolShape::Plate && (spec.polygon.size() < 3 || !(spec.plate_tolerance > 0.0)))
    throw ContactError("contact tool: a plate needs a polygon of at least 3 vertices and a positive plate_tolerance");
  if (!(spec.slide_margin >= 0.0 && std::isfinite(spec.slide_margin)))
    throw ContactError("contact tool: slide_margin must be finite and non-negative");
  if (spec.shape == ToolShape::Pinch && spec.mode != ContactMode::Bonded)
    throw ContactError("contact tool: a pinch holds the tissue, so it is bonded");
  Tool t;
  t.spec = spec;
  tools_.push_back(std::move(t));
  return static_cast<int>(tools_.size()) - 1;
}

BEMSURG_INLINE void ToolContactSolver::set_translation(int tool, const Eigen::Vector3d& delta) {
  Tool& t = tools_.at(static_cast<std::size_t>(tool));
  if (!delta.allFinite()) throw ContactError("contact tool: set_translation: the translation `delta` is not finite");
  t.delta = delta;
}

BEMSURG_INLINE void ToolContactSolver::set_rotation(int tool, const Eigen::Vector3d& rotation) {
  Tool& t = tools_.at(static_cast<std::size_t>(tool));
  if (!rotation.allFinite()) throw ContactError("contact tool: set_rotation: the rotation vector `rotation` is not finite");
  t.rotation = rotation;
}

BEMSURG_INLINE bool ToolContactSolver::try_set_translation(int tool, const Eigen::Vector3d& delta) noexcept {
  if (tool < 0 || tool >= static_cast<int>(tools_.size()) || !delta.allFinite()) return false;
  tools_[static_cast<std::size_t>(tool)].delta = delta;
  return true;
}

BEMSURG_INLINE bool ToolContactSolver::try_set_rotation(int tool, const Eigen::Vector3d& rotation) noexcept {
  if (tool < 0 || tool >= static_cast<int>(tools_.size()) || !rotation.allFinite()) return false;
  tools_[static_cast<std::size_t>(tool)].rotation = rotation;
  return true;
}

BEMSURG_INLINE void ToolContactSolver::set_depth(int tool, double depth) {
  Tool& t = tools_.at(static_cast<std::size_t>(tool));
  if (!std::isfinite(depth)) throw ContactError("contact tool: set_depth: the depth `depth` is not finite");
  t.delta = depth * t.direction;
}

BEMSURG_INLINE void ToolContactSolver::collect_candidates(Tool& t) {
  t.candidates.clear();
  const Eigen::Matrix<double, 3, 2> box = mesh_->bounding_box();
  const double L = 2.0 * (box.col(1) - box.col(0)).norm() + (t.origin - box.col(0)).norm();
  const double r = t.spec.radius + t.spec.slide_margin;  // the tip, punch or sphere radius (+ slide room)
  const Eigen::Vector3d a = t.origin - L * t.direction, b = t.origin + L * t.direction;
  const Eigen::Vector3d lo = a.cwiseMin(b).array() - r, hi = a.cwiseMax(b).array() + r;
  std::vector<Index> found;
  bvh_.query_box(lo, hi, found);
  for (Index e : found) {
    if (table_->region_slot(e) < 0) continue;
    if (mesh_->normal(e).dot(t.direction) >= 0.0) continue;  // faces away from the tool
    const Eigen::Vector3d x = base_position(e) - t.origin;
    const double rho = (x - x.dot(t.direction) * t.direction).norm();
    if (rho <= r) t.candidates.push_back(e);
  }
}

BEMSURG_INLINE bool ToolContactSolver::engage(int tool, const Eigen::Vector3d& at, const Eigen::Vector3d& direction) {
  Tool& t = tools_.at(static_cast<std::size_t>(tool));
  release(tool);
  t.direction = detail::unit_or_throw(direction, "the approach direction");
  if (!at.allFinite()) throw ContactError("contact tool: the approach point is not finite");
  t.delta.setZero();
  t.rotation.setZero();
  t.candidates.clear();
  t.reach = t.spec.radius;
  const Eigen::Matrix<double, 3, 2> box = mesh_->bounding_box();
  const double L = 2.0 * (box.col(1) - box.col(0)).norm() + (at - box.col(0)).norm();
  switch (t.spec.shape) {
    case ToolShape::Point:
    case ToolShape::Pinch: {
      RayHit hit;
      if (!bvh_.intersect_ray(at - L * t.direction, t.direction, hit, 2.0 * L, true)) return false;
      if (table_->region_slot(hit.element) < 0)
        throw ContactError("contact tool: the tool touches element " + std::to_string(hit.element) + ", outside the table's region");
      t.origin = hit.point;
      t.candidates.push_back(hit.element);
      if (t.spec.shape == ToolShape::Pinch && t.spec.radius > 0.0) {
        std::vector<Index> found;
        const Eigen::Vector3d r = Eigen::Vector3d::Constant(t.spec.radius);
        bvh_.query_box(hit.point - r, hit.point + r, found);
        for (Index e : found)
          if (e != hit.element && table_->region_slot(e) >= 0 && mesh_->normal(e).dot(t.direction) < 0.0 &&
              (base_position(e) - hit.point).norm() <= t.spec.radius)
            t.candidates.push_back(e);
      }
      break;
    }
    case ToolShape::FlatPunch:
    case ToolShape::Sphere: {
      t.origin = at;
      collect_candidates(t);
      if (t.candidates.empty() && t.spec.shape == ToolShape::FlatPunch) {
        // A punch narrower than the elements under it covers no centroid; it still presses the
        // element its axis lands on rather than missing the body.
        RayHit hit;
        if (!bvh_.intersect_ray(at - L * t.direction, t.direction, hit, 2.0 * L, true)) return false;
        if (table_->region_slot(hit.element) < 0) return false;
        const Eigen::Vector3d x = base_position(hit.element) - at;
        t.reach = (1.0 + 1e-9) * (x - x.dot(t.direction) * t.direction).norm();
        t.candidates.push_back(hit.element);
      }
      // A sphere that covers no element centroid (it misses the body, or is narrower than the
      // elements under it) has nothing to push: unlike the flat punch's fallback, the element its
      // axis lands on cannot stand in for it, since the sphere contact moves centroids along their
      // normals onto the sphere and a centroid whose normal line misses the sphere never touches it.
      if (t.candidates.empty()) return false;
      // First contact: the disc face reaches the highest element; the sphere its first element.
      double s0 = std::numeric_limits<double>::infinity();
      for (Index e : t.candidates) {
        const Eigen::Vector3d x = base_position(e) - at;
        const double h = x.dot(t.direction);
        const double rho2 = (x - h * t.direction).squaredNorm();
        const double s = t.spec.shape == ToolShape::FlatPunch ? h : h - std::sqrt(std::max(0.0, t.spec.radius * t.spec.radius - rho2));
        s0 = std::min(s0, s);
      }
      if (!std::isfinite(s0)) {
        t.candidates.clear();
        return false;
      }
      t.origin = at + s0 * t.direction;
      break;
    }
    case ToolShape::Plate: {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (const auto& p : t.spec.polygon) c += p;
      c /= double(t.spec.polygon.size());
      t.origin = c;
      t.pivot = c;
      std::vector<Index> found;
      Eigen::Vector3d lo = c, hi = c;
      for (const auto& p : t.spec.polygon) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      bvh_.query_box(lo.array() - t.spec.plate_tolerance, hi.array() + t.spec.plate_tolerance, found);
      for (Index e : found) {
        const Eigen::Vector3d x = base_position(e);
        if (table_->region_slot(e) < 0) continue;
        if (std::abs((x - c).dot(t.direction)) > t.spec.plate_tolerance) continue;
        if (!detail::inside_polygon(t.spec.polygon, t.direction, x)) continue;
        t.candidates.push_back(e);
      }
      if (t.candidates.empty()) return false;
      break;
    }
  }
  t.released.assign(t.candidates.size(), 0);
  t.wanted.assign(t.candidates.size(), 0);
  t.engaged = true;
  return true;
}

BEMSURG_INLINE void ToolContactSolver::place(int tool, const Eigen::Vector3d& position, const Eigen::Vector3d& direction) {
  Tool& t = tools_.at(static_cast<std::size_t>(tool));
  if (t.spec.shape != ToolShape::FlatPunch && t.spec.shape != ToolShape::Sphere) {
    if (!engage(tool, position, direction))
      throw ContactError("contact tool: the tool placed at the given position does not touch the body");
    return;
  }
  if (!position.allFinite()) throw ContactError("contact tool: place: the position is not finite");
  release(tool);
  t.direction = detail::unit_or_throw(direction, "the tool direction");
  t.origin = position;
  t.reach = t.spec.radius;
  t.delta.setZero();
  t.rotation.setZero();
  collect_candidates(t);
  t.released.assign(t.candidates.size(), 0);
  t.wanted.assign(t.candidates.size(), 0);
  t.engaged = true;
}

BEMSURG_INLINE void ToolContactSolver::release(int tool) {
  Tool& t = tools_.at(static_cast<std::size_t>(tool));
  for (Index e : t.candidates)
    if (owner_[static_cast<std::size_t>(e)] == tool) {
      contact_.remove_element(e);
      owner_[static_cast<std::size_t>(e)] = -1;
    }
  t.engaged = false;
}

BEMSURG_INLINE bool ToolContactSolver::geometric_contact(const Tool& t, Index e, Eigen::Vector3d& push, Eigen::Vector3d& w,
                                                         bool held) const {
  const Eigen::Vector3d n = mesh_->normal(e);
  switch (t.spec.shape) {
    case ToolShape::Point: {
      w = -n;
      push = t.spec.mode == ContactMode::Bonded ? t.delta : Eigen::Vector3d(t.delta.dot(w) * w);
      return t.delta.dot(w) > 0.0;
    }
    case ToolShape::Pinch:
      push = t.delta;
      w = -n;
      return true;
    case ToolShape::FlatPunch: {
      const Eigen::Vector3d x = base_position(e) - t.origin - t.delta;
      const double h = x.dot(t.direction);  // > 0: the element lies beyond the disc face
      const double rho = (x - h * t.direction).norm();
      w = t.direction;
      if (rho > t.reach || h > 0.0) return false;
      const Eigen::Vector3d lateral = t.delta - t.delta.dot(t.direction) * t.direction;
      push = -h * t.direction + (t.spec.mode == ContactMode::Bonded ? lateral : Eigen::Vector3d::Zero());
      return true;
    }
    case ToolShape::Sphere: {
      const Eigen::Vector3d x = base_position(e) - (t.origin + t.delta);
      const double b = n.dot(x);
      const double disc = b * b - x.squaredNorm() + t.spec.radius * t.spec.radius;
      w = -n;
      // In contact when the centroid lies inside the sphere: delta_n < 0 alone also holds for a
      // centroid outside the sphere with the sphere on its -n side (both crossings behind it). Or
      // when the sphere has passed it: the centroid lies in the column the sphere swept since it
      // was engaged or placed (within R of its axis, behind its centre now, not behind where it
      // started). Without this a sphere pressed deeper than 2 R (the CLI refuses that, a haptic
      // device does not) left every centroid behind it and the force dropped to zero
      // (docs/stability.md (h)); now the elements stay on its far side.
      const double r2 = t.spec.radius * t.spec.radius, along = x.dot(t.direction);
      const bool passed = along < 0.0 && x.squaredNorm() - along * along < r2 && (x + t.delta).dot(t.direction) >= -t.spec.radius;
      // A face is taken only while it looks at the sphere (its centre on the face's outer side,
      // b < 0): its centroid then meets the sphere with delta_n = 0 and joins with zero reaction.
      // A face looking away (b > 0: a cut's wall on the tool's side of the groove, whose normal
      // points into the gap, or any steep back face) is reached by the sphere only through the
      // material, and would join with a finite push of -2 b at once: a step of the force in one
      // tick (issue 39, item 4). A face already held stays held as the sphere's centre passes its
      // plane (a press deeper than R, or one dragged sideways there).
      const bool inside = x.squaredNorm() < r2 && (b < 0.0 || held);
      if (disc < 0.0 || !(inside || passed)) return false;
      const double delta_n = -b - std::sqrt(disc);  // normal move (along n) onto the sphere
      if (!(delta_n < 0.0)) return false;
      push = delta_n * n;
      return true;
    }
    case ToolShape::Plate: {
      w = t.direction;
      const Eigen::Vector3d move = t.delta + t.rotation.cross(base_position(e) - t.pivot);
      push = t.spec.mode == ContactMode::Bonded ? move : Eigen::Vector3d(move.dot(w) * w);
      return true;
    }
  }
  return false;
}

BEMSURG_INLINE void ToolContactSolver::set_targets() {
  const Index k = contact_.num_rows();
  const double* ug = table_->base_displacement().data();
  for (Index a = 0; a < k; ++a) {
    const ContactRow& r = contact_.row(a);
    const Tool& t = tools_[static_cast<std::size_t>(r.tag)];
    Eigen::Vector3d push, w;
    geometric_contact(t, r.element, push, w, true);
    const double* u = ug + 3 * r.element;
    contact_.set_target(a, r.direction.dot(Eigen::Vector3d(u[0] + push(0), u[1] + push(1), u[2] + push(2))));
  }
}

BEMSURG_INLINE void ToolContactSolver::add_element_rows(const Tool& t, int tag, Index e, const Eigen::Vector3d& w) {
  if (t.spec.mode == ContactMode::Bonded) {
    add_buffer_.push_back({e, Eigen::Vector3d::UnitX(), tag});
    add_buffer_.push_back({e, Eigen::Vector3d::UnitY(), tag});
    add_buffer_.push_back({e, Eigen::Vector3d::UnitZ(), tag});
  } else {
    add_buffer_.push_back({e, w, tag});
  }
}

BEMSURG_INLINE void ToolContactSolver::rollback_additions() {
  for (const ContactRow& r : add_buffer_) owner_[static_cast<std::size_t>(r.element)] = -1;
  add_buffer_.clear();
}

BEMSURG_INLINE ContactUpdateResult ToolContactSolver::update(int max_iterations) {
  ContactUpdateResult report;
  switch (step(report, max_iterations)) {
    case ContactStatus::CapacityExceeded:
      throw CapacityError("contact tools: the contact set needs at least " + std::to_string(rows_needed_) +
                          " constraint rows, more than the capacity of " + std::to_string(contact_.capacity()) +
                          " (construct the ToolContactSolver with a larger capacity_rows); the contact set is unchanged");
    case ContactStatus::Singular: detail::throw_singular_contact();
    default: break;
  }
  return report;
}

BEMSURG_INLINE void ToolContactSolver::remove_unwanted_rows() {
  // Marks which candidates each engaged tool wants now and removes the rows of those it no longer
  // wants (first, so that the capacity they free is there for the additions).
  for (std::size_t ti = 0; ti < tools_.size(); ++ti) {
    Tool& t = tools_[ti];
    if (!t.engaged) continue;
    const int tag = static_cast<int>(ti);
    for (std::size_t i = 0; i < t.candidates.size(); ++i) {
      const Index e = t.candidates[i];
      int& owner = owner_[static_cast<std::size_t>(e)];
      Eigen::Vector3d push, w;
      const bool geo = geometric_contact(t, e, push, w, owner == tag);
      if (!geo) t.released[i] = 0;  // out of reach: forget an old release
      const bool want = geo && !t.released[i];
      t.wanted[i] = want ? 1 : 0;
      if (owner == tag && !want) {
        contact_.remove_element(e);
        owner = -1;
      }
    }
  }
}

BEMSURG_INLINE bool ToolContactSolver::gather_additions() {
  // The rows of wanted elements that no tool holds yet, into add_buffer_ (committed by the caller
  // in one add_rows); each element is claimed at once so that no other tool adds it too.
  const Index free_rows = contact_.capacity() - contact_.num_rows();
  for (std::size_t ti = 0; ti < tools_.size(); ++ti) {
    Tool& t = tools_[ti];
    if (!t.engaged) continue;
    const int tag = static_cast<int>(ti);
    for (std::size_t i = 0; i < t.candidates.size(); ++i) {
      if (!t.wanted[i]) continue;
      const Index e = t.candidates[i];
      int& owner = owner_[static_cast<std::size_t>(e)];
      if (owner != -1) continue;  // already in contact (with this tool or another)
      const Index need = t.spec.mode == ContactMode::Bonded ? 3 : 1;
      if (static_cast<Index>(add_buffer_.size()) + need > free_rows) {
        rows_needed_ = contact_.num_rows() + static_cast<Index>(add_buffer_.size()) + need;
        rollback_additions();
        return false;
      }
      Eigen::Vector3d push, w;
      geometric_contact(t, e, push, w, false);
      add_element_rows(t, tag, e, w);
      owner = tag;  // claimed; rolled back if add_rows fails
    }
  }
  return true;
}

BEMSURG_INLINE bool ToolContactSolver::release_tension() {
  // Unilateral tools only push: an element whose contact traction pulls (beyond round-off of the
  // largest multiplier) is released. True when any was.
  double scale = 0.0;
  for (Index a = 0; a < contact_.num_rows(); ++a) scale = std::max(scale, std::abs(contact_.multiplier(a)));
  const double tol = 1e-10 * scale;
  bool released_any = false;
  for (std::size_t ti = 0; ti < tools_.size(); ++ti) {
    Tool& t = tools_[ti];
    if (!t.engaged || !unilateral(t)) continue;
    for (std::size_t i = 0; i < t.candidates.size(); ++i) {
      const Index e = t.candidates[i];
      if (owner_[static_cast<std::size_t>(e)] != static_cast<int>(ti)) continue;
      const Eigen::Vector3d tr = contact_.traction(e) - table_->base_traction().segment<3>(3 * e);
      if (tr.dot(mesh_->normal(e)) > tol) {
        t.released[i] = 1;
        released_any = true;
      }
    }
  }
  return released_any;
}

BEMSURG_INLINE bool ToolContactSolver::readmit_penetrating() {
  // A released element that the tool still reaches and that lags behind it (the tool would
  // penetrate) comes back. True when any did.
  bool readmitted = false;
  for (std::size_t ti = 0; ti < tools_.size(); ++ti) {
    Tool& t = tools_[ti];
    if (!t.engaged || !unilateral(t)) continue;
    for (std::size_t i = 0; i < t.candidates.size(); ++i) {
      if (!t.released[i]) continue;
      const Index e = t.candidates[i];
      Eigen::Vector3d push, w;
      if (!geometric_contact(t, e, push, w, false)) continue;
      const Eigen::Vector3d moved = contact_.displacement_of(e) - table_->base_displacement().segment<3>(3 * e);
      // Penetration: the element has not moved as far into the body as the tool demands.
      const double need = push.dot(w);
      if (moved.dot(w) < need - 1e-9 * std::abs(need)) {
        t.released[i] = 0;
        readmitted = true;
      }
    }
  }
  return readmitted;
}

BEMSURG_INLINE ContactStatus ToolContactSolver::step(ContactUpdateResult& report, int max_iterations) noexcept {
  report = ContactUpdateResult{};
  report.consistent = false;
  ContactStatus failed = ContactStatus::Ok;
  for (int iter = 0; iter < std::max(1, max_iterations); ++iter) {
    report.active_set_iterations = iter + 1;
    // 1. Bring the rows in line with the geometry and the released flags: first every removal
    //    (it frees capacity), then the additions, committed in one add_rows. A failure (capacity
    //    exceeded, singular S) rolls the new elements' ownership back, so the solver stays
    //    consistent with the contact set and a later update() starts from there.
    add_buffer_.clear();
    remove_unwanted_rows();
    if (!gather_additions()) {
      failed = ContactStatus::CapacityExceeded;
      break;
    }
    if (!contact_.try_add_rows(add_buffer_.data(), static_cast<Index>(add_buffer_.size()))) {
      rollback_additions();
      failed = ContactStatus::Singular;
      break;
    }
    // 2. Targets from the poses, then the small solve.
    set_targets();
    contact_.solve();
    // 3. Active set of unilateral tools: release tension; re-admit released elements that would
    //    penetrate. One kind of change per iteration, so the two cannot undo each other at once.
    if (release_tension()) continue;
    if (!readmit_penetrating()) {
      report.consistent = true;
      break;
    }
  }
  report.rows = contact_.num_rows();
  report.elements = contact_.num_elements();
  if (failed != ContactStatus::Ok) return failed;
  return report.consistent ? ContactStatus::Ok : ContactStatus::Unsettled;
}

BEMSURG_INLINE Index ToolContactSolver::contact_elements(int tool) const {
  Index count = 0;
  for (Index e : tools_.at(static_cast<std::size_t>(tool)).candidates)
    if (owner_[static_cast<std::size_t>(e)] == tool) ++count;
  return count;
}

BEMSURG_INLINE void ToolContactSolver::contact_element_list(int tool, std::vector<Index>& out) const {
  for (Index e : tools_.at(static_cast<std::size_t>(tool)).candidates)
    if (owner_[static_cast<std::size_t>(e)] == tool) out.push_back(e);
}

}  // namespace bemsurg
