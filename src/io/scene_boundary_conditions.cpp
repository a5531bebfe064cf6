// The "boundary_conditions" section of a scene (docs/scene-format.md#boundary_conditions,
// docs/design.md §5): per element and component u or t prescribed; pressure p means t = -p n.
// Rules select elements geometrically and apply in order; the per-element CSV file comes last.
#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>

#include "bemsurg/io/element_selector.hpp"
#include "bemsurg/mesh/space_region.hpp"
#include "csv_reader.hpp"
#include "scene_rule.hpp"
#include "scene_sections.hpp"

namespace bemsurg::io {
namespace {

BcKind parse_kind(const std::string& text, const std::string& where) {
  if (text == "u" || text == "U") return BcKind::Displacement;
  if (text == "t" || text == "T") return BcKind::Traction;
  fail_at(where, "unknown kind '" + text + "' (expected u for displacement or t for traction)");
}

std::string out_of_range(long long element, const TriangleMesh& mesh) {
  return "element " + std::to_string(element) + " out of range (mesh has " + std::to_string(mesh.num_elements()) + " elements)";
}

/// One selector of a "select" object ("plane", "box", ...); nothing for a key that is not one
/// (already warned about).
std::optional<ElementSelector> read_selector(const JsonReader& v, const std::string& name, const TriangleMesh& mesh) {
  if (name == "plane") {
    v.object().warn_unknown_keys({"point", "normal", "tolerance"});
    const Vec3 point = v.required("point").vec3();
    const JsonReader normal_key = v.required("normal");
    const Vec3 normal = normal_key.vec3();
    if (normal.norm() == 0.0) normal_key.fail("must be a non-zero vector");
    const double diagonal = (mesh.bounding_box().col(1) - mesh.bounding_box().col(0)).norm();
    double tol = 1e-6 * diagonal;
    if (const std::optional<JsonReader> t = v.optional("tolerance")) {
      tol = t->number();
      if (tol < 0.0) t->fail("must not be negative");
    }
    return ElementSelector::plane(point, normal, tol);
  }
  if (name == "box") {
    v.object().warn_unknown_keys({"min", "max"});
    const Vec3 lo = v.required("min").vec3();
    const JsonReader max = v.required("max");
    const Vec3 hi = max.vec3();
    if ((lo.array() > hi.array()).any()) max.fail("must not be below min in any component");
    return ElementSelector::box(lo, hi);
  }
  if (name == "sphere") {
    v.object().warn_unknown_keys({"center", "radius"});
    const Vec3 center = v.required("center").vec3();
    return ElementSelector::sphere(center, v.required("radius").positive());
  }
  if (name == "normal") {
    v.object().warn_unknown_keys({"direction", "min_cos"});
    const JsonReader direction = v.required("direction");
    const Vec3 dir = direction.vec3();
    if (dir.norm() == 0.0) direction.fail("must be a non-zero vector");
    double min_cos = 0.9;
    if (const std::optional<JsonReader> c = v.optional("min_cos")) {
      min_cos = c->number();
      if (min_cos < -1.0 || min_cos > 1.0) c->fail("must lie in [-1, 1], got " + c->dump());
    }
    return ElementSelector::normal_direction(dir, min_cos);
  }
  if (name == "shell") return ElementSelector::shell_index(v.integer_in(0, std::numeric_limits<int>::max()));
  if (name == "elements") {
    if (!v.is_array()) v.fail("expected an array of element indices, got " + v.type_name());
    std::vector<Index> list;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const long long e = v[i].integer();
      if (e < 0 || e >= mesh.num_elements()) v[i].fail(out_of_range(e, mesh));
      list.push_back(static_cast<Index>(e));
    }
    return ElementSelector::element_list(std::move(list));
  }
  if (name == "all") {
    if (!v.boolean()) v.fail("only true is meaningful here");
    return ElementSelector::all();
  }
  return std::nullopt;
}

/// The region of space a selector describes, for the three that describe one.
std::optional<SpaceRegion> region_of(const ElementSelector& s) {
  switch (s.kind) {
    case ElementSelector::Kind::Plane: return SpaceRegion::slab(s.point, s.direction, s.tolerance);
    case ElementSelector::Kind::Box: return SpaceRegion::box(s.box_min, s.box_max);
    case ElementSelector::Kind::Sphere: return SpaceRegion::ball(s.point, s.tolerance);
    default: return std::nullopt;
  }
}

std::vector<Index> intersect(const std::vector<Index>& a, const std::vector<Index>& b) {
  std::vector<Index> both;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(both));
  return both;
}

