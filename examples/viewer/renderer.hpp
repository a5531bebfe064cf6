// examples/viewer/renderer.hpp: OpenGL 3.3 core drawing for the viewer: the surface as solid
// shaded, wireframe or points (the paper's three display modes, Wang et al. 2007 §6), coloured
// plainly or by a scalar (|u| or |t|) through one colour map that the colour bar shares, plus
// flat-coloured triangles for tools and force arrows. Also the orbit camera.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace bemsurg::viewer {

enum class RenderMode { Solid, Wireframe, Points };

/// The colour map of the surface and the colour bar: s in [0, 1] -> RGB (blue, cyan, green,
/// yellow, red).
Eigen::Vector3f colour_map(float s);

struct OrbitCamera {
  Eigen::Vector3f target = Eigen::Vector3f::Zero();
  float yaw = 0.6f, pitch = 0.55f, distance = 0.3f;
  float fov_y = 0.7f;  // radians
  Eigen::Vector3f home_target = Eigen::Vector3f::Zero();
  float home_distance = 0.3f;
  float shift_ndc = 0.0f;  // the view's centre moved right by this (NDC units) to clear the side panel

  void fit(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi);
  void reset();
  Eigen::Vector3f eye() const;
  Eigen::Matrix4f view() const;
  Eigen::Matrix4f projection(float aspect) const;
  /// World ray through the pixel (x, y) (origin top-left) of a w x h viewport.
  void ray(double x, double y, int w, int h, Eigen::Vector3f& origin, Eigen::Vector3f& direction) const;
  Eigen::Vector3f right() const;
  Eigen::Vector3f up() const;
  void orbit(float dx, float dy);
  void pan(float dx, float dy, int h);
  void zoom(float steps);
};

/// A triangle soup: 3 vertices per triangle, per-vertex position, normal, scalar and highlight.
struct SurfaceBuffers {
  std::vector<float> positions, normals, scalars, highlight;
  void clear() {
    positions.clear();
    normals.clear();
    scalars.clear();
    highlight.clear();
  }
};

class Renderer {
 public:
  Renderer() = default;
  ~Renderer();
  /// Compiles the shaders; false with a message when the context cannot (shown in the window).
  bool init(std::string& error);
  void begin_frame(int width, int height);
  void set_camera(const Eigen::Matrix4f& view_projection, const Eigen::Vector3f& eye);
  /// colour_by: false = tissue colour; true = colour_map((scalar - lo) / (hi - lo)).
  void draw_surface(const SurfaceBuffers& b, RenderMode mode, bool colour_by, float lo, float hi);
  /// Flat-shaded triangles in one colour (tools, arrows), lit like the surface.
  void draw_solid(const SurfaceBuffers& b, const Eigen::Vector3f& colour, float alpha = 1.0f);
  /// Line segments (pairs of points) in one colour.
  void draw_lines(const std::vector<float>& points, const Eigen::Vector3f& colour);

 private:
  void upload(const SurfaceBuffers& b);
  unsigned program_ = 0, vao_ = 0, vbo_[4] = {0, 0, 0, 0};
  int u_mvp_ = -1, u_eye_ = -1, u_mode_ = -1, u_lo_ = -1, u_hi_ = -1, u_colour_ = -1, u_alpha_ = -1, u_lit_ = -1;
  Eigen::Matrix4f vp_ = Eigen::Matrix4f::Identity();
  Eigen::Vector3f eye_ = Eigen::Vector3f::Zero();
};

/// Geometry helpers appending to a soup: a sphere, a cylinder between two points, a cone, a disc.
void append_sphere(SurfaceBuffers& b, const Eigen::Vector3f& centre, float radius, int rings = 10, int segments = 16);
void append_cylinder(SurfaceBuffers& b, const Eigen::Vector3f& a, const Eigen::Vector3f& c, float radius, int segments = 12);
void append_cone(SurfaceBuffers& b, const Eigen::Vector3f& base, const Eigen::Vector3f& apex, float radius, int segments = 16);
void append_disc(SurfaceBuffers& b, const Eigen::Vector3f& centre, const Eigen::Vector3f& normal, float radius, int segments = 24);
void append_quad(SurfaceBuffers& b, const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
                 const Eigen::Vector3f& p3);
/// An arrow from `from` along `vec` (shaft and head), for the contact force.
void append_arrow(SurfaceBuffers& b, const Eigen::Vector3f& from, const Eigen::Vector3f& vec, float radius);

}  // namespace bemsurg::viewer
