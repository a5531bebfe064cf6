// bemsurg/io/boundary_rule_area.hpp: what one boundary rule of a scene held, as report.json's
// "boundary_rules" gives it (docs/scene-format.md, "boundary_rules"; issue 38: a support that
// holds less than its region is the largest error of a hanging organ, so every solve says so).
#pragma once

#include <string>

namespace bemsurg {

/// What one boundary rule held (report.json "boundary_rules", docs/scene-format.md; issue 38): the
/// area whose conditions the rule set and kept after later rules and the CSV file, and where its
/// selectors describe a region of space (sphere, box, plane), that region's area on the mesh as read.
/// \ingroup io
struct BoundaryRuleArea {
  std::string key;            ///< e.g. "boundary_conditions.rules[0]"
  bool displacement = false;  ///< the rule prescribes a displacement component
  double area = 0.0;          ///< m^2 of the solved surface
  bool has_region = false;
  double region_area = 0.0;  ///< m^2 of the mesh as read (before any remesh) inside the region
  bool conform = false;      ///< "conform": true (the mesh was split along the region's boundary)
  bool can_conform = false;  ///< the selectors hold a sphere or a box ("conform" applies)
  int refine_rim = 0;        ///< "refine_rim": red-green levels along the rule's rim
};

}  // namespace bemsurg
