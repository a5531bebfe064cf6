// Scene files (bemsurg/io/scene.hpp, docs/scene-format.md): JSON and CSV in, a checked
// ElastostaticProblem out. Boundary conditions follow docs/design.md §5 (per element and component,
// u or t prescribed; pressure p means t = -p n). Every check throws SceneError whose message starts
// with the key path ("boundary_conditions.rules[1].select.plane.normal") or the file and line.
#include "bemsurg/io/scene.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

#include "bemsurg/error.hpp"
#include "bemsurg/elastostatic_solver.hpp"
#include "bemsurg/io/element_selector.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/brain_model.hpp"
#include "bemsurg/mesh/graded_remesher.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_io.hpp"
#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/post/interior_clearance.hpp"

namespace bemsurg {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// ---- JSON access with key paths -------------------------------------------------------------

[[noreturn]] void fail(const std::string& key, const std::string& what) { throw SceneError(key + ": " + what); }

std::string child(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}
std::string item(const std::string& parent, std::size_t i) { return parent + "[" + std::to_string(i) + "]"; }

/// "a string", "an array", ... for messages.
std::string describe_type(const json& v) {
  switch (v.type()) {
    case json::value_t::null: return "null";
    case json::value_t::object: return "an object";
    case json::value_t::array: return "an array";
    case json::value_t::string: return "a string";
    case json::value_t::boolean: return "a boolean";
    default: return "a number";
  }
}

void require_object(const json& v, const std::string& key) {
  if (!v.is_object()) fail(key, "expected an object, got " + describe_type(v));
}

const json& required(const json& obj, const std::string& name, const std::string& parent) {
  const auto it = obj.find(name);
  if (it == obj.end()) fail(child(parent, name), "missing (required)");
  return *it;
}

const json* optional(const json& obj, const std::string& name) {
  const auto it = obj.find(name);
  return it == obj.end() ? nullptr : &*it;
}

double as_number(const json& v, const std::string& key) {
  if (!v.is_number()) fail(key, "expected a number, got " + describe_type(v));
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(key, "expected a finite number");
  return x;
}

long long as_integer(const json& v, const std::string& key) {
  if (v.is_number_integer()) return v.get<long long>();
  if (v.is_number_float()) {
    const double x = v.get<double>();
    // 3.0 is accepted as 3: JSON writers differ in how they print whole numbers.
    if (std::isfinite(x) && x == std::floor(x) && std::abs(x) < 9.0e15) return static_cast<long long>(x);
    fail(key, "expected an integer, got " + v.dump());
  }
  fail(key, "expected an integer, got " + describe_type(v));
}

int as_int_in(const json& v, const std::string& key, long long lo, long long hi) {
  const long long x = as_integer(v, key);
  if (x < lo || x > hi) fail(key, "must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(x));
  return static_cast<int>(x);
}

std::string as_string(const json& v, const std::string& key) {
  if (!v.is_string()) fail(key, "expected a string, got " + describe_type(v));
  return v.get<std::string>();
}

bool as_bool(const json& v, const std::string& key) {
  if (!v.is_boolean()) fail(key, "expected true or false, got " + describe_type(v));
  return v.get<bool>();
}

Eigen::Vector3d as_vec3(const json& v, const std::string& key) {
  if (!v.is_array() || v.size() != 3)
    fail(key, "expected an array of 3 numbers, got " + (v.is_array() ? "an array of " + std::to_string(v.size()) : describe_type(v)));
  Eigen::Vector3d out;
  for (std::size_t i = 0; i < 3; ++i) out(static_cast<Index>(i)) = as_number(v[i], item(key, i));
  return out;
}

double positive(double x, const std::string& key) {
  if (!(x > 0.0)) fail(key, "must be positive, got " + json(x).dump());
  return x;
}

/// Unknown keys are reported as warnings, not errors: a scene written for a later version (or
/// annotated with extra keys) still runs, but a typo such as "gravty" does not pass unnoticed.
void note_unknown_keys(const json& obj, const std::string& parent, std::initializer_list<const char*> known,
                       std::vector<std::string>& warnings) {
  for (auto it = obj.begin(); it != obj.end(); ++it) {
    const std::string& k = it.key();
    if (k.empty() || k[0] == '_' || k == "comment" || k == "description" || k == "name" || k == "title") continue;
    bool found = false;
    for (const char* name : known) found = found || k == name;
    if (found) continue;
    std::string list;
    for (const char* name : known) list += (list.empty() ? "" : ", ") + std::string(name);
    warnings.push_back(child(parent, k) + ": unknown key, ignored (known here: " + list + ")");
  }
}

// ---- CSV with line numbers -------------------------------------------------------------------

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) fields.push_back(trim(field));
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

struct CsvRow {
  std::size_t line = 0;  // 1-based line number in the file
  std::vector<std::string> fields;
};

/// Reads a CSV whose first non-blank line must be `header` exactly (fields compared after trimming
/// blanks). Blank lines and lines starting with '#' are skipped. `key` names the file in messages.
std::vector<CsvRow> read_csv(const std::string& path, const std::string& header, const std::string& key) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(key, "cannot read '" + path + "': " + std::strerror(errno));
  std::vector<CsvRow> rows;
  const std::vector<std::string> expected = split_fields(header);
  std::string line;
  std::size_t number = 0;
  bool header_seen = false;
  while (std::getline(in, line)) {
    ++number;
    if (number == 1 && line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // UTF-8 BOM
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    std::vector<std::string> fields = split_fields(t);
    if (!header_seen) {
      if (fields != expected)
        fail(key + " line " + std::to_string(number), "expected the header '" + header + "', got '" + t + "'");
      header_seen = true;
      continue;
    }
    if (fields.size() != expected.size())
      fail(key + " line " + std::to_string(number),
           "expected " + std::to_string(expected.size()) + " fields, got " + std::to_string(fields.size()));
    rows.push_back({number, std::move(fields)});
  }
  if (!header_seen) fail(key, "'" + path + "' is empty (expected the header '" + header + "')");
  return rows;
}

double parse_csv_number(const std::string& text, const std::string& where) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(x))
    fail(where, "expected a finite number, got '" + text + "'");
  return x;
}

