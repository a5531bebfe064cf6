// bemsurg/meshing.hpp: the meshing module in one include (docs/design.md, "Module order").
#pragma once

/// \defgroup meshing Meshing
/// \brief The compiled meshing part (library bemsurg::meshing): mesh files (OBJ, OFF, PLY, STL, VTK), implicit surfaces and organ shapes, defects of segmented surfaces, graded remeshing (Gmsh) that keeps creases and flat faces and the preparation of raw segmentations (CGAL repair, optional at build time).
///
/// Headers (each can be included on its own for faster builds):
/// - graded_remesher.hpp
/// - implicit_surface.hpp
/// - mesh_defects.hpp
/// - mesh_io.hpp
/// - mesh_preparation.hpp
/// - organ_shapes.hpp
/// - planar_regions.hpp

#include "bemsurg/meshing/graded_remesher.hpp"
#include "bemsurg/meshing/implicit_surface.hpp"
#include "bemsurg/meshing/mesh_defects.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/meshing/mesh_preparation.hpp"
#include "bemsurg/meshing/organ_shapes.hpp"
#include "bemsurg/meshing/planar_regions.hpp"
