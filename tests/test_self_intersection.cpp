// Tests for mesh/self_intersection.hpp: crafted intersecting pairs are found (crossing, piercing
// through a shared vertex, folded over a shared edge, touching), clean closed surfaces have none,
// two overlapping spheres give exactly the pairs the geometry predicts, and the BVH search finds
// the same pairs as a loop over all pairs.
#include <catch2/catch.hpp>
#include <random>
#include <set>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/self_intersection.hpp"

using namespace bemsurg;

namespace {
TriangleMesh make_mesh(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& faces) {
  RowMatrixX3d V(static_cast<Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) V.row(static_cast<Index>(i)) = points[i].transpose();
  RowMatrixX3i F(static_cast<Index>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) F(static_cast<Index>(i), k) = faces[i][static_cast<std::size_t>(k)];
  return TriangleMesh(V, F);
}

std::vector<std::pair<Index, Index>> all_pairs(const TriangleMesh& mesh) {
  const auto box = mesh.bounding_box();
  const double tol = SelfIntersectionOptions{}.tolerance * (box.col(1) - box.col(0)).norm();
  std::vector<std::pair<Index, Index>> out;
  for (Index f = 0; f < mesh.num_elements(); ++f)
    for (Index g = f + 1; g < mesh.num_elements(); ++g)
      if (faces_intersect(mesh, f, g, tol)) out.emplace_back(f, g);
  return out;
}
}  // namespace

TEST_CASE("self-intersection finds crafted intersecting pairs and passes their separated versions", "[self_intersection]") {
  // Two triangles without shared vertices: one crossing the other's interior, then lifted clear.
  const std::vector<std::array<int, 3>> two{{{0, 1, 2}}, {{3, 4, 5}}};
  const std::vector<Vec3> flat{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  auto with = [&](std::vector<Vec3> extra) {
    std::vector<Vec3> p = flat;
    p.insert(p.end(), extra.begin(), extra.end());
    return p;
  };
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.2, 0.2, -1), Vec3(0.3, 0.2, 1), Vec3(0.2, 0.3, 1)}), two)).size() == 1);
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.2, 0.2, 0.1), Vec3(0.3, 0.2, 1), Vec3(0.2, 0.3, 1)}), two)).empty());
  // Touching: a vertex of the second lies on the first's interior.
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.2, 0.2, 0), Vec3(0.3, 0.2, 1), Vec3(0.2, 0.3, 1)}), two)).size() == 1);
  // Coplanar, overlapping without any edge crossing: a small triangle inside the large one.
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.1, 0.1, 0), Vec3(0.2, 0.1, 0), Vec3(0.1, 0.2, 0)}), two)).size() == 1);
  // Coplanar and apart.
  CHECK(find_self_intersections(make_mesh(with({Vec3(1, 1, 0), Vec3(2, 1, 0), Vec3(1, 2, 0)}), two)).empty());

  // Sharing vertex 0: the second's far edge pierces the first, or stays above it.
  const std::vector<std::array<int, 3>> fan{{{0, 1, 2}}, {{0, 3, 4}}};
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.4, 0.3, -0.5), Vec3(0.3, 0.4, 0.5)}), fan)).size() == 1);
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.4, 0.3, 0.5), Vec3(0.3, 0.4, 0.5)}), fan)).empty());
  // Coplanar neighbours around a shared vertex (a flat fan) do not intersect; overlapping ones do.
  CHECK(find_self_intersections(make_mesh(with({Vec3(-1, 0, 0), Vec3(-1, -1, 0)}), fan)).empty());
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.8, 0.5, 0), Vec3(0.5, 0.8, 0)}), fan)).size() == 1);

  // Sharing edge (0, 1): folded flat onto the first (intersecting), opened to 90 degrees (not).
  const std::vector<std::array<int, 3>> hinge{{{0, 1, 2}}, {{1, 0, 3}}};
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.5, 0.5, 0)}), hinge)).size() == 1);
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.5, 0, 1)}), hinge)).empty());
  CHECK(find_self_intersections(make_mesh(with({Vec3(0.5, -0.5, 0)}), hinge)).empty());  // flat, the other side
  // The same triangle twice.
  CHECK(find_self_intersections(make_mesh(flat, {{{0, 1, 2}}, {{0, 2, 1}}})).size() == 1);
}

