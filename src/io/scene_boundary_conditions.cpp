// The "boundary_conditions" section of a scene (docs/scene-format.md#boundary_conditions,
// docs/design.md §5): per element and component u or t prescribed; pressure p means t = -p n.
// Rules select elements geometrically and apply in order; the per-element CSV file comes last.
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include "bemsurg/io/element_selector.hpp"
#include "csv_reader.hpp"
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

std::vector<Index> evaluate_select(const JsonReader& sel, const TriangleMesh& mesh) {
  sel.object();
  if (sel.empty()) sel.fail("expected at least one of plane, box, sphere, normal, shell, elements, all");
  sel.warn_unknown_keys({"plane", "box", "sphere", "normal", "shell", "elements", "all"});
  std::vector<Index> result;
  bool first = true;
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
    if (first) {
      result = std::move(picked);
      first = false;
    } else {
      std::vector<Index> both;
      std::set_intersection(result.begin(), result.end(), picked.begin(), picked.end(), std::back_inserter(both));
      result = std::move(both);
    }
  }
  if (first) sel.fail("expected at least one of plane, box, sphere, normal, shell, elements, all");
  return result;
}

void apply_rule(const JsonReader& rule, const TriangleMesh& mesh, BoundaryConditions& bc) {
  rule.object().warn_unknown_keys({"select", "displacement", "traction", "pressure", "kind", "value"});
  const JsonReader select = rule.required("select");
  const std::vector<Index> elements = evaluate_select(select, mesh);
  if (elements.empty()) select.fail("selects no elements (check the coordinates and the tolerance against the mesh's bounding box)");

  int given = 0;
  for (const char* k : {"displacement", "traction", "pressure", "kind"}) given += rule.has(k) ? 1 : 0;
  if (given != 1)
    rule.fail(given == 0 ? "expected one of displacement, traction, pressure, or kind with value"
                         : "give only one of displacement, traction, pressure, or kind with value");
  if (rule.has("value") && !rule.has("kind")) rule.required("value").fail("needs \"kind\" beside it");

  if (const std::optional<JsonReader> v = rule.optional("displacement")) {
    const Vec3 u = v->vec3();
    for (Index e : elements) bc.prescribe_displacement(e, u);
  } else if (const std::optional<JsonReader> v = rule.optional("traction")) {
    const Vec3 t = v->vec3();
    for (Index e : elements) bc.prescribe_traction(e, t);
  } else if (const std::optional<JsonReader> v = rule.optional("pressure")) {
    const double p = v->number();
    for (Index e : elements) bc.prescribe_pressure(e, p, mesh.normal(e));
  } else {
    const JsonReader kinds = rule.required("kind");
    BcKind k3[3];
    if (kinds.is_string()) {
      k3[0] = k3[1] = k3[2] = parse_kind(kinds.string(), kinds.path());
    } else if (kinds.is_array() && kinds.size() == 3) {
      for (std::size_t c = 0; c < 3; ++c) k3[c] = parse_kind(kinds[c].string(), kinds[c].path());
    } else {
      kinds.fail("expected \"u\", \"t\" or an array of 3 of them, got " + kinds.type_name());
    }
    const Vec3 value = rule.required("value").vec3();
    for (Index e : elements)
      for (int c = 0; c < 3; ++c) bc.prescribe_component(e, c, k3[c], value(c));
  }
}

void apply_element_rows(const std::vector<CsvRow>& rows, const std::string& key, const TriangleMesh& mesh, BoundaryConditions& bc) {
  static const char* kind_names[3] = {"kind_x", "kind_y", "kind_z"};
  static const char* value_names[3] = {"value_x", "value_y", "value_z"};
  for (const CsvRow& row : rows) {
    const std::string where = csv_row_key(key, row);
    const long long e = parse_csv_integer(row.fields[0], where + ": element", "an integer element index");
    if (e < 0 || e >= mesh.num_elements()) fail_at(where, out_of_range(e, mesh));
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
                       RowMatrixX3d& corners, const std::string& point = "corner") {
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

/// Returns whether the values given are at the nodes (the node variant) rather than the corners.
bool apply_bc_file(const std::string& path, const std::string& key, const TriangleMesh& mesh, BoundaryConditions& bc,
                   RowMatrixX3d& corners) {
  std::size_t variant = 0;
  const auto rows =
      read_csv(path,
               {"element,kind_x,kind_y,kind_z,value_x,value_y,value_z", "element,corner,kind_x,kind_y,kind_z,value_x,value_y,value_z",
                "element,node,kind_x,kind_y,kind_z,value_x,value_y,value_z"},
               key, variant);
  if (variant == 0) {
    apply_element_rows(rows, key, mesh, bc);
    return false;
  }
  // The rules' values at every corner (or node) first: an element's constant value is the same at
  // its corners and at its nodes.
  for (Index e = 0; e < mesh.num_elements(); ++e)
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) corners(3 * e + k, c) = bc.value(3 * e + c);
  apply_corner_rows(rows, key, mesh, bc, corners, variant == 1 ? "corner" : "node");
  return variant == 2;
}

}  // namespace

BoundaryConditions load_boundary_conditions(const JsonReader& b, const std::string& directory, const TriangleMesh& mesh,
                                            RowMatrixX3d* corner_values, bool* at_nodes) {
  b.object().warn_unknown_keys({"file", "rules"});
  // Everything starts traction-free; rules apply in order (later ones win on shared elements);
  // the file comes last, so a per-element file can refine what the rules set.
  BoundaryConditions bc(mesh.num_elements());
  if (const std::optional<JsonReader> rules = b.optional("rules")) {
    if (!rules->is_array()) rules->fail("expected an array of rules, got " + rules->type_name());
    for (std::size_t i = 0; i < rules->size(); ++i) apply_rule((*rules)[i], mesh, bc);
  }
  // Values at the corners: the element's value at all three unless the corner variant gives them.
  RowMatrixX3d corners = RowMatrixX3d::Constant(3 * mesh.num_elements(), 3, std::numeric_limits<double>::quiet_NaN());
  bool nodes = false;
  if (const std::optional<JsonReader> file = b.optional("file"))
    nodes = apply_bc_file(resolve_existing(directory, *file), file->path(), mesh, bc, corners);
  if (at_nodes) *at_nodes = nodes;
  if (corner_values) {
    for (Index e = 0; e < mesh.num_elements(); ++e)
      for (int k = 0; k < 3; ++k)
        for (int c = 0; c < 3; ++c)
          if (std::isnan(corners(3 * e + k, c))) corners(3 * e + k, c) = bc.value(3 * e + c);
    *corner_values = std::move(corners);
  }
  return bc;
}

}  // namespace bemsurg::io
