// bench_accuracy: accuracy of the BEM core against closed-form solutions (docs/design.md §8), at several
// mesh levels, with the observed order and the time per phase. Writes the table that
// docs/accuracy.md quotes (--markdown PATH), a CSV (--csv PATH) and JSON (--json PATH).
//   bench_accuracy [--quick] [--json PATH] [--csv PATH] [--markdown PATH]
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "accuracy_elements.hpp"
#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/elastostatics/elastostatic_solver.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/post/interior_evaluator.hpp"
#include "bemsurg/verification/reference_solutions.hpp"
#include "bench_support.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;

namespace {

struct Row {
  std::string problem;
  std::string variant;
  Index elements = 0;
  double h = 0.0;  // mean element diameter
  double error_u = 0.0;
  double error_t = 0.0;
  double order_u = NAN;
  double order_t = NAN;
  double assembly_s = 0.0;
  double solve_s = 0.0;
  std::string note;
};

Row solve_case(const std::string& problem, const std::string& variant, const TriangleMesh& mesh, const Material& m,
               const ElasticField& field, const std::function<bool(Index)>& u_prescribed,
               const Eigen::Vector3d& gravity = Eigen::Vector3d::Zero(), BoundarySolution* solution = nullptr) {
  ElastostaticProblem p{mesh, m, gravity, exact_trace_conditions(mesh, field, u_prescribed), QuadratureOptions()};
  const ElastostaticSolution s = solve_elastostatic(p);
  if (solution) *solution = s.boundary;
  const RelativeErrors err = relative_l2_errors(p.mesh, p.boundary_conditions, s.boundary, exact_traces(p.mesh, field));
  Row r;
  r.problem = problem;
  r.variant = variant;
  r.elements = mesh.num_elements();
  r.h = mesh.diameters().mean();
  r.error_u = err.displacement;
  r.error_t = err.traction;
  r.assembly_s = s.report.assembly_seconds;
  r.solve_s = s.report.system_seconds + s.report.solver.setup_seconds + s.report.solver.solve_seconds;
  std::cerr << problem << " / " << variant << ": " << r.elements << " elements, u " << r.error_u << ", t " << r.error_t << ", assembly "
            << r.assembly_s << " s, solve " << r.solve_s << " s\n";
  return r;
}

// Traction error of a Dirichlet solve split into the first row of elements along the box's
// edges (where the exact traction is discontinuous across the edge) and all other elements.
std::pair<double, double> edge_split_traction_error(const TriangleMesh& mesh, const BoundarySolution& computed,
                                                    const BoundarySolution& exact, const Eigen::Vector3d& spacing) {
  const Eigen::Matrix<double, 3, 2> box = mesh.bounding_box();
  double d[2] = {0, 0}, n[2] = {0, 0};
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const Eigen::Vector3d c = mesh.centroid(e);
    int near = 0;
    for (int k = 0; k < 3; ++k) {
      const double gap = std::min(c(k) - box(k, 0), box(k, 1) - c(k));
      if (gap > 1e-12 && gap < spacing(k)) ++near;
    }
    const int bin = near > 0 ? 0 : 1;
    d[bin] += mesh.area(e) * (computed.traction.row(e) - exact.traction.row(e)).squaredNorm();
    n[bin] += mesh.area(e) * exact.traction.row(e).squaredNorm();
  }
  return {std::sqrt(d[0] / n[0]), std::sqrt(d[1] / n[1])};
}

void add_orders(std::vector<Row>& rows) {
  // Compare each row with the previous mesh level of the same problem and case.
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = i; j-- > 0;) {
      const Row& q = rows[j];
      Row& r = rows[i];
      if (r.problem != q.problem || r.variant != q.variant) continue;
      const double ratio = std::log(q.h / r.h);
      if (r.error_u > 0 && q.error_u > 0) r.order_u = std::log(q.error_u / r.error_u) / ratio;
      if (r.error_t > 0 && q.error_t > 0) r.order_t = std::log(q.error_t / r.error_t) / ratio;
      break;
    }
}

std::string fmt(double v, int prec = 3, bool percent = false) {
  if (std::isnan(v)) return "–";
  return fixed_text(percent ? 100.0 * v : v, prec);
}

// ---- the two element types (accuracy_elements.hpp, docs/elements.md) ------------------------------
struct ElementComparison {
  std::vector<bench::elements::Run> runs;
  std::vector<bench::elements::HalfRow> halves;
  bench::elements::EntryTiming entry;
  std::vector<bench::elements::GradedRow> graded;
};

