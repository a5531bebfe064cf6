// Tests for the surgical tools on exact contact (presolution/contact_tools.hpp, docs/design.md §6):
// Boussinesq's flat punch and Hertz's sphere on a large graded block (closed-form forces),
// pinch sign reversal, plate retractor, two tools at once, unilateral release.
#include <catch2/catch.hpp>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/contact_tools.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "support/cached_greens_table.hpp"
#include "support/test_constants.hpp"

using namespace bemsurg;

namespace {

// A block [-L, L]^2 x [-L, 0], fine (spacing h) on the top face within `fine` of the z axis, graded
// into a coarse remainder; bottom held. The half-space of the closed-form solutions, truncated.
struct Block {
  TriangleMesh mesh;
  GreensTable table;
  Block(double L, double h, double growth, double h_max, double fine, double region_radius, const Material& m) {
    const auto xs = graded_coordinates(-L, L, 0.0, h, h_max, growth, fine);
    const auto zs = graded_coordinates(-L, 0.0, 0.0, 2.0 * h, h_max, growth, 0.0);
    mesh = box_mesh_from_grid(xs, xs, zs);
    std::vector<Index> bottom, region;
    for (Index e = 0; e < mesh.num_elements(); ++e) {
      if (mesh.normal(e).z() < -0.99) bottom.push_back(e);
      if (mesh.normal(e).z() > 0.99 && mesh.centroid(e).head<2>().norm() < region_radius) region.push_back(e);
    }
    GreensTableOptions options;
    options.region = region;  // columns only where the tool acts: n x 3|region| memory
    table = GreensTable::compute(mesh, m, supported_base_conditions(mesh.num_elements(), bottom), options);
    mesh_ptr = std::make_shared<const TriangleMesh>(mesh);  // the solvers hold shared snapshots
    table_ptr = std::make_shared<const GreensTable>(table);
  }
  std::shared_ptr<const TriangleMesh> mesh_ptr;
  std::shared_ptr<const GreensTable> table_ptr;
};

// Round-off bounds of the form c n eps (the same on any CPU and BLAS). A contact solve on one
// table is a solve with the capacitance block G_CC of the rows in contact, whose condition number
// is at most about 30 on these meshes (1.5, 6.6, 27 for 1, 7, 50 bonded elements on the top of the
// 6 x 6 x 3 box: tests/test_contact_capacitance.cpp): c = kCond, n = the rows.
using bemsurg_test::kEps;
constexpr double kCond = 30.0;

double contact_area(const ToolContactSolver& s, const TriangleMesh& mesh, int tool) {
  std::vector<Index> list;
  s.contact_element_list(tool, list);
  double a = 0.0;
  for (Index e : list) a += mesh.area(e);
  return a;
}

struct SmallBox {
  TriangleMesh mesh = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 0.5), 6, 6, 3);
  Material material{2.0e5, 0.3, 1000.0};  // sags ~1 % of its height under its own weight
  GreensTable table;
  SmallBox() {
    std::vector<Index> bottom;
    for (Index e = 0; e < mesh.num_elements(); ++e)
      if (mesh.normal(e).z() < -0.99) bottom.push_back(e);
    GreensTableOptions options;
    options.gravity = Eigen::Vector3d(0, 0, -9.81);
    // Shared by 11 cases, each its own process under ctest: computed once, then read from its file.
    table = testing::cached_greens_table("contact-tools-small-box", mesh, material, supported_base_conditions(mesh.num_elements(), bottom),
                                         options);
    mesh_ptr = std::make_shared<const TriangleMesh>(mesh);  // the solvers hold shared snapshots
    table_ptr = std::make_shared<const GreensTable>(table);
  }
  std::shared_ptr<const TriangleMesh> mesh_ptr;
  std::shared_ptr<const GreensTable> table_ptr;
};
SmallBox& small_box() {
  static SmallBox b;
  return b;
}

/// The largest ratio of successive force increments |F_k - F_(k-1)| / |F_(k-1) - F_(k-2)| over a press
/// in equal depth steps: about 1 while the force grows smoothly, large where it steps.
double largest_increment_ratio(const std::vector<Eigen::Vector3d>& forces) {
  double worst = 0.0;
  for (std::size_t k = 2; k < forces.size(); ++k) {
    const double before = (forces[k - 1] - forces[k - 2]).norm(), now = (forces[k] - forces[k - 1]).norm();
    if (before > 0.0) worst = std::max(worst, now / before);
  }
  return worst;
}

}  // namespace

