// Result files of a solve (bemsurg/io/results_io.hpp; docs/scene-format.md, "Outputs"): the
// per-element boundary solution of Wang et al. 2007 eq. 6 after recovery, the interior field of
// eqs. 7-9, a VTK surface for viewers and a JSON run report.
#include "bemsurg/io/results_io.hpp"

#include <sys/resource.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>
#include <vector>

#include "bemsurg/assembly/element_types.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/version.hpp"

namespace bemsurg {
namespace {

void append_row(std::string& out, const double* values, int count) {
  for (int i = 0; i < count; ++i) {
    out += ',';
    append_number(out, values[i]);
  }
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError("cannot write '" + path + "': " + std::generic_category().message(errno));
  out << text;
  out.close();
  if (!out) throw IoError("cannot write '" + path + "': write failed (disk full?)");
}

}  // namespace

void write_elements_csv(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& solution) {
  const Index n = mesh.num_elements();
  if (solution.displacement.rows() != n || solution.traction.rows() != n)
    throw InvalidArgumentError("write_elements_csv: the solution has " + std::to_string(solution.displacement.rows()) + " rows, the mesh " +
                               std::to_string(n) + " elements");
  std::string text = kElementsCsvHeader;
  text += '\n';
  text.reserve(text.size() + static_cast<std::size_t>(n) * 300);
  for (Index e = 0; e < n; ++e) {
    double row[13];
    for (int c = 0; c < 3; ++c) {
      row[c] = mesh.centroids()(e, c);
      row[3 + c] = mesh.normals()(e, c);
      row[7 + c] = solution.displacement(e, c);
      row[10 + c] = solution.traction(e, c);
    }
    row[6] = mesh.area(e);
    append_integer(text, e);
    append_row(text, row, 13);
    text += '\n';
  }
  write_text(path, text);
}

namespace {

/// corners.csv and nodes.csv: three rows per element (point k = corner or collocation node k), the
/// point's position and the linear field there.
void write_linear_points_csv(const std::string& path, const char* header, const char* who, const TriangleMesh& mesh,
                             const BoundarySolution& nodes, bool at_corners) {
  const Index n = mesh.num_elements();
  if (nodes.displacement.rows() != 3 * n || nodes.traction.rows() != 3 * n)
    throw InvalidArgumentError(std::string(who) + ": the per-node solution has " + std::to_string(nodes.displacement.rows()) +
                               " rows, linear elements on this mesh have " + std::to_string(3 * n) + " nodes");
  std::string text = header;
  text += '\n';
  for (Index e = 0; e < n; ++e) {
    const Eigen::Matrix3d node_u = nodes.displacement.middleRows<3>(3 * e), node_t = nodes.traction.middleRows<3>(3 * e);
    const Eigen::Matrix3d u = at_corners ? linear_nodes_to_corners(node_u) : node_u;
    const Eigen::Matrix3d t = at_corners ? linear_nodes_to_corners(node_t) : node_t;
    const auto corner = mesh.corners(e);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d x = at_corners ? Eigen::Vector3d(corner[std::size_t(k)]) : collocation_node<LinearElement>(corner, k);
      double row[9];
      for (int c = 0; c < 3; ++c) {
        row[c] = x(c);
        row[3 + c] = u(k, c);
        row[6 + c] = t(k, c);
      }
      append_integer(text, e);
      text += ',';
      append_integer(text, k);
      append_row(text, row, 9);
      text += '\n';
    }
  }
  write_text(path, text);
}

}  // namespace

void write_corners_csv(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& nodes) {
  write_linear_points_csv(path, kCornersCsvHeader, "write_corners_csv", mesh, nodes, true);
}

void write_nodes_csv(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& nodes) {
  write_linear_points_csv(path, kNodesCsvHeader, "write_nodes_csv", mesh, nodes, false);
}

void write_interior_csv(const std::string& path, const RowMatrixX3d& points, const RowMatrixX3d& displacement, const StressRows& stress) {
  const Index n = points.rows();
  if (displacement.rows() != n || stress.rows() != n)
    throw InvalidArgumentError("write_interior_csv: " + std::to_string(n) + " points but " + std::to_string(displacement.rows()) +
                               " displacements and " + std::to_string(stress.rows()) + " stresses");
  std::string text = kInteriorCsvHeader;
  text += '\n';
  for (Index i = 0; i < n; ++i) {
    double row[12];
    for (int c = 0; c < 3; ++c) {
      row[c] = points(i, c);
      row[3 + c] = displacement(i, c);
    }
    for (int c = 0; c < 6; ++c) row[6 + c] = stress(i, c);
    append_number(text, row[0]);
    append_row(text, row + 1, 11);
    text += '\n';
  }
  write_text(path, text);
}

void write_solution_vtk(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& solution) {
  Eigen::VectorXd normal_traction(mesh.num_elements());
  for (Index e = 0; e < mesh.num_elements(); ++e) normal_traction(e) = solution.traction.row(e).dot(mesh.normals().row(e));
  write_vtk(path, mesh,
            {MeshField("displacement", solution.displacement), MeshField("traction", solution.traction),
             MeshField("normal_traction", normal_traction)},
            {MeshField("displacement", mesh.element_to_vertex(solution.displacement))}, "bemsurg solve");
}

