// prepare_mesh (mesh/mesh_preparation.hpp, docs/organs.md) on one kind of defect at a time, made by
// mesh/mesh_defects.hpp on an ellipsoid whose volume is known in closed form, and on their mix on
// a sampled liver: the result is a valid body (closed, 2-manifold, outward, not crossing itself),
// the report counts exactly the defects injected, the element count is near the target, the volume
// is the closed form's and the Hausdorff distance agrees with a brute-force one computed here.
// Also: holes too long and open sheets are refused naming the limit, cavities stay cavities, units,
// determinism, and a graded remesh. Every case skips (exit 77) in a build without CGAL and Gmsh.
//
// The defects are SECTIONs of few TEST_CASEs: ctest runs each case in a process of its own, and
// each process pays Gmsh's and CGAL's start-up once.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/meshing/implicit_surface.hpp"
#include "bemsurg/meshing/mesh_defects.hpp"
#include "bemsurg/meshing/mesh_preparation.hpp"
#include "bemsurg/meshing/organ_shapes.hpp"
#include "bemsurg/number_text.hpp"
#include "support/skip.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {

using bemsurg_test::kPi;
const Vec3 kCenter(0.01, -0.02, 0.005);
const Vec3 kAxes(0.06, 0.045, 0.035);
constexpr Index kTarget = 800;

void skip_without_preparation() {
  testing::skip_unless(mesh_preparation_available(), "this build has no mesh preparation (BEMSURG_WITH_PREPARE: CGAL and Gmsh)");
}

double ellipsoid_volume() { return 4.0 / 3.0 * kPi * kAxes.x() * kAxes.y() * kAxes.z(); }

/// The clean input: an ellipsoid of 5,120 faces (icosphere level 4) in metres.
const TriangleMesh& ellipsoid() {
  static const TriangleMesh mesh = ellipsoid_mesh(kCenter, kAxes, 4);
  return mesh;
}

/// Uniform remesh to kTarget elements; the wrap's alpha 1/60 of the diagonal instead of 1/150,
/// so that a rebuilt ellipsoid has ~8,000 faces instead of ~50,000 and each case takes well under
/// a second (the default alpha is exercised by the liver case and the benchmark).
MeshPreparationOptions options(double alpha_fraction = 1.0 / 60.0) {
  MeshPreparationOptions o;
  o.scale_given = true;
  o.target_elements = kTarget;
  o.wrap_alpha_fraction = alpha_fraction;
  return o;
}

/// The largest distance from the points to the mesh, by brute force over every face (not CGAL's
/// AABB tree, which the report uses).
double max_distance(const std::vector<Vec3>& points, const TriangleMesh& mesh) {
  double worst = 0.0;
  for (const Vec3& p : points) {
    double best = std::numeric_limits<double>::infinity();
    for (Index f = 0; f < mesh.num_elements(); ++f) {
      const auto c = mesh.corners(f);
      best = std::min(best, point_triangle_distance(p, c[0], c[1], c[2]));  // mesh/geometry.hpp
    }
    worst = std::max(worst, best);
  }
  return worst;
}

/// Every vertex, and for `with_centroids` every face's centroid too.
std::vector<Vec3> sample_points(const TriangleMesh& mesh, bool with_centroids) {
  std::vector<Vec3> out;
  for (Index v = 0; v < mesh.num_vertices(); ++v) out.push_back(mesh.vertex(v));
  if (with_centroids)
    for (Index f = 0; f < mesh.num_elements(); ++f) out.push_back(mesh.centroid(f));
  return out;
}

/// What every prepared mesh must be: valid (require_valid_mesh: closed, 2-manifold, outward, no
/// crossing faces), with the reported counts and the element count within 15 % of the target.
PreparedMesh prepare_checked(const TriangleMesh& input, const MeshPreparationOptions& o) {
  PreparedMesh p = prepare_mesh(input, o);
  CHECK_NOTHROW(require_valid_mesh(p.mesh));
  CHECK(find_self_intersections(p.mesh).empty());
  CHECK(p.report.elements == p.mesh.num_elements());
  CHECK(p.report.vertices == p.mesh.num_vertices());
  if (o.target_elements > 0) CHECK(std::abs(double(p.mesh.num_elements()) / double(o.target_elements) - 1.0) < 0.15);
  CHECK(p.report.volume == Approx(p.mesh.enclosed_volume()).epsilon(1e-12));
  CHECK(std::isfinite(p.report.hausdorff));
  return p;
}

