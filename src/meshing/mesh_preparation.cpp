// prepare_mesh (mesh/mesh_preparation.hpp, docs/organs.md): a segmentation's surface as exported to
// a closed, outward, validated surface of a size the dense BEM solves on a small machine. The
// steps are numbered as in the header; the CGAL ones are in cgal_repair.cpp, the others in
// mesh_preparation_steps.cpp.
#include "bemsurg/meshing/mesh_preparation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/red_green_refinement.hpp"
#include "bemsurg/mesh/self_intersection.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"
#include "bemsurg/meshing/planar_regions.hpp"
#include "bemsurg/number_text.hpp"
#include "cgal_repair.hpp"
#include "mesh_preparation_steps.hpp"

namespace bemsurg {
namespace {

using Clock = std::chrono::steady_clock;

/// Appends the seconds since the last mark (or construction) to the report's timings.
class StageTimer {
 public:
  explicit StageTimer(MeshPreparationReport& r) : r_(r), last_(Clock::now()) {}
  void mark(const char* stage) {
    const auto now = Clock::now();
    r_.timings.emplace_back(stage, std::chrono::duration<double>(now - last_).count());
    last_ = now;
  }

 private:
  MeshPreparationReport& r_;
  Clock::time_point last_;
};

void check_options(const MeshPreparationOptions& o) {
  const auto positive = [](double x, const char* name) {
    if (!(std::isfinite(x) && x > 0.0))
      throw InvalidArgumentError(std::string(name) + " must be positive and finite, got " + general_text(x, 3));
  };
  positive(o.scale, "scale");
  positive(o.wrap_alpha_fraction, "wrap alpha");
  positive(o.wrap_offset_fraction, "wrap offset");
  positive(o.max_hole_fraction, "hole limit");
  if (o.target_elements < 0 || o.target_elements > kMaxPreparedElements)
    throw InvalidArgumentError("target elements must be between 1 and " + std::to_string(kMaxPreparedElements) + ", got " +
                               std::to_string(o.target_elements));
  if (o.default_elements < 1 || o.default_elements > kMaxPreparedElements)
    throw InvalidArgumentError("the default target must be between 1 and " + std::to_string(kMaxPreparedElements) + " elements, got " +
                               std::to_string(o.default_elements));
  if (o.edge_length != 0.0) positive(o.edge_length, "edge length");
  const int targets = int(o.target_elements > 0) + int(o.edge_length > 0.0) + int(o.region.has_value());
  if (targets > 1) throw InvalidArgumentError("give at most one of a target element count, an edge length and an operating region");
}

/// Shells that enclose no volume (|V| below 1e-6 of the volume of a sphere of their area): fins and
/// double-sided sheets, whose orienting and hole filling leaves two copies of each face.
TriangleMesh drop_flat_shells(const TriangleMesh& mesh, MeshPreparationReport& r) {
  const MeshTopology topo(mesh);
  RowMatrixX3i kept(mesh.num_elements(), 3);
  Index n = 0, dropped = 0;
  for (Index s = 0; s < topo.num_shells(); ++s) {
    double area = 0.0;
    for (const Index f : topo.shell(s)) area += mesh.area(f);
    const double sphere_volume = std::pow(area, 1.5) / (6.0 * std::sqrt(numbers::pi));
    if (std::abs(topo.shell_volume(s)) < 1e-6 * sphere_volume) {
      ++dropped;
      continue;
    }
    for (const Index f : topo.shell(s)) kept.row(n++) = mesh.faces().row(f);
  }
  if (dropped == 0) return mesh;
  r.steps.push_back("dropped " + std::to_string(dropped) + " shell" + (dropped > 1 ? "s" : "") + " enclosing no volume (fins, sheets)");
  return weld_vertices(TriangleMesh(mesh.vertices(), kept.topRows(n)), 0.0);
}

/// Steps 2-4: the repaired surface (closed, 2-manifold; orientation still to be set by nesting).
TriangleMesh repair(const RowMatrixX3d& vertices, const RowMatrixX3i& faces, double diagonal, const MeshPreparationOptions& o,
                    MeshPreparationReport& r, double& input_volume, detail::CleanSoup& soup) {
  StageTimer timer(r);
  soup = detail::clean_soup(vertices, faces, diagonal, r.defects);
  if (soup.faces.rows() == 0) throw InvalidMeshError("the input has no face of non-zero area");
  detail::count_non_manifold(TriangleMesh(soup.vertices, soup.faces), r.defects);
  r.steps.push_back("cleaned: " + std::to_string(r.defects.duplicate_vertices) + " duplicate vertices merged, " +
                    std::to_string(r.defects.degenerate_faces + r.defects.duplicate_faces) + " degenerate or repeated faces dropped");
  const double max_hole = o.max_hole_fraction * diagonal;
  timer.mark("clean");
  detail::OrientedClosedSoup closed = detail::cgal_orient_and_close(soup.vertices, soup.faces, max_hole);
  r.defects.holes = closed.holes;
  if (closed.unfilled > 0)
    throw InvalidMeshError("the surface is open: " + std::to_string(closed.unfilled) + " hole" + (closed.unfilled > 1 ? "s" : "") +
                           " with a boundary up to " + general_text(closed.longest_unfilled, 3) + " m long, more than the limit of " +
                           general_text(max_hole, 3) + " m (" + general_text(o.max_hole_fraction, 3) +
                           " of the bounding-box diagonal): an open sheet is not a body; raise the limit (--max-hole) only if "
                           "the hole really is to be closed flat");
  r.holes_filled = closed.filled;
  // Flipped faces: per connected part, the faces whose order disagreed with the majority.
  {
    const MeshTopology topo(TriangleMesh(soup.vertices, soup.faces));
    for (Index s = 0; s < topo.num_shells(); ++s) {
      Index k = 0;
      for (const Index f : topo.shell(s)) k += closed.reversed[std::size_t(f)];
      r.defects.flipped_faces += std::min<Index>(k, static_cast<Index>(topo.shell(s).size()) - k);
    }
  }
  if (closed.filled > 0) r.steps.push_back("filled " + std::to_string(closed.filled) + " holes");
  // A fin or a stray sheet comes out of orienting as a shell of zero volume (its hole filled by a
  // copy of itself): no body to keep, and a spike that the rebuild would keep as one.
  TriangleMesh closed_mesh = drop_flat_shells(closed.mesh, r);
  timer.mark("orient_and_close");
  SelfIntersectionOptions si;
  si.max_pairs = 1000000;
  r.defects.self_intersections = static_cast<Index>(find_self_intersections(closed_mesh, si).size());
  const MeshTopology closed_topo(closed_mesh);
  for (Index s = 0; s < closed_topo.num_shells(); ++s) input_volume += std::abs(closed_topo.shell_volume(s));
  timer.mark("self_intersection");

  std::string reason;
  // Where the surface was not manifold, orienting made copies of vertices; the copies' faces touch
  // there, so the crossing test counts those places too.
  if (r.defects.self_intersections > 0)
    reason = std::to_string(r.defects.self_intersections) + " pairs of faces that cross or touch" +
             (closed.duplicated_vertices > 0 ? " (also at non-manifold places)" : "");
  if (closed.failed > 0)
    reason += std::string(reason.empty() ? "" : ", ") + std::to_string(closed.failed) + " short hole" + (closed.failed > 1 ? "s" : "") +
              " that no triangulation closes";
  if (o.force_wrap && reason.empty()) reason = "asked for";
  if (reason.empty()) return closed_mesh;
  r.rebuilt = true;
  r.rebuild_reason = reason;
  r.wrap_alpha = o.wrap_alpha_fraction * diagonal;
  r.wrap_offset = o.wrap_offset_fraction * r.wrap_alpha;
  TriangleMesh wrap = detail::cgal_alpha_wrap(closed_mesh.vertices(), closed_mesh.faces(), r.wrap_alpha, r.wrap_offset);
  timer.mark("wrap");
  r.steps.push_back("rebuilt by alpha wrapping (" + reason + "): alpha " + general_text(r.wrap_alpha, 3) + " m, offset " +
                    general_text(r.wrap_offset, 3) + " m, " + std::to_string(wrap.num_elements()) + " faces");
  return wrap;
}

/// Gmsh's reparametrisation splits the surface at creases sharper than the feature angle; on an
/// organic surface (a marching-cubes staircase, a wrap around a thin part) those can cut patches
/// Gmsh cannot parametrise. Then the same remesh is tried with fewer creases: 90 degrees, none.
TriangleMesh remesh_with_fewer_creases(const TriangleMesh& surface, const OperatingRegion& region, GradedRemeshOptions g,
                                       MeshPreparationReport& r) {
  for (const double angle : {g.feature_angle_degrees, 90.0, 179.0}) {  // graded_remesh takes angles below 180
    if (angle < g.feature_angle_degrees) continue;
    g.feature_angle_degrees = angle;
    try {
      return graded_remesh(surface, region, g).mesh;
    } catch (const InvalidArgumentError&) { throw; } catch (const InvalidMeshError&) {
      throw;
    } catch (const Error& e) {
      if (angle >= 179.0) throw;
      r.steps.push_back("remesh with creases above " + general_text(angle, 3) + " degrees failed (" + e.what() + "); trying fewer");
    }
  }
  throw Error("unreachable");
}

double repaired_diagonal(const TriangleMesh& mesh) { return bounding_box_diagonal(mesh.vertices()); }

/// The wrap's vertices within twice the wrap offset of a flat face of the body go back onto the
/// face's plane, where their faces all face the face's way within 60 degrees (a face turned further,
/// on the wrap's rounded rim, would be flattened over its neighbours): the remesh then finds the
/// face as a planar region again and keeps it flat up to its rim.
void snap_wrap_to_planes(const TriangleMesh& body, const std::vector<PlanarRegion>& planes, double offset, RowMatrixX3d& v,
                         const RowMatrixX3i& f, MeshPreparationReport& r) {
  if (planes.empty()) return;
  const Index moved = snap_to_planar_regions(v, f, body, planes, 2.0 * offset, 0.5);
  r.steps.push_back("put " + std::to_string(moved) + " vertices of the wrap back onto the body's " + std::to_string(planes.size()) +
                    " flat face" + (planes.size() > 1 ? "s" : ""));
}

/// Gmsh's reparametrisation costs grow with its input (measured: 44 s for a 327,680-face surface,
/// 2.4 s for a 41,000-face one of the same body), so a body much finer than the remesh needs is
/// first coarsened: each shell wrapped at `alpha` (the wrap of a cavity turned back inward). Only
/// when the wraps will have under half the faces (they have ~area / (0.433 alpha^2): 41,000 estimated 52,000).
/// The wrap lies its offset (alpha / 20) outside the body and rounds every rim off, so a flat face
/// of the body (a resection plane) would come out as a slightly domed one that the remesh cannot
/// find; the wrap's vertices over a flat face are put back onto its plane (snap_wrap_to_planes).
TriangleMesh coarsen_for_remesh(const TriangleMesh& body, double alpha, MeshPreparationReport& r) {
  const double wrap_faces = body.total_area() / (0.433 * alpha * alpha);
  if (body.num_elements() < 50000 || wrap_faces > 0.5 * double(body.num_elements())) return body;
  const std::vector<PlanarRegion> planes = find_planar_regions(body);
  const MeshTopology topo(body);
  std::vector<TriangleMesh> parts;
  Index faces = 0, vertices = 0;
  for (Index s = 0; s < topo.num_shells(); ++s) {
    RowMatrixX3i shell(static_cast<Index>(topo.shell(s).size()), 3);
    for (std::size_t i = 0; i < topo.shell(s).size(); ++i) shell.row(Index(i)) = body.faces().row(topo.shell(s)[i]);
    TriangleMesh wrap = detail::cgal_alpha_wrap(body.vertices(), shell, alpha, alpha / 20.0);
    RowMatrixX3i f = wrap.faces();
    if (topo.shell_volume(s) < 0.0) f.col(1).swap(f.col(2));  // a cavity stays a cavity
    parts.emplace_back(wrap.vertices(), f);
    faces += f.rows();
    vertices += wrap.num_vertices();
  }
  RowMatrixX3d v(vertices, 3);
  RowMatrixX3i f(faces, 3);
  Index nv = 0, nf = 0;
  for (const TriangleMesh& part : parts) {
    v.middleRows(nv, part.num_vertices()) = part.vertices();
    f.middleRows(nf, part.num_elements()) = part.faces().array() + int(nv);
    nv += part.num_vertices();
    nf += part.num_elements();
  }
  r.steps.push_back("coarsened for the remesh by wrapping at " + general_text(alpha, 3) + " m: " + std::to_string(body.num_elements()) +
                    " -> " + std::to_string(faces) + " faces");
  snap_wrap_to_planes(body, planes, alpha / 20.0, v, f, r);
  return TriangleMesh(std::move(v), std::move(f));
}

/// Gmsh's reparametrisation of a surface of a handful of faces can fail to finish (a tetrahedron's
/// four faces ran for over 10 minutes): a repaired surface of under 1,000 faces is first split
/// uniformly (red-green, every face into four per level; the geometry is unchanged).
TriangleMesh refine_for_remesh(const TriangleMesh& mesh) {
  int levels = 0;
  while (double(mesh.num_elements()) * std::pow(4.0, levels) < 1000.0) ++levels;
  if (levels == 0) return mesh;
  std::vector<Index> all(static_cast<std::size_t>(mesh.num_elements()));
  std::iota(all.begin(), all.end(), Index(0));
  return refine_red_green(mesh, all, levels).mesh;
}

/// Gmsh cannot mesh a closed shell with triangles of edge h when the shell is not even two of them
/// across (a speck kept with keep_all): refused here with the figures, not left to Gmsh's message.
template <typename EdgeAt>
void require_shells_meshable(const TriangleMesh& mesh, EdgeAt edge_at) {
  const MeshTopology topo(mesh);
  for (Index s = 0; s < topo.num_shells(); ++s) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const Index f : topo.shell(s))
      for (int c = 0; c < 3; ++c) {
        lo = lo.cwiseMin(mesh.vertices().row(mesh.faces()(f, c)).transpose());
        hi = hi.cwiseMax(mesh.vertices().row(mesh.faces()(f, c)).transpose());
      }
    const double h = edge_at(Vec3(0.5 * (lo + hi)));
    if ((hi - lo).norm() < 2.0 * h)
      throw InvalidMeshError("shell " + std::to_string(s) + " of the repaired surface is " + general_text((hi - lo).norm(), 3) +
                             " m across, less than two elements of " + general_text(h, 3) +
                             " m: it cannot be remeshed at that size; leave out --keep-all (the largest body is kept) or ask "
                             "for shorter edges");
  }
}