long long parse_csv_integer(const std::string& text, const std::string& where) {
  errno = 0;
  char* end = nullptr;
  const long long x = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE)
    fail(where, "expected an integer element index, got '" + text + "'");
  return x;
}

BcKind parse_kind(const std::string& text, const std::string& where) {
  if (text == "u" || text == "U") return BcKind::Displacement;
  if (text == "t" || text == "T") return BcKind::Traction;
  fail(where, "unknown kind '" + text + "' (expected u for displacement or t for traction)");
}

// ---- paths -----------------------------------------------------------------------------------

std::string resolve(const std::string& directory, const std::string& file) {
  const fs::path p(file);
  if (p.is_absolute() || directory.empty()) return p.lexically_normal().string();
  return (fs::path(directory) / p).lexically_normal().string();
}

std::string resolve_existing(const std::string& directory, const json& v, const std::string& key) {
  const std::string name = as_string(v, key);
  if (name.empty()) fail(key, "expected a file name, got an empty string");
  const std::string path = resolve(directory, name);
  std::error_code ec;
  if (!fs::exists(path, ec)) fail(key, "cannot read '" + path + "': no such file");
  if (fs::is_directory(path, ec)) fail(key, "cannot read '" + path + "': it is a directory");
  return path;
}

// ---- mesh ------------------------------------------------------------------------------------

// Generators beyond these sizes give dense systems no machine holds; refusing them here turns an
// out-of-memory crash into a message.
constexpr int kMaxSubdivisions = 7;
constexpr int kMaxDivisions = 1000;

std::vector<double> as_increasing(const json& v, const std::string& key) {
  if (!v.is_array() || v.size() < 2) fail(key, "expected an array of at least 2 increasing numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    out.push_back(as_number(v[i], item(key, i)));
    if (i > 0 && !(out[i] > out[i - 1])) fail(item(key, i), "coordinates must be strictly increasing");
  }
  return out;
}

// A generated mesh is sized from its parameters before it is generated (docs/design.md §10): one
// that the dense solve could not hold (H and G alone) is refused with the estimate, instead of
// generating and validating millions of elements first.
void require_generated_size(const std::string& key, const std::string& what, double elements) {
  const double need = estimate_elastostatic_bytes(static_cast<Index>(elements)), limit = default_memory_limit_bytes();
  if (need <= limit) return;
  std::ostringstream m;
  m.precision(3);
  m << key << ": " << what << " has " << static_cast<long long>(elements) << " elements; the dense solve needs about " << format_gib(need)
    << ", more than the limit of " << format_gib(limit) << " (80 % of physical memory); refused before generating it";
  throw ResourceError(m.str());
}

