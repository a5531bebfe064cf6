// bench_assembly: the O(E^2) integration of the influence matrices H, G and the gravity vector g
// (docs/design.md, kernels and integration; Wang et al. 2007 eq. 5) measured beside the bare LAPACK
// dgetrf at the same n in the same process, plus the cutting path: the rows and columns of 30 new
// elements (docs/assembly.md).
//
// Per size (a box of N x N x (N-1) cells per face edge, as in bench_contact), medians of --repeats:
//   - assembly phases: H, G and gravity in one pass (assemble(gravity, g)), A* and right-hand sides
//     (build_system_matrix_in_place, build_right_hand_side, the table's G columns); their sum is what
//     GreensTable::compute times as "assembly". Also H, G alone (assemble()), gravity alone
//     (gravity_vector()) and H, G into storage written before (the integration without the first
//     touch of fresh memory);
//   - the factorisation of that A* right after the assembly (dgetrf + dgetrs of 3*64+1 right-hand
//     sides, as the precompute does), and the bare dgetrf + dgetrs on a random matrix of the same n;
//   - ns per element pair per thread: assembly seconds * threads / E^2;
//   - the pair mix (far / mid / near / self by distance / diameter, the quadrature policy's test)
//     and, single-threaded on a sample, the time per pair of each kind (the profile).
// Ratios: assembly / bare dgetrf (issue 9 target <= 0.5 at n = 6,720), precompute_over_bare
// ((assembly + factorisation + solve) / (bare dgetrf + dgetrs), target <= 1.5) and the
// factorisation-only ratio (factorisation + solve after assembly) / bare.
// Rows + columns of 30 new elements at about 3,000 elements (assemble_rows + assemble_columns):
// target <= 10 ms.
//
// usage: bench_assembly [--quick] [--json PATH] [--sizes N1,N2,...] [--repeats R] [--update-size N]
// Thread count: OMP_NUM_THREADS (OpenBLAS follows its own OPENBLAS_NUM_THREADS / default).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/solvers/lu_in_place.hpp"
#include "bench_support.hpp"

using namespace bemsurg;
using bench::Clock;
using bench::median;

namespace {

double seconds(Clock::time_point a) { return seconds_since(a); }

TriangleMesh bench_box(int N) { return box_mesh(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.1 * (N - 1) / N), N, N, std::max(1, N - 1)); }