/// Step 6: the remesh the options ask for (graded, uniform to a count or a length, or the default).
TriangleMesh remesh(const TriangleMesh& repaired, const MeshPreparationOptions& o, MeshPreparationReport& r) {
  const double alpha = o.wrap_alpha_fraction * repaired_diagonal(repaired);
  if (o.no_remesh) {  // a later graded remesh (a scene's operating region) gets a coarsened copy
    r.remesh = "none";
    const double inside = o.graded_options.inside_edge_length;
    return inside > 0.0 ? coarsen_for_remesh(repaired, std::min(alpha, 0.5 * inside), r) : repaired;
  }
  if (o.region) {
    r.remesh = "graded";
    const TriangleMesh coarse =
        refine_for_remesh(coarsen_for_remesh(repaired, std::min(alpha, 0.5 * o.graded_options.inside_edge_length), r));
    require_shells_meshable(coarse, [&](const Vec3& x) { return graded_target_size(*o.region, o.graded_options, x); });
    TriangleMesh m = remesh_with_fewer_creases(coarse, *o.region, o.graded_options, r);
    r.steps.push_back("graded remesh to " + o.region->describe() + ": " + std::to_string(m.num_elements()) + " elements");
    return m;
  }
  // The default never asks for more elements than the repair left (docs/organs.md). A surface that
  // is still no valid body (slivers above kMaxAspectRatio: the repair keeps them) is remeshed to its
  // own face count instead.
  const bool few = o.target_elements == 0 && o.edge_length <= 0.0 && repaired.num_elements() <= o.default_elements;
  if (few && validate_mesh(repaired).valid()) {
    r.remesh = "none";
    r.steps.push_back("kept as repaired: " + std::to_string(repaired.num_elements()) + " faces, no more than the default target");
    return repaired;
  }
  r.remesh = "uniform";
  const Index target = o.target_elements > 0 ? o.target_elements : few ? repaired.num_elements() : o.default_elements;
  r.target_elements = o.edge_length > 0.0 ? 0 : target;
  // An equilateral triangle of edge h has area (sqrt(3)/4) h^2; Gmsh's frontal mesher makes ~8 %
  // more triangles than area / that, and one correction pass follows when it misses by over 10 %.
  double h = o.edge_length > 0.0 ? o.edge_length : std::sqrt(1.08 * repaired.total_area() / (0.433 * double(target)));
  GradedRemeshOptions g;
  g.inside_edge_length = g.outside_edge_length = h;
  g.feature_angle_degrees = 60.0;  // organs have no sharp edges; a segmentation's staircase is not one
  const TriangleMesh coarse = refine_for_remesh(coarsen_for_remesh(repaired, std::min(alpha, 0.5 * h), r));
  require_shells_meshable(coarse, [h](const Vec3&) { return h; });
  const OperatingRegion anywhere = OperatingRegion::sphere(coarse.vertices().row(coarse.faces()(0, 0)).transpose(), h);
  TriangleMesh m = remesh_with_fewer_creases(coarse, anywhere, g, r);
  if (o.edge_length <= 0.0 && std::abs(double(m.num_elements()) / double(target) - 1.0) > 0.1) {
    h *= std::sqrt(double(m.num_elements()) / double(target));
    g.inside_edge_length = g.outside_edge_length = h;
    m = remesh_with_fewer_creases(coarse, anywhere, g, r);
  }
  r.target_edge_length = h;
  r.steps.push_back("uniform remesh, edge " + general_text(h, 3) + " m: " + std::to_string(m.num_elements()) + " elements");
  return m;
}

