// examples/viewer/renderer.cpp: OpenGL 3.3 core drawing (see renderer.hpp). GL entry points come
// straight from libOpenGL (GLVND exports the core functions), so no loader is needed.
#include "renderer.hpp"

#include "bemsurg/mesh/geometry.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>

namespace bemsurg::viewer {

namespace {

const char* kVertex = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in float scalar;
layout(location = 3) in float highlight;
uniform mat4 mvp;
out vec3 v_position;
out vec3 v_normal;
out float v_scalar;
out float v_highlight;
void main() {
  v_position = position;
  v_normal = normal;
  v_scalar = scalar;
  v_highlight = highlight;
  gl_Position = mvp * vec4(position, 1.0);
  gl_PointSize = 3.0;
}
)";

const char* kFragment = R"(#version 330 core
in vec3 v_position;
in vec3 v_normal;
in float v_scalar;
in float v_highlight;
uniform vec3 eye;
uniform int mode;      // 0: uniform colour, 1: colour map, 2: tissue with supports
uniform float lo;
uniform float hi;
uniform vec3 colour;
uniform float alpha;
uniform int lit;
out vec4 frag;
vec3 cmap(float s) {
  s = clamp(s, 0.0, 1.0);
  vec3 c0 = vec3(0.10, 0.15, 0.60), c1 = vec3(0.10, 0.65, 0.90), c2 = vec3(0.20, 0.80, 0.30),
       c3 = vec3(0.95, 0.85, 0.15), c4 = vec3(0.85, 0.12, 0.10);
  float t = s * 4.0;
  if (t < 1.0) return mix(c0, c1, t);
  if (t < 2.0) return mix(c1, c2, t - 1.0);
  if (t < 3.0) return mix(c2, c3, t - 2.0);
  return mix(c3, c4, t - 3.0);
}
void main() {
  vec3 base = colour;
  if (mode == 1) base = cmap((v_scalar - lo) / max(hi - lo, 1e-30));
  if (mode == 2) base = mix(vec3(0.86, 0.56, 0.52), vec3(0.45, 0.45, 0.50), clamp(v_scalar, 0.0, 1.0));
  // highlight 1: in contact with a tool (orange); 2: a cut wall (dark red).
  if (v_highlight > 1.5) base = mix(base, vec3(0.55, 0.04, 0.10), 0.8);
  else base = mix(base, vec3(1.0, 0.55, 0.0), clamp(v_highlight, 0.0, 1.0) * 0.7);
  vec3 c = base;
  if (lit == 1) {
    vec3 n = normalize(v_normal);
    vec3 l = normalize(eye - v_position);
    float d = abs(dot(n, l));
    vec3 h = normalize(l + normalize(eye - v_position));
    float sp = pow(max(abs(dot(n, h)), 0.0), 40.0);
    c = base * (0.30 + 0.70 * d) + vec3(0.12) * sp;
  }
  frag = vec4(c, alpha);
}
)";

unsigned compile(unsigned kind, const char* src, std::string& error) {
  const unsigned s = glCreateShader(kind);
  glShaderSource(s, 1, &src, nullptr);
  glCompileShader(s);
  int ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024];
    glGetShaderInfoLog(s, sizeof log, nullptr, log);
    error = std::string("shader compilation failed: ") + log;
    return 0;
  }
  return s;
}

}  // namespace

Eigen::Vector3f colour_map(float s) {
  s = std::clamp(s, 0.0f, 1.0f);
  const Eigen::Vector3f c[5] = {
      {0.10f, 0.15f, 0.60f}, {0.10f, 0.65f, 0.90f}, {0.20f, 0.80f, 0.30f}, {0.95f, 0.85f, 0.15f}, {0.85f, 0.12f, 0.10f}};
  const float t = s * 4.0f;
  const int i = std::min(3, static_cast<int>(t));
  return c[i] + (t - float(i)) * (c[i + 1] - c[i]);
}

// ---- camera ----------------------------------------------------------------------------------

void OrbitCamera::fit(const Eigen::Vector3f& lo, const Eigen::Vector3f& hi) {
  home_target = 0.5f * (lo + hi);
  home_distance = 1.25f * (hi - lo).norm() / (2.0f * std::tan(0.5f * fov_y)) + 1e-6f;
  reset();
}

void OrbitCamera::reset() {
  target = home_target;
  distance = home_distance;
  yaw = 0.6f;
  pitch = 0.55f;
}

