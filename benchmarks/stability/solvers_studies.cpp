// solvers_studies.cpp: studies (a) and (e) of issue 25 (docs/stability.md): Poisson's ratio towards
// 0.5 on closed-form problems, per solver; GMRES(m) restart length, BiCG and BiCGStab breakdowns
// against the size of the system and Poisson's ratio.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iterator>
#include <string>
#include <vector>

#include "stability_study.hpp"
#include "support/studies/solvers_setup.hpp"

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
  // Per held problem and method: the first nu from which the error stays above 100 % (NaN: never).
  std::vector<std::string> held_text;
  for (ss::PoissonCase c : {ss::PoissonCase::KelvinDirichlet, ss::PoissonCase::KelvinMixed, ss::PoissonCase::LameMixed}) {
    std::vector<double> first_over(std::size(kMethods), std::nan(""));
    for (double nu : nus) {
      const ss::ClosedFormSystem s = ss::closed_form_system(c, nu, c == ss::PoissonCase::LameMixed ? 1 : level);
      const double cond = ss::condition_2norm(s.A);
      for (std::size_t k = 0; k < std::size(kMethods); ++k) {
        const SolverMethod m = kMethods[k];
        const MethodOutcome o = solve_with(s, m);
        if (m == SolverMethod::Lu && c == ss::PoissonCase::KelvinMixed) mixed_worst = std::max(mixed_worst, o.error);
        if (m == SolverMethod::Lu && c != ss::PoissonCase::KelvinMixed && o.error > 1.0 && !(threshold <= nu)) threshold = nu;
        if (o.error > 1.0 && std::isnan(first_over[k])) first_over[k] = nu;
        if (o.error <= 1.0) first_over[k] = std::nan("");  // back under 100 %: not past it for good (NaN: not measured)
        csv.row({std::string(ss::to_string(c)), nu, 0.5 - nu, double(s.mesh.num_elements()), cond, std::string(to_string(m)), o.status,
                 double(o.iterations), o.residual, o.error});
      }
    }
    if (c == ss::PoissonCase::KelvinMixed) continue;
    const std::string name =
        c == ss::PoissonCase::KelvinDirichlet ? "the Kelvin box held everywhere" : "Lamé's sphere with its cavity held";
    const bool alike = std::all_of(first_over.begin(), first_over.end(),
                                   [&](double v) { return (std::isnan(v) && std::isnan(first_over[0])) || v == first_over[0]; });
    const auto from = [](double v) { return std::isnan(v) ? std::string("never") : "from nu = " + number_text(v); };
    std::string t = name + " " + from(first_over[0]);
    if (alike) {
      t += " for every solver";
    } else {
      t += " with LU";
      for (std::size_t k = 1; k < std::size(kMethods); ++k)
        t += ", " + from(first_over[k]) + " with " + std::string(to_string(kMethods[k]));
    }
    held_text.push_back(t);
  }
  return {{"parameter", "poisson_ratio"},
          {"threshold", threshold},
          {"threshold_text",
           "With a closed surface component whose displacement is prescribed everywhere (Kelvin Dirichlet box, Lamé sphere "
           "with its cavity displaced), cond(A*) grows as 1/(0.5 - nu) and the error against the closed form passes 100 %, "
           "each solver still reporting convergence: " +
               (held_text.empty() ? std::string() : held_text[0]) + (held_text.size() > 1 ? "; " + held_text[1] : std::string()) +
               " (the first of these, nu = " + number_text(threshold) +
               ", is the threshold drawn). The mixed Kelvin "
               "problem stays below " +
               fixed_text(100.0 * mixed_worst, 1) + " % up to the last nu swept."},
          {"behaviour",
           "check_before_solve (include/bemsurg/elastostatics/impl/elastostatic_problem_impl.hpp), run by solve_elastostatic and "
           "GreensTable::compute, warns (ElastostaticResult::warnings, GreensTable::warnings) from "
           "nu = " +
               number_text(kPoissonRatioWarning) +
               " (kPoissonRatioWarning) and refuses with InvalidMaterialError from nu = " + number_text(kPoissonRatioLimit) +
               " (kPoissonRatioLimit, bemsurg/material.hpp) when such a component exists; "
               "other problems are solved up to nu < 0.5 (Material::validate)."},
          {"warning_poisson_ratio", kPoissonRatioWarning},
          {"limit_poisson_ratio", kPoissonRatioLimit},
          {"csv", {"stability_a_poisson.csv"}}};
}