/// Step 7's distances: the two-sided Hausdorff distance between the input and the result, less
/// what the repair removed on purpose: input points nearer a dropped body than the kept surface,
/// and walls inside the result (overlapping shells' inner parts: points inside the body and farther
/// than 1 % of the diagonal from its surface). `excluded` counts those sample points.
double hausdorff_distance(const TriangleMesh& input, const TriangleMesh& result, const TriangleMesh& dropped, double diagonal,
                          Index& excluded) {
  RowMatrixX3d from_input = detail::surface_samples(input, false);  // a fine input: corners and centroids
  const Eigen::VectorXd to_kept = detail::cgal_distances(from_input, result.vertices(), result.faces());
  Eigen::VectorXd to_dropped = Eigen::VectorXd::Constant(from_input.rows(), std::numeric_limits<double>::infinity());
  if (dropped.num_elements() > 0) to_dropped = detail::cgal_distances(from_input, dropped.vertices(), dropped.faces());
  // Inside-tests only for the far points (few, unless shells overlapped), by ray casting.
  std::vector<Index> far;
  for (Index i = 0; i < from_input.rows(); ++i)
    if (to_kept(i) > 0.01 * diagonal && to_kept(i) <= to_dropped(i)) far.push_back(i);
  RowMatrixX3d far_points(static_cast<Index>(far.size()), 3);
  for (std::size_t k = 0; k < far.size(); ++k) far_points.row(Index(k)) = from_input.row(far[k]);
  const std::vector<char> inside = detail::cgal_inside(far_points, result);
  std::vector<char> wall(static_cast<std::size_t>(from_input.rows()), 0);
  for (std::size_t k = 0; k < far.size(); ++k) wall[std::size_t(far[k])] = inside[k];
  double there = 0.0;
  excluded = 0;
  for (Index i = 0; i < from_input.rows(); ++i) {
    const bool removed = to_dropped(i) < to_kept(i) || wall[std::size_t(i)];
    if (removed)
      ++excluded;
    else
      there = std::max(there, to_kept(i));
  }
  const double back = detail::cgal_distances(detail::surface_samples(result), input.vertices(), input.faces()).maxCoeff();
  return std::max(there, back);
}

}  // namespace