TriangleMesh generate_mesh(const json& m, std::string& source, std::vector<std::string>& warnings) {
  const std::string kind = as_string(m["generator"], "mesh.generator");
  const auto center = [&] { return optional(m, "center") ? as_vec3(m["center"], "mesh.center") : Vec3(Vec3::Zero()); };
  const auto subdivisions = [&](const char* name, int fallback) {
    return optional(m, name) ? as_int_in(m[name], child("mesh", name), 0, kMaxSubdivisions) : fallback;
  };
  try {
    if (kind == "box") {
      note_unknown_keys(m, "mesh", {"generator", "min", "max", "divisions"}, warnings);
      const Vec3 lo = as_vec3(required(m, "min", "mesh"), "mesh.min");
      const Vec3 hi = as_vec3(required(m, "max", "mesh"), "mesh.max");
      for (int c = 0; c < 3; ++c)
        if (!(lo(c) < hi(c))) fail("mesh.max", "must exceed mesh.min in every component");
      const json& d = required(m, "divisions", "mesh");
      if (!d.is_array() || d.size() != 3) fail("mesh.divisions", "expected an array of 3 integers [nx, ny, nz]");
      int n[3];
      for (std::size_t i = 0; i < 3; ++i) n[i] = as_int_in(d[i], item("mesh.divisions", i), 1, kMaxDivisions);
      source = "box generator, " + std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
      require_generated_size("mesh.divisions", "a " + source.substr(15) + " box",
                             4.0 * (double(n[0]) * n[1] + double(n[1]) * n[2] + double(n[0]) * n[2]));
      return box_mesh(lo, hi, n[0], n[1], n[2]);
    }
    if (kind == "box_grid") {
      note_unknown_keys(m, "mesh", {"generator", "x", "y", "z"}, warnings);
      const auto xs = as_increasing(required(m, "x", "mesh"), "mesh.x");
      const auto ys = as_increasing(required(m, "y", "mesh"), "mesh.y");
      const auto zs = as_increasing(required(m, "z", "mesh"), "mesh.z");
      source = "box_grid generator";
      const double gx = double(xs.size() - 1), gy = double(ys.size() - 1), gz = double(zs.size() - 1);
      require_generated_size("mesh", "the box_grid", 4.0 * (gx * gy + gy * gz + gx * gz));
      return box_mesh_from_grid(xs, ys, zs);
    }
    if (kind == "icosphere") {
      note_unknown_keys(m, "mesh", {"generator", "center", "radius", "subdivisions"}, warnings);
      const double r = positive(as_number(required(m, "radius", "mesh"), "mesh.radius"), "mesh.radius");
      const int s = subdivisions("subdivisions", 2);
      source = "icosphere generator, subdivisions " + std::to_string(s);
      require_generated_size("mesh.subdivisions", "the icosphere", 20.0 * std::pow(4.0, s));
      return icosphere_mesh(center(), r, s);
    }
    if (kind == "ellipsoid") {
      note_unknown_keys(m, "mesh", {"generator", "center", "semi_axes", "subdivisions"}, warnings);
      const Vec3 axes = as_vec3(required(m, "semi_axes", "mesh"), "mesh.semi_axes");
      for (int c = 0; c < 3; ++c) positive(axes(c), item("mesh.semi_axes", static_cast<std::size_t>(c)));
      const int s = subdivisions("subdivisions", 2);
      source = "ellipsoid generator, subdivisions " + std::to_string(s);
      require_generated_size("mesh.subdivisions", "the ellipsoid", 20.0 * std::pow(4.0, s));
      return ellipsoid_mesh(center(), axes, s);
    }
    if (kind == "hollow_sphere") {
      note_unknown_keys(m, "mesh",
                        {"generator", "center", "inner_radius", "outer_radius", "subdivisions", "subdivisions_inner",
                         "subdivisions_outer"},
                        warnings);
      const double a = positive(as_number(required(m, "inner_radius", "mesh"), "mesh.inner_radius"), "mesh.inner_radius");
      const double b = positive(as_number(required(m, "outer_radius", "mesh"), "mesh.outer_radius"), "mesh.outer_radius");
      if (!(a < b)) fail("mesh.outer_radius", "must exceed mesh.inner_radius");
      const int s = subdivisions("subdivisions", 2);
      const int si = subdivisions("subdivisions_inner", s);
      const int so = subdivisions("subdivisions_outer", s);
      source = "hollow_sphere generator, subdivisions " + std::to_string(si) + "/" + std::to_string(so);
      require_generated_size("mesh.subdivisions", "the hollow sphere", 20.0 * (std::pow(4.0, si) + std::pow(4.0, so)));
      return hollow_sphere_mesh(center(), a, b, si, so);
    }
    if (kind == "brain") {
      note_unknown_keys(m, "mesh",
                        {"generator", "size", "subdivisions", "fissure_depth", "fissure_half_width", "fold_amplitude",
                         "fold_wavelength"},
                        warnings);
      BrainModelOptions o;
      if (optional(m, "size")) {
        o.size = as_vec3(m["size"], "mesh.size");
        for (int c = 0; c < 3; ++c) positive(o.size(c), item("mesh.size", static_cast<std::size_t>(c)));
      }
      o.subdivisions = subdivisions("subdivisions", o.subdivisions);
      const auto number = [&](const char* name, double& value) {
        if (optional(m, name)) value = as_number(m[name], child("mesh", name));
      };
      number("fissure_depth", o.fissure_depth);
      number("fissure_half_width", o.fissure_half_width);
      number("fold_amplitude", o.fold_amplitude);
      number("fold_wavelength", o.fold_wavelength);
      source = "brain generator, subdivisions " + std::to_string(o.subdivisions);
      return brain_mesh(o);
    }
  } catch (const SceneError&) {
    throw;
  } catch (const ResourceError&) {
    throw;
  } catch (const Error& e) {
    fail("mesh", std::string("generator '") + kind + "' failed: " + e.what());
  }
  fail("mesh.generator",
       "unknown generator '" + kind + "' (expected box, box_grid, icosphere, ellipsoid, hollow_sphere or brain)");
}

TriangleMesh load_mesh(const json& m, const std::string& directory, std::string& source, std::vector<std::string>& warnings) {
  require_object(m, "mesh");
  const bool has_file = m.contains("file");
  const bool has_generator = m.contains("generator");
  if (has_file == has_generator)
    fail("mesh", has_file ? "give either \"file\" or \"generator\", not both" : "expected a \"file\" or a \"generator\" key");

  TriangleMesh mesh;
  if (has_file) {
    note_unknown_keys(m, "mesh", {"file", "scale", "translate"}, warnings);
    const std::string path = resolve_existing(directory, m["file"], "mesh.file");
    try {
      mesh = read_mesh(path);
    } catch (const Error& e) {
      fail("mesh.file", "cannot load '" + path + "': " + e.what());
    }
    source = path;
    // Optional affine map, for meshes drawn in millimetres or away from the origin: x' = s x + t.
    const double scale = optional(m, "scale") ? positive(as_number(m["scale"], "mesh.scale"), "mesh.scale") : 1.0;
    const Vec3 shift = optional(m, "translate") ? as_vec3(m["translate"], "mesh.translate") : Vec3(Vec3::Zero());
    if (scale != 1.0 || !shift.isZero(0.0)) {
      RowMatrixX3d v = mesh.vertices() * scale;
      v.rowwise() += shift.transpose();
      mesh = TriangleMesh(v, mesh.faces());
    }
  } else {
    mesh = generate_mesh(m, source, warnings);
  }

  try {
    require_valid_mesh(mesh);
  } catch (const Error& e) {
    // The validator's message may already start with "invalid mesh: "; say it once.
    std::string what = e.what();
    if (what.rfind("invalid mesh: ", 0) == 0) what.erase(0, 14);
    fail(has_file ? "mesh.file" : "mesh", "invalid mesh (" + source + "): " + what);
  }
  // Legal but unreliable: a body thinner than its elements (docs/design.md §2).
  const ThinElements thin = find_thin_elements(mesh);
  if (thin.count > 0) {
    std::ostringstream w;
    w.precision(3);
    w << (has_file ? "mesh.file" : "mesh") << ": " << thin.count
      << " elements are larger than the body is thick under them (element " << thin.element << ": size " << thin.size
      << ", thickness " << thin.thickness
      << " along its inward normal); constant elements cannot resolve a part thinner than themselves and the "
         "results there may be far off: refine the mesh to elements no larger than the thickness";
    warnings.push_back(w.str());
  }
  return mesh;
}

