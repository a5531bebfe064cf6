// examples/viewer/viewer_app.cpp: window, GUI, mouse device, haptic thread, headless playback
// (see viewer_app.hpp and docs/viewer.md).
#include "viewer_app.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <imgui.h>
#include <imgui_stdlib.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <stb_image_write.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "script_player.hpp"
#include "bemsurg/io/action_script.hpp"
#include "bemsurg/haptics/scripted_device.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/haptics/haptic_device.hpp"
#include "bemsurg/haptics/triple_buffer.hpp"
#include "bemsurg/mesh/bvh.hpp"
#include "cut_session.hpp"
#include "model_worker.hpp"
#include "renderer.hpp"
#include "tool_stepper.hpp"

namespace bemsurg::viewer {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Events per second over a sliding second.
class RateCounter {
 public:
  void tick() {
    ++count_;
    const double dt = seconds_since(start_);
    if (dt >= 0.5) {
      rate_.store(count_ / dt, std::memory_order_relaxed);
      count_ = 0;
      start_ = Clock::now();
    }
  }
  double rate() const { return rate_.load(std::memory_order_relaxed); }

 private:
  long count_ = 0;
  Clock::time_point start_ = Clock::now();
  std::atomic<double> rate_{0.0};
};

/// A session recorded from the mouse, written as an action script (docs/viewer.md).
struct Recorder {
  bool on = false;
  Clock::time_point start = Clock::now();
  nlohmann::json actions = nlohmann::json::array();
  nlohmann::json tools = nlohmann::json::array();
  double last_move = -1.0;
  double now() const { return seconds_since(start); }
  std::string tool_name(int slot, ToolKind k, double radius) {
    const std::string name = "tool" + std::to_string(slot + 1) + "-" + tool_kind_name(k) + "-" +
                             std::to_string(static_cast<long>(std::lround(radius * 1e5)));
    for (const auto& t : tools)
      if (t["name"] == name) return name;
    nlohmann::json t = {{"name", name}, {"shape", tool_kind_name(k)}, {"device", slot}};
    if (radius > 0.0) t["radius"] = radius;
    tools.push_back(t);
    return name;
  }
  bool save(const std::string& path, const std::string& scene, std::string& error) const {
    nlohmann::json root = {{"format", "bemsurg-actions"}, {"version", 1}, {"tools", tools}, {"actions", actions}};
    if (!scene.empty()) root["scene"] = scene;
    std::ofstream out(path);
    if (!out) {
      error = "cannot write " + path;
      return false;
    }
    out << std::setw(2) << root << "\n";
    return true;
  }
};

nlohmann::json vec_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

/// Everything the frame needs to draw the deformed model; built by the graphics thread.
struct FrameField {
  std::uint64_t version = 0;
  std::shared_ptr<const PhysicsState> physics;
  Eigen::VectorXd u;                // element displacements (3E)
  RowMatrixX3d vertices;            // deformed vertices
  RowMatrixX3d base_vertices;       // base state (gravity) vertices, for picking
  std::unique_ptr<TriangleBvh> base_bvh;
  std::vector<double> traction_magnitude;  // per element
  std::vector<char> in_contact;            // per element
};

ContactSnapshot snapshot_prototype() {
  ContactSnapshot proto;
  proto.elements.resize(2048);
  proto.tractions.resize(3 * 2048);
  return proto;
}

struct App {
  ViewerOptions options;
  GLFWwindow* window = nullptr;
  Renderer renderer;
  OrbitCamera camera;
  ModelWorker worker;
  CutSession cuts;
  bool camera_fitted = false;
  std::uint64_t fitted_version = 0;

  // GUI state
  RenderMode mode = RenderMode::Solid;
  int colour_by = 1;  // 0 none, 1 |u|, 2 |t|
  ToolKind tool = ToolKind::Sphere;
  float tool_radius_mm = 0.0f;  // 0 = default
  float young_kpa = 3.0f, poisson = 0.45f;
  bool gravity = true;
  float gap_mm = -1.0f;  // cut gap width; negative: 0.2 x the mean element size of the model
  StepperSettings settings;
  std::string scene_input;
  std::string record_path = "session.json";
  std::string record_message;
  int active_slot = 0;  // the slot the mouse drives; slot 0 is pinned when this is 1

  // Devices and the haptic thread
  std::array<std::unique_ptr<MouseDevice>, kMaxTools> mice;
  std::array<std::unique_ptr<haptics::ScriptedDevice>, kMaxTools> scripted;
  haptics::TripleBuffer<StepperSettings> settings_buffer;
  haptics::TripleBuffer<ContactSnapshot> snapshots{snapshot_prototype()};
  ToolStepper stepper;
  std::thread haptic_thread;
  std::atomic<bool> haptic_run{false};
  RateCounter haptic_rate, graphics_rate;
  Clock::time_point started = Clock::now();
  std::atomic<double> force_us{0.0};

  // Mouse interaction
  bool pressing = false;
  double press_x = 0, press_y = 0, last_x = 0, last_y = 0;
  double world_per_pixel = 0.0, wheel_depth = 0.0;
  Eigen::Vector3d press_point = Eigen::Vector3d::Zero(), press_dir = -Eigen::Vector3d::UnitZ();
  bool orbiting = false, panning = false;
  Recorder recorder;
  std::string recorded_tool;

  // Frame data
  FrameField field;
  ContactSnapshot contact = snapshot_prototype();
  std::vector<float> plot[kMaxTools];
  double max_force_seen = 0.01;
  float u_hi = 0.0f, t_hi = 0.0f;
  std::string frame_error;
  double script_time = 0.0;

