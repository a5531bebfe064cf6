// The "interior_points" section of a scene (docs/scene-format.md#interior_points): where the
// displacement and stress are evaluated after the solve (Wang et al. 2007 eqs. 7-9). Points
// outside the body, on its surface or too close to it for the quadrature are refused here, before
// the solve, naming the point.
#include <cmath>

#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/post/interior_clearance.hpp"
#include "csv_reader.hpp"
#include "scene_sections.hpp"

namespace bemsurg::io {
namespace {

std::string point_text(const Vec3& p) {
  return "point (" + json_number_text(p.x()) + ", " + json_number_text(p.y()) + ", " + json_number_text(p.z()) + ")";
}

}  // namespace

RowMatrixX3d load_interior_points(const JsonReader& ip, const std::string& directory, const TriangleMesh& mesh,
                                  const QuadratureOptions& quadrature) {
  std::vector<Vec3> points;
  std::vector<std::string> where;  // how to name each point in a message
  const auto add_inline = [&](const JsonReader& list) {
    if (!list.is_array()) list.fail("expected an array of [x, y, z] points, got " + list.type_name());
    for (std::size_t i = 0; i < list.size(); ++i) {
      points.push_back(list[i].vec3());
      where.push_back(list[i].path());
    }
  };
  if (ip.is_array()) {
    add_inline(ip);
  } else {
    ip.object().warn_unknown_keys({"file", "points"});
    if (!ip.has("file") && !ip.has("points")) ip.fail("expected a \"file\" or a \"points\" key");
    if (const std::optional<JsonReader> list = ip.optional("points")) add_inline(*list);
    if (const std::optional<JsonReader> file = ip.optional("file")) {
      const std::string path = resolve_existing(directory, *file);
      for (const CsvRow& row : read_csv(path, "x,y,z", file->path())) {
        const std::string w = csv_row_key(file->path(), row);
        points.emplace_back(parse_csv_number(row.fields[0], w + ": x"), parse_csv_number(row.fields[1], w + ": y"),
                            parse_csv_number(row.fields[2], w + ": z"));
        where.push_back(w);
      }
    }
  }
  RowMatrixX3d out(static_cast<Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    // Somigliana's identity with c = I holds only inside; outside it returns zero-ish garbage and
    // on the surface it is singular, so such points are refused rather than evaluated.
    bool on_surface = false;
    const double w = winding_number(mesh, points[i], &on_surface);
    if (on_surface || std::abs(w - 1.0) > 0.25)
      fail_at(where[i], point_text(points[i]) + " is not inside the body" + (on_surface ? " (it lies on the surface)" : ""));
    out.row(static_cast<Index>(i)) = points[i].transpose();
  }
  // Too close to the surface for the quadrature, or for the stress that `solve` writes with every
  // interior point (kMinStressClearanceFraction, docs/stability.md (b)): refused here rather than
  // after the solve (issue 37).
  const ClearanceViolation v = find_point_too_close(mesh, out, quadrature, ClearanceQuantity::Stress);
  if (v.point >= 0) {
    const auto i = static_cast<std::size_t>(v.point);
    fail_at(where[i], point_text(points[i]) + " " + describe_clearance_violation(v, quadrature));
  }
  return out;
}

}  // namespace bemsurg::io
