// A consumer of the hierarchical-matrix backend (bemsurg::hmatrix, docs/solvers.md "Hierarchical
// matrices"): a soft block held at its bottom, sagging under gravity, solved dense and by H-LU; the
// two answers compared. The package says whether it was built with hmat-oss (BEMSURG_WITH_HMATRIX),
// and this program fails when it was and the backend is missing, or when the answers differ.
#include <bemsurg/elastostatics/elastostatic_solver.hpp>
#include <bemsurg/elastostatics/hierarchical_solver.hpp>
#include <bemsurg/mesh/mesh_generators.hpp>
#include <iostream>

int main() {
  using namespace bemsurg;
  ElastostaticProblem block{box_mesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.03), 10, 10, 3),
                            Material{3000.0, 0.45, 1000.0},
                            Eigen::Vector3d(0.0, 0.0, -9.81),
                            BoundaryConditions(),
                            {}};
  block.boundary_conditions = BoundaryConditions(block.mesh.num_elements());
  for (Index e = 0; e < block.mesh.num_elements(); ++e)
    if (block.mesh.normal(e).z() < -0.99) block.boundary_conditions.prescribe_displacement(e, Eigen::Vector3d::Zero());
  if (!hierarchical_backend_available()) {
#ifdef BEMSURG_EXPECT_HMATRIX
    std::cerr << "consumer_hmatrix: the package says it has the hierarchical backend, but it is missing\n";
    return 1;
#else
    std::cout << "consumer_hmatrix: bemsurg was built without hmat-oss; nothing to check\n";
    return 0;
#endif
  }
  LinearSolverOptions options;
  options.backend = SolverBackend::HMatrix;
  options.compression_tolerance = 1e-6;
  HierarchicalResult r;
  const ElastostaticSolution h = solve_elastostatic_hierarchical(block, options, &r);
  const ElastostaticSolution d = solve_elastostatic(block);
  const double difference =
      (h.boundary.displacement - d.boundary.displacement).cwiseAbs().maxCoeff() / d.boundary.displacement.cwiseAbs().maxCoeff();
  std::cout << "consumer_hmatrix: " << block.mesh.num_elements() << " elements, " << r.compression_ratio
            << " of dense storage, displacement against the dense solve " << difference << "\n";
  return difference <= 1e-4 ? 0 : 1;
}