  App() {
    for (int i = 0; i < kMaxTools; ++i) {
      mice[static_cast<std::size_t>(i)] = std::make_unique<MouseDevice>("mouse (tool " + std::to_string(i + 1) + ")");
      plot[i].assign(300, 0.0f);
    }
  }
};

/// The cut gap width in metres: the GUI's value, or 0.2 x the mean element size by default.
double gap_width(const App& app) {
  if (app.gap_mm > 0.0f) return 1e-3 * app.gap_mm;
  const auto ph = app.worker.state();
  return ph ? 0.2 * ph->mean_edge : 0.0;
}

// ---- field ------------------------------------------------------------------------------------

void update_field(App& app, const std::shared_ptr<const PhysicsState>& ph, const ContactSnapshot& c) {
  FrameField& f = app.field;
  if (!ph || !ph->mesh) {
    f.physics.reset();
    return;
  }
  const TriangleMesh& mesh = *ph->mesh;
  const Index E = mesh.num_elements();
  if (f.physics != ph) {
    f.physics = ph;
    f.version = ph->version;
    f.u = Eigen::VectorXd::Zero(3 * E);
    if (ph->table) f.base_vertices = deformed_vertices(mesh, ph->table->base_displacement());
    else if (ph->provisional_displacement.size() == 3 * E) f.base_vertices = deformed_vertices(mesh, ph->provisional_displacement);
    else f.base_vertices = mesh.vertices();
    f.base_bvh = std::make_unique<TriangleBvh>(f.base_vertices, mesh.faces());
  }
  f.traction_magnitude.assign(static_cast<std::size_t>(E), 0.0);
  f.in_contact.assign(static_cast<std::size_t>(E), 0);
  if (ph->table) {
    const GreensTable& table = *ph->table;
    f.u = table.base_displacement();
    const bool same = c.physics_version == ph->version;
    const Index count = same ? c.count : 0;
    if (count > 0) table.displacement_field(c.elements.data(), c.tractions.data(), count, f.u);
    const Eigen::VectorXd& tb = table.base_traction();
    for (Index e = 0; e < E; ++e) f.traction_magnitude[static_cast<std::size_t>(e)] = tb.segment<3>(3 * e).norm();
    for (Index i = 0; i < count; ++i) {
      const Index e = c.elements[static_cast<std::size_t>(i)];
      if (e < 0 || e >= E) continue;
      const Eigen::Vector3d t = tb.segment<3>(3 * e) + Eigen::Map<const Eigen::Vector3d>(c.tractions.data() + 3 * i);
      f.traction_magnitude[static_cast<std::size_t>(e)] = t.norm();
      f.in_contact[static_cast<std::size_t>(e)] = 1;
    }
    f.vertices = deformed_vertices(mesh, f.u);
  } else {
    f.u.setZero(3 * E);
    if (ph->provisional_displacement.size() == 3 * E) f.u = ph->provisional_displacement;
    f.vertices = deformed_vertices(mesh, f.u);
  }
}

void build_surface(const App& app, SurfaceBuffers& b, float& u_max, float& t_max) {
  const FrameField& f = app.field;
  b.clear();
  if (!f.physics) return;
  const TriangleMesh& mesh = *f.physics->mesh;
  const Index E = mesh.num_elements();
  b.positions.reserve(static_cast<std::size_t>(9 * E));
  b.normals.reserve(static_cast<std::size_t>(9 * E));
  b.scalars.reserve(static_cast<std::size_t>(3 * E));
  b.highlight.reserve(static_cast<std::size_t>(3 * E));
  u_max = 0.0f;
  t_max = 0.0f;
  for (Index e = 0; e < E; ++e) {
    Eigen::Vector3d p[3];
    for (int k = 0; k < 3; ++k) p[k] = f.vertices.row(mesh.faces()(e, k)).transpose();
    Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);
    if (n.norm() > 0.0) n.normalize();
    const float tmag = float(f.traction_magnitude[static_cast<std::size_t>(e)]);
    t_max = std::max(t_max, tmag);
    for (int k = 0; k < 3; ++k) {
      const Index v = mesh.faces()(e, k);
      b.positions.insert(b.positions.end(), {float(p[k].x()), float(p[k].y()), float(p[k].z())});
      b.normals.insert(b.normals.end(), {float(n.x()), float(n.y()), float(n.z())});
      const float umag = float((f.vertices.row(v) - mesh.vertices().row(v)).norm());
      u_max = std::max(u_max, umag);
      float s = 0.0f;
      if (app.colour_by == 1) s = umag;
      else if (app.colour_by == 2) s = tmag;
      else s = f.physics->supported[static_cast<std::size_t>(e)] ? 1.0f : 0.0f;
      b.scalars.push_back(s);
      const bool wall = f.physics->original_elements > 0 && e >= f.physics->original_elements;
      b.highlight.push_back(wall ? 2.0f : f.in_contact[static_cast<std::size_t>(e)] ? 1.0f : 0.0f);
    }
  }
}

void build_tools(const App& app, SurfaceBuffers& tools, SurfaceBuffers& arrows, std::vector<float>& lines) {
  tools.clear();
  arrows.clear();
  lines.clear();
  if (!app.field.physics) return;
  const Eigen::Matrix<double, 3, 2> box = app.field.physics->mesh->bounding_box();
  const float size = float((box.col(1) - box.col(0)).norm());
  const float edge = float(app.field.physics->mean_edge);
  for (int i = 0; i < kMaxTools; ++i) {
    const SlotSnapshot& s = app.contact.slots[static_cast<std::size_t>(i)];
    if (!s.engaged || app.contact.physics_version != app.field.physics->version) continue;
    const Eigen::Vector3f tip = s.tip.cast<float>(), d = s.direction.cast<float>().normalized();
    const float shaft = 0.25f * size;
    switch (s.kind) {
      case ToolKind::Sphere:
        append_sphere(tools, tip, float(s.radius));
        append_cylinder(tools, tip - float(s.radius) * d, tip - (float(s.radius) + shaft) * d, 0.15f * float(s.radius));
        break;
      case ToolKind::Flat:
        append_disc(tools, tip, -d, float(s.radius));
        append_cylinder(tools, tip, tip - shaft * d, 0.2f * float(s.radius));
        break;
      case ToolKind::Point:
        append_cone(tools, tip - 0.8f * edge * d, tip, 0.2f * edge);
        append_cylinder(tools, tip - 0.8f * edge * d, tip - shaft * d, 0.08f * edge);
        break;
      case ToolKind::Pinch: {
        const Eigen::Vector3f a = d.unitOrthogonal();
        const float w = std::max(float(s.radius), 0.3f * edge);
        append_cylinder(tools, tip + w * a, tip + w * a - shaft * d, 0.08f * edge);
        append_cylinder(tools, tip - w * a, tip - w * a - shaft * d, 0.08f * edge);
        append_sphere(tools, tip, 0.15f * edge);
        break;
      }
      case ToolKind::Plate: {
        const Eigen::Vector3f a = d.unitOrthogonal(), b = d.cross(a);
        const float h = float(s.plate_size);
        append_quad(tools, tip + h * (a + b), tip + h * (-a + b), tip + h * (-a - b), tip + h * (a - b));
        append_quad(tools, tip + h * (a - b), tip + h * (-a - b), tip + h * (-a + b), tip + h * (a + b));
        append_cylinder(tools, tip, tip - shaft * d, 0.08f * edge);
        break;
      }
      case ToolKind::Cut: break;
    }
    // The force on the tool, drawn from the tip (scaled to the largest force seen this session).
    const Eigen::Vector3f F = s.force.cast<float>();
    if (F.norm() > 1e-9f) {
      // Drawn beside the tool (the force on a pressing tool points back along its shaft).
      const float len = 0.3f * size * F.norm() / float(app.max_force_seen);
      const Eigen::Vector3f side = app.camera.right();
      const float offset = std::max(float(s.radius), 0.5f * edge) + 0.03f * size;
      append_arrow(arrows, tip + offset * side, len * F.normalized(), 0.01f * size);
    }
  }
  // The pending cut path, if a cut is being dragged.
  for (const auto& seg : app.cuts.path_segments()) {
    lines.insert(lines.end(), {float(seg.first.x()), float(seg.first.y()), float(seg.first.z()), float(seg.second.x()),
                               float(seg.second.y()), float(seg.second.z())});
  }
}

