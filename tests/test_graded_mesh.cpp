// Graded remeshing, operating regions and the brain model (mesh/graded_remesher.hpp,
// mesh/operating_region.hpp, mesh/brain_model.hpp, docs/graded.md): graded meshes are closed,
// oriented, well shaped and graded within the stated bound; creases are kept; in the operating
// region a graded model answers a tool like a uniformly fine one; bad input is refused by name.
// Self-intersection is checked with mesh/self_intersection.hpp on the input brain (free of it by
// construction: a radial graph) and on every remeshed surface.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <set>
#include <string>

#include "bemsurg/io/element_selector.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/mesh/brain_model.hpp"
#include "bemsurg/mesh/liver_model.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/meshing/graded_remesher.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/meshing/planar_regions.hpp"
#include "support/skip.hpp"
#include "support/studies/graded_comparison.hpp"
#include "support/temp_dir.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;
namespace fs = std::filesystem;

namespace {

using bemsurg_test::kEps;

const fs::path kScenes = fs::path(__FILE__).parent_path().parent_path() / "examples" / "scenes";

GradedRemeshOptions lengths(double inside, double outside) {
  GradedRemeshOptions o;
  o.inside_edge_length = inside;
  o.outside_edge_length = outside;
  return o;
}

BrainModelOptions test_brain() {
  return BrainModelOptions();  // subdivisions 5: 20480 faces
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) { return e.what(); }
  return "NO EXCEPTION";
}

std::string scene_error(const std::string& json) {
  try {
    load_scene_from_string(json, ".", "test.json");
  } catch (const SceneError& e) { return e.what(); } catch (const std::exception& e) {
    return std::string("WRONG EXCEPTION TYPE: ") + e.what();
  }
  return "NO EXCEPTION";
}

// A 10 x 10 x 5 cm box scene with an operating region given as JSON text.
std::string box_scene(const std::string& region) {
  return R"({"mesh": {"generator": "box", "min": [-0.05, -0.05, 0], "max": [0.05, 0.05, 0.05], "divisions": [4, 4, 2]},
             "material": {"young_modulus": 3000, "poisson_ratio": 0.45},
             "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]},
             "operating_region": )" +
         region + "}";
}

}  // namespace

TEST_CASE("The liver model is a valid, deterministic surface that holds both lobes and stays within the smooth union's bound",
          "[graded][liver]") {
  const LiverModelOptions o{Vec3(0.2, 0.15, 0.1), 3};
  const TriangleMesh a = liver_mesh(o), b = liver_mesh(o);
  REQUIRE_NOTHROW(require_valid_mesh(a));
  CHECK(find_self_intersections(a).empty());
  CHECK(a.vertices() == b.vertices());  // bit for bit
  // Every vertex is the surface point of its own direction (the radial graph, outward).
  for (Index v = 0; v < a.num_vertices(); v += 37)
    CHECK((liver_surface_point(o, a.vertex(v)) - a.vertex(v)).norm() <= 8 * kEps * a.vertex(v).norm());
  // R = (R1^6 + R2^6)^(1/6) lies between max(R1, R2) and 2^(1/6) max(R1, R2): the body holds each
  // lobe's ellipsoid and lies within 2^(1/2) times their union's volume. The lobes' volumes (the
  // semi-axes of liver_model_impl.hpp, as fractions of the size) bound the mesh's volume, less the
  // inscribed polyhedron's shortfall at 3 subdivisions (a few %).
  const double v1 = 4.0 / 3.0 * M_PI * (0.38 * 0.2) * (0.48 * 0.15) * (0.44 * 0.1);
  const double v2 = 4.0 / 3.0 * M_PI * (0.32 * 0.2) * (0.34 * 0.15) * (0.26 * 0.1);
  const double volume = a.enclosed_volume();
  CHECK(volume > 0.95 * std::max(v1, v2));
  CHECK(volume < std::sqrt(2.0) * (v1 + v2));
  CHECK(volume > 1.05 * v1);  // the left lobe adds to the right one
  CHECK_THROWS_AS(liver_mesh(LiverModelOptions{Vec3(0.2, -0.1, 0.1), 3}), InvalidMeshError);
  CHECK_THROWS_AS(liver_mesh(LiverModelOptions{Vec3(0.2, 0.15, 0.1), 8}), InvalidMeshError);
}