/// The counts of a defect kind that is not injected are zero; `except` names the ones that are.
void check_only(const MeshDefectCounts& d, std::initializer_list<Index MeshDefectCounts::*> except) {
  const std::initializer_list<Index MeshDefectCounts::*> all = {&MeshDefectCounts::duplicate_vertices,
                                                                &MeshDefectCounts::degenerate_faces,
                                                                &MeshDefectCounts::slivers,
                                                                &MeshDefectCounts::duplicate_faces,
                                                                &MeshDefectCounts::flipped_faces,
                                                                &MeshDefectCounts::boundary_edges,
                                                                &MeshDefectCounts::holes,
                                                                &MeshDefectCounts::non_manifold_edges,
                                                                &MeshDefectCounts::non_manifold_vertices,
                                                                &MeshDefectCounts::self_intersections};
  for (const auto member : all)
    if (std::find(except.begin(), except.end(), member) == except.end()) CHECK(d.*member == 0);
}

}  // namespace

TEST_CASE("prepare_mesh repairs each kind of defect on an ellipsoid into a valid body of its volume", "[prepare]") {
  skip_without_preparation();
  SECTION("clean: kept as it is, closed-form volume, Hausdorff distance as measured by brute force") {
    const PreparedMesh p = prepare_checked(ellipsoid(), options());
    const MeshPreparationReport& r = p.report;
    check_only(r.defects, {});
    CHECK(r.defects.shells == 1);
    CHECK_FALSE(r.rebuilt);
    CHECK(r.holes_filled == 0);
    CHECK(r.bodies == 1);
    CHECK(r.remesh == "uniform");
    // 800 flat triangles inscribed in the ellipsoid (edge h ~ 9 mm): each face's middle lies about
    // h^2 / (6 R) inside the surface (R ~ 0.03-0.06 m, the curvature radii), so the mean gap is a
    // few tenths of a mm and the volume ~3 x that / R ~ 1.5 % low; the largest gap, ~1 mm where R
    // is smallest (b^2/a ~ 0.02 m), is under 1 % of the 0.17 m diagonal.
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.02));
    CHECK(r.hausdorff_relative < 0.01);
    CHECK(r.hausdorff_relative == Approx(r.hausdorff / (2.0 * kAxes.norm())).epsilon(0.03));  // the box spans 2 x axes
    // Independently: input vertices to the result's faces, the result's vertices and centroids to
    // the input's faces. These points are a subset of the report's samples (vertices, centroids,
    // edge midpoints of both), so the estimate is at most the report's; the largest gap of two
    // inscribed meshes lies at a vertex of one over a face of the other, so it is not far below.
    const double estimate =
        std::max(max_distance(sample_points(ellipsoid(), false), p.mesh), max_distance(sample_points(p.mesh, true), ellipsoid()));
    CHECK(estimate <= r.hausdorff * (1.0 + 1e-9));
    CHECK(estimate >= 0.8 * r.hausdorff);
    const double v0 = ellipsoid().enclosed_volume();
    CHECK(r.volume_change == Approx((p.mesh.enclosed_volume() - v0) / v0).margin(1e-12));
    CHECK(r.estimated_bytes == 0.0);  // filled by `bemsurg prepare`, not by the mesh module
  }
  SECTION("a flipped patch: turned back, its faces counted") {
    const PreparedMesh p = prepare_checked(flip_face_patch(ellipsoid(), 10, 5), options());
    check_only(p.report.defects, {&MeshDefectCounts::flipped_faces});
    CHECK(p.report.defects.flipped_faces == 10);
    CHECK_FALSE(p.report.rebuilt);
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.02));
  }
  SECTION("inside out: turned outward") {
    const TriangleMesh inverted = flip_orientation(ellipsoid());
    REQUIRE(inverted.enclosed_volume() < 0.0);
    const PreparedMesh p = prepare_checked(inverted, options());
    check_only(p.report.defects, {});  // consistently oriented: no face disagrees with its neighbours
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.02));
    CHECK(p.report.cavities == 0);
  }
  SECTION("pushed through itself: rebuilt") {
    const TriangleMesh poked = poke_through(ellipsoid(), 3);
    REQUIRE_FALSE(find_self_intersections(poked).empty());
    const PreparedMesh p = prepare_checked(poked, options());
    check_only(p.report.defects, {&MeshDefectCounts::self_intersections});
    CHECK(p.report.defects.self_intersections > 0);
    CHECK(p.report.rebuilt);
    // The spike stands two input edges (~7 mm) out of the far side; the wrap keeps it, thickened
    // to about alpha (2.8 mm), and the Hausdorff distance includes it (~4 % of the diagonal).
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.03));
    CHECK(p.report.hausdorff_relative < 0.05);
  }
  SECTION("a fin on a non-manifold edge: removed") {
    const PreparedMesh p = prepare_checked(add_fin(ellipsoid(), 7), options());
    const MeshDefectCounts& d = p.report.defects;
    check_only(d, {&MeshDefectCounts::non_manifold_edges, &MeshDefectCounts::boundary_edges, &MeshDefectCounts::holes});
    CHECK(d.non_manifold_edges == 1);
    CHECK(d.boundary_edges == 2);  // the fin's free edges
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.02));
    CHECK(p.report.bodies == 1);
    // The fin is gone from the result, but its apex, one input edge (3.5 mm) out, counts in the
    // distance: 2.1 % of the 0.17 m diagonal.
    CHECK(p.report.hausdorff_relative < 0.03);
  }
  SECTION("a cone touching at a non-manifold vertex: one body") {
    const PreparedMesh p = prepare_checked(add_touching_cone(ellipsoid(), 9), options());
    const MeshDefectCounts& d = p.report.defects;
    CHECK(d.non_manifold_vertices == 1);
    CHECK(d.non_manifold_edges == 0);
    CHECK(d.shells == 2);
    CHECK(MeshTopology(p.mesh).num_shells() == 1);
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.03));
  }
  SECTION("an overlapping shell: merged into one body") {
    const TriangleMesh overlapped = add_overlapping_ellipsoid(ellipsoid(), 4);
    const PreparedMesh p = prepare_checked(overlapped, options());
    const MeshPreparationReport& r = p.report;
    CHECK(r.defects.self_intersections > 0);
    CHECK(r.defects.shells == 2);
    CHECK(r.rebuilt);
    CHECK(MeshTopology(p.mesh).num_shells() == 1);
    // The union is larger than the body and smaller than the sum of the two shells.
    CHECK(p.mesh.enclosed_volume() > ellipsoid_volume());
    CHECK(p.mesh.enclosed_volume() < std::abs(overlapped.enclosed_volume()));
    CHECK(r.hausdorff_excluded_samples > 0);  // the inner half of the second shell
    CHECK(r.hausdorff_relative < 0.02);
  }
  SECTION("a disjoint speck: dropped and reported, or kept with keep_all") {
    const PreparedMesh p = prepare_checked(add_speck(ellipsoid(), 1e-3), options());
    check_only(p.report.defects, {});
    CHECK(p.report.bodies == 2);
    CHECK(p.report.bodies_dropped == 1);
    CHECK(p.report.dropped_volume == Approx(1e-3 * ellipsoid().enclosed_volume()).epsilon(0.05));
    CHECK(MeshTopology(p.mesh).num_shells() == 1);
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.02));
    CHECK(p.report.hausdorff_relative < 0.01);  // the speck's samples are left out, not counted as lost
    // keep_all: a 1e-3 speck (radius 4.5 mm) is less than two of the 9 mm elements across: refused,
    // naming the shell, its size and the way out; a speck larger than the elements (~12 mm) is kept.
    MeshPreparationOptions all = options();
    all.keep_all = true;
    CHECK_THROWS_AS(prepare_mesh(add_speck(ellipsoid(), 1e-3), all), InvalidMeshError);
    CHECK_THROWS_WITH(prepare_mesh(add_speck(ellipsoid(), 1e-3), all),
                      Catch::Matchers::Contains("less than two elements of") && Catch::Matchers::Contains("--keep-all"));
    const TriangleMesh big = add_speck(ellipsoid(), 0.05);
    const PreparedMesh q = prepare_checked(big, all);
    CHECK(q.report.bodies == 2);
    CHECK(q.report.bodies_dropped == 0);
    CHECK(MeshTopology(q.mesh).num_shells() == 2);
    CHECK(q.mesh.enclosed_volume() == Approx(big.enclosed_volume()).epsilon(0.03));
  }
  SECTION("a small hole: filled") {
    const PreparedMesh p = prepare_checked(punch_hole(ellipsoid(), 6, 8), options());
    check_only(p.report.defects, {&MeshDefectCounts::boundary_edges, &MeshDefectCounts::holes});
    CHECK(p.report.defects.holes == 1);
    CHECK(p.report.defects.boundary_edges >= 6);
    CHECK(p.report.holes_filled == 1);
    CHECK_FALSE(p.report.rebuilt);
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.02));
  }
  SECTION("a nested cavity: kept inward, and an outward one made inward") {
    const double radius = 0.015;
    const double expected = ellipsoid_volume() - 4.0 / 3.0 * kPi * radius * radius * radius;
    for (const bool mistake : {false, true}) {
      INFO("cavity oriented outward by mistake: " << mistake);
      const PreparedMesh p = prepare_checked(add_cavity(ellipsoid(), kCenter, radius, mistake), options());
      CHECK(p.report.cavities == 1);
      CHECK(p.report.bodies == 1);
      const MeshTopology topo(p.mesh);
      REQUIRE(topo.num_shells() == 2);
      CHECK(std::min(topo.shell_volume(0), topo.shell_volume(1)) < 0.0);  // the cavity's normals point into the hole
      CHECK(std::max(topo.shell_volume(0), topo.shell_volume(1)) > 0.0);
      CHECK(p.mesh.enclosed_volume() == Approx(expected).epsilon(0.03));
    }
  }
  SECTION("millimetres: scaled to metres; without a unit, a warning naming --units mm") {
    const TriangleMesh mm = scale_mesh(ellipsoid(), 1000.0);
    MeshPreparationOptions o = options();
    o.scale = length_unit_to_metres("mm");
    const PreparedMesh p = prepare_checked(mm, o);
    CHECK(p.report.warnings.empty());
    const Vec3 size = p.mesh.bounding_box().col(1) - p.mesh.bounding_box().col(0);
    CHECK((size - 2.0 * kAxes).norm() < 0.02 * 2.0 * kAxes.norm());
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.02));
    MeshPreparationOptions none;  // no unit given, no remesh: the warning only
    none.no_remesh = true;
    const PreparedMesh q = prepare_mesh(mm, none);
    REQUIRE(q.report.warnings.size() == 1);
    CHECK_THAT(q.report.warnings[0], Catch::Contains("millimetres") && Catch::Contains("--units mm"));
    CHECK(q.report.remesh == "none");
    CHECK(q.mesh.num_elements() == mm.num_elements());
  }
  SECTION("graded to an operating region: finer elements in it than far from it") {
    MeshPreparationOptions o;
    o.scale_given = true;
    const Vec3 at = kCenter + Vec3(kAxes.x(), 0.0, 0.0);  // the tip of the long axis, on the surface
    o.region = OperatingRegion::sphere(at, 0.015);
    o.graded_options.inside_edge_length = 0.004;
    o.graded_options.outside_edge_length = 0.016;
    const PreparedMesh p = prepare_checked(ellipsoid(), o);
    CHECK(p.report.remesh == "graded");
    std::vector<double> inside, far;
    for (Index f = 0; f < p.mesh.num_elements(); ++f) {
      const double d = (p.mesh.centroid(f) - at).norm();
      if (d < 0.015) inside.push_back(std::sqrt(p.mesh.area(f)));
      if (d > 0.08) far.push_back(std::sqrt(p.mesh.area(f)));
    }
    REQUIRE(inside.size() > 20);
    REQUIRE_FALSE(far.empty());
    const auto mean = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size()); };
    // sqrt(area) of an equilateral element of edge h is 0.66 h: 2.6 mm inside, up to 10.5 mm far out.
    CHECK(mean(inside) < 0.5 * mean(far));
    CHECK(mean(inside) == Approx(0.66 * 0.004).epsilon(0.35));
    // Elements of 16 mm far out cut deeper into the curved surface (h^2 / (6 R) ~ 1-2 mm): 5 %, 3 %.
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.05));
    CHECK(p.report.hausdorff_relative < 0.03);
  }
}

