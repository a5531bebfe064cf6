// geometry_studies.cpp: stability studies (b) interior points approaching the surface and (c)
// sliver triangles (issue 25, docs/stability.md).
#include <Eigen/SVD>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/post/interior_evaluator.hpp"
#include "bemsurg/verification/reference_solutions.hpp"
#include "stability_study.hpp"
#include "support/studies/geometry_setup.hpp"

namespace bemsurg::bench::stability {

namespace {
using verification::ElasticField;

/// The Kelvin problem of tests/test_bem_interior.cpp: a point force above a 2 x 1.2 x 1.2 box,
/// the exact displacement held on the lower half, the exact traction elsewhere.
struct KelvinBox {
  Material m{1.0, 0.3, 0.0};
  ElasticField field = verification::kelvin_field(m, Eigen::Vector3d(0.3, 0.2, 1.4), Eigen::Vector3d(0.4, -0.3, 1.0));
  static bool held(const TriangleMesh& mesh, Index e) { return mesh.centroid(e).z() < 0.0; }
};

/// Relative errors of u and of the six stress components at one point against the field.
std::pair<double, double> point_errors(const ElasticField& f, const Eigen::Vector3d& x, const RowMatrixX3d& u, const StressRows& s) {
  const Eigen::Matrix3d S = f.stress(x);
  Eigen::Matrix<double, 1, 6> exact;
  exact << S(0, 0), S(1, 1), S(2, 2), S(0, 1), S(1, 2), S(0, 2);
  return {(u.row(0).transpose() - f.displacement(x)).norm() / f.displacement(x).norm(), (s.row(0) - exact).norm() / exact.norm()};
}

/// The three targets on the top face z = 0.6 that a point approaches along -z: the centroid of the
/// top element nearest the face's centre, the midpoint of its longest edge (shared with its
/// neighbour in the same cell) and its corner nearest the centre (shared by six elements).
struct Targets {
  Index element = -1;
  double h = 0.0;
  std::vector<std::pair<const char*, Eigen::Vector3d>> at;
};
Targets top_targets(const TriangleMesh& mesh) {
  Targets t;
  double best = 1e300;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    const Eigen::Vector3d c = mesh.centroid(e);
    if (c.z() > 0.6 - 1e-9 && c.head<2>().norm() < best) best = c.head<2>().norm(), t.element = e;
  }
  const auto c = mesh.corners(t.element);
  t.h = element_diameter(c[0], c[1], c[2]);
  int longest = 0, nearest = 0;
  for (int k = 0; k < 3; ++k) {
    if ((c[(k + 1) % 3] - c[k]).norm() > (c[(longest + 1) % 3] - c[longest]).norm()) longest = k;
    if (c[k].head<2>().norm() < c[nearest].head<2>().norm()) nearest = k;
  }
  t.at = {{"face", mesh.centroid(t.element)}, {"edge", 0.5 * (c[longest] + c[(longest + 1) % 3])}, {"vertex", c[nearest]}};
  return t;
}
/// The stress error that counts as wrong near the surface (20 %: the interior stress of a converged
/// mesh here is within a few per cent at d ~ h; interior_clearance.hpp).
constexpr double kStressTolerance = 0.2;

/// The largest d/h at which `error` (keyed by d/h) reaches `level`, interpolated log-log with the
/// next larger d/h; 0 if it never does.
double first_crossing(const std::map<double, double>& error, double level) {
  for (auto it = error.rbegin(); it != error.rend(); ++it) {
    if (it->second < level) continue;
    if (it == error.rbegin()) return it->first;
    const auto above = std::prev(it);
    const double t = std::log(level / it->second) / std::log(above->second / it->second);
    return std::exp(std::log(it->first) + t * std::log(above->first / it->first));
  }
  return 0.0;
}

/// The smallest x of (x, y) pairs (ascending in x) at which y reaches `level`, interpolated log-log
/// with the previous pair; 0 if it never does.
double first_reaching(const std::vector<std::pair<double, double>>& xy, double level) {
  for (std::size_t i = 0; i < xy.size(); ++i) {
    if (xy[i].second < level) continue;
    if (i == 0) return xy[i].first;
    const auto [x0, y0] = xy[i - 1];
    const auto [x1, y1] = xy[i];
    const double t = std::log(level / std::max(y0, 1e-300)) / std::log(y1 / std::max(y0, 1e-300));
    return std::exp(std::log(x0) + t * std::log(x1 / x0));
  }
  return 0.0;
}
}  // namespace

