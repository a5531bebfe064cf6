// Tests of MeshTopology and mesh validation: each kind of defect is found, reported with the
// offending face, edge, vertex or shell, and nothing is reported for good meshes (including a
// hollow sphere, whose cavity shell legitimately encloses a negative volume).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {

using bemsurg_test::kEps;

TriangleMesh with_faces(const TriangleMesh& mesh, const RowMatrixX3i& faces) { return TriangleMesh(mesh.vertices(), faces); }

/// Each face gets its own three vertices: what an STL file holds before welding.
TriangleMesh unweld(const TriangleMesh& mesh) {
  RowMatrixX3d V(3 * mesh.num_elements(), 3);
  RowMatrixX3i F(mesh.num_elements(), 3);
  for (Index f = 0; f < mesh.num_elements(); ++f)
    for (int k = 0; k < 3; ++k) {
      V.row(3 * f + k) = mesh.vertices().row(mesh.faces()(f, k));
      F(f, k) = static_cast<int>(3 * f + k);
    }
  return TriangleMesh(V, F);
}

bool has_kind(const MeshValidationResult& r, MeshIssueKind kind) { return r.count(kind) > 0; }

}  // namespace

TEST_CASE("MeshTopology of a closed sphere", "[mesh][topology]") {
  const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 2);
  const MeshTopology topo(sphere);
  CHECK(topo.num_faces() == sphere.num_elements());
  CHECK(topo.num_edges() == 3 * sphere.num_elements() / 2);
  CHECK(sphere.num_vertices() - topo.num_edges() + sphere.num_elements() == 2);  // Euler characteristic
  CHECK(topo.is_closed_and_oriented());
  CHECK(topo.boundary_edges().empty());
  CHECK(topo.non_manifold_edges().empty());
  REQUIRE(topo.num_shells() == 1);
  CHECK(topo.shell_is_closed_and_oriented(0));
  // Two sums of the same 320 terms, all positive (a sphere about the origin), in different orders:
  // they differ by <= N eps V (measured 2 eps).
  CHECK(topo.shell_volume(0) == Approx(sphere.enclosed_volume()).epsilon(static_cast<double>(sphere.num_elements()) * kEps));

  for (Index f = 0; f < topo.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index g = topo.neighbour(f, k);
      REQUIRE(g >= 0);
      const auto back = topo.neighbours(g);
      CHECK(std::count(back.begin(), back.end(), f) == 1);  // symmetric
      // The edge found by vertices is the face's edge, and it lists both faces, opposite directions.
      const Index a = sphere.faces()(f, k), b = sphere.faces()(f, (k + 1) % 3);
      const Index e = topo.find_edge(b, a);
      CHECK(e == topo.face_edge(f, k));
      CHECK(topo.edge(e).is_manifold_oriented());
    }
  CHECK(topo.find_edge(0, 0) == -1);
  // Every vertex of a subdivided icosahedron has five or six faces around it.
  for (Index v = 0; v < topo.num_vertices(); ++v) {
    const auto& around = topo.vertex_faces(v);
    CHECK((around.size() == 5 || around.size() == 6));
    for (Index f : around) CHECK((sphere.faces().row(f).array() == static_cast<int>(v)).any());
  }
}

TEST_CASE("winding number tells inside from outside", "[mesh][topology]") {
  const TriangleMesh sphere = icosphere_mesh(Vec3(1, 1, 1), 2.0, 2);
  const MeshTopology topo(sphere);
  // A sum of N = 320 solid angles over 4 pi whose absolute values add up to at most 4 pi (inside,
  // all one sign; outside, the near and far sides cancel, each <= 2 pi): summation <= N eps/2, each
  // angle's own rounding a few eps; bound 2 N eps = 1.4e-13. Measured 2.2e-15 at worst.
  const double margin = 2.0 * static_cast<double>(sphere.num_elements()) * kEps;
  CHECK(winding_number(sphere, topo.shell(0), Vec3(1, 1, 1)) == Approx(1.0).margin(margin));
  CHECK(winding_number(sphere, topo.shell(0), Vec3(2.5, 1, 1)) == Approx(1.0).margin(margin));
  CHECK(winding_number(sphere, topo.shell(0), Vec3(3.5, 1, 1)) == Approx(0.0).margin(margin));
  const TriangleMesh flipped = flip_orientation(sphere);
  CHECK(winding_number(flipped, topo.shell(0), Vec3(1, 1, 1)) == Approx(-1.0).margin(margin));
}

