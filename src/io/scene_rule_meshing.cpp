// What a rule's "conform" and "refine_rim" keys do to the mesh before the rules apply
// (docs/scene-format.md, "What a rule holds"; docs/graded.md, "Rim refinement").
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "bemsurg/mesh/conforming_split.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/red_green_refinement.hpp"
#include "bemsurg/meshing/graded_remesher.hpp"
#include "bemsurg/number_text.hpp"
#include "scene_rule.hpp"

namespace bemsurg::io {

/// "conform": the mesh split along the rule's sphere or box (mesh/conforming_split.hpp); the rule
/// then holds the pieces inside (and picked by its other selectors). Returns what was done, for
/// the mesh's source line (empty when the boundary crosses no element: nothing changed).
std::string conform_rule(const JsonReader& rule, std::size_t index, std::vector<Rule>& rules, TriangleMesh& mesh,
                         std::vector<Index>& origin, std::vector<double>& grading_size, std::vector<std::string>& warnings) {
  Rule& r = rules[index];
  const ElementSplit split = conform_to_region(mesh, *r.conform);
  if (!(split.held_area > 0.0))
    rule.required("select").fail(split.region_area > 0.0 ? "its region covers " + general_text(split.region_area, 3) +
                                                               " m^2 of the surface but lies between the mesh's vertices even after " +
                                                               std::to_string(split.refinement_levels) +
                                                               " levels of refinement: enlarge it or refine the mesh there (mesh.refine)"
                                                         : "holds no part of the surface: its region does not meet the mesh");
  if (std::abs(split.held_area - split.region_area) > 0.01 * split.region_area)
    warnings.push_back(r.key + ": conformed, it holds " + general_text(split.held_area, 4) + " m^2 of the " +
                       general_text(split.region_area, 4) + " m^2 inside its region (" +
                       general_text(100.0 * split.held_area / split.region_area, 3) +
                       " %): the region is small against the elements; refine the mesh there (mesh.refine)");
  if (split.split_elements == 0 && split.refinement_levels == 0) {  // the pieces are the elements
    for (std::size_t e = 0; e < r.selected.size(); ++e) r.selected[e] = split.inside[e] && r.others[e];
    return {};
  }
  remap_rules(rules, origin, split.parent);
  for (std::size_t e = 0; e < r.selected.size(); ++e) r.selected[e] = split.inside[e] && r.others[e];
  // The safe-grading rule counts a piece with the size of the element it was cut from: the split
  // makes the boundary true, not the mesh finer (refine_rim, which runs first, does that).
  if (grading_size.empty())
    for (Index e = 0; e < mesh.num_elements(); ++e) grading_size.push_back(element_size(mesh, e));
  std::vector<double> pieces(split.parent.size());
  for (std::size_t e = 0; e < pieces.size(); ++e) pieces[e] = grading_size[static_cast<std::size_t>(split.parent[e])];
  grading_size.swap(pieces);
  mesh = split.mesh;
  return "rules[" + std::to_string(index) + "] conformed (" + std::to_string(split.split_elements) + " elements split" +
         (split.refinement_levels > 0 ? ", " + std::to_string(split.refinement_levels) + " red-green levels along the boundary" : "") + ")";
}

namespace {

/// The elements along rule `r`'s rim: either side of an edge between its elements and the rest
/// and, for a conforming rule, those its region's boundary crosses. None: the rule has no rim.
std::vector<char> rim_elements(const Rule& r, const TriangleMesh& mesh, const MeshTopology& topology) {
  const Index E = mesh.num_elements();
  std::vector<char> marked(static_cast<std::size_t>(E), 0);
  for (Index e = 0; e < E; ++e)
    for (Index g : topology.neighbours(e))
      if (g >= 0 && r.selected[std::size_t(g)] != r.selected[std::size_t(e)]) marked[std::size_t(e)] = 1;
  if (r.conform)
    for (Index e = 0; e < E; ++e) {
      const std::array<Vec3, 3> c = mesh.corners(e);
      const double inside = triangle_area_inside(c[0], c[1], c[2], *r.conform);
      if (inside > 1e-12 * mesh.area(e) && inside < (1.0 - 1e-12) * mesh.area(e)) marked[std::size_t(e)] = 1;
    }
  return marked;
}

bool any_marked(const std::vector<char>& marked) { return std::find(marked.begin(), marked.end(), 1) != marked.end(); }

}  // namespace

/// Constant elements, a displacement rule with "refine_rim" and a rim: the whole surface is refined
/// red once before any rim is. Why: a coarse organ held on constant elements is close to right only
/// by a cancellation, its clamp too soft by about as much as its free surface is too stiff, so
/// refining the rim alone makes it stiffer and the error larger, and so does refining a region
/// around the support; refining everything once first removes most of the free surface's error,
/// and the rim levels then lower the error (issue 38's hung liver: docs/graded.md, "Rim
/// refinement", has the table). Returns the mesh source line's text, empty when no rule asks for it.
std::string refine_surface_for_constant_rims(std::vector<Rule>& rules, TriangleMesh& mesh, std::vector<Index>& origin,
                                             ElementType elements) {
  if (elements != ElementType::Constant) return {};
  std::string asked;
  const MeshTopology topology(mesh);
  for (std::size_t i = 0; i < rules.size(); ++i)
    if (rules[i].refine_rim > 0 && rules[i].holds_displacement() && any_marked(rim_elements(rules[i], mesh, topology)))
      asked += (asked.empty() ? "" : ", ") + ("rules[" + std::to_string(i) + "]");
  if (asked.empty()) return {};
  const Index E = mesh.num_elements();
  std::vector<Index> all(static_cast<std::size_t>(E));
  for (Index e = 0; e < E; ++e) all[std::size_t(e)] = e;
  const RedGreenRefinement refined = refine_red_green(mesh, all, 1);
  const ElementSplit kept = keep_parent_ids(refined.mesh, refined.parent, E);
  remap_rules(rules, origin, kept.parent);
  mesh = kept.mesh;
  return "the whole surface refined once (" + std::to_string(E) + " -> " + std::to_string(mesh.num_elements()) +
         " elements) before the rim of " + asked +
         ": constant elements, where refining the rim alone stiffens a coarse organ (docs/graded.md, Rim refinement)";
}

/// "refine_rim": k red-green levels on the elements either side of the rule's rim (the edges
/// between its elements and the rest) and, for a conforming rule, on the elements its region's
/// boundary crosses. It runs before any conforming split, so that the split then cuts the refined
/// elements (and needs fewer levels of its own) and the grading below is measured on whole
/// elements, not on the split's pieces.
///
/// Constant elements: for a displacement rule the whole surface was refined once before
/// (refine_surface_for_constant_rims says why), and the rim's refinement then spreads over the held side, a
/// ring at a time, until the safe-grading ratio (docs/graded.md, "Safe gradings": held elements
/// against the finest) is no worse than before the refinement (or within the rule's limit of 1.2),
/// or the whole held side is refined; the rule comes from constant elements' non-monotone local
/// refinement (study (i)).
///
/// Linear elements: the refinement stays a band, and its elements count with the size of the element
/// they came from in the safe-grading rule (`grading_size`, as a conforming split's pieces do). The
/// rule was measured for constant elements only, and spreading costs linear elements the memory
/// the refinement is for: on a prepared liver of 2,358 elements hung from a 154-element patch, two
/// levels spread over the held side made 4,740 elements (27 GiB dense, refused on 24 GB), a band
/// 3,750; at one level the band's error equalled the spread's (docs/graded.md, "Rim refinement").
std::string refine_rule_rim(std::size_t index, std::vector<Rule>& rules, TriangleMesh& mesh, std::vector<Index>& origin,
                            std::vector<double>& grading_size, ElementType elements) {
  const Rule& r = rules[index];
  const MeshTopology topology(mesh);
  const Index E = mesh.num_elements();
  std::vector<char> marked = rim_elements(r, mesh, topology), held(static_cast<std::size_t>(E), 0);
  for (const Rule& other : rules)
    if (other.holds_displacement())
      for (Index e = 0; e < E; ++e) held[std::size_t(e)] = held[std::size_t(e)] || other.selected[std::size_t(e)];
  if (!any_marked(marked)) return {};  // no rim: nothing to refine
  const bool spread = elements == ElementType::Constant;
  const double allowed = std::max(kMaxSupportSizeRatio, 1.05 * support_size_ratio(mesh, held));
  int rings = 0;
  for (;;) {
    std::vector<Index> list;
    for (Index e = 0; e < E; ++e)
      if (marked[std::size_t(e)]) list.push_back(e);
    const RedGreenRefinement refined = refine_red_green(mesh, list, r.refine_rim);
    const ElementSplit kept = keep_parent_ids(refined.mesh, refined.parent, E);
    std::vector<char> held_now(kept.parent.size());
    for (std::size_t e = 0; e < kept.parent.size(); ++e) held_now[e] = held[std::size_t(kept.parent[e])];
    bool grown = false;
    if (spread && r.holds_displacement() && support_size_ratio(kept.mesh, held_now) > allowed) {
      std::vector<char> next = marked;
      for (Index e = 0; e < E; ++e)
        if (marked[std::size_t(e)])
          for (Index g : topology.neighbours(e))
            if (g >= 0 && r.selected[std::size_t(g)] && !next[std::size_t(g)]) next[std::size_t(g)] = grown = true;
      marked.swap(next);
      rings += grown;
    }
    if (grown) continue;
    remap_rules(rules, origin, kept.parent);
    if (!spread) {  // the band's elements count with their parent's size (a scene has one element type)
      if (grading_size.empty())
        for (Index e = 0; e < E; ++e) grading_size.push_back(element_size(mesh, e));
      std::vector<double> sizes(kept.parent.size());
      for (std::size_t e = 0; e < sizes.size(); ++e) sizes[e] = grading_size[static_cast<std::size_t>(kept.parent[e])];
      grading_size.swap(sizes);
    }
    mesh = kept.mesh;
    return "rules[" + std::to_string(index) + "] rim refined (" + std::to_string(list.size()) + " elements, " +
           std::to_string(r.refine_rim) + " level" + (r.refine_rim > 1 ? "s" : "") +
           (rings > 0 ? ", spread " + std::to_string(rings) + " rings into the held side for the safe grading" : "") +
           (!spread && r.holds_displacement() ? ", a band: linear elements" : "") + ")";
  }
}

}  // namespace bemsurg::io