TEST_CASE("The brain model is a valid, deterministic, mirror-symmetric surface with a fissure and a flat underside", "[graded][brain]") {
  const BrainModelOptions o = test_brain();
  const TriangleMesh a = brain_mesh(o), b = brain_mesh(o);
  REQUIRE_NOTHROW(require_valid_mesh(a));
  CHECK(find_self_intersections(a).empty());
  CHECK(a.vertices() == b.vertices());  // bit for bit
  CHECK(a.faces() == b.faces());
  // Two hemispheres: the vertex set maps onto itself under y -> -y (icosphere and radial function
  // are both symmetric); checked for every vertex against its nearest mirror image.
  double worst = 0.0;
  for (Index v = 0; v < a.num_vertices(); ++v) {
    Vec3 m = a.vertex(v);
    m.y() = -m.y();
    double best = 1e300;
    for (Index w = 0; w < a.num_vertices(); ++w) best = std::min(best, (a.vertex(w) - m).norm());
    worst = std::max(worst, best);
  }
  // Measured 0: every vertex's mirror image comes from the same operations with y negated (odd and
  // even functions of y), exact in floating point; bound a few roundings of the largest coordinate.
  CHECK(worst <= 16.0 * kEps * a.vertices().cwiseAbs().maxCoeff());
  // The underside lies on z = 0 and is flat; the top of a hemisphere stands well above the fissure.
  const auto box = a.bounding_box();
  CHECK(box(2, 0) == 0.0);
  CHECK(box(2, 1) == Approx(o.size.z()).epsilon(0.08));  // measured 2.6 % below
  double flat_area = 0.0;
  for (Index e = 0; e < a.num_elements(); ++e)
    if (a.normal(e).z() < -0.999999) flat_area += a.area(e);
  CHECK(flat_area > 0.4 * M_PI * 0.25 * o.size.x() * o.size.y());  // the rim lies at 0.87 of the semi-axes (measured 0.68)
  const double fissure_top = brain_surface_point(o, Vec3(0, 0, 1)).z();
  const double hemisphere_top = brain_surface_point(o, Vec3(0.1, 0.45, 1.0)).z();
  CHECK(hemisphere_top - fissure_top > 0.008);  // a groove of more than 8 mm (measured 9.7 mm)
  CHECK_THROWS_WITH(brain_mesh([] {
                      BrainModelOptions x;
                      x.size.y() = -1;
                      return x;
                    }()),
                    Catch::Contains("size must be three positive lengths"));
}

