// Tests of the mesh generators: every generated mesh is valid (closed, oriented outward), box
// area and volume are exact, sphere area and volume converge at the expected rate, and graded
// coordinates keep their promises on spacing and growth.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {
using bemsurg_test::kEps;
using bemsurg_test::kPi;
}  // namespace

TEST_CASE("box_mesh has exact area, volume, counts and outward normals", "[mesh][generators]") {
  const Vec3 lo(-1.0, 0.5, 2.0), hi(2.0, 1.5, 4.5);
  const int nx = 3, ny = 2, nz = 5;
  const TriangleMesh box = box_mesh(lo, hi, nx, ny, nz);
  const Vec3 d = hi - lo;
  CHECK(box.num_elements() == 4 * (nx * ny + ny * nz + nz * nx));
  CHECK(box.num_vertices() == 2 * (nx * ny + ny * nz + nz * nx) + 2);
  // Rounding: measured 0 and 2.4e-16. Worst case for the 124-term sums (the volume's terms cancel,
  // the box is off the origin) is looser than these 45 eps bounds, kept.
  CHECK(box.total_area() == Approx(2.0 * (d.x() * d.y() + d.y() * d.z() + d.z() * d.x())).epsilon(1e-14));
  CHECK(box.enclosed_volume() == Approx(d.prod()).epsilon(1e-14));
  // Every normal is an axis direction pointing away from the box centre.
  const Vec3 mid = 0.5 * (lo + hi);
  for (Index e = 0; e < box.num_elements(); ++e) {
    CHECK(box.normal(e).cwiseAbs().maxCoeff() == Approx(1.0));
    CHECK(box.normal(e).dot(box.centroid(e) - mid) > 0.0);
  }
  const MeshValidationResult report = validate_mesh(box);
  INFO(report.summary());
  CHECK(report.valid());
  CHECK(report.issues.empty());
}

TEST_CASE("box_mesh diagonals alternate in a checkerboard", "[mesh][generators]") {
  // On the top face (z = hi) of a 2 x 2 x 1 box, the four quads must use both diagonal directions.
  const TriangleMesh box = box_mesh(Vec3::Zero(), Vec3::Ones(), 2, 2, 1);
  int diag_pp = 0, diag_pm = 0;  // diagonal along (1, 1) or (1, -1)
  for (Index e = 0; e < box.num_elements(); ++e) {
    if (box.normal(e).z() < 0.5) continue;
    const auto c = box.corners(e);
    for (int k = 0; k < 3; ++k) {
      const Vec3 edge = c[static_cast<std::size_t>((k + 1) % 3)] - c[static_cast<std::size_t>(k)];
      if (std::abs(edge.x()) > 1e-12 && std::abs(edge.y()) > 1e-12) (edge.x() * edge.y() > 0 ? diag_pp : diag_pm)++;
    }
  }
  CHECK(diag_pp == 4);  // two quads, each diagonal shared by its two triangles
  CHECK(diag_pm == 4);
}

TEST_CASE("box_mesh_from_grid is conforming with arbitrary spacing", "[mesh][generators]") {
  const std::vector<double> xs{0.0, 0.1, 0.3, 1.0}, ys{-2.0, 0.0, 0.5}, zs{0.0, 0.01, 0.05, 0.2, 1.0};
  const TriangleMesh box = box_mesh_from_grid(xs, ys, zs);
  CHECK(box.enclosed_volume() == Approx(1.0 * 2.5 * 1.0).epsilon(1e-14));  // measured 3.6e-16 and 3.0e-16
  CHECK(box.total_area() == Approx(2.0 * (2.5 + 2.5 + 1.0)).epsilon(1e-14));
  const MeshTopology topo(box);
  CHECK(topo.is_closed_and_oriented());  // conforming: no T-junctions, so no open edges
  CHECK(topo.num_shells() == 1);
  CHECK(box.num_vertices() - topo.num_edges() + box.num_elements() == 2);  // Euler: a sphere
  CHECK(validate_mesh(box).valid());

  CHECK_THROWS_AS(box_mesh_from_grid({0.0, 1.0, 1.0}, ys, zs), InvalidMeshError);
  CHECK_THROWS_WITH(box_mesh_from_grid({0.0, 1.0, 1.0}, ys, zs), Catch::Contains("xs[2]"));
  CHECK_THROWS_WITH(box_mesh_from_grid(xs, {1.0}, zs), Catch::Contains("ys needs at least two"));
  CHECK_THROWS_AS(box_mesh(Vec3::Zero(), Vec3::Ones(), 0, 1, 1), InvalidMeshError);
  CHECK_THROWS_AS(box_mesh(Vec3::Ones(), Vec3::Zero(), 1, 1, 1), InvalidMeshError);
}

