// grading_setup.hpp: the problem of study (i), non-uniform meshes (issue 25, docs/graded.md),
// shared by benchmarks/stability/grading_studies.cpp and tests/test_stability_grading.cpp.
//
// A 1 x 1 x 3 box [-0.5, 0.5]^2 x [0, 3], clamped at its top (z = 3) and loaded by Kelvin's point
// force at x0 = (0, 0.25, 3.5) above it, on its mirror plane x = 0, with f = (0, 0.3, -1) in that
// plane: the exact field is mirror-symmetric in x. Its exact displacement is prescribed on the top
// face and its exact traction everywhere else, so the exact solution is the Kelvin field (docs/design.md §8).
// A mesh is a base box of n x n x 3n squares (box_mesh, checkerboard diagonals: the triangulation
// itself is not mirror-symmetric) refined by one of the strategies below. Another element type
// (linear elements, issue 27) is one more solver over the same meshes.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/red_green_refinement.hpp"
#include "bemsurg/meshing/graded_remesher.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

namespace bemsurg::bench::grading {

inline const Material kMaterial{1.0, 0.3, 0.0};
inline verification::ElasticField kelvin() { return verification::kelvin_field(kMaterial, Vec3(0.0, 0.25, 3.5), Vec3(0.0, 0.3, -1.0)); }
constexpr double kTop = 3.0;
inline bool on_top(const TriangleMesh& m, Index e) { return m.centroid(e).z() > kTop - 1e-9; }
inline TriangleMesh base_box(int n) { return box_mesh(Vec3(-0.5, -0.5, 0.0), Vec3(0.5, 0.5, kTop), n, n, 3 * n); }

/// Where a strategy refines, as a test on an element's centroid: one half of the box, both, the
/// supported (top) face, or a half together with the supported face.
enum class Zone { HalfMinus, HalfPlus, Both, Supported, HalfMinusAndSupported, HalfPlusAndSupported };
inline const char* zone_name(Zone z) {
  switch (z) {
    case Zone::HalfMinus: return "half x<0";
    case Zone::HalfPlus: return "half x>0";
    case Zone::Both: return "both halves";
    case Zone::Supported: return "supported face";
    case Zone::HalfMinusAndSupported: return "half x<0 + supported";
    default: return "half x>0 + supported";
  }
}
inline bool in_zone(Zone z, const TriangleMesh& m, Index e) {
  const double x = m.centroid(e).x();
  switch (z) {
    case Zone::HalfMinus: return x < 0.0;
    case Zone::HalfPlus: return x > 0.0;
    case Zone::Both: return true;
    case Zone::Supported: return on_top(m, e);
    case Zone::HalfMinusAndSupported: return x < 0.0 || on_top(m, e);
    default: return x > 0.0 || on_top(m, e);
  }
}

/// The base box refined red-green `levels` times in `zone`.
inline TriangleMesh refined_box(int n, Zone zone, int levels) {
  const TriangleMesh base = base_box(n);
  std::vector<Index> marked;
  for (Index e = 0; e < base.num_elements(); ++e)
    if (in_zone(zone, base, e)) marked.push_back(e);
  return refine_red_green(base, marked, levels).mesh;
}

/// One solve of the Kelvin problem on `mesh` with constant elements: the relative L2 error of the
/// displacement (solved on every face but the top) and of the traction (solved on the top).
struct GradingResult {
  Index elements = 0;
  double max_ratio = 0.0;      // largest neighbouring size ratio (MeshQuality)
  double support_ratio = 0.0;  // largest held element over the smallest (support_size_ratio)
  double displacement_error = 0.0;
  double traction_error = 0.0;
};
inline std::vector<char> held(const TriangleMesh& mesh) {
  std::vector<char> h(static_cast<std::size_t>(mesh.num_elements()));
  for (Index e = 0; e < mesh.num_elements(); ++e) h[static_cast<std::size_t>(e)] = on_top(mesh, e);
  return h;
}
inline GradingResult solve_constant(const TriangleMesh& mesh) {
  const verification::RelativeErrors e =
      verification::solve_exact_trace_problem(mesh, kMaterial, kelvin(), [&mesh](Index i) { return on_top(mesh, i); });
  return {mesh.num_elements(), measure_mesh_quality(mesh).max_neighbour_size_ratio, support_size_ratio(mesh, held(mesh)), e.displacement,
          e.traction};
}

/// The graded (Gmsh) box: fine (inside) in the half x < 0, graded at `growth` to `outside`; with
/// `with_support` the clamped top face is meshed at `inside` too (the safe-grading rule).
inline TriangleMesh graded_box(double inside, double outside, bool with_support, double growth = 2.0) {
  GradedRemeshOptions o;
  o.inside_edge_length = inside;
  o.outside_edge_length = outside;
  o.growth = growth;
  if (with_support) o.supported_regions.push_back(OperatingRegion::box(Vec3(-1, -1, kTop - 0.01), Vec3(1, 1, kTop + 1)));
  return graded_remesh(base_box(4), OperatingRegion::box(Vec3(-1, -1, -1), Vec3(0, 1, kTop + 1)), o).mesh;
}

}  // namespace bemsurg::bench::grading
