// Tests for exact capacitance-matrix contact (presolution/capacitance_contact.hpp, docs/design.md §6)
// and the paper's look-up tables (presolution/paper_lookup_table.hpp, Wang et al. 2007 eq. 10):
// against a full re-solve of the BEM system with the contacted elements' displacements prescribed.
#include <algorithm>
#include <atomic>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <limits>
#include <memory>
#include <new>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/capacitance_contact.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/presolution/paper_lookup_table.hpp"
#include "bemsurg/solvers/dense_lu.hpp"
#include "support/allocation_counter.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {

struct Fixture {
  TriangleMesh mesh = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 6, 6, 3);
  Material material{2000.0, 0.3, 1000.0};
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  std::vector<Index> bottom, top;
  BoundaryConditions base;
  InfluenceMatrices hg;
  Eigen::VectorXd gvec;
  GreensTable table;

  Fixture() {
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      if (mesh.normal(e).z() < -0.99) bottom.push_back(e);
      if (mesh.normal(e).z() > 0.99) top.push_back(e);
    }
    // Top elements ordered by distance from the face's centre: the contact patches grow outwards.
    std::sort(top.begin(), top.end(), [&](Index a, Index b) {
      return (mesh.centroid(a) - Vec3(0.5, 0.5, 0.5)).norm() < (mesh.centroid(b) - Vec3(0.5, 0.5, 0.5)).norm();
    });
    base = supported_base_conditions(mesh.num_elements(), bottom);
    const InfluenceAssembler assembler(mesh, material);
    hg = assembler.assemble();
    gvec = assembler.gravity_vector(gravity);
    GreensTableOptions options;
    options.region = top;
    options.gravity = gravity;
    table = GreensTable::compute(mesh, material, base, options);
    mesh_ptr = std::make_shared<const TriangleMesh>(mesh);  // CapacitanceContact holds shared snapshots
    table_ptr = std::make_shared<const GreensTable>(table);
  }
  std::shared_ptr<const TriangleMesh> mesh_ptr;
  std::shared_ptr<const GreensTable> table_ptr;

  /// The reference: the whole BEM system solved again with these conditions.
  BoundarySolution full_solve(const BoundaryConditions& bc) const {
    const Eigen::MatrixXd A = build_system_matrix(hg, bc);
    const Eigen::VectorXd b = build_right_hand_side(hg, bc, gvec);
    DenseLu lu(A);
    return recover_boundary_solution(bc, lu.solve(b));
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

// A displacement target per contact element that differs from element to element.
Eigen::Vector3d prescribed(const Fixture& f, Index e, int i) {
  return f.table.base_displacement().segment<3>(3 * e) +
         Eigen::Vector3d(1e-3 * std::sin(1.0 + i), 2e-3 * std::cos(0.5 * i), -0.01 - 1e-3 * (i % 5));
}

// Round-off bounds of the form c n eps, the same on any CPU and BLAS. The fixture's BEM system has
// n = 864 unknowns. LU with partial pivoting does not depend on how the columns are scaled (H's
// columns are O(1), G's O(1/E)), so its forward error follows the condition number of the
// column-equilibrated matrix: 34.2 for this mesh (6.5e4 unscaled), hence kSolve = 40 n eps. A
// contact solve adds the capacitance block G_CC, whose condition number is 1.5, 6.6 and 27 for 1, 7
// and 50 bonded elements: kContact = 30 kSolve.
using bemsurg_test::kEps;
constexpr double kSolve = 40.0 * 864.0 * kEps;  // 7.7e-12
constexpr double kContact = 30.0 * kSolve;      // 2.3e-10

double relative_difference(const RowMatrixX3d& a, const RowMatrixX3d& b) { return (a - b).norm() / std::max(1e-300, b.norm()); }

}  // namespace

TEST_CASE("base state of the table equals a direct solve with gravity", "[contact]") {
  Fixture& f = fixture();
  const BoundarySolution ref = f.full_solve(f.base);
  RowMatrixX3d u = Eigen::Map<const RowMatrixX3d>(f.table.base_displacement().data(), f.mesh.num_elements(), 3);
  REQUIRE(ref.displacement.norm() > 0.0);
  CHECK(relative_difference(u, ref.displacement) < kSolve);  // measured 2.5e-15
}

