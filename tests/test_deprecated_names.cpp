// The names renamed in 0.2 (option structs end in Options, results in Result; docs/design.md,
// "Module order") still compile as deprecated aliases for one minor version, so a user's 0.1
// code keeps building. Each alias must name exactly the new type: a program that mixes old and
// new names (passes a KrylovSettings where a KrylovOptions is expected) must see one type.
#include <catch2/catch.hpp>
#include <type_traits>

#include "bemsurg/bemsurg.hpp"
#include "bemsurg/haptics.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
namespace {
template <class Old, class New>
constexpr bool same = std::is_same_v<Old, New>;

constexpr bool kAllAliasesAreTheNewTypes =
    same<bemsurg::KrylovSettings, bemsurg::KrylovOptions> && same<bemsurg::KrylovReport, bemsurg::KrylovResult> &&
    same<bemsurg::LinearSolverSettings, bemsurg::LinearSolverOptions> && same<bemsurg::LinearSolveSummary, bemsurg::LinearSolveResult> &&
    same<bemsurg::DenseLU, bemsurg::DenseLu> && same<bemsurg::ElastostaticReport, bemsurg::ElastostaticResult> &&
    same<bemsurg::MeshValidationReport, bemsurg::MeshValidationResult> &&
    same<bemsurg::ContactUpdateReport, bemsurg::ContactUpdateResult> &&
    same<bemsurg::GreensTableUpdateReport, bemsurg::GreensTableUpdateResult> && same<bemsurg::CutStepReport, bemsurg::CutStepResult> &&
    same<bemsurg::RunReport, bemsurg::RunResult> && same<bemsurg::haptics::HapticLoopSettings, bemsurg::haptics::HapticLoopOptions> &&
    same<bemsurg::haptics::UdpDeviceSettings, bemsurg::haptics::UdpDeviceOptions>;

/// A 0.1-style call: options under the old name, validated and used by a 0.2 function.
double solve_with_old_names(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  bemsurg::DenseLU lu(A);
  x = lu.solve(b);
  bemsurg::KrylovSettings settings;
  settings.tolerance = 1e-10;
  settings.validate();
  return (A * x - b).norm() / b.norm();
}
}  // namespace
#pragma GCC diagnostic pop

TEST_CASE("the names renamed in 0.2 remain as deprecated aliases of the new types", "[api]") {
  CHECK(kAllAliasesAreTheNewTypes);
  Eigen::MatrixXd A(3, 3);
  A << 4, 1, 0, 1, 3, 1, 0, 1, 2;
  const Eigen::VectorXd x_exact(Eigen::Vector3d(1.0, -2.0, 0.5));
  const Eigen::VectorXd b = A * x_exact;
  Eigen::VectorXd x;
  // A 3x3 LU solve: round-off bound c n eps with c = 10.
  CHECK(solve_with_old_names(A, b, x) < 10 * 3 * 2.2e-16);
  CHECK((x - x_exact).norm() < 1e-14);
}