double length_unit_to_metres(const std::string& unit) {
  if (unit == "m") return 1.0;
  if (unit == "cm") return 1e-2;
  if (unit == "mm") return 1e-3;
  throw InvalidArgumentError("unknown length unit '" + unit + "' (expected mm, cm or m)");
}

bool mesh_preparation_available() { return detail::cgal_repair_available() && graded_remesher_available(); }

PreparedMesh prepare_mesh(const TriangleMesh& input, const MeshPreparationOptions& o) {
  check_options(o);
  if (!mesh_preparation_available())
    throw Error("mesh preparation: this build of bemsurg has neither CGAL nor Gmsh, or lacks one (BEMSURG_WITH_PREPARE; docs/organs.md)");
  const auto start = Clock::now();
  PreparedMesh out;
  MeshPreparationReport& r = out.report;
  r.input_vertices = input.num_vertices();
  r.input_faces = input.num_elements();
  r.scale = o.scale;
  if (input.num_elements() == 0) throw InvalidMeshError("the input has no faces");
  const RowMatrixX3d vertices = input.vertices() * o.scale;
  for (Index v = 0; v < vertices.rows(); ++v)
    if (!vertices.row(v).allFinite()) throw InvalidMeshError("vertex " + std::to_string(v) + " has a coordinate that is not finite");
  const Eigen::Vector3d lo = vertices.colwise().minCoeff(), hi = vertices.colwise().maxCoeff();
  r.input_size = hi - lo;
  const double diagonal = r.input_size.norm();
  if (!(diagonal > 0.0)) throw InvalidMeshError("the input's vertices all lie at one point");
  if (!o.scale_given && r.input_size.maxCoeff() > kLargestBodyMetres)
    r.warnings.push_back("the input is " + general_text(r.input_size.maxCoeff(), 3) +
                         " m across, larger than any organ: it is almost "
                         "certainly in millimetres; pass --units mm (scene: \"prepare\": {\"units\": \"mm\"})");

  double input_volume = 0.0;
  detail::CleanSoup soup;  // the input less its degenerate faces: what distances are measured from
  const TriangleMesh repaired = repair(vertices, input.faces(), diagonal, o, r, input_volume, soup);
  TriangleMesh dropped;
  StageTimer timer(r);
  TriangleMesh body = detail::select_bodies(repaired, o.keep_all, r, dropped);
  body = weld_vertices(body, 0.0);  // drops the vertices of the shells left out
  if (r.bodies_dropped > 0)
    r.steps.push_back("kept the largest of " + std::to_string(r.bodies) + " bodies; dropped " + std::to_string(r.bodies_dropped) + " (" +
                      general_text(r.dropped_volume, 3) + " m^3)");
  r.repaired_elements = body.num_elements();
  // Not rebuilt: the body as the input bounds it (cavities subtracted). Rebuilt: the sum of the
  // input's shells less what was dropped, so an overlap of two shells counts twice (docs/organs.md).
  r.input_volume = r.rebuilt ? input_volume - r.dropped_volume : body.enclosed_volume();

  timer.mark("bodies");
  out.mesh = remesh(body, o, r);
  timer.mark("remesh");
  require_valid_mesh(out.mesh);
  r.elements = out.mesh.num_elements();
  r.vertices = out.mesh.num_vertices();
  r.volume = out.mesh.enclosed_volume();
  r.volume_change = r.input_volume > 0.0 ? (r.volume - r.input_volume) / r.input_volume : 0.0;
  r.hausdorff = hausdorff_distance(TriangleMesh(soup.vertices, soup.faces), out.mesh, dropped, diagonal, r.hausdorff_excluded_samples);
  r.hausdorff_relative = r.hausdorff / diagonal;
  timer.mark("measure");
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return out;
}