TEST_CASE("bonded capacitance contact equals a full re-solve for 1, 7 and 50 elements", "[contact]") {
  Fixture& f = fixture();
  for (int k : {1, 7, 50}) {
    CapacitanceContact contact(f.mesh_ptr, f.table_ptr, 200);
    BoundaryConditions bc = f.base;
    for (int i = 0; i < k; ++i) {
      const Index e = f.top[static_cast<std::size_t>(i)];
      contact.add_bonded(e);
      bc.prescribe_displacement(e, prescribed(f, e, i));
    }
    for (Index a = 0; a < contact.num_rows(); ++a) {
      const ContactRow& r = contact.row(a);
      const int i = static_cast<int>(std::find(f.top.begin(), f.top.end(), r.element) - f.top.begin());
      contact.set_target(a, r.direction.dot(prescribed(f, r.element, i)));
    }
    contact.solve();
    const BoundarySolution ref = f.full_solve(bc);
    Eigen::VectorXd u(f.mesh.num_dofs());
    contact.displacement_field(u);
    const RowMatrixX3d uc = Eigen::Map<const RowMatrixX3d>(u.data(), f.mesh.num_elements(), 3);
    INFO("k = " << k);
    CHECK(relative_difference(uc, ref.displacement) < kContact);  // measured 2.3e-15 .. 2.7e-15 (k = 1, 7, 50)
    Eigen::Vector3d ref_force = Eigen::Vector3d::Zero();
    RowMatrixX3d tc(k, 3), tr(k, 3);
    for (int i = 0; i < k; ++i) {
      const Index e = f.top[static_cast<std::size_t>(i)];
      tc.row(i) = contact.traction(e).transpose();
      tr.row(i) = ref.traction.row(e);
      ref_force -= f.mesh.area(e) * ref.traction.row(e).transpose();
    }
    CHECK(relative_difference(tc, tr) < kContact);                              // measured 1.1e-14, 2.6e-13, 3.2e-13
    CHECK((contact.force() - ref_force).norm() < kContact * ref_force.norm());  // measured 1.1e-14, 1.0e-14, 2.7e-14
    // The O(k) force-only path gives the same force without the tractions: the same 3k terms summed
    // another way, 2 (3k) eps (measured 1.5e-17, 1.6e-16, 1.6e-16).
    CHECK((contact.force_for_targets() - contact.force()).norm() < 6.0 * k * kEps * ref_force.norm());
  }
}

TEST_CASE("frictionless capacitance contact equals a full re-solve for 1, 7 and 50 elements", "[contact]") {
  Fixture& f = fixture();
  for (int k : {1, 7, 50}) {
    CapacitanceContact contact(f.mesh_ptr, f.table_ptr, 200);
    BoundaryConditions bc = f.base;
    for (int i = 0; i < k; ++i) {
      const Index e = f.top[static_cast<std::size_t>(i)];
      contact.add_normal(e, Eigen::Vector3d::UnitZ());
      const double uz = prescribed(f, e, i).z();
      bc.prescribe_component(e, 2, BcKind::Displacement, uz);  // normal component only
      contact.set_target(contact.num_rows() - 1, uz);
    }
    contact.solve();
    const BoundarySolution ref = f.full_solve(bc);
    Eigen::VectorXd u(f.mesh.num_dofs());
    contact.displacement_field(u);
    const RowMatrixX3d uc = Eigen::Map<const RowMatrixX3d>(u.data(), f.mesh.num_elements(), 3);
    INFO("k = " << k);
    CHECK(relative_difference(uc, ref.displacement) < kContact);  // measured 2.3e-15 .. 2.7e-15
    double worst = 0.0, scale = 0.0;
    for (int i = 0; i < k; ++i) {
      const Index e = f.top[static_cast<std::size_t>(i)];
      worst = std::max(worst, (contact.traction(e) - ref.traction.row(e).transpose()).norm());
      scale = std::max(scale, ref.traction.row(e).norm());
      // No tangential traction: measured 0 (the rows act along z only); bound 45 eps x the largest traction.
      CHECK(std::abs(contact.traction(e).x()) < 1e-14 * scale + 1e-300);
    }
    CHECK(worst < kContact * scale);  // measured 1.7e-14, 2.5e-13, 5.5e-13
    // k normal rows summed two ways: 2 k eps (measured 0, 0, 1.6e-16).
    CHECK((contact.force_for_targets() - contact.force()).norm() < 2.0 * k * kEps * contact.force().norm());
  }
}