// ---- material, gravity, solver, quadrature ----------------------------------------------------

Material load_material(const json& m, bool gravity_on, std::vector<std::string>& warnings) {
  require_object(m, "material");
  note_unknown_keys(m, "material", {"young_modulus", "poisson_ratio", "density"}, warnings);
  Material mat;
  mat.young_modulus = as_number(required(m, "young_modulus", "material"), "material.young_modulus");
  if (!(mat.young_modulus > 0.0))
    fail("material.young_modulus", "must be positive (Pa), got " + json(mat.young_modulus).dump());
  mat.poisson_ratio = as_number(required(m, "poisson_ratio", "material"), "material.poisson_ratio");
  if (!(mat.poisson_ratio > -1.0 && mat.poisson_ratio < 0.5))
    fail("material.poisson_ratio", "must lie in the open interval (-1, 0.5), got " + json(mat.poisson_ratio).dump());
  if (const json* d = optional(m, "density")) {
    mat.density = as_number(*d, "material.density");
    if (mat.density < 0.0) fail("material.density", "must not be negative (kg/m^3), got " + json(mat.density).dump());
  } else if (gravity_on) {
    fail("material.density", "missing (required when gravity is non-zero: the body force is density * gravity)");
  }
  try {
    mat.validate();
  } catch (const Error& e) {
    fail("material", e.what());
  }
  return mat;
}

LinearSolverSettings load_solver(const json& s, std::vector<std::string>& warnings) {
  require_object(s, "solver");
  note_unknown_keys(s, "solver",
                    {"method", "tolerance", "max_iterations", "restart", "preconditioner", "near_field_radius"}, warnings);
  LinearSolverSettings out;
  if (const json* v = optional(s, "method")) {
    const std::string name = as_string(*v, "solver.method");
    try {
      out.method = parse_solver_method(name);
    } catch (const SolverError&) {
      fail("solver.method", "unknown method '" + name + "' (expected lu, gmres, bicgstab or bicg)");
    }
  }
  if (const json* v = optional(s, "tolerance")) {
    out.tolerance = as_number(*v, "solver.tolerance");
    if (!(out.tolerance > 0.0 && out.tolerance < 1.0))
      fail("solver.tolerance", "must lie in (0, 1) (a relative residual), got " + v->dump());
  }
  // A cap of a million iterations: far beyond any useful BEM solve (GMRES restarts or BiCGSTAB
  // on A* converge in tens to hundreds), while a typo such as 1e8 is caught here.
  if (const json* v = optional(s, "max_iterations")) out.max_iterations = as_int_in(*v, "solver.max_iterations", 1, 1000000);
  if (const json* v = optional(s, "restart")) out.restart = as_int_in(*v, "solver.restart", 0, 100000000);
  if (const json* v = optional(s, "preconditioner")) {
    const std::string name = as_string(*v, "solver.preconditioner");
    try {
      out.preconditioner = parse_preconditioner(name);
    } catch (const SolverError&) {
      fail("solver.preconditioner", "unknown preconditioner '" + name + "' (expected none, block_jacobi or near_field)");
    }
  }
  if (const json* v = optional(s, "near_field_radius")) {
    // In element diameters: a few is typical; beyond 100 every pair of a practical mesh is near,
    // which makes the sparse factor a slower dense one (and can overflow UMFPACK's int indices).
    out.near_field_radius = as_number(*v, "solver.near_field_radius");
    if (!(out.near_field_radius > 0.0 && out.near_field_radius <= 100.0))
      fail("solver.near_field_radius", "must lie in (0, 100] element diameters, got " + v->dump());
  }
  return out;
}

QuadratureOptions load_quadrature(const json& q, std::vector<std::string>& warnings) {
  require_object(q, "quadrature");
  note_unknown_keys(q, "quadrature", {"far_ratio", "mid_ratio", "mid_order", "max_depth", "polar_order", "polar_max_angle"},
                    warnings);
  QuadratureOptions o;
  if (const json* v = optional(q, "far_ratio")) o.far_ratio = positive(as_number(*v, "quadrature.far_ratio"), "quadrature.far_ratio");
  if (const json* v = optional(q, "mid_ratio")) o.mid_ratio = positive(as_number(*v, "quadrature.mid_ratio"), "quadrature.mid_ratio");
  if (o.mid_ratio > o.far_ratio) fail("quadrature.mid_ratio", "must not exceed quadrature.far_ratio");
  if (const json* v = optional(q, "mid_order")) o.mid_order = as_int_in(*v, "quadrature.mid_order", 1, 20);
  if (const json* v = optional(q, "max_depth")) o.max_depth = as_int_in(*v, "quadrature.max_depth", 0, 20);
  if (const json* v = optional(q, "polar_order")) o.polar_order = as_int_in(*v, "quadrature.polar_order", 1, 40);
  if (const json* v = optional(q, "polar_max_angle")) {
    o.polar_max_angle = positive(as_number(*v, "quadrature.polar_max_angle"), "quadrature.polar_max_angle");
    if (o.polar_max_angle > M_PI) fail("quadrature.polar_max_angle", "must not exceed pi");
  }
  return o;
}