TEST_CASE("A graded remesh of the brain is closed, oriented, well shaped and graded within the stated bound", "[graded]") {
  testing::skip_unless(graded_remesher_available(), "this build has no graded remesher (BEMSURG_WITH_REMESHER=OFF)");
  const BrainModelOptions bo = test_brain();
  const TriangleMesh input = brain_mesh(bo);
  const Vec3 top = brain_surface_point(bo, Vec3(0.1, 0.45, 1.0));
  const OperatingRegion region = OperatingRegion::sphere(top, 0.025);
  const GradedRemeshOptions o = lengths(0.01, 0.03);
  const GradedRemeshResult r = graded_remesh(input, region, o);
  REQUIRE_NOTHROW(require_valid_mesh(r.mesh));
  const MeshTopology topo(r.mesh);
  CHECK(topo.num_shells() == 1);
  CHECK(topo.is_closed_and_oriented());
  CHECK(find_self_intersections(r.mesh).empty());
  // Coarse (30 mm) chords cut the folds and the curvature: measured 6.3 % less volume.
  CHECK(r.mesh.enclosed_volume() == Approx(input.enclosed_volume()).epsilon(0.09));
  // Shape: Frontal-Delaunay gives ~30 degrees at worst (measured 30-33).
  CHECK(r.quality.min_angle_degrees > 22.0);
  CHECK(r.quality.fraction_below_20_degrees == 0.0);
  // Grading: neighbouring sizes differ by at most 1.6 (growth 1.25 asked; measured max 1.42-1.51,
  // 99th percentile 1.25-1.35; a uniform Gmsh mesh has the same spread).
  CHECK(r.quality.max_neighbour_size_ratio < 1.6);
  CHECK(r.quality.p99_neighbour_size_ratio < 1.45);
  // Sizes follow the target function h(x): inside the region, and far from it (d > 6 cm, where
  // h is 2.5-3 cm), the mean element size is within 25 % of the mean target at the centroids.
  double inside = 0.0, far = 0.0, far_target = 0.0;
  int n_inside = 0, n_far = 0;
  for (Index e = 0; e < r.mesh.num_elements(); ++e) {
    const double d = region.distance(r.mesh.centroid(e));
    if (d == 0.0) inside += element_size(r.mesh, e), ++n_inside;
    if (d > 0.06) far += element_size(r.mesh, e), far_target += graded_target_size(region, o, r.mesh.centroid(e)), ++n_far;
  }
  REQUIRE(n_inside > 10);
  REQUIRE(n_far > 10);
  CHECK(inside / n_inside == Approx(o.inside_edge_length).epsilon(0.03));  // measured 1.0 % below
  CHECK(far / n_far == Approx(far_target / n_far).epsilon(0.25));          // measured 11 % below
  CHECK(far / n_far > 2.0 * o.inside_edge_length);
}

TEST_CASE("A graded remesh keeps the creases of a box and both shells of a hollow sphere", "[graded]") {
  testing::skip_unless(graded_remesher_available(), "this build has no graded remesher (BEMSURG_WITH_REMESHER=OFF)");
  const TriangleMesh box = box_mesh(Vec3(-0.05, -0.05, 0), Vec3(0.05, 0.05, 0.05), 4, 4, 2);
  const GradedRemeshResult r = graded_remesh(box, OperatingRegion::sphere(Vec3(0, 0, 0.05), 0.015), lengths(0.006, 0.02));
  REQUIRE_NOTHROW(require_valid_mesh(r.mesh));
  // Edges and corners kept: the volume of a polyhedron with the box's faces is the box's, exactly
  // up to rounding, and the bounding box is unchanged.
  CHECK(find_self_intersections(r.mesh).empty());
  // Round-off: the origin lies on the box, so every face's signed tetrahedron volume is >= 0 and the
  // N-term sum is within ~N eps of the box's (measured 4.3e-16 relative). Gmsh's parametrisation puts
  // the vertices within a few roundings of the box's planes (measured 1 ulp of 0.05): bound 64 eps
  // of the box's size 0.1.
  CHECK(r.mesh.enclosed_volume() == Approx(0.1 * 0.1 * 0.05).epsilon(static_cast<double>(r.mesh.num_elements()) * kEps));
  CHECK((r.mesh.bounding_box() - box.bounding_box()).cwiseAbs().maxCoeff() < 64.0 * kEps * 0.1);
  CHECK(r.quality.max_neighbour_size_ratio < 1.6);

  const TriangleMesh hollow = hollow_sphere_mesh(Vec3::Zero(), 0.02, 0.04, 3, 3);
  const GradedRemeshResult h = graded_remesh(hollow, OperatingRegion::sphere(Vec3(0, 0, 0.04), 0.01), lengths(0.005, 0.012));
  REQUIRE_NOTHROW(require_valid_mesh(h.mesh));  // includes: the cavity's normals point into it
  const MeshTopology topo(h.mesh);
  CHECK(topo.num_shells() == 2);
  CHECK(find_self_intersections(h.mesh).empty());
  CHECK(h.mesh.enclosed_volume() == Approx(hollow.enclosed_volume()).epsilon(0.03));
}