TEST_CASE("incremental updates of the capacitance matrix match a fresh factorisation", "[contact]") {
  Fixture& f = fixture();
  CapacitanceContact inc(f.mesh_ptr, f.table_ptr, 200), fresh(f.mesh_ptr, f.table_ptr, 200);
  // Grow one element at a time (bordering), shrink by removing every third, then compare with a
  // set built in one go and with refactor().
  for (int i = 0; i < 30; ++i) inc.add_bonded(f.top[static_cast<std::size_t>(i)]);
  for (int i = 0; i < 30; i += 3) inc.remove_element(f.top[static_cast<std::size_t>(i)]);
  for (int i = 0; i < 30; ++i)
    if (i % 3 != 0) fresh.add_bonded(f.top[static_cast<std::size_t>(i)]);
  REQUIRE(inc.num_rows() == fresh.num_rows());
  REQUIRE(inc.num_elements() == 20);
  auto solve_both = [&](CapacitanceContact& c) {
    for (Index a = 0; a < c.num_rows(); ++a) c.set_target(a, c.base_target(a) - 0.01 * c.row(a).direction.z());
    c.solve();
  };
  solve_both(inc);
  solve_both(fresh);
  // 40 set changes (30 borderings, 10 Schur reductions) of a P of at most 90 rows, each backward
  // stable: rounding accumulates over at most 40 x 90 operations per entry, times cond(G_CC) <= 30:
  // 30 x 3600 eps = 2.4e-11.
  const double incremental = 30.0 * 40.0 * 90.0 * kEps;
  CHECK((inc.force() - fresh.force()).norm() < incremental * fresh.force().norm());  // measured 1.5e-16
  for (int i = 0; i < 30; ++i) {
    const Index e = f.top[static_cast<std::size_t>(i)];
    CHECK(inc.contains(e) == (i % 3 != 0));
    if (i % 3) CHECK((inc.traction(e) - fresh.traction(e)).norm() < incremental * fresh.traction(e).norm());  // measured <= 3.0e-15
  }
  CHECK((inc.force_for_targets() - fresh.force()).norm() < incremental * fresh.force().norm());  // measured 1.4e-17
  inc.refactor();
  solve_both(inc);
  // Two fresh factorisations of the same 60-row set: cond(G_CC) x 60 eps = 4.0e-13 (measured 1.5e-16).
  CHECK((inc.force() - fresh.force()).norm() < 30.0 * 60.0 * kEps * fresh.force().norm());
}

TEST_CASE("the force path allocates nothing", "[contact]") {
  Fixture& f = fixture();
  CapacitanceContact c(f.mesh_ptr, f.table_ptr, 200);
  for (int i = 0; i < 7; ++i) c.add_bonded(f.top[static_cast<std::size_t>(i)]);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const long allocations = bemsurg_test::allocations_during([&] {
    for (int rep = 0; rep < 1000; ++rep) {
      for (Index a = 0; a < c.num_rows(); ++a) c.set_target(a, c.base_target(a) - 1e-4 * rep * c.row(a).direction.z());
      c.solve();
      sum += c.force();
      sum += c.force_for_targets();
    }
    // Contact-set changes within capacity allocate nothing either.
    c.remove_element(f.top[3]);
    c.add_bonded(f.top[40]);
  });
  CHECK(allocations == 0);
  CHECK(sum.allFinite());
}

