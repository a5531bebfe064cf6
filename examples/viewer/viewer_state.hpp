// examples/viewer/viewer_state.hpp: what the parts of the viewer's window share (docs/viewer.md):
// the App (the GUI's choices, the devices and the haptic thread, the mouse interaction, the frame's
// field) and the function each part provides. viewer_app.cpp opens the window and runs the frame
// loop; frame_geometry.cpp turns the model and the contact into what is drawn; gui_panels.cpp
// draws the side panel; mouse_input.cpp turns the mouse and the keys into tool poses, cuts and
// camera moves; headless_playback.cpp plays an action script frame by frame.
#pragma once

#include <Eigen/Core>
#include <array>
#include <atomic>
#include <chrono>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "bemsurg/haptics/scripted_device.hpp"
#include "bemsurg/haptics/triple_buffer.hpp"
#include "bemsurg/mesh/bvh.hpp"
#include "bemsurg/timing.hpp"
#include "cut_session.hpp"
#include "model_worker.hpp"
#include "renderer.hpp"
#include "script_player.hpp"
#include "session_recorder.hpp"
#include "tool_stepper.hpp"
#include "viewer_app.hpp"

struct GLFWwindow;  // <GLFW/glfw3.h>, included only where a window is touched

namespace bemsurg::viewer {

using Clock = SteadyClock;

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

/// Everything the frame needs to draw the deformed model; built by the graphics thread.
struct FrameField {
  std::uint64_t version = 0;
  std::shared_ptr<const PhysicsState> physics;
  Eigen::VectorXd u;           // element displacements (3E)
  RowMatrixX3d vertices;       // deformed vertices
  RowMatrixX3d base_vertices;  // base state (gravity) vertices, for picking
  std::unique_ptr<TriangleBvh> base_bvh;
  std::vector<double> traction_magnitude;  // per element
  std::vector<char> in_contact;            // per element
};

/// A contact snapshot with room for 2048 contact elements (more grows it, off the haptic thread).
inline ContactSnapshot snapshot_prototype() {
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
  ParameterControls params;     // E, nu, gravity: from the loaded scene (model_worker.hpp)
  float gap_mm = -1.0f;         // cut gap width; negative: 0.2 x the mean element size of the model
  StepperOptions settings;
  std::string scene_input;
  std::string record_path = "session.json";
  std::string record_message;
  int active_slot = 0;  // the slot the mouse drives; slot 0 is pinned when this is 1

  // Devices and the haptic thread
  std::array<std::unique_ptr<MouseDevice>, kMaxTools> mice;
  std::array<std::unique_ptr<haptics::ScriptedDevice>, kMaxTools> scripted;
  haptics::TripleBuffer<StepperOptions> settings_buffer;
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
  SessionRecorder recorder;
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
inline double gap_width(const App& app) {
  if (app.gap_mm > 0.0f) return 1e-3 * app.gap_mm;
  const auto ph = app.worker.state();
  return ph ? 0.2 * ph->mean_edge : 0.0;
}

// frame_geometry.cpp: the field of the frame from the model and the contact, and the buffers drawn.
void update_field(App& app, const std::shared_ptr<const PhysicsState>& ph, const ContactSnapshot& c);
/// Tells the worker where the tools are, for the first response of the next cut steps.
void share_cut_reach(App& app, const std::shared_ptr<const PhysicsState>& ph, const ContactSnapshot& c);
void build_surface(const App& app, SurfaceBuffers& b, float& u_max, float& t_max);
void build_tools(const App& app, SurfaceBuffers& tools, SurfaceBuffers& arrows, std::vector<float>& lines);

// gui_panels.cpp: the side panel and the colour bar.
void gui(App& app, int width, int height);

// mouse_input.cpp: the mouse as tool and camera, the wheel and the keys.
void handle_mouse(App& app);
void scroll_callback(GLFWwindow* window, double xoff, double yoff);
void key_callback(GLFWwindow* window, int key, int scancode, int action, int mods);
/// Lets go of the pinned tool 1 and gives the mouse back to it.
void release_pinned_tool(App& app);

// viewer_app.cpp: one frame (field, buffers, 3D view, panel) into the current framebuffer.
void draw_frame(App& app, int fbw, int fbh, int width, int height);

// headless_playback.cpp: the script read and the model computed before the window opens (0, or
// the exit code), then every frame played and the pictures written (the exit code).
int prepare_headless(App& app, const ViewerOptions& o, std::unique_ptr<ScriptPlayer>& player);
int play_headless(App& app, ScriptPlayer& player, const ViewerOptions& o);

}  // namespace bemsurg::viewer
