// work_precision_setup.hpp: the configurations bench_work_precision runs (issue 24, item 2: accuracy
// against cost) and how each problem is built from its closed form (verification/reference_solutions.hpp,
// set up as benchmarks/bench_accuracy.cpp does).
//
// The studies are one factor at a time around one baseline: default QuadratureOptions, LU,
// uniform mesh. `levels` refines the mesh at the baseline; `quadrature` and `solver` change one
// setting at two mid levels of `lame` and `bar`, so each of their points has a baseline point of
// the same mesh in the `levels` series.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>
#include <vector>

#include "bemsurg/material.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"
#include "bemsurg/solvers/linear_solve.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

namespace bemsurg::work_precision {

/// One configuration: what a line of --list gives and one process runs.
struct Config {
  std::string problem;  // lame, kelvin, bar
  std::string study = "levels";
  int level = 1;
  std::string quadrature = "baseline";  // cheap, baseline, fine
  std::string solver = "lu";            // lu, gmres, bicgstab, hmatrix
  double tolerance = 0.0;               // Krylov relative residual, or hmatrix's compression tolerance; 0 for LU
  std::string mesh = "uniform";
  std::string element_type = "constant";  // constant, linear (docs/elements.md)
  // Where linear elements are given the prescribed data (issue 37): "nodes", the exact field at
  // their collocation nodes (bc.csv's node form), or "corners", the exact field at the triangle's
  // corners interpolated to the nodes (bc.csv's corner form: what a user with vertex data gives).
  std::string feed = "nodes";
};

/// The command-line arguments that run `c` (one line of --list).
inline std::string arguments(const Config& c) {
  return "--problem " + c.problem + " --study " + c.study + " --level " + std::to_string(c.level) + " --quadrature " + c.quadrature +
         " --solver " + c.solver + " --tolerance " + number_text(c.tolerance) + " --mesh " + c.mesh + " --element_type " + c.element_type +
         (c.element_type == "linear" ? " --feed " + c.feed : std::string());
}

/// The named quadrature settings of the `quadrature` study; throws InvalidArgumentError for an
/// unknown name (and validate() for a setting out of range, so a typo here fails at once).
inline QuadratureOptions quadrature_setting(const std::string& name) {
  QuadratureOptions q;  // "baseline": the defaults every bemsurg solve uses
  if (name == "cheap") {
    q.far_ratio = 2.0;
    q.mid_ratio = 1.0;
    q.mid_order = 3;
    q.polar_order = 4;
  } else if (name == "fine") {
    q.far_ratio = 8.0;
    q.mid_ratio = 3.0;
    q.mid_order = 8;
    q.polar_order = 16;
  } else if (name != "baseline") {
    throw InvalidArgumentError("unknown quadrature setting '" + name + "' (expected cheap, baseline or fine)");
  }
  q.validate();
  return q;
}

/// The mesh levels of each problem: full mode spans over a decade of cost, the largest solving in
/// tens of seconds (about 5,000 to 8,000 equations); quick mode takes the first two.
inline int level_count(const std::string& problem) { return problem == "kelvin" || problem == "lame" ? 3 : 6; }
/// The two mid levels where the quadrature and solver studies change one factor (Lamé: its last two).
inline std::vector<int> mid_levels(const std::string& problem, bool quick) {
  return quick ? std::vector<int>{1} : problem == "lame" ? std::vector<int>{2, 3} : std::vector<int>{3, 4};
}
/// The levels of the hierarchical front (study "hmatrix"): the dense levels and one more, past what
/// the dense levels reach (Lamé 10,240, Kelvin 5,120, the bar 5,488 elements).
inline int hmatrix_level_count(const std::string& problem) { return level_count(problem) + 1; }
/// The levels solved with linear elements too (9 unknowns per element: up to about 6,000 equations).
inline int linear_level_count(const std::string& problem) { return problem == "bar" ? 3 : 2; }

/// A problem ready to solve: the mesh, the closed form, where u is prescribed, and gravity.
struct Setup {
  TriangleMesh mesh;
  verification::ElasticField field;
  std::function<bool(const Eigen::Vector3d&)> displacement_prescribed_at;  // of an element's centroid
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
};

inline Setup lame_setup(const Material& m, int level) {
  // Lamé's hollow sphere a = 1, b = 2, inner pressure 1, outer surface free; the inner
  // displacement is prescribed, the outer traction (zero): u solved outside, t inside. The levels
  // are nested: both shells subdivided s = level times (160, 640, 2,560 elements), each level's
  // mesh the previous one's triangles split in four, so an observed order is a refinement's (levels
  // that alternated (s, s) and (s, s + 1) once made the traction error rise between two).
  const int s_in = level, s_out = level;
  const double a = 1.0, b = 2.0;
  Setup s;
  s.mesh = hollow_sphere_mesh(Eigen::Vector3d::Zero(), a, b, s_in, s_out);
  s.field = verification::lame_field(m, Eigen::Vector3d::Zero(), a, b, 1.0, 0.0);
  s.displacement_prescribed_at = [mid = 0.5 * (a + b)](const Eigen::Vector3d& x) { return x.norm() < mid; };
  return s;
}

inline Setup kelvin_setup(const Material& m, int level) {
  // Kelvin's point force outside the unit sphere (icosphere, 80 * 4^(level - 1) elements), at a
  // distance of 0.64 from it; displacement prescribed on the lower half, traction on the upper half
  // (which faces the force), so both a traction and a displacement error are measured.
  Setup s;
  s.mesh = icosphere_mesh(Eigen::Vector3d::Zero(), 1.0, level);
  s.field = verification::kelvin_field(m, Eigen::Vector3d(0.3, 0.2, 1.6), Eigen::Vector3d(0.4, -0.3, 1.0));
  s.displacement_prescribed_at = [](const Eigen::Vector3d& x) { return x.z() < 0.0; };
  return s;
}

inline Setup bar_setup(const Material& m, int level) {
  // A 1 x 1 x 3 bar hanging under gravity g = 1, held at its top face z = 3 (displacement
  // prescribed there, traction-free elsewhere), as bench_accuracy: n x n x 3n cells, 28 n^2 elements.
  static const int cells[] = {2, 3, 4, 6, 8, 10, 14};  // the last: the hierarchical front's level only
  const int n = cells[level - 1];
  const double L = 3.0;
  Setup s;
  s.mesh = box_mesh(Eigen::Vector3d(-0.5, -0.5, 0.0), Eigen::Vector3d(0.5, 0.5, L), n, n, 3 * n);
  s.field = verification::hanging_bar_field(m, 1.0, L);
  s.displacement_prescribed_at = [L](const Eigen::Vector3d& x) { return x.z() > L - 1e-9; };
  s.gravity = Eigen::Vector3d(0, 0, -1.0);
  return s;
}

/// Builds the configuration's problem; throws InvalidArgumentError for an unknown problem, level
/// or mesh kind.
inline Setup make_setup(const Config& c, const Material& m) {
  if (c.mesh != "uniform") throw InvalidArgumentError("--mesh " + c.mesh + ": this benchmark has uniform meshes only");
  if (c.problem != "lame" && c.problem != "kelvin" && c.problem != "bar")
    throw InvalidArgumentError("unknown problem '" + c.problem + "' (expected lame, kelvin or bar)");
  const int levels = c.solver == "hmatrix" ? hmatrix_level_count(c.problem) : level_count(c.problem);
  if (c.level < 1 || c.level > levels)
    throw InvalidArgumentError("--level " + std::to_string(c.level) + ": " + c.problem + " has levels 1 to " + std::to_string(levels) +
                               (c.solver == "hmatrix" ? "" : " (one more with --solver hmatrix)"));
  if (c.problem == "lame") return lame_setup(m, c.level);
  if (c.problem == "kelvin") return kelvin_setup(m, c.level);
  return bar_setup(m, c.level);
}

/// Every configuration of the full (or quick) benchmark, in running order.
inline std::vector<Config> all_configs(bool quick) {
  std::vector<Config> out;
  for (const char* p : {"lame", "kelvin", "bar"})
    for (int l = 1; l <= (quick ? 2 : level_count(p)); ++l) {
      Config c;
      c.problem = p;
      c.level = l;
      out.push_back(c);
    }
  for (const char* p : {"lame", "kelvin", "bar"})  // the second front: linear elements (study "elements")
    for (int l = 1; l <= (quick ? 1 : linear_level_count(p)); ++l) {
      Config c;
      c.problem = p;
      c.level = l;
      c.study = "elements";
      c.element_type = "linear";
      for (const char* feed : {"nodes", "corners"}) {
        c.feed = feed;
        out.push_back(c);
      }
    }
  for (const char* p : {"lame", "kelvin", "bar"})  // the hierarchical front (study "hmatrix"), beyond dense's levels
    for (int l = quick ? 1 : 2; l <= (quick ? 1 : hmatrix_level_count(p)); ++l) {
      if (quick && std::string(p) != "lame") continue;  // CI: one small solve runs the path
      Config c;
      c.problem = p;
      c.level = l;
      c.study = "hmatrix";
      c.solver = "hmatrix";
      c.tolerance = 1e-5;
      out.push_back(c);
    }
  const std::vector<double> tolerances = quick ? std::vector<double>{1e-2, 1e-6} : std::vector<double>{1e-2, 1e-4, 1e-6, 1e-8};
  for (const char* p : {"lame", "bar"})
    for (int l : mid_levels(p, quick)) {
      Config c;
      c.problem = p;
      c.level = l;
      c.study = "quadrature";
      for (const char* q : {"cheap", "fine"}) {
        c.quadrature = q;
        out.push_back(c);
      }
      c.quadrature = "baseline";
      c.study = "solver";
      for (const char* method : {"gmres", "bicgstab"})
        for (double t : tolerances) {
          c.solver = method;
          c.tolerance = t;
          out.push_back(c);
        }
    }
  return out;
}

}  // namespace bemsurg::work_precision