void write_linear_solution_vtk(const std::string& path, const TriangleMesh& mesh, const BoundarySolution& centroids,
                               const BoundarySolution& nodes) {
  const Index n = mesh.num_elements();
  if (nodes.displacement.rows() != 3 * n || centroids.displacement.rows() != n)
    throw InvalidArgumentError("write_linear_solution_vtk: expected " + std::to_string(n) + " centroid and " + std::to_string(3 * n) +
                               " node rows");
  RowMatrixX3d points(3 * n, 3), u(3 * n, 3), t(3 * n, 3);
  RowMatrixX3i faces(n, 3);
  for (Index e = 0; e < n; ++e) {
    const auto corner = mesh.corners(e);
    for (int k = 0; k < 3; ++k) points.row(3 * e + k) = corner[std::size_t(k)].transpose();
    faces.row(e) << int(3 * e), int(3 * e + 1), int(3 * e + 2);
    u.middleRows<3>(3 * e) = linear_nodes_to_corners(nodes.displacement.middleRows<3>(3 * e));
    t.middleRows<3>(3 * e) = linear_nodes_to_corners(nodes.traction.middleRows<3>(3 * e));
  }
  const TriangleMesh unshared(points, faces);
  Eigen::VectorXd normal_traction(n);
  for (Index e = 0; e < n; ++e) normal_traction(e) = centroids.traction.row(e).dot(mesh.normals().row(e));
  write_vtk(path, unshared,
            {MeshField("displacement", centroids.displacement), MeshField("traction", centroids.traction),
             MeshField("normal_traction", normal_traction)},
            {MeshField("displacement", u), MeshField("traction", t)}, "bemsurg solve (linear elements)");
}

double peak_memory_mb() {
  // VmHWM is this image's own peak (it starts afresh at exec); getrusage's ru_maxrss is the fallback
  // only, because Linux carries it across fork and exec: a small program started by a large parent
  // would report the parent's size (the benchmark report runs each configuration that way).
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kib = 0.0;
      if (status >> kib) return kib / 1024.0;
      break;
    }
    status.ignore(1 << 16, '\n');
  }
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

void write_report_json(const std::string& path, const RunResult& report) {
  // Non-finite values are not JSON; a residual that is NaN is reported as null.
  const auto number = [](double x) { return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(); };
  nlohmann::ordered_json j;
  j["element_type"] = report.element_type;
  j["elements"] = report.elements;
  j["equations"] = report.equations;
  j["interior_points"] = report.interior_points;
  j["timings"] = {{"load", number(report.timings.load)},     {"assembly", number(report.timings.assembly)},
                  {"system", number(report.timings.system)}, {"solve", number(report.timings.solve)},
                  {"post", number(report.timings.post)},     {"total", number(report.timings.total)}};
  j["peak_memory_mb"] = number(report.peak_memory_mb);
  j["ranks"] = report.ranks;
  j["peak_memory_mb_per_rank"] = nlohmann::ordered_json::array();
  for (double mb : report.peak_memory_mb_per_rank.empty() ? std::vector<double>{report.peak_memory_mb} : report.peak_memory_mb_per_rank)
    j["peak_memory_mb_per_rank"].push_back(number(mb));
  const bool hierarchical = report.backend == SolverBackend::HMatrix;
  const bool distributed = report.backend == SolverBackend::ScaLapack;
  j["solver"] = {{"method", hierarchical || distributed ? to_string(report.backend) : to_string(report.solver.method)},
                 {"preconditioner", to_string(report.solver.preconditioner)},
                 {"iterations", report.solver.iterations},
                 {"status", to_string(report.solver.status)},
                 {"relative_residual", number(report.solver.relative_residual)},
                 {"setup_seconds", number(report.solver.setup_seconds)},
                 {"solve_seconds", number(report.solver.solve_seconds)}};
  j["backend"] = {{"name", to_string(report.backend)}, {"chosen_by", report.backend_automatic ? "auto" : "scene"}};
  if (hierarchical) {
    const HierarchicalResult& h = report.hierarchical;
    j["backend"]["compression_tolerance"] = number(h.compression_tolerance);
    j["backend"]["compression_ratio"] = number(h.compression_ratio);
    j["backend"]["largest_rank"] = h.largest_rank;
    j["backend"]["stored_entries"] = h.stored_entries;
    j["backend"]["dense_entries"] = h.dense_entries;
    j["backend"]["leaves_full"] = h.leaves_full;
    j["backend"]["leaves_low_rank"] = h.leaves_low_rank;
    j["backend"]["column_scale"] = number(h.column_scale);
    j["backend"]["assembly_seconds"] = number(h.assembly_seconds);
    j["backend"]["factorization_seconds"] = number(h.factorization_seconds);
    j["backend"]["solve_seconds"] = number(h.solve_seconds);
  }
  if (distributed) {
    const ScalapackResult& s = report.scalapack;
    j["backend"]["process_grid"] = {s.process_rows, s.process_columns};
    j["backend"]["block_size"] = s.block_size;
    j["backend"]["local_rows"] = s.local_rows;
    j["backend"]["local_columns"] = s.local_columns;
    j["backend"]["assembly_seconds"] = number(s.assembly_seconds);
    j["backend"]["factorization_seconds"] = number(s.factorization_seconds);
    j["backend"]["solve_seconds"] = number(s.solve_seconds);
    j["backend"]["gather_seconds"] = number(s.gather_seconds);
  }
  j["boundary_rules"] = nlohmann::ordered_json::array();
  for (const BoundaryRuleArea& r : report.boundary_rules) {
    nlohmann::ordered_json rule;
    rule["rule"] = r.key;
    rule["area"] = number(r.area);
    if (r.has_region) rule["region_area"] = number(r.region_area);
    rule["conform"] = r.conform;
    rule["refine_rim"] = r.refine_rim;
    j["boundary_rules"].push_back(std::move(rule));
  }
  j["warnings"] = report.warnings;
  j["scene"] = report.scene;
  j["mesh"] = report.mesh_source;
  j["bemsurg_version"] = version_string();
  write_text(path, j.dump(2) + "\n");
}

}  // namespace bemsurg