// ---- boundary conditions ---------------------------------------------------------------------

std::vector<Index> evaluate_select(const json& sel, const TriangleMesh& mesh, const std::string& key,
                                   std::vector<std::string>& warnings) {
  require_object(sel, key);
  if (sel.empty()) fail(key, "expected at least one of plane, box, normal, shell, elements, all");
  note_unknown_keys(sel, key, {"plane", "box", "normal", "shell", "elements", "all"}, warnings);
  std::vector<Index> result;
  bool first = true;
  // Several selectors in one "select" must all hold (intersection), e.g. plane and normal.
  for (auto it = sel.begin(); it != sel.end(); ++it) {
    const std::string name = it.key();
    const std::string k = child(key, name);
    const json& v = it.value();
    ElementSelector s;
    if (name == "plane") {
      require_object(v, k);
      note_unknown_keys(v, k, {"point", "normal", "tolerance"}, warnings);
      const Vec3 point = as_vec3(required(v, "point", k), child(k, "point"));
      const Vec3 normal = as_vec3(required(v, "normal", k), child(k, "normal"));
      if (normal.norm() == 0.0) fail(child(k, "normal"), "must be a non-zero vector");
      const double diagonal = (mesh.bounding_box().col(1) - mesh.bounding_box().col(0)).norm();
      double tol = 1e-6 * diagonal;
      if (const json* t = optional(v, "tolerance")) {
        tol = as_number(*t, child(k, "tolerance"));
        if (tol < 0.0) fail(child(k, "tolerance"), "must not be negative");
      }
      s = ElementSelector::plane(point, normal, tol);
    } else if (name == "box") {
      require_object(v, k);
      note_unknown_keys(v, k, {"min", "max"}, warnings);
      const Vec3 lo = as_vec3(required(v, "min", k), child(k, "min"));
      const Vec3 hi = as_vec3(required(v, "max", k), child(k, "max"));
      if ((lo.array() > hi.array()).any()) fail(child(k, "max"), "must not be below min in any component");
      s = ElementSelector::box(lo, hi);
    } else if (name == "normal") {
      require_object(v, k);
      note_unknown_keys(v, k, {"direction", "min_cos"}, warnings);
      const Vec3 dir = as_vec3(required(v, "direction", k), child(k, "direction"));
      if (dir.norm() == 0.0) fail(child(k, "direction"), "must be a non-zero vector");
      double min_cos = 0.9;
      if (const json* c = optional(v, "min_cos")) {
        min_cos = as_number(*c, child(k, "min_cos"));
        if (min_cos < -1.0 || min_cos > 1.0) fail(child(k, "min_cos"), "must lie in [-1, 1], got " + c->dump());
      }
      s = ElementSelector::normal_direction(dir, min_cos);
    } else if (name == "shell") {
      s = ElementSelector::shell_index(as_int_in(v, k, 0, std::numeric_limits<int>::max()));
    } else if (name == "elements") {
      if (!v.is_array()) fail(k, "expected an array of element indices, got " + describe_type(v));
      std::vector<Index> list;
      for (std::size_t i = 0; i < v.size(); ++i) {
        const long long e = as_integer(v[i], item(k, i));
        if (e < 0 || e >= mesh.num_elements())
          fail(item(k, i), "element " + std::to_string(e) + " out of range (mesh has " +
                               std::to_string(mesh.num_elements()) + " elements)");
        list.push_back(static_cast<Index>(e));
      }
      s = ElementSelector::element_list(std::move(list));
    } else if (name == "all") {
      if (!as_bool(v, k)) fail(k, "only true is meaningful here");
      s = ElementSelector::all();
    } else {
      continue;  // already warned about
    }
    std::vector<Index> picked;
    try {
      picked = select_elements(mesh, s);
    } catch (const SceneError& e) {
      fail(key, e.what());  // e.what() starts with the selector name: "shell: index 3 out of range"
    }
    if (first) {
      result = std::move(picked);
      first = false;
    } else {
      std::vector<Index> both;
      std::set_intersection(result.begin(), result.end(), picked.begin(), picked.end(), std::back_inserter(both));
      result = std::move(both);
    }
  }
  if (first) fail(key, "expected at least one of plane, box, normal, shell, elements, all");
  return result;
}

void apply_rule(const json& rule, const std::string& key, const TriangleMesh& mesh, BoundaryConditions& bc,
                std::vector<std::string>& warnings) {
  require_object(rule, key);
  note_unknown_keys(rule, key, {"select", "displacement", "traction", "pressure", "kind", "value"}, warnings);
  const std::vector<Index> elements = evaluate_select(required(rule, "select", key), mesh, child(key, "select"), warnings);
  if (elements.empty())
    fail(child(key, "select"), "selects no elements (check the coordinates and the tolerance against the mesh's "
                               "bounding box)");

  int given = 0;
  for (const char* k : {"displacement", "traction", "pressure", "kind"}) given += rule.contains(k) ? 1 : 0;
  if (given != 1)
    fail(key, given == 0 ? "expected one of displacement, traction, pressure, or kind with value"
                         : "give only one of displacement, traction, pressure, or kind with value");
  if (rule.contains("value") && !rule.contains("kind")) fail(child(key, "value"), "needs \"kind\" beside it");

  if (const json* v = optional(rule, "displacement")) {
    const Vec3 u = as_vec3(*v, child(key, "displacement"));
    for (Index e : elements) bc.prescribe_displacement(e, u);
  } else if (const json* v = optional(rule, "traction")) {
    const Vec3 t = as_vec3(*v, child(key, "traction"));
    for (Index e : elements) bc.prescribe_traction(e, t);
  } else if (const json* v = optional(rule, "pressure")) {
    const double p = as_number(*v, child(key, "pressure"));
    for (Index e : elements) bc.prescribe_pressure(e, p, mesh.normal(e));
  } else {
    const json& kinds = rule["kind"];
    const std::string kk = child(key, "kind");
    BcKind k3[3];
    if (kinds.is_string()) {
      k3[0] = k3[1] = k3[2] = parse_kind(kinds.get<std::string>(), kk);
    } else if (kinds.is_array() && kinds.size() == 3) {
      for (std::size_t c = 0; c < 3; ++c) k3[c] = parse_kind(as_string(kinds[c], item(kk, c)), item(kk, c));
    } else {
      fail(kk, "expected \"u\", \"t\" or an array of 3 of them, got " + describe_type(kinds));
    }
    const Vec3 value = as_vec3(required(rule, "value", key), child(key, "value"));
    for (Index e : elements)
      for (int c = 0; c < 3; ++c) bc.prescribe_component(e, c, k3[c], value(c));
  }
}

