// The checks behind validate_mesh, in order from the cheapest and most basic (is there a mesh,
// are the numbers finite) to the ones that need the others to pass (shell orientation needs
// closed, oriented shells to have a meaningful volume).
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"
#include "bemsurg/number_text.hpp"

namespace bemsurg {

namespace detail {

BEMSURG_INLINE const char* kind_name(MeshIssueKind kind) {
  switch (kind) {
    case MeshIssueKind::EmptyMesh: return "empty mesh";
    case MeshIssueKind::NonFiniteVertex: return "non-finite vertices";
    case MeshIssueKind::DegenerateFace: return "degenerate faces";
    case MeshIssueKind::DuplicateVertex: return "duplicate vertices";
    case MeshIssueKind::BoundaryEdge: return "boundary edges";
    case MeshIssueKind::NonManifoldEdge: return "non-manifold edges";
    case MeshIssueKind::InconsistentOrientation: return "inconsistently oriented edges";
    case MeshIssueKind::InwardShell: return "wrongly oriented shells";
    case MeshIssueKind::UnreferencedVertex: return "unreferenced vertices";
    case MeshIssueKind::SelfIntersection: return "intersecting face pairs";
  }
  return "issues";
}

BEMSURG_INLINE std::string num(double x) { return general_text(x, 6); }

BEMSURG_INLINE std::string edge_name(const MeshEdge& e) {
  return "edge (" + std::to_string(e.vertices[0]) + ", " + std::to_string(e.vertices[1]) + ")";
}

BEMSURG_INLINE std::string shell_name(const MeshTopology& topo, Index s) {
  return "shell " + std::to_string(s) + " (" + std::to_string(topo.shell(s).size()) + " faces, first face " +
         std::to_string(topo.shell(s).front()) + ")";
}

class Collector {
 public:
  Collector(MeshValidationResult& report, std::size_t max_per_kind) : report_(report), max_(max_per_kind) {}
  void add(MeshIssueKind kind, MeshIssueSeverity severity, Index index, std::string message) {
    std::size_t& n = report_.counts[static_cast<std::size_t>(kind)];
    if (n < max_) report_.issues.push_back({kind, severity, index, std::move(message)});
    ++n;
  }
  void error(MeshIssueKind kind, Index index, std::string message) { add(kind, MeshIssueSeverity::Error, index, std::move(message)); }