// The quadrature policy's classification of a pair (source centroid p, element e): the same test
// as ElementQuadrature's first level (distance from p to e's centroid over e's longest edge).
enum class PairKind { Far, Mid, Near, Self };
PairKind classify(const TriangleMesh& mesh, const QuadratureOptions& o, Index i, Index e) {
  if (i == e) return PairKind::Self;
  const auto c = mesh.corners(e);
  const double h = element_diameter(c[0], c[1], c[2]);
  const double dist = (mesh.centroid(i) - (c[0] + c[1] + c[2]) / 3.0).norm();
  if (dist >= o.far_ratio * h) return PairKind::Far;
  if (dist >= o.mid_ratio * h) return PairKind::Mid;
  return PairKind::Near;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false;
  std::string json_path;
  std::vector<int> sizes;
  int repeats = 0, update_size = 0;
  cli::OptionParser parser =
      bench::command_line("bench_assembly",
                          "The integration of H, G and gravity beside the bare LAPACK dgetrf, and a cut's rows and columns\n"
                          "(docs/assembly.md).\n",
                          quick, json_path);
  parser.value("--sizes", "N1,N2,...", sizes, "boxes of N cells per face edge").at_least(1).default_text("9,14; --quick: 5");
  parser.value("--repeats", "R", repeats, "timings per figure (median)").default_text("3; --quick: 2");
  parser.value("--update-size", "N", update_size, "the box of the cut update").default_text("16; --quick: 6");
  if (const std::optional<int> status = cli::parse_command_line(parser, argc, argv)) return *status;
  if (sizes.empty()) sizes = quick ? std::vector<int>{5} : std::vector<int>{9, 14};
  if (repeats <= 0) repeats = quick ? 2 : 3;
  if (update_size <= 0) update_size = quick ? 6 : 16;  // N = 16: 2,944 elements
  const Material material{3000.0, 0.45, 1000.0};
  const Eigen::Vector3d gravity(0, 0, -9.81);
  const QuadratureOptions qopt;
  const int threads = omp_get_max_threads();
  const Index region_rhs = 3 * 64 + 1;  // as GreensTable with a 64-element region

  nlohmann::json out;
  out["benchmark"] = "bench_assembly";
  out["quick"] = quick;
  out["threads"] = threads;
  out["repeats"] = repeats;
#ifdef BEMSURG_HAVE_BLAS
  out["dense_backend"] = "OpenBLAS+LAPACKE (dgetrf/dgetrs)";
#else
  out["dense_backend"] = "Eigen PartialPivLU";
#endif
  std::printf("bench_assembly (%s), %d OpenMP threads, median of %d\n", quick ? "quick" : "full", threads, repeats);
  {
    // Warm-up: the first LAPACK call of a process starts BLAS threads; neither side should pay it.
    Eigen::MatrixXd A = Eigen::MatrixXd::Random(300, 300), B = Eigen::MatrixXd::Random(300, 10);
    A.diagonal().array() += 300.0;
    lu_factor_and_solve_in_place(A, B);
  }
  double checksum = 0.0;
  for (int N : sizes) {
    const TriangleMesh mesh = bench_box(N);
    const Index E = mesh.num_elements(), n = 3 * E;
    std::vector<Index> bottom;
    for (Index e = 0; e < E; ++e)
      if (mesh.normal(e).z() < -0.99) bottom.push_back(e);
    const BoundaryConditions base = supported_base_conditions(E, bottom);
    const InfluenceAssembler assembler(mesh, material, qopt);

    std::vector<double> t_hg, t_grav, t_build, t_fac, t_sol, t_bare_f, t_bare_s, t_reuse, t_one_pass;
    for (int rep = 0; rep < repeats; ++rep) {
      // H, G and gravity in one pass, as GreensTable::compute does.
      auto t0 = Clock::now();
      Eigen::VectorXd g;
      InfluenceMatrices hg = assembler.assemble(gravity, g);
      t_one_pass.push_back(seconds(t0));
      // H and G alone, then gravity alone (the two passes the precompute used to make).
      hg = InfluenceMatrices();
      t0 = Clock::now();
      hg = assembler.assemble();
      t_hg.push_back(seconds(t0));
      // The same integration into storage that has been written before (no page faults): the
      // compute part of the above.
      t0 = Clock::now();
      assembler.assemble_block(nullptr, E, nullptr, E, hg.H.data(), hg.G.data(), nullptr, Eigen::Vector3d::Zero());
      t_reuse.push_back(seconds(t0));
      t0 = Clock::now();
      checksum += assembler.gravity_vector(gravity)(0);
      t_grav.push_back(seconds(t0));
      t0 = Clock::now();
      Eigen::MatrixXd B(n, region_rhs);
      B.leftCols(region_rhs - 1) = hg.G.leftCols(region_rhs - 1);
      B.col(region_rhs - 1) = build_right_hand_side(hg, base, g);
      Eigen::MatrixXd A = build_system_matrix_in_place(hg, base);  // as GreensTable::compute
      t_build.push_back(seconds(t0));
      hg = InfluenceMatrices();
      // The factorisation right after the assembly (the OpenMP team has just finished).
      double f = 0.0, s = 0.0;
      lu_factor_and_solve_in_place(A, B, &f, &s);
      t_fac.push_back(f);
      t_sol.push_back(s);
      checksum += B(0, 0);
      // The bare baseline: same n, same right-hand sides, same back end, no assembly before it.
      Eigen::MatrixXd R = Eigen::MatrixXd::Random(n, n);
      R.diagonal().array() += double(n);
      Eigen::MatrixXd RB = Eigen::MatrixXd::Random(n, region_rhs);
      lu_factor_and_solve_in_place(R, RB, &f, &s);
      t_bare_f.push_back(f);
      t_bare_s.push_back(s);
    }
    const double hg_s = median(t_hg), grav_s = median(t_grav), build_s = median(t_build), reuse_s = median(t_reuse);
    const double one_pass_s = median(t_one_pass);
    const double assembly_s = one_pass_s + build_s;  // what GreensTable::compute times as assembly
    const double fac_s = median(t_fac), sol_s = median(t_sol), bare_f = median(t_bare_f), bare_s = median(t_bare_s);
    const double pairs = double(E) * double(E);
    const double ns_pair_thread = hg_s * threads / pairs * 1e9;

    // The pair mix and, on one thread, the cost of each kind (a sample of up to 4000 pairs each).
    long count[4] = {0, 0, 0, 0};
    std::vector<std::pair<Index, Index>> sample[4];
    std::mt19937 rng(7);
    for (Index i = 0; i < E; ++i)
      for (Index e = 0; e < E; ++e) {
        const int k = static_cast<int>(classify(mesh, qopt, i, e));
        ++count[k];
        auto& s = sample[k];
        if (s.size() < 4000)
          s.emplace_back(i, e);
        else {
          const long j = std::uniform_int_distribution<long>(0, count[k] - 1)(rng);
          if (j < 4000) s[static_cast<std::size_t>(j)] = {i, e};
        }
      }
    const char* kind_name[4] = {"far", "mid", "near", "self"};
    double kind_ns[4] = {0, 0, 0, 0};
    Eigen::Matrix3d h, gg;
    for (int k = 0; k < 4; ++k) {
      if (sample[k].empty()) continue;
      std::vector<double> per;
      for (int rep = 0; rep < 3; ++rep) {
        const auto t0 = Clock::now();
        for (const auto& pr : sample[k]) {
          assembler.element_pair(pr.first, pr.second, h, gg);
          checksum += h(0, 0);
        }
        per.push_back(seconds(t0) / double(sample[k].size()) * 1e9);
      }
      kind_ns[k] = median(per);
    }

    std::printf("\nn = %ld equations (%ld elements, %s pairs)\n", long(n), long(E), general_text(pairs, 3).c_str());
    std::printf(
        "  assembly %s s = H,G and gravity in one pass %s s + A*, rhs %s s (H,G alone %s s, %s ns per pair per thread; "
        "gravity alone %s s)\n",
        fixed_text(assembly_s, 3).c_str(), fixed_text(one_pass_s, 3).c_str(), fixed_text(build_s, 3).c_str(), fixed_text(hg_s, 3).c_str(),
        fixed_text(ns_pair_thread, 1).c_str(), fixed_text(grav_s, 3).c_str());
    std::printf("  H,G into storage written before (integration only, no first-touch page faults): %s s, %s ns per pair per thread\n",
                fixed_text(reuse_s, 3).c_str(), fixed_text(reuse_s * threads / pairs * 1e9, 1).c_str());
    std::printf("  after assembly: dgetrf %s s + dgetrs %s s; bare: dgetrf %s s + dgetrs %s s\n", fixed_text(fac_s, 3).c_str(),
                fixed_text(sol_s, 3).c_str(), fixed_text(bare_f, 3).c_str(), fixed_text(bare_s, 3).c_str());
    std::printf(
        "  assembly / bare dgetrf = %s (target <= 0.5); precompute / bare = %s (target <= 1.5); "
        "factorisation only / bare = %s\n",
        fixed_text(assembly_s / bare_f, 2).c_str(), fixed_text((assembly_s + fac_s + sol_s) / (bare_f + bare_s), 2).c_str(),
        fixed_text((fac_s + sol_s) / (bare_f + bare_s), 2).c_str());
    std::printf("  pair mix and one-thread cost via element_pair:");
    for (int k = 0; k < 4; ++k)
      std::printf(" %s %s%% (%s ns)", kind_name[k], fixed_text(100.0 * double(count[k]) / pairs, 2).c_str(),
                  fixed_text(kind_ns[k], 0).c_str());
    std::printf("\n");
    nlohmann::json mix;
    for (int k = 0; k < 4; ++k) mix[kind_name[k]] = {{"pairs", count[k]}, {"element_pair_ns", kind_ns[k]}};
    out["sizes"].push_back({{"equations", n},
                            {"elements", E},
                            {"hg_gravity_one_pass_seconds", one_pass_s},
                            {"hg_seconds", hg_s},
                            {"gravity_seconds", grav_s},
                            {"system_build_seconds", build_s},
                            {"assembly_seconds", assembly_s},
                            {"factorization_seconds", fac_s},
                            {"solve_seconds", sol_s},
                            {"bare_factorization_seconds", bare_f},
                            {"bare_solve_seconds", bare_s},
                            {"ns_per_pair_per_thread", ns_pair_thread},
                            {"hg_reused_storage_seconds", reuse_s},
                            {"ns_per_pair_per_thread_reused_storage", reuse_s * threads / pairs * 1e9},
                            {"assembly_over_bare_dgetrf", assembly_s / bare_f},
                            {"precompute_over_bare", (assembly_s + fac_s + sol_s) / (bare_f + bare_s)},
                            {"factorization_over_bare", (fac_s + sol_s) / (bare_f + bare_s)},
                            {"pair_mix", mix}});
    std::fflush(stdout);
  }

  {
    // Cutting: the rows and columns of 30 new elements (here: 30 elements of the top face, taken
    // as if they had just been appended) over all elements.
    const TriangleMesh mesh = bench_box(update_size);
    const Index E = mesh.num_elements();
    const InfluenceAssembler assembler(mesh, material, qopt);
    std::vector<Index> fresh;
    for (Index e = 0; e < E && fresh.size() < 30; ++e)
      if (mesh.normal(e).z() > 0.99) fresh.push_back(e);
    Eigen::MatrixXd rh, rg, ch, cg;
    std::vector<double> t_rows, t_cols;
    const int reps = quick ? 3 : 9;
    for (int rep = 0; rep < reps; ++rep) {
      auto t0 = Clock::now();
      assembler.assemble_rows(fresh, rh, rg);
      t_rows.push_back(seconds(t0));
      t0 = Clock::now();
      assembler.assemble_columns(fresh, ch, cg);
      t_cols.push_back(seconds(t0));
      checksum += rh(0, 0) + cg(0, 0);
    }
    const double rows_ms = median(t_rows) * 1e3, cols_ms = median(t_cols) * 1e3;
    std::printf("\ncut update at %ld elements: rows of %zu new elements %s ms + columns %s ms = %s ms (target <= 10 ms)\n", long(E),
                fresh.size(), fixed_text(rows_ms, 2).c_str(), fixed_text(cols_ms, 2).c_str(), fixed_text(rows_ms + cols_ms, 2).c_str());
    out["cut_update"] = {
        {"elements", E}, {"new_elements", fresh.size()}, {"rows_ms", rows_ms}, {"columns_ms", cols_ms}, {"total_ms", rows_ms + cols_ms}};
  }
  if (!std::isfinite(checksum)) std::printf("(non-finite checksum!)\n");
  if (!bench::write_json_file(json_path, out, "bench_assembly")) return 1;
  return 0;
}
