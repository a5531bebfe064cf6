// Generated segmentation surfaces (docs/organ-samples.md): the marching-tetrahedra sampler against
// a sphere's closed-form volume (and its order of convergence), the organ shapes' sizes and
// regions, each defect function creating its one kind of defect as validate_mesh, MeshTopology and
// find_self_intersections see it, and the STL, OFF and PLY writers read back by the readers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>

#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"
#include "bemsurg/meshing/implicit_surface.hpp"
#include "bemsurg/meshing/mesh_defects.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/meshing/organ_shapes.hpp"
#include "support/temp_dir.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {

using bemsurg_test::kPi;

/// The sampled kidney of about 6,000 triangles: a clean marching-cubes surface with its slivers.
const TriangleMesh& kidney_sample() {
  static const TriangleMesh mesh = [] {
    const OrganShape k = kidney_shape();
    return sample_implicit_surface(k.signed_function, k.box_lo, k.box_hi, 0.0028);
  }();
  return mesh;
}

/// Errors validate_mesh reports, by kind, leaving out the warnings.
std::map<MeshIssueKind, std::size_t> error_counts(const TriangleMesh& mesh) {
  const MeshValidationResult r = validate_mesh(mesh);
  std::map<MeshIssueKind, std::size_t> out;
  for (std::size_t k = 0; k < kNumMeshIssueKinds; ++k)
    if (r.counts[k] > 0 && static_cast<MeshIssueKind>(k) != MeshIssueKind::UnreferencedVertex)
      out[static_cast<MeshIssueKind>(k)] = r.counts[k];
  return out;
}

double sphere_volume_error(double radius, double cell) {
  // The box is offset from the centre so that the grid is not symmetric about it.
  const TriangleMesh m = sample_implicit_surface([radius](const Vec3& x) { return (x - Vec3(0.003, -0.002, 0.001)).norm() - radius; },
                                                 Vec3::Constant(-1.3 * radius), Vec3::Constant(1.3 * radius), cell);
  require_valid_mesh(m);
  return std::abs(m.enclosed_volume() - 4.0 / 3.0 * kPi * radius * radius * radius) / (4.0 / 3.0 * kPi * radius * radius * radius);
}

}  // namespace

TEST_CASE("sampling a sphere gives a valid closed outward mesh whose volume error falls as the cell size squared", "[organ_samples]") {
  const double r = 0.05;
  const double coarse = sphere_volume_error(r, r / 8.0), fine = sphere_volume_error(r, r / 16.0), finer = sphere_volume_error(r, r / 32.0);
  CHECK(coarse < 0.03);
  CHECK(finer < 0.002);
  const double order = std::log(coarse / finer) / std::log(4.0);  // over two halvings, so grid alignment averages out
  CHECK(order > 1.6);
  CHECK(order < 2.5);
  CHECK(fine < coarse);
}

TEST_CASE("a function that is zero at grid nodes still gives a valid mesh with no vertex on a node", "[organ_samples]") {
  // The cube |x|_inf = 0.5 with cell 0.125: its faces pass exactly through grid nodes.
  const ImplicitFunction cube = [](const Vec3& x) { return x.cwiseAbs().maxCoeff() - 0.5; };
  const TriangleMesh m = sample_implicit_surface(cube, Vec3::Constant(-0.75), Vec3::Constant(0.75), 0.125);
  require_valid_mesh(m);
  // Every vertex sits at least a hundredth of a grid edge (>= 0.125) from every node, and the zeros
  // count as outside: the body lies within the cube (its edges chamfered by the tetrahedra).
  double nearest = 1.0;
  for (Index v = 0; v < m.num_vertices(); ++v) {
    const Vec3 p = m.vertex(v);
    const Vec3 node = (p / 0.125).array().round().matrix() * 0.125;
    nearest = std::min(nearest, (p - node).norm());
  }
  CHECK(nearest >= 0.0099 * 0.125);
  CHECK(m.bounding_box().cwiseAbs().maxCoeff() < 0.5);
  CHECK(m.enclosed_volume() < 1.0);
  CHECK(m.enclosed_volume() > 0.9);
}

TEST_CASE("the sampler refuses a surface that leaves its box and a non-positive cell", "[organ_samples]") {
  const ImplicitFunction ball = [](const Vec3& x) { return x.norm() - 1.0; };
  CHECK_THROWS_WITH(sample_implicit_surface(ball, Vec3::Constant(-0.5), Vec3::Constant(2.0), 0.1),
                    Catch::Contains("on the boundary of the box is inside the surface"));
  CHECK_THROWS_AS(sample_implicit_surface(ball, Vec3::Constant(-2.0), Vec3::Constant(2.0), 0.0), InvalidArgumentError);
  CHECK(sample_implicit_surface([](const Vec3&) { return 1.0; }, Vec3::Zero(), Vec3::Ones(), 0.25).num_elements() == 0);
}

