// bemsurg/constants.hpp: mathematical constants, spelt once for every module (core: no module
// below it, so kernels, quadrature and io need not reach into mesh/ for a number).
#pragma once

namespace bemsurg {

namespace numbers {
/// pi to double precision: the one spelling in bemsurg (M_PI is POSIX, not standard C++17).
/// Named as C++20's std::numbers::pi, which it becomes when the project moves to C++20.
inline constexpr double pi = 3.14159265358979323846;
}  // namespace numbers

}  // namespace bemsurg
