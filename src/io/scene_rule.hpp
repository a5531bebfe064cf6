// A boundary-condition rule as the scene reads it (docs/scene-format.md#boundary_conditions), and
// what its "conform" and "refine_rim" keys do to the mesh (scene_rule_meshing.cpp). Private to the
// library: scene_boundary_conditions.cpp reads the rules and applies them.
#pragma once

#include <algorithm>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "bemsurg/assembly/boundary_conditions.hpp"
#include "bemsurg/assembly/element_types.hpp"
#include "bemsurg/mesh/space_region.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/types.hpp"
#include "json_reader.hpp"

namespace bemsurg::io {

/// One rule as read (docs/scene-format.md#boundary_conditions): what it selects on the mesh the
/// rules are given on (then carried through the rules' splits), and what it prescribes.
struct Rule {
  std::string key;
  std::vector<char> selected;  // on the current mesh
  std::vector<char> others;    // conform: the elements the selectors other than sphere and box pick
  std::optional<SpaceRegion> region;
  std::optional<SpaceRegion> conform;
  bool can_conform = false;  // a sphere or box selector
  int refine_rim = 0;
  enum class Action { Displacement, Traction, Pressure, Kinds } action = Action::Traction;
  std::array<BcKind, 3> kinds{BcKind::Traction, BcKind::Traction, BcKind::Traction};
  Vec3 value = Vec3::Zero();
  double region_area = 0.0;

  bool holds_displacement() const {
    return action == Action::Displacement ||
           (action == Action::Kinds && std::find(kinds.begin(), kinds.end(), BcKind::Displacement) != kinds.end());
  }
};

/// Carries every rule's selection and `origin` (each element's element of the mesh given) over a
/// split of the mesh, where `parent` maps each new element to the element it lies in.
template <class Map>
void remap_rules(std::vector<Rule>& rules, std::vector<Index>& origin, const Map& parent) {
  const auto remap = [&](std::vector<char>& f) {
    if (f.empty()) return;
    std::vector<char> g(parent.size());
    for (std::size_t e = 0; e < parent.size(); ++e) g[e] = f[static_cast<std::size_t>(parent[e])];
    f.swap(g);
  };
  for (Rule& r : rules) {
    remap(r.selected);
    remap(r.others);
  }
  std::vector<Index> o(parent.size());
  for (std::size_t e = 0; e < parent.size(); ++e) o[e] = origin[static_cast<std::size_t>(parent[e])];
  origin.swap(o);
}

/// "conform": the mesh split along rule `index`'s sphere or box; the rule then holds the pieces
/// inside. Returns the mesh source line's text (empty: nothing changed); warns where the pieces
/// miss the region's area by more than 1 %.
std::string conform_rule(const JsonReader& rule, std::size_t index, std::vector<Rule>& rules, TriangleMesh& mesh,
                         std::vector<Index>& origin, std::vector<double>& grading_size, std::vector<std::string>& warnings);

/// Constant elements with a displacement rule's "refine_rim": the whole surface refined red once
/// before any rim (scene_rule_meshing.cpp says why). Returns the mesh source line's text, empty
/// when no rule asks for it.
std::string refine_surface_for_constant_rims(std::vector<Rule>& rules, TriangleMesh& mesh, std::vector<Index>& origin,
                                             ElementType elements);

/// "refine_rim": rule `index`'s rim refined red-green (scene_rule_meshing.cpp). Returns the mesh
/// source line's text, empty when the rule has no rim.
std::string refine_rule_rim(std::size_t index, std::vector<Rule>& rules, TriangleMesh& mesh, std::vector<Index>& origin,
                            std::vector<double>& grading_size, ElementType elements);

}  // namespace bemsurg::io