TEST_CASE("self-intersection finds nothing on clean closed surfaces and agrees with a loop over all pairs", "[self_intersection]") {
  for (const TriangleMesh& mesh :
       {box_mesh(Vec3(0, 0, 0), Vec3(1, 2, 0.5), 6, 5, 4), icosphere_mesh(Vec3(0.1, 0, 0), 1.0, 3),
        hollow_sphere_mesh(Vec3(0, 0, 0), 0.5, 1.0, 2, 2), ellipsoid_mesh(Vec3(0, 0, 0), Vec3(1, 0.5, 0.2), 3)}) {
    CHECK(find_self_intersections(mesh).empty());
    CHECK(all_pairs(mesh).empty());
  }
}

TEST_CASE("two overlapping spheres intersect exactly along the faces that straddle the other sphere", "[self_intersection]") {
  const double r = 1.0;
  const Vec3 ca(0, 0, 0), cb(1.1, 0.3, 0.2);
  const TriangleMesh a = icosphere_mesh(ca, r, 3), b = icosphere_mesh(cb, r, 3);
  const TriangleMesh both = merge_meshes(a, b);
  const auto pairs = find_self_intersections(both);
  CHECK(pairs == all_pairs(both));
  // Independent prediction from the spheres: the polyhedra lie within `gap` of the spheres
  // (inscribed, chord sagitta h^2 / (8 r) with h the longest edge).
  const double h = a.diameters().maxCoeff(), gap = h * h / (8.0 * r) + 1e-12;
  std::set<Index> in_pairs;
  for (const auto& p : pairs) {
    const bool first_in_a = p.first < a.num_elements(), second_in_a = p.second < a.num_elements();
    REQUIRE(first_in_a != second_in_a);  // a sphere never intersects itself
    in_pairs.insert(p.first);
    in_pairs.insert(p.second);
  }
  Index straddling = 0;
  for (Index f = 0; f < both.num_elements(); ++f) {
    const Vec3 other = f < a.num_elements() ? cb : ca;
    double lo = 1e300, hi = -1e300;
    for (const Vec3& c : both.corners(f)) {
      lo = std::min(lo, (c - other).norm());
      hi = std::max(hi, (c - other).norm());
    }
    // A corner inside the ball of radius r - gap (inside the other polyhedron) and one outside
    // the ball of radius r (outside it): the face crosses the other surface.
    if (lo < r - gap - 1e-9 && hi > r + 1e-9) {
      CHECK(in_pairs.count(f) == 1);
      ++straddling;
    }
    // Entirely outside the ball of radius r, or inside that of radius r - gap: no pair.
    if (lo > r + 1e-9 || hi < r - gap - 1e-9) CHECK(in_pairs.count(f) == 0);
  }
  // Measured 146 straddling faces and 150 pairs (lower bounds ~1/3 and ~2/3 of those).
  CHECK(straddling > 50);
  CHECK(pairs.size() > 100);
}

TEST_CASE("a vertex pushed through the opposite side is found by the full and the restricted search", "[self_intersection]") {
  const TriangleMesh sphere = icosphere_mesh(Vec3(0, 0, 0), 1.0, 3);
  RowMatrixX3d V = sphere.vertices();
  const Index v = 5;
  V.row(v) *= -1.3;  // through the centre and out of the far side
  const TriangleMesh pushed(V, sphere.faces());
  const auto pairs = find_self_intersections(pushed);
  REQUIRE(!pairs.empty());
  std::vector<Index> around;
  for (Index f = 0; f < pushed.num_elements(); ++f)
    for (int k = 0; k < 3; ++k)
      if (pushed.faces()(f, k) == v) around.push_back(f);
  for (const auto& p : pairs) {  // every pair involves a face of the moved vertex
    const bool involved = std::count(around.begin(), around.end(), p.first) + std::count(around.begin(), around.end(), p.second);
    CHECK(involved);
  }
  CHECK(find_self_intersections(pushed, around) == pairs);
  SelfIntersectionOptions first_only;
  first_only.max_pairs = 1;
  CHECK(find_self_intersections(pushed, first_only).size() == 1);
  CHECK(find_self_intersections(sphere, around).empty());
  CHECK_THROWS_AS(find_self_intersections(pushed, std::vector<Index>{pushed.num_elements()}), InvalidArgumentError);
}
