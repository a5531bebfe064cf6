// bemsurg/error.hpp: the exceptions bemsurg throws. Every message names the offending item
// (face, edge, key, element) so a user can act on it; programs catch them at their edge.
#pragma once

#include <stdexcept>
#include <string>

namespace bemsurg {

/// Base of every bemsurg error.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The surface mesh is unusable: open, non-manifold, flipped, degenerate, non-finite, unreadable.
class InvalidMeshError : public Error {
 public:
  using Error::Error;
};

/// Material constants outside their physical range (E <= 0, nu outside (-1, 0.5), rho < 0).
class InvalidMaterialError : public Error {
 public:
  using Error::Error;
};

/// Boundary conditions that leave rigid-body motion free, or that do not fit the mesh.
class BoundaryConditionError : public Error {
 public:
  using Error::Error;
};

/// A linear solver did not reach its tolerance, broke down, or met non-finite values.
class SolverError : public Error {
 public:
  using Error::Error;
};

/// A scene file or command line that cannot be used (missing key, wrong type, bad value).
class SceneError : public Error {
 public:
  using Error::Error;
};

/// A memory estimate that does not fit, or a cache file that is stale or corrupt.
class ResourceError : public Error {
 public:
  using Error::Error;
};

}  // namespace bemsurg
