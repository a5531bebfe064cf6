// accuracy_elements.hpp: bench_accuracy's comparison of the two element types (docs/elements.md):
// constant and linear discontinuous elements on the same closed-form problems (exact values at
// each type's collocation points, errors there), with time and memory; linear level k against
// constant level k + 1 (four times the elements); the traction in the first row of elements
// along the box's sharp edges; refinement of either half of the surface against the uniform parent.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "bemsurg/assembly/node_influence_assembler.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/red_green_refinement.hpp"
#include "bemsurg/verification/reference_solutions.hpp"
#include "support/studies/grading_setup.hpp"

namespace bemsurg::bench::elements {

/// One solve of one problem with one element type.
struct Run {
  std::string problem, type;
  int level = 0;
  Index elements = 0, equations = 0;
  double h = 0.0, error_u = 0.0, error_t = 0.0, edge_t = 0.0, assembly_s = 0.0, solve_s = 0.0, memory_bytes = 0.0;
};

/// A problem: its mesh at a level, the field, where u is prescribed (by element), gravity.
struct Problem {
  std::string name;
  std::function<TriangleMesh(int)> mesh;
  verification::ElasticField field;
  std::function<bool(const TriangleMesh&, Index)> held;
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  Material material{1.0, 0.3, 1.0};
};

/// The first row of elements along a box's edges: centroid within one cell of a face other than its own.
inline std::function<bool(Index)> first_row(const TriangleMesh& mesh, const Eigen::Vector3d& spacing) {
  const Eigen::Matrix<double, 3, 2> box = mesh.bounding_box();
  return [&mesh, box, spacing](Index e) {
    const Eigen::Vector3d c = mesh.centroid(e);
    for (int k = 0; k < 3; ++k) {
      const double gap = std::min(c(k) - box(k, 0), box(k, 1) - c(k));
      if (gap > 1e-12 && gap < spacing(k)) return true;
    }
    return false;
  };
}

/// Solves `p` on `mesh` with element type `type`; errors at the collocation points of that type,
/// over all elements and over `edge` (when given, traction only).
inline Run solve(const Problem& p, const TriangleMesh& mesh, ElementType type, int level,
                 const std::function<bool(Index)>& edge = nullptr) {
  using namespace verification;
  const auto held = [&](Index e) { return p.held(mesh, e); };
  ElastostaticProblem problem{mesh, p.material, p.gravity, exact_trace_conditions(mesh, p.field, held), QuadratureOptions()};
  problem.elements = type;
  const bool linear = type == ElementType::Linear;
  const BoundarySolution exact = linear ? exact_node_traces(mesh, p.field) : exact_traces(mesh, p.field);
  if (linear) {
    problem.node_values.resize(3 * mesh.num_elements(), 3);
    for (Index r = 0; r < exact.displacement.rows(); ++r)
      for (int c = 0; c < 3; ++c)
        problem.node_values(r, c) =
            problem.boundary_conditions.kind(3 * (r / 3) + c) == BcKind::Displacement ? exact.displacement(r, c) : exact.traction(r, c);
  }
  const ElastostaticSolution s = solve_elastostatic(problem);
  const auto all = [](Index) { return true; };
  auto errors = [&](const std::function<bool(Index)>& include) {
    return linear ? node_relative_l2_errors(mesh, problem.boundary_conditions, s.nodes, exact, include)
                  : relative_l2_errors(mesh, problem.boundary_conditions, s.boundary, exact, include);
  };
  const RelativeErrors e = errors(all);
  Run r{p.name, to_string(type), level, mesh.num_elements(), s.report.equations, mesh.diameters().mean(), e.displacement, e.traction};
  if (edge) r.edge_t = errors(edge).traction;
  r.assembly_s = s.report.assembly_seconds;
  r.solve_s = s.report.system_seconds + s.report.solver.setup_seconds + s.report.solver.solve_seconds;
  r.memory_bytes = estimate_elastostatic_bytes(mesh.num_elements(), type);
  std::cerr << p.name << " / " << r.type << " level " << level << ": " << r.elements << " elements, u " << r.error_u << ", t " << r.error_t
            << ", assembly " << r.assembly_s << " s\n";
  return r;
}

/// The problems and their levels (constant: levels 1..n; linear: the first ones).
inline std::vector<Problem> problems() {
  const Material m{1.0, 0.3, 1.0};
  std::vector<Problem> out;
  out.push_back({"kelvin box (mixed)",
                 [](int n) { return box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 3 * n, 2 * n, 2 * n); },
                 verification::kelvin_field(m, Eigen::Vector3d(0.3, 0.2, 1.4), Eigen::Vector3d(0.4, -0.3, 1.0)),
                 [](const TriangleMesh& mesh, Index e) { return mesh.centroid(e).z() < 0.0; }});
  out.push_back({"kelvin box (dirichlet)", out[0].mesh, out[0].field, [](const TriangleMesh&, Index) { return true; }});
  out.push_back({"lame (inner u, outer t)", [](int s) { return hollow_sphere_mesh(Eigen::Vector3d::Zero(), 1.0, 2.0, s, s); },
                 verification::lame_field(m, Eigen::Vector3d::Zero(), 1.0, 2.0, 1.0, 0.0),
                 [](const TriangleMesh& mesh, Index e) { return mesh.centroid(e).norm() < 1.5; }});
  out.push_back({"hanging bar",
                 [](int n) { return box_mesh(Eigen::Vector3d(-0.5, -0.5, 0.0), Eigen::Vector3d(0.5, 0.5, 3.0), 2 * n, 2 * n, 6 * n); },
                 verification::hanging_bar_field(m, 1.0, 3.0),
                 [](const TriangleMesh& mesh, Index e) { return mesh.centroid(e).z() > 3.0 - 1e-9; }, Eigen::Vector3d(0, 0, -1)});
  return out;
}

