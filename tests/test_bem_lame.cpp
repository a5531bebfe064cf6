// Lamé's thick hollow sphere under inner and outer pressure (DESIGN.md §8): two closed shells,
// the cavity's normals pointing into the cavity (out of the material).
#include <catch2/catch.hpp>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/verification/reference_solutions.hpp"

using namespace bemsurg;
using namespace bemsurg::verification;

namespace {
const Material kMaterial{1.0, 0.3, 0.0};
const double kA = 1.0, kB = 2.0;
const ElasticField kField = lame_field(kMaterial, Eigen::Vector3d::Zero(), kA, kB, 1.0, 0.0);
}  // namespace

TEST_CASE("Lamé: inner surface displaced, outer surface loaded") {
  std::vector<RelativeErrors> errors;
  for (int s : {1, 2}) {
    const TriangleMesh m = hollow_sphere_mesh(Eigen::Vector3d::Zero(), kA, kB, s, s);
    errors.push_back(solve_exact_trace_problem(m, kMaterial, kField, [&](Index e) { return m.centroid(e).norm() < 1.5; }));
  }
  INFO("u: " << errors[0].displacement << " -> " << errors[1].displacement << ", t: " << errors[0].traction << " -> "
             << errors[1].traction);
  CHECK(errors[1].displacement < 0.6 * errors[0].displacement);
  CHECK(errors[1].traction < 0.6 * errors[0].traction);
  CHECK(errors[1].displacement < 0.05);
  CHECK(errors[1].traction < 0.075);
}

TEST_CASE("Lamé: both pressures prescribed, four elements fix rigid motion") {
  std::vector<RelativeErrors> errors;
  for (int s : {1, 2}) {
    const TriangleMesh m = hollow_sphere_mesh(Eigen::Vector3d::Zero(), kA, kB, s, s);
    errors.push_back(solve_exact_trace_problem(m, kMaterial, kField, a_few_elements(m)));
  }
  INFO("u: " << errors[0].displacement << " -> " << errors[1].displacement);
  CHECK(errors[1].displacement < 0.6 * errors[0].displacement);
  CHECK(errors[1].displacement < 0.08);
}