Eigen::Vector3f OrbitCamera::eye() const {
  const Eigen::Vector3f d(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  return target + distance * d;
}

Eigen::Vector3f OrbitCamera::right() const { return Eigen::Vector3f(-std::sin(yaw), std::cos(yaw), 0.0f); }

Eigen::Vector3f OrbitCamera::up() const {
  const Eigen::Vector3f f = (target - eye()).normalized();
  return right().cross(f).normalized();
}

Eigen::Matrix4f OrbitCamera::view() const {
  const Eigen::Vector3f e = eye();
  const Eigen::Vector3f f = (target - e).normalized();
  const Eigen::Vector3f r = f.cross(Eigen::Vector3f::UnitZ()).normalized();
  const Eigen::Vector3f u = r.cross(f);
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  m.block<1, 3>(0, 0) = r.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = -f.transpose();
  m(0, 3) = -r.dot(e);
  m(1, 3) = -u.dot(e);
  m(2, 3) = f.dot(e);
  return m;
}

Eigen::Matrix4f OrbitCamera::projection(float aspect) const {
  const float n = 0.01f * distance, f = 20.0f * distance;
  const float t = 1.0f / std::tan(0.5f * fov_y);
  Eigen::Matrix4f p = Eigen::Matrix4f::Zero();
  p(0, 0) = t / aspect;
  p(0, 2) = -shift_ndc;
  p(1, 1) = t;
  p(2, 2) = (f + n) / (n - f);
  p(2, 3) = 2.0f * f * n / (n - f);
  p(3, 2) = -1.0f;
  return p;
}

void OrbitCamera::ray(double x, double y, int w, int h, Eigen::Vector3f& origin, Eigen::Vector3f& direction) const {
  const Eigen::Vector3f e = eye();
  const Eigen::Vector3f f = (target - e).normalized();
  const Eigen::Vector3f r = f.cross(Eigen::Vector3f::UnitZ()).normalized();
  const Eigen::Vector3f u = r.cross(f);
  const float t = std::tan(0.5f * fov_y);
  const float aspect = float(w) / float(std::max(h, 1));
  const float px = (float(2.0 * x / w - 1.0) - shift_ndc) * t * aspect;
  const float py = float(1.0 - 2.0 * y / h) * t;
  origin = e;
  direction = (f + px * r + py * u).normalized();
}

void OrbitCamera::orbit(float dx, float dy) {
  yaw -= 0.008f * dx;
  pitch = std::clamp(pitch + 0.008f * dy, -1.5f, 1.5f);
}

void OrbitCamera::pan(float dx, float dy, int h) {
  const float s = 2.0f * distance * std::tan(0.5f * fov_y) / float(std::max(h, 1));
  target += s * (-dx * right() + dy * up());
}

void OrbitCamera::zoom(float steps) { distance *= std::pow(0.9f, steps); }

// ---- renderer --------------------------------------------------------------------------------

Renderer::~Renderer() {
  if (vao_) glDeleteVertexArrays(1, &vao_);
  if (vbo_[0]) glDeleteBuffers(4, vbo_);
  if (program_) glDeleteProgram(program_);
}

bool Renderer::init(std::string& error) {
  const unsigned vs = compile(GL_VERTEX_SHADER, kVertex, error);
  if (!vs) return false;
  const unsigned fs = compile(GL_FRAGMENT_SHADER, kFragment, error);
  if (!fs) return false;
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  int ok = 0;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  glDeleteShader(vs);
  glDeleteShader(fs);
  if (!ok) {
    error = "shader link failed";
    return false;
  }
  u_mvp_ = glGetUniformLocation(program_, "mvp");
  u_eye_ = glGetUniformLocation(program_, "eye");
  u_mode_ = glGetUniformLocation(program_, "mode");
  u_lo_ = glGetUniformLocation(program_, "lo");
  u_hi_ = glGetUniformLocation(program_, "hi");
  u_colour_ = glGetUniformLocation(program_, "colour");
  u_alpha_ = glGetUniformLocation(program_, "alpha");
  u_lit_ = glGetUniformLocation(program_, "lit");
  glGenVertexArrays(1, &vao_);
  glGenBuffers(4, vbo_);
  return true;
}

void Renderer::begin_frame(int width, int height) {
  glViewport(0, 0, width, height);
  glClearColor(0.93f, 0.94f, 0.96f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_PROGRAM_POINT_SIZE);
}

void Renderer::set_camera(const Eigen::Matrix4f& vp, const Eigen::Vector3f& eye) {
  vp_ = vp;
  eye_ = eye;
}

void Renderer::upload(const SurfaceBuffers& b) {
  const std::size_t n = b.positions.size() / 3;
  glBindVertexArray(vao_);
  const std::vector<float>* data[4] = {&b.positions, &b.normals, &b.scalars, &b.highlight};
  const int width[4] = {3, 3, 1, 1};
  for (int i = 0; i < 4; ++i) {
    glBindBuffer(GL_ARRAY_BUFFER, vbo_[i]);
    if (data[i]->size() >= n * std::size_t(width[i])) {
      glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(n * width[i] * sizeof(float)), data[i]->data(), GL_STREAM_DRAW);
      glEnableVertexAttribArray(GLuint(i));
      glVertexAttribPointer(GLuint(i), width[i], GL_FLOAT, GL_FALSE, 0, nullptr);
    } else {
      glDisableVertexAttribArray(GLuint(i));
      const float zero[3] = {0.0f, 0.0f, 1.0f};
      if (width[i] == 3)
        glVertexAttrib3fv(GLuint(i), zero);
      else
        glVertexAttrib1f(GLuint(i), 0.0f);
    }
  }
}

