// The "operating_region" section of a scene (docs/scene-format.md#operating_region,
// docs/graded.md): where tools act, as a sphere, a box or a list of elements of the mesh as
// generated or read, and optionally the edge lengths of a graded remesh around it. Reading only:
// operating_region_remesh.cpp performs the remesh the request asks for.
#include "bemsurg/error.hpp"
#include "scene_sections.hpp"

namespace bemsurg::io {

// Shared with mesh.refine (scene_mesh.cpp), which selects the elements to refine by the same shapes.
OperatingRegion read_region_shape(const JsonReader& r, const TriangleMesh& mesh) {
  if (const std::optional<JsonReader> s = r.optional("sphere")) {
    s->object().warn_unknown_keys({"center", "radius"});
    const Vec3 c = s->required("center").vec3();
    const double radius = s->required("radius").positive();
    return OperatingRegion::sphere(c, radius);
  }
  if (const std::optional<JsonReader> b = r.optional("box")) {
    b->object().warn_unknown_keys({"min", "max"});
    const Vec3 lo = b->required("min").vec3();
    const JsonReader max = b->required("max");
    const Vec3 hi = max.vec3();
    if (!(lo.array() < hi.array()).all()) max.fail("must exceed " + b->path_of("min") + " in every component");
    return OperatingRegion::box(lo, hi);
  }
  const JsonReader e = r.required("elements");
  if (!e.is_array() || e.empty()) e.fail("expected a non-empty array of element indices");
  std::vector<Index> ids;
  for (std::size_t i = 0; i < e.size(); ++i) {
    const long long id = e[i].integer();
    if (id < 0 || id >= mesh.num_elements())
      e[i].fail("element " + std::to_string(id) + " out of range (mesh has " + std::to_string(mesh.num_elements()) + " elements)");
    ids.push_back(static_cast<Index>(id));
  }
  return OperatingRegion::element_set(mesh, ids);
}

namespace {

/// The graded remesh's options; `graded` false when no edge lengths are given.
GradedRemeshOptions read_remesh_options(const JsonReader& r, const TriangleMesh& mesh, bool& graded) {
  const bool has_inside = r.has("inside_edge_length"), has_outside = r.has("outside_edge_length");
  if (has_inside != has_outside)
    r.fail_at(r.path_of(has_inside ? "outside_edge_length" : "inside_edge_length"),
              "missing (inside_edge_length and outside_edge_length come together: they ask for a graded remesh)");
  graded = has_inside;
  GradedRemeshOptions options;
  if (!graded) {
    for (const char* k : {"growth", "feature_angle", "supported", "keep_flat_faces", "flat_rim_area_loss"})
      if (const std::optional<JsonReader> v = r.optional(k)) v->warn("ignored without inside_edge_length and outside_edge_length");
    return options;
  }
  const JsonReader inside = r.required("inside_edge_length"), outside = r.required("outside_edge_length");
  options.inside_edge_length = inside.positive();
  options.outside_edge_length = outside.positive();
  if (options.inside_edge_length > options.outside_edge_length)
    inside.fail("is larger than " + outside.path() + " (" + json_number_text(options.inside_edge_length) + " > " +
                json_number_text(options.outside_edge_length) + "): the operating region must be the finer part");
  if (const std::optional<JsonReader> g = r.optional("growth")) {
    options.growth = g->number();
    if (!(options.growth > 1.0 && options.growth <= 2.0)) g->fail("must lie in (1, 2], got " + g->dump());
  }
  if (const std::optional<JsonReader> a = r.optional("feature_angle")) {
    options.feature_angle_degrees = a->number();
    if (!(options.feature_angle_degrees > 0.0 && options.feature_angle_degrees < 180.0))
      a->fail("must lie in (0, 180) degrees, got " + a->dump());
  }
  // Flat faces kept up to their rims (docs/graded.md, "What a remesh keeps"; on by default).
  if (const std::optional<JsonReader> k = r.optional("keep_flat_faces")) options.keep_planar_regions = k->boolean();
  if (const std::optional<JsonReader> l = r.optional("flat_rim_area_loss")) {
    options.planar_rim_area_loss = l->number();
    if (!(options.planar_rim_area_loss >= 0.0 && options.planar_rim_area_loss < 0.1)) l->fail("must lie in [0, 0.1), got " + l->dump());
    if (!options.keep_planar_regions) l->warn("ignored without \"keep_flat_faces\": true");
  }
  // The safe-grading rule (docs/graded.md#safe-gradings): the held part meshed as finely as the region.
  if (const std::optional<JsonReader> s = r.optional("supported")) {
    s->object().warn_unknown_keys({"sphere", "box", "elements"});
    const int shapes = int(s->has("sphere")) + int(s->has("box")) + int(s->has("elements"));
    if (shapes != 1) s->fail("expected exactly one of \"sphere\", \"box\" or \"elements\", got " + std::to_string(shapes));
    options.supported_regions.push_back(read_region_shape(*s, mesh));
  }
  return options;
}

}  // namespace

OperatingRegionRequest parse_operating_region(const JsonReader& r, const TriangleMesh& mesh) {
  r.object().warn_unknown_keys({"sphere", "box", "elements", "inside_edge_length", "outside_edge_length", "growth", "feature_angle",
                                "supported", "keep_flat_faces", "flat_rim_area_loss"});
  const int shapes = int(r.has("sphere")) + int(r.has("box")) + int(r.has("elements"));
  if (shapes != 1) r.fail("expected exactly one of \"sphere\", \"box\" or \"elements\", got " + std::to_string(shapes));
  OperatingRegionRequest request;
  request.region = read_region_shape(r, mesh);
  request.options = read_remesh_options(r, mesh, request.graded);
  try {
    request.region.require_meets_surface(mesh, request.graded ? 0.5 * request.options.inside_edge_length : 0.0);
  } catch (const Error& e) {
    std::string what = e.what();
    if (what.rfind("operating region: ", 0) == 0) what.erase(0, 18);
    r.fail(what);
  }
  return request;
}

}  // namespace bemsurg::io