TEST_CASE("graded_coordinates respect h_min, h_max and growth", "[mesh][generators]") {
  struct Case {
    double lo, hi, focus, h_min, h_max, growth, plateau;
  };
  const std::vector<Case> cases{{0.0, 10.0, 3.0, 0.1, 1.0, 1.2, 0.0},   {-5.0, 5.0, 0.0, 0.05, 0.8, 1.3, 0.5},
                                {0.0, 1.0, 0.0, 0.01, 0.2, 1.1, 0.0},   {0.0, 1.0, 1.0, 0.02, 0.1, 1.5, 0.1},
                                {-1.0, 1.0, 0.25, 0.1, 0.15, 1.2, 0.0}, {0.0, 100.0, 37.0, 0.5, 10.0, 1.15, 2.0}};
  for (const Case& c : cases) {
    const std::vector<double> x = graded_coordinates(c.lo, c.hi, c.focus, c.h_min, c.h_max, c.growth, c.plateau);
    INFO("lo " << c.lo << " hi " << c.hi << " focus " << c.focus << " h_min " << c.h_min << " growth " << c.growth);
    REQUIRE(x.size() >= 2);
    // Rounding allowance on a spacing: each line is focus -/+ an offset summed over at most x.size()
    // steps, so it is off by <= x.size() eps max|x| (with the bisected ratio's 1e-15 a few eps more);
    // a difference of two lines by twice that; slack = twice that again, relative to h_min (1.4e-13
    // to 8.3e-12 for these cases). Measured: 4.7e-15 relative at worst.
    const double slack = 4.0 * static_cast<double>(x.size()) * std::max(std::abs(c.lo), std::abs(c.hi)) / c.h_min * kEps;
    CHECK(x.front() == c.lo);
    CHECK(x.back() == c.hi);
    CHECK(std::find(x.begin(), x.end(), c.focus) != x.end());  // the focus is a grid line
    double smallest = 1e300;
    for (std::size_t i = 1; i < x.size(); ++i) {
      const double h = x[i] - x[i - 1];
      smallest = std::min(smallest, h);
      CHECK(h >= c.h_min * (1.0 - slack));
      CHECK(h <= c.h_max * (1.0 + slack));
      if (i >= 2) {
        const double ratio = h / (x[i - 1] - x[i - 2]);
        CHECK(ratio <= c.growth * (1.0 + 2.0 * slack));
        CHECK(ratio >= 1.0 / c.growth * (1.0 - 2.0 * slack));
      }
      // Within the fine zone the spacing is h_min.
      if (std::abs(x[i] - c.focus) <= c.plateau + 1e-12 && std::abs(x[i - 1] - c.focus) <= c.plateau + 1e-12)
        CHECK(h == Approx(c.h_min).epsilon(slack));
    }
    CHECK(smallest == Approx(c.h_min).epsilon(slack));
  }
  // Grading pays off: far fewer lines than a uniform h_min grid.
  CHECK(graded_coordinates(0.0, 100.0, 50.0, 0.1, 5.0, 1.2).size() < 120);  // measured 55 (uniform: 1001)
  // growth = 1 gives a uniform grid; a huge fine zone covers the whole interval.
  const auto uniform = graded_coordinates(0.0, 1.0, 0.5, 0.1, 1.0, 1.0);
  CHECK(uniform.size() == 11);                                                   // [0, 1] in steps of 0.1: 10 steps, 11 lines
  CHECK(uniform[3] == Approx(0.3).epsilon(4.0 * kEps));                          // 0.5 - 0.5 x 2 / 5, three roundings: measured 0
  CHECK(graded_coordinates(-1.0, 1.0, 0.0, 0.1, 1.0, 1.2, 1e300).size() == 21);  // 20 steps of 0.1
  CHECK_THROWS_WITH(graded_coordinates(0.0, 1.0, 0.5, 1e-12, 1.0, 1.0), Catch::Contains("grid lines"));
  CHECK_THROWS_AS(graded_coordinates(0.0, 1.0, 0.5, 0.0, 1.0, 1.2), InvalidMeshError);
  CHECK_THROWS_AS(graded_coordinates(0.0, 1.0, 0.5, 0.1, 1.0, 0.9), InvalidMeshError);
  CHECK_THROWS_AS(graded_coordinates(1.0, 1.0, 0.5, 0.1, 1.0, 1.2), InvalidMeshError);
}