TEST_CASE("frictionless flat punch converges towards Boussinesq 2aEd/(1-nu^2) as the block grows", "[contact][punch]") {
  // Levels: the block grows (L/a = 3, 8, 20) at a fixed fine spacing a/2 under the disc, so h/L
  // falls. The truncation error (a held bottom at depth L) dominates the first levels; at the last
  // one it and the discretisation error are both about 1 % (docs/contact.md has the table).
  const Material m{1.0, 0.3, 0.0};
  const double a = 1.0, d = 0.01, boussinesq = 2.0 * a * m.young_modulus * d / (1.0 - 0.3 * 0.3);
  struct Level {
    double L, h, growth, h_max;
  };
  const Level levels[] = {{3.0, 0.5, 1.5, 1.5}, {8.0, 0.5, 2.0, 4.0}, {20.0, 0.5, 2.0, 8.0}};
  std::vector<double> errors;
  double bonded_ratio = 0.0;
  for (const Level& lv : levels) {
    Block block(lv.L, lv.h, lv.growth, lv.h_max, a, 1.5 * a, m);
    ToolContactSolver solver(block.mesh_ptr, block.table_ptr, 400);
    const int punch = solver.add_tool(ToolSpec::flat(a, ContactMode::Frictionless));
    solver.place(punch, Vec3(0, 0, 0), Vec3(0, 0, -1));
    solver.set_depth(punch, d);
    const ContactUpdateResult report = solver.update();
    REQUIRE(report.consistent);
    const Eigen::Vector3d F = solver.force(punch);
    // No lateral force: measured 0 (frictionless rows act along the axis, the base state is zero);
    // bound 2 k eps of Fz over the k elements: each row's direction within an eps of the axis, and
    // the k-term sum's rounding.
    CHECK(std::abs(F.x()) < 2.0 * solver.contact_elements(punch) * kEps * F.z());
    const double err = F.z() / boussinesq - 1.0;
    errors.push_back(std::abs(err));
    std::cout << "flat punch: L/a = " << lv.L << ", h/a = " << lv.h << ", " << block.mesh.num_elements() << " elements, "
              << solver.contact_elements(punch) << " in contact: F/F_Boussinesq = " << 1.0 + err << "\n";
    const int bonded = solver.add_tool(ToolSpec::flat(a, ContactMode::Bonded));
    solver.release(punch);
    solver.place(bonded, Vec3(0, 0, 0), Vec3(0, 0, -1));
    solver.set_depth(bonded, d);
    solver.update();
    bonded_ratio = solver.force(bonded).z() / F.z();
  }
  // Measured F/F_Boussinesq - 1 = 0.272, 0.0702, 0.00565 (L/a = 3, 8, 20): the error falls, and the
  // last is bounded at 3x its measurement.
  for (std::size_t i = 1; i < errors.size(); ++i) CHECK(errors[i] < errors[i - 1]);
  CHECK(errors.back() < 0.017);  // measured 0.0057
  // A bonded punch is a few per cent stiffer than a frictionless one at nu = 0.3: measured 1.0178 at
  // L/a = 20 (1.0133, 1.0176 at 3, 8). Window: at least a third of the measured excess, at most the
  // old 5 % (3x the excess, 5.3 %, would be wider).
  CHECK(bonded_ratio > 1.006);
  CHECK(bonded_ratio < 1.05);
}

