// Constants many test files use, defined once so that a unity build of a test program (every
// file of the program in one translation unit, scripts/run-tests.sh) sees one definition.
#pragma once

#include <limits>

#include "bemsurg/constants.hpp"

namespace bemsurg_test {

/// Machine epsilon of double: the unit in which tests state round-off bounds.
constexpr double kEps = std::numeric_limits<double>::epsilon();
/// π, as the library defines it.
constexpr double kPi = bemsurg::numbers::pi;

}  // namespace bemsurg_test