TEST_CASE("a graded block is fine under the tool and valid", "[mesh][generators]") {
  // The flat-punch set-up: top face z = 0 fine around (0, 0), coarse elsewhere.
  const auto xs = graded_coordinates(-4.0, 4.0, 0.0, 0.1, 1.0, 1.3, 0.3);
  const auto zs = graded_coordinates(-4.0, 0.0, 0.0, 0.1, 1.0, 1.3);
  const TriangleMesh block = box_mesh_from_grid(xs, xs, zs);
  CHECK(block.enclosed_volume() == Approx(8.0 * 8.0 * 4.0).epsilon(1e-13));  // measured 1.2e-15
  CHECK(validate_mesh(block).valid());
  double smallest_top = 1e300, largest_top = 0.0;
  for (Index e = 0; e < block.num_elements(); ++e)
    if (block.normal(e).z() > 0.5) {
      smallest_top = std::min(smallest_top, block.diameter(e));
      largest_top = std::max(largest_top, block.diameter(e));
    }
  // Lines within 4 of the origin are off by <= xs.size() eps x 4 (see graded_coordinates above), a
  // 0.1 step 40 times that relative, twice for a difference; bound twice that again (measured 0).
  CHECK(smallest_top == Approx(0.1 * std::sqrt(2.0)).epsilon(4.0 * static_cast<double>(xs.size()) * 40.0 * kEps));
  CHECK(largest_top <= std::sqrt(2.0) * 1.0 + 1e-9);
}

TEST_CASE("icosphere area and volume converge to the sphere's at second order", "[mesh][generators]") {
  const Vec3 c(1.0, -2.0, 0.5);
  const double r = 1.7;
  const double exact_area = 4.0 * kPi * r * r, exact_volume = 4.0 / 3.0 * kPi * r * r * r;
  double prev_area_err = 1e300, prev_vol_err = 1e300;
  for (int s = 0; s <= 5; ++s) {
    const TriangleMesh sphere = icosphere_mesh(c, r, s);
    CHECK(sphere.num_elements() == 20 * (1 << (2 * s)));
    CHECK(sphere.num_vertices() == 10 * (1 << (2 * s)) + 2);
    // A unit vertex (normalised: 2 eps), scaled by r (1), shifted by c (|c| = 1.35 r) and back
    // (2 x 1.35 eps), then its norm (2 eps): <= ~8 eps. Measured 1.8 eps; bound 16 eps.
    for (Index v = 0; v < sphere.num_vertices(); ++v) CHECK((sphere.vertex(v) - c).norm() == Approx(r).epsilon(16.0 * kEps));
    const double area_err = (exact_area - sphere.total_area()) / exact_area;
    const double vol_err = (exact_volume - sphere.enclosed_volume()) / exact_volume;
    CHECK(area_err > 0.0);  // inscribed: converges from below
    CHECK(vol_err > 0.0);
    if (s >= 2) {
      // O(h^2): each subdivision halves h, so the error drops by about four (measured at least 3.81
      // for the area, 3.74 for the volume).
      CHECK(prev_area_err / area_err > 3.5);
      CHECK(prev_vol_err / vol_err > 3.5);
    }
    prev_area_err = area_err;
    prev_vol_err = vol_err;
  }
  CHECK(prev_area_err < 9e-4);  // measured 3.0e-4
  CHECK(prev_vol_err < 1e-3);   // measured 5.4e-4
  const TriangleMesh sphere = icosphere_mesh(c, r, 3);
  for (Index e = 0; e < sphere.num_elements(); ++e) CHECK(sphere.normal(e).dot(sphere.centroid(e) - c) > 0.0);
  CHECK(validate_mesh(sphere).valid());
  CHECK_THROWS_AS(icosphere_mesh(c, -1.0, 2), InvalidMeshError);
  CHECK_THROWS_AS(icosphere_mesh(c, 1.0, -1), InvalidMeshError);
}