void Renderer::draw_surface(const SurfaceBuffers& b, RenderMode mode, bool colour_by, float lo, float hi) {
  if (b.positions.empty()) return;
  glUseProgram(program_);
  glUniformMatrix4fv(u_mvp_, 1, GL_FALSE, vp_.data());
  glUniform3f(u_eye_, eye_.x(), eye_.y(), eye_.z());
  glUniform1i(u_mode_, colour_by ? 1 : 2);
  glUniform1f(u_lo_, lo);
  glUniform1f(u_hi_, hi);
  glUniform3f(u_colour_, 0.2f, 0.2f, 0.25f);
  glUniform1f(u_alpha_, 1.0f);
  glUniform1i(u_lit_, 1);
  upload(b);
  const GLsizei n = GLsizei(b.positions.size() / 3);
  switch (mode) {
    case RenderMode::Solid: glDrawArrays(GL_TRIANGLES, 0, n); break;
    case RenderMode::Wireframe:
      glUniform1i(u_lit_, 0);
      glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
      glDrawArrays(GL_TRIANGLES, 0, n);
      glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
      break;
    case RenderMode::Points:
      glUniform1i(u_lit_, 0);
      glDrawArrays(GL_POINTS, 0, n);
      break;
  }
  glBindVertexArray(0);
}

void Renderer::draw_solid(const SurfaceBuffers& b, const Eigen::Vector3f& colour, float alpha) {
  if (b.positions.empty()) return;
  glUseProgram(program_);
  glUniformMatrix4fv(u_mvp_, 1, GL_FALSE, vp_.data());
  glUniform3f(u_eye_, eye_.x(), eye_.y(), eye_.z());
  glUniform1i(u_mode_, 0);
  glUniform3f(u_colour_, colour.x(), colour.y(), colour.z());
  glUniform1f(u_alpha_, alpha);
  glUniform1i(u_lit_, 1);
  if (alpha < 1.0f) {
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  }
  upload(b);
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(b.positions.size() / 3));
  glDisable(GL_BLEND);
  glBindVertexArray(0);
}

void Renderer::draw_lines(const std::vector<float>& points, const Eigen::Vector3f& colour) {
  if (points.empty()) return;
  SurfaceBuffers b;
  b.positions = points;
  glUseProgram(program_);
  glUniformMatrix4fv(u_mvp_, 1, GL_FALSE, vp_.data());
  glUniform1i(u_mode_, 0);
  glUniform3f(u_colour_, colour.x(), colour.y(), colour.z());
  glUniform1f(u_alpha_, 1.0f);
  glUniform1i(u_lit_, 0);
  upload(b);
  glDrawArrays(GL_LINES, 0, GLsizei(points.size() / 3));
  glBindVertexArray(0);
}

// ---- geometry helpers ------------------------------------------------------------------------

namespace {

void push_vertex(SurfaceBuffers& b, const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  b.positions.insert(b.positions.end(), {p.x(), p.y(), p.z()});
  b.normals.insert(b.normals.end(), {n.x(), n.y(), n.z()});
}

void push_triangle(SurfaceBuffers& b, const Eigen::Vector3f& a, const Eigen::Vector3f& c, const Eigen::Vector3f& d) {
  Eigen::Vector3f n = (c - a).cross(d - a);
  if (n.norm() > 0.0f) n.normalize();
  push_vertex(b, a, n);
  push_vertex(b, c, n);
  push_vertex(b, d, n);
}

void frame(const Eigen::Vector3f& axis, Eigen::Vector3f& u, Eigen::Vector3f& v) {
  u = axis.unitOrthogonal();
  v = axis.cross(u).normalized();
}

}  // namespace

