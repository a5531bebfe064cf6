// Implementation of bemsurg/assembly/influence_assembler.hpp: the O(E^2) quadrature loop.
// Rows are independent, so they run in parallel; each row reads only the shared mesh and writes
// its own three rows of H and G.
#pragma once

namespace bemsurg {

inline InfluenceAssembler::InfluenceAssembler(const TriangleMesh& mesh, const Material& material, const QuadratureOptions& options)
    : mesh_(mesh), material_(material), kernel_((material.validate(), material)), quadrature_(options) {}

inline void InfluenceAssembler::element_pair(Index i, Index e, Eigen::Matrix3d& H, Eigen::Matrix3d& G) const {
  const Eigen::Vector3d p = mesh_.centroid(i);
  const auto c = mesh_.corners(e);
  const Eigen::Vector3d n = mesh_.normal(e);
  H.setZero();
  G.setZero();
  if (i == e) {
    // Polar about the centroid: int U dS = sum w (U r)(d) R; PV int T dS = sum w T_t(d) ln R
    // (the ln(eps) part vanishes because the directions d integrate to zero around the circle).
    quadrature_.polar(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& d, double R, double w) {
      G.noalias() += (w * R) * kernel_.displacement_times_r(d);
      H.noalias() += (w * std::log(R)) * kernel_.traction_tangential_part(d, n);
    });
    H.diagonal().array() += 0.5;
    return;
  }
  Eigen::Matrix3d u, t;
  quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double w) {
    kernel_.displacement_and_traction(x - p, n, u, t);
    G.noalias() += w * u;
    H.noalias() += w * t;
  });
}

inline InfluenceMatrices InfluenceAssembler::assemble() const {
  const Index E = mesh_.num_elements();
  InfluenceMatrices m{Eigen::MatrixXd(3 * E, 3 * E), Eigen::MatrixXd(3 * E, 3 * E)};
#pragma omp parallel for schedule(dynamic, 4)
  for (Index i = 0; i < E; ++i) {
    Eigen::Matrix3d h, g;
    for (Index e = 0; e < E; ++e) {
      element_pair(i, e, h, g);
      m.H.block<3, 3>(3 * i, 3 * e) = h;
      m.G.block<3, 3>(3 * i, 3 * e) = g;
    }
  }
  return m;
}

inline void InfluenceAssembler::assemble_rows(const std::vector<Index>& rows, Eigen::MatrixXd& out_H, Eigen::MatrixXd& out_G) const {
  const Index E = mesh_.num_elements();
  const Index R = static_cast<Index>(rows.size());
  out_H.resize(3 * R, 3 * E);
  out_G.resize(3 * R, 3 * E);
#pragma omp parallel for schedule(dynamic, 1)
  for (Index k = 0; k < R; ++k) {
    Eigen::Matrix3d h, g;
    for (Index e = 0; e < E; ++e) {
      element_pair(rows[static_cast<std::size_t>(k)], e, h, g);
      out_H.block<3, 3>(3 * k, 3 * e) = h;
      out_G.block<3, 3>(3 * k, 3 * e) = g;
    }
  }
}

inline void InfluenceAssembler::assemble_columns(const std::vector<Index>& cols, Eigen::MatrixXd& out_H, Eigen::MatrixXd& out_G) const {
  const Index E = mesh_.num_elements();
  const Index C = static_cast<Index>(cols.size());
  out_H.resize(3 * E, 3 * C);
  out_G.resize(3 * E, 3 * C);
#pragma omp parallel for schedule(dynamic, 16)
  for (Index i = 0; i < E; ++i) {
    Eigen::Matrix3d h, g;
    for (Index k = 0; k < C; ++k) {
      element_pair(i, cols[static_cast<std::size_t>(k)], h, g);
      out_H.block<3, 3>(3 * i, 3 * k) = h;
      out_G.block<3, 3>(3 * i, 3 * k) = g;
    }
  }
}

inline Eigen::Vector3d InfluenceAssembler::gravity_element(const Eigen::Vector3d& p, Index e, const GravityKernel& kernel,
                                                    bool self) const {
  const auto c = mesh_.corners(e);
  const Eigen::Vector3d n = mesh_.normal(e);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  if (self) {
    // P depends on the direction only when dr/dn = 0: int_0^R P r dr = P(d) R^2 / 2.
    quadrature_.polar(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& d, double R, double w) {
      sum += (0.5 * w * R * R) * kernel.tangential_part(d, n);
    });
  } else {
    quadrature_.integrate(p, c[0], c[1], c[2], [&](const Eigen::Vector3d& x, double w) { sum += w * kernel(x - p, n); });
  }
  return sum;
}

inline Eigen::VectorXd InfluenceAssembler::gravity_vector(const Eigen::Vector3d& gravity) const {
  const Index E = mesh_.num_elements();
  Eigen::VectorXd g = Eigen::VectorXd::Zero(3 * E);
  const Eigen::Vector3d body_force = material_.density * gravity;
  if (body_force.squaredNorm() == 0.0) return g;
  const GravityKernel kernel(material_, body_force);
#pragma omp parallel for schedule(dynamic, 4)
  for (Index i = 0; i < E; ++i) {
    const Eigen::Vector3d p = mesh_.centroid(i);
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (Index e = 0; e < E; ++e) sum += gravity_element(p, e, kernel, e == i);
    g.segment<3>(3 * i) = sum;
  }
  return g;
}

}  // namespace bemsurg