namespace {

// A ball of radius r cut by the plane z = cut: an icosphere whose vertices below the plane are
// projected onto it, so the flat face's rim runs along the icosphere's edges in a zigzag and many
// triangles along it rise only a few degrees from the face.
TriangleMesh cut_ball(double r, double cut, int subdivisions) {
  const TriangleMesh ball = icosphere_mesh(Vec3::Zero(), r, subdivisions);
  RowMatrixX3d v = ball.vertices();
  for (Index i = 0; i < v.rows(); ++i) v(i, 2) = std::max(v(i, 2), cut);
  return TriangleMesh(v, ball.faces());
}

// The area of the elements whose three corners lie within `tolerance` of the plane z = z0.
double area_on_plane_z(const TriangleMesh& m, double z0, double tolerance) {
  double area = 0.0;
  for (Index e = 0; e < m.num_elements(); ++e) {
    bool on = true;
    for (int k = 0; k < 3; ++k) on = on && std::abs(m.vertices()(m.faces()(e, k), 2) - z0) <= tolerance;
    if (on) area += m.area(e);
  }
  return area;
}

double selected_area(const TriangleMesh& m, const ElementSelector& s) {
  double area = 0.0;
  for (const Index e : select_elements(m, s)) area += m.area(e);
  return area;
}

}  // namespace

TEST_CASE("Planar regions are the flat faces of a box, and a faceted sphere has none", "[graded][planar]") {
  const TriangleMesh box = box_mesh(Vec3(-0.05, -0.05, 0), Vec3(0.05, 0.05, 0.05), 4, 4, 2);
  const std::vector<PlanarRegion> faces = find_planar_regions(box);
  REQUIRE(faces.size() == 6u);
  Index counted = 0;
  for (const PlanarRegion& f : faces) {
    // Each region is one side of the box: an axis normal, the side's offset and area.
    const Eigen::Index axis = [&] {
      Eigen::Index i = 0;
      f.normal.cwiseAbs().maxCoeff(&i);
      return i;
    }();
    CHECK(std::abs(f.normal(axis)) == Approx(1.0).epsilon(kEps));
    const double side = f.normal(axis) > 0.0 ? box.bounding_box()(axis, 1) : -box.bounding_box()(axis, 0);
    CHECK(f.offset == Approx(side).margin(4 * kEps));
    const double expected_area = (axis == 2 ? 0.1 * 0.1 : 0.1 * 0.05);
    CHECK(f.area == Approx(expected_area).epsilon(16 * kEps));
    counted += static_cast<Index>(f.faces.size());
  }
  CHECK(counted == box.num_elements());
  // An icosphere's neighbouring faces meet at a few degrees: no two are coplanar.
  CHECK(find_planar_regions(icosphere_mesh(Vec3::Zero(), 0.05, 4)).empty());
  // The cut ball: one region, exactly the input's faces on the plane.
  const TriangleMesh cut = cut_ball(0.05, -0.03, 4);
  const std::vector<PlanarRegion> disc = find_planar_regions(cut);
  REQUIRE(disc.size() == 1u);
  CHECK(disc[0].normal.z() == Approx(-1.0).epsilon(kEps));
  CHECK(disc[0].area == Approx(area_on_plane_z(cut, -0.03, 0.0)).epsilon(1e-12));
}

