// Bad input to the solver gets a clear error that names the problem, never garbage.
#include <catch2/catch.hpp>

#include <chrono>
#include <limits>
#include <vector>

#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/quadrature/quadrature_cost.hpp"
#include "bemsurg/solvers/dense_lu.hpp"

using namespace bemsurg;
using Catch::Matchers::Contains;

TEST_CASE("a body with no displacement condition is reported as unsupported") {
  const TriangleMesh m = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 1, 1, 1);
  ElastostaticProblem p{m, Material{1.0, 0.3, 1.0}, Eigen::Vector3d(0, 0, -9.81), BoundaryConditions(m.num_elements()), {}};
  CHECK_THROWS_AS(solve_elastostatic(p), BoundaryConditionError);
  CHECK_THROWS_WITH(solve_elastostatic(p), Contains("no support"));
}

TEST_CASE("support that leaves a rotation free is named") {
  const TriangleMesh m = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 1, 1, 1);
  BoundaryConditions bc(m.num_elements());
  bc.prescribe_displacement(0, Eigen::Vector3d::Zero());  // one element pinned: rotations about it stay free
  ElastostaticProblem p{m, Material{1.0, 0.3, 0.0}, Eigen::Vector3d::Zero(), bc, {}};
  CHECK_THROWS_WITH(solve_elastostatic(p), Contains("rotation"));
}

TEST_CASE("Poisson's ratio outside (-1, 0.5) and non-positive stiffness are rejected") {
  const TriangleMesh m = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 1, 1, 1);
  BoundaryConditions bc(m.num_elements());
  for (Index e = 0; e < m.num_elements(); ++e) bc.prescribe_displacement(e, Eigen::Vector3d::Zero());
  for (const Material bad : {Material{1.0, 0.5, 0.0}, Material{1.0, -1.0, 0.0}, Material{0.0, 0.3, 0.0}, Material{1.0, std::nan(""), 0.0},
                             Material{1.0, 0.3, -1.0}}) {
    ElastostaticProblem p{m, bad, Eigen::Vector3d::Zero(), bc, {}};
    CHECK_THROWS_AS(solve_elastostatic(p), InvalidMaterialError);
  }
}

TEST_CASE("boundary conditions of the wrong size or element are rejected") {
  const TriangleMesh m = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 1, 1, 1);
  BoundaryConditions bc(m.num_elements());
  CHECK_THROWS_WITH(bc.prescribe_displacement(m.num_elements(), Eigen::Vector3d::Zero()), Contains("out of range"));
  ElastostaticProblem p{m, Material{1.0, 0.3, 0.0}, Eigen::Vector3d::Zero(), BoundaryConditions(3), {}};
  CHECK_THROWS_AS(solve_elastostatic(p), BoundaryConditionError);
}

TEST_CASE("a dense solve that cannot fit in memory is refused before allocating") {
  // 12 * 80^2 = 76,800 elements: H and G (A* is built in H's storage) would need about 0.85 TB
  // (2 x 8 x 230,400^2 bytes).
  const TriangleMesh m = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 80, 80, 80);
  REQUIRE(m.num_elements() == 76800);
  const double need = estimate_elastostatic_bytes(m.num_elements());
  // The estimate is 8 (2 n^2 + 8 n) bytes (H, G and eight n-vectors): 4 / n = 1.74e-5 above the
  // matrices' 16 n^2. Window ~3x that.
  CHECK(need == Approx(2.0 * 8.0 * 230400.0 * 230400.0).epsilon(5e-5));
  if (need <= default_memory_limit_bytes()) {
    WARN("this machine has more than 1 TB of memory; the refusal is not exercised");
    return;
  }
  BoundaryConditions bc(m.num_elements());
  for (Index e = 0; e < m.num_elements(); ++e)
    if (m.normal(e).z() < -0.999) bc.prescribe_displacement(e, Eigen::Vector3d::Zero());
  ElastostaticProblem p{m, Material{1.0, 0.3, 0.0}, Eigen::Vector3d::Zero(), bc, {}};
  const auto start = std::chrono::steady_clock::now();
  CHECK_THROWS_AS(solve_elastostatic(p), ResourceError);
  CHECK_THROWS_WITH(solve_elastostatic(p), Contains("76800 elements") && Contains(format_gib(need)) && Contains("physical memory"));
  // Refused before assembly, which would take hours here: 60 s tells the two apart on any machine
  // and under the sanitizers (a hang detector, not a speed bound).
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(60));
}

