// bench_contact: the haptic path of docs/design.md §6 (Wang et al. 2007 §5.1-5.2) measured.
//  1. Precompute (GreensTable::compute) split into assembly, factorisation and table, against size,
//     beside the bare baseline measured in the same process at the same size: one dense LU plus
//     the same multi-right-hand-side solve through the same BLAS/LAPACK back end.
//  2. Force update (tool pose in, force out at a fixed contact set) for 1, 7 and 50 bonded contact
//     elements: median, p99, p99.9 over >= 1e5 updates (1e4 with --quick), two ways: with the
//     tractions (targets, the k x k capacitance product, the force: what the active set needs) and
//     force only (targets and the 3 x k force operator), the latter beside a bare baseline in the
//     same run (the same targets into a plain vector and one 3 x k product); also one contact-set
//     change (remove + add one element, Schur updates of P).
//  3. Full-field update u = u_g + G_{:,C} t_C (graphics rate), median.
// Targets (docs/contact.md): precompute <= 1.5x the baseline; force update p99.9 <= 20 us with 7 and
// <= 50 us with 50 contact elements at 15,000 equations; full field <= 2 ms at 15,000 equations.
//
// usage: bench_contact [--quick] [--json PATH] [--csv PATH] [--sizes N1,N2,...] [--no-updates]
//   (N: box cells per edge; --no-updates: the precompute and its baseline only, no contact timings,
//   what the benchmark report's precompute-against-n chart needs)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/capacitance_contact.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/solvers/lu_in_place.hpp"
#include "bench_support.hpp"

using namespace bemsurg;
using bench::Clock;
using bench::median;
using bench::Percentiles;
using bench::percentiles;

namespace {

double seconds(Clock::time_point a) { return seconds_since(a); }

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path, csv_path;
  std::vector<int> sizes;
  bool no_updates = false;
  cli::OptionParser parser = bench::command_line(
      "bench_contact", "The pre-solution table's cost and the haptic force update (docs/contact.md).\n", quick, json_path);
  parser.value("--csv", "PATH", csv_path, "write one row per size and contact set to PATH as CSV");
  parser.value("--sizes", "N1,N2,...", sizes, "boxes of N cells per edge").at_least(1).default_text("5,9,14,21; --quick: 6,7");
  parser.flag("--no-updates", no_updates, "time the precompute and its baseline only (no force updates, set changes or fields)");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  // Box of N x N x N cells per face edge (N in z one less): 4 (N^2 + 2 N (N-1)) elements.
  if (sizes.empty()) sizes = quick ? std::vector<int>{6, 7} : std::vector<int>{5, 9, 14, 21};
  const int updates = quick ? 10000 : 100000;
  const int contact_sizes[] = {1, 7, 50};
  const Material material{3000.0, 0.45, 1000.0};  // soft tissue-like, SI
  const Eigen::Vector3d gravity(0, 0, -9.81);

