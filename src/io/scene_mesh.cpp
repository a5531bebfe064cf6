// The "mesh" section of a scene (docs/scene-format.md#mesh): a mesh file or one of the generators,
// refused before generating when the dense solve could not hold it, then validated (closed,
// manifold, oriented, non-degenerate). The checks of the solved mesh (size, thin parts) run in
// scene.cpp, after the operating region's remesh.
#include <cmath>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/brain_model.hpp"
#include "bemsurg/mesh/liver_model.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/red_green_refinement.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/number_text.hpp"
#include "scene_sections.hpp"

namespace bemsurg::io {

// scene_operating_region.cpp: the sphere / box / elements shapes of operating_region.
OperatingRegion read_region_shape(const JsonReader& r, const TriangleMesh& mesh);

namespace {

// Generators beyond these sizes give dense systems no machine holds; refusing them here turns an
// out-of-memory crash into a message.
constexpr int kMaxSubdivisions = 7;
constexpr int kMaxDivisions = 1000;

std::vector<double> increasing_numbers(const JsonReader& v) {
  if (!v.is_array() || v.size() < 2) v.fail("expected an array of at least 2 increasing numbers");
  std::vector<double> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    out.push_back(v[i].number());
    if (i > 0 && !(out[i] > out[i - 1])) v[i].fail("coordinates must be strictly increasing");
  }
  return out;
}

// A generated mesh is sized from its parameters before it is generated (docs/design.md §10): one
// that the dense solve could not hold (H and G alone) is refused with the estimate, instead of
// generating and validating millions of elements first.
void require_generated_size(const std::string& key, const std::string& what, double elements) {
  const double need = estimate_elastostatic_bytes(static_cast<Index>(elements)), limit = default_memory_limit_bytes();
  if (need <= limit) return;
  throw ResourceError(key + ": " + what + " has " + std::to_string(static_cast<long long>(elements)) +
                      " elements; the dense solve needs about " + format_gib(need) + ", more than the limit of " + format_gib(limit) +
                      " (80 % of physical memory); refused before generating it");
}

/// The mesh of generator `kind`, its parameters checked against the limits above; nothing for an
/// unknown generator.
std::optional<TriangleMesh> run_generator(const JsonReader& m, const std::string& kind, std::string& source) {
  const auto center = [&] {
    const std::optional<JsonReader> c = m.optional("center");
    return c ? c->vec3() : Vec3(Vec3::Zero());
  };
  const auto subdivisions = [&](const char* name, int fallback) {
    const std::optional<JsonReader> s = m.optional(name);
    return s ? s->integer_in(0, kMaxSubdivisions) : fallback;
  };
  if (kind == "box") {
    m.warn_unknown_keys({"refine", "generator", "min", "max", "divisions"});
    const Vec3 lo = m.required("min").vec3();
    const JsonReader max = m.required("max");
    const Vec3 hi = max.vec3();
    for (int c = 0; c < 3; ++c)
      if (!(lo(c) < hi(c))) max.fail("must exceed mesh.min in every component");
    const JsonReader d = m.required("divisions");
    if (!d.is_array() || d.size() != 3) d.fail("expected an array of 3 integers [nx, ny, nz]");
    int n[3];
    for (std::size_t i = 0; i < 3; ++i) n[i] = d[i].integer_in(1, kMaxDivisions);
    source = "box generator, " + std::to_string(n[0]) + "x" + std::to_string(n[1]) + "x" + std::to_string(n[2]);
    require_generated_size(d.path(), "a " + source.substr(15) + " box",
                           4.0 * (double(n[0]) * n[1] + double(n[1]) * n[2] + double(n[0]) * n[2]));
    return box_mesh(lo, hi, n[0], n[1], n[2]);
  }
  if (kind == "box_grid") {
    m.warn_unknown_keys({"refine", "generator", "x", "y", "z"});
    const auto xs = increasing_numbers(m.required("x"));
    const auto ys = increasing_numbers(m.required("y"));
    const auto zs = increasing_numbers(m.required("z"));
    source = "box_grid generator";
    const double gx = double(xs.size() - 1), gy = double(ys.size() - 1), gz = double(zs.size() - 1);
    require_generated_size(m.path(), "the box_grid", 4.0 * (gx * gy + gy * gz + gx * gz));
    return box_mesh_from_grid(xs, ys, zs);
  }
  if (kind == "icosphere") {
    m.warn_unknown_keys({"refine", "generator", "center", "radius", "subdivisions"});
    const double r = m.required("radius").positive();
    const int s = subdivisions("subdivisions", 2);
    source = "icosphere generator, subdivisions " + std::to_string(s);
    require_generated_size(m.path_of("subdivisions"), "the icosphere", 20.0 * std::pow(4.0, s));
    return icosphere_mesh(center(), r, s);
  }
  if (kind == "ellipsoid") {
    m.warn_unknown_keys({"refine", "generator", "center", "semi_axes", "subdivisions"});
    const JsonReader semi_axes = m.required("semi_axes");
    const Vec3 axes = semi_axes.vec3();
    for (std::size_t c = 0; c < 3; ++c) semi_axes[c].positive();
    const int s = subdivisions("subdivisions", 2);
    source = "ellipsoid generator, subdivisions " + std::to_string(s);
    require_generated_size(m.path_of("subdivisions"), "the ellipsoid", 20.0 * std::pow(4.0, s));
    return ellipsoid_mesh(center(), axes, s);
  }
  if (kind == "hollow_sphere") {
    m.warn_unknown_keys(
        {"refine", "generator", "center", "inner_radius", "outer_radius", "subdivisions", "subdivisions_inner", "subdivisions_outer"});
    const double a = m.required("inner_radius").positive();
    const JsonReader outer = m.required("outer_radius");
    const double b = outer.positive();
    if (!(a < b)) outer.fail("must exceed mesh.inner_radius");
    const int s = subdivisions("subdivisions", 2);
    const int si = subdivisions("subdivisions_inner", s);
    const int so = subdivisions("subdivisions_outer", s);
    source = "hollow_sphere generator, subdivisions " + std::to_string(si) + "/" + std::to_string(so);
    require_generated_size(m.path_of("subdivisions"), "the hollow sphere", 20.0 * (std::pow(4.0, si) + std::pow(4.0, so)));
    return hollow_sphere_mesh(center(), a, b, si, so);
  }
  if (kind == "brain") {
    m.warn_unknown_keys(
        {"refine", "generator", "size", "subdivisions", "fissure_depth", "fissure_half_width", "fold_amplitude", "fold_wavelength"});
    BrainModelOptions o;
    if (const std::optional<JsonReader> size = m.optional("size")) {
      o.size = size->vec3();
      for (std::size_t c = 0; c < 3; ++c) (*size)[c].positive();
    }
    o.subdivisions = subdivisions("subdivisions", o.subdivisions);
    const auto number = [&](const char* name, double& value) {
      if (const std::optional<JsonReader> v = m.optional(name)) value = v->number();
    };
    number("fissure_depth", o.fissure_depth);
    number("fissure_half_width", o.fissure_half_width);
    number("fold_amplitude", o.fold_amplitude);
    number("fold_wavelength", o.fold_wavelength);
    source = "brain generator, subdivisions " + std::to_string(o.subdivisions);
    return brain_mesh(o);
  }
  if (kind == "liver") {
    m.warn_unknown_keys({"refine", "generator", "size", "subdivisions"});
    LiverModelOptions o;
    if (const std::optional<JsonReader> size = m.optional("size")) {
      o.size = size->vec3();
      for (std::size_t c = 0; c < 3; ++c) (*size)[c].positive();
    }
    o.subdivisions = subdivisions("subdivisions", o.subdivisions);
    source = "liver generator, subdivisions " + std::to_string(o.subdivisions);
    return liver_mesh(o);
  }
  return std::nullopt;
}

TriangleMesh generate_mesh(const JsonReader& m, std::string& source) {
  const JsonReader generator = m.required("generator");
  const std::string kind = generator.string();
  std::optional<TriangleMesh> mesh;
  try {
    mesh = run_generator(m, kind, source);
  } catch (const SceneError&) { throw; } catch (const ResourceError&) {
    throw;
  } catch (const Error& e) { m.fail(std::string("generator '") + kind + "' failed: " + e.what()); }
  if (!mesh)
    generator.fail("unknown generator '" + kind + "' (expected box, box_grid, icosphere, ellipsoid, hollow_sphere, brain or liver)");
  return std::move(*mesh);
}

/// "refine" (docs/scene-format.md#local-refinement-refine, docs/graded.md): the elements whose
/// centroid lies in the region (the operating_region shapes) are refined red-green `levels` times.
void refine_in_region(const JsonReader& m, TriangleMesh& mesh, std::string& source) {
  const JsonReader r = m.required("refine");
  r.object().warn_unknown_keys({"sphere", "box", "elements", "levels"});
  const int shapes = int(r.has("sphere")) + int(r.has("box")) + int(r.has("elements"));
  if (shapes != 1) r.fail("expected exactly one of \"sphere\", \"box\" or \"elements\", got " + std::to_string(shapes));
  const OperatingRegion region = read_region_shape(r, mesh);
  const std::optional<JsonReader> l = r.optional("levels");
  const int levels = l ? l->integer_in(1, 6) : 1;
  // A centroid lies ~1e-18 from its own triangle, not 0: a rounding slack selects listed elements.
  const double slack = 1e-9 * (mesh.bounding_box().col(1) - mesh.bounding_box().col(0)).norm();
  const std::vector<Index> marked = region.elements_of(mesh, slack);
  if (marked.empty()) r.fail(region.describe() + " holds no element centroid of the mesh: nothing to refine");
  // Each level multiplies the marked elements by four; the closure adds at most a band around them.
  // No element ends in more than 4^levels pieces, so that bounds the whole (refining every element
  // of a 2,358-element liver once was refused as 30,654 elements; it makes 9,432).
  const double E = double(mesh.num_elements()), grow = std::pow(4.0, levels);
  require_generated_size(r.path(), "the refined mesh", std::min(E * grow, E + 3.0 * double(marked.size()) * grow));
  mesh = refine_red_green(mesh, marked, levels).mesh;
  source += ", red-green refined (" + std::to_string(marked.size()) + " elements, " + std::to_string(levels) + " level" +
            (levels > 1 ? "s" : "") + ")";
}

}  // namespace

