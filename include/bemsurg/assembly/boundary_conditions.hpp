// bemsurg/assembly/boundary_conditions.hpp: what is prescribed on each element (docs/design.md §5).
// Per element and per global component x, y, z either the displacement or the traction is given;
// the other one is the unknown. Degree of freedom k = 3 e + c (element e, component c).
#pragma once

#include <Eigen/Core>
#include <Eigen/SVD>
#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Which quantity is prescribed for one degree of freedom: the displacement or the traction (docs/design.md §5).
/// \ingroup assembly
enum class BcKind : unsigned char { Displacement, Traction };

/// What is prescribed on each element (docs/design.md §5): per element and global component x, y, z either the
/// displacement or the traction, the other one being the unknown; degree of freedom k = 3 e + c.
/// \ingroup assembly
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
  /// motions of every body: without that the BEM system is singular (or nearly so, after
  /// discretisation) and any answer would be garbage. The check is exact: the rigid modes (3
  /// translations, 3 rotations about the centroid of the body's surface) restricted to the body's
  /// prescribed dofs must have rank 6. A body is a closed shell with the cavities inside it
  /// (shell_bodies); with several bodies each is checked on its own, and the message names the
  /// body that floats by its outer shell and an element of it.
  void require_supported(const TriangleMesh& mesh) const {
    if (mesh.num_elements() != num_elements())
      throw BoundaryConditionError("boundary conditions are for " + std::to_string(num_elements()) + " elements, the mesh has " +
                                   std::to_string(mesh.num_elements()));
    if (num_displacement_dofs() == 0)
      throw BoundaryConditionError(
          "the body has no support: no element has a prescribed displacement, so rigid-body motion is free "
          "(prescribe u on some elements)");
    const MeshTopology topo(mesh);
    const std::vector<Index> body_of_shell = shell_bodies(mesh, topo);
    const Index num_bodies = body_of_shell.empty() ? 0 : 1 + *std::max_element(body_of_shell.begin(), body_of_shell.end());
    if (num_bodies <= 1) {
      std::vector<Index> all(static_cast<std::size_t>(mesh.num_elements()));
      for (Index e = 0; e < mesh.num_elements(); ++e) all[static_cast<std::size_t>(e)] = e;
      const std::string free = free_rigid_motions(mesh, all);
      if (!free.empty())
        throw BoundaryConditionError("the body is not fully supported: the prescribed displacements leave rigid-body motion free (" + free +
                                     "); prescribe displacements on more elements or components");
      return;
    }
    for (Index b = 0; b < num_bodies; ++b) {
      std::vector<Index> elements;
      Index outer = -1;
      for (Index s = 0; s < topo.num_shells(); ++s) {
        if (body_of_shell[static_cast<std::size_t>(s)] != b) continue;
        if (outer < 0) outer = s;  // shells are numbered by their lowest face; the outer one is the body's root
        elements.insert(elements.end(), topo.shell(s).begin(), topo.shell(s).end());
      }
      std::sort(elements.begin(), elements.end());
      const std::string free = free_rigid_motions(mesh, elements);
      if (free.empty()) continue;
      Index prescribed = 0;
      for (Index e : elements)
        for (int c = 0; c < 3; ++c) prescribed += kind(3 * e + c) == BcKind::Displacement ? 1 : 0;
      const std::string which = "body " + std::to_string(b) + " of " + std::to_string(num_bodies) + " (shell " + std::to_string(outer) +
                                ", " + std::to_string(elements.size()) + " elements, element " + std::to_string(elements.front()) +
                                " among them)";
      throw BoundaryConditionError(
          prescribed == 0 ? which + " has no support: none of its elements has a prescribed displacement, so it floats free (" + free +
                                "); each separate body needs its own support"
                          : which + " is not fully supported: its prescribed displacements leave rigid-body motion free (" + free +
                                "); prescribe displacements on more of its elements or components");
    }
  }

 private:
  void check_element(Index e) const {
    if (e < 0 || e >= num_elements())
      throw BoundaryConditionError("element " + std::to_string(e) + " is out of range (the mesh has " + std::to_string(num_elements()) +
                                   " elements)");
  }

  /// The rigid motions of the surface made of `elements` that its prescribed displacements leave
  /// free, named ("translation x, rotation about z"); empty when all six are fixed.
  std::string free_rigid_motions(const TriangleMesh& mesh, const std::vector<Index>& elements) const {
    Index m = 0;
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    Eigen::Vector3d center = Eigen::Vector3d::Zero();
    for (Index e : elements) {
      for (int c = 0; c < 3; ++c) m += kind(3 * e + c) == BcKind::Displacement ? 1 : 0;
      center += mesh.centroid(e);
      for (const Vec3& p : mesh.corners(e)) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    static const char* names[6] = {"translation x",    "translation y",    "translation z",
                                   "rotation about x", "rotation about y", "rotation about z"};
    if (m == 0 || elements.empty()) return "translation x, y, z and rotation about x, y, z";
    center /= static_cast<double>(elements.size());
    const double scale = std::max(1e-300, (hi - lo).norm());
    Eigen::MatrixXd modes(m, 6);
    Index row = 0;
    for (Index e : elements)
      for (int c = 0; c < 3; ++c) {
        if (kind(3 * e + c) != BcKind::Displacement) continue;
        const Eigen::Vector3d x = (mesh.centroid(e) - center) / scale;
        Eigen::Matrix<double, 6, 1> r = Eigen::Matrix<double, 6, 1>::Zero();
        r(c) = 1.0;
        // Rotation about axis a moves x by a x x; component c of that for each axis.
        for (int a = 0; a < 3; ++a) r(3 + a) = Eigen::Vector3d::Unit(a).cross(x)(c);
        modes.row(row++) = r.transpose();
      }
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(modes, Eigen::ComputeFullV);
    const auto& s = svd.singularValues();
    const double tol = 1e-8 * std::max(1.0, s(0));
    if (s.size() == 6 && s(5) > tol) return std::string();
    // Name the motions that stay free: right singular vectors of the (near-)zero singular values.
    std::string free;
    for (Index i = 0; i < 6; ++i) {
      if (i < s.size() && s(i) > tol) continue;
      Eigen::Index best = 0;
      svd.matrixV().col(i).cwiseAbs().maxCoeff(&best);
      free += (free.empty() ? "" : ", ") + std::string(names[best]);
    }
    return free;
  }

  std::vector<BcKind> kinds_;
  Eigen::VectorXd values_;
};

}  // namespace bemsurg