  nlohmann::json out;
  out["benchmark"] = "bench_contact";
  out["quick"] = quick;
#ifdef BEMSURG_HAVE_BLAS
  out["dense_backend"] = "OpenBLAS+LAPACKE (dgetrf/dgetrs)";
#else
  out["dense_backend"] = "Eigen PartialPivLU";
#endif
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    use_classic_locale(csv);
    csv << "equations,region_elements,assembly_s,factorization_s,table_s,bare_factorization_s,bare_solve_s,ratio,"
           "contact_elements,force_median_us,force_p99_us,force_p999_us,force_only_median_us,force_only_p999_us,"
           "set_change_median_us,field_median_ms,bare_force_product_median_us,force_only_over_bare\n";
  }
  std::printf("bench_contact (%s)\n", quick ? "quick" : "full");
  {
    // Warm-up: the first LAPACK call of a process starts BLAS threads; neither side should pay it.
    Eigen::MatrixXd A = Eigen::MatrixXd::Random(300, 300), B = Eigen::MatrixXd::Random(300, 10);
    A.diagonal().array() += 300.0;
    lu_factor_and_solve_in_place(A, B);
  }
  for (int N : sizes) {
    const TriangleMesh mesh = box_mesh(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.1 * (N - 1) / N), N, N, std::max(1, N - 1));
    const Index E = mesh.num_elements(), n = 3 * E;
    std::vector<Index> bottom, top;
    for (Index e = 0; e < E; ++e) {
      if (mesh.normal(e).z() < -0.99) bottom.push_back(e);
      if (mesh.normal(e).z() > 0.99) top.push_back(e);
    }
    const Vec3 centre(0.05, 0.05, 0.0);
    std::sort(top.begin(), top.end(), [&](Index a, Index b) {
      return (mesh.centroid(a) - centre).head<2>().norm() < (mesh.centroid(b) - centre).head<2>().norm();
    });
    // Region: where the tool acts (enough for 50 contact elements plus a ring for set changes).
    std::vector<Index> region(top.begin(), top.begin() + std::min<std::size_t>(top.size(), 64));
    const BoundaryConditions base = supported_base_conditions(E, bottom);
    GreensTableOptions options;
    options.region = region;
    options.gravity = gravity;

    // 1. Precompute, then the bare baseline on the same A* with the same right-hand sides.
    const auto t_pre = Clock::now();
    const GreensTable table = GreensTable::compute(mesh, material, base, options);
    // The contact holds shared immutable snapshots (docs/design.md §9).
    const auto mesh_ptr = std::make_shared<const TriangleMesh>(mesh);
    const auto table_ptr = std::make_shared<const GreensTable>(table);
    const double pre_total = seconds(t_pre);
    const PrecomputeTimings& pt = table.timings();
    double bare_f = 0.0, bare_s = 0.0;
    {
      // Same size, same number of right-hand sides, same back end. A random matrix stands in for
      // A* (dgetrf's and dgetrs's cost does not depend on the values), which spares a second
      // assembly of the same system at the largest sizes.
      Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n);
      A.diagonal().array() += double(n);
      Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, 3 * static_cast<Index>(region.size()) + 1);
      lu_factor_and_solve_in_place(A, B, &bare_f, &bare_s);
    }
    // A peer as a user would write it: Eigen's dense LU (PartialPivLU; this build maps it to LAPACKE's
    // dgetrf, EIGEN_USE_LAPACKE), on a fresh matrix of the same n (it factorises a copy).
    double eigen_lu = 0.0;
    {
      Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n);
      A.diagonal().array() += double(n);
      const auto t = Clock::now();
      const Eigen::PartialPivLU<Eigen::MatrixXd> lu(A);
      eigen_lu = seconds(t);
      if (!std::isfinite(lu.matrixLU()(n - 1, n - 1))) eigen_lu = NAN;
    }
    // The whole precompute (assembly included) and the factorisation alone, both against the bare
    // dgetrf + dgetrs; and the assembly against the bare dgetrf (issue 9: <= 0.5).
    const double ratio = (pt.assembly_seconds + pt.factorization_seconds + pt.table_seconds) / (bare_f + bare_s);
    const double factorization_ratio = (pt.factorization_seconds + pt.table_seconds) / (bare_f + bare_s);
    const double assembly_ratio = pt.assembly_seconds / bare_f;
    std::printf("\nn = %ld equations (%ld elements), region %zu elements, table %s MiB\n", long(n), long(E), region.size(),
                fixed_text(double(table.bytes()) / 1048576.0, 1).c_str());
    std::printf("  precompute: assembly %s s, factorisation %s s, table %s s (total %s s)\n", fixed_text(pt.assembly_seconds, 3).c_str(),
                fixed_text(pt.factorization_seconds, 3).c_str(), fixed_text(pt.table_seconds, 3).c_str(), fixed_text(pre_total, 3).c_str());
    std::printf(
        "  bare dgetrf + dgetrs(%zu rhs): %s s + %s s; precompute (assembly + factorisation + table) / bare = %s "
        "(target <= 1.5); factorisation + table / bare = %s; assembly / bare dgetrf = %s (target <= 0.5)\n",
        3 * region.size() + 1, fixed_text(bare_f, 3).c_str(), fixed_text(bare_s, 3).c_str(), fixed_text(ratio, 2).c_str(),
        fixed_text(factorization_ratio, 2).c_str(), fixed_text(assembly_ratio, 2).c_str());
    nlohmann::json size_json = {{"equations", n},
                                {"elements", E},
                                {"region_elements", region.size()},
                                {"assembly_seconds", pt.assembly_seconds},
                                {"factorization_seconds", pt.factorization_seconds},
                                {"table_seconds", pt.table_seconds},
                                {"bare_factorization_seconds", bare_f},
                                {"bare_solve_seconds", bare_s},
                                {"eigen_lu_seconds", eigen_lu},
                                {"precompute_over_bare", ratio},
                                {"factorization_over_bare", factorization_ratio},
                                {"assembly_over_bare_factorization", assembly_ratio}};

    // 2. and 3. per contact size.
    if (no_updates && csv.is_open())  // one row per size, the contact columns empty (not measured)
      csv << n << ',' << region.size() << ',' << pt.assembly_seconds << ',' << pt.factorization_seconds << ',' << pt.table_seconds << ','
          << bare_f << ',' << bare_s << ',' << ratio << ",,,,,,,,,,\n";
    for (int k : contact_sizes) {
      if (no_updates) break;
      if (k + 1 > static_cast<int>(region.size())) {
        std::printf("  k = %d: skipped (the top face has only %zu elements at this size)\n", k, region.size());
        continue;
      }
      CapacitanceContact contact(mesh_ptr, table_ptr, 3 * 64);
      for (int i = 0; i < k; ++i) contact.add_bonded(region[static_cast<std::size_t>(i)]);
      const Index rows = contact.num_rows();
      std::vector<double> base_targets(static_cast<std::size_t>(rows));
      for (Index a = 0; a < rows; ++a) base_targets[static_cast<std::size_t>(a)] = contact.base_target(a);
      std::vector<double> us(static_cast<std::size_t>(updates));
      Eigen::Vector3d sink = Eigen::Vector3d::Zero();
      // Times `updates` haptic ticks: the tool pose of each tick (pressed 0.1..1 mm, swaying
      // sideways) sets every row's target, then `evaluate` turns the targets into a force.
      auto time_ticks = [&](auto&& evaluate) {
        for (int it = 0; it < updates; ++it) {
          const double depth = 1e-4 * (1.0 + 9.0 * 0.5 * (1.0 + std::sin(1e-3 * it)));
          const double sway = 2e-5 * std::cos(7e-4 * it);
          const auto t0 = Clock::now();
          for (Index a = 0; a < rows; ++a) {
            const Eigen::Vector3d& w = contact.row(a).direction;
            contact.set_target(a, base_targets[static_cast<std::size_t>(a)] - depth * w.z() + sway * w.x());
          }
          sink += evaluate();
          us[static_cast<std::size_t>(it)] = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
        }
      };
      time_ticks([&] {
        contact.solve();
        return contact.force();
      });
      const Percentiles p = percentiles(us);
      // Force only (O(k) force operator, no tractions): the same poses.
      time_ticks([&] { return contact.force_for_targets(); });
      const Percentiles q = percentiles(us);
      // Baseline for the force-only path, timed the same way in the same run: the same poses with
      // only the arithmetic no implementation can skip, each row's target written to a plain
      // vector and one 3 x rows product with a fixed matrix (no contact bookkeeping). `bemsurg
      // press` reports this path's median at its own contact set as force.json "force_update_us";
      // that figure is measured here, not bounded in tests/test_contact_press_cli.cpp (the tests
      // also run under sanitizers).
      std::vector<Eigen::Vector3d> directions(static_cast<std::size_t>(rows));
      for (Index a = 0; a < rows; ++a) directions[static_cast<std::size_t>(a)] = contact.row(a).direction;
      const Eigen::Matrix<double, 3, Eigen::Dynamic> bare_operator = Eigen::Matrix<double, 3, Eigen::Dynamic>::Random(3, rows);
      Eigen::VectorXd bare_targets(rows);
      for (int it = 0; it < updates; ++it) {
        const double depth = 1e-4 * (1.0 + 9.0 * 0.5 * (1.0 + std::sin(1e-3 * it)));
        const double sway = 2e-5 * std::cos(7e-4 * it);
        const auto t0 = Clock::now();
        for (Index a = 0; a < rows; ++a) {
          const Eigen::Vector3d& w = directions[static_cast<std::size_t>(a)];
          bare_targets(a) = base_targets[static_cast<std::size_t>(a)] - depth * w.z() + sway * w.x();
        }
        sink += bare_operator * bare_targets;
        us[static_cast<std::size_t>(it)] = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
      }
      const Percentiles bare = percentiles(us);
      const double force_only_over_bare = bare.median > 0.0 ? q.median / bare.median : 0.0;
      // Contact-set change: one element leaves, another joins (Schur updates of P), then solve.
      std::vector<double> change;
      const int changes = quick ? 50 : 500;
      for (int it = 0; it < changes; ++it) {
        const Index leave = region[static_cast<std::size_t>(it % k)];
        const Index join = region[static_cast<std::size_t>(k + it % (static_cast<int>(region.size()) - k))];
        const auto t0 = Clock::now();
        contact.remove_element(leave);
        contact.add_bonded(join);
        for (Index a = 0; a < contact.num_rows(); ++a) contact.set_target(a, contact.base_target(a) - 1e-4 * contact.row(a).direction.z());
        contact.solve();
        sink += contact.force();
        change.push_back(std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
        contact.remove_element(join);
        contact.add_bonded(leave);
      }
      const double change_med = median(change);
      // Full field.
      Eigen::VectorXd u(n);
      std::vector<double> field;
      for (int it = 0; it < (quick ? 20 : 200); ++it) {
        const auto t0 = Clock::now();
        contact.displacement_field(u);
        field.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      }
      const double field_med = median(field);
      std::printf(
          "  k = %2d contact elements, %d updates: force+tractions (solve) median %s us, p99 %s us, p99.9 %s us "
          "(max %s); force only median %s us, p99 %s us, p99.9 %s us (bare 3 x k product median %s us: ratio %s); "
          "set change %s us; full field %s ms%s\n",
          k, updates, fixed_text(p.median, 2).c_str(), fixed_text(p.p99, 2).c_str(), fixed_text(p.p999, 2).c_str(),
          fixed_text(p.max, 1).c_str(), fixed_text(q.median, 2).c_str(), fixed_text(q.p99, 2).c_str(), fixed_text(q.p999, 2).c_str(),
          fixed_text(bare.median, 2).c_str(), fixed_text(force_only_over_bare, 2).c_str(), fixed_text(change_med, 1).c_str(),
          fixed_text(field_med, 3).c_str(), sink.allFinite() ? "" : " (non-finite!)");
      size_json["contact"].push_back(
          {{"contact_elements", k},
           {"force_update_us", {{"median", p.median}, {"p99", p.p99}, {"p999", p.p999}, {"max", p.max}}},
           {"force_only_update_us", {{"median", q.median}, {"p99", q.p99}, {"p999", q.p999}, {"max", q.max}}},
           {"bare_force_product_us", {{"median", bare.median}, {"p99", bare.p99}, {"p999", bare.p999}, {"max", bare.max}}},
           {"force_only_over_bare", force_only_over_bare},
           {"updates", updates},
           {"set_change_median_us", change_med},
           {"full_field_median_ms", field_med}});
      if (csv.is_open())
        csv << n << ',' << region.size() << ',' << pt.assembly_seconds << ',' << pt.factorization_seconds << ',' << pt.table_seconds << ','
            << bare_f << ',' << bare_s << ',' << ratio << ',' << k << ',' << p.median << ',' << p.p99 << ',' << p.p999 << ',' << q.median
            << ',' << q.p999 << ',' << change_med << ',' << field_med << ',' << bare.median << ',' << force_only_over_bare << '\n';
    }
    out["sizes"].push_back(size_json);
    std::fflush(stdout);
  }
  if (!bench::write_json_file(json_path, out, "bench_contact")) return 1;
  return 0;
}