std::string describe_preparation(const MeshPreparationReport& r) {
  std::ostringstream s;
  const MeshDefectCounts& d = r.defects;
  s << "input: " << r.input_faces << " faces, " << r.input_vertices << " vertices, " << general_text(r.input_size(0), 3) << " x "
    << general_text(r.input_size(1), 3) << " x " << general_text(r.input_size(2), 3) << " m (scale " << general_text(r.scale, 3) << ")\n";
  s << "defects: " << d.duplicate_vertices << " duplicate vertices, " << d.degenerate_faces << " degenerate faces, " << d.duplicate_faces
    << " repeated faces, " << d.flipped_faces << " flipped faces, " << d.holes << " holes (" << d.boundary_edges << " boundary edges), "
    << d.non_manifold_edges << " non-manifold edges, " << d.non_manifold_vertices << " non-manifold vertices, " << d.self_intersections
    << " crossing face pairs, " << d.shells << " shells\n";
  for (const std::string& step : r.steps) s << "  " << step << "\n";
  s << "result: " << r.elements << " elements, " << r.vertices << " vertices (" << r.bodies - r.bodies_dropped << " bod"
    << (r.bodies - r.bodies_dropped == 1 ? "y" : "ies") << ", " << r.cavities << " cavit" << (r.cavities == 1 ? "y" : "ies") << ")\n";
  s << "change: Hausdorff distance " << general_text(r.hausdorff, 3) << " m (" << general_text(100.0 * r.hausdorff_relative, 3)
    << " % of the diagonal" << (r.hausdorff_excluded_samples > 0 ? ", not counting removed parts" : "") << "), volume "
    << general_text(100.0 * r.volume_change, 3) << " %\n";
  if (r.estimated_bytes > 0.0)
    s << "dense solve of this mesh: about " << format_gib(r.estimated_bytes) << " and " << general_text(r.estimated_seconds, 3)
      << " s on this machine\n";
  if (r.hierarchical_estimated_bytes > 0.0)
    s << "hierarchical solve of this mesh (\"method\": \"hmatrix\"): about " << format_gib(r.hierarchical_estimated_bytes) << "\n";
  for (const std::string& w : r.warnings) s << "warning: " << w << "\n";
  return s.str();
}

}  // namespace bemsurg