TEST_CASE("prepare_mesh drops collinear zero-area faces and reports nothing else", "[prepare]") {
  skip_without_preparation();
  // add_degenerate_faces' first kind splits a face at the midpoint m of its edge ab and closes the
  // gap with the flat face (b, m, a): the surface is closed, manifold and oriented, only that face
  // has zero area (validate_mesh reports DegenerateFace and nothing else). Dropping it must not
  // leave a hole the input did not have.
  const TriangleMesh input = add_degenerate_faces(ellipsoid(), 6, 11);
  REQUIRE(validate_mesh(input).count(MeshIssueKind::DegenerateFace) == 6);
  REQUIRE(validate_mesh(input).num_errors() == 6);
  const PreparedMesh p = prepare_checked(input, options());
  check_only(p.report.defects, {&MeshDefectCounts::degenerate_faces});
  CHECK(p.report.defects.degenerate_faces == 6);
  CHECK_FALSE(p.report.rebuilt);  // nothing crosses: no reason to wrap
  CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.02));
}

TEST_CASE("prepare_mesh remeshes slivers above the solver's aspect-ratio limit away, to a target and by default", "[prepare]") {
  skip_without_preparation();
  // add_slivers splits faces at a point near an edge's midpoint (mesh_defects.hpp): the surface
  // stays closed, manifold and oriented with its volume, and each sliver of aspect ratio 3e4 is a
  // DegenerateFace error (above kMaxAspectRatio = 1e4) and nothing else. A segmentation's
  // decimated surface has such faces; prepare must remesh them away, never refuse them (issue 37).
  const TriangleMesh coarse = ellipsoid_mesh(kCenter, kAxes, 3);  // 1,280 faces: fewer than the default target
  const TriangleMesh input = add_slivers(coarse, 8, 3e4, 13);
  const MeshValidationResult v = validate_mesh(input);
  REQUIRE(v.count(MeshIssueKind::DegenerateFace) == 8);
  REQUIRE(v.num_errors() == 8);
  CHECK(input.num_elements() == coarse.num_elements() + 16);
  CHECK(worst_aspect_ratio(input).ratio == Approx(3e4).epsilon(1e-9));
  CHECK(input.enclosed_volume() == Approx(coarse.enclosed_volume()).epsilon(1e-12));
  SECTION("to a target: remeshed to it, the slivers counted") {
    const PreparedMesh p = prepare_checked(input, options());
    check_only(p.report.defects, {&MeshDefectCounts::slivers});
    CHECK(p.report.defects.slivers == 8);
    CHECK(p.report.remesh == "uniform");
    CHECK(worst_aspect_ratio(p.mesh).ratio < kSliverWarningAspectRatio);
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.03));
  }
  SECTION("by default: not kept as repaired, remeshed to its own face count") {
    MeshPreparationOptions o = options();
    o.target_elements = 0;
    const PreparedMesh p = prepare_checked(input, o);
    CHECK(p.report.defects.slivers == 8);
    CHECK(p.report.remesh == "uniform");
    CHECK(p.report.target_elements == input.num_elements());
    CHECK(std::abs(double(p.mesh.num_elements()) / double(input.num_elements()) - 1.0) < 0.15);
    CHECK(worst_aspect_ratio(p.mesh).ratio < kSliverWarningAspectRatio);
    CHECK(p.mesh.enclosed_volume() == Approx(ellipsoid_volume()).epsilon(0.03));
  }
}