/// What a "select" object picks: the elements (centroids and normals, element_selector.hpp), the
/// region of space when every selector describes one (for "region_area"), and, apart, the sphere
/// and box selectors' region (what "conform" splits along) and the other selectors' elements.
struct Selection {
  std::vector<Index> elements;
  std::optional<SpaceRegion> region;
  std::optional<SpaceRegion> shape;  // the sphere and box selectors, intersected
  std::optional<std::vector<Index>> others;
  int spheres = 0;
};

Selection evaluate_select(const JsonReader& sel, const TriangleMesh& mesh) {
  sel.object();
  if (sel.empty()) sel.fail("expected at least one of plane, box, sphere, normal, shell, elements, all");
  sel.warn_unknown_keys({"plane", "box", "sphere", "normal", "shell", "elements", "all"});
  Selection out;
  bool first = true, all_regions = true;
  SpaceRegion region;
  // Several selectors in one "select" must all hold (intersection), e.g. plane and normal.
  for (const std::string& name : sel.keys()) {
    const std::optional<ElementSelector> s = read_selector(sel.required(name), name, mesh);
    if (!s) continue;
    std::vector<Index> picked;
    try {
      picked = select_elements(mesh, *s);
    } catch (const SceneError& e) {
      sel.fail(e.what());  // e.what() starts with the selector name: "shell: index 3 out of range"
    }
    out.elements = first ? picked : intersect(out.elements, picked);
    first = false;
    const std::optional<SpaceRegion> r = region_of(*s);
    out.spheres += s->kind == ElementSelector::Kind::Sphere;
    all_regions = all_regions && r.has_value();
    if (r) region = region.intersected(*r);
    if (s->kind == ElementSelector::Kind::Sphere || s->kind == ElementSelector::Kind::Box)
      out.shape = out.shape ? out.shape->intersected(*r) : *r;
    else
      out.others = out.others ? intersect(*out.others, picked) : picked;
  }
  if (first) sel.fail("expected at least one of plane, box, sphere, normal, shell, elements, all");
  if (all_regions && out.spheres <= 1) out.region = region;
  return out;
}

std::vector<char> flags_of(const std::vector<Index>& elements, Index n) {
  std::vector<char> f(static_cast<std::size_t>(n), 0);
  for (Index e : elements) f[static_cast<std::size_t>(e)] = 1;
  return f;
}

Rule read_rule(const JsonReader& rule, const TriangleMesh& mesh, const TriangleMesh& as_read) {
  rule.object().warn_unknown_keys({"select", "displacement", "traction", "pressure", "kind", "value", "conform", "refine_rim"});
  Rule r;
  r.key = rule.path();
  const JsonReader select = rule.required("select");
  const Selection s = evaluate_select(select, mesh);
  r.selected = flags_of(s.elements, mesh.num_elements());
  r.region = s.region;
  r.can_conform = s.shape.has_value();
  if (s.region) r.region_area = area_inside(as_read, *s.region);
  if (const std::optional<JsonReader> c = rule.optional("conform"); c && c->boolean()) {
    if (!s.shape)
      c->fail(
          "needs a sphere or box selector in \"select\" to split the elements along (the rim of a flat face is kept by the "
          "remesher instead; docs/graded.md)");
    if (s.spheres > 1) c->fail("conforms to one sphere at a time; give one sphere selector per rule");
    r.conform = s.shape;
    r.others = s.others ? flags_of(*s.others, mesh.num_elements()) : std::vector<char>(std::size_t(mesh.num_elements()), 1);
  } else if (s.elements.empty()) {
    select.fail("selects no elements (check the coordinates and the tolerance against the mesh's bounding box)");
  }
  if (const std::optional<JsonReader> k = rule.optional("refine_rim")) r.refine_rim = k->integer_in(0, 4);

  int given = 0;
  for (const char* k : {"displacement", "traction", "pressure", "kind"}) given += rule.has(k) ? 1 : 0;
  if (given != 1)
    rule.fail(given == 0 ? "expected one of displacement, traction, pressure, or kind with value"
                         : "give only one of displacement, traction, pressure, or kind with value");
  if (rule.has("value") && !rule.has("kind")) rule.required("value").fail("needs \"kind\" beside it");
  if (const std::optional<JsonReader> v = rule.optional("displacement")) {
    r.action = Rule::Action::Displacement;
    r.value = v->vec3();
  } else if (const std::optional<JsonReader> v = rule.optional("traction")) {
    r.action = Rule::Action::Traction;
    r.value = v->vec3();
  } else if (const std::optional<JsonReader> v = rule.optional("pressure")) {
    r.action = Rule::Action::Pressure;
    r.value = Vec3(v->number(), 0.0, 0.0);
  } else {
    r.action = Rule::Action::Kinds;
    const JsonReader kinds = rule.required("kind");
    if (kinds.is_string()) {
      r.kinds.fill(parse_kind(kinds.string(), kinds.path()));
    } else if (kinds.is_array() && kinds.size() == 3) {
      for (std::size_t c = 0; c < 3; ++c) r.kinds[c] = parse_kind(kinds[c].string(), kinds[c].path());
    } else {
      kinds.fail("expected \"u\", \"t\" or an array of 3 of them, got " + kinds.type_name());
    }
    r.value = rule.required("value").vec3();
  }
  return r;
}

