// examples/viewer/frame_geometry.cpp: what a frame draws, from the model snapshot and the latest
// contact: the displacement field from the read-only table (docs/design.md §9: the graphics
// thread computes it, never the haptic thread's solver), the deformed and coloured surface, the
// tools with their force arrows and the pending cut path (see viewer_state.hpp).
#include <algorithm>
#include <cmath>

#include "bemsurg/haptics/session.hpp"
#include "viewer_state.hpp"

namespace bemsurg::viewer {

void share_cut_reach(App& app, const std::shared_ptr<const PhysicsState>& ph, const ContactSnapshot& c) {
  // A cut step's first response covers the region elements within reach of the engaged tools' tips
  // and of the elements they touch, by the rule sessions use (haptics::SessionOptions: radius x (1 +
  // slide margin) + the margin a tool may move while the step completes; docs/viewer.md).
  const haptics::SessionOptions rule;
  std::vector<Eigen::Vector3d> points;
  double reach = rule.reach_margin;
  for (const SlotSnapshot& s : c.slots) {
    if (!s.engaged) continue;
    points.push_back(s.tip);
    reach = std::max(reach, rule.tool_reach(s.radius, s.plate_size));
  }
  if (ph && ph->mesh && c.physics_version == ph->version)
    for (Index i = 0; i < c.count; ++i) {
      const Index e = c.elements[static_cast<std::size_t>(i)];
      if (e >= 0 && e < ph->mesh->num_elements()) points.push_back(ph->mesh->centroid(e));
    }
  app.worker.set_cut_reach(std::move(points), reach);
}

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
    if (ph->table)
      f.base_vertices = deformed_vertices(mesh, ph->table->base_displacement());
    else if (ph->provisional_displacement.size() == 3 * E)
      f.base_vertices = deformed_vertices(mesh, ph->provisional_displacement);
    else
      f.base_vertices = mesh.vertices();
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
      if (app.colour_by == 1)
        s = umag;
      else if (app.colour_by == 2)
        s = tmag;
      else
        s = f.physics->supported[static_cast<std::size_t>(e)] ? 1.0f : 0.0f;
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

}  // namespace bemsurg::viewer
