// Linear discontinuous elements (docs/elements.md): the assembler against its own pair-by-pair rules
// and the constant assembler, the rigid-body identity, and the closed-form problems of
// docs/design.md §8 with exact values at the collocation nodes (u(x_k), sigma(x_k) n), errors at
// the nodes. Small meshes (9 unknowns per element); the bounds are ~1.3x the measured errors and
// ~0.75x the measured orders (Release, one thread), written beside each check. The larger sweep
// (both element types, time and memory) is benchmarks/bench_accuracy.cpp.
#include <catch2/catch.hpp>

#include "bemsurg/assembly/node_influence_assembler.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/red_green_refinement.hpp"
#include "bemsurg/verification/reference_solutions.hpp"
#include "support/convergence.hpp"
#include "support/studies/grading_setup.hpp"
#include "support/temp_dir.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;
using bemsurg_test::observed_order;

namespace {
const Material kLinearMaterial{1.0, 0.3, 0.0};
const ElasticField kKelvin = kelvin_field(kLinearMaterial, Eigen::Vector3d(0.3, 0.2, 1.4), Eigen::Vector3d(0.4, -0.3, 1.0));
TriangleMesh linear_box(int n) { return box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 3 * n, 2 * n, 2 * n); }
auto all_held() {
  return [](Index) { return true; };
}
auto lower_half(const TriangleMesh& m) {
  return [&m](Index e) { return m.centroid(e).z() < 0.0; };
}
}  // namespace

TEST_CASE(
    "linear elements: blocked assembly equals the pair rules, rows of H sum to zero, the constant trait reproduces the constant assembler") {
  const TriangleMesh m = linear_box(1);
  const LinearInfluenceAssembler linear(m, kLinearMaterial);
  const InfluenceMatrices hg = linear.assemble();
  REQUIRE(hg.H.rows() == 9 * m.num_elements());
  // Rigid translation: every block row of H sums to zero (the self blocks are evaluated directly).
  // Measured: 1.4e-8 (box), 1.1e-8 (sphere).
  CHECK(rigid_body_row_sum_ratio(hg) < 5e-8);
  const TriangleMesh sphere = icosphere_mesh(Eigen::Vector3d::Zero(), 1.0, 1);
  CHECK(rigid_body_row_sum_ratio(LinearInfluenceAssembler(sphere, kLinearMaterial).assemble()) < 5e-8);
  // The blocked path (far pairs 64 nodes at a time) against node_element_pair, self and near pairs included.
  double worst = 0.0;
  LinearInfluenceAssembler::PairBlock H, G;
  for (Index i : {Index(0), Index(1), Index(5), Index(100), Index(191)})
    for (Index e = 0; e < m.num_elements(); ++e) {
      linear.node_element_pair(i, e, H, G);
      worst = std::max(worst, (hg.H.block<3, 9>(3 * i, 9 * e) - H).norm() / hg.H.block<3, 3>(3 * i, 3 * i).norm());
      worst = std::max(worst, (hg.G.block<3, 9>(3 * i, 9 * e) - G).norm() / hg.G.block<3, 3>(3 * i, 3 * i).norm());
    }
  CHECK(worst < 1e-12);
  // The same template with the constant trait: the constant assembler's matrices (to quadrature
  // round-off; measured 6e-11, pairs exactly at a rule threshold may take the other rule).
  const InfluenceMatrices c = InfluenceAssembler(m, kLinearMaterial).assemble();
  const InfluenceMatrices g = NodeInfluenceAssembler<ConstantElement>(m, kLinearMaterial).assemble();
  CHECK((c.H - g.H).norm() < 1e-9 * c.H.norm());
  CHECK((c.G - g.G).norm() < 1e-9 * c.G.norm());
}

