// examples/viewer/tool_stepper.cpp: the viewer's haptic tick (see tool_stepper.hpp).
#include "tool_stepper.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>

#include "bemsurg/error.hpp"

namespace bemsurg::viewer {

double default_tool_radius(ToolKind k, double edge) {
  switch (k) {
    case ToolKind::Sphere: return 1.5 * edge;  // covers a few centroids: a resolved Hertz-like contact
    case ToolKind::Flat: return 1.0 * edge;
    case ToolKind::Pinch: return 0.6 * edge;  // the element hit and its nearest neighbours
    default: return 0.0;
  }
}

double default_plate_size(double edge) { return 1.5 * edge; }

ToolStepper::ToolStepper() = default;

namespace {

void set_message(ContactSnapshot& out, const std::string& m) {
  const std::size_t n = std::min(m.size(), out.message.size() - 1);
  std::memcpy(out.message.data(), m.data(), n);
  out.message[n] = '\0';
}

}  // namespace

bool ToolStepper::engage(Slot& s, const SlotOptions& want, const haptics::DeviceState& d, std::string& why) {
  const PhysicsState& ph = *physics_;
  const double edge = ph.mean_edge;
  const double radius = want.radius > 0.0 ? want.radius : default_tool_radius(want.kind, edge);
  const double plate = want.plate_size > 0.0 ? want.plate_size : default_plate_size(edge);
  Eigen::Vector3d dir = d.direction;
  if (!(dir.norm() > 0.0) || !dir.allFinite() || !d.position.allFinite()) {
    why = "the device pose is not finite";
    return false;
  }
  dir.normalize();
  // First contact on the base-state surface along the approach line (as ToolContactSolver does).
  const Eigen::Matrix<double, 3, 2> box = ph.mesh->bounding_box();
  const double L = 2.0 * (box.col(1) - box.col(0)).norm() + (d.position - box.col(0)).norm();
  RayHit hit;
  const bool script_plate = want.kind == ToolKind::Plate && !want.polygon.empty();
  if (!script_plate && !solver_->base_surface().intersect_ray(d.position - L * dir, dir, hit, 2.0 * L, true)) {
    why = "the tool's line misses the body";
    return false;
  }
  ToolSpec spec;
  Eigen::Vector3d origin = hit.point;
  const bool frictionless = want.frictionless_given ? want.frictionless : (want.kind == ToolKind::Sphere || want.kind == ToolKind::Flat);
  const ContactMode mode = frictionless ? ContactMode::Frictionless : ContactMode::Bonded;
  switch (want.kind) {
    case ToolKind::Point: spec = ToolSpec::point(mode); break;
    case ToolKind::Sphere:
      spec = ToolSpec::sphere(radius, mode);
      origin = hit.point - radius * dir;  // the sphere rests on the hit point
      break;
    case ToolKind::Flat: spec = ToolSpec::flat(radius, mode); break;
    case ToolKind::Pinch: spec = ToolSpec::pinch(radius); break;
    case ToolKind::Plate: {
      if (!want.polygon.empty()) {
        // A script's plate: its own outline, engaged where it is (docs/actions.md).
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (const auto& p : want.polygon) c += p;
        origin = c / double(want.polygon.size());
        spec = ToolSpec::plate(want.polygon, want.plate_tolerance > 0.0 ? want.plate_tolerance : 0.5 * edge);
        break;
      }
      // A square retractor plate across the approach direction, gripping what it touches.
      Eigen::Vector3d a = dir.unitOrthogonal(), b = dir.cross(a);
      std::vector<Eigen::Vector3d> poly = {hit.point + plate * (a + b), hit.point + plate * (-a + b), hit.point + plate * (-a - b),
                                           hit.point + plate * (a - b)};
      spec = ToolSpec::plate(std::move(poly), 0.5 * edge);
      break;
    }
    case ToolKind::Cut: why = "the cut tool does not press"; return false;
  }
  // Reuse the slot's tool while its shape is unchanged (a plate carries its polygon: new each time).
  if (s.tool < 0 || s.kind != want.kind || s.radius != radius || s.frictionless != frictionless || want.kind == ToolKind::Plate)
    s.tool = solver_->add_tool(spec);
  s.kind = want.kind;
  s.radius = radius;
  s.frictionless = frictionless;
  s.spec = spec;
  s.plate_size = plate;
  bool ok = true;
  if (want.kind == ToolKind::Sphere || want.kind == ToolKind::Flat)
    solver_->place(s.tool, origin, dir);
  else
    ok = solver_->engage(s.tool, origin, dir);
  if (!ok) {
    why = std::string("the ") + tool_kind_name(want.kind) + " finds nothing to hold there";
    return false;
  }
  s.engaged = true;
  s.engage_position = d.position;
  s.origin = origin;
  s.direction = dir;
  s.translation.setZero();
  return true;
}

bool ToolStepper::reengage(Slot& s) {
  s.tool = solver_->add_tool(s.spec);
  if (s.kind == ToolKind::Sphere || s.kind == ToolKind::Flat) {
    solver_->place(s.tool, s.origin, s.direction);
  } else if (!solver_->engage(s.tool, s.origin, s.direction)) {
    return false;
  }
  return solver_->try_set_translation(s.tool, s.translation);
}

bool ToolStepper::takes_over(const std::shared_ptr<const PhysicsState>& physics) const {
  if (physics == physics_) return false;
  // A cut's provisional state (the new surface, no tables yet) leaves the tools on the uncut model,
  // which stays a valid linear model of the tissue until the exact tables of the cut arrive.
  const bool provisional = physics && !physics->table && physics_ && physics_->table && solver_ &&
                           physics->model_name == physics_->model_name && physics->cuts > physics_->cuts;
  return !provisional;
}

void ToolStepper::follow_model(const std::shared_ptr<const PhysicsState>& physics, double time, double blend_s) {
  // A new model, table or parameter set (a cut, E, nu, gravity): a new solver on the new
  // snapshots; tools held through the change are engaged again where they were, at the same
  // translation, so a cut under a held probe keeps the probe in the tissue. The old solver stays
  // for the blend (the same model only: a new scene switches at once).
  const bool blend = blend_s > 0.0 && solver_ && physics && physics->table && physics_ && physics_->model_name == physics->model_name;
  previous_solver_.reset();
  previous_physics_.reset();
  if (blend) {
    previous_physics_ = physics_;
    previous_solver_ = std::move(solver_);
    for (std::size_t i = 0; i < slots_.size(); ++i) previous_tool_[i] = slots_[i].engaged ? slots_[i].tool : -1;
    blend_.set_duration(blend_s);
    blend_.start(time);
  }
  physics_ = physics;
  solver_.reset();
  if (physics_ && physics_->table) {
    const Index cap = std::max<Index>(300, 3 * physics_->mesh->num_elements() / 4);
    solver_ = std::make_unique<ToolContactSolver>(physics_->mesh, physics_->table, std::min<Index>(cap, 1500));
  }
  for (auto& s : slots_) {
    const bool was = s.engaged;
    s.engaged = false;
    s.tool = -1;
    if (!was) continue;
    bool ok = false;
    if (solver_) {
      try {
        ok = reengage(s);
      } catch (const std::exception& e) { message_ = std::string("re-engaging after the model changed: ") + e.what(); }
    }
    s.engaged = ok;
    s.missed = !ok && s.button;  // a tool that could not follow waits for its button's release
  }
}

void ToolStepper::follow_device(int i, haptics::HapticDevice* dev, const SlotOptions& want, double time) {
  // The button's edges engage and release the slot's tool; while engaged it follows the device.
  Slot& s = slots_[static_cast<std::size_t>(i)];
  const haptics::DeviceState d = dev ? dev->read(time) : haptics::DeviceState{};
  const bool button = d.button(0) && d.connected;
  if (!solver_) {
    s.button = button;
    return;
  }
  try {
    if (button != s.button) previous_tool_[static_cast<std::size_t>(i)] = -1;  // a new engagement or a release: not blended
    if (button && !s.button && want.kind != ToolKind::Cut) {
      std::string why;
      s.missed = !engage(s, want, d, why);
      if (s.missed) message_ = "tool " + std::to_string(i + 1) + ": " + why;
    } else if (!button && s.button) {
      if (s.engaged) solver_->release(s.tool);
      s.engaged = false;
      s.missed = false;
    }
    if (s.engaged) {
      const Eigen::Vector3d tr = d.position - s.engage_position;
      if (solver_->try_set_translation(s.tool, tr)) s.translation = tr;
    }
  } catch (const std::exception& e) {
    message_ = "tool " + std::to_string(i + 1) + ": " + e.what();
    if (s.engaged) solver_->release(s.tool);
    s.engaged = false;
    s.missed = true;
  }
  s.button = button;
}

void ToolStepper::step_contact() {
  if (!solver_) return;
  // The never-throwing step: a failed step leaves the contact set (and force) of the last good one.
  ContactUpdateResult report;
  const ContactStatus status = solver_->step(report);
  if (status == ContactStatus::CapacityExceeded)
    message_ = "the contact set needs " + std::to_string(solver_->rows_needed()) +
               " constraint rows, more than reserved: the force is the last good one";
  else if (status != ContactStatus::Ok)
    message_ = std::string("contact: ") + to_string(status);
}

void ToolStepper::step_previous() {
  // The blended-out model: each tool still held follows the device as in the new one.
  previous_force_.fill(Eigen::Vector3d::Zero());
  if (!previous_solver_) return;
  for (std::size_t i = 0; i < slots_.size(); ++i)
    if (previous_tool_[i] >= 0 && slots_[i].engaged) previous_solver_->try_set_translation(previous_tool_[i], slots_[i].translation);
  ContactUpdateResult report;
  if (previous_solver_->step(report) != ContactStatus::Ok) return;  // a failed step: the new model alone
  for (std::size_t i = 0; i < slots_.size(); ++i)
    if (previous_tool_[i] >= 0 && slots_[i].engaged && previous_solver_->engaged(previous_tool_[i]))
      previous_force_[i] = previous_solver_->force(previous_tool_[i]);
}

void ToolStepper::send_force(int i, haptics::HapticDevice* dev, const StepperOptions& settings, double dt, double weight, SlotSnapshot& o) {
  // The slot's state for the graphics thread, and its force to the device.
  Slot& s = slots_[static_cast<std::size_t>(i)];
  o.engaged = s.engaged;
  o.missed = s.missed;
  o.kind = s.kind;
  o.radius = s.radius;
  o.plate_size = s.plate_size;
  o.direction = s.direction;
  o.tip = s.origin + s.translation;
  o.force = (solver_ && s.engaged) ? solver_->force(s.tool) : Eigen::Vector3d::Zero();
  o.contact_elements = (solver_ && s.engaged) ? solver_->contact_elements(s.tool) : 0;
  if (!o.force.allFinite()) o.force = s.force;  // never hand a NaN on
  s.force = o.force;
  // The device gets the force limited in magnitude and in rate of change (haptics/force_limiter.hpp).
  if (s.limit != settings.force_limit || s.rate != settings.force_rate) {
    s.limit = settings.force_limit;
    s.rate = settings.force_rate;
    s.limiter = haptics::ForceLimiter(s.limit, s.rate);
  }
  Eigen::Vector3d wanted = o.force;
  if (previous_solver_ && weight < 1.0 && previous_force_[static_cast<std::size_t>(i)].allFinite())
    wanted = haptics::ModelCrossfade::mix(previous_force_[static_cast<std::size_t>(i)], o.force, weight);
  const Eigen::Vector3d limited = s.limiter(wanted, dt);
  o.sent_force = settings.haptic_force ? limited : Eigen::Vector3d::Zero();
  if (dev) dev->write_force(o.sent_force);
}

void ToolStepper::tick(const std::shared_ptr<const PhysicsState>& physics, haptics::HapticDevice* const* devices,
                       const StepperOptions& settings, double time, double dt, ContactSnapshot& out) {
  const auto t0 = std::chrono::steady_clock::now();
  if (takes_over(physics)) follow_model(physics, time, settings.blend_s);
  out.physics_version = physics_ ? physics_->version : 0;
  for (int i = 0; i < kMaxTools; ++i) follow_device(i, devices[i], settings.slots[static_cast<std::size_t>(i)], time);
  step_contact();
  const double weight = previous_solver_ ? blend_.weight(time) : 1.0;
  if (weight < 1.0) step_previous();
  out.blend_weight = weight;
  // Snapshot for the graphics thread.
  out.count = 0;
  for (int i = 0; i < kMaxTools; ++i) send_force(i, devices[i], settings, dt, weight, out.slots[static_cast<std::size_t>(i)]);
  if (previous_solver_ && weight >= 1.0) {  // the blend is over
    previous_solver_.reset();
    previous_physics_.reset();
  }
  if (solver_) {
    const CapacitanceContact& c = solver_->contact();
    const std::size_t need = static_cast<std::size_t>(c.num_elements());
    if (out.elements.size() < need) {
      out.elements.resize(std::max<std::size_t>(need, 512));
      out.tractions.resize(3 * out.elements.size());
    }
    out.count = c.contact_tractions(out.elements.data(), out.tractions.data());
  }
  set_message(out, message_);
  out.force_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace bemsurg::viewer