namespace {
// A unit cube held on its bottom face and pressed on its top: the correct input the
// non-finite cases below are variations of.
ElastostaticProblem pressed_cube(double scale, double youngs_modulus) {
  // Supports chosen on the unit cube: a huge mesh's normals may have overflowed to zero.
  const TriangleMesh unit = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 2, 2, 2);
  const TriangleMesh m(scale * unit.vertices(), unit.faces());
  BoundaryConditions bc(m.num_elements());
  for (Index e = 0; e < m.num_elements(); ++e) {
    if (unit.normal(e).z() < -0.999) bc.prescribe_displacement(e, Eigen::Vector3d::Zero());
    if (unit.normal(e).z() > 0.999) bc.prescribe_pressure(e, 1.0, unit.normal(e));
  }
  return ElastostaticProblem{m, Material{youngs_modulus, 0.3, 0.0}, Eigen::Vector3d::Zero(), bc, {}};
}
}  // namespace

TEST_CASE("a non-finite system from a vanishing Young's modulus is refused by LU and GMRES") {
  LinearSolverOptions lu, gmres;
  gmres.method = SolverMethod::Gmres;
  // The correct input solves with both methods and gives finite displacements.
  for (const LinearSolverOptions& s : {lu, gmres}) {
    const ElastostaticSolution ok = solve_elastostatic(pressed_cube(1.0, 1e3), s);
    CHECK(ok.report.solver.status == KrylovStatus::Converged);
    CHECK(ok.boundary.displacement.allFinite());
  }
  // E = the smallest positive double passes Material::validate (E > 0), but 1 / mu overflows in G.
  for (const LinearSolverOptions& s : {lu, gmres}) {
    const ElastostaticProblem p = pressed_cube(1.0, std::numeric_limits<double>::denorm_min());
    CHECK_THROWS_AS(solve_elastostatic(p, s), SolverError);
    CHECK_THROWS_WITH(solve_elastostatic(p, s), Contains("non-finite") && Contains("Young's modulus") && Contains("mesh scale"));
  }
}

TEST_CASE("a mesh scaled to 1e80 gives a SolverError naming the cause, not a crash") {
  LinearSolverOptions lu, gmres;
  gmres.method = SolverMethod::Gmres;
  for (const LinearSolverOptions& s : {lu, gmres}) {
    const ElastostaticProblem p = pressed_cube(1e80, 1e3);
    CHECK_THROWS_AS(solve_elastostatic(p, s), SolverError);
    CHECK_THROWS_WITH(solve_elastostatic(p, s), Contains("non-finite") && Contains("mesh scale"));
  }
}

TEST_CASE("solve_linear_system and DenseLu refuse NaN and infinity before factorising") {
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(6, 6);
  Eigen::VectorXd b = Eigen::VectorXd::Ones(6);
  LinearSolveResult summary;
  CHECK(solve_linear_system(A, b, LinearSolverOptions(), summary).isApprox(b));
  A(4, 2) = std::numeric_limits<double>::quiet_NaN();
  CHECK_THROWS_WITH(solve_linear_system(A, b, LinearSolverOptions(), summary), Contains("system matrix") && Contains("row 4, column 2"));
  CHECK(summary.status == KrylovStatus::NonFinite);
  CHECK_THROWS_WITH(DenseLu(A), Contains("non-finite") && Contains("row 4, column 2"));
  A(4, 2) = 0.0;
  b(5) = std::numeric_limits<double>::infinity();
  CHECK_THROWS_WITH(solve_linear_system(A, b, LinearSolverOptions(), summary),
                    Contains("right-hand side") && Contains("element 1, component z"));
}

