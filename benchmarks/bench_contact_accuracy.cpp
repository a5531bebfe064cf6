// bench_contact_accuracy: accuracy against cost of the two contact closed forms (docs/contact.md
// §"Closed-form checks"): a rigid flat punch (Boussinesq) and a rigid sphere (Hertz), both
// frictionless (ToolContactSolver, ToolSpec::flat / ToolSpec::sphere), pressed into the top face
// of a block [-L, L]^2 x [-L, 0] with its bottom held, E = 1, nu = 0.3, contact radius a = 1.
// Closed forms (half-space, E* = E / (1 - nu^2)): tests/support/studies/contact_accuracy_closed_forms.hpp.
//
// Errors (constant elements: one traction and one displacement per element, at its centroid):
//   Z, the contact zone: the top elements that the closed-form contact disc r < a overlaps (a
//     positive closed-form pressure integral), together with the elements the tool holds.
//   error_t = sqrt(sum_Z A_e (p_e - pbar_e)^2 / sum_Z A_e pbar_e^2): relative, area-weighted L2 of
//     the normal pressure p_e = -t_e . e_z (zero on an element the tool does not hold) against
//     pbar_e, the closed-form pressure AVERAGED over element e. The punch's pressure
//     F / (2 pi a sqrt(a^2 - r^2)) is not square integrable, its element averages are finite:
//     pbar_e comes from polar coordinates about the axis, exact in r (the pressure's radial
//     antiderivative in closed form) and Gauss-Legendre in the angle between the corners' and the
//     disc edge's crossings. Self-check: sum_Z A_e pbar_e = F of the closed form to 1e-8, else the
//     run's status is "reference_quadrature_failed".
//   error_u = the same relative, area-weighted L2 of the vertical surface displacement -u_z at the
//     centroids of the top elements outside Z within 3 a of the axis, against the closed form at
//     each centroid (punch: (2 d / pi) asin(a / r); Hertz: [(2 a^2 - r^2) asin(a / r)
//     + a sqrt(r^2 - a^2)] / (pi R), checked continuous at r = a and Boussinesq's point load far away).
//   force_ratio = F / F of the closed form (punch 2 a E* d, Hertz (4/3) E* sqrt(R) d^1.5).
// Floors: the block truncates the half-space (the held bottom at depth L stiffens it; pressed to a
// prescribed depth, the far surface sags less). The displacement outside the contact feels it most:
// loaded with the exact Hertz pressure (no contact set: the body's own error), the block's outer
// displacement falls short by about 2.8 a / L (2.6 % at L / a = 100, 1.4 % at 200, 0.9 % at 400,
// 0.7 % at 800, h = a / 2). Pressed to a prescribed depth, the truncation shows mostly as extra
// force, and its leftover outer deficit cancels the discretisation's force excess (+1 to +2 %,
// shrinking with h): at L / a = 100 the sphere's error_u sat at 1.29, 1.11, 1.11, 1.48 % over the
// four levels, a plateau that hid both (issue 37). At L / a = 800, which the levels use, it falls
// 1.45, 1.32, 0.83, 0.36 % (F / F_Hertz 1.019 -> 1.010); the graded top face and coarse far faces
// keep that cheap. Hertz against Sneddon's exact sphere at d / R = 0.0025: 0.03 % in the force and
// the field, so Hertz stays the reference. error_t (of order 10-40 %, dominated by the pressure's
// edge) is not limited by the truncation.
// The mesh study's block (L / a = 6) has a floor near 10 % in the force and 30 % in error_u: there
// uniform and graded share it (their errors within 3 % of each other), and the comparison is of cost.
// Not monotone: the punch holds the elements whose centroid lies under the disc, a staircase whose
// area jumps with h (F / F_closed 0.971, 0.979, 1.012, 1.014 at h = a/2 .. a/6, L / a = 100), so
// error_t and the force step rather than fall smoothly; the sphere's contact set is as granular
// (its farthest held centroid at 0.90, 0.90, 0.98, 0.99 a): that makes the levels non-monotone,
// not the plateau above.
//
// Studies (each --list line runs one configuration; the report runs them one process each):
//   levels  graded top face, contact-zone spacing h = a/2, a/3, a/4, a/6, L / a = 800, LU.
//   mesh    graded against uniform top face at the same h (a/2, a/3), L / a = 6.
// quadrature and solver are fixed here ("baseline", "lu"; tolerance 0): bench_work_precision
// studies them.
//
// usage: bench_contact_accuracy --list [--quick]
//        bench_contact_accuracy --problem punch|sphere --study levels|mesh --level L --mesh graded|uniform
//                               [--quadrature baseline --solver lu --tolerance 0] --json PATH
//        bench_contact_accuracy --quick --json PATH   (the smoke run: the coarsest level of each problem)
#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "support/studies/contact_accuracy_setup.hpp"

