// A scene's "method": "auto" resolved for one command (docs/solvers.md, "Hierarchical matrices"):
// choose_backend picks dense LU or the hierarchical backend for the scene's mesh, and the command
// says which and why before it starts (stderr, a note, unless quiet).
#pragma once

#include <iostream>
#include <string>
#include <utility>

#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/io/scene.hpp"

namespace bemsurg::cli {

/// `scene` with its backend chosen when it says "auto" (unchanged otherwise).
inline Scene with_chosen_backend(Scene scene, bool quiet, const std::string& command) {
  if (!scene.solver.automatic_backend) return scene;
  const BackendChoice c = choose_backend(scene.problem.mesh.num_elements(), scene.problem.elements);
  scene.solver.backend = c.backend;
  if (!quiet) std::cerr << "bemsurg: note: " << command << ": solver method auto: " << c.reason << "\n";
  return scene;
}

}  // namespace bemsurg::cli