TEST_CASE("A graded remesh keeps the flat face of a cut ball flat up to its rim", "[graded][planar]") {
  testing::skip_unless(graded_remesher_available(), "this build has no graded remesher (BEMSURG_WITH_REMESHER=OFF)");
  const double r = 0.05, cut = -0.6 * r;
  const TriangleMesh input = cut_ball(r, cut, 5);
  // The reference is the input's own flat face (a polygon inscribed in the disc of radius 0.8 r).
  const double flat = area_on_plane_z(input, cut, 0.0);
  REQUIRE(flat == Approx(numbers::pi * 0.64 * r * r).epsilon(0.03));
  const OperatingRegion top = OperatingRegion::sphere(Vec3(0, 0, r), 0.3 * r);
  GradedRemeshOptions o = lengths(0.1 * r, 0.3 * r);
  o.keep_planar_regions = true;
  const auto fractions = [&](const GradedRemeshOptions& options) {
    const GradedRemeshResult g = graded_remesh(input, top, options);
    CHECK_NOTHROW(require_valid_mesh(g.mesh));
    CHECK(find_self_intersections(g.mesh).empty());
    CHECK(g.quality.min_angle_degrees > 22.0);
    return std::make_pair(area_on_plane_z(g.mesh, cut, 1e-9 * r) / flat,
                          selected_area(g.mesh, ElementSelector::normal_direction(-Vec3::UnitZ(), 0.99)) / flat);
  };
  // Default: the rim is resampled at the size function's 0.3 r, and the chords leave the sliver
  // between them and the rim to the sides (a 17-gon inscribed in a circle loses 2.3 %).
  const auto plain = fractions(o);
  INFO("default: on the plane " << plain.first << ", normal rule " << plain.second);
  CHECK(plain.first > 0.97);  // measured 0.983
  CHECK(plain.first <= 1.0);
  CHECK(plain.second == Approx(plain.first).epsilon(1e-12));  // no element off the plane is within 8 degrees of it
  // The rim meshed for a 0.5 % loss: the acceptance of issue 38, within 1 %.
  o.planar_rim_area_loss = 0.005;
  const auto fine_rim = fractions(o);
  INFO("rim for 0.5 %: on the plane " << fine_rim.first << ", normal rule " << fine_rim.second);
  CHECK(std::abs(fine_rim.first - 1.0) < 0.01);
  CHECK(std::abs(fine_rim.second - 1.0) < 0.01);
}

TEST_CASE("A graded remesh of the brain keeps its underside flat up to its rim", "[graded][planar]") {
  testing::skip_unless(graded_remesher_available(), "this build has no graded remesher (BEMSURG_WITH_REMESHER=OFF)");
  const TriangleMesh input = brain_mesh(test_brain());
  const double flat = area_on_plane_z(input, 0.0, 0.0);
  // The brain scene's region and lengths (examples/scenes/brain.json) and its support selector.
  const OperatingRegion region = OperatingRegion::sphere(Vec3(0.0053, 0.024, 0.0817), 0.02);
  GradedRemeshOptions o = lengths(0.006, 0.018);
  o.keep_planar_regions = true;
  const auto held_fraction = [&](const GradedRemeshOptions& options) {
    const GradedRemeshResult g = graded_remesh(input, region, options);
    CHECK_NOTHROW(require_valid_mesh(g.mesh));
    CHECK(g.quality.min_angle_degrees > 22.0);
    const double held = selected_area(g.mesh, ElementSelector::plane(Vec3::Zero(), Vec3::UnitZ(), 1e-6)) / flat;
    CHECK(area_on_plane_z(g.mesh, 0.0, 0.0) / flat == Approx(held).epsilon(1e-12));  // held elements lie exactly on z = 0
    return held;
  };
  const double plain = held_fraction(o);
  o.planar_rim_area_loss = 0.005;
  const double fine_rim = held_fraction(o);
  INFO("held: default " << plain << ", rim for 0.5 % " << fine_rim);
  CHECK(plain > 0.985);  // measured 0.991 (before issue 38: 0.71, the rim rounded off)
  CHECK(plain <= 1.0);
  CHECK(std::abs(fine_rim - 1.0) < 0.01);
}