TEST_CASE(
    "linear elements: a rigid motion is reproduced exactly, the Krylov solvers agree with LU, the memory estimate counts 9 unknowns per element") {
  // u = a + w x x (linear, so represented exactly at the nodes), zero stress: traction 0 everywhere.
  const Eigen::Vector3d a(0.01, -0.02, 0.03), w(0.002, 0.001, -0.003);
  const ElasticField rigid{[=](const Eigen::Vector3d& x) { return Eigen::Vector3d(a + w.cross(x)); },
                           [](const Eigen::Vector3d&) { return Eigen::Matrix3d(Eigen::Matrix3d::Zero()); }};
  const TriangleMesh m = linear_box(1);
  BoundarySolution s;
  solve_linear_exact_trace_problem(m, kLinearMaterial, rigid, lower_half(m), Eigen::Vector3d::Zero(), &s);
  const BoundarySolution exact = exact_node_traces(m, rigid);
  // Measured: 3e-9 (u), 1e-10 (t, relative to the load scale |a| mu).
  CHECK((s.displacement - exact.displacement).cwiseAbs().maxCoeff() < 1e-7 * a.norm());
  CHECK(s.traction.cwiseAbs().maxCoeff() < 1e-6 * a.norm() * kLinearMaterial.shear_modulus());
  CHECK(estimate_elastostatic_bytes(100, ElementType::Linear) > 8.9 * estimate_elastostatic_bytes(100));
  // The Krylov methods with block-Jacobi (3x3 node blocks) and the near-field preconditioner (on the
  // proxy mesh of corner children) agree with LU on a mixed Kelvin problem.
  ElastostaticProblem p{m, kLinearMaterial, Eigen::Vector3d::Zero(), exact_trace_conditions(m, kKelvin, lower_half(m)),
                        QuadratureOptions()};
  p.elements = ElementType::Linear;
  const ElastostaticSolution lu = solve_elastostatic(p);
  REQUIRE(lu.nodes.displacement.rows() == 3 * m.num_elements());
  for (SolverMethod method : {SolverMethod::Gmres, SolverMethod::BiCgStab, SolverMethod::BiCg})
    for (PreconditionerKind pre : {PreconditionerKind::BlockJacobi, PreconditionerKind::NearField}) {
      LinearSolverOptions o;
      o.method = method;
      o.preconditioner = pre;
      const ElastostaticSolution k = solve_elastostatic(p, o);
      INFO(to_string(method) << " with " << to_string(pre) << ": " << k.report.solver.iterations << " iterations");
      CHECK((k.nodes.displacement - lu.nodes.displacement).norm() < 1e-7 * lu.nodes.displacement.norm());
      CHECK((k.nodes.traction - lu.nodes.traction).norm() < 1e-7 * lu.nodes.traction.norm());
    }
}

TEST_CASE("linear elements, Kelvin box: second-order displacement and a fifth of the constant error on the same mesh") {
  // Mixed problem (lower half held): u on the upper half, t on the lower; h = 0.6 -> 0.3.
  std::vector<RelativeErrors> lin, con;
  std::vector<InteriorErrors> lin_inside, con_inside;
  RowMatrixX3d points(4, 3);  // bench_accuracy's interior points
  points << 0.0, 0.0, 0.0, 0.5, -0.2, 0.1, -0.4, 0.3, -0.2, 0.2, 0.1, 0.3;
  for (int n : {1, 2}) {
    const TriangleMesh m = linear_box(n);
    BoundarySolution nodes, centroids;
    lin.push_back(solve_linear_exact_trace_problem(m, kLinearMaterial, kKelvin, lower_half(m), Eigen::Vector3d::Zero(), &nodes));
    con.push_back(solve_exact_trace_problem(m, kLinearMaterial, kKelvin, lower_half(m), Eigen::Vector3d::Zero(), &centroids));
    // Somigliana's identity with the linear field (the 3E-row per-node solution).
    lin_inside.push_back(interior_relative_errors(m, kLinearMaterial, kKelvin, nodes, points));
    con_inside.push_back(interior_relative_errors(m, kLinearMaterial, kKelvin, centroids, points));
  }
  INFO("interior u: linear " << lin_inside[0].displacement << " -> " << lin_inside[1].displacement << ", constant "
                             << con_inside[0].displacement << " -> " << con_inside[1].displacement);
  INFO("interior stress: linear " << lin_inside[0].stress << " -> " << lin_inside[1].stress << ", constant " << con_inside[0].stress
                                  << " -> " << con_inside[1].stress);
  INFO("linear u " << lin[0].displacement << " -> " << lin[1].displacement << ", t " << lin[0].traction << " -> " << lin[1].traction);
  INFO("constant u " << con[0].displacement << " -> " << con[1].displacement << ", t " << con[0].traction << " -> " << con[1].traction);
  // Measured: u 2.37e-2 -> 2.68e-3 (order 3.1), t 4.69e-2 -> 1.78e-2 (1.4); constant on the same
  // meshes u 2.85e-2, t 9.2e-2.
  CHECK(observed_order(lin[0].displacement, lin[1].displacement, 0.6, 0.3) > 2.0);
  CHECK(observed_order(lin[0].traction, lin[1].traction, 0.6, 0.3) > 1.05);
  CHECK(lin[1].displacement < 0.0036);
  CHECK(lin[1].traction < 0.024);
  // Against constant elements on the same mesh (level k against k + 1 is bench_accuracy's, docs/elements.md).
  CHECK(lin[1].displacement < 0.2 * con[1].displacement);
  CHECK(lin[1].traction < 0.4 * con[1].traction);
  CHECK(lin_inside[1].displacement < 0.5 * con_inside[1].displacement);
  CHECK(lin_inside[1].stress < 0.5 * con_inside[1].stress);
  CHECK(observed_order(lin_inside[0].displacement, lin_inside[1].displacement, 0.6, 0.3) > 1.5);
}

