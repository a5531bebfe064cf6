// examples/viewer/mouse_input.cpp: the mouse as a haptic device and a scalpel, and the camera
// (docs/viewer.md, controls). A left press on the model engages the chosen tool where it hit
// (drag down to press in, sideways to slide; pinch and plate pull where the mouse goes, the wheel
// pushes along the approach) or starts a cut path; right-drag orbits, middle- or shift-right-drag
// pans, the wheel zooms. A recording session turns presses, moves and releases into actions.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "viewer_state.hpp"

namespace bemsurg::viewer {

namespace {

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
    const SlotOptions& slot = app.settings.slots[static_cast<std::size_t>(app.active_slot)];
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

/// A recorded press or pinch where the tool met the body at `p` (surface normal `n`).
void record_press(App& app, const SlotOptions& s, const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  const double radius = app.tool == ToolKind::Point ? 0.0
                        : s.radius > 0.0            ? s.radius
                                                    : default_tool_radius(app.tool, app.field.physics->mean_edge);
  app.recorder.last_move = app.recorder.now();  // the next move starts after the press
  if (app.tool == ToolKind::Plate) {
    app.record_message = "a retractor plate is not recorded (scripts give a plate its own polygon)";
    return;
  }
  app.recorded_tool = app.recorder.tool_name(app.active_slot, app.tool, radius);
  const char* type = app.tool == ToolKind::Pinch ? "pinch" : "press";
  nlohmann::json a = {
      {"time", app.recorder.now()}, {"tool", app.recorded_tool}, {"type", type}, {"at", vec_json(p)}, {"direction", vec_json(-n)}};
  if (app.tool != ToolKind::Pinch) a["depth"] = 0.0;
  app.recorder.actions.push_back(a);
}

/// Left button down on the model: the cut path starts, or the active slot's tool engages there.
void begin_press(App& app, double x, double y) {
  Eigen::Vector3d p, n;
  if (!pick(app, x, y, p, n)) return;
  app.pressing = true;
  app.press_x = x;
  app.press_y = y;
  app.wheel_depth = 0.0;
  app.press_point = p;
  app.press_dir = -n;
  if (app.tool == ToolKind::Cut) {
    app.cuts.begin_drag(p, app.worker, gap_width(app));
    return;
  }
  SlotOptions& s = app.settings.slots[static_cast<std::size_t>(app.active_slot)];
  s.kind = app.tool;
  s.radius = app.tool == ToolKind::Plate ? 0.0 : 1e-3 * app.tool_radius_mm;
  s.plate_size = app.tool == ToolKind::Plate ? 1e-3 * app.tool_radius_mm : 0.0;
  if (app.tool == ToolKind::Point) s.radius = 0.0;
  if (app.recorder.on) record_press(app, s, p, n);
  mouse_to_device(app, x, y, true);
}

/// Left button up: the cut path ends (the cut is applied), or the tool is released.
void end_press(App& app, double x, double y) {
  app.pressing = false;
  if (app.tool == ToolKind::Cut) {
    app.cuts.end_drag();
    return;
  }
  mouse_to_device(app, x, y, false);
  if (app.recorder.on && !app.recorded_tool.empty() && app.tool != ToolKind::Plate)
    app.recorder.actions.push_back(
        {{"time", std::max(app.recorder.now(), app.recorder.last_move + 0.1001)}, {"tool", app.recorded_tool}, {"type", "release"}});
}

/// Pan (middle, or shift + right) and orbit (right) while no tool is pressed.
void move_camera(App& app, double x, double y, int h) {
  const ImGuiIO& io = ImGui::GetIO();
  const bool right = glfwGetMouseButton(app.window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
  const bool middle = glfwGetMouseButton(app.window, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS;
  const bool shift = glfwGetKey(app.window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS;
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

}  // namespace

void handle_mouse(App& app) {
  ImGuiIO& io = ImGui::GetIO();
  double x, y;
  glfwGetCursorPos(app.window, &x, &y);
  const bool left = glfwGetMouseButton(app.window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
  int w, h;
  glfwGetWindowSize(app.window, &w, &h);
  // The panel keeps the mouse unless a press, orbit or pan began on the model.
  if (!io.WantCaptureMouse || app.pressing || app.orbiting || app.panning) {
    if (left && !app.pressing && !io.WantCaptureMouse) {
      begin_press(app, x, y);
    } else if (left && app.pressing) {
      if (app.tool == ToolKind::Cut) {
        Eigen::Vector3d p, n;
        if (pick(app, x, y, p, n)) app.cuts.drag_to(p, app.worker, gap_width(app));
      } else {
        mouse_to_device(app, x, y, true);
      }
    } else if (!left && app.pressing) {
      end_press(app, x, y);
    }
    if (!app.pressing) move_camera(app, x, y, h);
  }
  app.last_x = x;
  app.last_y = y;
}

void release_pinned_tool(App& app) {
  haptics::DeviceState s = app.mice[0]->read(0.0);
  s.buttons = 0;
  app.mice[0]->set_state(s);
  app.active_slot = 0;
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
  if (key == GLFW_KEY_ESCAPE && app->active_slot == 1) release_pinned_tool(*app);
}

}  // namespace bemsurg::viewer
