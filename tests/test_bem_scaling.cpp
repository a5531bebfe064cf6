// Physical units do not change the answer: the cube under uniform pressure solved in SI units for
// steel (E = 2e11 Pa) on a 1 mm cube has the same relative error as with E = 1 on a unit cube.
// A* then mixes H columns (~1/2) with -G columns (~1e-15), so every singularity test on the way
// (DenseLu, the Green's table's in-place LU, the block-Jacobi blocks) must be scale-invariant.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/solvers/block_jacobi_preconditioner.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "bemsurg/solvers/lu_in_place.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;

namespace {

struct Units {
  double size;      // cube edge, m
  double young;     // Pa
  double pressure;  // Pa
};
const Units kUnit{1.0, 1.0, 1.0};
const Units kSteelMillimetre{1e-3, 2e11, 1e6};

TriangleMesh cube(double size) { return box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(size), 2, 2, 2); }

/// Exact traces with a few elements held, and the bottom face (z = 0) on rollers: u_z prescribed,
/// t_x and t_y prescribed, so its elements' 3x3 blocks mix an H column with -G columns.
BoundaryConditions mixed_conditions(const TriangleMesh& m, const ElasticField& field) {
  const auto held = a_few_elements(m);
  BoundaryConditions bc = exact_trace_conditions(m, field, held);
  for (Index e = 0; e < m.num_elements(); ++e) {
    if (held(e) || !(m.normal(e).z() < -0.999)) continue;
    const Eigen::Vector3d x = m.centroid(e);
    const Eigen::Vector3d t = field.stress(x) * m.normal(e);
    bc.prescribe_component(e, 0, BcKind::Traction, t.x());
    bc.prescribe_component(e, 1, BcKind::Traction, t.y());
    bc.prescribe_component(e, 2, BcKind::Displacement, field.displacement(x).z());
  }
  return bc;
}

RelativeErrors solve_mixed(const Units& u, const LinearSolverOptions& settings) {
  const TriangleMesh m = cube(u.size);
  const Material material{u.young, 0.3, 0.0};
  const ElasticField field = uniform_pressure_field(material, u.pressure);
  ElastostaticProblem p{m, material, Eigen::Vector3d::Zero(), mixed_conditions(m, field), QuadratureOptions()};
  const ElastostaticSolution s = solve_elastostatic(p, settings);
  return relative_l2_errors(m, p.boundary_conditions, s.boundary, exact_traces(m, field));
}

/// The two solutions differ by round-off (and GMRES's tolerance) only. The system (144 unknowns)
/// has condition number 12-16 once its columns are equilibrated (LU with partial pivoting does not
/// see column scaling, and the block-Jacobi blocks are equilibrated the same way); its entries are
/// sums of up to 925 quadrature terms; GMRES stops at relative residual 1e-13. So the solutions
/// differ by at most ~16 x ((925 + 144) eps + 1e-13) = 5e-12 relative, which moves errors of ~4 %
/// by 1.5e-10 of themselves. Measured: at most 8e-14 (LU vs GMRES), 6e-15 between units. Bound 1e-9.
void check_same(const RelativeErrors& a, const RelativeErrors& b) {
  INFO("u: " << a.displacement << " vs " << b.displacement << ", t: " << a.traction << " vs " << b.traction);
  CHECK(std::abs(a.displacement - b.displacement) <= 1e-9 * std::abs(a.displacement));
  CHECK(std::abs(a.traction - b.traction) <= 1e-9 * std::abs(a.traction));
}

}  // namespace

TEST_CASE("uniform pressure: steel on a 1 mm cube matches E = 1 on a unit cube (direct LU)", "[bem][scaling]") {
  RelativeErrors errors[2];
  int k = 0;
  for (const Units& u : {kUnit, kSteelMillimetre}) {
    const TriangleMesh m = cube(u.size);
    const Material material{u.young, 0.3, 0.0};
    REQUIRE_NOTHROW(errors[k] = solve_exact_trace_problem(m, material, uniform_pressure_field(material, u.pressure), a_few_elements(m)));
    ++k;
  }
  CHECK(errors[0].displacement > 0.0);
  CHECK(errors[0].displacement < 0.1);  // measured 0.038
  check_same(errors[0], errors[1]);
}

