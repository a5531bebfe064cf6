// examples/viewer/headless_playback.cpp: the viewer without a hand on it (docs/viewer.md, headless
// mode): an action script played deterministically, frame f showing the script at t = f / fps with
// one contact tick per frame, and the frames asked for written as PNGs. The script and the model
// are prepared before the display is touched, so bad input is reported as such on any machine.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>

#include "bemsurg/haptics/felt_force.hpp"
#include "viewer_state.hpp"

namespace bemsurg::viewer {

namespace {

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

/// The options headless mode needs: 0, or the exit code after saying what is missing.
int check_headless_options(const ViewerOptions& o) {
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
  return 0;
}

/// The scripted devices: first contacts found on the body resting under its own weight.
void make_scripted_devices(App& app, const ScriptPlayer& player) {
  const auto ph = app.worker.state();
  const TriangleBvh base(deformed_vertices(*ph->mesh, ph->table->base_displacement()), ph->mesh->faces());
  for (int s = 0; s < kMaxTools; ++s) {
    const int tool = player.tool_of_slot(s);
    if (tool < 0) continue;
    app.scripted[static_cast<std::size_t>(s)] = std::make_unique<haptics::ScriptedDevice>(
        player.keyframes(tool, base), player.script().tools[static_cast<std::size_t>(tool)].name, 1e9);
  }
}

/// The script's tool choices at time t into the stepper's settings (the panel shows the first).
void apply_slot_settings(App& app, const ScriptPlayer& player) {
  for (int s = 0; s < kMaxTools; ++s) {
    const int tool = player.tool_of_slot(s);
    if (tool < 0) continue;
    app.settings.slots[static_cast<std::size_t>(s)] = player.slot_settings(tool);
    if (s == 0) {  // the panel shows the first tool's choice
      app.tool = app.settings.slots[0].kind;
      app.tool_radius_mm = float(1000.0 * app.settings.slots[0].radius);
    }
  }
}

/// The frame's pictures: frame f when --shots names it, the last as --screenshot. False on a
/// failed write (said on stderr).
bool write_shots(const ViewerOptions& o, int f, int fbw, int fbh) {
  std::string error;
  bool ok = true;
  const bool last = f + 1 == o.frames;
  if (std::find(o.shots.begin(), o.shots.end(), f) != o.shots.end() && !write_png(shot_name(o.screenshot, f), fbw, fbh, error)) {
    std::cerr << "bemsurg-viewer: " << error << "\n";
    ok = false;
  }
  if (last && !write_png(o.screenshot, fbw, fbh, error)) {
    std::cerr << "bemsurg-viewer: " << error << "\n";
    ok = false;
  }
  return ok;
}

void print_summary(App& app, const ViewerOptions& o, const double* peak, const haptics::FeltForce& felt, int code) {
  std::cerr << "bemsurg-viewer: " << o.frames << " frames (" << o.frames / o.fps << " s of script); peak |F| tool 1 "
            << std::setprecision(4) << peak[0] << " N, tool 2 " << peak[1] << " N; " << app.cuts.summary() << "\n";
  // What a hand would feel (1 kHz ticks, model force above 10 % of its peak): check-viewer.sh reads this line.
  std::cerr << "bemsurg-viewer: felt: delivered force at least " << std::setprecision(4) << 100.0 * felt.min_delivered_ratio
            << " % of the model's, largest tick-to-tick change " << 100.0 * felt.max_tick_change_fraction << " % (tool "
            << felt.max_tick_change_tool + 1 << ", t = " << felt.max_tick_change_time << " s)\n";
  if (app.cuts.accepted() > 0) {
    const WorkerStatus st = app.worker.status();
    std::cerr << "bemsurg-viewer: tables after the last cut step: "
              << "first response in " << std::setprecision(1) << 1000.0 * st.last_cut_first_seconds << " ms, complete in "
              << 1000.0 * st.last_cut_update_seconds << " ms (" << app.worker.state()->mesh->num_elements() << " elements)\n";
  }
  if (app.contact.message[0]) std::cerr << "bemsurg-viewer: note: " << app.contact.message.data() << "\n";
  if (code == 0) std::cerr << "bemsurg-viewer: wrote " << o.screenshot << "\n";
}

}  // namespace

int prepare_headless(App& app, const ViewerOptions& o, std::unique_ptr<ScriptPlayer>& player) {
  if (const int code = check_headless_options(o)) return code;
  try {
    player = std::make_unique<ScriptPlayer>(load_action_script(o.script));
  } catch (const std::exception& e) {
    std::cerr << "bemsurg-viewer: " << e.what() << "\n";
    return 1;
  }
  for (const auto& w : player->script().warnings) std::cerr << "bemsurg-viewer: warning: " << w << "\n";
  std::string scene = o.scene;
  if (scene.empty() && !player->script().scene.empty()) scene = player->script().scene;
  app.scene_input = scene;
  app.worker.load(scene.empty() ? ModelWorker::default_scene_path() : scene);
  const auto t0 = Clock::now();
  app.worker.wait_idle();
  const WorkerStatus st = app.worker.status();
  if (st.phase == WorkerPhase::Failed || !app.worker.state() || !app.worker.state()->table) {
    std::cerr << "bemsurg-viewer: " << (st.error.empty() ? "the model could not be prepared" : st.error) << "\n";
    return 1;
  }
  try {
    make_scripted_devices(app, *player);
  } catch (const std::exception& e) {
    std::cerr << "bemsurg-viewer: " << e.what() << "\n";
    return 1;
  }
  std::cerr << "bemsurg-viewer: " << app.worker.state()->model_name << ": " << app.worker.state()->mesh->num_elements()
            << " elements, precomputed in " << std::fixed << std::setprecision(2) << seconds_since(t0) << " s\n";
  return 0;
}

int play_headless(App& app, ScriptPlayer& player, const ViewerOptions& o) {
  // Deterministic playback: frame f shows the script at t = f / fps; between frames the haptic
  // tick runs at 1 kHz as in the interactive viewer (its ticks at f / fps - k ms), so the force a
  // hand would feel is measured tick by tick (haptics/felt_force.hpp).
  haptics::HapticDevice* devices[kMaxTools] = {app.scripted[0].get(), app.scripted[1].get()};
  constexpr double kHapticPeriod = 1e-3;
  double t_prev = -1.0;
  double peak[kMaxTools] = {0.0, 0.0};
  haptics::FeltForceRecorder felt(kMaxTools, app.settings.force_limit);
  int fbw = 0, fbh = 0;
  int code = 0;
  if (!player.cuts_between(-1.0, o.frames / o.fps).empty()) {  // as a person picking the scalpel: ready before the clock runs
    app.worker.prepare_cuts();
    app.worker.wait_idle();
  }
  for (int f = 0; f < o.frames; ++f) {
    const double t = f / o.fps;
    glfwPollEvents();
    apply_slot_settings(app, player);
    for (const ScriptCut& c : player.cuts_between(t_prev, t))
      app.cuts.scripted_step(c.action, c.from, c.direction, app.worker, gap_width(app));
    const int ticks = f == 0 ? 1 : std::max(1, static_cast<int>(std::lround((t - t_prev) / kHapticPeriod)));
    for (int k = ticks - 1; k >= 0; --k) {
      const double tk = t - k * (f == 0 ? 0.0 : (t - t_prev) / ticks);
      app.stepper.tick(app.worker.state(), devices, app.settings, tk, f == 0 ? kHapticPeriod : (t - t_prev) / ticks, app.contact);
      for (int s = 0; s < kMaxTools; ++s) {
        const SlotSnapshot& slot = app.contact.slots[static_cast<std::size_t>(s)];
        peak[s] = std::max(peak[s], slot.force.norm());
        felt.add(s, tk, slot.force, slot.sent_force);
      }
    }
    t_prev = t;
    app.script_time = t;
    app.force_us.store(1e6 * app.contact.force_seconds);
    app.graphics_rate.tick();
    int w, h;
    glfwGetFramebufferSize(app.window, &fbw, &fbh);
    glfwGetWindowSize(app.window, &w, &h);
    draw_frame(app, fbw, fbh, w, h);
    if (!write_shots(o, f, fbw, fbh)) code = 1;
    glfwSwapBuffers(app.window);
  }
  print_summary(app, o, peak, felt.result(), code);
  return code;
}

}  // namespace bemsurg::viewer