// ---- haptic thread ----------------------------------------------------------------------------

void haptic_loop(App* app) {
  // 1 kHz: read the mice, solve the contact, publish the snapshot (docs/design.md §9).
  haptics::HapticDevice* devices[kMaxTools];
  for (int i = 0; i < kMaxTools; ++i) devices[i] = app->mice[static_cast<std::size_t>(i)].get();
  auto next = Clock::now();
  const auto period = std::chrono::microseconds(1000);
  while (app->haptic_run.load(std::memory_order_relaxed)) {
    app->settings_buffer.acquire();
    const auto physics = app->worker.state();
    app->stepper.tick(physics, devices, app->settings_buffer.front(), seconds_since(app->started), 1e-3,
                      app->snapshots.back());
    app->force_us.store(1e6 * app->snapshots.back().force_seconds, std::memory_order_relaxed);
    app->snapshots.publish();
    app->haptic_rate.tick();
    next += period;
    const auto now = Clock::now();
    if (next < now) next = now;  // overrun: do not try to catch up
    std::this_thread::sleep_until(next);
  }
  // Zero force on stop.
  for (auto* d : devices) d->write_force(Eigen::Vector3d::Zero());
}

// ---- GUI --------------------------------------------------------------------------------------

const char* kToolNames[] = {"point", "sphere", "flat", "pinch", "retract (plate)", "cut"};

void colour_bar(App& app, int width, int height) {
  (void)height;
  if (app.colour_by == 0 || !app.field.physics) return;
  const float hi = app.colour_by == 1 ? app.u_hi : app.t_hi;
  ImGui::SetNextWindowPos(ImVec2(float(width) - 120.0f, 60.0f), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(110.0f, 300.0f), ImGuiCond_Always);
  ImGui::Begin("colour bar", nullptr,
               ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
                   ImGuiWindowFlags_NoScrollbar | ImGuiWindowFlags_NoInputs);
  ImGui::TextUnformatted(app.colour_by == 1 ? "|u| (mm)" : "|t| (Pa)");
  const float shown = app.colour_by == 1 ? 1000.0f * hi : hi;
  ImGui::Text("%.3g", shown);
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p = ImGui::GetCursorScreenPos();
  const float h = 200.0f, w = 24.0f;
  const int steps = 40;
  for (int i = 0; i < steps; ++i) {
    const float s0 = 1.0f - float(i) / steps, s1 = 1.0f - float(i + 1) / steps;
    const Eigen::Vector3f c0 = colour_map(s0), c1 = colour_map(s1);
    dl->AddRectFilledMultiColor(ImVec2(p.x, p.y + h * i / steps), ImVec2(p.x + w, p.y + h * (i + 1) / steps),
                                ImColor(c0.x(), c0.y(), c0.z()), ImColor(c0.x(), c0.y(), c0.z()),
                                ImColor(c1.x(), c1.y(), c1.z()), ImColor(c1.x(), c1.y(), c1.z()));
  }
  dl->AddRect(p, ImVec2(p.x + w, p.y + h), IM_COL32(40, 40, 40, 255));
  for (int i = 1; i < 4; ++i) {
    const float y = p.y + h * i / 4.0f;
    dl->AddLine(ImVec2(p.x + w, y), ImVec2(p.x + w + 5, y), IM_COL32(40, 40, 40, 255));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", shown * (1.0f - i / 4.0f));
    dl->AddText(ImVec2(p.x + w + 8, y - 7), IM_COL32(20, 20, 20, 255), buf);
  }
  ImGui::Dummy(ImVec2(w, h));
  ImGui::Text("0");
  ImGui::End();
}