TEST_CASE("prepare_mesh refuses a hole longer than the limit and an open sheet, naming the limit", "[prepare]") {
  skip_without_preparation();
  MeshPreparationOptions strict = options();
  strict.max_hole_fraction = 0.02;  // 3.3 mm: shorter than the 6-edge rim (~6 x 3.5 mm)
  try {
    prepare_mesh(punch_hole(ellipsoid(), 6, 8), strict);
    FAIL("a hole longer than the limit was accepted");
  } catch (const InvalidMeshError& e) {
    const std::string what = e.what();
    CHECK_THAT(what, Catch::Contains("the surface is open: 1 hole with a boundary up to"));
    const std::string limit = general_text(0.02 * (ellipsoid().bounding_box().col(1) - ellipsoid().bounding_box().col(0)).norm(), 3);
    CHECK_THAT(what, Catch::Contains("more than the limit of " + limit + " m (0.02 of the bounding-box diagonal)"));
    CHECK_THAT(what, Catch::Contains("--max-hole"));
  }
  // The upper half of the ellipsoid: a dome whose rim (~0.33 m) is twice the diagonal.
  const TriangleMesh& e = ellipsoid();
  RowMatrixX3i upper(e.num_elements(), 3);
  Index n = 0;
  for (Index f = 0; f < e.num_elements(); ++f)
    if (e.centroid(f).z() > kCenter.z()) upper.row(n++) = e.faces().row(f);
  CHECK_THROWS_WITH(prepare_mesh(TriangleMesh(e.vertices(), upper.topRows(n)), options()),
                    Catch::Contains("the surface is open") && Catch::Contains("an open sheet is not a body"));
  // Conflicting remesh targets and a bad scale: named.
  MeshPreparationOptions o = options();
  o.edge_length = 0.01;
  CHECK_THROWS_WITH(prepare_mesh(e, o), Catch::Contains("at most one of a target element count, an edge length"));
  o.edge_length = 0.0;
  o.scale = -1.0;
  CHECK_THROWS_WITH(prepare_mesh(e, o), Catch::Contains("scale must be positive"));
}

