// bemsurg/assembly/element_types.hpp: the boundary element types (docs/elements.md). An element type is
// a trait: how many collocation nodes a flat triangle carries, where they sit (barycentric
// coordinates) and the shape functions that interpolate the nodal values. Both types here have
// shape functions affine in the barycentric coordinates lambda, N_k = sum_c S(k, c) lambda_c, which
// is all the assembler (node_influence_assembler.hpp) needs: values at quadrature points, and the
// in-plane gradient that makes the self-element integrals exact in r. Adding an element type
// touches this file and the assembler's self rule only when it is not affine.
//   - constant: one node at the centroid, N = 1 (docs/design.md §2);
//   - linear discontinuous: three nodes pulled inside the element, x_k = c + f (v_k - c) with
//     c the centroid, v_k corner k and f = kLinearNodeFraction = 1/2 (lambda = (2/3, 1/6, 1/6),
//     the points of the 3-point Strang-Fix rule); N_k = (lambda_k - (1 - f)/3) / f, N_k(x_j) = delta_kj.
//     No node is shared, so the unknowns per element are 9 and meshes, cuts and per-element rules
//     keep working.
#pragma once

#include <Eigen/Core>
#include <array>
#include <string>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/types.hpp"

namespace bemsurg {

/// The boundary element type of a problem (docs/elements.md): constant (one collocation node per
/// element, at the centroid) or linear discontinuous (three nodes inside each element).
/// \ingroup assembly
enum class ElementType { Constant, Linear };

/// "constant" or "linear", as scene files and report.json write them.
inline const char* to_string(ElementType type) { return type == ElementType::Linear ? "linear" : "constant"; }

/// The inverse of to_string; throws InvalidArgumentError naming the value and the accepted ones.
inline ElementType parse_element_type(const std::string& name) {
  if (name == "constant") return ElementType::Constant;
  if (name == "linear") return ElementType::Linear;
  throw InvalidArgumentError("unknown element type '" + name + "' (expected constant or linear)");
}

/// Collocation nodes per element: 1 (constant) or 3 (linear).
inline int nodes_per_element(ElementType type) { return type == ElementType::Linear ? 3 : 1; }

/// The fraction f of the way from the centroid to each corner at which a linear element's
/// collocation nodes sit (docs/elements.md: why 1/2).
inline constexpr double kLinearNodeFraction = 0.5;

/// Constant element trait: one node at the centroid, shape function 1.
/// \ingroup assembly
struct ConstantElement {
  static constexpr int kNodes = 1;
  static constexpr ElementType kType = ElementType::Constant;
  /// Barycentric coordinates of node k.
  static Eigen::Vector3d node_barycentric(int) { return Eigen::Vector3d::Constant(1.0 / 3.0); }
  /// S(k, c) with N_k = sum_c S(k, c) lambda_c.
  static Eigen::Matrix<double, kNodes, 3> shape_matrix() { return Eigen::Matrix<double, kNodes, 3>::Ones(); }
};

/// Linear discontinuous element trait: three nodes at x_k = c + f (v_k - c), N_k(x_j) = delta_kj.
/// \ingroup assembly
struct LinearElement {
  static constexpr int kNodes = 3;
  static constexpr ElementType kType = ElementType::Linear;
  static Eigen::Vector3d node_barycentric(int k) {
    Eigen::Vector3d l = Eigen::Vector3d::Constant((1.0 - kLinearNodeFraction) / 3.0);
    l(k) += kLinearNodeFraction;
    return l;
  }
  /// N_k = (lambda_k - (1 - f)/3) / f = sum_c [(delta_kc - (1 - f)/3) / f] lambda_c (sum lambda = 1).
  static Eigen::Matrix<double, kNodes, 3> shape_matrix() {
    Eigen::Matrix3d s = Eigen::Matrix3d::Constant(-(1.0 - kLinearNodeFraction) / 3.0);
    s.diagonal().array() += 1.0;
    return s / kLinearNodeFraction;
  }
};

/// Position of collocation node k of the flat triangle (a, b, c) for element type Element.
template <class Element>
Eigen::Vector3d collocation_node(const std::array<Vec3, 3>& corners, int k) {
  const Eigen::Vector3d l = Element::node_barycentric(k);
  return l(0) * corners[0] + l(1) * corners[1] + l(2) * corners[2];
}

/// Values at the three linear collocation nodes from values at the three corners (rows in the
/// face's vertex order): linear interpolation, node k = sum_c lambda_c(x_k) corner_c.
inline Eigen::Matrix3d linear_corners_to_nodes(const Eigen::Matrix3d& corner_rows) {
  Eigen::Matrix3d l;
  for (int k = 0; k < 3; ++k) l.row(k) = LinearElement::node_barycentric(k).transpose();
  return l * corner_rows;
}

/// Values at the three corners (extrapolated) from values at the three linear collocation nodes:
/// corner c = sum_k N_k(v_c) node_k, N_k(v_c) = S(k, c).
inline Eigen::Matrix3d linear_nodes_to_corners(const Eigen::Matrix3d& node_rows) {
  return LinearElement::shape_matrix().transpose() * node_rows;
}

/// N_k(x) of the linear element with corners c and unit normal n at a point x in its plane:
/// lambda_v = ((c_(v+1) - x) x (c_(v+2) - x)) . n / (2 A), N = S lambda.
inline Eigen::Vector3d linear_shape_values(const std::array<Vec3, 3>& c, const Eigen::Vector3d& n, const Eigen::Vector3d& x) {
  const double twice_area = (c[1] - c[0]).cross(c[2] - c[0]).dot(n);
  Eigen::Vector3d lambda;
  for (int v = 0; v < 3; ++v) lambda(v) = (c[(v + 1) % 3] - x).cross(c[(v + 2) % 3] - x).dot(n) / twice_area;
  return LinearElement::shape_matrix() * lambda;
}

/// One triangle per linear collocation node: the corner child (v_k, mid(v_k, v_k+1), mid(v_k, v_k+2))
/// of each element, same orientation, vertices unshared, 3E triangles (triangle 3e + k). Its centroid
/// is node k for the fraction 1/2: what the near-field preconditioner and other per-"element"
/// geometry readers see for a linear problem (docs/elements.md).
inline TriangleMesh linear_node_proxy_mesh(const TriangleMesh& mesh) {
  const Index E = mesh.num_elements();
  RowMatrixX3d v(9 * E, 3);
  RowMatrixX3i f(3 * E, 3);
  for (Index e = 0; e < E; ++e) {
    const auto c = mesh.corners(e);
    for (int k = 0; k < 3; ++k) {
      const Index row = 9 * e + 3 * k;
      v.row(row) = c[k].transpose();
      v.row(row + 1) = (0.5 * (c[k] + c[(k + 1) % 3])).transpose();
      v.row(row + 2) = (0.5 * (c[k] + c[(k + 2) % 3])).transpose();
      f.row(3 * e + k) << int(row), int(row + 1), int(row + 2);
    }
  }
  return TriangleMesh(std::move(v), std::move(f));
}

}  // namespace bemsurg
