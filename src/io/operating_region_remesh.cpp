// The graded remesh a scene's operating region asks for (docs/graded.md): sized before Gmsh runs,
// then performed through bemsurg/meshing/graded_remesher.hpp. Reading the request is
// scene_operating_region.cpp's job.
#include <algorithm>
#include <cmath>
#include <utility>

#include "bemsurg/error.hpp"
#include "scene_sections.hpp"

namespace bemsurg::io {
namespace {

// A graded mesh of more elements than this would give a dense system (3E unknowns) of more than
// 10^11 entries: refused before Gmsh spends minutes producing it.
constexpr double kMaxGradedElements = 60000.0;

/// Estimated element count of the graded mesh: each input face's area over the area of an
/// equilateral triangle of the target size at its centroid. Faces larger than the inside length
/// are sampled on a k x k sub-grid (k <= 16), so a small region inside one coarse face still
/// counts at its own size. Stops counting once past kMaxGradedElements.
double estimate_graded_elements(const TriangleMesh& mesh, const OperatingRegion& region, const GradedRemeshOptions& options) {
  double estimate = 0.0;
  for (Index e = 0; e < mesh.num_elements() && estimate <= kMaxGradedElements; ++e) {
    const auto c = mesh.corners(e);
    const int k = static_cast<int>(std::min(16.0, std::ceil(2.0 * mesh.diameter(e) / options.inside_edge_length)));
    const double sub_area = mesh.area(e) / (k * k);
    for (int i = 0; i < k; ++i)
      for (int j = 0; j < k - i; ++j)
        for (int up = 0; up < (j < k - i - 1 ? 2 : 1); ++up) {
          // Centroid of sub-triangle (i, j) pointing up or down in barycentric grid coordinates.
          const double a = (up == 0 ? i + 1.0 / 3.0 : i + 2.0 / 3.0) / k;
          const double b = (up == 0 ? j + 1.0 / 3.0 : j + 2.0 / 3.0) / k;
          const Vec3 x = c[0] + a * (c[1] - c[0]) + b * (c[2] - c[0]);
          const double h = graded_target_size(region, options, x);
          estimate += sub_area / (0.433 * h * h);
        }
  }
  return estimate;
}

}  // namespace

void remesh_for_operating_region(const OperatingRegionRequest& request, Scene& scene) {
  const std::string key = "operating_region";
  TriangleMesh& mesh = scene.problem.mesh;
  scene.input_elements = mesh.num_elements();
  if (!request.graded) return;
  const GradedRemeshOptions& options = request.options;
  const double estimate = estimate_graded_elements(mesh, request.region, options);
  if (estimate > kMaxGradedElements)
    fail_at(key + ".inside_edge_length", "would give about " + std::to_string(static_cast<long long>(estimate)) + " elements (limit " +
                                             std::to_string(static_cast<long long>(kMaxGradedElements)) +
                                             "): the dense BEM system would not fit in memory; use longer edges");
  if (!graded_remesher_available()) {
    scene.warnings.push_back(
        key +
        ": this build of bemsurg has no remesher (BEMSURG_WITH_REMESHER=OFF, or libgmsh cannot be loaded): the mesh is "
        "used as generated or read, not graded");
    return;
  }
  try {
    GradedRemeshResult g = graded_remesh(mesh, request.region, options);
    mesh = std::move(g.mesh);
    scene.graded = true;
    scene.remesh_seconds = g.seconds;
    scene.mesh_source += ", graded remesh (inside " + json_number_text(options.inside_edge_length) + " m, outside " +
                         json_number_text(options.outside_edge_length) + " m)";
  } catch (const Error& e) { fail_at(key, std::string("remeshing failed: ") + e.what()); }
}

}  // namespace bemsurg::io
