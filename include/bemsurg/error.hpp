// bemsurg/error.hpp: the exceptions bemsurg throws, one family with a type per cause, so that a
// caller can catch what it can act on (a bad mesh, a stale cache file, a full contact set) and
// let the rest reach its edge. Every message names the offending item (face, edge, key, element,
// file) so a user can act on it. The haptic force path never throws (docs/design.md §9): it
// returns statuses; these exceptions belong to set-up, loading and the simulation side.
#pragma once

#include <stdexcept>
#include <string>

namespace bemsurg {

/// Base of every bemsurg error: `catch (const bemsurg::Error&)` catches them all.
/// \ingroup core
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The surface mesh is unusable: open, non-manifold, flipped, degenerate, non-finite, malformed.
/// \ingroup core
class InvalidMeshError : public Error {
 public:
  using Error::Error;
};

/// Material constants outside their physical range (E <= 0, nu outside (-1, 0.5), rho < 0).
/// \ingroup core
class InvalidMaterialError : public Error {
 public:
  using Error::Error;
};

/// Boundary conditions that leave rigid-body motion free, or that do not fit the mesh.
/// \ingroup core
class BoundaryConditionError : public Error {
 public:
  using Error::Error;
};

/// A linear solver did not reach its tolerance, broke down, met non-finite values, or the
/// system is singular.
/// \ingroup core
class SolverError : public Error {
 public:
  using Error::Error;
};

/// A scene file or command line that cannot be used (missing key, wrong type, bad value).
/// \ingroup core
class SceneError : public Error {
 public:
  using Error::Error;
};

/// A computation whose memory or cost estimate does not fit this machine; refused before it starts.
/// \ingroup core
class ResourceError : public Error {
 public:
  using Error::Error;
};

/// A file that cannot be opened, read or written, or whose content is corrupt or stale (a
/// pre-solution table computed for another mesh, material or version).
/// \ingroup core
class IoError : public Error {
 public:
  using Error::Error;
};

/// A contact tool or contact set that cannot be used: a tool that misses the body, a pose that is
/// not finite, an element outside the table's region.
/// \ingroup core
class ContactError : public Error {
 public:
  using Error::Error;
};

/// The contact set would exceed the capacity reserved up front (the force path never allocates);
/// construct the contact model with a larger capacity.
/// \ingroup core
class CapacityError : public ContactError {
 public:
  using ContactError::ContactError;
};

/// An argument outside the documented range of a function or option (sizes that do not agree,
/// a non-positive limit): a programming error in the caller, not a property of the model.
/// \ingroup core
class InvalidArgumentError : public Error {
 public:
  using Error::Error;
};

}  // namespace bemsurg
