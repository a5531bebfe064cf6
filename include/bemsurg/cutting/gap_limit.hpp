// bemsurg/cutting/gap_limit.hpp: the narrowest cut gap whose BEM solution is still trusted.
// The far wall of a narrow gap is a near-singular neighbour of the near wall's collocation
// points; the adaptive quadrature (docs/design.md §4) integrates it accurately only down to some
// gap width / element size. bench_cut's gap study (docs/cutting.md, "Narrow gaps") compares the
// solution on cut meshes of shrinking gap ratio with a much finer quadrature; kMinimumGapRatio is
// the smallest ratio at which they still agreed to 1e-6 there. Narrower gaps are refused, by
// SurfaceCutter itself (its last check; CutOptions::allow_narrow_gap_for_studies switches it off
// for studies). bench_stability's gap study (docs/stability.md (d)) confirmed the limit: the
// condition of A* and the Krylov iterations grow steadily as the gap narrows and every method
// converges, but the error against the refined quadrature crosses 1e-6 between 0.1 and 0.05.
#pragma once

#include <sstream>
#include <string>

#include "bemsurg/number_text.hpp"

#include "bemsurg/error.hpp"

namespace bemsurg {

/// Smallest gap width / local edge length accepted by cut updates (measured: docs/cutting.md).
/// bench_cut (8 x 8 x 3 box of 1 cm cells, a two-step cut, fine quadrature far 8, mid 4, order 10,
/// depth 18, polar 20): largest relative displacement difference 2.0e-8 uncut, 2.4e-7 at 0.2,
/// 6.2e-7 at 0.1, 1.25e-6 at 0.05, 7.6e-6 at 0.02, 1.0e-3 at 0.002 (the subdivision depth runs out).
inline constexpr double kMinimumGapRatio = 0.1;

/// Empty when `gap_width` / `edge_length` >= kMinimumGapRatio, else the reason to refuse.
inline std::string narrow_gap_reason(double gap_width, double edge_length) {
  // Slack of 1e-9: the cutter's default width is exactly 0.1 x the edge length, up to rounding.
  if (!(edge_length > 0.0) || gap_width >= kMinimumGapRatio * edge_length * (1.0 - 1e-9)) return {};
  std::ostringstream s;
  use_classic_locale(s);
  s << "the gap is too narrow: width " << gap_width << " is " << gap_width / edge_length << " x the local edge length " << edge_length
    << "; below " << kMinimumGapRatio
    << " x the edge length the far wall's near-singular integration no longer agrees with a refined reference to 1e-6 "
       "(docs/cutting.md); use a gap of at least "
    << kMinimumGapRatio * edge_length;
  return s.str();
}

}  // namespace bemsurg