TEST_CASE("sphere: Hertz force and a contact set that grows as sqrt(R d)", "[contact][sphere]") {
  // R = 8, fine spacing 0.3 within 0.9 of the axis on a block of half-width 14: contact radii
  // sqrt(R d) = 0.63 .. 0.94 at the depths asserted, i.e. 4 to 6 elements across the contact.
  // The remaining 5-8 % excess is mostly the truncated half-space (the punch test shows the same
  // trend with the block size); see docs/contact.md. Measured F/F_Hertz = 1.050, 1.060, 1.072, 1.075
  // and area / pi R d = 1.43, 1.15, 1.25, 1.04 at d = 0.02, 0.05, 0.08, 0.11: the excess over Hertz
  // grows with the contact radius relative to the block, as the truncation error does.
  const Material m{1.0, 0.3, 0.0};
  const double R = 8.0;
  Block block(14.0, 0.3, 2.2, 6.0, 0.9, 1.6, m);
  ToolContactSolver solver(block.mesh_ptr, block.table_ptr, 400);
  const int sphere = solver.add_tool(ToolSpec::sphere(R));
  solver.place(sphere, Vec3(0, 0, R), Vec3(0, 0, -1));  // touching the top face z = 0 at the origin
  Index last_count = 0;
  double last_ratio = 1.0;
  for (double d : {0.02, 0.05, 0.08, 0.11}) {
    solver.set_depth(sphere, d);
    const ContactUpdateResult report = solver.update();
    REQUIRE(report.consistent);
    const double F = solver.force(sphere).z();
    const double hertz = 4.0 / 3.0 * m.young_modulus / (1.0 - 0.09) * std::sqrt(R) * std::pow(d, 1.5);
    const double area = contact_area(solver, block.mesh, sphere);
    std::cout << "sphere: d = " << d << ", " << solver.contact_elements(sphere)
              << " elements in contact (area / pi R d = " << area / (M_PI * R * d) << "), F/F_Hertz = " << F / hertz
              << ", active-set iterations " << report.active_set_iterations << "\n";
    CHECK(solver.contact_elements(sphere) > last_count);  // the set grows with depth
    last_count = solver.contact_elements(sphere);
    // The excess over Hertz is positive and grows with the depth (the truncated block's trend).
    CHECK(F / hertz > last_ratio);
    last_ratio = F / hertz;
    if (d >= 0.05) {
      CHECK(F / hertz - 1.0 > 0.02);                       // measured >= 0.060: a third of it
      CHECK(std::abs(F / hertz - 1.0) < 0.10);             // measured <= 0.075
      CHECK(std::abs(area / (M_PI * R * d) - 1.0) < 0.3);  // measured <= 0.25
    }
    // Unilateral: no contact element pulls (measured: every one pushes with at least 0.05 |F|; the
    // slack 1e-12 |F| only admits rounding).
    std::vector<Index> list;
    solver.contact_element_list(sphere, list);
    for (Index e : list) CHECK(solver.contact().traction(e).dot(block.mesh.normal(e)) <= 1e-12 * std::abs(F));
  }
}

TEST_CASE("pinch: the contact sticks and pulling reverses the force exactly", "[contact][pinch]") {
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const int pinch = solver.add_tool(ToolSpec::pinch(0.1));
  REQUIRE(solver.engage(pinch, Vec3(0.52, 0.47, 2.0), Vec3(0, 0, -1)));
  REQUIRE(solver.contact_elements(pinch) == 0);           // not yet updated
  solver.set_translation(pinch, Vec3(0.001, 0.0, 0.01));  // pull up and a little sideways
  solver.update();
  const Eigen::Vector3d pull = solver.force(pinch);
  REQUIRE(solver.contact_elements(pinch) >= 1);
  CHECK(pull.z() < 0.0);  // the tissue pulls the tool back down
  std::vector<Index> list;
  solver.contact_element_list(pinch, list);
  double tension = 0.0;
  for (Index e : list) tension += solver.contact().traction(e).dot(b.mesh.normal(e));
  CHECK(tension > 0.0);  // carries tension: a pushing tool would have released it
  solver.set_translation(pinch, Vec3(-0.001, 0.0, -0.01));
  solver.update();
  const Eigen::Vector3d push = solver.force(pinch);
  // Linear: signs reverse, magnitudes equal. Two solves with negated targets on the same rows:
  // kCond x rows x eps (measured 2.8e-16 with 6 rows).
  CHECK((push + pull).norm() < kCond * solver.contact().num_rows() * kEps * pull.norm());
}

TEST_CASE("point tool: its element takes the tool displacement as in the paper and is released when pulled back", "[contact][point]") {
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const int point = solver.add_tool(ToolSpec::point(ContactMode::Bonded));
  REQUIRE(solver.engage(point, Vec3(0.5, 0.5, 3.0), Vec3(0, 0, -1)));
  solver.set_depth(point, 0.01);
  solver.update();
  REQUIRE(solver.contact_elements(point) == 1);
  std::vector<Index> list;
  solver.contact_element_list(point, list);
  const Index e = list[0];
  Eigen::VectorXd u(b.mesh.num_dofs());
  solver.displacement_field(u);
  // The touched element takes the tool's displacement on top of the self-weight state.
  // Measured 5.4e-20; bound a few roundings (16 eps) of the 1 cm push.
  CHECK((u.segment<3>(3 * e) - b.table.base_displacement().segment<3>(3 * e) - Vec3(0, 0, -0.01)).norm() < 16.0 * kEps * 0.01);
  CHECK(solver.force(point).z() > 0.0);
  solver.set_depth(point, -0.01);  // pulled away: a point tool does not stick
  solver.update();
  CHECK(solver.contact_elements(point) == 0);
  CHECK(solver.force(point).norm() == 0.0);
  // The hit element is the one under the approach line (checked against the triangle directly).
  const auto c = b.mesh.corners(e);
  const Eigen::Vector2d p(0.5, 0.5);
  auto side = [&](const Vec3& a, const Vec3& q) { return (q.x() - a.x()) * (p.y() - a.y()) - (q.y() - a.y()) * (p.x() - a.x()); };
  const double s0 = side(c[0], c[1]), s1 = side(c[1], c[2]), s2 = side(c[2], c[0]);
  // Measured s = 0.028, 0, 0: the line passes through a vertex of the grid; the slack (4 eps) admits
  // the rounding of the products of coordinates <= 1.
  const double slack = 4.0 * kEps;
  CHECK(((s0 >= -slack && s1 >= -slack && s2 >= -slack) || (s0 <= slack && s1 <= slack && s2 <= slack)));
}