void apply_rule(const Rule& r, Index e, const TriangleMesh& mesh, BoundaryConditions& bc) {
  switch (r.action) {
    case Rule::Action::Displacement: bc.prescribe_displacement(e, r.value); break;
    case Rule::Action::Traction: bc.prescribe_traction(e, r.value); break;
    case Rule::Action::Pressure: bc.prescribe_pressure(e, r.value.x(), mesh.normal(e)); break;
    case Rule::Action::Kinds:
      for (int c = 0; c < 3; ++c) bc.prescribe_component(e, c, r.kinds[std::size_t(c)], r.value(c));
      break;
  }
}

void apply_element_rows(const std::vector<CsvRow>& rows, const std::string& key, const TriangleMesh& mesh, BoundaryConditions& bc,
                        std::vector<char>& listed) {
  static const char* kind_names[3] = {"kind_x", "kind_y", "kind_z"};
  static const char* value_names[3] = {"value_x", "value_y", "value_z"};
  for (const CsvRow& row : rows) {
    const std::string where = csv_row_key(key, row);
    const long long e = parse_csv_integer(row.fields[0], where + ": element", "an integer element index");
    if (e < 0 || e >= mesh.num_elements()) fail_at(where, out_of_range(e, mesh));
    listed[static_cast<std::size_t>(e)] = 1;
    for (int c = 0; c < 3; ++c) {
      const BcKind kind = parse_kind(row.fields[static_cast<std::size_t>(1 + c)], where + ": " + kind_names[c]);
      const double value = parse_csv_number(row.fields[static_cast<std::size_t>(4 + c)], where + ": " + value_names[c]);
      bc.prescribe_component(static_cast<Index>(e), c, kind, value);
    }
  }
}

/// The corner and node variants (element,corner|node,kind_x..,value_x..; docs/scene-format.md):
/// values at the corners, or at the linear elements' collocation nodes (docs/elements.md), of the
/// listed elements, every one given at all three, a component's kind the same at the three; the
/// element's own value becomes the mean (the value at the centroid, for corners and nodes alike).
void apply_corner_rows(const std::vector<CsvRow>& rows, const std::string& key, const TriangleMesh& mesh, BoundaryConditions& bc,
                       RowMatrixX3d& corners, std::vector<char>& listed, const std::string& point) {
  static const char* kind_names[3] = {"kind_x", "kind_y", "kind_z"};
  static const char* value_names[3] = {"value_x", "value_y", "value_z"};
  const std::size_t E = static_cast<std::size_t>(mesh.num_elements());
  std::vector<std::size_t> line(3 * E, 0);  // the row that gave (element, corner); 0 = none
  std::vector<BcKind> kinds(9 * E);
  for (const CsvRow& row : rows) {
    const std::string where = csv_row_key(key, row);
    const long long e = parse_csv_integer(row.fields[0], where + ": element", "an integer element index");
    if (e < 0 || e >= mesh.num_elements()) fail_at(where, out_of_range(e, mesh));
    const long long k = parse_csv_integer(row.fields[1], where + ": " + point, "a " + point + " 0, 1 or 2");
    if (k < 0 || k > 2)
      fail_at(where + ": " + point, "expected a " + point + " 0, 1 or 2 (" +
                                        (point == "corner" ? "the face's vertex order" : "the nodes of docs/elements.md") + "), got " +
                                        std::to_string(k));
    const std::size_t slot = 3 * std::size_t(e) + std::size_t(k);
    line[slot] = row.line;
    for (int c = 0; c < 3; ++c) {
      kinds[3 * slot + std::size_t(c)] = parse_kind(row.fields[std::size_t(2 + c)], where + ": " + kind_names[c]);
      corners(Index(slot), c) = parse_csv_number(row.fields[std::size_t(5 + c)], where + ": " + value_names[c]);
    }
  }
  for (std::size_t e = 0; e < E; ++e) {
    const std::size_t* l = &line[3 * e];
    const int given = (l[0] ? 1 : 0) + (l[1] ? 1 : 0) + (l[2] ? 1 : 0);
    if (given == 0) continue;
    listed[e] = 1;
    const std::size_t first = std::max({l[0], l[1], l[2]});
    if (given < 3) {
      std::string missing;
      for (int k = 0; k < 3; ++k)
        if (!l[k]) missing += (missing.empty() ? "" : " and ") + std::to_string(k);
      fail_at(key + " line " + std::to_string(first), "element " + std::to_string(e) + " lacks " + point + " " + missing + ": the " +
                                                          point + " variant needs every listed element at all three " + point + "s");
    }
    for (int c = 0; c < 3; ++c) {
      const BcKind k0 = kinds[9 * e + std::size_t(c)];
      for (int k = 1; k < 3; ++k)
        if (kinds[9 * e + 3 * std::size_t(k) + std::size_t(c)] != k0)
          fail_at(key + " line " + std::to_string(l[k]),
                  std::string("element ") + std::to_string(e) + ", " + kind_names[c] + ": kind '" +
                      (k0 == BcKind::Displacement ? "u" : "t") + "' at " + point + " 0 (line " + std::to_string(l[0]) + ") but '" +
                      (k0 == BcKind::Displacement ? "t" : "u") + "' at " + point + " " + std::to_string(k) +
                      ": a component's kind must be the same at the three " + point + "s of an element");
      const double mean = (corners(Index(3 * e), c) + corners(Index(3 * e + 1), c) + corners(Index(3 * e + 2), c)) / 3.0;
      bc.prescribe_component(Index(e), c, k0, mean);
    }
  }
}