TEST_CASE("good meshes pass validation", "[mesh][validation]") {
  for (const TriangleMesh& mesh : {icosphere_mesh(Vec3::Zero(), 1.0, 2), box_mesh(Vec3::Zero(), Vec3(1, 2, 3), 2, 3, 4),
                                   hollow_sphere_mesh(Vec3::Zero(), 0.5, 1.0, 2, 2),
                                   merge_meshes(icosphere_mesh(Vec3::Zero(), 1.0, 1), icosphere_mesh(Vec3(5, 0, 0), 1.0, 1))}) {
    const MeshValidationResult report = validate_mesh(mesh);
    INFO(report.summary());
    CHECK(report.valid());
    CHECK(report.issues.empty());
    CHECK_NOTHROW(require_valid_mesh(mesh));
  }
}

TEST_CASE("empty and non-finite meshes are errors", "[mesh][validation]") {
  CHECK_THROWS_AS(require_valid_mesh(TriangleMesh()), InvalidMeshError);
  CHECK_THROWS_WITH(require_valid_mesh(TriangleMesh()), Catch::Contains("empty"));

  const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 1);
  RowMatrixX3d V = sphere.vertices();
  V(7, 1) = std::numeric_limits<double>::quiet_NaN();
  V(9, 2) = std::numeric_limits<double>::infinity();
  const TriangleMesh bad(V, sphere.faces());
  const MeshValidationResult report = validate_mesh(bad);
  CHECK(report.count(MeshIssueKind::NonFiniteVertex) == 2);
  CHECK_FALSE(report.valid());
  CHECK_THROWS_WITH(require_valid_mesh(bad), Catch::Contains("vertex 7") && Catch::Contains("non-finite"));
}

TEST_CASE("a mesh scaled until its areas overflow names the face and the mesh scale", "[mesh][validation]") {
  // Corners of 1e80 are finite, but the edge cross products (1e160) overflow when squared: the
  // areas come out infinite and the normals zero, which must not pass for a valid mesh.
  const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 1);
  const TriangleMesh scaled_ok(1e3 * sphere.vertices(), sphere.faces());
  CHECK(validate_mesh(scaled_ok).valid());
  const TriangleMesh huge(1e80 * sphere.vertices(), sphere.faces());
  REQUIRE(huge.vertices().allFinite());
  REQUIRE_FALSE(std::isfinite(huge.area(0)));
  const MeshValidationResult report = validate_mesh(huge);
  INFO(report.summary());
  CHECK(report.count(MeshIssueKind::DegenerateFace) == static_cast<std::size_t>(huge.num_elements()));
  CHECK(report.count(MeshIssueKind::NonFiniteVertex) == 0);
  CHECK(report.issues.at(0).index == 0);
  CHECK_THROWS_AS(require_valid_mesh(huge), InvalidMeshError);
  CHECK_THROWS_WITH(require_valid_mesh(huge),
                    Catch::Contains("face 0") && Catch::Contains("non-finite area") && Catch::Contains("mesh scale"));
}

TEST_CASE("a degenerate face in an otherwise closed mesh is found by index", "[mesh][validation]") {
  // Split face 0 (a, b, c) at the midpoint m of edge ab, leaving its neighbour unsplit, and close
  // the T-junction with the zero-area triangle (a, b, m): closed and oriented, one bad face.
  const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 1);
  const int a = sphere.faces()(0, 0), b = sphere.faces()(0, 1), c = sphere.faces()(0, 2);
  RowMatrixX3d V(sphere.num_vertices() + 1, 3);
  V << sphere.vertices(), 0.5 * (sphere.vertices().row(a) + sphere.vertices().row(b));
  const int m = static_cast<int>(sphere.num_vertices());
  RowMatrixX3i F(sphere.num_elements() + 2, 3);
  F << sphere.faces(), RowMatrixX3i::Zero(2, 3);
  F.row(0) << a, m, c;
  const Index n = sphere.num_elements();
  F.row(n) << m, b, c;
  F.row(n + 1) << a, b, m;
  const TriangleMesh mesh(V, F);
  const MeshValidationResult report = validate_mesh(mesh);
  INFO(report.summary());
  CHECK(report.count(MeshIssueKind::DegenerateFace) == 1);
  CHECK(report.num_errors() == 1);
  CHECK(report.issues.at(0).index == n + 1);
  CHECK_THROWS_WITH(require_valid_mesh(mesh), Catch::Contains("face " + std::to_string(n + 1)) && Catch::Contains("degenerate"));

  // A face that repeats a vertex is degenerate too (and its self-edge is not also reported).
  RowMatrixX3i G = sphere.faces();
  G(3, 1) = G(3, 0);
  const MeshValidationResult r2 = validate_mesh(with_faces(sphere, G));
  CHECK(has_kind(r2, MeshIssueKind::DegenerateFace));
  CHECK_THROWS_WITH(require_valid_mesh(with_faces(sphere, G)), Catch::Contains("face 3") && Catch::Contains("repeats a vertex"));
}