/// Levels per problem: {constant levels, linear levels}; linear level k is compared with constant k + 1.
inline std::pair<std::vector<int>, std::vector<int>> levels(const std::string& problem, bool quick) {
  if (quick) return {{1}, {1}};
  if (problem.rfind("kelvin", 0) == 0) return {{1, 2, 3, 4, 6}, {1, 2, 3}};  // box(2n) has 4x the elements of box(n)
  if (problem.rfind("lame", 0) == 0) return {{1, 2, 3}, {1, 2}};
  return {{1, 2, 4}, {1, 2}};
}

/// The half-refinement study: the parent mesh and its two halves refined red-green once.
struct HalfRow {
  std::string problem, type;
  double parent_u = 0, parent_t = 0, minus_u = 0, minus_t = 0, plus_u = 0, plus_t = 0;
};

inline HalfRow half_refinement(const Problem& p, const TriangleMesh& base, ElementType type) {
  HalfRow h{p.name, to_string(type)};
  const Run parent = solve(p, base, type, 0);
  h.parent_u = parent.error_u;
  h.parent_t = parent.error_t;
  for (const double side : {-1.0, 1.0}) {
    std::vector<Index> marked;
    for (Index e = 0; e < base.num_elements(); ++e)
      if (side * base.centroid(e).x() > 0.0) marked.push_back(e);
    const TriangleMesh refined = refine_red_green(base, marked, 1).mesh;
    const Run r = solve(p, refined, type, 1);
    (side < 0 ? h.minus_u : h.plus_u) = r.error_u;
    (side < 0 ? h.minus_t : h.plus_t) = r.error_t;
  }
  return h;
}

