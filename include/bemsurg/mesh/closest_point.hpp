// Deprecated path, kept until 0.3: closest_point_on_triangle and point_triangle_distance live in
// bemsurg/mesh/geometry.hpp. Include that.
#pragma once
#pragma GCC warning "bemsurg/mesh/closest_point.hpp is deprecated: include bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/geometry.hpp"