TEST_CASE("linear elements, Kelvin box: the traction in the first row along the sharp edges falls with refinement") {
  // Dirichlet problem: traction solved everywhere; relative L2 at the nodes of the edge row.
  std::vector<RelativeErrors> lin;
  std::vector<bemsurg_test::SplitErrors> con;
  for (int n : {1, 2}) {
    const TriangleMesh m = linear_box(n);
    lin.push_back(solve_linear_exact_trace_problem(m, kLinearMaterial, kKelvin, all_held(), Eigen::Vector3d::Zero(), nullptr,
                                                   bemsurg_test::box_edge_row(m)));
    con.push_back(bemsurg_test::solve_split(m, kLinearMaterial, kKelvin, all_held()));
  }
  INFO("edge row t: linear " << lin[0].traction << " -> " << lin[1].traction << ", constant " << con[0].edge.traction << " -> "
                             << con[1].edge.traction);
  // Measured: linear 7.8e-2 -> 3.6e-2 (order 1.13), constant 0.141 -> 0.111 (0.34).
  CHECK(observed_order(lin[0].traction, lin[1].traction, 0.6, 0.3) > 0.85);
  CHECK(lin[1].traction < 0.047);
  CHECK(lin[1].traction < 0.4 * con[1].edge.traction);
}

TEST_CASE("linear elements, Lamé sphere: second-order displacement and a converging traction on two shells") {
  const ElasticField lame = lame_field(kLinearMaterial, Eigen::Vector3d::Zero(), 1.0, 2.0, 1.0, 0.0);
  std::vector<RelativeErrors> e;
  std::vector<double> h;
  for (int s : {0, 1}) {
    const TriangleMesh m = hollow_sphere_mesh(Eigen::Vector3d::Zero(), 1.0, 2.0, s, s);
    e.push_back(solve_linear_exact_trace_problem(m, kLinearMaterial, lame, [&m](Index k) { return m.centroid(k).norm() < 1.5; }));
    h.push_back(m.diameters().mean());
  }
  INFO("h " << h[0] << " -> " << h[1] << ", u " << e[0].displacement << " -> " << e[1].displacement << ", t " << e[0].traction << " -> "
            << e[1].traction);
  // Measured: h 1.58 -> 0.93, u 4.8e-2 -> 8.7e-3 (order 3.2), t 0.174 -> 7.2e-2 (1.66).
  CHECK(observed_order(e[0].displacement, e[1].displacement, h[0], h[1]) > 2.4);
  CHECK(observed_order(e[0].traction, e[1].traction, h[0], h[1]) > 1.25);
  CHECK(e[1].displacement < 0.0115);
  CHECK(e[1].traction < 0.094);
}

TEST_CASE("linear elements, hanging bar: gravity's surface integral carries the load, second order") {
  const Material m{1.0, 0.3, 1.0};
  const ElasticField field = hanging_bar_field(m, 1.0, 3.0);
  std::vector<RelativeErrors> e;
  for (int n : {2, 3}) {
    const TriangleMesh bar = box_mesh(Eigen::Vector3d(-0.5, -0.5, 0.0), Eigen::Vector3d(0.5, 0.5, 3.0), n, n, 3 * n);
    e.push_back(solve_linear_exact_trace_problem(
        bar, m, field, [&bar](Index k) { return bar.centroid(k).z() > 3.0 - 1e-9; }, Eigen::Vector3d(0, 0, -1)));
  }
  INFO("u " << e[0].displacement << " -> " << e[1].displacement << ", t " << e[0].traction << " -> " << e[1].traction);
  // Measured: u 7.7e-4 -> 3.4e-4 (order 2.03), t (held top face) 3.6e-3 -> 2.4e-3.
  CHECK(observed_order(e[0].displacement, e[1].displacement, 0.5, 1.0 / 3.0) > 1.5);
  CHECK(e[1].displacement < 4.5e-4);
  CHECK(e[1].traction < 3.1e-3);
}