TEST_CASE("an unwelded mesh reports coincident vertices and open edges", "[mesh][validation]") {
  const TriangleMesh soup = unweld(box_mesh(Vec3::Zero(), Vec3::Ones(), 1, 1, 1));
  MeshValidationOptions options;
  options.max_issues_per_kind = 5;
  const MeshValidationResult report = validate_mesh(soup, options);
  // 12 faces x 3 corners = 36 vertices at the cube's 8 positions: 28 duplicates; each face's 3
  // edges now border that face alone: 36 open edges.
  CHECK(report.count(MeshIssueKind::DuplicateVertex) == 36 - 8);
  CHECK(report.count(MeshIssueKind::BoundaryEdge) == 36);
  CHECK(report.issues.size() == 10);  // 5 stored per kind, the rest counted
  CHECK_THAT(report.summary(), Catch::Contains("and 31 more boundary edges"));
  CHECK_THROWS_WITH(require_valid_mesh(soup), Catch::Contains("coincide") && Catch::Contains("not welded"));
  // Welding repairs it.
  CHECK(validate_mesh(weld_vertices(soup)).valid());
  CHECK(weld_vertices(soup).num_vertices() == 8);
}

TEST_CASE("an open mesh names the boundary edge", "[mesh][validation]") {
  const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 1);
  const RowMatrixX3i F = sphere.faces().bottomRows(sphere.num_elements() - 1);  // drop face 0
  const TriangleMesh open = with_faces(sphere, F);
  const MeshValidationResult report = validate_mesh(open);
  CHECK(report.count(MeshIssueKind::BoundaryEdge) == 3);      // the dropped face's three edges
  CHECK_FALSE(has_kind(report, MeshIssueKind::InwardShell));  // an open shell has no inside to judge
  const int a = sphere.faces()(0, 0), b = sphere.faces()(0, 1);
  const std::string edge = "edge (" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
  bool named = false;
  for (const MeshIssue& issue : report.issues) named = named || issue.message.find(edge) != std::string::npos;
  CHECK(named);
  CHECK_THROWS_WITH(require_valid_mesh(open), Catch::Contains("not closed") && Catch::Contains("(and 2 more errors)"));
}

TEST_CASE("a non-manifold edge is named with its face count", "[mesh][validation]") {
  // A fin: one extra triangle hanging from edge (a, b) of a closed sphere.
  const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 1);
  const int a = sphere.faces()(4, 0), b = sphere.faces()(4, 1);
  RowMatrixX3d V(sphere.num_vertices() + 1, 3);
  V << sphere.vertices(), RowMatrixX3d::Constant(1, 3, 3.0);
  RowMatrixX3i F(sphere.num_elements() + 1, 3);
  F << sphere.faces(), a, b, static_cast<int>(sphere.num_vertices());
  const TriangleMesh fin(V, F);
  const MeshValidationResult report = validate_mesh(fin);
  CHECK(report.count(MeshIssueKind::NonManifoldEdge) == 1);
  const std::string edge = "edge (" + std::to_string(std::min(a, b)) + ", " + std::to_string(std::max(a, b)) + ")";
  CHECK_THROWS_WITH(require_valid_mesh(fin), Catch::Contains(edge + " is shared by 3 faces: the mesh is not 2-manifold"));
  CHECK(MeshTopology(fin).neighbour(4, 0) == -1);  // no single neighbour across a non-manifold edge
}

TEST_CASE("one flipped face is an inconsistent orientation", "[mesh][validation]") {
  const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 1);
  RowMatrixX3i F = sphere.faces();
  std::swap(F(11, 1), F(11, 2));
  const MeshValidationResult report = validate_mesh(with_faces(sphere, F));
  CHECK(report.count(MeshIssueKind::InconsistentOrientation) == 3);  // one per edge of the flipped face
  CHECK(report.num_errors() == 3);
  for (const MeshIssue& issue : report.issues) CHECK_THAT(issue.message, Catch::Contains("11"));
  CHECK_THROWS_WITH(require_valid_mesh(with_faces(sphere, F)), Catch::Contains("same direction"));
}