namespace {

/// The sampled liver of about 12,000 triangles (a clean marching-cubes surface, metres).
const TriangleMesh& liver_sample() {
  static const TriangleMesh mesh = [] {
    const OrganShape s = liver_shape();
    return sample_implicit_surface(s.signed_function, s.box_lo, s.box_hi,
                                   cell_size_for_triangle_count(s.signed_function, s.box_lo, s.box_hi, 12000));
  }();
  return mesh;
}

}  // namespace

TEST_CASE("prepare_mesh repairs a segmentation-like liver in millimetres, the same mesh bit for bit twice", "[prepare]") {
  skip_without_preparation();
  const TriangleMesh input = segmentation_like(liver_sample(), 21);
  MeshPreparationOptions o = options();
  o.scale = 1e-3;
  const PreparedMesh p = prepare_checked(input, o);
  const MeshPreparationReport& r = p.report;
  const SegmentationDefects injected;
  CHECK(r.defects.degenerate_faces == injected.degenerate_faces);
  CHECK(r.defects.flipped_faces == injected.flipped_faces);
  CHECK(r.defects.holes >= 1);
  CHECK(r.defects.non_manifold_edges == 1);
  CHECK(r.defects.self_intersections > 0);
  CHECK(r.rebuilt);
  CHECK(r.bodies_dropped == 1);  // the speck
  // The speck: segmentation_like's last 80 faces (add_speck's icosphere), in millimetres. Dropped
  // after the rebuild, as wrapped: a convex body grown by at most the wrap's offset all round.
  const TriangleMesh speck(1e-3 * input.vertices(), input.faces().bottomRows(80));
  const double speck_radius = std::cbrt(3.0 * speck.enclosed_volume() / (4.0 * kPi));
  CHECK(r.dropped_volume > speck.enclosed_volume());
  CHECK(r.dropped_volume < speck.enclosed_volume() * std::pow(1.0 + 1.5 * r.wrap_offset / speck_radius, 3));
  // The wrap lies alpha/20 outside, the remesh inscribes 800 flat elements: the clean liver's
  // volume within 3 %, the distance (the poked spike included) within 5 % of the diagonal.
  CHECK(p.mesh.enclosed_volume() == Approx(liver_sample().enclosed_volume()).epsilon(0.03));
  CHECK(std::abs(r.volume_change) < 0.03);
  CHECK(r.hausdorff_relative < 0.05);
  const Vec3 size = p.mesh.bounding_box().col(1) - p.mesh.bounding_box().col(0);
  const Vec3 clean = liver_sample().bounding_box().col(1) - liver_sample().bounding_box().col(0);
  CHECK((size - clean).norm() < 0.03 * clean.norm());  // metres, and the speck is gone

  const PreparedMesh again = prepare_mesh(input, o);
  REQUIRE(again.mesh.num_vertices() == p.mesh.num_vertices());
  REQUIRE(again.mesh.num_elements() == p.mesh.num_elements());
  CHECK((again.mesh.faces().array() == p.mesh.faces().array()).all());
  CHECK((again.mesh.vertices().array() == p.mesh.vertices().array()).all());  // exact, not approximate
  CHECK(again.report.hausdorff == r.hausdorff);
}

