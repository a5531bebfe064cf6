// A consumer of bemsurg::distributed (docs/distributed.md): a soft block held at its bottom, sagging
// under gravity, solved by ScaLAPACK as a single-rank MPI job (run without mpirun; under
// `mpirun -np K` the ranks share A*) and by the dense LU; the two answers compared. The package says
// whether it was built with MPI (BEMSURG_WITH_MPI), and this program fails when it was and the
// backend is missing, or when the answers differ.
#include <bemsurg/distributed/mpi_runtime.hpp>
#include <bemsurg/distributed/scalapack_solver.hpp>
#include <bemsurg/elastostatics/elastostatic_solver.hpp>
#include <bemsurg/mesh/mesh_generators.hpp>
#include <iostream>

int main() {
  using namespace bemsurg;
  if (!distributed_backend_available()) {
#ifdef BEMSURG_EXPECT_MPI
    std::cerr << "consumer_distributed: the package says it has MPI and ScaLAPACK, but they are missing\n";
    return 1;
#else
    std::cout << "consumer_distributed: bemsurg was built without MPI; nothing to check\n";
    return 0;
#endif
  }
  ElastostaticProblem block{box_mesh(Eigen::Vector3d(-0.05, -0.05, 0.0), Eigen::Vector3d(0.05, 0.05, 0.03), 8, 8, 3),
                            Material{3000.0, 0.45, 1000.0},
                            Eigen::Vector3d(0.0, 0.0, -9.81),
                            BoundaryConditions(),
                            {}};
  block.boundary_conditions = BoundaryConditions(block.mesh.num_elements());
  for (Index e = 0; e < block.mesh.num_elements(); ++e)
    if (block.mesh.normal(e).z() < -0.99) block.boundary_conditions.prescribe_displacement(e, Eigen::Vector3d::Zero());
  const MpiRuntime mpi(true);  // MPI for the method: one rank without mpirun
  ScalapackResult r;
  const ElastostaticSolution s = solve_elastostatic_scalapack(mpi, block, &r);
  if (!mpi.root()) return 0;
  const ElastostaticSolution d = solve_elastostatic(block);
  const double difference =
      (s.boundary.displacement - d.boundary.displacement).cwiseAbs().maxCoeff() / d.boundary.displacement.cwiseAbs().maxCoeff();
  std::cout << "consumer_distributed: " << block.mesh.num_elements() << " elements on " << mpi.size() << " rank(s), a " << r.process_rows
            << " x " << r.process_columns << " grid; displacement against the dense LU " << difference << "\n";
  return difference <= 1e-10 ? 0 : 1;
}