TEST_CASE("inside-out shells are errors, cavities are not", "[mesh][validation]") {
  const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 2);
  SECTION("a single inward sphere") {
    const MeshValidationResult report = validate_mesh(flip_orientation(sphere));
    CHECK(report.count(MeshIssueKind::InwardShell) == 1);
    CHECK(report.num_errors() == 1);
    CHECK_THROWS_WITH(require_valid_mesh(flip_orientation(sphere)), Catch::Contains("shell 0") && Catch::Contains("inward-facing"));
  }
  const TriangleMesh outer = icosphere_mesh(Vec3::Zero(), 2.0, 2);
  const TriangleMesh inner = icosphere_mesh(Vec3(0.2, 0.1, 0.0), 1.0, 1);
  SECTION("hollow sphere with the cavity pointing into the cavity: valid") {
    CHECK(validate_mesh(merge_meshes(outer, flip_orientation(inner))).valid());
  }
  SECTION("cavity shell facing outward: an error naming the inner shell") {
    const TriangleMesh bad = merge_meshes(outer, inner);
    const MeshValidationResult report = validate_mesh(bad);
    INFO(report.summary());
    CHECK(report.num_errors() == 1);
    REQUIRE(report.count(MeshIssueKind::InwardShell) == 1);
    CHECK(report.issues.at(0).index == 1);
    CHECK_THROWS_WITH(require_valid_mesh(bad), Catch::Contains("shell 1") && Catch::Contains("cavity inside shell 0"));
  }
  SECTION("outer shell flipped: only the outer shell is wrong") {
    const TriangleMesh bad = merge_meshes(flip_orientation(outer), flip_orientation(inner));
    const MeshValidationResult report = validate_mesh(bad);
    CHECK(report.num_errors() == 1);
    REQUIRE(report.count(MeshIssueKind::InwardShell) == 1);
    CHECK(report.issues.at(0).index == 0);
  }
  SECTION("both flipped: both wrong") {
    CHECK(validate_mesh(merge_meshes(flip_orientation(outer), inner)).count(MeshIssueKind::InwardShell) == 2);
  }
  SECTION("an island inside a cavity faces outward again") {
    const TriangleMesh island = icosphere_mesh(Vec3(0.2, 0.1, 0.0), 0.5, 1);
    const TriangleMesh good = merge_meshes(merge_meshes(outer, flip_orientation(inner)), island);
    CHECK(validate_mesh(good).valid());
    CHECK_FALSE(validate_mesh(merge_meshes(merge_meshes(outer, flip_orientation(inner)), flip_orientation(island))).valid());
  }
  SECTION("two separate bodies, one inside-out") {
    const TriangleMesh two = merge_meshes(sphere, flip_orientation(icosphere_mesh(Vec3(3, 0, 0), 1.0, 1)));
    const MeshValidationResult report = validate_mesh(two);
    REQUIRE(report.count(MeshIssueKind::InwardShell) == 1);
    CHECK(report.issues.at(0).index == 1);
    MeshValidationOptions lenient;
    lenient.check_shell_orientation = false;
    CHECK(validate_mesh(two, lenient).valid());
  }
}

TEST_CASE("unreferenced vertices are warnings only", "[mesh][validation]") {
  const TriangleMesh sphere = icosphere_mesh(Vec3::Zero(), 1.0, 1);
  RowMatrixX3d V(sphere.num_vertices() + 1, 3);
  V << sphere.vertices(), RowMatrixX3d::Constant(1, 3, 0.0);
  const TriangleMesh mesh(V, sphere.faces());
  const MeshValidationResult report = validate_mesh(mesh);
  CHECK(report.valid());
  CHECK(report.num_warnings() == 1);
  CHECK(report.issues.at(0).severity == MeshIssueSeverity::Warning);
  CHECK_THAT(report.summary(), Catch::Contains("warning: vertex " + std::to_string(sphere.num_vertices())));
  CHECK_NOTHROW(require_valid_mesh(mesh));
}