void apply_bc_file(const std::string& path, const std::string& key, const TriangleMesh& mesh, BoundaryConditions& bc) {
  const auto rows = read_csv(path, "element,kind_x,kind_y,kind_z,value_x,value_y,value_z", key);
  static const char* kind_names[3] = {"kind_x", "kind_y", "kind_z"};
  static const char* value_names[3] = {"value_x", "value_y", "value_z"};
  for (const CsvRow& row : rows) {
    const std::string where = key + " line " + std::to_string(row.line);
    const long long e = parse_csv_integer(row.fields[0], where + ": element");
    if (e < 0 || e >= mesh.num_elements())
      fail(where, "element " + std::to_string(e) + " out of range (mesh has " + std::to_string(mesh.num_elements()) +
                      " elements)");
    for (int c = 0; c < 3; ++c) {
      const BcKind kind = parse_kind(row.fields[static_cast<std::size_t>(1 + c)], where + ": " + kind_names[c]);
      const double value = parse_csv_number(row.fields[static_cast<std::size_t>(4 + c)], where + ": " + value_names[c]);
      bc.prescribe_component(static_cast<Index>(e), c, kind, value);
    }
  }
}

BoundaryConditions load_boundary_conditions(const json& b, const std::string& directory, const TriangleMesh& mesh,
                                            std::vector<std::string>& warnings) {
  require_object(b, "boundary_conditions");
  note_unknown_keys(b, "boundary_conditions", {"file", "rules"}, warnings);
  // Everything starts traction-free; rules apply in order (later ones win on shared elements);
  // the file comes last, so a per-element file can refine what the rules set.
  BoundaryConditions bc(mesh.num_elements());
  if (const json* rules = optional(b, "rules")) {
    if (!rules->is_array()) fail("boundary_conditions.rules", "expected an array of rules, got " + describe_type(*rules));
    for (std::size_t i = 0; i < rules->size(); ++i)
      apply_rule((*rules)[i], item("boundary_conditions.rules", i), mesh, bc, warnings);
  }
  if (const json* file = optional(b, "file")) {
    const std::string path = resolve_existing(directory, *file, "boundary_conditions.file");
    apply_bc_file(path, "boundary_conditions.file", mesh, bc);
  }
  return bc;
}

// ---- interior points -------------------------------------------------------------------------

RowMatrixX3d load_interior_points(const json& ip, const std::string& directory, const TriangleMesh& mesh,
                                  const QuadratureOptions& quadrature, std::vector<std::string>& warnings) {
  const std::string key = "interior_points";
  std::vector<Vec3> points;
  std::vector<std::string> where;  // how to name each point in a message
  const auto add_inline = [&](const json& list, const std::string& k) {
    if (!list.is_array()) fail(k, "expected an array of [x, y, z] points, got " + describe_type(list));
    for (std::size_t i = 0; i < list.size(); ++i) {
      points.push_back(as_vec3(list[i], item(k, i)));
      where.push_back(item(k, i));
    }
  };
  if (ip.is_array()) {
    add_inline(ip, key);
  } else {
    require_object(ip, key);
    note_unknown_keys(ip, key, {"file", "points"}, warnings);
    if (!ip.contains("file") && !ip.contains("points")) fail(key, "expected a \"file\" or a \"points\" key");
    if (const json* list = optional(ip, "points")) add_inline(*list, child(key, "points"));
    if (const json* file = optional(ip, "file")) {
      const std::string path = resolve_existing(directory, *file, child(key, "file"));
      const std::string k = child(key, "file");
      for (const CsvRow& row : read_csv(path, "x,y,z", k)) {
        const std::string w = k + " line " + std::to_string(row.line);
        points.emplace_back(parse_csv_number(row.fields[0], w + ": x"), parse_csv_number(row.fields[1], w + ": y"),
                            parse_csv_number(row.fields[2], w + ": z"));
        where.push_back(w);
      }
    }
  }
  RowMatrixX3d out(static_cast<Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    // Somigliana's identity with c = I holds only inside; outside it returns zero-ish garbage and
    // on the surface it is singular, so such points are refused rather than evaluated.
    bool on_surface = false;
    const double w = winding_number(mesh, points[i], &on_surface);
    if (on_surface || std::abs(w - 1.0) > 0.25) {
      const Vec3& p = points[i];
      fail(where[i], "point (" + json(p.x()).dump() + ", " + json(p.y()).dump() + ", " + json(p.z()).dump() +
                         ") is not inside the body" + (on_surface ? " (it lies on the surface)" : ""));
    }
    out.row(static_cast<Index>(i)) = points[i].transpose();
  }
  // Too close to the surface for the quadrature: refused here rather than after the solve.
  const ClearanceViolation v = find_point_too_close(mesh, out, quadrature);
  if (v.point >= 0) {
    const Vec3& p = points[static_cast<std::size_t>(v.point)];
    fail(where[static_cast<std::size_t>(v.point)], "point (" + json(p.x()).dump() + ", " + json(p.y()).dump() + ", " +
                                                       json(p.z()).dump() + ") " + describe_clearance_violation(v, quadrature));
  }
  return out;
}

