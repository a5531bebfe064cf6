// The mesh module's definitions: topology, validation, generators, BVH, self-intersection,
// thickness, operating regions, the brain and liver models, implicit surfaces, organ shapes and
// the defects of segmented surfaces.
// Compiled once here under BEMSURG_SEPARATE_COMPILATION (include/bemsurg/config.hpp); header-only
// programs (bemsurg::core) get the same definitions inline from the headers.
#include "bemsurg/mesh/brain_model.hpp"
#include "bemsurg/mesh/bvh.hpp"
#include "bemsurg/mesh/liver_model.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/operating_region.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"

#include "bemsurg/mesh/impl/brain_model_impl.hpp"
#include "bemsurg/mesh/impl/bvh_impl.hpp"
#include "bemsurg/mesh/impl/liver_model_impl.hpp"
#include "bemsurg/mesh/impl/mesh_generators_impl.hpp"
#include "bemsurg/mesh/impl/mesh_thickness_impl.hpp"
#include "bemsurg/mesh/impl/mesh_topology_impl.hpp"
#include "bemsurg/mesh/impl/mesh_validation_impl.hpp"
#include "bemsurg/mesh/impl/operating_region_impl.hpp"
#include "bemsurg/mesh/impl/self_intersection_impl.hpp"
#include "bemsurg/mesh/impl/vertex_welding_impl.hpp"
