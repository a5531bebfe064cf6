// examples/viewer/gui_panels.cpp: the side panel (model and precomputation, forces and rates,
// tool, display, parameters, recording) and the colour bar, drawn with Dear ImGui every frame
// (docs/viewer.md describes the controls; see viewer_state.hpp).
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "viewer_state.hpp"

namespace bemsurg::viewer {

namespace {

const char* kToolNames[] = {"point", "sphere", "flat", "pinch", "retract (plate)", "cut"};

void colour_bar(App& app, int width, int height) {
  (void)height;
  if (app.colour_by == 0 || !app.field.physics) return;
  const float hi = app.colour_by == 1 ? app.u_hi : app.t_hi;
  ImGui::SetNextWindowPos(ImVec2(float(width) - 120.0f, 60.0f), ImGuiCond_Always);
  ImGui::SetNextWindowSize(ImVec2(110.0f, 300.0f), ImGuiCond_Always);
  ImGui::Begin("colour bar", nullptr,
               ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoScrollbar |
                   ImGuiWindowFlags_NoInputs);
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
                                ImColor(c0.x(), c0.y(), c0.z()), ImColor(c0.x(), c0.y(), c0.z()), ImColor(c1.x(), c1.y(), c1.z()),
                                ImColor(c1.x(), c1.y(), c1.z()));
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

// The model, the precomputation's progress, the cut tables, errors; loading a scene.
void model_panel(App& app, const WorkerStatus& st, const std::shared_ptr<const PhysicsState>& ph) {
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
    if (ph->table && st.first_response) {
      ImGui::TextColored(ImVec4(0.1f, 0.5f, 0.1f, 1.0f), "exact near the tools (first response, %.0f ms); completing the tables...",
                         1000.0 * st.last_cut_first_seconds);
    } else if (ph->table && st.tables_exact) {
      ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.1f, 0.5f, 0.1f, 1.0f));
      ImGui::TextWrapped("exact tables in after %d cut steps (delta update, %.0f ms)", ph->cuts, 1000.0 * st.last_cut_update_seconds);
      ImGui::PopStyleColor();
    } else {
      ImGui::TextColored(ImVec4(0.7f, 0.35f, 0.0f, 1.0f), "cut shown; exact tables being computed...");
    }
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

// Each tool's force and its recent history; the graphics and haptic rates.
void forces_panel(App& app, const std::shared_ptr<const PhysicsState>& ph) {
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
  ImGui::Text("arrow: %.0f mm = %.3g N",
              0.3 * 1000.0 * (ph ? (ph->mesh->bounding_box().col(1) - ph->mesh->bounding_box().col(0)).norm() : 0.0), app.max_force_seen);
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

// The tool the mouse drives, its size, pinning tool 1, the cut gap.
void tool_panel(App& app, const std::shared_ptr<const PhysicsState>& ph) {
  int t = static_cast<int>(app.tool);
  for (int i = 0; i < 6; ++i) {
    if (i % 3) ImGui::SameLine();
    ImGui::RadioButton(kToolNames[i], &t, i);
  }
  // Picking the scalpel readies the first cut steps' storage in the background (ModelWorker::prepare_cuts).
  if (static_cast<ToolKind>(t) == ToolKind::Cut && app.tool != ToolKind::Cut) app.worker.prepare_cuts();
  app.tool = static_cast<ToolKind>(t);
  if (app.tool == ToolKind::Sphere || app.tool == ToolKind::Flat || app.tool == ToolKind::Pinch || app.tool == ToolKind::Plate) {
    const double def =
        ph ? (app.tool == ToolKind::Plate ? default_plate_size(ph->mean_edge) : default_tool_radius(app.tool, ph->mean_edge)) : 0.0;
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
    if (ImGui::Button("Release pinned tool (Esc)")) release_pinned_tool(app);
  }
  if (app.tool == ToolKind::Cut) {
    if (app.gap_mm < 0.0f && ph) app.gap_mm = float(0.2 * 1000.0 * ph->mean_edge);
    ImGui::SliderFloat("cut gap width (mm)", &app.gap_mm, 0.2f, 5.0f, "%.2f");
    ImGui::TextWrapped("%s", app.cuts.status_line().c_str());
  }
}

// Solid, wireframe or points; what the colours show.
void display_panel(App& app) {
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

// E, nu, gravity (E rescales without recomputing where it can), the force to the device.
void parameters_panel(App& app, const WorkerStatus& st) {
  ParameterControls& c = app.params;  // the loaded scene's values, then the user's (gui() follows loads)
  ImGui::SliderFloat("E (kPa)", &c.young_kpa, c.young_min(), c.young_max(), "%.2f", ImGuiSliderFlags_Logarithmic);
  if (ImGui::IsItemDeactivatedAfterEdit()) app.worker.set_young_modulus(1000.0 * c.young_kpa);
  ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
  ImGui::TextWrapped(st.rescale_exact ? "E rescales forces and the sag at once, without recomputing (linear elasticity)"
                                      : "E recomputes: this scene prescribes nonzero displacements");
  ImGui::PopStyleColor();
  ImGui::SliderFloat("nu", &c.poisson, c.poisson_min(), c.poisson_max(), "%.3f");
  if (ImGui::IsItemDeactivatedAfterEdit()) app.worker.set_poisson_ratio(c.poisson);
  ImGui::TextDisabled("nu recomputes the table in the background");
  if (ImGui::Checkbox("gravity", &c.gravity)) app.worker.set_gravity(c.gravity);
  if (!c.scene_gravity) ImGui::TextDisabled("the scene has no gravity: the switch changes nothing");
  ImGui::Checkbox("haptic force to device", &app.settings.haptic_force);
  float limit = float(app.settings.force_limit);
  ImGui::SliderFloat("force limit (N)", &limit, 0.1f, 10.0f, "%.2f");
  app.settings.force_limit = limit;
}

// Records the mouse session as an action script (docs/viewer.md).
void record_panel(App& app) {
  ImGui::InputText("file", &app.record_path);
  if (!app.recorder.on) {
    if (ImGui::Button("Start recording")) {
      app.recorder = SessionRecorder{};
      app.recorder.on = true;
      app.record_message = "recording...";
    }
  } else if (ImGui::Button("Stop and save")) {
    app.recorder.on = false;
    std::string err;
    app.record_message =
        app.recorder.save(app.record_path, app.scene_input, err) ? "saved " + app.record_path + ": replay with --script" : err;
  }
  ImGui::TextWrapped("%s", app.record_message.c_str());
}

}  // namespace

void gui(App& app, int width, int height) {
  app.params.follow(app.worker);  // a scene loaded since the last frame: the controls start from it
  const WorkerStatus st = app.worker.status();
  const auto ph = app.field.physics;
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(380, float(height) - 16.0f), ImGuiCond_FirstUseEver);
  ImGui::Begin("bemsurg");
  if (ImGui::CollapsingHeader("Model", ImGuiTreeNodeFlags_DefaultOpen)) model_panel(app, st, ph);
  if (ImGui::CollapsingHeader("Forces", ImGuiTreeNodeFlags_DefaultOpen)) forces_panel(app, ph);
  if (ImGui::CollapsingHeader("Tool", ImGuiTreeNodeFlags_DefaultOpen)) tool_panel(app, ph);
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) display_panel(app);
  if (ImGui::CollapsingHeader("Parameters", ImGuiTreeNodeFlags_DefaultOpen)) parameters_panel(app, st);
  if (ImGui::CollapsingHeader("Record session")) record_panel(app);
  ImGui::End();
  colour_bar(app, width, height);
}

}  // namespace bemsurg::viewer