void gui(App& app, int width, int height) {
  const WorkerStatus st = app.worker.status();
  const auto ph = app.field.physics;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(380, float(height) - 16.0f), ImGuiCond_FirstUseEver);
  ImGui::Begin("bemsurg");

  // Model and precomputation
  if (ImGui::CollapsingHeader("Model", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (ph) {
      ImGui::TextWrapped("%s", ph->model_name.c_str());
      ImGui::Text("%ld elements, %ld equations", long(ph->mesh->num_elements()), long(3 * ph->mesh->num_elements()));
    }
    if (st.phase == WorkerPhase::Precomputing || st.phase == WorkerPhase::Loading || st.phase == WorkerPhase::Rescaling) {
      ImGui::TextWrapped("%s", st.message.c_str());
      char overlay[64];
      std::snprintf(overlay, sizeof overlay, "%.0f %%  about %.0f s left", 100.0 * st.progress, std::ceil(st.seconds_left));
      ImGui::ProgressBar(float(st.progress), ImVec2(-1, 0), overlay);
      ImGui::TextDisabled("the model is shown undeformed until the table is in");
    } else if (st.phase == WorkerPhase::Ready) {
      ImGui::Text("table ready (precompute %.1f s)", st.last_precompute_seconds);
    }
    if (ph && ph->cuts > 0) {
      if (ph->table && st.tables_exact)
      {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.1f, 0.5f, 0.1f, 1.0f));
        ImGui::TextWrapped("exact tables in after %d cut steps (%s, %.0f ms)", ph->cuts,
                           st.last_cut_exact_update ? "delta update" : "recomputed", 1000.0 * st.last_cut_update_seconds);
        ImGui::PopStyleColor();
      }
      else
        ImGui::TextColored(ImVec4(0.7f, 0.35f, 0.0f, 1.0f), "cut shown; exact tables being computed...");
    }
    if (app.cuts.accepted() + app.cuts.refused() > 0 && app.tool != ToolKind::Cut) ImGui::TextWrapped("%s", app.cuts.status_line().c_str());
    if (!st.error.empty()) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.8f, 0.1f, 0.1f, 1.0f));
      ImGui::TextWrapped("error: %s", st.error.c_str());
      ImGui::PopStyleColor();
    }
    ImGui::InputText("scene", &app.scene_input);
    if (ImGui::Button("Load scene")) app.worker.load(app.scene_input);
    ImGui::SameLine();
    if (ImGui::Button("Default model")) app.worker.load(ModelWorker::default_scene_path());
  }

  // Forces and rates
  if (ImGui::CollapsingHeader("Forces", ImGuiTreeNodeFlags_DefaultOpen)) {
    for (int i = 0; i < kMaxTools; ++i) {
      const SlotSnapshot& s = app.contact.slots[static_cast<std::size_t>(i)];
      const Eigen::Vector3d& F = s.force;
      ImGui::Text("tool %d: |F| = %.4f N  (%ld elements)", i + 1, F.norm(), long(s.contact_elements));
      ImGui::Text("   F = (%.4f, %.4f, %.4f) N", F.x(), F.y(), F.z());
      char label[32];
      std::snprintf(label, sizeof label, "##plot%d", i);
      const auto& p = app.plot[i];
      const float top = *std::max_element(p.begin(), p.end());
      if (i == 0 || top > 0.0f) {
        char overlay[48];
        std::snprintf(overlay, sizeof overlay, "|F| tool %d, N (max %.3g)", i + 1, top);
        ImGui::PlotLines(label, p.data(), int(p.size()), 0, overlay, 0.0f, std::max(top * 1.1f, 1e-3f),
                         ImVec2(ImGui::GetContentRegionAvail().x, 55.0f));
      }
    }
    ImGui::Text("arrow: %.0f mm = %.3g N", 0.3 * 1000.0 * (ph ? (ph->mesh->bounding_box().col(1) - ph->mesh->bounding_box().col(0)).norm() : 0.0),
                app.max_force_seen);
    if (app.options.headless)
      ImGui::Text("headless: t = %.2f s of script, one contact update per frame", app.script_time);
    else
      ImGui::Text("graphics %.0f Hz   haptic %.0f Hz", app.graphics_rate.rate(), app.haptic_rate.rate());
    ImGui::Text("contact update %.1f us", app.force_us.load());
    if (app.contact.message[0]) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.7f, 0.3f, 0.0f, 1.0f));
      ImGui::TextWrapped("%s", app.contact.message.data());
      ImGui::PopStyleColor();
    }
  }

  // Tools
  if (ImGui::CollapsingHeader("Tool", ImGuiTreeNodeFlags_DefaultOpen)) {
    int t = static_cast<int>(app.tool);
    for (int i = 0; i < 6; ++i) {
      if (i % 3) ImGui::SameLine();
      ImGui::RadioButton(kToolNames[i], &t, i);
    }
    app.tool = static_cast<ToolKind>(t);
    if (app.tool == ToolKind::Sphere || app.tool == ToolKind::Flat || app.tool == ToolKind::Pinch ||
        app.tool == ToolKind::Plate) {
      const double def = ph ? (app.tool == ToolKind::Plate ? default_plate_size(ph->mean_edge)
                                                           : default_tool_radius(app.tool, ph->mean_edge))
                            : 0.0;
      if (app.tool_radius_mm <= 0.0f) app.tool_radius_mm = float(1000.0 * def);
      ImGui::SliderFloat(app.tool == ToolKind::Plate ? "half-width (mm)" : "radius (mm)", &app.tool_radius_mm, 1.0f, 40.0f, "%.1f");
    }
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("left-drag on the model: press (drag down) or pull; right-drag: orbit; wheel: zoom");
    ImGui::PopStyleColor();
    if (app.active_slot == 0) {
      if (ImGui::Button("Pin tool 1, drive tool 2 (P)")) app.active_slot = 1;
    } else {
      ImGui::Text("tool 1 pinned");
      ImGui::SameLine();
      if (ImGui::Button("Release pinned tool (Esc)")) {
        haptics::DeviceState s = app.mice[0]->read(0.0);
        s.buttons = 0;
        app.mice[0]->set_state(s);
        app.active_slot = 0;
      }
    }
    if (app.tool == ToolKind::Cut) {
      if (app.gap_mm < 0.0f && ph) app.gap_mm = float(0.2 * 1000.0 * ph->mean_edge);
      ImGui::SliderFloat("cut gap width (mm)", &app.gap_mm, 0.2f, 5.0f, "%.2f");
      ImGui::TextWrapped("%s", app.cuts.status_line().c_str());
    }
  }

  // Display
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) {
    int m = static_cast<int>(app.mode);
    ImGui::RadioButton("solid", &m, 0);
    ImGui::SameLine();
    ImGui::RadioButton("wireframe", &m, 1);
    ImGui::SameLine();
    ImGui::RadioButton("points", &m, 2);
    app.mode = static_cast<RenderMode>(m);
    ImGui::RadioButton("tissue", &app.colour_by, 0);
    ImGui::SameLine();
    ImGui::RadioButton("colour by |u|", &app.colour_by, 1);
    ImGui::SameLine();
    ImGui::RadioButton("|t|", &app.colour_by, 2);
    if (ImGui::Button("Reset view (R)")) app.camera.reset();
  }

  // Parameters
  if (ImGui::CollapsingHeader("Parameters", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::SliderFloat("E (kPa)", &app.young_kpa, 0.3f, 100.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
    if (ImGui::IsItemDeactivatedAfterEdit()) app.worker.set_young_modulus(1000.0 * app.young_kpa);
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped(st.rescale_exact ? "E rescales forces and the sag at once, without recomputing (linear elasticity)"
                                        : "E recomputes: this scene prescribes nonzero displacements");
    ImGui::PopStyleColor();
    ImGui::SliderFloat("nu", &app.poisson, 0.0f, 0.49f, "%.3f");
    if (ImGui::IsItemDeactivatedAfterEdit()) app.worker.set_poisson_ratio(app.poisson);
    ImGui::TextDisabled("nu recomputes the table in the background");
    if (ImGui::Checkbox("gravity", &app.gravity)) app.worker.set_gravity(app.gravity);
    ImGui::Checkbox("haptic force to device", &app.settings.haptic_force);
    float limit = float(app.settings.force_limit);
    ImGui::SliderFloat("force limit (N)", &limit, 0.1f, 10.0f, "%.2f");
    app.settings.force_limit = limit;
  }

  if (ImGui::CollapsingHeader("Record session")) {
    ImGui::InputText("file", &app.record_path);
    if (!app.recorder.on) {
      if (ImGui::Button("Start recording")) {
        app.recorder = Recorder{};
        app.recorder.on = true;
        app.record_message = "recording...";
      }
    } else if (ImGui::Button("Stop and save")) {
      app.recorder.on = false;
      std::string err;
      app.record_message = app.recorder.save(app.record_path, app.scene_input, err)
                               ? "saved " + app.record_path + ": replay with --script"
                               : err;
    }
    ImGui::TextWrapped("%s", app.record_message.c_str());
  }
  ImGui::End();
  colour_bar(app, width, height);
}

// ---- mouse ------------------------------------------------------------------------------------

void mouse_to_device(App& app, double x, double y, bool down) {
  MouseDevice& dev = *app.mice[static_cast<std::size_t>(app.active_slot)];
  haptics::DeviceState s;
  s.direction = app.press_dir;
  s.buttons = down ? 1U : 0U;
  if (!down) {
    s.position = app.press_point;
    s.buttons = 0;
    dev.set_state(s);
    return;
  }
  const double dx = x - app.press_x, dy = y - app.press_y;
  const Eigen::Vector3d right = app.camera.right().cast<double>(), up = app.camera.up().cast<double>();
  Eigen::Vector3d tr;
  if (app.tool == ToolKind::Pinch || app.tool == ToolKind::Plate) {
    // Pull where the mouse goes (in the screen plane), the wheel pushes along the approach.
    tr = app.world_per_pixel * (dx * right - dy * up) + app.wheel_depth * app.press_dir;
  } else {
    // Drag down to press in, sideways to slide.
    const Eigen::Vector3d side = (right - right.dot(app.press_dir) * app.press_dir);
    tr = app.world_per_pixel * (std::max(0.0, dy) * app.press_dir + dx * side) + app.wheel_depth * app.press_dir;
  }
  s.position = app.press_point + tr;
  dev.set_state(s);
  if (app.recorder.on && app.recorder.now() - app.recorder.last_move > 0.1) {
    // The script's tool tip (docs/actions.md): a sphere's centre sits one radius behind the point hit.
    const double now = app.recorder.now();
    app.recorder.last_move = now;
    Eigen::Vector3d tip = s.position;
    const SlotSettings& slot = app.settings.slots[static_cast<std::size_t>(app.active_slot)];
    if (app.tool == ToolKind::Sphere && app.field.physics)
      tip -= (slot.radius > 0.0 ? slot.radius : default_tool_radius(ToolKind::Sphere, app.field.physics->mean_edge)) * app.press_dir;
    // Samples at most every 0.1 s, each a 0.1 s linear move (a tool's actions may not overlap).
    app.recorder.actions.push_back(
        {{"time", now}, {"tool", app.recorded_tool}, {"type", "move"}, {"to", vec_json(tip)}, {"duration", 0.1}});
  }
}

bool pick(App& app, double x, double y, Eigen::Vector3d& point, Eigen::Vector3d& normal) {
  if (!app.field.base_bvh) return false;
  int w, h;
  glfwGetWindowSize(app.window, &w, &h);
  Eigen::Vector3f o, d;
  app.camera.ray(x, y, w, h, o, d);
  RayHit hit;
  if (!app.field.base_bvh->intersect_ray(o.cast<double>(), d.cast<double>(), hit)) return false;
  point = hit.point;
  normal = app.field.physics->mesh->normal(hit.element);
  app.world_per_pixel = 2.0 * hit.t * std::tan(0.5 * app.camera.fov_y) / double(std::max(h, 1));
  return true;
}

void handle_mouse(App& app) {
  ImGuiIO& io = ImGui::GetIO();
  double x, y;
  glfwGetCursorPos(app.window, &x, &y);
  const bool left = glfwGetMouseButton(app.window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  const bool right = glfwGetMouseButton(app.window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  const bool middle = glfwGetMouseButton(app.window, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  const bool shift = glfwGetKey(app.window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS;
  int w, h;
  glfwGetWindowSize(app.window, &w, &h);
  if (!io.WantCaptureMouse || app.pressing || app.orbiting || app.panning) {
    if (left && !app.pressing && !io.WantCaptureMouse) {
      Eigen::Vector3d p, n;
      if (pick(app, x, y, p, n)) {
        app.pressing = true;
        app.press_x = x;
        app.press_y = y;
        app.wheel_depth = 0.0;
        app.press_point = p;
        app.press_dir = -n;
        if (app.tool == ToolKind::Cut) {
          app.cuts.begin_drag(p, app.worker, gap_width(app));
        } else {
          SlotSettings& s = app.settings.slots[static_cast<std::size_t>(app.active_slot)];
          s.kind = app.tool;
          s.radius = app.tool == ToolKind::Plate ? 0.0 : 1e-3 * app.tool_radius_mm;
          s.plate_size = app.tool == ToolKind::Plate ? 1e-3 * app.tool_radius_mm : 0.0;
          if (app.tool == ToolKind::Point) s.radius = 0.0;
          if (app.recorder.on) {
            const double radius = app.tool == ToolKind::Point ? 0.0
                                  : s.radius > 0.0 ? s.radius
                                  : default_tool_radius(app.tool, app.field.physics->mean_edge);
            app.recorder.last_move = app.recorder.now();  // the next move starts after the press
            if (app.tool == ToolKind::Plate) {
              app.record_message = "a retractor plate is not recorded (scripts give a plate its own polygon)";
            } else {
              app.recorded_tool = app.recorder.tool_name(app.active_slot, app.tool, radius);
              const char* type = app.tool == ToolKind::Pinch ? "pinch" : "press";
              nlohmann::json a = {{"time", app.recorder.now()}, {"tool", app.recorded_tool}, {"type", type},
                                  {"at", vec_json(p)}, {"direction", vec_json(-n)}};
              if (app.tool != ToolKind::Pinch) a["depth"] = 0.0;
              app.recorder.actions.push_back(a);
            }
          }
          mouse_to_device(app, x, y, true);
        }
      }
    } else if (left && app.pressing) {
      if (app.tool == ToolKind::Cut) {
        Eigen::Vector3d p, n;
        if (pick(app, x, y, p, n)) app.cuts.drag_to(p, app.worker, gap_width(app));
      } else {
        mouse_to_device(app, x, y, true);
      }
    } else if (!left && app.pressing) {
      app.pressing = false;
      if (app.tool == ToolKind::Cut) {
        app.cuts.end_drag();
      } else {
        mouse_to_device(app, x, y, false);
        if (app.recorder.on && !app.recorded_tool.empty() && app.tool != ToolKind::Plate)
          app.recorder.actions.push_back({{"time", std::max(app.recorder.now(), app.recorder.last_move + 0.1001)},
                                          {"tool", app.recorded_tool}, {"type", "release"}});
      }
    }
    if (!app.pressing) {
      const bool want_pan = middle || (right && shift);
      if (want_pan && (app.panning || !io.WantCaptureMouse)) {
        if (app.panning) app.camera.pan(float(x - app.last_x), float(y - app.last_y), h);
        app.panning = true;
      } else {
        app.panning = false;
      }
      if (right && !shift && (app.orbiting || !io.WantCaptureMouse)) {
        if (app.orbiting) app.camera.orbit(float(x - app.last_x), float(y - app.last_y));
        app.orbiting = true;
      } else {
        app.orbiting = false;
      }
    }
  }
  app.last_x = x;
  app.last_y = y;
}

void scroll_callback(GLFWwindow* window, double xoff, double yoff) {
  ImGui_ImplGlfw_ScrollCallback(window, xoff, yoff);
  App* app = static_cast<App*>(glfwGetWindowUserPointer(window));
  if (ImGui::GetIO().WantCaptureMouse) return;
  if (app->pressing) {
    app->wheel_depth += 0.05 * app->field.physics->mean_edge * yoff;
  } else {
    app->camera.zoom(float(yoff));
  }
}

void key_callback(GLFWwindow* window, int key, int scancode, int action, int mods) {
  ImGui_ImplGlfw_KeyCallback(window, key, scancode, action, mods);
  App* app = static_cast<App*>(glfwGetWindowUserPointer(window));
  if (action != GLFW_PRESS || ImGui::GetIO().WantCaptureKeyboard) return;
  if (key == GLFW_KEY_R) app->camera.reset();
  if (key == GLFW_KEY_1) app->mode = RenderMode::Solid;
  if (key == GLFW_KEY_2) app->mode = RenderMode::Wireframe;
  if (key == GLFW_KEY_3) app->mode = RenderMode::Points;
  if (key == GLFW_KEY_P && app->active_slot == 0) app->active_slot = 1;
  if (key == GLFW_KEY_ESCAPE && app->active_slot == 1) {
    haptics::DeviceState s = app->mice[0]->read(0.0);
    s.buttons = 0;
    app->mice[0]->set_state(s);
    app->active_slot = 0;
  }
}

// ---- frame ------------------------------------------------------------------------------------

void draw_frame(App& app, int fbw, int fbh, int width, int height) {
  const auto ph = app.worker.state();
  if (ph && ph->mesh && (!app.camera_fitted || ph->mesh.get() != (app.field.physics ? app.field.physics->mesh.get() : nullptr))) {
    if (!app.camera_fitted) {
      const Eigen::Matrix<double, 3, 2> box = ph->mesh->bounding_box();
      app.camera.fit(box.col(0).cast<float>(), box.col(1).cast<float>());
      app.camera_fitted = true;
    }
  }
  update_field(app, ph, app.contact);
  for (int i = 0; i < kMaxTools; ++i) {
    auto& p = app.plot[i];
    std::rotate(p.begin(), p.begin() + 1, p.end());
    p.back() = float(app.contact.slots[static_cast<std::size_t>(i)].force.norm());
    app.max_force_seen = std::max(app.max_force_seen, double(p.back()));
  }
  SurfaceBuffers surface, tools, arrows;
  std::vector<float> lines;
  float umax = 0.0f, tmax = 0.0f;
  build_surface(app, surface, umax, tmax);
  app.u_hi = std::max(umax, 1e-9f);
  app.t_hi = std::max(tmax, 1e-9f);
  build_tools(app, tools, arrows, lines);

  app.renderer.begin_frame(fbw, fbh);
  const float aspect = float(fbw) / float(std::max(fbh, 1));
  app.camera.shift_ndc = 390.0f / float(std::max(width, 1));  // the side panel's width
  app.renderer.set_camera(app.camera.projection(aspect) * app.camera.view(), app.camera.eye());
  const float hi = app.colour_by == 1 ? app.u_hi : app.t_hi;
  app.renderer.draw_surface(surface, app.mode, app.colour_by != 0, 0.0f, hi);
  app.renderer.draw_solid(tools, Eigen::Vector3f(0.70f, 0.72f, 0.78f));
  app.renderer.draw_solid(arrows, Eigen::Vector3f(0.85f, 0.10f, 0.55f));
  app.renderer.draw_lines(lines, Eigen::Vector3f(0.1f, 0.1f, 0.1f));

  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  gui(app, width, height);
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

bool write_png(const std::string& path, int w, int h, std::string& error) {
  std::vector<unsigned char> pixels(static_cast<std::size_t>(w) * h * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, pixels.data());
  // OpenGL's rows run bottom-up; PNG's top-down: write with a negative stride from the last row.
  if (!stbi_write_png(path.c_str(), w, h, 3, pixels.data() + static_cast<std::size_t>(w) * 3 * (h - 1), -w * 3)) {
    error = "cannot write the screenshot " + path;
    return false;
  }
  return true;
}

std::string shot_name(const std::string& out, int frame) {
  const std::size_t dot = out.rfind('.');
  const std::string stem = dot == std::string::npos ? out : out.substr(0, dot);
  char buf[32];
  std::snprintf(buf, sizeof buf, "-f%04d.png", frame);
  return stem + buf;
}

GLFWwindow* open_window(const ViewerOptions& o, std::string& error) {
  glfwSetErrorCallback([](int, const char* text) { std::cerr << "bemsurg-viewer: GLFW: " << text << "\n"; });
  if (!glfwInit()) {
    error = "no display: GLFW could not open one (DISPLAY is " +
            std::string(std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "not set") +
            "). On a machine without a screen run the viewer under a virtual X server:\n"
            "  xvfb-run -a -s \"-screen 0 1280x800x24\" bemsurg-viewer --script examples/viewer-prod.json --frames 90 "
            "--screenshot out.png\n(Debian package xvfb)";
    return nullptr;
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_SAMPLES, o.headless ? 0 : 4);
  GLFWwindow* w = glfwCreateWindow(o.width, o.height, "bemsurg viewer", nullptr, nullptr);
  if (!w) {
    error = "could not create an OpenGL 3.3 core window on this display; without a GPU or screen run under "
            "xvfb-run -a -s \"-screen 0 1280x800x24\" (Mesa's llvmpipe provides OpenGL 3.3)";
    glfwTerminate();
    return nullptr;
  }
  glfwMakeContextCurrent(w);
  const char* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const std::string name = renderer ? renderer : "";
  if (!o.headless && (name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos)) {
    // Software rendering: multisampling costs more than it gives; open the window without it.
    glfwDestroyWindow(w);
    glfwWindowHint(GLFW_SAMPLES, 0);
    w = glfwCreateWindow(o.width, o.height, "bemsurg viewer", nullptr, nullptr);
    if (!w) {
      error = "could not create an OpenGL 3.3 core window on this display";
      glfwTerminate();
      return nullptr;
    }
    glfwMakeContextCurrent(w);
  }
  if (o.quit_after > 0.0) std::cerr << "bemsurg-viewer: OpenGL renderer: " << name << "\n";
  glfwSwapInterval(o.headless ? 0 : 1);
  return w;
}

}  // namespace

int run_viewer(const ViewerOptions& o) {
  auto app = std::make_unique<App>();
  app->options = o;
  app->scene_input = o.scene;

  // Headless: read the script and compute the model before touching the display, so bad input is
  // reported as such (and exits non-zero) on any machine.
  std::unique_ptr<ScriptPlayer> player;
  if (o.headless) {
    if (o.script.empty()) {
      std::cerr << "bemsurg-viewer: headless mode needs --script ACTIONS.json\n";
      return 2;
    }
    if (o.frames < 1) {
      std::cerr << "bemsurg-viewer: --frames N must be at least 1\n";
      return 2;
    }
    if (o.screenshot.empty()) {
      std::cerr << "bemsurg-viewer: headless mode needs --screenshot OUT.png\n";
      return 2;
    }
    try {
      player = std::make_unique<ScriptPlayer>(load_action_script(o.script));
    } catch (const std::exception& e) {
      std::cerr << "bemsurg-viewer: " << e.what() << "\n";
      return 1;
    }
    for (const auto& w : player->script().warnings) std::cerr << "bemsurg-viewer: warning: " << w << "\n";
    std::string scene = o.scene;
    if (scene.empty() && !player->script().scene.empty()) scene = player->script().scene;
    app->scene_input = scene;
    app->worker.load(scene.empty() ? ModelWorker::default_scene_path() : scene);
    const auto t0 = Clock::now();
    app->worker.wait_idle();
    const WorkerStatus st = app->worker.status();
    if (st.phase == WorkerPhase::Failed || !app->worker.state() || !app->worker.state()->table) {
      std::cerr << "bemsurg-viewer: " << (st.error.empty() ? "the model could not be prepared" : st.error) << "\n";
      return 1;
    }
    // The scripted devices: first contacts found on the body resting under its own weight.
    try {
      const auto ph = app->worker.state();
      const TriangleBvh base(deformed_vertices(*ph->mesh, ph->table->base_displacement()), ph->mesh->faces());
      for (int s = 0; s < kMaxTools; ++s) {
        const int tool = player->tool_of_slot(s);
        if (tool < 0) continue;
        app->scripted[static_cast<std::size_t>(s)] = std::make_unique<haptics::ScriptedDevice>(
            player->keyframes(tool, base), player->script().tools[static_cast<std::size_t>(tool)].name, 1e9);
      }
    } catch (const std::exception& e) {
      std::cerr << "bemsurg-viewer: " << e.what() << "\n";
      return 1;
    }
    std::cerr << "bemsurg-viewer: " << app->worker.state()->model_name << ": "
              << app->worker.state()->mesh->num_elements() << " elements, precomputed in " << std::fixed
              << std::setprecision(2) << seconds_since(t0) << " s\n";
  } else {
    app->worker.load(o.scene.empty() ? ModelWorker::default_scene_path() : o.scene);
  }

  std::string error;
  app->window = open_window(o, error);
  if (!app->window) {
    std::cerr << "bemsurg-viewer: " << error << "\n";
    return 3;
  }
  glfwSetWindowUserPointer(app->window, app.get());
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsLight();
  ImGui_ImplGlfw_InitForOpenGL(app->window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  glfwSetScrollCallback(app->window, scroll_callback);
  glfwSetKeyCallback(app->window, key_callback);
  if (!app->renderer.init(error)) {
    std::cerr << "bemsurg-viewer: " << error << "\n";
    return 3;
  }

  int code = 0;
  if (o.headless) {
    // Deterministic playback: frame f shows the script at t = f / fps; one contact tick per frame.
    haptics::HapticDevice* devices[kMaxTools] = {app->scripted[0].get(), app->scripted[1].get()};
    const double dt = 1.0 / o.fps;
    double t_prev = -1.0;
    double peak[kMaxTools] = {0.0, 0.0};
    int fbw = 0, fbh = 0;
    for (int f = 0; f < o.frames; ++f) {
      const double t = f / o.fps;
      glfwPollEvents();
      for (int s = 0; s < kMaxTools; ++s) {
        const int tool = player->tool_of_slot(s);
        if (tool < 0) continue;
        app->settings.slots[static_cast<std::size_t>(s)] = player->slot_settings(tool);
        if (s == 0) {  // the panel shows the first tool's choice
          app->tool = app->settings.slots[0].kind;
          app->tool_radius_mm = float(1000.0 * app->settings.slots[0].radius);
        }
      }
      for (const ScriptCut& c : player->cuts_between(t_prev, t)) app->cuts.scripted_step(c.action, c.from, c.direction, app->worker, gap_width(*app));
      t_prev = t;
      app->stepper.tick(app->worker.state(), devices, app->settings, t, dt, app->contact);
      app->script_time = t;
      app->force_us.store(1e6 * app->contact.force_seconds);
      for (int s = 0; s < kMaxTools; ++s) peak[s] = std::max(peak[s], app->contact.slots[static_cast<std::size_t>(s)].force.norm());
      app->graphics_rate.tick();
      int w, h;
      glfwGetFramebufferSize(app->window, &fbw, &fbh);
      glfwGetWindowSize(app->window, &w, &h);
      draw_frame(*app, fbw, fbh, w, h);
      const bool last = f + 1 == o.frames;
      if (std::find(o.shots.begin(), o.shots.end(), f) != o.shots.end() && !write_png(shot_name(o.screenshot, f), fbw, fbh, error)) {
        std::cerr << "bemsurg-viewer: " << error << "\n";
        code = 1;
      }
      if (last && !write_png(o.screenshot, fbw, fbh, error)) {
        std::cerr << "bemsurg-viewer: " << error << "\n";
        code = 1;
      }
      glfwSwapBuffers(app->window);
    }
    std::cerr << "bemsurg-viewer: " << o.frames << " frames (" << o.frames / o.fps << " s of script); peak |F| tool 1 "
              << std::setprecision(4) << peak[0] << " N, tool 2 " << peak[1] << " N; " << app->cuts.summary() << "\n";
    if (app->cuts.accepted() > 0) {
      const WorkerStatus st = app->worker.status();
      std::cerr << "bemsurg-viewer: tables after the last cut step: " << (st.last_cut_exact_update ? "delta update" : "recomputed")
                << " in " << std::setprecision(1) << 1000.0 * st.last_cut_update_seconds << " ms ("
                << app->worker.state()->mesh->num_elements() << " elements)\n";
    }
    if (app->contact.message[0]) std::cerr << "bemsurg-viewer: note: " << app->contact.message.data() << "\n";
    if (code == 0) std::cerr << "bemsurg-viewer: wrote " << o.screenshot << "\n";
  } else {
    if (!o.record.empty()) {  // --record FILE: record from the start, save at exit
      app->recorder.on = true;
      app->record_path = o.record;
      app->record_message = "recording to " + o.record + " (saved at exit)";
    }
    app->haptic_run = true;
    app->haptic_thread = std::thread(haptic_loop, app.get());
    const auto opened = Clock::now();
    double graphics_sum = 0.0, haptic_sum = 0.0;
    int rate_samples = 0;
    while (!glfwWindowShouldClose(app->window)) {
      if (o.quit_after > 0.0) {
        const double t = seconds_since(opened);
        if (t > 0.5 * o.quit_after && app->field.physics && app->field.physics->table) {
          graphics_sum += app->graphics_rate.rate();
          haptic_sum += app->haptic_rate.rate();
          ++rate_samples;
        }
        if (t > o.quit_after) break;
      }
      glfwPollEvents();
      handle_mouse(*app);
      app->settings_buffer.back() = app->settings;
      app->settings_buffer.publish();
      if (app->snapshots.acquire()) {
        const ContactSnapshot& s = app->snapshots.front();
        app->contact.physics_version = s.physics_version;
        app->contact.slots = s.slots;
        app->contact.count = s.count;
        if (app->contact.elements.size() < s.elements.size()) {
          app->contact.elements.resize(s.elements.size());
          app->contact.tractions.resize(s.tractions.size());
        }
        std::copy(s.elements.begin(), s.elements.begin() + s.count, app->contact.elements.begin());
        std::copy(s.tractions.begin(), s.tractions.begin() + 3 * s.count, app->contact.tractions.begin());
        app->contact.message = s.message;
        app->contact.force_seconds = s.force_seconds;
      }
      int fbw, fbh, w, h;
      glfwGetFramebufferSize(app->window, &fbw, &fbh);
      glfwGetWindowSize(app->window, &w, &h);
      draw_frame(*app, fbw, fbh, w, h);
      glfwSwapBuffers(app->window);
      app->graphics_rate.tick();
    }
    app->haptic_run = false;
    app->haptic_thread.join();
    if (o.quit_after > 0.0) {
      if (rate_samples > 0)
        std::cerr << "bemsurg-viewer: mean rates over the second half: graphics " << std::fixed << std::setprecision(1)
                  << graphics_sum / rate_samples << " Hz, haptic " << haptic_sum / rate_samples << " Hz; largest |F| "
                  << std::setprecision(4) << app->max_force_seen << " N\n";
      else
        std::cerr << "bemsurg-viewer: the table was not ready within --quit-after; no rates measured\n";
      const WorkerStatus st = app->worker.status();
      if (!st.error.empty()) std::cerr << "bemsurg-viewer: error shown in the window: " << st.error << "\n";
    }
    if (!o.record.empty() && app->recorder.on) {
      std::string err;
      if (app->recorder.actions.empty())
        std::cerr << "bemsurg-viewer: nothing to record: " << o.record << " not written\n";
      else if (!app->recorder.save(o.record, app->scene_input, err))
        std::cerr << "bemsurg-viewer: " << err << "\n";
      else
        std::cerr << "bemsurg-viewer: session recorded to " << o.record << "\n";
    }
  }
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(app->window);
  glfwTerminate();
  return code;
}

}  // namespace bemsurg::viewer
