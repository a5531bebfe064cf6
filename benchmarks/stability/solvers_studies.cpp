// solvers_studies.cpp: studies (a) and (e) of issue 25 (docs/stability.md): Poisson's ratio towards
// 0.5 on closed-form problems, per solver; GMRES(m) restart length, BiCG and BiCGStab breakdowns
// against the size of the system and Poisson's ratio.
#include <algorithm>
#include <chrono>
#include <vector>

#include "solvers_setup.hpp"
#include "stability_study.hpp"

namespace bemsurg::bench::stability {
namespace {

namespace ss = bemsurg::stability_setup;

const SolverMethod kMethods[] = {SolverMethod::Lu, SolverMethod::Gmres, SolverMethod::BiCgStab, SolverMethod::BiCg};

/// One solve of a closed-form system by `method` with its defaults (block-Jacobi for the Krylov
/// methods): status, iterations, residual and the error against the closed form (NaN if refused).
struct MethodOutcome {
  std::string status;
  int iterations = 0;
  double residual = 0.0, error = 0.0;
};

MethodOutcome solve_with(const ss::ClosedFormSystem& s, SolverMethod method) {
  LinearSolverOptions o;
  o.method = method;
  LinearSolveResult r;
  MethodOutcome out;
  try {
    const Eigen::VectorXd x = solve_linear_system(s.A, s.b, o, r, &s.mesh);
    out.error = ss::closed_form_error(s, x);
  } catch (const SolverError&) { out.error = std::nan(""); }
  out.status = to_string(r.status);
  out.iterations = r.iterations;
  out.residual = r.relative_residual;
  return out;
}

}  // namespace

nlohmann::json study_poisson(const StudyContext& ctx) {
  const std::vector<double> nus = ctx.quick ? std::vector<double>{0.45, 0.49, 0.499, 0.4999, 0.49999}
                                            : std::vector<double>{0.3,    0.45,    0.47,    0.49,     0.495,    0.499,     0.4995,
                                                                  0.4999, 0.49995, 0.49999, 0.499995, 0.499999, 0.4999999, 0.49999999};
  const int level = ctx.quick ? 1 : 2;
  CsvTable csv(ctx.csv_dir / "stability_a_poisson.csv", {"problem", "poisson_ratio", "gap", "elements", "condition", "method", "status",
                                                         "iterations", "relative_residual", "error"});
  double threshold = std::nan("");  // smallest nu where the LU error passes 100 % (a held component)
  double mixed_worst = 0.0;         // largest error of the problem without one (kelvin_mixed)
  for (ss::PoissonCase c : {ss::PoissonCase::KelvinDirichlet, ss::PoissonCase::KelvinMixed, ss::PoissonCase::LameMixed}) {
    for (double nu : nus) {
      const ss::ClosedFormSystem s = ss::closed_form_system(c, nu, c == ss::PoissonCase::LameMixed ? 1 : level);
      const double cond = ss::condition_2norm(s.A);
      for (SolverMethod m : kMethods) {
        const MethodOutcome o = solve_with(s, m);
        if (m == SolverMethod::Lu && c == ss::PoissonCase::KelvinMixed) mixed_worst = std::max(mixed_worst, o.error);
        if (m == SolverMethod::Lu && c != ss::PoissonCase::KelvinMixed && o.error > 1.0 && !(threshold <= nu)) threshold = nu;
        csv.row({std::string(ss::to_string(c)), nu, 0.5 - nu, double(s.mesh.num_elements()), cond, std::string(to_string(m)), o.status,
                 double(o.iterations), o.residual, o.error});
      }
    }
  }
  return {{"parameter", "poisson_ratio"},
          {"threshold", threshold},
          {"threshold_text",
           "With a closed surface component whose displacement is prescribed everywhere (Kelvin Dirichlet box, Lamé sphere "
           "with its cavity displaced), cond(A*) grows as 1/(0.5 - nu) and the error against the closed form passes 100 % "
           "from nu = " +
               number_text(threshold) +
               " for every solver, each still reporting convergence; the mixed Kelvin "
               "problem stays below " +
               fixed_text(100.0 * mixed_worst, 1) + " % up to the last nu swept."},
          {"behaviour",
           "solve_elastostatic (include/bemsurg/impl/elastostatic_solver_impl.hpp) warns in ElastostaticResult::warnings from "
           "nu = " +
               number_text(kPoissonRatioWarning) +
               " (kPoissonRatioWarning) and refuses with InvalidMaterialError from nu = " + number_text(kPoissonRatioLimit) +
               " (kPoissonRatioLimit, bemsurg/material.hpp) when such a component exists; "
               "other problems are solved up to nu < 0.5 (Material::validate)."},
          {"warning_poisson_ratio", kPoissonRatioWarning},
          {"limit_poisson_ratio", kPoissonRatioLimit},
          {"csv", {"stability_a_poisson.csv"}}};
}

nlohmann::json study_krylov(const StudyContext&) { throw Error("study krylov: not written yet"); }
}  // namespace bemsurg::bench::stability