// long: one sweep, three boundary data sets, two quadratures, three targets, written row by row
nlohmann::json study_interior(const StudyContext& ctx) {
  const KelvinBox kb;
  const int n = ctx.quick ? 1 : 2;
  const TriangleMesh box = box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 3 * n, 2 * n, 2 * n);
  const Index E = box.num_elements();
  BoundarySolution solved;
  verification::solve_exact_trace_problem(
      box, kb.m, kb.field, [&](Index e) { return KelvinBox::held(box, e); }, Eigen::Vector3d::Zero(), &solved);
  const BoundarySolution traces = verification::exact_traces(box, kb.field);
  const Eigen::Vector3d c(1.0, 2.0, 3.0);
  BoundarySolution rigid{RowMatrixX3d(E, 3), RowMatrixX3d::Zero(E, 3)};
  for (Index e = 0; e < E; ++e) rigid.displacement.row(e) = c.transpose();

  QuadratureOptions deep;
  deep.max_depth = 20;
  InteriorEvaluator def(box, kb.m), ref(box, kb.m, Eigen::Vector3d::Zero(), deep);
  def.allow_points_too_close_for_studies(true);
  ref.allow_points_too_close_for_studies(true);
  const double limit_u = min_clearance_fraction(QuadratureOptions());
  const Targets t = top_targets(box);
  const int per_decade = ctx.quick ? 2 : 4;
  CsvTable csv(ctx.csv_dir / "stability_interior.csv", {"distance_over_h", "target", "quadrature", "data", "refused_displacement",
                                                        "refused_stress", "displacement_error", "stress_error"});
  // What the thresholds are read from: per target, the sweep's worst figures.
  std::map<double, double> bem_stress;    // d/h -> worst stress error of the BEM solution, max_depth 20
  std::map<double, double> rigid_stress;  // d/h -> worst stress error of the rigid motion, default rule
  double worst_u_allowed = 0.0;           // worst u error of the BEM solution where the default rule allows u
  for (const auto& [name, x0] : t.at) {
    for (int k = 0; k <= 4 * per_decade; ++k) {
      const double ratio = std::pow(10.0, -static_cast<double>(k) / per_decade);
      RowMatrixX3d p(1, 3);
      p.row(0) = (x0 - Eigen::Vector3d(0, 0, ratio * t.h)).transpose();
      for (const InteriorEvaluator* ev : std::array<const InteriorEvaluator*, 2>{&def, &ref}) {
        const char* q = ev == &def ? "default" : "max_depth_20";
        const QuadratureOptions& qo = ev == &def ? QuadratureOptions() : deep;
        const bool refused_u = find_point_too_close(box, p, qo).point >= 0;
        const bool refused_s = find_point_too_close(box, p, qo, ClearanceQuantity::Stress).point >= 0;
        for (const BoundarySolution* data : std::array<const BoundarySolution*, 3>{&solved, &traces, &rigid}) {
          if (ctx.quick && data == &traces) continue;  // the full sweep only: it follows the BEM solution's curve
          const RowMatrixX3d u = ev->displacement(p, *data);
          const StressRows s = ev->stress(p, *data);
          double eu, es;
          if (data == &rigid) {
            eu = (u.row(0).transpose() - c).norm() / c.norm();
            es = s.row(0).norm() / (kb.m.young_modulus * c.norm());
          } else {
            std::tie(eu, es) = point_errors(kb.field, p.row(0).transpose(), u, s);
          }
          const char* d = data == &solved ? "bem" : data == &traces ? "exact_traces" : "rigid";
          csv.row({ratio, std::string(name), std::string(q), std::string(d), refused_u ? 1.0 : 0.0, refused_s ? 1.0 : 0.0, eu, es});
          if (data == &solved && ev == &ref) bem_stress[ratio] = std::max(bem_stress[ratio], es);
          if (data == &rigid && ev == &def) rigid_stress[ratio] = std::max(rigid_stress[ratio], es);
          if (data == &solved && ev == &def && !refused_u) worst_u_allowed = std::max(worst_u_allowed, eu);
        }
      }
    }
  }
  const double stress_at = first_crossing(bem_stress, kStressTolerance), quad_at = first_crossing(rigid_stress, 1e-4);
  nlohmann::json j;
  j["parameter"] = "distance / longest edge h of the nearest element, 1 ... 1e-4 (towards an element's centroid, an edge and a vertex)";
  j["threshold"] = stress_at;
  j["stress_threshold"] = stress_at;
  j["stress_limit"] = min_stress_clearance_fraction(QuadratureOptions());
  j["quadrature_breakdown"] = quad_at;
  j["displacement_limit"] = limit_u;
  j["worst_displacement_error_allowed"] = worst_u_allowed;
  j["threshold_text"] = "The stress of the BEM solution exceeds " + general_text(100 * kStressTolerance, 3) +
                        " % error below d = " + general_text(stress_at, 2) +
                        " h (it grows like h / d next to element edges and vertices, with any quadrature); "
                        "the default quadrature itself breaks (rigid-motion stress above 1e-4 E|c|) below d = " +
                        general_text(quad_at, 2) + " h, while the displacement error stays below " +
                        general_text(100 * worst_u_allowed, 2) + " % down to the displacement limit " + general_text(limit_u, 3) + " h.";
  j["behaviour"] =
      "InteriorEvaluator::stress refuses points closer than kMinStressClearanceFraction = " + general_text(kMinStressClearanceFraction, 3) +
      " x h, and displacement (and the scene loader) points closer than " + "min_clearance_fraction = " + general_text(limit_u, 3) +
      " x h, with InvalidArgumentError naming the point, the "
      "element, the distance and the limit (include/bemsurg/post/interior_clearance.hpp).";
  j["csv"] = {"stability_interior.csv"};
  j["elements"] = E;
  j["h"] = t.h;
  return j;
}