TEST_CASE("the cell size for a triangle count gives that count within 10 per cent", "[organ_samples]") {
  const OrganShape liver = liver_shape();
  const double h = cell_size_for_triangle_count(liver.signed_function, liver.box_lo, liver.box_hi, 20000);
  const Index n = sample_implicit_surface(liver.signed_function, liver.box_lo, liver.box_hi, h).num_elements();
  CHECK(std::abs(static_cast<double>(n) - 20000.0) < 2000.0);
}

TEST_CASE("the liver and kidney shapes are valid bodies of their documented sizes with regions on their surfaces", "[organ_samples]") {
  struct Case {
    OrganShape shape;
    Vec3 size;
  };
  for (const Case& c : {Case{liver_shape(), Vec3(0.2, 0.15, 0.1)}, Case{kidney_shape(), Vec3(0.06, 0.04, 0.11)}}) {
    const double h = 0.004 * c.size.minCoeff() / 0.04;
    const TriangleMesh m = sample_implicit_surface(c.shape.signed_function, c.shape.box_lo, c.shape.box_hi, h);
    require_valid_mesh(m);
    const Vec3 extent = m.bounding_box().col(1) - m.bounding_box().col(0);
    for (int k = 0; k < 3; ++k) {
      CHECK(extent(k) > 0.8 * c.size(k));
      CHECK(extent(k) < 1.1 * c.size(k));
    }
    // On the surface (bisected to machine precision), and near the sampled mesh's vertices.
    for (const Vec3& p : {c.shape.support_center, c.shape.operating_center}) {
      CHECK(std::abs(c.shape.signed_function(p)) < 1e-9);
      CHECK((m.vertices().rowwise() - p.transpose()).rowwise().norm().minCoeff() < 2.0 * h);
    }
    CHECK(c.shape.support_center.y() > 0.0);    // held from behind
    CHECK(c.shape.operating_center.y() < 0.0);  // worked on from the front
    CHECK(c.shape.support_radius > 0.0);
    CHECK(c.shape.operating_radius > 0.0);
  }
  // The hilum is carved out: the ellipsoid's medial extreme is outside the kidney, and the bean
  // encloses less than its ellipsoid.
  const OrganShape k = kidney_shape();
  CHECK(k.signed_function(Vec3(-0.029, 0.0, 0.0)) > 0.0);
  const double ellipsoid = 4.0 / 3.0 * kPi * 0.03 * 0.02 * 0.055;
  CHECK(kidney_sample().enclosed_volume() < 0.97 * ellipsoid);
  CHECK(kidney_sample().enclosed_volume() > 0.8 * ellipsoid);
}

TEST_CASE("each defect function creates its one kind of defect", "[organ_samples]") {
  const TriangleMesh& clean = kidney_sample();
  REQUIRE(error_counts(clean).empty());
  using K = MeshIssueKind;

  const TriangleMesh soup = unweld_mesh(clean);
  CHECK(error_counts(soup).count(K::DuplicateVertex) == 1);
  const TriangleMesh welded = weld_vertices(soup);
  CHECK(welded.num_vertices() == clean.num_vertices());
  CHECK(error_counts(welded).empty());

  CHECK(error_counts(add_degenerate_faces(clean, 4, 7)) == std::map<K, std::size_t>{{K::DegenerateFace, 4}});

  const auto flipped = error_counts(flip_face_patch(clean, 10, 7));
  CHECK(flipped.size() == 1);
  CHECK(flipped.count(K::InconsistentOrientation) == 1);

  const TriangleMesh holed = punch_hole(clean, 12, 7);
  const auto hole = error_counts(holed);
  REQUIRE(hole.size() == 1);
  CHECK(hole.at(K::BoundaryEdge) >= 12);
  CHECK(hole.at(K::BoundaryEdge) <= 16);
  // One loop: as many rim vertices as rim edges, each on two of them.
  const MeshTopology ht(holed);
  std::map<Index, int> rim_degree;
  for (Index e : ht.boundary_edges())
    for (Index v : ht.edge(e).vertices) ++rim_degree[v];
  CHECK(rim_degree.size() == hole.at(K::BoundaryEdge));
  for (const auto& [v, d] : rim_degree) CHECK(d == 2);

  const TriangleMesh poked = poke_through(clean, 7);
  CHECK(error_counts(poked) == std::map<K, std::size_t>{{K::SelfIntersection, error_counts(poked).at(K::SelfIntersection)}});
  const auto pairs = find_self_intersections(poked);
  REQUIRE(!pairs.empty());
  Index moved = -1;
  for (Index v = 0; v < clean.num_vertices(); ++v)
    if ((poked.vertex(v) - clean.vertex(v)).norm() > 0.0) moved = v;
  for (const auto& [f, g] : pairs) {
    const auto uses = [&](Index face) { return (poked.faces().row(face).array() == moved).any(); };
    CHECK(uses(f) != uses(g));  // a face of the spike against a face it shares no vertex with
  }

  const TriangleMesh finned = add_fin(clean, 7);
  CHECK(error_counts(finned) == std::map<K, std::size_t>{{K::NonManifoldEdge, 1}, {K::BoundaryEdge, 2}});
}

