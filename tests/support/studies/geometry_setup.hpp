// geometry_setup.hpp: the sliver meshes of stability study (c) (bench_stability --study sliver,
// tests/test_stability_geometry.cpp; docs/stability.md): the Kelvin box of tests/test_bem_interior.cpp
// (2 x 1.2 x 1.2), with a band of needles or with flat caps of a chosen thinness.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "bemsurg/mesh/mesh_generators.hpp"

namespace bemsurg::bench::stability {

/// The Kelvin box with a band of needles: the grid line x = 0 doubled at x = eps, so the slab
/// [0, eps] puts needles of legs eps and the cell size around the box (closed, valid, oriented).
inline TriangleMesh needle_box(int n, double eps) {
  std::vector<double> xs;
  for (int i = 0; i <= 4 * n; ++i) xs.push_back(-1.0 + 0.5 * i / n);
  xs.insert(std::upper_bound(xs.begin(), xs.end(), 0.0), eps);
  std::vector<double> ys;
  for (int i = 0; i <= 2 * n; ++i) ys.push_back(-0.6 + 0.6 * i / n);
  return box_mesh_from_grid(xs, ys, ys);
}

/// The Kelvin box with caps: every vertex inside the top and bottom faces (traction given and
/// solved for) met by four elements (the
/// checkerboard's corners without a diagonal) moved towards the midpoint of one of its opposite
/// diagonals, to height eps x the diagonal above it: that element becomes a flat cap, the other
/// three stay within the vertex's diamond, so the surface stays flat, closed and valid.
inline TriangleMesh cap_box(int n, double eps) {
  TriangleMesh box = box_mesh(Eigen::Vector3d(-1, -0.6, -0.6), Eigen::Vector3d(1, 0.6, 0.6), 4 * n, 2 * n, 2 * n);
  RowMatrixX3d V = box.vertices();
  std::vector<std::vector<Index>> star(static_cast<std::size_t>(V.rows()));
  for (Index f = 0; f < box.num_elements(); ++f)
    for (int k = 0; k < 3; ++k) star[static_cast<std::size_t>(box.faces()(f, k))].push_back(f);
  for (Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d x = V.row(v).transpose();
    const auto& fs = star[static_cast<std::size_t>(v)];
    if (fs.size() != 4 || std::abs(std::abs(x.z()) - 0.6) > 1e-12 || std::abs(x.x()) > 1 - 1e-9 || std::abs(x.y()) > 0.6 - 1e-9) continue;
    const Index f = fs.front();  // the cap: v and the diagonal of the cell opposite it
    Index a = -1, b = -1;
    for (int k = 0; k < 3; ++k)
      if (box.faces()(f, k) != v) (a < 0 ? a : b) = box.faces()(f, k);
    const Eigen::Vector3d mid = 0.5 * (V.row(a) + V.row(b)).transpose();
    const double diag = (V.row(a) - V.row(b)).norm();
    V.row(v) = (mid + eps * diag * (x - mid).normalized()).transpose();
  }
  return TriangleMesh(V, box.faces());
}

}  // namespace bemsurg::bench::stability