TEST_CASE("In the operating region a graded brain answers a sphere tool like a uniformly fine one", "[graded][contact]") {
  testing::skip_unless(graded_remesher_available(), "this build has no graded remesher (BEMSURG_WITH_REMESHER=OFF)");
  BrainModelOptions bo = test_brain();
  bo.fold_amplitude = 0.0;  // at test sizes (9 mm) the folds are not resolved; see docs/graded.md
  const TriangleMesh input = brain_mesh(bo);
  const graded::PressCase c = graded::brain_press_case(bo);
  const OperatingRegion region = OperatingRegion::sphere(c.region_center, c.region_radius);
  // The reference is uniformly finer than the graded mesh's finest (6.5 against 9 mm): at 9 mm the
  // tool touches a handful of elements and a uniform 9 mm reference was itself 25 % off the 6.5 mm
  // one once the held underside kept its rim (issue 38).
  const TriangleMesh fine = graded_remesh(input, region, lengths(0.0065, 0.0065)).mesh;
  const TriangleMesh grad = graded_remesh(input, region, lengths(0.009, 0.018)).mesh;
  REQUIRE(grad.num_elements() < fine.num_elements() / 4);
  CHECK(find_self_intersections(fine).empty());
  CHECK(find_self_intersections(grad).empty());
  const graded::PressResult rf = graded::press(fine, c);
  const graded::PressResult rg = graded::press(grad, c);
  const double force = (rg.force - rf.force).norm() / rf.force.norm();
  const double disp = graded::region_displacement_difference(fine, rf, grad, rg, c);
  INFO("force fine " << rf.force.transpose() << " graded " << rg.force.transpose() << ", force difference " << force
                     << ", displacement difference " << disp);
  CHECK(rf.force.z() > 0.0);
  // The differences are mostly discretisation noise of a tool touching few elements (at 7 mm,
  // bench_graded: force 2-3 %).
  CHECK(force < 0.10);  // measured 0.071
  CHECK(disp < 0.12);   // measured 0.084 (relative L2 over the region)
}

TEST_CASE("The remesher refuses bad input with messages that name the problem", "[graded][errors]") {
  const TriangleMesh box = box_mesh(Vec3(-0.05, -0.05, 0), Vec3(0.05, 0.05, 0.05), 4, 4, 2);
  const OperatingRegion top = OperatingRegion::sphere(Vec3(0, 0, 0.05), 0.015);
  CHECK_THAT(error_of([&] { graded_remesh(box, OperatingRegion::sphere(Vec3(1, 1, 1), 0.01), lengths(0.005, 0.02)); }),
             Catch::Contains("does not meet the surface of the body"));
  CHECK_THAT(error_of([&] { graded_remesh(box, top, lengths(0.0, 0.02)); }),
             Catch::Contains("inside_edge_length must be a positive length"));
  CHECK_THAT(error_of([&] { graded_remesh(box, top, lengths(0.005, -1.0)); }),
             Catch::Contains("outside_edge_length must be a positive length"));
  CHECK_THAT(error_of([&] { graded_remesh(box, top, lengths(0.02, 0.005)); }), Catch::Contains("is larger than outside_edge_length"));
  // An open surface: the box without its last face.
  const TriangleMesh open(box.vertices(), box.faces().topRows(box.num_elements() - 1));
  CHECK_THAT(error_of([&] { graded_remesh(open, top, lengths(0.005, 0.02)); }),
             Catch::Contains("not a closed, oriented mesh") && Catch::Contains("not closed"));
  CHECK_THAT(error_of([&] { OperatingRegion::element_set(box, {0, 999}); }), Catch::Contains("element 999"));
  // Gmsh's own failures (it throws std::string) arrive as bemsurg::Error with its message: here the
  // brain at subdivision 4 with crease detection only, whose jagged rim breaks Gmsh's patch
  // parametrisation.
  if (graded_remesher_available()) {
    BrainModelOptions coarse;
    coarse.subdivisions = 4;
    const TriangleMesh b = brain_mesh(coarse);
    const OperatingRegion on_top = OperatingRegion::sphere(brain_surface_point(coarse, Vec3(0.1, 0.45, 1.0)), 0.025);
    GradedRemeshOptions crease_only = lengths(0.012, 0.03);
    crease_only.keep_planar_regions = false;
    CHECK_THROWS_AS(graded_remesh(b, on_top, crease_only), Error);
    // With its underside handed to Gmsh as a flat face of its own, it remeshes.
    GradedRemeshOptions planar = crease_only;
    planar.keep_planar_regions = true;
    CHECK_NOTHROW(require_valid_mesh(graded_remesh(b, on_top, planar).mesh));
  }
}

