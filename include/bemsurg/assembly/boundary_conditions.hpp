// bemsurg/assembly/boundary_conditions.hpp: what is prescribed on each element (docs/design.md §5).
// Per element and per global component x, y, z either the displacement or the traction is given;
// the other one is the unknown. Degree of freedom k = 3 e + c (element e, component c).
#pragma once

#include <Eigen/Core>
#include <Eigen/SVD>
#include <string>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

enum class BcKind : unsigned char { Displacement, Traction };

class BoundaryConditions {
 public:
  BoundaryConditions() = default;
  /// Every element traction-free (t = 0): the natural state of a free surface.
  explicit BoundaryConditions(Index num_elements)
      : kinds_(static_cast<std::size_t>(3 * num_elements), BcKind::Traction), values_(Eigen::VectorXd::Zero(3 * num_elements)) {}

  Index num_elements() const { return values_.size() / 3; }
  Index num_dofs() const { return values_.size(); }

  void prescribe_component(Index element, int component, BcKind kind, double value) {
    check_element(element);
    if (component < 0 || component > 2) throw BoundaryConditionError("component must be 0, 1 or 2");
    kinds_[static_cast<std::size_t>(3 * element + component)] = kind;
    values_(3 * element + component) = value;
  }
  void prescribe_displacement(Index element, const Eigen::Vector3d& u) {
    for (int c = 0; c < 3; ++c) prescribe_component(element, c, BcKind::Displacement, u(c));
  }
  void prescribe_traction(Index element, const Eigen::Vector3d& t) {
    for (int c = 0; c < 3; ++c) prescribe_component(element, c, BcKind::Traction, t(c));
  }
  /// A normal pressure p (positive pushes into the material): t = -p n.
  void prescribe_pressure(Index element, double pressure, const Eigen::Vector3d& outward_normal) {
    prescribe_traction(element, -pressure * outward_normal);
  }

  BcKind kind(Index dof) const { return kinds_[static_cast<std::size_t>(dof)]; }
  double value(Index dof) const { return values_(dof); }
  const std::vector<BcKind>& kinds() const { return kinds_; }
  /// True when all three dofs of the element are traction-prescribed (a tool may act on it).
  bool is_free(Index element) const { return is_free_element(kinds_, element); }
  /// The same test on a stored list of kinds (3 per element), as the Green's table keeps them.
  static bool is_free_element(const std::vector<BcKind>& kinds, Index element) {
    const auto k = static_cast<std::size_t>(3 * element);
    return kinds[k] == BcKind::Traction && kinds[k + 1] == BcKind::Traction && kinds[k + 2] == BcKind::Traction;
  }
  const Eigen::VectorXd& values() const { return values_; }

  Index num_displacement_dofs() const {
    Index n = 0;
    for (BcKind k : kinds_) n += k == BcKind::Displacement ? 1 : 0;
    return n;
  }

  /// Throws BoundaryConditionError unless the prescribed displacements fix all six rigid-body
  /// motions: without that the BEM system is singular (or nearly so, after discretisation) and
  /// any answer would be garbage. The check is exact: the rigid modes (3 translations, 3 rotations
  /// about the centroid of the surface) restricted to the prescribed dofs must have rank 6.
  void require_supported(const TriangleMesh& mesh) const {
    if (mesh.num_elements() != num_elements())
      throw BoundaryConditionError("boundary conditions are for " + std::to_string(num_elements()) +
                                   " elements, the mesh has " + std::to_string(mesh.num_elements()));
    const Index m = num_displacement_dofs();
    if (m == 0)
      throw BoundaryConditionError(
          "the body has no support: no element has a prescribed displacement, so rigid-body motion is free "
          "(prescribe u on some elements)");
    const Eigen::Vector3d center = mesh.centroids().colwise().mean().transpose();
    const double scale = std::max(1e-300, (mesh.bounding_box().col(1) - mesh.bounding_box().col(0)).norm());
    Eigen::MatrixXd modes(m, 6);
    Index row = 0;
    for (Index k = 0; k < num_dofs(); ++k) {
      if (kind(k) != BcKind::Displacement) continue;
      const int c = static_cast<int>(k % 3);
      const Eigen::Vector3d x = (mesh.centroid(k / 3) - center) / scale;
      Eigen::Matrix<double, 6, 1> r = Eigen::Matrix<double, 6, 1>::Zero();
      r(c) = 1.0;
      // Rotation about axis a moves x by a x x; component c of that for each axis.
      for (int a = 0; a < 3; ++a) r(3 + a) = Eigen::Vector3d::Unit(a).cross(x)(c);
      modes.row(row++) = r.transpose();
    }
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(modes, Eigen::ComputeFullV);
    const auto& s = svd.singularValues();
    const double tol = 1e-8 * std::max(1.0, s(0));
    if (s.size() == 6 && s(5) > tol) return;
    // Name the motions that stay free: right singular vectors of the (near-)zero singular values.
    static const char* names[6] = {"translation x", "translation y", "translation z",
                                   "rotation about x", "rotation about y", "rotation about z"};
    std::string free;
    for (Index i = 0; i < 6; ++i) {
      if (i < s.size() && s(i) > tol) continue;
      Eigen::Index best = 0;
      svd.matrixV().col(i).cwiseAbs().maxCoeff(&best);
      free += (free.empty() ? "" : ", ") + std::string(names[best]);
    }
    throw BoundaryConditionError("the body is not fully supported: the prescribed displacements leave rigid-body motion free (" +
                                 free + "); prescribe displacements on more elements or components");
  }

 private:
  void check_element(Index e) const {
    if (e < 0 || e >= num_elements())
      throw BoundaryConditionError("element " + std::to_string(e) + " is out of range (the mesh has " +
                                   std::to_string(num_elements()) + " elements)");
  }

  std::vector<BcKind> kinds_;
  Eigen::VectorXd values_;
};

}  // namespace bemsurg