/// The barycentric coordinates of p in the triangle `t` (p in its plane).
Vec3 barycentric(const std::array<Vec3, 3>& t, const Vec3& p) {
  const Vec3 u = t[1] - t[0], v = t[2] - t[0], w = p - t[0];
  const double uu = u.dot(u), uv = u.dot(v), vv = v.dot(v), wu = w.dot(u), wv = w.dot(v), d = uu * vv - uv * uv;
  const double b = (vv * wu - uv * wv) / d, c = (uu * wv - uv * wu) / d;
  return Vec3(1.0 - b - c, b, c);
}

/// The CSV file (docs/scene-format.md#boundary_conditions), whose rows name elements of `given`
/// (the mesh the rules are given on), applied to the solved `mesh`, where `origin` (empty when
/// the two are one) maps every solved element to its element of `given`. Returns whether the
/// values are at the nodes; a split element takes the linear interpolation of its origin's corner
/// values at its own corners (the corners then, never the nodes). `from_file` marks the elements set.
bool apply_bc_file(const std::string& path, const std::string& key, const TriangleMesh& given, const TriangleMesh& mesh,
                   const std::vector<Index>& origin, BoundaryConditions& bc, RowMatrixX3d& corners, std::vector<char>& from_file) {
  std::size_t variant = 0;
  const auto rows =
      read_csv(path,
               {"element,kind_x,kind_y,kind_z,value_x,value_y,value_z", "element,corner,kind_x,kind_y,kind_z,value_x,value_y,value_z",
                "element,node,kind_x,kind_y,kind_z,value_x,value_y,value_z"},
               key, variant);
  const Index E0 = given.num_elements();
  BoundaryConditions on_given(E0);
  RowMatrixX3d given_corners = RowMatrixX3d::Constant(3 * E0, 3, std::numeric_limits<double>::quiet_NaN());
  std::vector<char> listed(static_cast<std::size_t>(E0), 0);
  if (variant == 0)
    apply_element_rows(rows, key, given, on_given, listed);
  else
    apply_corner_rows(rows, key, given, on_given, given_corners, listed, variant == 1 ? "corner" : "node");
  for (Index f = 0; f < mesh.num_elements(); ++f) {
    const Index o = origin.empty() ? f : origin[static_cast<std::size_t>(f)];
    if (!listed[static_cast<std::size_t>(o)]) continue;
    from_file[static_cast<std::size_t>(f)] = 1;
    for (int c = 0; c < 3; ++c) bc.prescribe_component(f, c, on_given.kind(3 * o + c), on_given.value(3 * o + c));
    if (variant == 0) continue;
    Eigen::Matrix3d values = given_corners.middleRows<3>(3 * o);
    if (origin.empty()) {
      corners.middleRows<3>(3 * f) = values;
      continue;
    }
    if (variant == 2) values = linear_nodes_to_corners(values);
    const std::array<Vec3, 3> parent = given.corners(o), own = mesh.corners(f);
    for (int k = 0; k < 3; ++k) corners.row(3 * f + k) = barycentric(parent, own[std::size_t(k)]).transpose() * values;
    for (int c = 0; c < 3; ++c) bc.prescribe_component(f, c, on_given.kind(3 * o + c), corners.middleRows<3>(3 * f).col(c).mean());
  }
  return variant == 2 && origin.empty();
}

}  // namespace