TEST_CASE("plate retractor: the elements it touches move with it", "[contact][plate]") {
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  // A square plate against the x = 1 side face, pushing along -x.
  const std::vector<Eigen::Vector3d> poly = {Vec3(1, 0.3, 0.15), Vec3(1, 0.7, 0.15), Vec3(1, 0.7, 0.4), Vec3(1, 0.3, 0.4)};
  const int plate = solver.add_tool(ToolSpec::plate(poly, 0.01));
  REQUIRE(solver.engage(plate, Vec3(1, 0.5, 0.3), Vec3(-1, 0, 0)));
  const Vec3 move(-0.01, 0.002, 0.001);
  solver.set_translation(plate, move);
  solver.update();
  REQUIRE(solver.contact_elements(plate) >= 4);
  std::vector<Index> list;
  solver.contact_element_list(plate, list);
  Eigen::VectorXd u(b.mesh.num_dofs());
  solver.displacement_field(u);
  for (Index e : list) {
    // Only the side face it lies on: a centroid (1 + 1 + 1) / 3, two roundings (measured 0).
    CHECK(std::abs(b.mesh.centroid(e).x() - 1.0) < 2.0 * kEps);
    // Measured <= 3.5e-18; bound kCond x rows x eps x |move| (3 rows per element).
    CHECK((u.segment<3>(3 * e) - b.table.base_displacement().segment<3>(3 * e) - move).norm() <
          kCond * 3.0 * static_cast<double>(list.size()) * kEps * move.norm());
  }
  CHECK(solver.force(plate).dot(move) < 0.0);  // the tissue resists the retractor
}

namespace {
/// The plate's contact computed without the contact solver: prescribed displacement increments d_e
/// (bonded: all three components; frictionless: only the component along w) on the elements in
/// contact, tractions from the compliance table's block G_CC, force on the tool -sum a_e t_e.
Vec3 plate_force_from_table(const SmallBox& b, const std::vector<Index>& list, const std::vector<Vec3>& d, bool frictionless,
                            const Vec3& w) {
  const Index k = static_cast<Index>(list.size());
  Eigen::MatrixXd G(3 * k, 3 * k);
  Eigen::VectorXd rhs(3 * k);
  for (Index i = 0; i < k; ++i) {
    rhs.segment<3>(3 * i) = d[static_cast<std::size_t>(i)];
    for (Index j = 0; j < k; ++j)
      G.block<3, 3>(3 * i, 3 * j) = b.table.block(list[static_cast<std::size_t>(i)], list[static_cast<std::size_t>(j)]);
  }
  Eigen::VectorXd t;
  if (!frictionless) {
    t = G.partialPivLu().solve(rhs);
  } else {  // normal tractions lambda_e w with w.(G lambda w) = w.d on every element
    Eigen::MatrixXd W = Eigen::MatrixXd::Zero(3 * k, k);
    for (Index i = 0; i < k; ++i) W.block<3, 1>(3 * i, i) = w;
    const Eigen::VectorXd lambda = (W.transpose() * G * W).partialPivLu().solve(W.transpose() * rhs);
    t = W * lambda;
  }
  Vec3 F = Vec3::Zero();
  for (Index i = 0; i < k; ++i) F -= b.mesh.area(list[static_cast<std::size_t>(i)]) * t.segment<3>(3 * i);
  return F;
}
}  // namespace

