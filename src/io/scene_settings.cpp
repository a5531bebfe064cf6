// The "material", "solver" and "quadrature" sections of a scene (docs/scene-format.md): plain
// values with their ranges; the material is validated as the solver will use it (docs/design.md §2).
#include <cmath>

#include "bemsurg/constants.hpp"
#include "bemsurg/error.hpp"
#include "scene_sections.hpp"

namespace bemsurg::io {

Material load_material(const JsonReader& m, bool gravity_on) {
  m.object();
  m.warn_unknown_keys({"young_modulus", "poisson_ratio", "density"});
  Material mat;
  const JsonReader young = m.required("young_modulus");
  mat.young_modulus = young.number();
  if (!(mat.young_modulus > 0.0)) young.fail("must be positive (Pa), got " + json_number_text(mat.young_modulus));
  const JsonReader poisson = m.required("poisson_ratio");
  mat.poisson_ratio = poisson.number();
  if (!(mat.poisson_ratio > -1.0 && mat.poisson_ratio < 0.5))
    poisson.fail("must lie in the open interval (-1, 0.5), got " + json_number_text(mat.poisson_ratio));
  if (const std::optional<JsonReader> d = m.optional("density")) {
    mat.density = d->number();
    if (mat.density < 0.0) d->fail("must not be negative (kg/m^3), got " + json_number_text(mat.density));
  } else if (gravity_on) {
    m.fail_at(m.path_of("density"), "missing (required when gravity is non-zero: the body force is density * gravity)");
  }
  try {
    mat.validate();
  } catch (const Error& e) { m.fail(e.what()); }
  return mat;
}

namespace {

/// A name from a fixed list, turned into its enum by `parse` (which throws SolverError for a name
/// it does not know).
template <typename Parse>
auto read_name(const JsonReader& v, Parse parse, const std::string& what, const std::string& known) {
  const std::string name = v.string();
  try {
    return parse(name);
  } catch (const SolverError&) { v.fail("unknown " + what + " '" + name + "' (expected " + known + ")"); }
}

}  // namespace

LinearSolverOptions load_solver(const JsonReader& s) {
  s.object();
  s.warn_unknown_keys({"method", "tolerance", "max_iterations", "restart", "preconditioner", "near_field_radius", "compression_tolerance"});
  LinearSolverOptions out;
  if (const std::optional<JsonReader> v = s.optional("method")) {
    // "hmatrix": the hierarchical backend (docs/solvers.md, "Hierarchical matrices"), a direct H-LU.
    // "auto": dense LU or hmatrix, chosen per mesh by the command (choose_backend, hierarchical_solver.hpp).
    // "scalapack": the dense LU split over MPI ranks (docs/distributed.md), one rank outside mpirun.
    if (v->is_string() && v->string() == to_string(SolverBackend::HMatrix))
      out.backend = SolverBackend::HMatrix;
    else if (v->is_string() && v->string() == to_string(SolverBackend::ScaLapack))
      out.backend = SolverBackend::ScaLapack;
    else if (v->is_string() && v->string() == "auto")
      out.automatic_backend = true;
    else
      out.method = read_name(*v, parse_solver_method, "method", "lu, gmres, bicgstab, bicg, hmatrix, scalapack or auto");
  }
  if (const std::optional<JsonReader> v = s.optional("compression_tolerance")) {
    // Per far-field block, relative: below 1e-12 ACA+ works at round-off and stores little less than dense;
    // above 0.1 the answer is not worth having.
    out.compression_tolerance = v->number();
    if (!(out.compression_tolerance >= 1e-12 && out.compression_tolerance <= 0.1))
      v->fail("must lie in [1e-12, 0.1] (ACA+'s relative tolerance per block), got " + v->dump());
    if (out.backend != SolverBackend::HMatrix && !out.automatic_backend)
      s.fail_at(s.path_of("compression_tolerance"), "applies only to \"method\": \"hmatrix\" or \"auto\"");
  }
  if (const std::optional<JsonReader> v = s.optional("tolerance")) {
    out.tolerance = v->number();
    if (!(out.tolerance > 0.0 && out.tolerance < 1.0)) v->fail("must lie in (0, 1) (a relative residual), got " + v->dump());
  }
  // A cap of a million iterations: far beyond any useful BEM solve (GMRES restarts or BiCGSTAB
  // on A* converge in tens to hundreds), while a typo such as 1e8 is caught here.
  if (const std::optional<JsonReader> v = s.optional("max_iterations")) out.max_iterations = v->integer_in(1, 1000000);
  if (const std::optional<JsonReader> v = s.optional("restart")) out.restart = v->integer_in(0, 100000000);
  if (const std::optional<JsonReader> v = s.optional("preconditioner"))
    out.preconditioner = read_name(*v, parse_preconditioner, "preconditioner", "none, block_jacobi or near_field");
  if (const std::optional<JsonReader> v = s.optional("near_field_radius")) {
    // In element diameters: a few is typical; beyond 100 every pair of a practical mesh is near,
    // which makes the sparse factor a slower dense one (and can overflow UMFPACK's int indices).
    out.near_field_radius = v->number();
    if (!(out.near_field_radius > 0.0 && out.near_field_radius <= 100.0))
      v->fail("must lie in (0, 100] element diameters, got " + v->dump());
  }
  return out;
}

QuadratureOptions load_quadrature(const JsonReader& q) {
  q.object();
  q.warn_unknown_keys({"far_ratio", "mid_ratio", "mid_order", "max_depth", "polar_order", "polar_max_angle"});
  QuadratureOptions o;
  if (const std::optional<JsonReader> v = q.optional("far_ratio")) o.far_ratio = v->positive();
  if (const std::optional<JsonReader> v = q.optional("mid_ratio")) o.mid_ratio = v->positive();
  if (o.mid_ratio > o.far_ratio) q.fail_at(q.path_of("mid_ratio"), "must not exceed quadrature.far_ratio");
  if (const std::optional<JsonReader> v = q.optional("mid_order")) o.mid_order = v->integer_in(1, 20);
  if (const std::optional<JsonReader> v = q.optional("max_depth")) o.max_depth = v->integer_in(0, 20);
  if (const std::optional<JsonReader> v = q.optional("polar_order")) o.polar_order = v->integer_in(1, 40);
  if (const std::optional<JsonReader> v = q.optional("polar_max_angle")) {
    o.polar_max_angle = v->positive();
    if (o.polar_max_angle > numbers::pi) v->fail("must not exceed pi");
  }
  return o;
}

}  // namespace bemsurg::io
