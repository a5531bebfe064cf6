// bemsurg/mesh/triangle_mesh.hpp: the surface of the body as flat triangles (docs/design.md §2).
//
// Conventions: faces list vertex indices counter-clockwise seen from outside the material, so the
// right-hand-rule normal points out of the material. Each face is one constant boundary element
// whose collocation node is its centroid; element e owns the unknowns 3e, 3e+1, 3e+2 (x, y, z).
// The geometry (centroids, unit normals, areas, diameters) is computed once on construction and
// kept, because quadrature reads it O(E^2) times during assembly.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <string>
#include <utility>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/types.hpp"

namespace bemsurg {

/// The surface of the body as flat triangles, counter-clockwise seen from outside: each face is one constant boundary
/// element collocated at its centroid, whose geometry (centroid, normal, area, diameter) is computed once on construction.
/// \ingroup mesh
class TriangleMesh {
 public:
  TriangleMesh() = default;

  /// Takes the vertex coordinates and the faces (0-based vertex indices). Throws InvalidMeshError
  /// if a face refers to a vertex that does not exist. Topological checks (closed, manifold,
  /// oriented, non-degenerate) live in mesh/mesh_validation.hpp and are not run here, so broken
  /// meshes can still be loaded, inspected and reported on.
  TriangleMesh(RowMatrixX3d vertices, RowMatrixX3i faces) : vertices_(std::move(vertices)), faces_(std::move(faces)) {
    for (Index f = 0; f < faces_.rows(); ++f)
      for (int k = 0; k < 3; ++k)
        if (faces_(f, k) < 0 || faces_(f, k) >= vertices_.rows())
          throw InvalidMeshError("face " + std::to_string(f) + " refers to vertex " + std::to_string(faces_(f, k)) + ", but the mesh has " +
                                 std::to_string(vertices_.rows()) + " vertices");
    update_geometry();
  }

  Index num_vertices() const { return vertices_.rows(); }
  Index num_elements() const { return faces_.rows(); }
  /// Number of equations of the BEM system: three per constant element.
  Index num_dofs() const { return 3 * faces_.rows(); }

  const RowMatrixX3d& vertices() const { return vertices_; }
  const RowMatrixX3i& faces() const { return faces_; }
  const RowMatrixX3d& centroids() const { return centroids_; }
  const RowMatrixX3d& normals() const { return normals_; }
  const Eigen::VectorXd& areas() const { return areas_; }
  /// Longest edge of each element.
  const Eigen::VectorXd& diameters() const { return diameters_; }

  Vec3 vertex(Index v) const { return vertices_.row(v).transpose(); }
  Vec3 centroid(Index e) const { return centroids_.row(e).transpose(); }
  Vec3 normal(Index e) const { return normals_.row(e).transpose(); }
  double area(Index e) const { return areas_(e); }
  double diameter(Index e) const { return diameters_(e); }
  std::array<Vec3, 3> corners(Index e) const { return {vertex(faces_(e, 0)), vertex(faces_(e, 1)), vertex(faces_(e, 2))}; }

  /// Total surface area and the volume enclosed (divergence theorem; positive for outward normals).
  double total_area() const { return areas_.sum(); }
  double enclosed_volume() const {
    // Tetrahedra from a point near the mesh rather than the origin: the sum of large, nearly
    // cancelling terms loses precision for a mesh far from the origin.
    if (num_elements() == 0) return 0.0;
    const Vec3 o = centroid(0);
    double v = 0.0;
    for (Index e = 0; e < num_elements(); ++e) {
      const auto c = corners(e);
      v += (c[0] - o).dot((c[1] - o).cross(c[2] - o)) / 6.0;
    }
    return v;
  }

  /// Axis-aligned bounding box: min corner in column 0, max corner in column 1.
  Eigen::Matrix<double, 3, 2> bounding_box() const {
    Eigen::Matrix<double, 3, 2> box;
    box.col(0) = vertices_.colwise().minCoeff().transpose();
    box.col(1) = vertices_.colwise().maxCoeff().transpose();
    return box;
  }

  /// Vertex values for drawing from per-element values: area-weighted average of the elements
  /// that share each vertex (docs/design.md §2).
  RowMatrixX3d element_to_vertex(const RowMatrixX3d& element_values) const {
    RowMatrixX3d out = RowMatrixX3d::Zero(num_vertices(), 3);
    Eigen::VectorXd weight = Eigen::VectorXd::Zero(num_vertices());
    for (Index e = 0; e < num_elements(); ++e)
      for (int k = 0; k < 3; ++k) {
        out.row(faces_(e, k)) += areas_(e) * element_values.row(e);
        weight(faces_(e, k)) += areas_(e);
      }
    for (Index v = 0; v < num_vertices(); ++v)
      if (weight(v) > 0.0) out.row(v) /= weight(v);
    return out;
  }

 private:
  void update_geometry() {
    const Index n = faces_.rows();
    centroids_.resize(n, 3);
    normals_.resize(n, 3);
    areas_.resize(n);
    diameters_.resize(n);
    for (Index e = 0; e < n; ++e) {
      const auto c = corners(e);
      const Vec3 cross = (c[1] - c[0]).cross(c[2] - c[0]);
      const double twice_area = cross.norm();
      centroids_.row(e) = ((c[0] + c[1] + c[2]) / 3.0).transpose();
      areas_(e) = 0.5 * twice_area;
      // A degenerate face keeps a zero normal; validation reports it by index.
      const Vec3 normal = twice_area > 0.0 ? Vec3(cross / twice_area) : Vec3(Vec3::Zero());
      normals_.row(e) = normal.transpose();
      diameters_(e) = element_diameter(c[0], c[1], c[2]);
    }
  }

  RowMatrixX3d vertices_;
  RowMatrixX3i faces_;
  RowMatrixX3d centroids_;
  RowMatrixX3d normals_;
  Eigen::VectorXd areas_;
  Eigen::VectorXd diameters_;
};

}  // namespace bemsurg