TEST_CASE("plate retractor turned by a small rotation: the rigid motion, and the force it takes", "[contact][plate]") {
  SmallBox& b = small_box();
  const std::vector<Eigen::Vector3d> poly = {Vec3(1, 0.3, 0.15), Vec3(1, 0.7, 0.15), Vec3(1, 0.7, 0.4), Vec3(1, 0.3, 0.4)};
  const Vec3 pivot = Vec3(1, 0.5, 0.275);  // the polygon's centroid
  const Vec3 w(-1, 0, 0);                  // approach direction
  const Vec3 move(-0.01, 0.002, 0.001), turn(0.02, 0.03, -0.01);
  for (const bool frictionless : {false, true}) {
    INFO((frictionless ? "frictionless" : "bonded"));
    // Force of the plate at a pose, with the list of its elements and their displacement increments.
    auto pose = [&](const Vec3& translation, const Vec3& rotation, std::vector<Index>& list, Eigen::VectorXd& u) {
      ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
      const int plate = solver.add_tool(ToolSpec::plate(poly, 0.01, frictionless ? ContactMode::Frictionless : ContactMode::Bonded));
      REQUIRE(solver.engage(plate, Vec3(1, 0.5, 0.3), w));
      solver.set_translation(plate, translation);
      solver.set_rotation(plate, rotation);
      solver.update();
      list.clear();
      solver.contact_element_list(plate, list);
      u.resize(b.mesh.num_dofs());
      solver.displacement_field(u);
      u -= b.table.base_displacement();
      return solver.force(plate);
    };
    std::vector<Index> list;
    Eigen::VectorXd u;
    const Vec3 F_turn = pose(Vec3::Zero(), turn, list, u);
    REQUIRE(list.size() >= 4);
    // Each element in contact follows the plate's rigid motion, omega x (x - pivot), x its base
    // position (frictionless: along w only), to rounding.
    std::vector<Vec3> d;
    for (Index e : list) {
      const Vec3 x = b.mesh.centroid(e) + b.table.base_displacement().segment<3>(3 * e);
      const Vec3 rigid = turn.cross(x - pivot);
      d.push_back(rigid);
      INFO("element " << e);
      CHECK(std::abs(b.mesh.centroid(e).x() - 1.0) < 2.0 * kEps);  // measured 0
      // Measured <= 3.8e-16 (frictionless), 6.2e-16 (bonded); bound kCond x rows x eps (1.2e-13 at 6 elements).
      const double tol = kCond * 3.0 * static_cast<double>(list.size()) * kEps;
      if (frictionless)
        CHECK(std::abs(w.dot(u.segment<3>(3 * e)) - w.dot(rigid)) < tol * rigid.norm());
      else
        CHECK((u.segment<3>(3 * e) - rigid).norm() < tol * rigid.norm());
    }
    // The force equals the one computed from the table directly for those displacements. Measured
    // relative differences: 1.1e-15 (bonded), 3.1e-14 (frictionless); bound kCond x rows x eps
    // (1.2e-13 at 6 elements; a wrong lever arm, pivot or projection is O(1)).
    const Vec3 F_table = plate_force_from_table(b, list, d, frictionless, w);
    INFO("rotated plate force " << F_turn.transpose() << ", from the table " << F_table.transpose() << ", relative difference "
                                << (F_turn - F_table).norm() / F_table.norm());
    const double rows = 3.0 * static_cast<double>(list.size());
    CHECK((F_turn - F_table).norm() < kCond * rows * kEps * F_table.norm());
    std::vector<Index> list_move;
    Eigen::VectorXd u_move;
    const Vec3 F_move = pose(move, Vec3::Zero(), list_move, u_move);
    // Translation and rotation together: the contact is linear, so the forces add (measured
    // 6.7e-17 and 2.7e-16 relative; bound kCond x rows x eps on each of the three forces).
    std::vector<Index> list_both;
    Eigen::VectorXd u_both;
    const Vec3 F_both = pose(move, turn, list_both, u_both);
    CHECK(list_both == list);
    INFO("superposition: relative difference " << (F_both - F_move - F_turn).norm() / F_both.norm());
    CHECK((F_both - F_move - F_turn).norm() < kCond * rows * kEps * (F_both.norm() + F_move.norm() + F_turn.norm()));
  }
}

TEST_CASE("two tools at once interact through the body", "[contact][two-hands]") {
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const int left = solver.add_tool(ToolSpec::flat(0.12));
  const int right = solver.add_tool(ToolSpec::flat(0.12));
  REQUIRE(solver.engage(left, Vec3(0.35, 0.5, 1.0), Vec3(0, 0, -1)));
  solver.set_depth(left, 0.005);
  solver.update();
  const Eigen::Vector3d alone = solver.force(left);
  REQUIRE(solver.engage(right, Vec3(0.65, 0.5, 1.0), Vec3(0, 0, -1)));
  solver.set_depth(right, 0.005);
  solver.update();
  const Eigen::Vector3d together = solver.force(left);
  CHECK(solver.contact_elements(left) > 0);
  CHECK(solver.contact_elements(right) > 0);
  // Pressing next to it softens the left tool's surface: less force for the same depth. Measured
  // together / alone = 0.915: the 8.5 % softening is bounded below at a third and above at 3x.
  CHECK(together.z() < 0.97 * alone.z());
  CHECK(together.z() > 0.75 * alone.z());
  // The same element forces summed in two groupings: 2 rows eps (measured 1.9e-16).
  const Index both_rows = solver.contact().num_rows();
  CHECK((solver.contact().force() - solver.force(left) - solver.force(right)).norm() < 2.0 * both_rows * kEps * together.norm());
  solver.release(right);
  solver.update();
  // Back by a bordering and a Schur reduction: 2 kCond rows eps (measured 1.8e-16).
  CHECK((solver.force(left) - alone).norm() < 2.0 * kCond * both_rows * kEps * alone.norm());
}