TEST_CASE("linear elements: refining either half of the surface keeps the error at most 1.05 times the uniform parent's") {
  // Kelvin box, lower half held (docs/stability.md (i) for constant elements): red-green refinement of
  // the half x < 0 or x > 0. Measured linear u 2.37e-2 -> 1.51e-2 / 4.95e-3, t 4.69e-2 -> 3.46e-2 /
  // 2.60e-2; constant u 8.2e-2 -> 8.0e-2 / 3.4e-2.
  const TriangleMesh base = linear_box(1);
  const RelativeErrors parent = solve_linear_exact_trace_problem(base, kLinearMaterial, kKelvin, lower_half(base));
  for (const double side : {-1.0, 1.0}) {
    std::vector<Index> marked;
    for (Index e = 0; e < base.num_elements(); ++e)
      if (side * base.centroid(e).x() > 0.0) marked.push_back(e);
    const TriangleMesh m = refine_red_green(base, marked, 1).mesh;
    const RelativeErrors half = solve_linear_exact_trace_problem(m, kLinearMaterial, kKelvin, lower_half(m));
    INFO("half x " << (side < 0 ? "< 0" : "> 0") << ": u " << parent.displacement << " -> " << half.displacement << ", t "
                   << parent.traction << " -> " << half.traction);
    CHECK(half.displacement <= 1.05 * parent.displacement);
    CHECK(half.traction <= 1.05 * parent.traction);
  }
  // The box clamped on its top face under a field mirror-symmetric across x = 0 (study (i)'s problem,
  // tests/support/studies/grading_setup.hpp), half x < 0 refined. Measured: u 1.22e-2 -> 6.3e-3,
  // t 8.6e-2 -> 7.3e-2; constant elements: u 5.5e-2 -> 0.155 (2.8 times).
  namespace grading = bemsurg::bench::grading;
  const TriangleMesh clamped = grading::base_box(2), refined = grading::refined_box(2, grading::Zone::HalfMinus, 1);
  auto top = [](const TriangleMesh& m) { return [&m](Index e) { return grading::on_top(m, e); }; };
  const RelativeErrors p = solve_linear_exact_trace_problem(clamped, grading::kMaterial, grading::kelvin(), top(clamped));
  const RelativeErrors r = solve_linear_exact_trace_problem(refined, grading::kMaterial, grading::kelvin(), top(refined));
  INFO("clamped box: u " << p.displacement << " -> " << r.displacement << ", t " << p.traction << " -> " << r.traction);
  CHECK(r.displacement <= 1.05 * p.displacement);
  CHECK(r.traction <= 1.05 * p.traction);
}

