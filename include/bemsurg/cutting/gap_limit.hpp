// bemsurg/cutting/gap_limit.hpp: the narrowest cut gap whose BEM solution is still trusted.
// The far wall of a narrow gap is a near-singular neighbour of the near wall's collocation
// points; the adaptive quadrature (docs/design.md §4) integrates it accurately only down to some
// gap width / element size. bench_cut's gap study (docs/cutting.md, "Narrow gaps") compares the
// solution on cut meshes of shrinking gap ratio with a much finer quadrature; kMinimumGapRatio is
// the smallest ratio at which they still agreed to 1e-6 there. Narrower gaps are refused.
#pragma once

#include <sstream>
#include <string>

#include "bemsurg/error.hpp"

namespace bemsurg {

/// Smallest gap width / local edge length accepted by cut updates (measured: docs/cutting.md).
inline constexpr double kMinimumGapRatio = 0.05;

/// Empty when `gap_width` / `edge_length` >= kMinimumGapRatio, else the reason to refuse.
inline std::string narrow_gap_reason(double gap_width, double edge_length) {
  if (!(edge_length > 0.0) || gap_width >= kMinimumGapRatio * edge_length) return {};
  std::ostringstream s;
  s << "the gap is too narrow: width " << gap_width << " is " << gap_width / edge_length << " x the local edge length "
    << edge_length << "; below " << kMinimumGapRatio
    << " x the edge length the far wall's near-singular integration no longer agrees with a refined reference to 1e-6 "
       "(docs/cutting.md); use a gap of at least "
    << kMinimumGapRatio * edge_length;
  return s.str();
}

}  // namespace bemsurg
