// Tests for the picking hierarchy (mesh/bvh.hpp): ray, segment and box queries on a 20480-element
// surface agree with a loop over all triangles, visit few nodes, and stay right after refit on a
// deformed surface (Wang et al. 2007 §6: ray-intersection picking).
#include <catch2/catch.hpp>
#include <limits>
#include <random>

#include "bemsurg/mesh/bvh.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {
using bemsurg_test::kEps;

// Brute force: closest hit over every triangle (Moller-Trumbore, both sides).
RayHit brute_force(const RowMatrixX3d& V, const RowMatrixX3i& F, const Vec3& o, const Vec3& d, double t_max) {
  RayHit best;
  for (Index f = 0; f < F.rows(); ++f) {
    const Vec3 a = V.row(F(f, 0)).transpose(), e1 = V.row(F(f, 1)).transpose() - a, e2 = V.row(F(f, 2)).transpose() - a;
    const Vec3 p = d.cross(e2);
    const double det = e1.dot(p);
    if (std::abs(det) < 1e-300) continue;
    const Vec3 s = o - a;
    const double u = s.dot(p) / det;
    const Vec3 q = s.cross(e1);
    const double v = d.dot(q) / det;
    const double t = e2.dot(q) / det;
    if (u < 0 || v < 0 || u + v > 1 || t < 0 || t > t_max || t >= best.t) continue;
    best.element = f;
    best.t = t;
  }
  return best;
}
}  // namespace

TEST_CASE("BVH ray queries equal a loop over all triangles and visit few nodes", "[bvh]") {
  const Vec3 center(0.1, -0.2, 0.3);
  const TriangleMesh mesh = icosphere_mesh(center, 1.0, 5);  // 20480 elements
  const TriangleBvh bvh(mesh);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Index max_visited = 0, hits = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 o = center + 3.0 * Vec3(U(rng), U(rng), U(rng)).normalized();
    const Vec3 target = center + 0.5 * Vec3(U(rng), U(rng), U(rng));  // inside: every ray hits
    const Vec3 d = target - o;
    RayHit hit;
    const bool found = bvh.intersect_ray(o, d, hit);
    max_visited = std::max(max_visited, TriangleBvh::last_nodes_visited());
    const RayHit ref = brute_force(mesh.vertices(), mesh.faces(), o, d, 1e300);
    REQUIRE(found == (ref.element >= 0));
    if (!found) continue;
    ++hits;
    // Round-off between two Moller-Trumbore evaluations (~10 roundings each): the rays aim at points
    // within 0.87 of the centre of the unit sphere, so they meet it at most 60 degrees off the normal
    // (det and numerator lose <= 2x to cancellation) with |o - corner| <= 1.5 |t d|: within ~30 eps;
    // bound 64 eps. Measured 0.9 eps.
    CHECK(hit.t == Approx(ref.t).epsilon(64.0 * kEps));
    CHECK(hit.front_facing);  // from outside, the first hit enters the material
    CHECK((hit.point - (o + ref.t * d)).norm() < 64.0 * kEps * (o.norm() + ref.t * d.norm()));  // measured 5e-16
  }
  CHECK(hits == 200);
  CHECK(max_visited < mesh.num_elements() / 50);  // not a loop over all triangles: measured 123 of 20480
}

TEST_CASE("BVH segment and box queries and refit on a deformed surface", "[bvh]") {
  const TriangleMesh mesh = icosphere_mesh(Vec3::Zero(), 1.0, 4);
  TriangleBvh bvh(mesh);
  RayHit hit;
  CHECK_FALSE(bvh.intersect_segment(Vec3(0, 0, 3), Vec3(0, 0, 1.5), hit));  // stops short
  REQUIRE(bvh.intersect_segment(Vec3(0, 0, 3), Vec3(0, 0, 0), hit));
  // The segment passes through the icosphere's vertex (0, 0, 1), so t = 2/3 up to rounding
  // (measured 1 ulp); a miss of the vertex would be off by the sagitta, ~1e-3.
  CHECK(hit.t * 3.0 == Approx(2.0).epsilon(8.0 * kEps));
  // Box query equals brute force over triangle boxes.
  std::vector<Index> found;
  bvh.query_box(Vec3(0.2, -0.3, 0.5), Vec3(0.6, 0.3, 1.2), found);
  Index brute = 0;
  for (Index f = 0; f < mesh.num_elements(); ++f) {
    const auto c = mesh.corners(f);
    const Vec3 lo = c[0].cwiseMin(c[1]).cwiseMin(c[2]), hi = c[0].cwiseMax(c[1]).cwiseMax(c[2]);
    if ((lo.array() <= Eigen::Array3d(0.6, 0.3, 1.2)).all() && (hi.array() >= Eigen::Array3d(0.2, -0.3, 0.5)).all()) ++brute;
  }
  CHECK(static_cast<Index>(found.size()) == brute);
  CHECK(brute > 0);
  // Deform: squash along z by a per-element displacement field; refit; compare with brute force.
  Eigen::VectorXd u(mesh.num_dofs());
  for (Index e = 0; e < mesh.num_elements(); ++e) u.segment<3>(3 * e) = Vec3(0.0, 0.0, -0.3 * mesh.centroid(e).z());
  const RowMatrixX3d V = deformed_vertices(mesh, u);
  bvh.refit(V);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  for (int i = 0; i < 100; ++i) {
    const Vec3 o = 3.0 * Vec3(U(rng), U(rng), U(rng)).normalized(), d = -o + 0.3 * Vec3(U(rng), U(rng), U(rng));
    const bool got = bvh.intersect_ray(o, d, hit);
    const RayHit ref = brute_force(V, mesh.faces(), o, d, 1e300);
    REQUIRE(got == (ref.element >= 0));
    if (got) CHECK(hit.t == Approx(ref.t).epsilon(64.0 * kEps));  // as above (aim within 0.52); measured 0.8 eps
  }
  CHECK_THROWS_AS(bvh.refit(RowMatrixX3d::Zero(3, 3)), InvalidMeshError);
}