TEST_CASE("shell defects: a touching cone, an overlapping shell, a speck and nested cavities", "[organ_samples]") {
  const TriangleMesh& clean = kidney_sample();
  using K = MeshIssueKind;

  const TriangleMesh coned = add_touching_cone(clean, 3);
  CHECK(error_counts(coned).empty());  // a non-manifold vertex: invisible to the edge checks
  const MeshTopology ct(coned);
  REQUIRE(ct.num_shells() == 2);
  std::set<Index> shells_at_apex;
  const MeshTopology clean_topology(clean);
  for (Index v = 0; v < clean.num_vertices(); ++v)
    if (ct.vertex_faces(v).size() != clean_topology.vertex_faces(v).size())
      for (Index f : ct.vertex_faces(v)) shells_at_apex.insert(ct.shell_of_face(f));
  CHECK(shells_at_apex.size() == 2);

  const TriangleMesh overlapped = add_overlapping_ellipsoid(clean, 3);
  CHECK(error_counts(overlapped).count(K::SelfIntersection) == 1);
  CHECK(MeshTopology(overlapped).num_shells() == 2);

  const TriangleMesh specked = add_speck(clean, 1e-3);
  CHECK(error_counts(specked).empty());
  const MeshTopology st(specked);
  REQUIRE(st.num_shells() == 2);
  const std::vector<Index> bodies = shell_bodies(specked, st);
  CHECK(bodies[0] != bodies[1]);
  CHECK(st.shell_volume(1) / st.shell_volume(0) == Approx(1e-3).epsilon(1e-6));

  const Vec3 inside(0.012, 0.0, 0.0);
  const TriangleMesh hollow = add_cavity(clean, inside, 0.008, false);
  CHECK(error_counts(hollow).empty());
  CHECK(hollow.enclosed_volume() < clean.enclosed_volume());
  CHECK(error_counts(add_cavity(clean, inside, 0.008, true)) == std::map<K, std::size_t>{{K::InwardShell, 1}});

  const TriangleMesh mm = scale_mesh(clean, 1000.0);
  CHECK(mm.enclosed_volume() == Approx(1e9 * clean.enclosed_volume()).epsilon(1e-12));
  CHECK(error_counts(mm).empty());
}

TEST_CASE("segmentation_like mixes the defects in millimetres, the same for the same seed", "[organ_samples]") {
  const TriangleMesh& clean = kidney_sample();
  const TriangleMesh a = segmentation_like(clean, 11), b = segmentation_like(clean, 11);
  CHECK(a.vertices() == b.vertices());
  CHECK(a.faces() == b.faces());
  const auto errors = error_counts(a);
  CHECK(errors.at(MeshIssueKind::DegenerateFace) == 4);
  CHECK(errors.at(MeshIssueKind::BoundaryEdge) >= 14);  // the hole's rim and the fin's two free edges
  CHECK(errors.at(MeshIssueKind::NonManifoldEdge) == 1);
  CHECK(errors.at(MeshIssueKind::InconsistentOrientation) >= 3);
  CHECK(!find_self_intersections(a).empty());
  CHECK(MeshTopology(a).num_shells() >= 3);  // the body, the speck, the repeated-index faces
  const Vec3 extent = a.bounding_box().col(1) - a.bounding_box().col(0);
  CHECK(extent.z() > 100.0);  // millimetres: the kidney is 110 long
  CHECK(segmentation_like(clean, 12).vertices() != a.vertices());
}

TEST_CASE("write_stl binary and ASCII, write_off and write_ply read back as the same mesh", "[organ_samples]") {
  const bemsurg_test::TempDir dir("bemsurg_test_organ_io_");
  const TriangleMesh mm = scale_mesh(kidney_sample(), 1000.0);
  const std::string bin = dir.file("k.stl"), ascii = dir.file("k_ascii.stl"), off = dir.file("k.off"), ply = dir.file("k.ply");
  write_stl(bin, mm, true);
  write_stl(ascii, mm, false);
  CHECK(std::filesystem::file_size(bin) == 84 + 50 * static_cast<std::uintmax_t>(mm.num_elements()));
  for (const std::string& path : {bin, ascii}) {
    const TriangleMesh back = read_stl(path);
    REQUIRE(back.num_elements() == mm.num_elements());
    CHECK(back.num_vertices() == mm.num_vertices());  // welded back, no vertex lost or split
    double worst = 0.0;                               // the faces in the same order, each with the same corners
    for (Index f = 0; f < mm.num_elements(); ++f)
      for (int k = 0; k < 3; ++k) worst = std::max(worst, (back.corners(f)[k] - mm.corners(f)[k]).cwiseAbs().maxCoeff());
    CHECK(worst <= (path == bin ? 1e-5 : 0.0));  // float32 of coordinates below 64 mm: 4e-6 mm
  }
  write_off(off, mm);
  write_ply(ply, mm);
  for (const std::string& path : {off, ply}) {
    const TriangleMesh back = read_mesh(path);
    CHECK(back.vertices() == mm.vertices());
    CHECK(back.faces() == mm.faces());
  }
  CHECK_THROWS_WITH(write_mesh(dir.file("k.xyz"), mm), Catch::Contains("unknown mesh file extension '.xyz'"));
}