 private:
  MeshValidationResult& report_;
  std::size_t max_;
};

struct Box {
  Vec3 lo, hi;
  bool contains(const Box& other, double slack) const {
    return (other.lo.array() >= lo.array() - slack).all() && (other.hi.array() <= hi.array() + slack).all();
  }
};

BEMSURG_INLINE void check_shell_orientation(const TriangleMesh& mesh, const MeshTopology& topo, double diag, Collector& out) {
  std::vector<Index> closed;
  for (Index s = 0; s < topo.num_shells(); ++s)
    if (topo.shell_is_closed_and_oriented(s)) closed.push_back(s);
  if (closed.empty()) return;

  const auto& F = mesh.faces();
  std::vector<Box> boxes;
  std::vector<Vec3> probe;  // a point on each shell: the centroid of its largest face
  for (Index s : closed) {
    Box b{Vec3::Constant(std::numeric_limits<double>::infinity()), Vec3::Constant(-std::numeric_limits<double>::infinity())};
    Index largest = topo.shell(s).front();
    for (Index f : topo.shell(s)) {
      for (int k = 0; k < 3; ++k) {
        b.lo = b.lo.cwiseMin(mesh.vertex(F(f, k)));
        b.hi = b.hi.cwiseMax(mesh.vertex(F(f, k)));
      }
      if (mesh.area(f) > mesh.area(largest)) largest = f;
    }
    boxes.push_back(b);
    probe.push_back(mesh.centroid(largest));
  }

  // Nesting depth: how many other closed shells contain this one. Material lies between depth 0
  // and 1, 2 and 3, ...: shells at even depth bound material from outside (positive volume),
  // shells at odd depth are cavities (negative volume). Using parity rather than the immediate
  // parent's sign keeps one flipped shell from making its nested shells look wrong too.
  const double slack = 1e-12 * diag;
  for (std::size_t i = 0; i < closed.size(); ++i) {
    const Index s = closed[i];
    const double volume = topo.shell_volume(s);
    if (std::abs(volume) <= 1e-14 * diag * diag * diag) continue;  // flat, zero-volume shell: no side to judge
    int depth = 0;
    Index parent = -1;
    for (std::size_t j = 0; j < closed.size(); ++j) {
      if (i == j || !boxes[j].contains(boxes[i], slack)) continue;
      const Index t = closed[j];
      if (std::abs(winding_number(mesh, topo.shell(t), probe[i])) > 0.5) {
        ++depth;
        if (parent < 0 || std::abs(topo.shell_volume(t)) < std::abs(topo.shell_volume(parent))) parent = t;
      }
    }
    const bool cavity = depth % 2 == 1;
    if (!cavity && volume < 0.0) {
      out.error(MeshIssueKind::InwardShell, s,
                shell_name(topo, s) + " is inward-facing: it encloses a negative volume (" + num(volume) +
                    "), so its normals point into the material; flip its faces");
    } else if (cavity && volume > 0.0) {
      out.error(MeshIssueKind::InwardShell, s,
                shell_name(topo, s) + " is a cavity inside shell " + std::to_string(parent) + " but encloses a positive volume (" +
                    num(volume) + "), so its normals point into the material; a cavity's normals must point into the cavity");
    }
  }
}

}  // namespace detail

BEMSURG_INLINE std::size_t MeshValidationResult::num_errors() const {
  std::size_t n = 0;
  for (std::size_t k = 0; k < counts.size(); ++k)
    if (static_cast<MeshIssueKind>(k) != MeshIssueKind::UnreferencedVertex) n += counts[k];
  return n;
}

BEMSURG_INLINE std::size_t MeshValidationResult::num_warnings() const { return count(MeshIssueKind::UnreferencedVertex); }

BEMSURG_INLINE std::string MeshValidationResult::summary() const {
  std::ostringstream s;
  use_classic_locale(s);
  for (auto severity : {MeshIssueSeverity::Error, MeshIssueSeverity::Warning})
    for (const MeshIssue& issue : issues)
      if (issue.severity == severity) s << (severity == MeshIssueSeverity::Error ? "error: " : "warning: ") << issue.message << '\n';
  std::vector<std::size_t> stored(kNumMeshIssueKinds, 0);
  for (const MeshIssue& issue : issues) ++stored[static_cast<std::size_t>(issue.kind)];
  for (std::size_t k = 0; k < kNumMeshIssueKinds; ++k)
    if (counts[k] > stored[k])
      s << "... and " << counts[k] - stored[k] << " more " << detail::kind_name(static_cast<MeshIssueKind>(k)) << '\n';
  return s.str();
}

namespace detail {

/// Reports vertices with a non-finite coordinate; true when every vertex is finite.
BEMSURG_INLINE bool check_vertices_finite(const TriangleMesh& mesh, Collector& out) {
  const auto& V = mesh.vertices();
  bool all_finite = true;
  for (Index v = 0; v < mesh.num_vertices(); ++v)
    if (!V.row(v).allFinite()) {
      all_finite = false;
      out.error(MeshIssueKind::NonFiniteVertex, v,
                "vertex " + std::to_string(v) + " has a non-finite coordinate (" + detail::num(V(v, 0)) + ", " + detail::num(V(v, 1)) +
                    ", " + detail::num(V(v, 2)) + ")");
    }

  return all_finite;
}

/// Reports faces that repeat a vertex, overflow, or have near-zero area relative to the mean.
BEMSURG_INLINE void check_degenerate_faces(const TriangleMesh& mesh, const MeshValidationOptions& options, Collector& out) {
  const Index nf = mesh.num_elements();
  const auto& V = mesh.vertices();
  const auto& F = mesh.faces();
  // Degenerate faces: relative to the mean area, so the test does not depend on units.
  double area_sum = 0.0;
  Index area_count = 0;
  for (Index f = 0; f < nf; ++f)
    if (std::isfinite(mesh.area(f))) {
      area_sum += mesh.area(f);
      ++area_count;
    }
  const double mean_area = area_count > 0 ? area_sum / static_cast<double>(area_count) : 0.0;
  for (Index f = 0; f < nf; ++f) {
    const bool repeats = F(f, 0) == F(f, 1) || F(f, 1) == F(f, 2) || F(f, 2) == F(f, 0);
    const std::string corners = "(" + std::to_string(F(f, 0)) + ", " + std::to_string(F(f, 1)) + ", " + std::to_string(F(f, 2)) + ")";
    const bool corners_finite = V.row(F(f, 0)).allFinite() && V.row(F(f, 1)).allFinite() && V.row(F(f, 2)).allFinite();
    const double normal_length = mesh.normal(f).norm();
    if (repeats) {
      out.error(MeshIssueKind::DegenerateFace, f,
                "face " + std::to_string(f) + " " + corners + " repeats a vertex: the triangle is degenerate");
    } else if (corners_finite && (!std::isfinite(mesh.area(f)) || (mesh.area(f) > 0.0 && !(std::abs(normal_length - 1.0) < 1e-6)))) {
      // Finite corners, yet the area or the normal overflowed (coordinates near 1e154 or beyond):
      // such an element would put inf into the assembly and its zero normal would pass for flat.
      out.error(MeshIssueKind::DegenerateFace, f,
                "face " + std::to_string(f) + " " + corners + " has a non-finite area (" + detail::num(mesh.area(f)) +
                    ") or normal (length " + detail::num(normal_length) + ") although its corners are finite (first corner (" +
                    detail::num(V(F(f, 0), 0)) + ", " + detail::num(V(F(f, 0), 1)) + ", " + detail::num(V(F(f, 0), 2)) +
                    ")): the coordinates are too large to compute with; check the mesh scale (bemsurg works in metres)");
    } else if (std::isfinite(mesh.area(f)) && !(mesh.area(f) > options.degenerate_area_tolerance * mean_area)) {
      out.error(MeshIssueKind::DegenerateFace, f,
                "face " + std::to_string(f) + " " + corners + " has near-zero area " + detail::num(mesh.area(f)) + " (mean face area " +
                    detail::num(mean_area) + "): the triangle is degenerate");
    } else if (corners_finite) {
      const auto c = mesh.corners(f);
      const double ratio = aspect_ratio(c[0], c[1], c[2]);
      if (ratio > options.max_aspect_ratio)
        out.error(MeshIssueKind::DegenerateFace, f,
                  "face " + std::to_string(f) + " " + corners + " is a sliver of aspect ratio " + detail::num(ratio) +
                      " (longest edge / shortest altitude), above the limit " + detail::num(options.max_aspect_ratio) +
                      " where the traction solved on it is meaningless (docs/stability.md): remesh it");
    }
  }
}

/// Warns about unused vertices and reports coincident used ones; returns the bounding-box
/// diagonal of the used vertices (the scale of the later tolerances).
BEMSURG_INLINE double check_vertex_use(const TriangleMesh& mesh, const MeshValidationOptions& options, Collector& out) {
  const Index nv = mesh.num_vertices(), nf = mesh.num_elements();
  const auto& V = mesh.vertices();
  const auto& F = mesh.faces();
  // Referenced vertices: unused ones are only warned about; coincident used ones are errors.
  std::vector<bool> used(static_cast<std::size_t>(nv), false);
  for (Index f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) used[static_cast<std::size_t>(F(f, k))] = true;
  std::vector<Index> used_list;
  for (Index v = 0; v < nv; ++v) {
    if (used[static_cast<std::size_t>(v)]) {
      used_list.push_back(v);
    } else if (options.warn_unreferenced_vertices) {
      out.add(MeshIssueKind::UnreferencedVertex, MeshIssueSeverity::Warning, v, "vertex " + std::to_string(v) + " is not used by any face");
    }
  }
  RowMatrixX3d used_coords(static_cast<Index>(used_list.size()), 3);
  for (std::size_t i = 0; i < used_list.size(); ++i) used_coords.row(static_cast<Index>(i)) = V.row(used_list[i]);
  const double diag = bounding_box_diagonal(used_coords);
  const std::vector<Index> rep = coincident_vertex_representatives(used_coords, options.duplicate_vertex_tolerance * diag);
  for (std::size_t i = 0; i < rep.size(); ++i)
    if (rep[i] != static_cast<Index>(i)) {
      const Index a = used_list[static_cast<std::size_t>(rep[i])], b = used_list[i];
      out.error(MeshIssueKind::DuplicateVertex, b,
                "vertices " + std::to_string(a) + " and " + std::to_string(b) + " coincide at (" + detail::num(V(b, 0)) + ", " +
                    detail::num(V(b, 1)) + ", " + detail::num(V(b, 2)) + "): the mesh is probably not welded");
    }

  return diag;
}

/// Reports open, non-manifold and inconsistently oriented edges.
BEMSURG_INLINE void check_edges(const MeshTopology& topo, Collector& out) {
  for (Index e = 0; e < topo.num_edges(); ++e) {
    const MeshEdge& edge = topo.edge(e);
    if (edge.vertices[0] == edge.vertices[1]) continue;  // reported as a degenerate face already
    const std::string first = "face " + std::to_string(edge.faces.front().face);
    if (edge.is_boundary()) {
      out.error(MeshIssueKind::BoundaryEdge, e,
                first + ": " + detail::edge_name(edge) + " belongs to this face only: the mesh is not closed");
    } else if (edge.is_non_manifold()) {
      out.error(MeshIssueKind::NonManifoldEdge, e,
                first + ": " + detail::edge_name(edge) + " is shared by " + std::to_string(edge.faces.size()) +
                    " faces: the mesh is not 2-manifold");
    } else if (edge.faces[0].forward == edge.faces[1].forward) {
      out.error(MeshIssueKind::InconsistentOrientation, e,
                "faces " + std::to_string(edge.faces[0].face) + " and " + std::to_string(edge.faces[1].face) + " traverse " +
                    detail::edge_name(edge) + " in the same direction: the orientation is inconsistent (one of them is flipped)");
    }
  }
}

/// Reports pairs of faces that intersect (only on meshes whose faces and vertices passed).
BEMSURG_INLINE void check_self_intersections(const TriangleMesh& mesh, const MeshValidationOptions& options, bool all_finite,
                                             const MeshValidationResult& report, Collector& out) {
  // Before the shell orientation: overlapping shells also confuse their nesting, and the face
  // pair is the cause to name.
  // Not on unwelded meshes: faces meeting at coincident but distinct vertices would all count as
  // touching, and the duplicates are the cause already named.
  if (options.check_self_intersection && all_finite && report.count(MeshIssueKind::DegenerateFace) == 0 &&
      report.count(MeshIssueKind::DuplicateVertex) == 0) {
    SelfIntersectionOptions so;
    so.max_pairs = options.max_issues_per_kind + 1;
    const auto pairs = find_self_intersections(mesh, so);
    for (const auto& pr : pairs) {
      const Vec3 c = mesh.centroid(pr.first);
      out.error(MeshIssueKind::SelfIntersection, pr.first,
                "faces " + std::to_string(pr.first) + " and " + std::to_string(pr.second) + " intersect (face " + std::to_string(pr.first) +
                    " near (" + detail::num(c.x()) + ", " + detail::num(c.y()) + ", " + detail::num(c.z()) +
                    ")): the surface cuts through itself or two shells overlap, so it bounds no body");
    }
  }
}

}  // namespace detail

BEMSURG_INLINE MeshValidationResult validate_mesh(const TriangleMesh& mesh, const MeshValidationOptions& options) {
  MeshValidationResult report;
  report.counts.assign(kNumMeshIssueKinds, 0);
  detail::Collector out(report, options.max_issues_per_kind);
  const Index nv = mesh.num_vertices(), nf = mesh.num_elements();
  if (nf == 0 || nv == 0) {
    out.error(MeshIssueKind::EmptyMesh, -1, "the mesh is empty (" + std::to_string(nv) + " vertices, " + std::to_string(nf) + " faces)");
    return report;
  }
  const bool all_finite = detail::check_vertices_finite(mesh, out);
  detail::check_degenerate_faces(mesh, options, out);
  const double diag = detail::check_vertex_use(mesh, options, out);
  const MeshTopology topo(mesh);
  detail::check_edges(topo, out);
  detail::check_self_intersections(mesh, options, all_finite, report, out);
  if (options.check_shell_orientation && all_finite) detail::check_shell_orientation(mesh, topo, diag, out);
  return report;
}

BEMSURG_INLINE void require_valid_mesh(const TriangleMesh& mesh, const MeshValidationOptions& options) {
  const MeshValidationResult report = validate_mesh(mesh, options);
  if (report.valid()) return;
  const auto first =
      std::find_if(report.issues.begin(), report.issues.end(), [](const MeshIssue& i) { return i.severity == MeshIssueSeverity::Error; });
  // With max_issues_per_kind = 0 nothing is stored; the counts still say what went wrong.
  std::string message = "invalid mesh: " + (first != report.issues.end() ? first->message : std::string("see validate_mesh"));
  const std::size_t more = report.num_errors() - 1;
  if (more > 0) message += " (and " + std::to_string(more) + " more error" + (more > 1 ? "s" : "") + ")";
  throw InvalidMeshError(message);
}

}  // namespace bemsurg