// ---- operating region ------------------------------------------------------------------------

// A graded mesh of more elements than this would give a dense system (3E unknowns) of more than
// 10^11 entries: refused before Gmsh spends minutes producing it.
constexpr double kMaxGradedElements = 60000.0;

/// Reads "operating_region" (docs/scene-format.md#operating_region) against the mesh as generated
/// or read; remeshes it when edge lengths are given. Returns the region; `mesh` may be replaced.
OperatingRegion load_operating_region(const json& r, TriangleMesh& mesh, Scene& scene) {
  const std::string key = "operating_region";
  require_object(r, key);
  note_unknown_keys(r, key,
                    {"sphere", "box", "elements", "inside_edge_length", "outside_edge_length", "growth", "feature_angle"},
                    scene.warnings);
  const int shapes = int(r.contains("sphere")) + int(r.contains("box")) + int(r.contains("elements"));
  if (shapes != 1) fail(key, "expected exactly one of \"sphere\", \"box\" or \"elements\", got " + std::to_string(shapes));
  OperatingRegion region;
  if (const json* s = optional(r, "sphere")) {
    const std::string k = child(key, "sphere");
    require_object(*s, k);
    note_unknown_keys(*s, k, {"center", "radius"}, scene.warnings);
    const Vec3 c = as_vec3(required(*s, "center", k), child(k, "center"));
    const double radius = positive(as_number(required(*s, "radius", k), child(k, "radius")), child(k, "radius"));
    region = OperatingRegion::sphere(c, radius);
  } else if (const json* b = optional(r, "box")) {
    const std::string k = child(key, "box");
    require_object(*b, k);
    note_unknown_keys(*b, k, {"min", "max"}, scene.warnings);
    const Vec3 lo = as_vec3(required(*b, "min", k), child(k, "min"));
    const Vec3 hi = as_vec3(required(*b, "max", k), child(k, "max"));
    if (!(lo.array() < hi.array()).all()) fail(child(k, "max"), "must exceed " + child(k, "min") + " in every component");
    region = OperatingRegion::box(lo, hi);
  } else {
    const std::string k = child(key, "elements");
    const json& e = r["elements"];
    if (!e.is_array() || e.empty()) fail(k, "expected a non-empty array of element indices");
    std::vector<Index> ids;
    for (std::size_t i = 0; i < e.size(); ++i) {
      const long long id = as_integer(e[i], item(k, i));
      if (id < 0 || id >= mesh.num_elements())
        fail(item(k, i), "element " + std::to_string(id) + " out of range (mesh has " +
                             std::to_string(mesh.num_elements()) + " elements)");
      ids.push_back(static_cast<Index>(id));
    }
    region = OperatingRegion::element_set(mesh, ids);
  }

  const bool has_inside = r.contains("inside_edge_length"), has_outside = r.contains("outside_edge_length");
  if (has_inside != has_outside)
    fail(child(key, has_inside ? "outside_edge_length" : "inside_edge_length"),
         "missing (inside_edge_length and outside_edge_length come together: they ask for a graded remesh)");
  GradedRemeshOptions options;
  if (has_inside) {
    const std::string ki = child(key, "inside_edge_length"), ko = child(key, "outside_edge_length");
    options.inside_edge_length = positive(as_number(r["inside_edge_length"], ki), ki);
    options.outside_edge_length = positive(as_number(r["outside_edge_length"], ko), ko);
    if (options.inside_edge_length > options.outside_edge_length)
      fail(ki, "is larger than " + ko + " (" + json(options.inside_edge_length).dump() + " > " +
                   json(options.outside_edge_length).dump() + "): the operating region must be the finer part");
    if (const json* g = optional(r, "growth")) {
      options.growth = as_number(*g, child(key, "growth"));
      if (!(options.growth > 1.0 && options.growth <= 2.0))
        fail(child(key, "growth"), "must lie in (1, 2], got " + g->dump());
    }
    if (const json* a = optional(r, "feature_angle")) {
      options.feature_angle_degrees = as_number(*a, child(key, "feature_angle"));
      if (!(options.feature_angle_degrees > 0.0 && options.feature_angle_degrees < 180.0))
        fail(child(key, "feature_angle"), "must lie in (0, 180) degrees, got " + a->dump());
    }
  } else {
    for (const char* k : {"growth", "feature_angle"})
      if (r.contains(k))
        scene.warnings.push_back(child(key, k) + ": ignored without inside_edge_length and outside_edge_length");
  }

  try {
    region.require_meets_surface(mesh, has_inside ? 0.5 * options.inside_edge_length : 0.0);
  } catch (const Error& e) {
    std::string what = e.what();
    if (what.rfind("operating region: ", 0) == 0) what.erase(0, 18);
    fail(key, what);
  }

  scene.input_elements = mesh.num_elements();
  if (has_inside) {
    // Estimated element count of the graded mesh: each input face's area over the area of an
    // equilateral triangle of the target size at its centroid.
    // Faces larger than the inside length are sampled on a k x k sub-grid (k <= 16), so a small
    // region inside one coarse face still counts at its own size.
    double estimate = 0.0;
    for (Index e = 0; e < mesh.num_elements() && estimate <= kMaxGradedElements; ++e) {
      const auto c = mesh.corners(e);
      const int k = static_cast<int>(std::min(16.0, std::ceil(2.0 * mesh.diameter(e) / options.inside_edge_length)));
      const double sub_area = mesh.area(e) / (k * k);
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k - i; ++j)
          for (int up = 0; up < (j < k - i - 1 ? 2 : 1); ++up) {
            // Centroid of sub-triangle (i, j) pointing up or down in barycentric grid coordinates.
            const double a = (up == 0 ? i + 1.0 / 3.0 : i + 2.0 / 3.0) / k;
            const double b = (up == 0 ? j + 1.0 / 3.0 : j + 2.0 / 3.0) / k;
            const Vec3 x = c[0] + a * (c[1] - c[0]) + b * (c[2] - c[0]);
            const double h = graded_target_size(region, options, x);
            estimate += sub_area / (0.433 * h * h);
          }
    }
    if (estimate > kMaxGradedElements)
      fail(child(key, "inside_edge_length"),
           "would give about " + std::to_string(static_cast<long long>(estimate)) + " elements (limit " +
               std::to_string(static_cast<long long>(kMaxGradedElements)) +
               "): the dense BEM system would not fit in memory; use longer edges");
    if (!graded_remesher_available()) {
      scene.warnings.push_back(key + ": this build of bemsurg has no remesher (BEMSURG_WITH_REMESHER=OFF): the mesh is "
                                     "used as generated or read, not graded");
    } else {
      try {
        GradedRemeshResult g = graded_remesh(mesh, region, options);
        mesh = std::move(g.mesh);
        scene.graded = true;
        scene.remesh_seconds = g.seconds;
        scene.mesh_source += ", graded remesh (inside " + json(options.inside_edge_length).dump() + " m, outside " +
                             json(options.outside_edge_length).dump() + " m)";
      } catch (const Error& e) {
        fail(key, std::string("remeshing failed: ") + e.what());
      }
    }
  }
  return region;
}