using namespace bemsurg;
namespace ca = bemsurg::bench::contact_accuracy;

namespace {

std::string list_line(const ca::Config& c) {
  return "--problem " + ca::problem_name(c.problem) + " --study " + c.study + " --level " + std::to_string(c.level) +
         " --quadrature baseline --solver lu --tolerance 0 --mesh " + c.mesh;
}

bool finite_errors(const nlohmann::json& run) {
  for (const char* key : {"error_u", "error_t"})
    if (!run[key].is_number() || !std::isfinite(run[key].get<double>())) return false;
  return run["status"] == "ok";
}

void print_run(const nlohmann::json& r) {
  auto num = [&](const char* key, int digits) { return r[key].is_number() ? general_text(r[key].get<double>(), digits) : "-"; };
  std::cerr << r["problem"].get<std::string>() << " " << r["study"].get<std::string>() << " level " << r["level"].get<int>() << " "
            << r["mesh"].get<std::string>() << ": " << r["elements"].get<long>() << " elements, mean_h " << num("mean_h", 3) << ", error_t "
            << num("error_t", 4) << ", error_u " << num("error_u", 4) << ", F/F_closed " << num("force_ratio", 5) << ", total "
            << num("total_s", 3) << " s, status " << r["status"].get<std::string>() << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, list = false;
  std::string json_path, problem, study = "levels", mesh = "graded", quadrature = "baseline", solver = "lu";
  int level = 0;
  double tolerance = 0.0;
  cli::OptionParser parser =
      bench::command_line("bench_contact_accuracy",
                          "Accuracy against cost of the flat punch and Hertz sphere closed forms (docs/contact.md).\n", quick, json_path);
  parser.flag("--list", list, "print the configurations, one command line a line, and exit");
  parser.value("--problem", "punch|sphere", problem, "run one configuration of this problem");
  parser.value("--study", "levels|mesh", study, "the study the configuration belongs to");
  parser.value("--level", "L", level, "refinement level (h = a/2, a/3, a/4, a/6)").between(0, 3);
  parser.value("--mesh", "graded|uniform", mesh, "the top face's mesh");
  parser.value("--quadrature", "baseline", quadrature, "fixed here: baseline");
  parser.value("--solver", "lu", solver, "fixed here: lu");
  parser.value("--tolerance", "T", tolerance, "fixed here: 0 (a direct solve)");
  const auto check = [&] {
    if (!problem.empty() && problem != "punch" && problem != "sphere")
      throw cli::UsageError("bench_contact_accuracy: --problem: punch or sphere");
    if (study != "levels" && study != "mesh") throw cli::UsageError("bench_contact_accuracy: --study: levels or mesh");
    if (mesh != "graded" && mesh != "uniform") throw cli::UsageError("bench_contact_accuracy: --mesh: graded or uniform");
    if (quadrature != "baseline" || solver != "lu")
      throw cli::UsageError("bench_contact_accuracy: only --quadrature baseline --solver lu are measured here");
    if (study == "levels" && mesh != "graded") throw cli::UsageError("bench_contact_accuracy: the levels study uses the graded mesh");
    if (study == "mesh" && level > 1) throw cli::UsageError("bench_contact_accuracy: the mesh study has levels 0 and 1");
  };
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv, check)) return *status;

  if (list) {
    for (const ca::Config& c : ca::configurations(quick)) std::cout << list_line(c) << "\n";
    return 0;
  }
  if (!problem.empty()) {
    const ca::Config c{problem == "punch" ? ca::Problem::Punch : ca::Problem::Sphere, study, level, mesh};
    const nlohmann::json r = ca::run_configuration(c, tolerance);
    print_run(r);
    if (!bench::write_json_file(json_path, r, "bench_contact_accuracy")) return 1;
    return r["status"] == "ok" ? 0 : 1;
  }
  // The smoke run: the coarsest level of each problem.
  nlohmann::json out = {{"benchmark", "bench_contact_accuracy"}, {"quick", quick}, {"runs", nlohmann::json::array()}};
  bool ok = true;
  for (ca::Problem p : {ca::Problem::Punch, ca::Problem::Sphere}) {
    const nlohmann::json r = ca::run_configuration({p, "levels", 0, "graded"}, tolerance);
    print_run(r);
    ok = ok && finite_errors(r);
    out["runs"].push_back(r);
  }
  if (!bench::write_json_file(json_path, out, "bench_contact_accuracy")) return 1;
  return ok ? 0 : 1;
}