void append_sphere(SurfaceBuffers& b, const Eigen::Vector3f& c, float r, int rings, int segments) {
  const float pi = static_cast<float>(bemsurg::numbers::pi);
  auto point = [&](int i, int j) {
    const float th = pi * float(i) / float(rings), ph = 2.0f * pi * float(j) / float(segments);
    return Eigen::Vector3f(c + r * Eigen::Vector3f(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
  };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const Eigen::Vector3f p00 = point(i, j), p01 = point(i, j + 1), p10 = point(i + 1, j), p11 = point(i + 1, j + 1);
      push_vertex(b, p00, (p00 - c).normalized());
      push_vertex(b, p10, (p10 - c).normalized());
      push_vertex(b, p11, (p11 - c).normalized());
      push_vertex(b, p00, (p00 - c).normalized());
      push_vertex(b, p11, (p11 - c).normalized());
      push_vertex(b, p01, (p01 - c).normalized());
    }
}

void append_cylinder(SurfaceBuffers& b, const Eigen::Vector3f& a, const Eigen::Vector3f& c, float r, int segments) {
  const Eigen::Vector3f axis = c - a;
  if (!(axis.norm() > 0.0f)) return;
  Eigen::Vector3f u, v;
  frame(axis.normalized(), u, v);
  for (int j = 0; j < segments; ++j) {
    const float p0 = 6.2831853f * float(j) / float(segments), p1 = 6.2831853f * float(j + 1) / float(segments);
    const Eigen::Vector3f d0 = std::cos(p0) * u + std::sin(p0) * v, d1 = std::cos(p1) * u + std::sin(p1) * v;
    push_vertex(b, a + r * d0, d0);
    push_vertex(b, c + r * d0, d0);
    push_vertex(b, c + r * d1, d1);
    push_vertex(b, a + r * d0, d0);
    push_vertex(b, c + r * d1, d1);
    push_vertex(b, a + r * d1, d1);
  }
}

void append_cone(SurfaceBuffers& b, const Eigen::Vector3f& base, const Eigen::Vector3f& apex, float r, int segments) {
  const Eigen::Vector3f axis = apex - base;
  if (!(axis.norm() > 0.0f)) return;
  Eigen::Vector3f u, v;
  frame(axis.normalized(), u, v);
  for (int j = 0; j < segments; ++j) {
    const float p0 = 6.2831853f * float(j) / float(segments), p1 = 6.2831853f * float(j + 1) / float(segments);
    const Eigen::Vector3f q0 = base + r * (std::cos(p0) * u + std::sin(p0) * v);
    const Eigen::Vector3f q1 = base + r * (std::cos(p1) * u + std::sin(p1) * v);
    push_triangle(b, q0, q1, apex);
    push_triangle(b, q1, q0, base);
  }
}

void append_disc(SurfaceBuffers& b, const Eigen::Vector3f& c, const Eigen::Vector3f& normal, float r, int segments) {
  Eigen::Vector3f u, v;
  frame(normal.normalized(), u, v);
  for (int j = 0; j < segments; ++j) {
    const float p0 = 6.2831853f * float(j) / float(segments), p1 = 6.2831853f * float(j + 1) / float(segments);
    push_triangle(b, c, c + r * (std::cos(p0) * u + std::sin(p0) * v), c + r * (std::cos(p1) * u + std::sin(p1) * v));
  }
}

void append_quad(SurfaceBuffers& b, const Eigen::Vector3f& p0, const Eigen::Vector3f& p1, const Eigen::Vector3f& p2,
                 const Eigen::Vector3f& p3) {
  push_triangle(b, p0, p1, p2);
  push_triangle(b, p0, p2, p3);
}

void append_arrow(SurfaceBuffers& b, const Eigen::Vector3f& from, const Eigen::Vector3f& vec, float radius) {
  const float len = vec.norm();
  if (!(len > 0.0f)) return;
  const Eigen::Vector3f d = vec / len;
  const float head = std::min(0.35f * len, 6.0f * radius);
  append_cylinder(b, from, from + (len - head) * d, radius);
  append_cone(b, from + (len - head) * d, from + vec, 2.5f * radius);
}

}  // namespace bemsurg::viewer