TEST_CASE("a flat punch narrower than the elements presses the element its axis lands on, like a bonded point", "[contact][punch]") {
  SmallBox& b = small_box();  // top elements are about 0.17 wide: a 0.01-radius disc covers no centroid
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const int narrow = solver.add_tool(ToolSpec::flat(0.01, ContactMode::Bonded));
  REQUIRE(solver.engage(narrow, Vec3(0.51, 0.52, 3.0), Vec3(0, 0, -1)));
  solver.set_depth(narrow, 0.01);
  solver.update();
  REQUIRE(solver.contact_elements(narrow) == 1);
  const Vec3 narrow_force = solver.force(narrow);
  solver.release(narrow);
  const int point = solver.add_tool(ToolSpec::point(ContactMode::Bonded));
  REQUIRE(solver.engage(point, Vec3(0.51, 0.52, 3.0), Vec3(0, 0, -1)));
  solver.set_depth(point, 0.01);
  solver.update();
  CHECK(narrow_force.z() > 0.0);
  // The same element and push, the 1 cm depth reached from poses 3 m away: its rounding is
  // 3 eps / 0.01 = 300 eps relative, times cond(G_jj) <= 2: 600 eps = 1.3e-13 (measured 5.7e-15).
  CHECK((solver.force(point) - narrow_force).norm() < 600.0 * kEps * narrow_force.norm());
}

TEST_CASE("a sphere that covers no element centroid is not engaged (no NaN pose)", "[contact][sphere]") {
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const int far = solver.add_tool(ToolSpec::sphere(0.01));
  const int big_far = solver.add_tool(ToolSpec::sphere(0.3));
  // Far from the body: no candidate, so no first contact (it used to report success at inf/NaN).
  CHECK_FALSE(solver.engage(far, Vec3(100, 100, 100), Vec3(0, 0, -1)));
  CHECK_FALSE(solver.engaged(far));
  CHECK_FALSE(solver.engage(big_far, Vec3(100, 100, 100), Vec3(0, 0, -1)));
  CHECK_FALSE(solver.engaged(big_far));
  // On the body but narrower than the elements (about 0.17 wide): no centroid's normal line can
  // meet it, so it is refused too rather than engaged and never touching.
  const int narrow = solver.add_tool(ToolSpec::sphere(0.01));
  CHECK_FALSE(solver.engage(narrow, Vec3(0.51, 0.52, 3.0), Vec3(0, 0, -1)));
  CHECK_FALSE(solver.engaged(narrow));
  const ContactUpdateResult report = solver.update();
  CHECK(report.rows == 0);
  CHECK(solver.force(far).allFinite());
  // A sphere that does cover centroids still engages, with a finite pose and force.
  const int good = solver.add_tool(ToolSpec::sphere(1.0));
  REQUIRE(solver.engage(good, Vec3(0.5, 0.5, 2.0), Vec3(0, 0, -1)));
  solver.set_depth(good, 0.01);
  solver.update();
  CHECK(solver.contact_elements(good) > 0);
  CHECK(solver.force(good).allFinite());
  CHECK(solver.force(good).z() > 0.0);
}