TEST_CASE("The scene's operating_region is checked key by key", "[graded][scene][errors]") {
  CHECK_THAT(scene_error(box_scene(R"({"sphere": {"center": [1, 1, 1], "radius": 0.01}})")),
             Catch::StartsWith("operating_region: sphere") && Catch::Contains("does not meet the surface"));
  CHECK_THAT(scene_error(box_scene(
                 R"({"sphere": {"center": [0, 0, 0.05], "radius": 0.01}, "inside_edge_length": 0, "outside_edge_length": 0.02})")),
             Catch::StartsWith("operating_region.inside_edge_length: must be positive"));
  CHECK_THAT(scene_error(box_scene(
                 R"({"sphere": {"center": [0, 0, 0.05], "radius": 0.01}, "inside_edge_length": 0.03, "outside_edge_length": 0.01})")),
             Catch::StartsWith("operating_region.inside_edge_length: is larger than operating_region.outside_edge_length"));
  CHECK_THAT(scene_error(box_scene(R"({"sphere": {"center": [0, 0, 0.05], "radius": 0.01}, "inside_edge_length": 0.01})")),
             Catch::StartsWith("operating_region.outside_edge_length: missing"));
  CHECK_THAT(scene_error(box_scene(R"({"box": {"min": [0, 0, 0], "max": [0, 1, 1]}})")),
             Catch::StartsWith("operating_region.box.max: must exceed"));
  CHECK_THAT(scene_error(box_scene(R"({"elements": [0, 999]})")),
             Catch::StartsWith("operating_region.elements[1]: element 999 out of range"));
  CHECK_THAT(scene_error(box_scene(R"({"sphere": {"center": [0, 0, 0.05], "radius": 0.01}, "box": {"min": [0, 0, 0], "max": [1, 1, 1]}})")),
             Catch::StartsWith("operating_region: expected exactly one of"));
  CHECK_THAT(scene_error(box_scene(
                 R"({"sphere": {"center": [0, 0, 0.05], "radius": 0.01}, "inside_edge_length": 1e-5, "outside_edge_length": 0.02})")),
             Catch::StartsWith("operating_region.inside_edge_length: would give about"));
  // Only the held bottom inside the region: nothing for a table.
  CHECK_THAT(scene_error(box_scene(R"({"box": {"min": [-0.01, -0.01, -0.001], "max": [0.01, 0.01, 0.001]}})")),
             Catch::StartsWith("operating_region: holds no free element"));
}

TEST_CASE("The cuboid scene's operating region is its top face and feeds the Green's table region", "[graded][scene]") {
  const Scene s = load_scene((kScenes / "cuboid.json").string());
  CHECK_FALSE(s.graded);
  REQUIRE(s.has_operating_region);
  CHECK(s.operating_elements.size() == 72u);  // 6 x 6 quads on top, two triangles each
  for (Index e : s.operating_elements)
    CHECK(s.problem.mesh.centroid(e).z() == Approx(0.05).epsilon(4.0 * kEps));  // (3 x 0.05) / 3: measured 0.6 eps
  GreensTableOptions options;
  options.region = s.operating_elements;
  const BoundaryConditions& bc = s.problem.boundary_conditions;
  const GreensTable table = GreensTable::compute(s.problem.mesh, s.problem.material, bc, options);
  CHECK(table.region() == s.operating_elements);
  CHECK(table.columns().cols() == 3 * 72);
}

