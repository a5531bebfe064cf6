// bemsurg/mesh.hpp: the mesh module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup mesh Mesh
/// \brief Triangle surface meshes from headers alone: the mesh type, generators, geometry, topology, validation (with the vertex welding it uses), quality, thickness, BVH, operating regions, red-green local refinement and the element-id contract of a mesh change (MeshDelta). Files, remeshing and repair are the compiled meshing module (bemsurg/meshing.hpp).
///
/// Headers (each can be included on its own for faster builds):
/// - brain_model.hpp
/// - bvh.hpp
/// - conforming_split.hpp
/// - geometry.hpp
/// - liver_model.hpp
/// - mesh_delta.hpp
/// - mesh_generators.hpp
/// - mesh_quality.hpp
/// - mesh_thickness.hpp
/// - mesh_topology.hpp
/// - mesh_validation.hpp
/// - operating_region.hpp
/// - red_green_refinement.hpp
/// - self_intersection.hpp
/// - space_region.hpp
/// - triangle_mesh.hpp
/// - vertex_welding.hpp

#include "bemsurg/mesh/brain_model.hpp"
#include "bemsurg/mesh/bvh.hpp"
#include "bemsurg/mesh/conforming_split.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/liver_model.hpp"
#include "bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/operating_region.hpp"
#include "bemsurg/mesh/red_green_refinement.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/mesh/space_region.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"