Scene build_scene(const json& root, const std::string& directory, const std::string& name) {
  if (!root.is_object()) throw SceneError(name + ": expected a JSON object at the top level, got " + describe_type(root));
  Scene scene;
  scene.path = name;
  scene.directory = directory;
  note_unknown_keys(root, "",
                    {"mesh", "material", "gravity", "boundary_conditions", "interior_points", "solver", "quadrature",
                     "operating_region"},
                    scene.warnings);

  ElastostaticProblem& problem = scene.problem;
  if (const json* g = optional(root, "gravity")) problem.gravity = as_vec3(*g, "gravity");
  problem.material = load_material(required(root, "material", ""), !problem.gravity.isZero(0.0), scene.warnings);
  problem.mesh = load_mesh(required(root, "mesh", ""), directory, scene.mesh_source, scene.warnings);
  scene.input_elements = problem.mesh.num_elements();
  // The operating region comes before the boundary conditions: it may remesh, and the rules then
  // select on the mesh that is solved.
  if (const json* r = optional(root, "operating_region")) {
    scene.operating_region = load_operating_region(*r, problem.mesh, scene);
    scene.has_operating_region = true;
  }
  scene.mesh_quality = measure_mesh_quality(problem.mesh);
  problem.boundary_conditions =
      load_boundary_conditions(required(root, "boundary_conditions", ""), directory, problem.mesh, scene.warnings);
  if (scene.has_operating_region) {
    // A remeshed element set is matched by distance: the new elements covering the old ones have
    // their centroids on (within a tenth of an element of) the old triangles.
    // Otherwise a slack of rounding only (a centroid's distance to its own triangle is ~1e-18, not 0).
    const double slack = scene.graded && scene.operating_region.kind() == OperatingRegion::Kind::Elements
                             ? 0.1 * scene.mesh_quality.min_size
                             : 1e-9 * (problem.mesh.bounding_box().col(1) - problem.mesh.bounding_box().col(0)).norm();
    std::size_t held = 0;
    for (Index e : scene.operating_region.elements_of(problem.mesh, slack)) {
      if (problem.boundary_conditions.is_free(e))
        scene.operating_elements.push_back(e);
      else
        ++held;
    }
    if (scene.operating_elements.empty())
      fail("operating_region", "holds no free element of the mesh (" + std::to_string(held) +
                                   " elements inside are displacement-prescribed, and a Green's table needs free ones)");
  }
  if (const json* q = optional(root, "quadrature")) problem.quadrature = load_quadrature(*q, scene.warnings);
  if (const json* s = optional(root, "solver")) scene.solver = load_solver(*s, scene.warnings);
  if (const json* ip = optional(root, "interior_points")) {
    scene.interior_points = load_interior_points(*ip, directory, problem.mesh, problem.quadrature, scene.warnings);
    scene.has_interior_points = true;
  }
  return scene;
}

json parse_json(const std::string& text, const std::string& name) {
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    // nlohmann's message already holds the line and column of the problem.
    throw SceneError(name + ": not valid JSON: " + e.what());
  }
}

}  // namespace

Scene load_scene_from_string(const std::string& json_text, const std::string& directory, const std::string& name) {
  return build_scene(parse_json(json_text, name), directory, name);
}

Scene load_scene(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw SceneError(path + ": cannot read the scene: it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot read the scene: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  const std::string directory = fs::path(path).parent_path().string();
  return build_scene(parse_json(text.str(), path), directory.empty() ? "." : directory, path);
}

}  // namespace bemsurg