TriangleMesh load_mesh(const JsonReader& m, const std::string& directory, std::string& source, double graded_inside_edge,
                       Index prepare_default) {
  m.object();
  const bool has_file = m.has("file");
  const bool has_generator = m.has("generator");
  if (has_file == has_generator)
    m.fail(has_file ? "give either \"file\" or \"generator\", not both" : "expected a \"file\" or a \"generator\" key");

  TriangleMesh mesh;
  if (has_file) {
    m.warn_unknown_keys({"file", "scale", "translate", "refine", "prepare"});
    const JsonReader file = m.required("file");
    const std::string path = resolve_existing(directory, file);
    try {
      mesh = read_mesh(path);
    } catch (const Error& e) { file.fail("cannot load '" + path + "': " + e.what()); }
    source = path;
    // Optional affine map, for meshes drawn in millimetres or away from the origin: x' = s x + t.
    const std::optional<JsonReader> scale_key = m.optional("scale"), translate_key = m.optional("translate");
    const double scale = scale_key ? scale_key->positive() : 1.0;
    // A raw segmentation surface: repaired and remeshed first, in metres, then mapped as above
    // (scene_prepare.cpp); the operating region's lengths are in the mapped coordinates.
    if (const std::optional<JsonReader> p = m.optional("prepare"))
      mesh = prepare_in_scene(*p, mesh, graded_inside_edge / scale, scale_key.has_value(), prepare_default, source);
    const Vec3 shift = translate_key ? translate_key->vec3() : Vec3(Vec3::Zero());
    if (scale != 1.0 || !shift.isZero(0.0)) {
      RowMatrixX3d v = mesh.vertices() * scale;
      v.rowwise() += shift.transpose();
      mesh = TriangleMesh(v, mesh.faces());
    }
  } else {
    if (m.has("prepare")) m.required("prepare").fail("\"prepare\" repairs a mesh file; a generator's mesh needs no repair");
    mesh = generate_mesh(m, source);
  }

  const JsonReader at = has_file ? m.required("file") : m;  // where problems of the mesh itself are reported
  try {
    require_valid_mesh(mesh);
  } catch (const Error& e) {
    // The validator's message may already start with "invalid mesh: "; say it once.
    std::string what = e.what();
    if (what.rfind("invalid mesh: ", 0) == 0) what.erase(0, 14);
    at.fail("invalid mesh (" + source + "): " + what);
  }
  if (m.has("refine")) refine_in_region(m, mesh, source);
  // The thin-part warning runs on the mesh actually solved, after any graded remesh (scene.cpp).
  return mesh;
}

}  // namespace bemsurg::io