namespace {
/// One Krylov solve of `s` with `o`: the row of stability_e_krylov.csv after the system's columns.
LinearSolveResult krylov_run(const ss::ClosedFormSystem& s, const LinearSolverOptions& o) {
  LinearSolveResult r;
  try {
    solve_linear_system(s.A, s.b, o, r, &s.mesh);
  } catch (const SolverError&) {  // r holds the status, iterations and residual it stopped at
  }
  return r;
}
}  // namespace

nlohmann::json study_krylov(const StudyContext& ctx) {
  const std::vector<int> levels = ctx.quick ? std::vector<int>{1} : std::vector<int>{1, 2};
  const std::vector<double> nus = ctx.quick ? std::vector<double>{0.3, 0.4999} : std::vector<double>{0.3, 0.45, 0.49, 0.499, 0.4999};
  const std::vector<int> restarts = ctx.quick ? std::vector<int>{2, 10, 0} : std::vector<int>{1, 2, 5, 10, 20, 40, 0};
  CsvTable csv(ctx.csv_dir / "stability_e_krylov.csv", {"n", "poisson_ratio", "preconditioner", "method", "restart", "status", "breakdown",
                                                        "iterations", "restarts", "relative_residual"});
  int smallest_ok = 0;  // smallest GMRES(m) that converges on every system with block-Jacobi
  std::vector<int> failed_restarts;
  int failures = 0, krylov_runs = 0, bi_failures = 0, bi_breakdowns = 0;
  Eigen::Index largest_n = 0;
  for (int level : levels)
    for (double nu : nus) {
      const ss::ClosedFormSystem s = ss::closed_form_system(ss::PoissonCase::KelvinDirichlet, nu, level);
      largest_n = std::max(largest_n, s.A.rows());
      for (PreconditionerKind pk : {PreconditionerKind::BlockJacobi, PreconditionerKind::None}) {
        LinearSolverOptions o;
        o.preconditioner = pk;
        auto write = [&](const LinearSolveResult& r, int m) {
          ++krylov_runs;
          failures += r.status == KrylovStatus::Converged ? 0 : 1;
          if (r.method != SolverMethod::Gmres) {
            bi_failures += r.status == KrylovStatus::Converged ? 0 : 1;
            bi_breakdowns += r.status == KrylovStatus::Breakdown ? 1 : 0;
          }
          csv.row({double(s.A.rows()), nu, std::string(to_string(pk)), std::string(to_string(r.method)), double(m),
                   std::string(to_string(r.status)), "\"" + r.breakdown + "\"", double(r.iterations), double(r.restarts),
                   r.relative_residual});
        };
        for (int m : restarts) {
          o.method = SolverMethod::Gmres;
          o.restart = m;
          const LinearSolveResult r = krylov_run(s, o);
          write(r, m);
          if (pk == PreconditionerKind::BlockJacobi && r.status != KrylovStatus::Converged && m > 0) failed_restarts.push_back(m);
        }
        for (SolverMethod method : {SolverMethod::BiCgStab, SolverMethod::BiCg}) {
          o.method = method;
          o.restart = 0;
          write(krylov_run(s, o), 0);
        }
      }
    }
  for (int m : failed_restarts) smallest_ok = std::max(smallest_ok, m);
  int threshold = 0;  // the next restart length swept past the largest that failed
  for (int m : restarts)
    if (m > smallest_ok && (threshold == 0 || m < threshold)) threshold = m;
  return {{"parameter", "gmres_restart"},
          {"threshold", threshold},
          {"threshold_text",
           "With block-Jacobi, GMRES(m) converges on every system swept (n up to " + std::to_string(largest_n) + ", nu up to " +
               number_text(nus.back()) + ") from m = " + std::to_string(threshold) +
               (failed_restarts.empty() ? std::string(" (no restart length failed)")
                                        : "; shorter restarts stagnate or hit the iteration limit") +
               "; " + std::to_string(failures) + " of " + std::to_string(krylov_runs) +
               " Krylov solves (with and without block-Jacobi) did not converge, each reported with its status; BiCGStab and BiCG "
               "failed " +
               std::to_string(bi_failures) + " times (" + std::to_string(bi_breakdowns) + " breakdowns) on these systems."},
          {"behaviour",
           "solve_linear_system (include/bemsurg/solvers/impl/linear_solve_impl.hpp) never returns an unconverged or broken-down "
           "Krylov solve: it throws SolverError naming the method, preconditioner, tolerance, status (iteration_limit, "
           "stagnation, breakdown with the vanished quantity), iterations and true residual, with LinearSolveResult filled; "
           "solve_elastostatic, CutSystemUpdate and the CLI (exit 1) pass it on."},
          {"failures", failures},
          {"runs", krylov_runs},
          {"csv", {"stability_e_krylov.csv"}}};
}
}  // namespace bemsurg::bench::stability
