// bemsurg/mesh/closest_point.hpp: kept so that code including it still compiles;
// closest_point_on_triangle and point_triangle_distance now live in bemsurg/mesh/geometry.hpp.
#pragma once

#include "bemsurg/mesh/geometry.hpp"