namespace {
// Two surfaces in one mesh; `flip_b` reverses b's faces (a cavity's normals point into it).
TriangleMesh join(const TriangleMesh& a, const TriangleMesh& b, bool flip_b = false) {
  RowMatrixX3d V(a.num_vertices() + b.num_vertices(), 3);
  V << a.vertices(), b.vertices();
  RowMatrixX3i Fb = (b.faces().array() + static_cast<int>(a.num_vertices())).matrix();
  if (flip_b) Fb.col(1).swap(Fb.col(2));
  RowMatrixX3i F(a.num_elements() + Fb.rows(), 3);
  F << a.faces(), Fb;
  return TriangleMesh(V, F);
}

// Holds the bottom (z = min) faces of elements [first, last) fixed.
void hold_bottom(const TriangleMesh& m, Index first, Index last, BoundaryConditions& bc) {
  for (Index e = first; e < last; ++e)
    if (m.normal(e).z() < -0.999) bc.prescribe_displacement(e, Eigen::Vector3d::Zero());
}
}  // namespace

TEST_CASE("a second closed body without support is named, not solved") {
  const TriangleMesh a = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 2, 2, 2);
  const TriangleMesh b = box_mesh(Eigen::Vector3d(3, 0, 0), Eigen::Vector3d(4, 1, 1), 2, 2, 2);
  const TriangleMesh both = join(a, b);
  const Index na = a.num_elements(), n = both.num_elements();
  BoundaryConditions bc(n);
  hold_bottom(both, 0, na, bc);
  for (Index e = 0; e < n; ++e)
    if (both.normal(e).z() > 0.999) bc.prescribe_pressure(e, 1.0, both.normal(e));
  ElastostaticProblem p{both, Material{1e3, 0.3, 0.0}, Eigen::Vector3d::Zero(), bc, {}};
  CHECK_THROWS_AS(solve_elastostatic(p), BoundaryConditionError);
  CHECK_THROWS_WITH(solve_elastostatic(p), Contains("body 1 of 2") && Contains("shell 1") && Contains("element " + std::to_string(na)) &&
                                               Contains("no support") && Contains("translation x"));

  // One pinned element leaves the second body's rotations free: named as such.
  p.boundary_conditions.prescribe_displacement(na, Eigen::Vector3d::Zero());
  CHECK_THROWS_WITH(solve_elastostatic(p), Contains("body 1 of 2") && Contains("not fully supported") && Contains("rotation"));

  // Both held: it solves, and the first body moves as it does alone (the bodies do not interact).
  hold_bottom(both, na, n, p.boundary_conditions);
  const ElastostaticSolution sol = solve_elastostatic(p);
  CHECK(sol.report.solver.status == KrylovStatus::Converged);
  BoundaryConditions alone_bc(na);
  hold_bottom(a, 0, na, alone_bc);
  for (Index e = 0; e < na; ++e)
    if (a.normal(e).z() > 0.999) alone_bc.prescribe_pressure(e, 1.0, a.normal(e));
  const ElastostaticSolution alone = solve_elastostatic({a, Material{1e3, 0.3, 0.0}, Eigen::Vector3d::Zero(), alone_bc, {}});
  const double scale = alone.boundary.displacement.cwiseAbs().maxCoeff();
  REQUIRE(scale > 0.0);
  // The discretised bodies still see each other a little (the other body's traces integrate to
  // zero only up to quadrature and collocation error): measured 5.0e-3 of the displacement; bound
  // ~3x. The second body, loaded alike, moves about as much: measured 1.005 x scale.
  CHECK((sol.boundary.displacement.topRows(na) - alone.boundary.displacement).cwiseAbs().maxCoeff() < 0.015 * scale);
  CHECK(sol.boundary.displacement.bottomRows(n - na).cwiseAbs().maxCoeff() < 2.0 * scale);
}

TEST_CASE("a cavity belongs to its body, an island inside it is a body of its own") {
  // A hollow box (outer shell 0, inward-facing cavity shell 1) held on its outer bottom.
  const TriangleMesh outer = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(3.0), 2, 2, 2);
  const TriangleMesh cavity = box_mesh(Eigen::Vector3d::Constant(0.5), Eigen::Vector3d::Constant(2.5), 2, 2, 2);
  const TriangleMesh hollow = join(outer, cavity, true);
  const MeshTopology topo(hollow);
  REQUIRE(topo.num_shells() == 2);
  CHECK(shell_bodies(hollow, topo) == std::vector<Index>{0, 0});
  BoundaryConditions bc(hollow.num_elements());
  hold_bottom(hollow, 0, outer.num_elements(), bc);
  CHECK_NOTHROW(bc.require_supported(hollow));

  // An island floating inside the cavity is a second body, and it has no support.
  const TriangleMesh island = box_mesh(Eigen::Vector3d::Constant(1.0), Eigen::Vector3d::Constant(2.0), 1, 1, 1);
  const TriangleMesh three = join(hollow, island);
  CHECK(shell_bodies(three, MeshTopology(three)) == std::vector<Index>{0, 0, 1});
  BoundaryConditions bc3(three.num_elements());
  hold_bottom(three, 0, outer.num_elements(), bc3);
  CHECK_THROWS_AS(bc3.require_supported(three), BoundaryConditionError);
  CHECK_THROWS_WITH(bc3.require_supported(three),
                    Contains("body 1 of 2") && Contains("shell 2") && Contains("element " + std::to_string(hollow.num_elements())));
}