LoadedBoundaryConditions load_boundary_conditions(const JsonReader& b, const std::string& directory, TriangleMesh& mesh,
                                                  const TriangleMesh& as_read, ElementType elements) {
  b.object().warn_unknown_keys({"file", "rules"});
  // Rules select on the mesh given (after any remesh); "conform" and "refine_rim" may then split
  // it, carrying every rule's selection and the file's element numbers over to the pieces.
  const TriangleMesh given = mesh;
  std::vector<Rule> rules;
  std::vector<JsonReader> rule_keys;
  if (const std::optional<JsonReader> list = b.optional("rules")) {
    if (!list->is_array()) list->fail("expected an array of rules, got " + list->type_name());
    for (std::size_t i = 0; i < list->size(); ++i) {
      rule_keys.push_back((*list)[i]);
      rules.push_back(read_rule(rule_keys.back(), mesh, as_read));
    }
  }
  LoadedBoundaryConditions out;
  std::vector<Index> origin(static_cast<std::size_t>(mesh.num_elements()));
  for (std::size_t e = 0; e < origin.size(); ++e) origin[e] = static_cast<Index>(e);
  // Rim refinement first, then the conforming splits (refine_rule_rim says why).
  std::vector<double> grading_size;
  if (std::string change = refine_surface_for_constant_rims(rules, mesh, origin, elements); !change.empty())
    out.mesh_changes.push_back(std::move(change));
  for (std::size_t i = 0; i < rules.size(); ++i)
    if (rules[i].refine_rim > 0)
      if (std::string change = refine_rule_rim(i, rules, mesh, origin, grading_size, elements); !change.empty())
        out.mesh_changes.push_back(std::move(change));
  for (std::size_t i = 0; i < rules.size(); ++i)
    if (rules[i].conform)
      if (std::string change = conform_rule(rule_keys[i], i, rules, mesh, origin, grading_size, out.warnings); !change.empty())
        out.mesh_changes.push_back(std::move(change));
  if (!out.mesh_changes.empty()) {
    out.origin = origin;
    out.grading_size = std::move(grading_size);
  }

  // Everything starts traction-free; rules apply in order (later ones win on shared elements);
  // the file comes last, so a per-element file can refine what the rules set. Every rule and
  // every row sets all three components, so one writer per element says who set it.
  const Index E = mesh.num_elements();
  BoundaryConditions bc(E);
  std::vector<int> writer(static_cast<std::size_t>(E), -1);
  for (std::size_t i = 0; i < rules.size(); ++i)
    for (Index e = 0; e < E; ++e)
      if (rules[i].selected[std::size_t(e)]) {
        apply_rule(rules[i], e, mesh, bc);
        writer[std::size_t(e)] = static_cast<int>(i);
      }
  // Values at the corners: the element's value at all three unless the corner variant gives them.
  RowMatrixX3d corners = RowMatrixX3d::Constant(3 * E, 3, std::numeric_limits<double>::quiet_NaN());
  if (const std::optional<JsonReader> file = b.optional("file")) {
    std::vector<char> from_file(static_cast<std::size_t>(E), 0);
    out.at_nodes = apply_bc_file(resolve_existing(directory, *file), file->path(), given, mesh, out.origin, bc, corners, from_file);
    for (Index e = 0; e < E; ++e)
      if (from_file[std::size_t(e)]) writer[std::size_t(e)] = -2;
  }
  for (Index e = 0; e < E; ++e)
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c)
        if (std::isnan(corners(3 * e + k, c))) corners(3 * e + k, c) = bc.value(3 * e + c);
  out.corner_values = std::move(corners);
  for (std::size_t i = 0; i < rules.size(); ++i) {
    BoundaryRuleArea a;
    a.key = rules[i].key;
    a.displacement = rules[i].holds_displacement();
    for (Index e = 0; e < E; ++e)
      if (writer[std::size_t(e)] == static_cast<int>(i)) a.area += mesh.area(e);
    a.has_region = rules[i].region.has_value();
    a.region_area = rules[i].region_area;
    a.conform = rules[i].conform.has_value();
    a.can_conform = rules[i].can_conform;
    a.refine_rim = rules[i].refine_rim;
    out.rules.push_back(std::move(a));
  }
  out.conditions = std::move(bc);
  return out;
}

}  // namespace bemsurg::io