TEST_CASE("an update past the capacity throws and leaves the solver consistent", "[contact][capacity]") {
  SmallBox& b = small_box();
  const Index capacity = 12;  // a frictionless R = 1 sphere takes 8 rows at depth 0.01, over 24 at 0.08
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr, capacity);
  const int s = solver.add_tool(ToolSpec::sphere(1.0));
  REQUIRE(solver.engage(s, Vec3(0.5, 0.5, 2.0), Vec3(0, 0, -1)));
  solver.set_depth(s, 0.08);
  CHECK_THROWS_WITH(solver.update(), Catch::Contains("capacity"));
  CHECK(solver.contact().num_rows() <= capacity);
  CHECK(solver.contact_elements(s) == solver.contact().num_elements());  // bookkeeping matches the set
  solver.set_depth(s, 0.01);
  const ContactUpdateResult report = solver.update();
  REQUIRE(report.consistent);
  ToolContactSolver fresh(b.mesh_ptr, b.table_ptr, capacity);
  const int f = fresh.add_tool(ToolSpec::sphere(1.0));
  REQUIRE(fresh.engage(f, Vec3(0.5, 0.5, 2.0), Vec3(0, 0, -1)));
  fresh.set_depth(f, 0.01);
  fresh.update();
  REQUIRE(fresh.contact_elements(f) > 0);
  CHECK(solver.contact_elements(s) == fresh.contact_elements(f));
  // The same set reached through a failed update: 2 kCond rows eps (measured 0; 8 rows).
  const double tol = 2.0 * kCond * static_cast<double>(fresh.contact().num_rows()) * kEps;
  CHECK((solver.force(s) - fresh.force(f)).norm() < tol * fresh.force(f).norm());
  // Also after a set had been in contact before the failed update.
  solver.set_depth(s, 0.08);
  CHECK_THROWS_WITH(solver.update(), Catch::Contains("capacity"));
  solver.set_depth(s, 0.01);
  solver.update();
  CHECK((solver.force(s) - fresh.force(f)).norm() < tol * fresh.force(f).norm());  // measured 0
}

TEST_CASE("a non-finite tool pose is refused, naming the argument", "[contact][pose]") {
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const int tool = solver.add_tool(ToolSpec::flat(0.12));
  REQUIRE(solver.engage(tool, Vec3(0.5, 0.5, 1.0), Vec3(0, 0, -1)));
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  CHECK_THROWS_AS(solver.set_depth(tool, nan), Error);
  CHECK_THROWS_WITH(solver.set_depth(tool, inf), Catch::Contains("depth"));
  CHECK_THROWS_WITH(solver.set_translation(tool, Vec3(0, nan, 0)), Catch::Contains("translation"));
  CHECK_THROWS_WITH(solver.set_rotation(tool, Vec3(inf, 0, 0)), Catch::Contains("rotation"));
  CHECK_THROWS_WITH(solver.place(tool, Vec3(nan, 0.5, 1.0), Vec3(0, 0, -1)), Catch::Contains("position"));
  // The pose is unchanged by a refused call: the force stays finite.
  solver.set_depth(tool, 0.005);
  CHECK_THROWS(solver.set_depth(tool, nan));
  solver.update();
  CHECK(solver.force(tool).allFinite());
  CHECK(solver.force(tool).z() > 0.0);
}

TEST_CASE("approach directions with tiny or huge components are normalised stably", "[contact][pose]") {
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const int ref = solver.add_tool(ToolSpec::point(ContactMode::Bonded));
  REQUIRE(solver.engage(ref, Vec3(0.5, 0.5, 3.0), Vec3(0, 0, -1)));
  solver.set_depth(ref, 0.01);
  solver.update();
  const Vec3 expected = solver.force(ref);
  solver.release(ref);
  for (double scale : {1e-200, 1e200}) {
    const int t = solver.add_tool(ToolSpec::point(ContactMode::Bonded));
    REQUIRE_NOTHROW(solver.engage(t, Vec3(0.5, 0.5, 3.0), Vec3(0, 0, -scale)));
    REQUIRE(solver.engaged(t));
    solver.set_depth(t, 0.01);
    solver.update();
    // Measured 0; bound 16 eps: a direction normalised from a scaled vector is within 2 eps per
    // component, times cond(G_jj) <= 2 over 3 rows, plus rounding.
    CHECK((solver.force(t) - expected).norm() < 16.0 * kEps * expected.norm());
    solver.release(t);
  }
  const int s = solver.add_tool(ToolSpec::sphere(0.5));
  CHECK_NOTHROW(solver.place(s, Vec3(0.5, 0.5, 1.0), Vec3(1e-200, 0, -1e-200)));
  CHECK_THROWS_WITH(solver.place(s, Vec3(0.5, 0.5, 1.0), Vec3(0, 0, 0)), Catch::Contains("non-zero finite"));
}

TEST_CASE("a sphere inside the body below a face does not touch it", "[contact][sphere]") {
  // The sphere lies on the -n side of the top elements (centre 0.3 below the top face, R = 0.15):
  // each centroid's normal line crosses it behind the centroid, so delta_n < 0, but no centroid
  // is inside the sphere and nothing is in contact.
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const int s = solver.add_tool(ToolSpec::sphere(0.15));
  solver.place(s, Vec3(0.5, 0.5, 0.2), Vec3(0, 0, -1));
  solver.update();
  CHECK(solver.contact_elements(s) == 0);
  CHECK(solver.force(s).norm() == 0.0);
  // Raised so that it reaches the face from inside (centre 0.05 below it), it still does not take
  // it: the face looks away from the sphere, which reaches it only through the material (the
  // next case). The same sphere placed above the face and pressed 0.05 past it does touch.
  solver.set_translation(s, Vec3(0, 0, 0.25));
  solver.update();
  CHECK(solver.contact_elements(s) == 0);
  CHECK(solver.force(s).norm() == 0.0);
  solver.place(s, Vec3(0.5, 0.5, 0.65), Vec3(0, 0, -1));
  solver.set_depth(s, 0.2);
  solver.update();
  CHECK(solver.contact_elements(s) > 0);
  CHECK(solver.force(s).z() > 0.0);
}

