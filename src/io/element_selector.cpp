// Geometric element selection for scene boundary conditions (bemsurg/io/element_selector.hpp;
// docs/scene-format.md, "Selectors"). Tests run on centroids and normals of constant elements.
#include "bemsurg/io/element_selector.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {
namespace {

std::string vec_to_string(const Eigen::Vector3d& v) {
  return "[" + number_text(v.x()) + ", " + number_text(v.y()) + ", " + number_text(v.z()) + "]";
}

bool all_finite(const Eigen::Vector3d& v) { return v.allFinite(); }

}  // namespace

std::vector<Index> select_elements(const TriangleMesh& mesh, const ElementSelector& s) {
  const Index n = mesh.num_elements();
  std::vector<Index> picked;
  // Centroids of a flat face lie on its plane only up to rounding; a slack of 1e-9 of the model
  // size absorbs that without ever reaching a neighbouring row of elements.
  const double diagonal = n > 0 ? (mesh.bounding_box().col(1) - mesh.bounding_box().col(0)).norm() : 0.0;
  const double slack = 1e-9 * diagonal;

  switch (s.kind) {
    case ElementSelector::Kind::All:
      for (Index e = 0; e < n; ++e) picked.push_back(e);
      break;

    case ElementSelector::Kind::Plane: {
      if (!all_finite(s.point) || !all_finite(s.direction) || s.direction.norm() == 0.0)
        throw SceneError("plane: the normal must be a finite non-zero vector, got " + vec_to_string(s.direction));
      if (!std::isfinite(s.tolerance) || s.tolerance < 0.0)
        throw SceneError("plane: tolerance must be a finite non-negative distance, got " + number_text(s.tolerance));
      const Eigen::Vector3d unit = s.direction.normalized();
      for (Index e = 0; e < n; ++e)
        if (std::abs((mesh.centroid(e) - s.point).dot(unit)) <= s.tolerance + slack) picked.push_back(e);
      break;
    }

    case ElementSelector::Kind::Box: {
      if (!all_finite(s.box_min) || !all_finite(s.box_max) || (s.box_min.array() > s.box_max.array()).any())
        throw SceneError("box: min " + vec_to_string(s.box_min) + " must be finite and not exceed max " + vec_to_string(s.box_max) +
                         " in any component");
      for (Index e = 0; e < n; ++e) {
        const Eigen::Vector3d c = mesh.centroid(e);
        if ((c.array() >= s.box_min.array() - slack).all() && (c.array() <= s.box_max.array() + slack).all()) picked.push_back(e);
      }
      break;
    }

    case ElementSelector::Kind::Sphere: {
      if (!all_finite(s.point) || !std::isfinite(s.tolerance) || !(s.tolerance > 0.0))
        throw SceneError("sphere: the centre must be finite and the radius positive, got centre " + vec_to_string(s.point) + ", radius " +
                         number_text(s.tolerance));
      for (Index e = 0; e < n; ++e)
        if ((mesh.centroid(e) - s.point).norm() <= s.tolerance + slack) picked.push_back(e);
      break;
    }

    case ElementSelector::Kind::Normal: {
      if (!all_finite(s.direction) || s.direction.norm() == 0.0)
        throw SceneError("normal: direction must be a finite non-zero vector, got " + vec_to_string(s.direction));
      if (!std::isfinite(s.min_cos) || s.min_cos < -1.0 || s.min_cos > 1.0)
        throw SceneError("normal: min_cos must lie in [-1, 1], got " + number_text(s.min_cos));
      const Eigen::Vector3d unit = s.direction.normalized();
      // 1e-12 below the threshold so that min_cos = 1 still picks faces exactly aligned with it.
      for (Index e = 0; e < n; ++e)
        if (mesh.normal(e).dot(unit) >= s.min_cos - 1e-12) picked.push_back(e);
      break;
    }

    case ElementSelector::Kind::Shell: {
      const MeshTopology topology(mesh);
      if (s.shell < 0 || s.shell >= topology.num_shells())
        throw SceneError("shell: index " + std::to_string(s.shell) + " out of range (mesh has " + std::to_string(topology.num_shells()) +
                         " shells)");
      picked = topology.shell(s.shell);
      break;
    }

    case ElementSelector::Kind::Elements: {
      for (Index e : s.elements) {
        if (e < 0 || e >= n)
          throw SceneError("elements: element " + std::to_string(e) + " out of range (mesh has " + std::to_string(n) + " elements)");
        picked.push_back(e);
      }
      std::sort(picked.begin(), picked.end());
      picked.erase(std::unique(picked.begin(), picked.end()), picked.end());
      break;
    }
  }
  return picked;
}

}  // namespace bemsurg
