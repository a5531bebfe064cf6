// cutting_setup.hpp: the bodies and cuts of the cutting studies (d) and (f) of bench_stability
// (issue 25, docs/stability.md), shared with tests/test_stability_cutting.cpp. A soft box of 1 cm
// cells standing on its base (u = 0) under gravity, as bench_cut's (docs/cutting.md), cut along
// its top face's centre line.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "bemsurg/assembly/influence_assembler.hpp"
#include "bemsurg/assembly/linear_system.hpp"
#include "bemsurg/cutting/surface_cutter.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"

namespace bemsurg::stability {

inline constexpr double kCutCell = 0.01;  // 1 cm cells

/// A box of nx x ny x nz cells clamped on its base, the cut's start and direction on its top.
struct CutBody {
  std::shared_ptr<const TriangleMesh> mesh;
  Material material{3000.0, 0.45, 1000.0};
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  std::vector<char> locked;  // the base: supported, no cut may touch it
  Vec3 from, direction;
};

inline CutBody make_cut_body(int nx, int ny, int nz) {
  CutBody b;
  b.mesh = std::make_shared<const TriangleMesh>(box_mesh(Vec3(0, 0, 0), Vec3(nx * kCutCell, ny * kCutCell, nz * kCutCell), nx, ny, nz));
  b.locked.assign(static_cast<std::size_t>(b.mesh->num_elements()), 0);
  for (Index e = 0; e < b.mesh->num_elements(); ++e) b.locked[static_cast<std::size_t>(e)] = b.mesh->normal(e).z() < -0.9;
  b.direction = Vec3(1, 0, 0);
  b.from = Vec3(kCutCell, 0.5 * ny * kCutCell, nz * kCutCell);  // one cell in from the edge, on the centre line
  return b;
}

/// Conditions of `mesh` (the body's elements first, ids kept by the cutter): the base clamped,
/// everything else (the cut's walls included) traction-free.
inline BoundaryConditions clamped_base(const CutBody& b, const TriangleMesh& mesh) {
  BoundaryConditions bc(mesh.num_elements());
  for (Index e = 0; e < b.mesh->num_elements(); ++e)
    if (b.locked[static_cast<std::size_t>(e)]) bc.prescribe_displacement(e, Vec3::Zero());
  return bc;
}

/// The body cut by `steps` steps of a groove of width `gap_ratio` x the local edge length, with
/// the gap limit switched off (CutOptions::allow_narrow_gap_for_studies) when `allow_narrow`.
/// Throws Error naming the step and the cutter's reason when a step is refused.
inline std::shared_ptr<const TriangleMesh> cut_mesh(const CutBody& b, double gap_ratio, int steps, bool allow_narrow) {
  CutOptions co;
  co.gap_fraction = gap_ratio;
  co.min_angle_degrees = 0.02;  // the groove's bottom has angles near atan(ratio): not the quantity studied
  co.allow_narrow_gap_for_studies = allow_narrow;
  SurfaceCutter cutter(b.mesh, b.locked, co);
  for (int i = 0; i < steps; ++i) {
    const CutStep s = cutter.step(b.from, b.direction);
    if (!s.accepted) throw Error("cut step " + std::to_string(i + 1) + " refused: " + s.reason);
  }
  return cutter.mesh();
}

/// The refined quadrature the gap study compares with (bench_cut's: far 8, mid 4, order 10,
/// depth 18, polar 20 up to 0.1 rad).
/// The Green's table of the uncut body for its top face (where the cuts and tools act), with the
/// base clamped and gravity on: what the update study and its test start every run from.
inline std::shared_ptr<const GreensTable> top_face_table(const CutBody& body) {
  std::vector<Index> top;
  for (Index e = 0; e < body.mesh->num_elements(); ++e)
    if (body.mesh->normal(e).z() > 0.99) top.push_back(e);
  GreensTableOptions to;
  to.gravity = body.gravity;
  to.region = top;
  return std::make_shared<const GreensTable>(GreensTable::compute(body.mesh, body.material, clamped_base(body, *body.mesh), to));
}

inline QuadratureOptions refined_quadrature() {
  QuadratureOptions q;
  q.far_ratio = 8.0;
  q.mid_ratio = 4.0;
  q.mid_order = 10;
  q.max_depth = 18;
  q.polar_order = 20;
  q.polar_max_angle = 0.1;
  return q;
}

/// A* and b of the cut body under gravity with quadrature `q`.
struct CutSystem {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  BoundaryConditions bc;
};
inline CutSystem cut_system(const CutBody& body, const TriangleMesh& mesh, const QuadratureOptions& q) {
  CutSystem s;
  s.bc = clamped_base(body, mesh);
  const InfluenceAssembler assembler(mesh, body.material, q);
  Eigen::VectorXd g;
  InfluenceMatrices hg = assembler.assemble(body.gravity, g);
  s.b = build_right_hand_side(hg, s.bc, g);
  s.A = build_system_matrix_in_place(hg, s.bc);
  return s;
}

/// Largest difference of the displacement unknowns (traction-prescribed dofs) of x and ref,
/// relative to the largest displacement of ref.
inline double displacement_difference(const Eigen::VectorXd& x, const Eigen::VectorXd& ref, const BoundaryConditions& bc) {
  double d = 0.0, s = 0.0;
  for (Index k = 0; k < x.size(); ++k)
    if (bc.kind(k) == BcKind::Traction) {
      d = std::max(d, std::abs(x(k) - ref(k)));
      s = std::max(s, std::abs(ref(k)));
    }
  return d / s;
}

}  // namespace bemsurg::stability