TEST_CASE(
    "linear scenes: corner values interpolated to the nodes, their mean for constant elements, bad corner rows named, other commands refuse") {
  bemsurg_test::TempDir dir("bemsurg_test_linear_");
  const std::string head = R"({"mesh": {"generator": "box", "min": [0, 0, 0], "max": [1, 1, 1], "divisions": [1, 1, 1]},
    "material": {"young_modulus": 1, "poisson_ratio": 0.3},
    "boundary_conditions": {"rules": [{"select": {"all": true}, "displacement": [0, 0, 0]}], "file": "bc.csv"})";
  const std::string corner_header = "element,corner,kind_x,kind_y,kind_z,value_x,value_y,value_z\n";
  dir.write("bc.csv", corner_header + "3,0,u,t,u,1,0,0\n3,1,u,t,u,2,0,0\n3,2,u,t,u,6,0,0\n");
  const Scene linear = load_scene_from_string(head + R"(, "elements": "linear"})", dir.path.string(), "s.json");
  REQUIRE(linear.problem.elements == ElementType::Linear);
  // Node k = (2/3) corner k + (1/6) the others: 1 -> 2/3 + 8/6 = 2, 2 -> 4/3 + 7/6 = 2.5, 6 -> 4 + 0.5 = 4.5.
  CHECK(linear.problem.node_values(9, 0) == Approx(2.0));
  CHECK(linear.problem.node_values(10, 0) == Approx(2.5));
  CHECK(linear.problem.node_values(11, 0) == Approx(4.5));
  CHECK(linear.problem.boundary_conditions.kind(3 * 3 + 1) == BcKind::Traction);
  CHECK(linear.problem.node_values(0, 0) == 0.0);  // rules: their constant at every node
  const Scene constant = load_scene_from_string(head + "}", dir.path.string(), "s.json");
  CHECK(constant.problem.boundary_conditions.value(9) == Approx(3.0));  // the mean, the value at the centroid
  CHECK(constant.problem.node_values.size() == 0);
  require_constant_elements(constant, "bemsurg press");
  CHECK_THROWS_WITH(require_constant_elements(linear, "bemsurg press"),
                    Catch::Contains("s.json: elements: \"linear\" is not supported by bemsurg press"));
  auto error = [&](const std::string& csv) {
    dir.write("bc.csv", csv);
    try {
      load_scene_from_string(head + "}", dir.path.string(), "s.json");
    } catch (const SceneError& e) { return std::string(e.what()); }
    return std::string("no error");
  };
  CHECK_THAT(error(corner_header + "3,0,u,u,u,0,0,0\n3,2,u,u,u,0,0,0\n"),
             Catch::Contains("boundary_conditions.file line 3: element 3 lacks corner 1: the corner variant needs every listed element"));
  CHECK_THAT(error(corner_header + "3,0,u,u,u,0,0,0\n3,1,u,t,u,0,0,0\n3,2,u,u,u,0,0,0\n"),
             Catch::Contains("boundary_conditions.file line 3: element 3, kind_y: kind 'u' at corner 0 (line 2) but 't' at corner 1"));
  CHECK_THAT(error(corner_header + "3,3,u,u,u,0,0,0\n"),
             Catch::Contains("boundary_conditions.file line 2: corner: expected a corner 0, 1 or 2"));
  CHECK_THAT(error("element,corner,kind_x\n"),
             Catch::Contains("expected the header 'element,kind_x,kind_y,kind_z,value_x,value_y,value_z', "
                             "'element,corner,kind_x,kind_y,kind_z,value_x,value_y,value_z' or "
                             "'element,node,kind_x,kind_y,kind_z,value_x,value_y,value_z'"));
  // The node variant (issue 37): the values at the linear elements' collocation nodes as given, their
  // mean (the centroid's) for constant elements; its rows named by node.
  const std::string node_header = "element,node,kind_x,kind_y,kind_z,value_x,value_y,value_z\n";
  dir.write("bc.csv", node_header + "3,0,u,t,u,1,0,0\n3,1,u,t,u,2,0,0\n3,2,u,t,u,6,0,0\n");
  const Scene fed = load_scene_from_string(head + R"(, "elements": "linear"})", dir.path.string(), "s.json");
  CHECK(fed.problem.node_values(9, 0) == 1.0);
  CHECK(fed.problem.node_values(10, 0) == 2.0);
  CHECK(fed.problem.node_values(11, 0) == 6.0);
  CHECK(fed.problem.boundary_conditions.kind(3 * 3 + 1) == BcKind::Traction);
  CHECK(fed.problem.node_values(0, 0) == 0.0);
  CHECK(load_scene_from_string(head + "}", dir.path.string(), "s.json").problem.boundary_conditions.value(9) == Approx(3.0));
  CHECK_THAT(error(node_header + "3,0,u,u,u,0,0,0\n3,2,u,u,u,0,0,0\n"),
             Catch::Contains("boundary_conditions.file line 3: element 3 lacks node 1: the node variant needs every listed element at all "
                             "three nodes"));
  CHECK_THAT(error(node_header + "3,3,u,u,u,0,0,0\n"),
             Catch::Contains("boundary_conditions.file line 2: node: expected a node 0, 1 or 2 (the nodes of docs/elements.md)"));
  dir.write("bc.csv", corner_header);
  CHECK_THAT(
      [&] {
        try {
          load_scene_from_string(head + R"(, "elements": "quadratic"})", dir.path.string(), "s.json");
        } catch (const SceneError& e) { return std::string(e.what()); }
        return std::string("no error");
      }(),
      Catch::Contains("elements: expected \"constant\" or \"linear\", got \"quadratic\""));
}
