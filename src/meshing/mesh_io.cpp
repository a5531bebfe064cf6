// Mesh files by extension, read and written (bemsurg/meshing/mesh_io.hpp). Each format lives in its own file under
// src/meshing/formats/ (obj, stl, off, ply, vtk), with what they share in text_tokens and
// mesh_builder; a new format is a new file there and one line here.
#include "bemsurg/meshing/mesh_io.hpp"

#include <filesystem>
#include <string>

#include "bemsurg/error.hpp"
#include "formats/text_tokens.hpp"

namespace bemsurg {

TriangleMesh read_mesh(const std::string& path) {
  const std::string ext = mesh_formats::lower(std::filesystem::path(path).extension().string());
  if (ext == ".obj") return read_obj(path);
  if (ext == ".stl") return read_stl(path);
  if (ext == ".off") return read_off(path);
  if (ext == ".ply") return read_ply(path);
  if (ext == ".vtk") return read_vtk(path);
  throw InvalidMeshError("cannot read '" + path + "': unknown mesh file extension '" + ext + "' (known: .obj, .stl, .off, .ply, .vtk)");
}

void write_mesh(const std::string& path, const TriangleMesh& mesh) {
  const std::string ext = mesh_formats::lower(std::filesystem::path(path).extension().string());
  if (ext == ".obj") return write_obj(path, mesh);
  if (ext == ".stl") return write_stl(path, mesh, true);
  if (ext == ".off") return write_off(path, mesh);
  if (ext == ".ply") return write_ply(path, mesh);
  if (ext == ".vtk") return write_vtk(path, mesh);
  throw InvalidArgumentError("cannot write '" + path + "': unknown mesh file extension '" + ext +
                             "' (known: .obj, .stl, .off, .ply, .vtk)");
}

}  // namespace bemsurg