TEST_CASE("The brain scene is graded around its operating region and held on its underside", "[graded][scene]") {
  const Scene s = load_scene((kScenes / "brain.json").string());
  REQUIRE(s.has_operating_region);
  CHECK(s.graded == graded_remesher_available());
  // Graded, the brain is held on an underside meshed far coarser than its operating region: the
  // safe-grading rule (docs/graded.md#safe-gradings, docs/stability.md (i)) warns about exactly that.
  // Without the remesher the one warning says the mesh is not graded.
  REQUIRE(s.warnings.size() == 1);
  CHECK((s.warnings[0].find("displacement-prescribed (supported) elements") != std::string::npos) == graded_remesher_available());
  REQUIRE_NOTHROW(require_valid_mesh(s.problem.mesh));
  CHECK(find_self_intersections(s.problem.mesh).empty());
  if (s.graded) {
    CHECK(s.problem.mesh.num_elements() < 1200);  // test-sized: precompute in seconds (measured 680)
    CHECK(s.mesh_quality.max_neighbour_size_ratio < 1.6);
  }
  REQUIRE_FALSE(s.operating_elements.empty());
  for (Index e : s.operating_elements) {
    CHECK(s.operating_region.distance(s.problem.mesh.centroid(e)) == 0.0);
    CHECK(s.problem.boundary_conditions.is_free(e));
  }
  Index held = 0;
  for (Index e = 0; e < s.problem.mesh.num_elements(); ++e)
    if (!s.problem.boundary_conditions.is_free(e)) {
      ++held;
      CHECK(std::abs(s.problem.mesh.centroid(e).z()) < 64.0 * kEps * 0.1);  // on z = 0: measured 0
    }
  CHECK(held > 20);  // measured 70
}

TEST_CASE("The thin-part warning judges the graded mesh solved, not the file read, and names its elements", "[graded][scene]") {
  testing::skip_unless(graded_remesher_available(), "this build has no graded remesher (BEMSURG_WITH_REMESHER=OFF)");
  // A plate 10 x 10 x 1 cm read from a file in 2 x 2 x 1 divisions: elements of size 5 cm over a
  // 1 cm thickness, thin as read.
  bemsurg_test::TempDir dir("bemsurg_test_graded_thin_");
  const TriangleMesh plate = box_mesh(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.01), 2, 2, 1);
  write_obj(dir.file("plate.obj"), plate);
  const ThinElements as_read = find_thin_elements(plate);
  REQUIRE(as_read.count == 16u);  // top and bottom
  CHECK(as_read.size == Approx(0.05).epsilon(1e-12));
  const auto load = [&](const std::string& region) {
    return load_scene_from_string(R"({"mesh": {"file": "plate.obj"}, "material": {"young_modulus": 3000, "poisson_ratio": 0.45},
      "boundary_conditions": {"rules": [{"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]},
      "operating_region": )" + region +
                                      "}",
                                  dir.path.string(), "plate.json");
  };
  const auto thin_warning = [](const Scene& s) {
    for (const std::string& w : s.warnings)
      if (w.find("larger than the body is thick") != std::string::npos) return w;
    return std::string();
  };
  // Remeshed at 6 mm everywhere (elements ~5.6 mm across a 1 cm thickness): nothing to warn about.
  const Scene fine = load(R"({"sphere": {"center": [0.05, 0.05, 0.01], "radius": 0.02}, "inside_edge_length": 0.006,
                              "outside_edge_length": 0.006})");
  REQUIRE(fine.graded);
  CHECK(find_thin_elements(fine.problem.mesh).count == 0u);
  CHECK(thin_warning(fine).empty());
  // Fine (4 mm) around one corner, 4 cm elsewhere: the coarse part of the graded mesh is thin, and
  // the warning names the worst element of that mesh with its figures, and says which mesh it is.
  const Scene graded = load(R"({"sphere": {"center": [0.0, 0.0, 0.01], "radius": 0.02}, "inside_edge_length": 0.004,
                                "outside_edge_length": 0.04})");
  REQUIRE(graded.graded);
  const ThinElements solved = find_thin_elements(graded.problem.mesh);
  REQUIRE(solved.count > 0u);
  CHECK(solved.element < graded.problem.mesh.num_elements());
  CHECK(solved.count != as_read.count);  // not the file's elements
  CHECK(solved.size < 0.9 * as_read.size);
  CHECK(thin_warning(graded) == "mesh: " + thin_elements_warning(solved) + " (element numbers refer to the solved mesh, " +
                                    std::to_string(graded.problem.mesh.num_elements()) +
                                    " elements after the graded remesh, not to the input; bemsurg solve, press, cut and session "
                                    "write it to OUTDIR/solved_mesh.obj)");
}