TEST_CASE("prepare_mesh keeps a surface of fewer faces than the default target and remeshes a tetrahedron to a target", "[prepare]") {
  testing::skip_unless(mesh_preparation_available(), "this build has no mesh preparation (BEMSURG_WITH_PREPARE: CGAL and Gmsh)");
  RowMatrixX3d V(4, 3);
  V << 0, 0, 0, 0.1, 0, 0, 0, 0.1, 0, 0, 0, 0.1;
  RowMatrixX3i F(4, 3);
  F << 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3;
  const TriangleMesh tet(V, F);
  MeshPreparationOptions o;
  o.scale_given = true;
  const PreparedMesh kept = prepare_mesh(tet, o);  // the default never adds elements
  CHECK(kept.report.remesh == "none");
  CHECK(kept.mesh.num_elements() == 4);
  CHECK(kept.mesh.enclosed_volume() == Approx(0.1 * 0.1 * 0.1 / 6.0).epsilon(1e-12));
  // Four faces alone kept Gmsh's reparametrisation from finishing; they are split first.
  o.target_elements = 200;
  const PreparedMesh remeshed = prepare_mesh(tet, o);
  CHECK(remeshed.report.remesh == "uniform");
  CHECK(remeshed.report.target_elements == 200);
  CHECK(remeshed.mesh.num_elements() == Approx(200).epsilon(0.2));
  CHECK(remeshed.mesh.enclosed_volume() == Approx(0.1 * 0.1 * 0.1 / 6.0).epsilon(0.02));
  CHECK(remeshed.report.hausdorff_relative < 1e-6);  // the flat faces are remeshed on themselves
  // Without a target the remesh aims at default_elements (3,000, or 6,000 for the hierarchical
  // backend): a smaller default remeshes a surface the dense default would keep.
  CHECK(kDefaultPreparedElementsHierarchical > kDefaultPreparedElements);
  const TriangleMesh ellipsoid = ellipsoid_mesh(kCenter, kAxes, 3);  // 1,280 faces
  MeshPreparationOptions d;
  d.scale_given = true;
  CHECK(prepare_mesh(ellipsoid, d).report.remesh == "none");
  d.default_elements = 400;
  const PreparedMesh coarser = prepare_mesh(ellipsoid, d);
  CHECK(coarser.report.remesh == "uniform");
  CHECK(coarser.report.target_elements == 400);
  CHECK(coarser.mesh.num_elements() == Approx(400).epsilon(0.2));
  d.default_elements = 0;
  CHECK_THROWS_WITH(prepare_mesh(ellipsoid, d), Catch::Contains("default target"));
}
