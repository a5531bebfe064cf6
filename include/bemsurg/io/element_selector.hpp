// bemsurg/io/element_selector.hpp: pick boundary elements by geometry instead of by index, so a
// scene can say "fix the bottom face" without listing face numbers that change with the mesh
// (docs/design.md §5: boundary conditions are prescribed per element; docs/scene-format.md, selectors).
//
// Every test is made on the element's centroid and unit normal (constant elements have one
// collocation node, at the centroid, docs/design.md §2), so "on the plane" means "centroid within
// `tolerance` of the plane" and a selector never splits an element.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Picks boundary elements by geometry (plane, box, sphere, normal direction, shell) or by list, tested on each element's
/// centroid and normal, so a scene need not list face numbers (docs/scene-format.md, selectors; see select_elements).
/// \ingroup io
struct ElementSelector {
  enum class Kind {
    Plane,     // centroid within `tolerance` of the plane through `point` with normal `direction`
    Box,       // centroid inside the axis-aligned box [box_min, box_max] (bounds included)
    Sphere,    // centroid within `tolerance` (the radius) of `point` (where an organ's ligaments attach)
    Normal,    // unit normal n with n . direction / |direction| >= min_cos
    Shell,     // every element of connected shell `shell` (MeshTopology numbering)
    Elements,  // an explicit list of element indices
    All,       // every element
  };

  Kind kind = Kind::All;
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // plane normal or preferred normal direction
  double tolerance = 0.0;                                // plane: absolute distance; sphere: radius
  double min_cos = 0.9;                                  // normal: cosine threshold
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_max = Eigen::Vector3d::Zero();
  Index shell = 0;
  std::vector<Index> elements;

  static ElementSelector plane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double tolerance) {
    ElementSelector s;
    s.kind = Kind::Plane;
    s.point = point;
    s.direction = normal;
    s.tolerance = tolerance;
    return s;
  }
  static ElementSelector box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
    ElementSelector s;
    s.kind = Kind::Box;
    s.box_min = lo;
    s.box_max = hi;
    return s;
  }
  static ElementSelector sphere(const Eigen::Vector3d& center, double radius) {
    ElementSelector s;
    s.kind = Kind::Sphere;
    s.point = center;
    s.tolerance = radius;
    return s;
  }
  static ElementSelector normal_direction(const Eigen::Vector3d& direction, double min_cos) {
    ElementSelector s;
    s.kind = Kind::Normal;
    s.direction = direction;
    s.min_cos = min_cos;
    return s;
  }
  static ElementSelector shell_index(Index shell) {
    ElementSelector s;
    s.kind = Kind::Shell;
    s.shell = shell;
    return s;
  }
  static ElementSelector element_list(std::vector<Index> elements) {
    ElementSelector s;
    s.kind = Kind::Elements;
    s.elements = std::move(elements);
    return s;
  }
  static ElementSelector all() { return ElementSelector(); }
};

/// The elements the selector picks, in increasing order without repeats. Throws SceneError for a
/// selector that cannot be evaluated (zero plane normal or direction, negative tolerance or radius, box with
/// min > max, min_cos outside [-1, 1], shell or element index out of range), naming the problem.
/// An empty result is not an error here; the scene loader decides what an empty selection means.
std::vector<Index> select_elements(const TriangleMesh& mesh, const ElementSelector& selector);

}  // namespace bemsurg