TEST_CASE("quadrature cost is counted exactly per pair and estimated from a sample of sources") {
  const TriangleMesh m = icosphere_mesh(Eigen::Vector3d::Zero(), 1.0, 3);  // 1280 elements
  QuadratureOptions o;
  o.far_ratio = 100.0;
  o.mid_ratio = 6.0;
  const ElementQuadrature q(o);
  // count_points makes integrate's decisions: the same number of points, for a neighbour, a
  // near and a far element.
  const Vec3 p = m.centroid(0);
  double total_visited = 0.0, total_counted = 0.0;
  for (Index j : {Index(1), Index(40), Index(700), Index(1279)}) {
    const auto c = m.corners(j);
    double visited = 0.0;
    q.integrate(p, c[0], c[1], c[2], [&](const Vec3&, double) { visited += 1.0; });
    CHECK(q.count_points(p, c[0], c[1], c[2], 1e300) == visited);
    total_visited += visited;
    total_counted += q.count_points(p, c[0], c[1], c[2], 1e300);
  }
  CHECK(total_counted == total_visited);
  // 16 sampled sources (the default) against all 1280 (exact). Measured: 2.5 % apart; bound 3.5 %.
  const QuadratureCostEstimate sampled = estimate_assembly_quadrature(m, o, 1e300);
  const QuadratureCostEstimate exact = estimate_assembly_quadrature(m, o, 1e300, m.num_elements());
  REQUIRE(exact.sampled_sources == m.num_elements());
  CHECK_FALSE(sampled.exceeded);
  INFO("sampled " << sampled.points << " exact " << exact.points);
  CHECK(std::abs(sampled.points / exact.points - 1.0) < 0.035);
  // The limit stops the count early and says so.
  const QuadratureCostEstimate stopped = estimate_assembly_quadrature(m, o, 0.01 * exact.points);
  CHECK(stopped.exceeded);
  CHECK(stopped.points > 0.01 * exact.points);
}

TEST_CASE("ruinous quadrature options are refused with the estimate before assembly") {
  // Before: far_ratio = mid_ratio = 1000 on 80 elements (inside every documented range) ran for
  // minutes (more than 30 s measured before it was stopped); now refused in well under a second.
  const TriangleMesh m = icosphere_mesh(Eigen::Vector3d::Zero(), 1.0, 1);
  BoundaryConditions bc(m.num_elements());
  for (Index e = 0; e < m.num_elements(); ++e)
    if (m.centroid(e).z() < -0.5) bc.prescribe_displacement(e, Eigen::Vector3d::Zero());
  ElastostaticProblem p{m, Material{1e3, 0.3, 1000.0}, Eigen::Vector3d(0, 0, -9.81), bc, {}};
  p.quadrature.far_ratio = 1000.0;
  p.quadrature.mid_ratio = 1000.0;
  CHECK_THROWS_AS(solve_elastostatic(p), ResourceError);
  CHECK_THROWS_WITH(solve_elastostatic(p),
                    Contains("kernel evaluations on 80 elements") && Contains("mid_ratio 1e+03") && Contains("lower mid_ratio"));
  GreensTableOptions to;
  to.quadrature = p.quadrature;
  CHECK_THROWS_WITH(GreensTable::compute(m, p.material, bc, to), Contains("GreensTable") && Contains("kernel evaluations"));
  // Finer than the defaults but affordable (mid_ratio 30: about 1 s here) is not refused.
  p.quadrature.mid_ratio = 30.0;
  CHECK_NOTHROW(require_assembly_quadrature_within(m, p.quadrature, "test"));
}