/// The problems of the half-refinement study: the Kelvin box (mixed), the hanging bar and study
/// (i)'s box clamped on its top face under a mirror-symmetric Kelvin field (grading_setup.hpp).
inline std::vector<std::pair<Problem, TriangleMesh>> half_problems(bool quick) {
  const std::vector<Problem> p = problems();
  std::vector<std::pair<Problem, TriangleMesh>> out;
  out.emplace_back(p[0], p[0].mesh(1));
  if (quick) return out;
  out.emplace_back(p[3], p[3].mesh(1));
  namespace g = bemsurg::bench::grading;
  Problem clamped{"clamped box (study (i))", [](int n) { return g::base_box(n); }, g::kelvin(),
                  [](const TriangleMesh& mesh, Index e) { return g::on_top(mesh, e); }};
  clamped.material = g::kMaterial;
  out.emplace_back(clamped, g::base_box(2));
  return out;
}

/// The Kelvin box (mixed) graded towards the point force (graded_coordinates: spacing h/2 near the
/// source's projection, growing by at most 1.5 to the uniform box's h) against the uniform box: a
/// refined region should lower the error.
struct GradedRow {
  std::string type;
  Index uniform_elements = 0, graded_elements = 0;
  double uniform_u = 0, uniform_t = 0, graded_u = 0, graded_t = 0;
};

inline std::vector<GradedRow> graded_comparison() {
  const Problem kelvin = problems()[0];
  const TriangleMesh uniform = kelvin.mesh(2);  // cells 1/3 x 0.3 x 0.3
  const TriangleMesh graded =
      box_mesh_from_grid(graded_coordinates(-1.0, 1.0, 0.3, 1.0 / 6.0, 1.0 / 3.0, 1.5), graded_coordinates(-0.6, 0.6, 0.2, 0.15, 0.3, 1.5),
                         graded_coordinates(-0.6, 0.6, 0.6, 0.15, 0.3, 1.5));
  std::vector<GradedRow> out;
  for (ElementType type : {ElementType::Constant, ElementType::Linear}) {
    const Run u = solve(kelvin, uniform, type, 2), g = solve(kelvin, graded, type, 2);
    out.push_back({to_string(type), u.elements, g.elements, u.error_u, u.error_t, g.error_u, g.error_t});
  }
  return out;
}

/// Assembly time per matrix entry of the two types at (nearly) equal matrix size on the same box:
/// linear elements on box(n) against constant elements on a grid with three times the elements;
/// median of three assemblies of H and G each (OpenMP, all threads).
struct EntryTiming {
  Index linear_equations = 0, constant_equations = 0;
  double linear_ns = 0.0, constant_ns = 0.0;  // per entry of H and G (n^2 entries each)
};

inline EntryTiming assembly_per_entry(bool quick) {
  const Material m{1.0, 0.3, 1.0};
  const Eigen::Vector3d lo(-1, -0.6, -0.6), hi(1, 0.6, 0.6);
  // 4 (nx ny + ny nz + nz nx) elements: (6, 4, 4) = 256 linear (2,304 equations) against
  // (9, 8, 7) = 764 constant (2,292); quick: (3, 2, 2) = 64 (576) against (5, 4, 3) = 188 (564).
  const TriangleMesh lin = quick ? box_mesh(lo, hi, 3, 2, 2) : box_mesh(lo, hi, 6, 4, 4);
  const TriangleMesh con = quick ? box_mesh(lo, hi, 5, 4, 3) : box_mesh(lo, hi, 9, 8, 7);
  auto median_seconds = [](const std::function<void()>& f) {
    std::vector<double> t;
    for (int k = 0; k < 3; ++k) {
      const auto start = std::chrono::steady_clock::now();
      f();
      t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    std::sort(t.begin(), t.end());
    return t[1];
  };
  EntryTiming out;
  out.linear_equations = 9 * lin.num_elements();
  out.constant_equations = 3 * con.num_elements();
  const double tl = median_seconds([&] { (void)LinearInfluenceAssembler(lin, m).assemble(); });
  const double tc = median_seconds([&] { (void)InfluenceAssembler(con, m).assemble(); });
  out.linear_ns = 1e9 * tl / (double(out.linear_equations) * double(out.linear_equations));
  out.constant_ns = 1e9 * tc / (double(out.constant_equations) * double(out.constant_equations));
  return out;
}

}  // namespace bemsurg::bench::elements
