// bemsurg/quadrature/quadrature_cost.hpp: how many kernel evaluations the assembly of H and G will
// take with given quadrature options, estimated from the inputs before the work, so that options
// inside their documented ranges but ruinous together (mid_ratio 1000 on 80 elements: minutes)
// are refused with the estimate instead of run (docs/design.md §4, §10).
#pragma once

#include <string>

#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/quadrature/element_quadrature.hpp"

namespace bemsurg {

/// The estimate: `points` kernel evaluations (quadrature points over all source-element pairs,
/// self pairs included), extrapolated from `sampled_sources` source points counted exactly with
/// ElementQuadrature::count_points; `exceeded` when counting stopped early because the count was
/// already above the limit asked for (points is then a lower bound).
/// \ingroup quadrature
struct QuadratureCostEstimate {
  double points = 0.0;
  Index sampled_sources = 0;
  bool exceeded = false;
  /// points per source-element pair, and the same with the default options (the rule's price).
  double points_per_pair = 0.0;
};

/// The refusal threshold: an assembly is refused when its options would take more than
/// kQuadratureCostFactor times the kernel evaluations of the default options on the same mesh AND
/// more than kQuadratureCostFloor evaluations (1e9: seconds of assembly at the kernel rates
/// benchmarks/bench_assembly reports). Relative, so that a large mesh with sensible options (whose memory
/// check passed) is never refused for its size; floored, so that small meshes may be integrated
/// as finely as anyone likes while it costs seconds.
constexpr double kQuadratureCostFactor = 20.0;
constexpr double kQuadratureCostFloor = 1e9;

/// Estimates the kernel evaluations of assembling H and G on `mesh` with `options`, counting the
/// pairs of at most `max_sampled_sources` source points spread evenly over the elements exactly
/// and scaling by the number of elements. Stops counting (exceeded = true) once the scaled count
/// passes `limit_points`.
QuadratureCostEstimate estimate_assembly_quadrature(const TriangleMesh& mesh, const QuadratureOptions& options, double limit_points,
                                                    Index max_sampled_sources = 16);

/// Throws ResourceError with the estimate, the limit and the options that drive it when the
/// assembly of `mesh` with `options` needs more kernel evaluations than the threshold above.
/// `who` names the caller in the message ("solve_elastostatic"). Costs at most about as much as
/// counting to the limit (a fraction of a second even for pathological options), far less for ordinary ones.
void require_assembly_quadrature_within(const TriangleMesh& mesh, const QuadratureOptions& options, const std::string& who);

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/quadrature/impl/quadrature_cost_impl.hpp"
#endif