TEST_CASE("ellipsoid volume converges and the mesh is valid", "[mesh][generators]") {
  const Vec3 axes(3.0, 2.0, 0.5);
  const double exact = 4.0 / 3.0 * kPi * axes.prod();
  double prev = 1e300;
  for (int s = 1; s <= 4; ++s) {
    const TriangleMesh e = ellipsoid_mesh(Vec3(0.0, 1.0, 2.0), axes, s);
    const double err = std::abs(exact - e.enclosed_volume()) / exact;
    CHECK(err < prev / 3.0);  // measured ratios 3.7 to 4.1
    prev = err;
  }
  CHECK(prev < 5e-3);  // measured 2.2e-3
  CHECK(validate_mesh(ellipsoid_mesh(Vec3::Zero(), axes, 2)).valid());
}

TEST_CASE("hollow sphere: two shells, cavity inward, material volume right", "[mesh][generators]") {
  const double a = 1.0, b = 2.0;
  const TriangleMesh hollow = hollow_sphere_mesh(Vec3::Zero(), a, b, 3, 4);
  CHECK(hollow.num_elements() == 20 * 64 + 20 * 256);
  const MeshTopology topo(hollow);
  REQUIRE(topo.num_shells() == 2);
  CHECK(topo.shell(0).size() == 20 * 256);  // outer first
  CHECK(topo.shell_volume(0) > 0.0);
  CHECK(topo.shell_volume(1) < 0.0);
  // Inner normals point towards the centre (into the cavity, out of the material).
  for (Index f : topo.shell(1)) CHECK(hollow.normal(f).dot(hollow.centroid(f)) < 0.0);
  const double exact = 4.0 / 3.0 * kPi * (b * b * b - a * a * a);
  CHECK(hollow.enclosed_volume() == Approx(exact).epsilon(3.7e-3));  // inscribed polyhedra: measured 1.24e-3 low
  const MeshValidationResult report = validate_mesh(hollow);
  INFO(report.summary());
  CHECK(report.valid());
  CHECK_THROWS_AS(hollow_sphere_mesh(Vec3::Zero(), 2.0, 1.0, 1, 1), InvalidMeshError);
}

TEST_CASE("merge_meshes and flip_orientation", "[mesh][generators]") {
  const TriangleMesh a = icosphere_mesh(Vec3::Zero(), 1.0, 1);
  const TriangleMesh b = box_mesh(Vec3(3, 0, 0), Vec3(4, 1, 1), 1, 1, 1);
  const TriangleMesh m = merge_meshes(a, b);
  CHECK(m.num_vertices() == a.num_vertices() + b.num_vertices());
  CHECK(m.num_elements() == a.num_elements() + b.num_elements());
  CHECK(m.enclosed_volume() == Approx(a.enclosed_volume() + 1.0).epsilon(1e-14));  // measured 3.8e-16
  CHECK(m.faces().bottomRows(b.num_elements()).minCoeff() == a.num_vertices());
  CHECK(MeshTopology(m).num_shells() == 2);
  CHECK(validate_mesh(m).valid());

  const TriangleMesh f = flip_orientation(a);
  // Swapping two corners negates every cross product and triple product exactly (products commute,
  // a - b = -(b - a)), so volume and normals flip to the bit: measured 0; bounds one rounding.
  CHECK(f.enclosed_volume() == Approx(-a.enclosed_volume()).epsilon(kEps));
  CHECK((f.normals() + a.normals()).cwiseAbs().maxCoeff() <= kEps);
  CHECK((flip_orientation(f).faces() - a.faces()).cwiseAbs().maxCoeff() == 0);
}