// long: one sweep over two families of slivers, each solved with two quadratures
nlohmann::json study_sliver(const StudyContext& ctx) {
  const KelvinBox kb;
  const int n = ctx.quick ? 1 : 2;  // 80-96 elements, or 320-352
  std::vector<double> eps_list;
  const int per_decade = ctx.quick ? 1 : 2;
  for (int k = 0; k <= 4 * per_decade; ++k) eps_list.push_back(0.25 / n * std::pow(10.0, -static_cast<double>(k) / per_decade));
  const QuadratureOptions standard;
  QuadratureOptions deep;
  deep.max_depth = 20;
  CsvTable csv(ctx.csv_dir / "stability_sliver.csv", {"family", "eps", "aspect_ratio", "min_angle_degrees", "elements", "quadrature",
                                                      "condition", "displacement_error", "traction_error", "sliver_displacement_error",
                                                      "sliver_traction_error", "interior_displacement_error", "interior_stress_error"});
  RowMatrixX3d points(4, 3);
  points << 0.0, 0.0, 0.0, 0.5, -0.2, 0.1, -0.4, 0.3, -0.2, 0.2, 0.1, 0.3;
  std::vector<std::pair<double, double>> needle_traction;  // (aspect ratio, traction error), default rule
  std::vector<std::pair<double, double>> quadrature_gap;   // (aspect ratio, |default - max_depth 20| / max_depth 20)
  std::vector<std::pair<double, double>> cap_traction;     // (aspect ratio, traction error), default rule
  for (const char* family : {"needle", "cap"}) {
    for (double eps : eps_list) {
      const TriangleMesh mesh = std::string(family) == "needle" ? needle_box(n, eps) : cap_box(n, eps);
      const WorstAspectRatio worst = worst_aspect_ratio(mesh);
      const MeshQuality q = measure_mesh_quality(mesh);
      for (const QuadratureOptions* qo : std::array<const QuadratureOptions*, 2>{&standard, &deep}) {
        if (ctx.quick && qo == &deep && std::string(family) == "cap") continue;  // --quick: the needles' comparison only
        const auto held = [&](Index e) { return mesh.centroid(e).z() < 0.0; };
        const BoundaryConditions bc = verification::exact_trace_conditions(mesh, kb.field, held);
        InfluenceMatrices hg = InfluenceAssembler(mesh, kb.m, *qo).assemble();
        const Eigen::VectorXd rhs = build_right_hand_side(hg, bc);
        const Eigen::MatrixXd A = build_system_matrix(hg, bc);
        const Eigen::VectorXd sv = Eigen::BDCSVD<Eigen::MatrixXd>(A).singularValues();
        const BoundarySolution s = recover_boundary_solution(bc, A.partialPivLu().solve(rhs));
        const BoundarySolution exact = verification::exact_traces(mesh, kb.field);
        const auto all = verification::relative_l2_errors(mesh, bc, s, exact);
        const auto slivers = verification::relative_l2_errors(mesh, bc, s, exact, [&](Index e) {
          const auto c = mesh.corners(e);
          return aspect_ratio(c[0], c[1], c[2]) > 0.5 * worst.ratio;
        });
        const auto interior = verification::interior_relative_errors(mesh, kb.m, kb.field, s, points);
        const bool needle = std::string(family) == "needle";
        if (needle && qo == &standard) needle_traction.emplace_back(worst.ratio, all.traction);
        if (needle && qo == &deep)
          quadrature_gap.emplace_back(worst.ratio, std::abs(needle_traction.back().second - all.traction) / all.traction);
        if (!needle && qo == &standard) cap_traction.emplace_back(worst.ratio, all.traction);
        csv.row({std::string(family), eps, worst.ratio, q.min_angle_degrees, static_cast<double>(mesh.num_elements()),
                 std::string(qo == &deep ? "max_depth_20" : "default"), sv(0) / sv(sv.size() - 1), all.displacement, all.traction,
                 slivers.displacement, slivers.traction, interior.displacement, interior.stress});
      }
    }
  }
  const double doubled = first_reaching(needle_traction, 2.0 * needle_traction.front().second);
  const double cap_doubled = first_reaching(cap_traction, 2.0 * cap_traction.front().second);
  const double quad = first_reaching(quadrature_gap, 0.1);
  nlohmann::json j;
  j["parameter"] = "largest element aspect ratio (longest edge / shortest altitude, 1 for equilateral), 2 ... 2e4";
  j["threshold"] = doubled;
  j["quadrature_threshold"] = quad;
  j["cap_threshold"] = cap_doubled;
  j["warning_aspect_ratio"] = kSliverWarningAspectRatio;
  j["refusal_aspect_ratio"] = kMaxAspectRatio;
  j["threshold_text"] = "With a band of needles the box's traction error doubles (from " +
                        general_text(100 * needle_traction.front().second, 2) + " %) at aspect ratio " + general_text(doubled, 2) +
                        " and grows in proportion beyond, as does the condition number "
                        "of A*; the default quadrature departs from max_depth 20 by 10 % at " +
                        general_text(quad, 2) + " (the loss is the collocation's, not the quadrature's); flat caps double it at " +
                        general_text(cap_doubled, 2) +
                        ". The traction solved on the slivers themselves is off by about 0.07 x their aspect ratio; displacement "
                        "and interior fields stay within a few per cent throughout.";
  j["behaviour"] = "sliver_warning (mesh_quality.hpp) names the worst element above kSliverWarningAspectRatio = " +
                   general_text(kSliverWarningAspectRatio, 3) +
                   " for the scene's and the solve's warnings; validate_mesh reports "
                   "an element above kMaxAspectRatio = " +
                   general_text(kMaxAspectRatio, 3) +
                   " as degenerate, so "
                   "require_valid_mesh refuses it with InvalidMeshError naming the element and its ratio.";
  j["csv"] = {"stability_sliver.csv"};
  return j;
}

}  // namespace bemsurg::bench::stability
