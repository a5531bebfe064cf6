// examples/viewer/viewer_app.cpp: the viewer's window and frame loop (see viewer_app.hpp and
// docs/viewer.md): opens the OpenGL window and Dear ImGui, runs the haptic thread (the mice as
// devices at 1 kHz) beside the graphics loop, draws each frame, and shuts everything down. The
// parts it runs are in viewer_state.hpp.
#include "viewer_app.hpp"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <pthread.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iomanip>
#include <iostream>

#include "bemsurg/haptics/background_threads.hpp"
#include "bemsurg/haptics/haptic_loop.hpp"
#include "viewer_state.hpp"

namespace bemsurg::viewer {

namespace {

void haptic_loop(App* app) {
  // 1 kHz: read the mice, solve the contact, publish the snapshot (docs/design.md §9). SCHED_FIFO
  // where the machine grants it, as the haptics module's loop asks (refused quietly otherwise).
  sched_param rt{};
  rt.sched_priority = haptics::HapticLoopOptions{}.realtime_priority;
  pthread_setschedparam(pthread_self(), SCHED_FIFO, &rt);
  haptics::HapticDevice* devices[kMaxTools];
  for (int i = 0; i < kMaxTools; ++i) devices[i] = app->mice[static_cast<std::size_t>(i)].get();
  auto next = Clock::now();
  const auto period = std::chrono::microseconds(1000);
  while (app->haptic_run.load(std::memory_order_relaxed)) {
    app->settings_buffer.acquire();
    const auto physics = app->worker.state();
    app->stepper.tick(physics, devices, app->settings_buffer.front(), seconds_since(app->started), 1e-3, app->snapshots.back());
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

GLFWwindow* open_window(const ViewerOptions& o, std::string& error) {
  glfwSetErrorCallback([](int, const char* text) { std::cerr << "bemsurg-viewer: GLFW: " << text << "\n"; });
  if (!glfwInit()) {
    error = "no display: GLFW could not open one (DISPLAY is " + std::string(std::getenv("DISPLAY") ? std::getenv("DISPLAY") : "not set") +
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
    error =
        "could not create an OpenGL 3.3 core window on this display; without a GPU or screen run under "
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

/// Dear ImGui on the window, the mouse wheel and key callbacks, the renderer's programs.
bool init_gui(App& app, std::string& error) {
  glfwSetWindowUserPointer(app.window, &app);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsLight();
  ImGui_ImplGlfw_InitForOpenGL(app.window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  glfwSetScrollCallback(app.window, scroll_callback);
  glfwSetKeyCallback(app.window, key_callback);
  return app.renderer.init(error);
}

void shut_down(App& app) {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(app.window);
  glfwTerminate();
}

/// The haptic thread's newest snapshot, copied for this frame (the buffers only grow).
void take_contact_snapshot(App& app) {
  if (!app.snapshots.acquire()) return;
  const ContactSnapshot& s = app.snapshots.front();
  app.contact.physics_version = s.physics_version;
  app.contact.slots = s.slots;
  app.contact.count = s.count;
  if (app.contact.elements.size() < s.elements.size()) {
    app.contact.elements.resize(s.elements.size());
    app.contact.tractions.resize(s.tractions.size());
  }
  std::copy(s.elements.begin(), s.elements.begin() + s.count, app.contact.elements.begin());
  std::copy(s.tractions.begin(), s.tractions.begin() + 3 * s.count, app.contact.tractions.begin());
  app.contact.message = s.message;
  app.contact.force_seconds = s.force_seconds;
}

/// --quit-after: the mean rates over the second half of the run, and any error the window showed.
void print_rates(App& app, double graphics_sum, double haptic_sum, int rate_samples) {
  if (rate_samples > 0)
    std::cerr << "bemsurg-viewer: mean rates over the second half: graphics " << std::fixed << std::setprecision(1)
              << graphics_sum / rate_samples << " Hz, haptic " << haptic_sum / rate_samples << " Hz; largest |F| " << std::setprecision(4)
              << app.max_force_seen << " N\n";
  else
    std::cerr << "bemsurg-viewer: the table was not ready within --quit-after; no rates measured\n";
  const WorkerStatus st = app.worker.status();
  if (!st.error.empty()) std::cerr << "bemsurg-viewer: error shown in the window: " << st.error << "\n";
}

/// --record FILE: the session recorded from the start, saved at exit.
void save_recording(App& app, const std::string& path) {
  std::string err;
  if (app.recorder.actions.empty())
    std::cerr << "bemsurg-viewer: nothing to record: " << path << " not written\n";
  else if (!app.recorder.save(path, app.scene_input, err))
    std::cerr << "bemsurg-viewer: " << err << "\n";
  else
    std::cerr << "bemsurg-viewer: session recorded to " << path << "\n";
}

/// The window with a hand on the mouse: the haptic thread beside the graphics loop until the
/// window closes (or --quit-after). Returns the exit code.
int run_interactive(App& app, const ViewerOptions& o) {
  if (!o.record.empty()) {  // --record FILE: record from the start, save at exit
    app.recorder.on = true;
    app.record_path = o.record;
    app.record_message = "recording to " + o.record + " (saved at exit)";
  }
  // While the haptic thread runs, background work (the worker's tables, cut updates) leaves it a
  // core: cores - 1 threads for OpenBLAS and the worker's OpenMP regions (docs/haptics.md).
  const haptics::BackgroundThreadBudget budget;
  app.worker.set_thread_budget(budget.threads());
  app.haptic_run = true;
  app.haptic_thread = std::thread(haptic_loop, &app);
  const auto opened = Clock::now();
  double graphics_sum = 0.0, haptic_sum = 0.0;
  int rate_samples = 0;
  while (!glfwWindowShouldClose(app.window)) {
    if (o.quit_after > 0.0) {
      const double t = seconds_since(opened);
      if (t > 0.5 * o.quit_after && app.field.physics && app.field.physics->table) {
        graphics_sum += app.graphics_rate.rate();
        haptic_sum += app.haptic_rate.rate();
        ++rate_samples;
      }
      if (t > o.quit_after) break;
    }
    glfwPollEvents();
    handle_mouse(app);
    app.settings_buffer.back() = app.settings;
    app.settings_buffer.publish();
    take_contact_snapshot(app);
    int fbw, fbh, w, h;
    glfwGetFramebufferSize(app.window, &fbw, &fbh);
    glfwGetWindowSize(app.window, &w, &h);
    draw_frame(app, fbw, fbh, w, h);
    glfwSwapBuffers(app.window);
    app.graphics_rate.tick();
  }
  app.haptic_run = false;
  app.haptic_thread.join();
  app.worker.set_thread_budget(0);
  if (o.quit_after > 0.0) print_rates(app, graphics_sum, haptic_sum, rate_samples);
  if (!o.record.empty() && app.recorder.on) save_recording(app, o.record);
  return 0;
}

}  // namespace

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
  share_cut_reach(app, ph, app.contact);
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

int run_viewer(const ViewerOptions& o) {
  auto app = std::make_unique<App>();
  app->options = o;
  app->scene_input = o.scene;

  // Headless: read the script and compute the model before touching the display, so bad input is
  // reported as such (and exits non-zero) on any machine.
  std::unique_ptr<ScriptPlayer> player;
  if (o.headless) {
    if (const int code = prepare_headless(*app, o, player)) return code;
  } else {
    app->worker.load(o.scene.empty() ? ModelWorker::default_scene_path() : o.scene);
  }

  std::string error;
  app->window = open_window(o, error);
  if (!app->window) {
    std::cerr << "bemsurg-viewer: " << error << "\n";
    return 3;
  }
  if (!init_gui(*app, error)) {
    std::cerr << "bemsurg-viewer: " << error << "\n";
    return 3;
  }
  const int code = o.headless ? play_headless(*app, *player, o) : run_interactive(*app, o);
  shut_down(*app);
  return code;
}

}  // namespace bemsurg::viewer