TEST_CASE("uniform pressure with rollers: scale-invariant by LU and by block-Jacobi GMRES", "[bem][scaling]") {
  LinearSolverOptions lu;
  LinearSolverOptions gmres;
  gmres.method = SolverMethod::Gmres;
  gmres.preconditioner = PreconditionerKind::BlockJacobi;
  gmres.tolerance = 1e-13;
  RelativeErrors by_lu[2], by_gmres[2];
  int k = 0;
  for (const Units& u : {kUnit, kSteelMillimetre}) {
    REQUIRE_NOTHROW(by_lu[k] = solve_mixed(u, lu));
    REQUIRE_NOTHROW(by_gmres[k] = solve_mixed(u, gmres));
    ++k;
  }
  check_same(by_lu[0], by_lu[1]);
  check_same(by_gmres[0], by_gmres[1]);
  check_same(by_lu[0], by_gmres[0]);
}

TEST_CASE("singularity tests judge column-equilibrated pivots", "[bem][scaling]") {
  const int n = 24;
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n) + 4.0 * Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(n);
  for (int j = 0; j < n; j += 2) scale(j) = 1e-15;  // as -G's columns for steel, millimetre elements
  const Eigen::MatrixXd As = A * scale.asDiagonal();
  // The unknowns of the small columns are large (tractions in Pa): x = D^-1 z with z = O(1).
  const Eigen::VectorXd z = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  const Eigen::VectorXd x = z.cwiseQuotient(scale);
  const Eigen::VectorXd b = A * z;

  // Partial pivoting picks the same pivots whatever the column scaling, so the scaled unknowns z
  // come out as accurately as from A itself: backward error ~3 n eps, forward error that times
  // cond(A) (Frobenius estimate, ~40 here). Measured 2.7e-16 and 3.9e-16 relative.
  const double kappa = A.norm() * A.inverse().norm();
  const double bound = 3.0 * n * std::numeric_limits<double>::epsilon() * kappa;
  const DenseLu lu(As);
  REQUIRE(lu.info() == Eigen::Success);
  const Eigen::VectorXd y = lu.solve(b);
  CHECK((y - x).cwiseProduct(scale).norm() <= bound * z.norm());

  Eigen::MatrixXd copy = As;
  Eigen::MatrixXd rhs = b;
  REQUIRE_NOTHROW(lu_factor_and_solve_in_place(copy, rhs));
  CHECK((rhs.col(0) - x).cwiseProduct(scale).norm() <= bound * z.norm());

  // A genuinely singular matrix is still caught, at either scale: one column repeats another.
  for (double s : {1.0, 1e-15}) {
    Eigen::MatrixXd S = A;
    S.col(3) = S.col(5);
    S *= s;
    CHECK(DenseLu(S).info() == Eigen::NumericalIssue);
    Eigen::MatrixXd B = Eigen::MatrixXd::Ones(n, 1);
    CHECK_THROWS_AS(lu_factor_and_solve_in_place(S, B), SolverError);
  }
  Eigen::MatrixXd Z = A;
  Z.col(7).setZero();
  CHECK(DenseLu(Z).info() == Eigen::NumericalIssue);

  // Block Jacobi: a block with one O(1) and two O(1e-15) columns is invertible.
  Eigen::MatrixXd blocks = Eigen::MatrixXd::Zero(6, 6);
  blocks.block<3, 3>(0, 0) << 0.5, 1e-15, 0.0, 0.1, 2e-15, 0.0, 0.0, 0.0, 3e-15;
  blocks.block<3, 3>(3, 3) = Eigen::Matrix3d::Identity();
  const BlockJacobiPreconditioner M(blocks);
  CHECK((M.inverse_blocks().block<3, 3>(0, 0) * blocks.block<3, 3>(0, 0) - Eigen::Matrix3d::Identity()).norm() < 1e-12);
  blocks(2, 2) = 0.0;
  CHECK_THROWS_AS(BlockJacobiPreconditioner(blocks), SolverError);
}