TEST_CASE("contact on an element outside the region or twice is refused, the set unchanged, the capacity held to the region", "[contact]") {
  Fixture& f = fixture();
  CapacitanceContact c(f.mesh_ptr, f.table_ptr, 6);
  c.add_bonded(f.top[0]);
  CHECK_THROWS_WITH(c.add_bonded(f.top[0]), Catch::Contains("already in the contact set"));
  CHECK_THROWS_WITH(c.add_bonded(f.bottom[0]), Catch::Contains("outside the table's region"));
  c.add_bonded(f.top[1]);
  CHECK_THROWS_WITH(c.add_bonded(f.top[2]), Catch::Contains("capacity"));
  CHECK(c.num_rows() == 6);
  // A capacity beyond every region element bonded (3 rows each) is held there: no row past it can exist.
  const Index most = 3 * static_cast<Index>(f.table.region().size());
  CHECK(CapacitanceContact(f.mesh_ptr, f.table_ptr, most + 1000).capacity() == most);
  CHECK(CapacitanceContact(f.mesh_ptr, f.table_ptr, most - 1).capacity() == most - 1);
}

TEST_CASE("the table refuses a precomputation that does not fit, with the estimate", "[contact]") {
  Fixture& f = fixture();
  GreensTableOptions options;
  options.memory_limit_bytes = 1e5;
  CHECK_THROWS_AS(GreensTable::compute(f.mesh, f.material, f.base, options), ResourceError);
  CHECK_THROWS_WITH(GreensTable::compute(f.mesh, f.material, f.base, options), Catch::Contains("needs about"));
  // The estimate scales with the region: n x 3|region| for the table.
  CHECK(GreensTable::estimate_bytes(1000, 100) < GreensTable::estimate_bytes(1000, 1000));
}

TEST_CASE("paper mode (Up/Tp, eq. 10) equals single-element capacitance contact", "[contact][paper]") {
  Fixture& f = fixture();
  const PaperLookupTable paper(f.mesh, f.table);
  for (int i : {0, 5, 20}) {
    const Index j = f.top[static_cast<std::size_t>(i)];
    const Eigen::Vector3d push(0.002, -0.001, -0.01);
    CapacitanceContact c(f.mesh_ptr, f.table_ptr, 3);
    c.add_bonded(j);
    const Eigen::Vector3d target = f.table.base_displacement().segment<3>(3 * j) + push;
    for (Index a = 0; a < 3; ++a) c.set_target(a, c.row(a).direction.dot(target));
    c.solve();
    Eigen::VectorXd up(f.mesh.num_dofs()), uc(f.mesh.num_dofs());
    paper.displacement_field(j, push, up);
    c.displacement_field(uc);
    // One element: a 3 x 3 block G_jj of condition number 1.5 solved two ways; c n eps with n = 3
    // and c = 10 (the condition number times the roundings of the 3 x 3 solves): 6.7e-15.
    const double tol = 10.0 * 3.0 * kEps;
    CHECK((up - uc).norm() < tol * uc.norm());                                  // measured 2.4e-18 .. 1.6e-17
    CHECK((paper.force(j, push) - c.force()).norm() < tol * c.force().norm());  // measured 6.6e-16 .. 9.7e-16
    // The paper's Up column j moves node j by exactly the unit push (measured 1.1e-16 .. 2.7e-16).
    CHECK((paper.up(j).middleRows(3 * j, 3) - Eigen::Matrix3d::Identity()).norm() < tol);
  }
}

TEST_CASE("superposing the paper's single-node tables is not exact for several nodes", "[contact][paper]") {
  // Why capacitance contact exists: the paper's tables superposed over 7 nodes miss the target.
  Fixture& f = fixture();
  const PaperLookupTable paper(f.mesh, f.table);
  const Eigen::Vector3d push(0, 0, -0.01);
  Eigen::VectorXd u = f.table.base_displacement(), tmp(f.mesh.num_dofs());
  for (int i = 0; i < 7; ++i) {
    paper.displacement_field(f.top[static_cast<std::size_t>(i)], push, tmp);
    u += tmp - f.table.base_displacement();
  }
  const Index j = f.top[0];
  const double moved = u(3 * j + 2) - f.table.base_displacement()(3 * j + 2);
  // Superposition overshoots: measured |moved - push| = 1.07 |push| (the element moves 2.07 times
  // the push); bound a third of that.
  CHECK(std::abs(moved - push.z()) > 0.35 * std::abs(push.z()));
}