TEST_CASE("a sphere pressed beside an edge does not take the faces that look away from it", "[contact][sphere]") {
  // A sphere pressed into the top face 0.05 in from the box's x = 1 edge, down and towards -x,
  // overlaps the side face's top row: their centroids fall inside the sphere and their normals
  // meet the press direction (n . d < 0, so they are candidates), but they point away from the
  // sphere's centre. Such a face is reached only through the material (as the near wall of a
  // cut's groove beside a probe is); taking it pushed it along -n by 2 b (b = n . (centroid -
  // centre)) the moment its centroid crossed the sphere, a step of the force in one tick (issue
  // 39, item 4: 19 % on a cut liver). Facing elements join with zero push, so the force grows
  // smoothly with the depth.
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const double R = 0.3;
  const Vec3 start(0.95, 0.5, 0.5 + R), direction = Vec3(-0.5, 0.0, -1.0).normalized();
  const int s = solver.add_tool(ToolSpec::sphere(R));
  solver.place(s, start, direction);
  std::vector<Eigen::Vector3d> forces;
  Index side_inside = 0;
  for (int k = 1; k <= 24; ++k) {
    const double d = 0.005 * k;
    solver.set_depth(s, d);
    REQUIRE(solver.update().consistent);
    forces.push_back(solver.force(s));
    const Vec3 centre = start + d * direction;
    for (Index e = 0; e < b.mesh.num_elements(); ++e)
      if (b.mesh.normal(e).x() > 0.99 && (b.mesh.centroid(e) - centre).norm() < R) ++side_inside;
    std::vector<Index> list;
    solver.contact_element_list(s, list);
    for (Index e : list) CHECK(b.mesh.normal(e).dot(b.mesh.centroid(e) - centre) < 0.0);
  }
  CHECK(side_inside > 0);  // the case arises: side centroids do fall inside the sphere
  // No step: each depth increment changes the force by at most 3 times the one before it.
  const double worst = largest_increment_ratio(forces);
  std::cout << "sphere beside an edge: largest ratio of successive force increments " << worst << ", side centroids inside " << side_inside
            << "\n";
  CHECK(worst < 3.0);
  CHECK(forces.back().z() > 0.0);
}

TEST_CASE("a sphere pressed past a face's plane keeps the face it holds", "[contact][sphere]") {
  // Pressed obliquely (towards +x and down) until its centre passes below the top face, the
  // sphere has faces ahead of its centre that it took while they looked at it and that now look
  // away (b = n . (centroid - centre) > 0), outside the column it swept. Dropping them at b = 0
  // would drop a finite push (delta_n = -sqrt(R^2 - |x|^2) there): the sphere keeps a face it
  // holds, so the force grows smoothly through the crossing.
  SmallBox& b = small_box();
  ToolContactSolver solver(b.mesh_ptr, b.table_ptr);
  const double R = 0.15;
  const Vec3 direction = Vec3(0.5, 0.0, -1.0).normalized(), start = Vec3(0.4, 0.5, 0.5) - R * direction;
  const int s = solver.add_tool(ToolSpec::sphere(R));
  solver.place(s, start, direction);
  std::vector<Eigen::Vector3d> forces;
  Index held_looking_away = 0;
  for (int k = 1; k <= 50; ++k) {
    const double d = 0.005 * k;
    solver.set_depth(s, d);
    REQUIRE(solver.update().consistent);
    forces.push_back(solver.force(s));
    const Vec3 centre = start + d * direction;
    std::vector<Index> list;
    solver.contact_element_list(s, list);
    for (Index e : list) held_looking_away += b.mesh.normal(e).dot(b.mesh.centroid(e) - centre) > 0.0 ? 1 : 0;
  }
  CHECK(held_looking_away > 0);  // the crossing happens
  const double worst = largest_increment_ratio(forces);
  std::cout << "sphere past a face's plane: largest ratio of successive force increments " << worst << ", held faces looking away "
            << held_looking_away << "\n";
  CHECK(worst < 3.0);
  CHECK(forces.back().z() > 0.0);
}