ElementComparison compare_element_types(bool quick) {
  namespace el = bench::elements;
  ElementComparison out;
  for (const el::Problem& p : el::problems()) {
    const auto [constant_levels, linear_levels] = el::levels(p.name, quick);
    const bool dirichlet = p.name == "kelvin box (dirichlet)";
    for (const auto& [type, list] : {std::pair{ElementType::Constant, constant_levels}, std::pair{ElementType::Linear, linear_levels}})
      for (int level : list) {
        const TriangleMesh mesh = p.mesh(level);
        const Eigen::Vector3d spacing(2.0 / (3 * level), 1.2 / (2 * level), 1.2 / (2 * level));
        out.runs.push_back(el::solve(p, mesh, type, level, dirichlet ? el::first_row(mesh, spacing) : nullptr));
      }
  }
  for (const auto& [p, base] : el::half_problems(quick))
    for (ElementType type : {ElementType::Constant, ElementType::Linear}) out.halves.push_back(el::half_refinement(p, base, type));
  out.entry = el::assembly_per_entry(quick);
  if (!quick) out.graded = el::graded_comparison();
  return out;
}

std::string ratio_text(double a, double b) { return b > 0.0 ? fixed_text(a / b, 2) : "–"; }

void write_element_tables(std::ostream& md, const ElementComparison& c) {
  namespace el = bench::elements;
  md << "\nConstant and linear elements (docs/elements.md; errors at each type's collocation points, exact values prescribed there; "
        "memory = estimate_elastostatic_bytes, H and G; assembly per entry = assembly time / equations^2):\n\n"
        "| problem | elements type | level | elements | equations | error u (%) | order u | error t (%) | order t | edge-row t (%) | "
        "order edge-row t | assembly (s) | assembly per entry (ns) | solve (s) | memory (MB) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  const el::Run* previous = nullptr;
  for (const el::Run& r : c.runs) {
    const bool same = previous && previous->problem == r.problem && previous->type == r.type;
    auto order = [&](double coarse, double fine) {
      return same && coarse > 0 && fine > 0 ? fmt(std::log(coarse / fine) / std::log(previous->h / r.h), 2) : std::string("–");
    };
    md << "| " << r.problem << " | " << r.type << " | " << r.level << " | " << r.elements << " | " << r.equations << " | "
       << fmt(r.error_u, 3, true) << " | " << order(same ? previous->error_u : 0, r.error_u) << " | " << fmt(r.error_t, 3, true) << " | "
       << order(same ? previous->error_t : 0, r.error_t) << " | " << (r.edge_t > 0 ? fmt(r.edge_t, 2, true) : "–") << " | "
       << order(same ? previous->edge_t : 0, r.edge_t) << " | " << fmt(r.assembly_s, 3) << " | "
       << fmt(1e9 * r.assembly_s / (double(r.equations) * double(r.equations)), 2) << " | " << fmt(r.solve_s, 3) << " | "
       << fmt(r.memory_bytes / 1e6, 1) << " |\n";
    previous = &r;
  }
  md << "\nLinear elements at level k against constant elements at level k + 1 (four times the elements, 4/3 the unknowns): "
        "error ratios (target: at most 0.5):\n\n| problem | linear elements | constant elements | ratio u | ratio t |\n|---|---|---|---|---|\n";
  for (const el::Run& l : c.runs) {
    if (l.type != "linear") continue;
    for (const el::Run& k : c.runs)
      if (k.type == "constant" && k.problem == l.problem && k.elements == 4 * l.elements)
        md << "| " << l.problem << " | " << l.elements << " | " << k.elements << " | " << ratio_text(l.error_u, k.error_u) << " | "
           << ratio_text(l.error_t, k.error_t) << " |\n";
  }
  md << "\nAssembly time per matrix entry (H and G, median of three, all threads) at nearly equal matrix size on the Kelvin box: "
        "linear "
     << c.entry.linear_equations << " equations " << fmt(c.entry.linear_ns, 2) << " ns, constant " << c.entry.constant_equations
     << " equations " << fmt(c.entry.constant_ns, 2) << " ns: ratio " << ratio_text(c.entry.linear_ns, c.entry.constant_ns)
     << " (target: at most 3).\n";
  if (!c.graded.empty()) {
    md << "\nThe Kelvin box (mixed) graded towards the point force (spacing halved near it, growth 1.5) against the uniform box "
          "it refines: error ratios graded / uniform:\n\n| elements type | uniform elements | graded elements | uniform u / t (%) | "
          "graded u / t (%) | ratio u | ratio t |\n|---|---|---|---|---|---|---|\n";
    for (const el::GradedRow& g : c.graded)
      md << "| " << g.type << " | " << g.uniform_elements << " | " << g.graded_elements << " | " << fmt(g.uniform_u, 3, true) << " / "
         << fmt(g.uniform_t, 3, true) << " | " << fmt(g.graded_u, 3, true) << " / " << fmt(g.graded_t, 3, true) << " | "
         << ratio_text(g.graded_u, g.uniform_u) << " | " << ratio_text(g.graded_t, g.uniform_t) << " |\n";
  }
  md << "\nRefining either half (x < 0, x > 0) of the surface red-green once, against the uniform parent: error ratios "
        "(target for linear elements: at most 1.05):\n\n| problem | elements type | parent u / t (%) | half x<0: u, t | half x>0: u, t |\n"
        "|---|---|---|---|---|\n";
  for (const el::HalfRow& h : c.halves)
    md << "| " << h.problem << " | " << h.type << " | " << fmt(h.parent_u, 3, true) << " / " << fmt(h.parent_t, 3, true) << " | "
       << ratio_text(h.minus_u, h.parent_u) << ", " << ratio_text(h.minus_t, h.parent_t) << " | " << ratio_text(h.plus_u, h.parent_u)
       << ", " << ratio_text(h.plus_t, h.parent_t) << " |\n";
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path, csv_path, md_path;
  cli::OptionParser parser = bench::command_line(
      "bench_accuracy", "Errors of the BEM solution against closed forms (docs/accuracy.md is generated from it).\n", quick, json_path);
  parser.value("--csv", "PATH", csv_path, "write one row per solve to PATH as CSV");
  parser.value("--markdown", "PATH", md_path, "write the tables to PATH as Markdown");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  const Material m{1.0, 0.3, 1.0};
  std::vector<Row> rows;
  std::vector<std::pair<Index, double>> rigid;

  // Rigid body: rows of H sum to zero (blocks), so the residual measures quadrature alone.
  for (int s : quick ? std::vector<int>{2} : std::vector<int>{2, 3}) {
    const TriangleMesh sphere = icosphere_mesh(Eigen::Vector3d::Zero(), 1.0, s);
    rigid.emplace_back(sphere.num_elements(), rigid_body_row_sum_ratio(InfluenceAssembler(sphere, m).assemble()));
  }
  for (int n : quick ? std::vector<int>{4} : std::vector<int>{4, 8}) {
    const TriangleMesh box = box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), n * 3 / 2, n, n);
    rigid.emplace_back(box.num_elements(), rigid_body_row_sum_ratio(InfluenceAssembler(box, m).assemble()));
  }

  // Kelvin point force outside a 2 x 1.2 x 1.2 box.
  const Eigen::Vector3d x0(0.3, 0.2, 1.4), f(0.4, -0.3, 1.0);
  const ElasticField kelvin = kelvin_field(m, x0, f);
  struct EdgeRow {
    Index elements;
    double edge, rest;
  };
  struct InteriorRow {
    std::string problem;
    Index elements;
    double u, stress;
  };
  std::vector<EdgeRow> edge_rows;
  std::vector<InteriorRow> interior_rows;
  RowMatrixX3d kelvin_points(4, 3), lame_points(3, 3);
  kelvin_points << 0.0, 0.0, 0.0, 0.5, -0.2, 0.1, -0.4, 0.3, -0.2, 0.2, 0.1, 0.3;
  lame_points << 1.5, 0.0, 0.0, 0.0, -1.2, 0.9, 0.8, 0.8, 0.8;
  for (int n : quick ? std::vector<int>{1} : std::vector<int>{1, 2, 3, 4, 6}) {
    const TriangleMesh box = box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 3 * n, 2 * n, 2 * n);
    BoundarySolution dirichlet, mixed;
    rows.push_back(solve_case(
        "kelvin", "dirichlet", box, m, kelvin, [](Index) { return true; }, Eigen::Vector3d::Zero(), &dirichlet));
    rows.push_back(solve_case("kelvin", "neumann", box, m, kelvin, a_few_elements(box)));
    rows.back().error_t = NAN;  // only four pinned elements carry an unknown traction: no field to compare
    rows.push_back(solve_case(
        "kelvin", "mixed", box, m, kelvin, [&](Index e) { return box.centroid(e).z() < 0.0; }, Eigen::Vector3d::Zero(), &mixed));
    const auto [edge, rest] =
        edge_split_traction_error(box, dirichlet, exact_traces(box, kelvin), Eigen::Vector3d(2.0 / (3 * n), 1.2 / (2 * n), 1.2 / (2 * n)));
    edge_rows.push_back({box.num_elements(), edge, rest});
    const InteriorErrors ie = interior_relative_errors(box, m, kelvin, mixed, kelvin_points);
    interior_rows.push_back({"kelvin (mixed)", box.num_elements(), ie.displacement, ie.stress});
  }

  // Lamé hollow sphere a = 1, b = 2, pressures inside and outside.
  const double a = 1.0, b = 2.0, pa = 1.0, pb = 0.0;
  const ElasticField lame = lame_field(m, Eigen::Vector3d::Zero(), a, b, pa, pb);
  for (int s : quick ? std::vector<int>{1} : std::vector<int>{1, 2, 3}) {
    const TriangleMesh shell = hollow_sphere_mesh(Eigen::Vector3d::Zero(), a, b, s, s);
    const double mid = 0.5 * (a + b);
    BoundarySolution sol;
    rows.push_back(solve_case(
        "lame", "inner u, outer t", shell, m, lame, [&](Index e) { return shell.centroid(e).norm() < mid; }, Eigen::Vector3d::Zero(),
        &sol));
    const InteriorErrors ie = interior_relative_errors(shell, m, lame, sol, lame_points);
    interior_rows.push_back({"lame (inner u, outer t)", shell.num_elements(), ie.displacement, ie.stress});
    rows.push_back(solve_case("lame", "pressures", shell, m, lame, a_few_elements(shell)));
    rows.back().error_t = NAN;  // only four pinned elements carry an unknown traction: no field to compare
  }

  // Uniform pressure on a cube.
  const ElasticField pressure = uniform_pressure_field(m, 1.0);
  for (int n : quick ? std::vector<int>{2} : std::vector<int>{2, 4, 6, 9}) {
    const TriangleMesh cube = box_mesh(Eigen::Vector3d(-0.5, -0.5, -0.5), Eigen::Vector3d(0.5, 0.5, 0.5), n, n, n);
    rows.push_back(solve_case("pressure", "cube", cube, m, pressure, a_few_elements(cube)));
    rows.back().error_t = NAN;  // only four pinned elements carry an unknown traction: no field to compare
  }

  // Bar hanging under its own weight: 1 x 1 x 3, held at z = 3.
  const double g = 1.0, L = 3.0;
  const ElasticField bar = hanging_bar_field(m, g, L);
  for (int n : quick ? std::vector<int>{2} : std::vector<int>{2, 4, 6}) {
    const TriangleMesh mesh = box_mesh(Eigen::Vector3d(-0.5, -0.5, 0.0), Eigen::Vector3d(0.5, 0.5, L), n, n, 3 * n);
    auto top = [&](Index e) { return mesh.centroid(e).z() > L - 1e-9; };
    rows.push_back(solve_case("hanging bar", "with gravity", mesh, m, bar, top, Eigen::Vector3d(0, 0, -g)));
    rows.push_back(solve_case("hanging bar", "gravity dropped", mesh, m, bar, top));
  }
  add_orders(rows);
  const ElementComparison elements = compare_element_types(quick);

  // ---- report --------------------------------------------------------------------------------
  std::ostringstream md;
  use_classic_locale(md);  // element counts without grouping, whatever the global locale
  md << "| problem | case | elements | mean h | error u (%) | order u | error t (%) | order t | assembly (s) | solve (s) |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows)
    md << "| " << r.problem << " | " << r.variant << " | " << r.elements << " | " << fmt(r.h, 4) << " | " << fmt(r.error_u, 2, true)
       << " | " << fmt(r.order_u, 2) << " | " << fmt(r.error_t, 2, true) << " | " << fmt(r.order_t, 2) << " | " << fmt(r.assembly_s, 3)
       << " | " << fmt(r.solve_s, 3) << " |\n";
  md << "\nRigid-body identity, max over block rows of |sum_e H_ie| / |H_ii|:\n\n| elements | ratio |\n|---|---|\n";
  for (const auto& [E, ratio] : rigid) { md << "| " << E << " | " << scientific_text(ratio, 2) << " |\n"; }
  md << "\nTraction error of the Kelvin Dirichlet solve, split into the first row of elements along the box's "
        "edges and the rest:\n\n| elements | first row at edges (%) | elsewhere (%) |\n|---|---|---|\n";
  for (const EdgeRow& r : edge_rows) md << "| " << r.elements << " | " << fmt(r.edge, 2, true) << " | " << fmt(r.rest, 2, true) << " |\n";
  md << "\nInterior points (relative L2 over the points of displacement and of the six stress components):\n\n"
        "| problem | elements | error u (%) | error stress (%) |\n|---|---|---|---|\n";
  for (const InteriorRow& r : interior_rows)
    md << "| " << r.problem << " | " << r.elements << " | " << fmt(r.u, 2, true) << " | " << fmt(r.stress, 2, true) << " |\n";
  write_element_tables(md, elements);
  std::cout << md.str();
  if (!md_path.empty()) std::ofstream(md_path) << md.str();
  if (!csv_path.empty()) {
    std::ofstream csv(csv_path);
    use_classic_locale(csv);
    csv << "problem,case,elements,mean_h,error_u,order_u,error_t,order_t,assembly_s,solve_s\n";
    for (const Row& r : rows)
      csv << r.problem << "," << r.variant << "," << r.elements << "," << r.h << "," << r.error_u << "," << r.order_u << "," << r.error_t
          << "," << r.order_t << "," << r.assembly_s << "," << r.solve_s << "\n";
  }
  if (!json_path.empty()) {
    nlohmann::json j;
    j["benchmark"] = "bench_accuracy";
    j["quick"] = quick;
    for (const Row& r : rows)
      j["rows"].push_back({{"problem", r.problem},
                           {"case", r.variant},
                           {"elements", r.elements},
                           {"mean_h", r.h},
                           {"error_u", r.error_u},
                           {"error_t", r.error_t},
                           {"order_u", std::isnan(r.order_u) ? nlohmann::json() : nlohmann::json(r.order_u)},
                           {"order_t", std::isnan(r.order_t) ? nlohmann::json() : nlohmann::json(r.order_t)},
                           {"assembly_s", r.assembly_s},
                           {"solve_s", r.solve_s}});
    for (const EdgeRow& r : edge_rows)
      j["kelvin_edge_split"].push_back({{"elements", r.elements}, {"error_t_edge_row", r.edge}, {"error_t_elsewhere", r.rest}});
    for (const InteriorRow& r : interior_rows)
      j["interior"].push_back({{"problem", r.problem}, {"elements", r.elements}, {"error_u", r.u}, {"error_stress", r.stress}});
    for (const auto& [E, ratio] : rigid) j["rigid_body"].push_back({{"elements", E}, {"row_sum_ratio", ratio}});
    for (const bench::elements::Run& r : elements.runs)
      j["element_types"].push_back({{"problem", r.problem},
                                    {"element_type", r.type},
                                    {"level", r.level},
                                    {"elements", r.elements},
                                    {"equations", r.equations},
                                    {"mean_h", r.h},
                                    {"error_u", r.error_u},
                                    {"error_t", r.error_t},
                                    {"error_t_edge_row", r.edge_t},
                                    {"assembly_s", r.assembly_s},
                                    {"solve_s", r.solve_s},
                                    {"memory_bytes", r.memory_bytes}});
    j["assembly_per_entry"] = {{"linear_equations", elements.entry.linear_equations},
                               {"linear_ns", elements.entry.linear_ns},
                               {"constant_equations", elements.entry.constant_equations},
                               {"constant_ns", elements.entry.constant_ns}};
    for (const bench::elements::GradedRow& g : elements.graded)
      j["graded"].push_back({{"element_type", g.type},
                             {"uniform_elements", g.uniform_elements},
                             {"graded_elements", g.graded_elements},
                             {"uniform", {g.uniform_u, g.uniform_t}},
                             {"graded", {g.graded_u, g.graded_t}}});
    for (const bench::elements::HalfRow& h : elements.halves)
      j["half_refinement"].push_back({{"problem", h.problem},
                                      {"element_type", h.type},
                                      {"parent", {h.parent_u, h.parent_t}},
                                      {"half_minus", {h.minus_u, h.minus_t}},
                                      {"half_plus", {h.plus_u, h.plus_t}}});
    if (!bench::write_json_file(json_path, j, "bench_accuracy")) return 1;  // say so: the doc is generated from it
  }
  return 0;
}
