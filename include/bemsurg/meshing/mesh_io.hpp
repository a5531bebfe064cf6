// bemsurg/meshing/mesh_io.hpp: reading surface meshes from common files, writing results to view.
//
// Readers return the mesh as stored (polygons fan-triangulated, STL welded) without judging it:
// run validate_mesh / require_valid_mesh on the result. Every reader error names the file and,
// for text formats, the line, because "index out of range" alone is useless in a 50 MB file.
// Writers produce OBJ, STL (binary or ASCII), OFF and ASCII PLY (geometry) and legacy VTK POLYDATA with named per-element and per-vertex
// fields (displacement, traction, ...) that ParaView opens directly.
//
// Errors: a file that cannot be opened, read or written throws bemsurg::Error; a file whose
// content cannot be understood (parse error, index out of range, non-triangular STL facet,
// unsupported variant) throws InvalidMeshError.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Reads by extension, case-insensitively: .obj, .stl, .off, .ply, .vtk.
TriangleMesh read_mesh(const std::string& path);

/// Wavefront OBJ: 'v x y z' and 'f' lines ('f a b c', 'a/t', 'a/t/n', 'a//n'; 1-based, negative
/// indices count back from the latest vertex; polygons are fan-triangulated). Everything else
/// (vt, vn, g, o, s, usemtl, l, ...) is ignored.
TriangleMesh read_obj(const std::string& path);

/// STL, ASCII or binary (detected from the size a binary file must have, so binary files whose
/// header starts with "solid" are read correctly). STL stores a triangle soup; coincident corners
/// (within relative_weld_tolerance times the bounding-box diagonal) are welded so a closed
/// surface comes back closed and indexed. Facet normals in the file are ignored: orientation
/// comes from the vertex order.
TriangleMesh read_stl(const std::string& path, double relative_weld_tolerance = 1e-9);

/// OFF (also COFF/NOFF/CNOFF/STOFF: extra per-vertex columns are skipped): vertex and face
/// counts, vertices, then 'n i1 ... in' faces (0-based), fan-triangulated. Binary OFF is refused.
TriangleMesh read_off(const std::string& path);

/// PLY, ASCII or binary little/big endian: 'vertex' elements with x, y, z of any scalar type,
/// 'face' elements with a list property 'vertex_indices' (or 'vertex_index') of any integer
/// types; other properties and elements are skipped. Polygons are fan-triangulated.
TriangleMesh read_ply(const std::string& path);

/// Legacy VTK ASCII POLYDATA (as write_vtk writes it): POINTS and POLYGONS; data arrays ignored.
TriangleMesh read_vtk(const std::string& path);

/// A named array over the elements or vertices of a mesh: n x 3 for vectors, n x 1 for scalars.
/// The name must be non-empty without whitespace (VTK's legacy format splits on it).
/// \ingroup meshing
struct MeshField {
  std::string name;
  Eigen::MatrixXd values;

  /// Any n x 3 or n x 1 Eigen matrix or expression (RowMatrixX3d, VectorXd, ...); the shape
  /// is checked when the field is written.
  template <typename Derived>
  MeshField(std::string field_name, const Eigen::MatrixBase<Derived>& field_values) : name(std::move(field_name)), values(field_values) {}
};

/// OBJ with 'v' and 'f' lines; coordinates written in the shortest form that reads back exactly.
void write_obj(const std::string& path, const TriangleMesh& mesh);

/// STL: binary (80-byte header, little-endian 32-bit floats: about 7 significant digits) or ASCII
/// (shortest exact decimal text), one facet per face with its unit normal (zero for a degenerate
/// face). STL cannot share vertices: read_stl welds them back.
void write_stl(const std::string& path, const TriangleMesh& mesh, bool binary = true);

/// OFF: header, vertex and face counts, 'x y z' lines, '3 a b c' lines (0-based), exact decimals.
void write_off(const std::string& path, const TriangleMesh& mesh);

/// PLY, ASCII: 'vertex' elements with double x, y, z and 'face' elements with a list
/// 'vertex_indices' (uchar count, int indices), exact decimals.
void write_ply(const std::string& path, const TriangleMesh& mesh);

/// Writes by extension, case-insensitively: .obj, .stl (binary), .off, .ply (ASCII), .vtk (no
/// fields). Throws InvalidArgumentError for any other extension, naming the known ones.
void write_mesh(const std::string& path, const TriangleMesh& mesh);

/// Legacy VTK (ASCII, POLYDATA, version 3.0): the mesh as POLYGONS, then CELL_DATA with one
/// entry per element and POINT_DATA with one per vertex (VECTORS for n x 3, SCALARS for n x 1).
/// Throws bemsurg::Error if a field has the wrong number of rows or columns or a bad name.
void write_vtk(const std::string& path, const TriangleMesh& mesh, const std::vector<MeshField>& cell_fields = {},
               const std::vector<MeshField>& point_fields = {}, const std::string& title = "bemsurg mesh");

}  // namespace bemsurg
