// bemsurg/mesh.hpp: the mesh module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup mesh Mesh
/// \brief Triangle surface meshes: the mesh type, generators, file formats, geometry, topology, validation, quality, implicit surfaces and organ shapes, defects of segmented surfaces, graded remeshing (Gmsh, optional at build time), red-green local refinement and the element-id contract of a mesh change (MeshDelta).
///
/// Headers (each can be included on its own for faster builds):
/// - brain_model.hpp
/// - bvh.hpp
/// - closest_point.hpp
/// - geometry.hpp
/// - graded_remesher.hpp
/// - implicit_surface.hpp
/// - liver_model.hpp
/// - mesh_defects.hpp
/// - mesh_delta.hpp
/// - mesh_generators.hpp
/// - mesh_io.hpp
/// - mesh_preparation.hpp
/// - mesh_quality.hpp
/// - mesh_thickness.hpp
/// - mesh_topology.hpp
/// - mesh_validation.hpp
/// - operating_region.hpp
/// - organ_shapes.hpp
/// - red_green_refinement.hpp
/// - self_intersection.hpp
/// - triangle_mesh.hpp
/// - vertex_welding.hpp

#include "bemsurg/mesh/brain_model.hpp"
#include "bemsurg/mesh/bvh.hpp"
#include "bemsurg/mesh/closest_point.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/graded_remesher.hpp"
#include "bemsurg/mesh/implicit_surface.hpp"
#include "bemsurg/mesh/liver_model.hpp"
#include "bemsurg/mesh/mesh_defects.hpp"
#include "bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_io.hpp"
#include "bemsurg/mesh/mesh_preparation.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/operating_region.hpp"
#include "bemsurg/mesh/organ_shapes.hpp"
#include "bemsurg/mesh/red_green_refinement.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"