TEST_CASE("coincident_vertex_representatives respects the tolerance", "[mesh][validation]") {
  RowMatrixX3d V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 1e-7, 0, 0, 1 + 5e-7, 0, 0, 2, 2, 2;
  const auto rep_tight = coincident_vertex_representatives(V, 1e-8);
  CHECK(rep_tight == std::vector<Index>{0, 1, 2, 3, 4});
  const auto rep_loose = coincident_vertex_representatives(V, 1e-6);
  CHECK(rep_loose == std::vector<Index>{0, 1, 0, 1, 4});
  CHECK(bounding_box_diagonal(V) == Approx(std::sqrt(4.0 + 4.0 + 4.0)).epsilon(2.0 * kEps));  // exact inputs, one sqrt
}

namespace {
TriangleMesh join_meshes(const TriangleMesh& a, const TriangleMesh& b) {
  RowMatrixX3d V(a.num_vertices() + b.num_vertices(), 3);
  V << a.vertices(), b.vertices();
  RowMatrixX3i F(a.num_elements() + b.num_elements(), 3);
  F << a.faces(), (b.faces().array() + static_cast<int>(a.num_vertices())).matrix();
  return TriangleMesh(V, F);
}
}  // namespace

TEST_CASE("self-intersecting surfaces and overlapping shells are refused naming a face pair", "[mesh][validation]") {
  // Before: both passed validation (closed, manifold, oriented) and were solved.
  // Two overlapping spheres: every shell is closed and outward, but they share material.
  const TriangleMesh a = icosphere_mesh(Eigen::Vector3d::Zero(), 1.0, 2);
  const TriangleMesh b = icosphere_mesh(Eigen::Vector3d(1.2, 0.0, 0.0), 1.0, 2);
  const TriangleMesh both = join_meshes(a, b);
  const MeshValidationResult r = validate_mesh(both);
  CHECK(has_kind(r, MeshIssueKind::SelfIntersection));
  CHECK_THROWS_WITH(require_valid_mesh(both), Catch::Contains("intersect") && Catch::Contains("two shells overlap"));
  // The same spheres apart are fine.
  const TriangleMesh apart = join_meshes(a, icosphere_mesh(Eigen::Vector3d(2.5, 0.0, 0.0), 1.0, 2));
  CHECK_FALSE(has_kind(validate_mesh(apart), MeshIssueKind::SelfIntersection));
  CHECK(validate_mesh(apart).valid());

  // One closed surface through itself: a vertex of a sphere pushed out through the far side.
  RowMatrixX3d V = a.vertices();
  Index top = 0;
  for (Index v = 0; v < V.rows(); ++v)
    if (V(v, 2) > V(top, 2)) top = v;
  V.row(top) = Eigen::RowVector3d(0.0, 0.0, -1.5);
  const TriangleMesh folded(V, a.faces());
  const MeshValidationResult rf = validate_mesh(folded);
  INFO(rf.summary());
  REQUIRE(has_kind(rf, MeshIssueKind::SelfIntersection));
  const MeshIssue& first =
      *std::find_if(rf.issues.begin(), rf.issues.end(), [](const MeshIssue& i) { return i.kind == MeshIssueKind::SelfIntersection; });
  CHECK_THAT(first.message, Catch::StartsWith("faces ") && Catch::Contains(" and ") && Catch::Contains("cuts through itself"));

  // The check can be switched off (a cutter that checked its own faces).
  MeshValidationOptions off;
  off.check_self_intersection = false;
  CHECK_FALSE(has_kind(validate_mesh(both, off), MeshIssueKind::SelfIntersection));
}

TEST_CASE("elements larger than the local thickness are found", "[mesh][validation]") {
  // Before: a plate 1 x 1 x 0.001 meshed with 0.5-size elements was accepted without a word (its
  // displacements came out ~1e6 too large).
  const TriangleMesh plate = box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 1.0, 0.001), 2, 2, 1);
  const ThinElements thin = find_thin_elements(plate);
  // The 16 top and bottom triangles: size sqrt(2 x 0.125) = 0.5 over a thickness of 0.001.
  CHECK(thin.count == 16);
  REQUIRE(thin.element >= 0);
  // Round-off: size sqrt(0.25) from exact inputs (measured 0); the thickness is a difference of
  // positions of size ~1, so ~16 eps absolute, 0.001 of it relative (measured 0).
  CHECK(thin.size == Approx(0.5).epsilon(4.0 * kEps));
  CHECK(thin.thickness == Approx(0.001).epsilon(16.0 * kEps / 0.001));
  // A cube as thick as its elements (one division), and a finely meshed sphere, are not thin.
  CHECK(find_thin_elements(box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 1, 1, 1)).count == 0);
  CHECK(find_thin_elements(icosphere_mesh(Eigen::Vector3d::Zero(), 1.0, 2)).count == 0);
}
