// bemsurg/cutting/surface_cutter.hpp: the topology of a cut (Wang et al. 2007 §5.3;
// docs/design.md §7; docs/cutting.md "Topology").
//
// A cut is a narrow groove, not a crack: it starts at the surface vertex nearest the tool, runs
// along the mesh edge best aligned with the tool's travel direction (largest dot product of the
// unit edge vector with the direction projected onto the surface, as the paper does), and opens
// a gap of width w perpendicular to the surface down to a depth of about one local edge length:
// two side walls and a bottom. Later steps extend it by one edge along the travel direction;
// deepen() lowers its bottom by one more level. Every path vertex inside the cut is split into
// a left rim vertex (the path vertex, unmoved) and a right rim vertex w to its right, with wall
// vertices below them; faces left of the path therefore keep their geometry (fewer reshaped
// elements per step). The cut's two ends stay single vertices, where the walls and bottom close
// in a fan.
//
// Every accepted step leaves a surface that is closed, 2-manifold, outward-oriented and free of
// self-intersection, and whose changed or new triangles have no angle below min_angle_degrees:
// the cutter checks this itself (mesh/mesh_validation.hpp, mesh/self_intersection.hpp) before it
// publishes the new mesh. A step that would fail any check, or touch a locked (supported)
// element, is refused with the reason and changes nothing: same snapshot pointer, same version.
//
// Element ids follow the contract of mesh/mesh_delta.hpp: unchanged elements keep their id
// and their three vertex positions bit for bit; a changed element keeps its id (`modified`); new
// ones are appended (`added`); nothing is ever removed.
//
// One cutter is one cut (open, extend, deepen). For a second cut, construct a new cutter on
// mesh() (with locked_elements() as its locks); its path refuses to run over the first cut's walls.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/Core>

#include "bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"

namespace bemsurg {

/// Geometry and acceptance limits of a cut: the gap width, the depth of one level, the smallest angle allowed in the
/// triangles a step changes or adds, and the largest normal deviation at a path vertex.
/// \ingroup cutting
struct CutOptions {
  /// Gap width as a fraction of the local edge length (used when gap_width == 0).
  double gap_fraction = 0.1;
  /// Absolute gap width; 0 means gap_fraction x the local edge length. The local edge length at
  /// a path vertex is the mean length of the (original) mesh edges the path runs along there.
  double gap_width = 0.0;
  /// Depth of one level of the groove as a fraction of the local edge length; opening makes one
  /// level, each deepen() adds one.
  double depth_fraction = 1.0;
  /// Smallest interior angle allowed in any triangle a step changes or adds. The groove's bottom
  /// is a strip w wide between cross-sections about one edge length h apart, so its triangles
  /// have angles near atan(w/h) (5.7 degrees at the default width), and the fans that close the
  /// ends narrow with depth (about 4 degrees at one level, 2.6 at two); 2 degrees admits those
  /// and refuses needles.
  double min_angle_degrees = 2.0;
  /// A path vertex whose surrounding faces turn more than this from their mean normal sits on a
  /// sharp feature: another cut's rim (wall and surface meet at 90 degrees), a box edge (45
  /// degrees from the mean each side) or a thin edge. "Perpendicular to the surface" has no
  /// meaning there, so the step is refused. Smooth parts of a 1,280-face sphere turn by a few
  /// degrees.
  double max_normal_deviation_degrees = 40.0;
  /// For studies only (bench_stability's and bench_cut's gap studies, docs/stability.md (d)):
  /// accept gaps narrower than kMinimumGapRatio x the local edge length (cutting/gap_limit.hpp),
  /// whose BEM solution is no longer trusted. Off: such a step is refused, naming the width, the
  /// edge length and the limit.
  bool allow_narrow_gap_for_studies = false;
};

/// The outcome of one SurfaceCutter step or deepen(): accepted or refused with the reason, the MeshDelta of the change,
/// and the parent of each added element.
/// \ingroup cutting
struct CutStep {
  bool accepted = false;
  /// Why a step was refused (empty when accepted).
  std::string reason;
  MeshDelta delta;
  /// One entry per element of delta.added, in the same order: -1 for new cut surface (walls and
  /// bottom: traction-free unless the scene says otherwise), or the id of the existing element it
  /// was split from (the second half of a triangle split on opening), whose boundary condition
  /// it inherits.
  std::vector<Index> added_parent;
};

/// The topology of one cut (docs/cutting.md, "Topology"): opens a narrow groove at the surface, extends it by one
/// edge per step and deepens it, publishing each step only after its checks pass and refusing it whole otherwise.
/// \ingroup cutting
class SurfaceCutter {
 public:
  /// `mesh` must be a valid closed surface (require_valid_mesh); `locked_elements` has one entry
  /// per element (or is empty: nothing locked); a non-zero entry marks an element that is
  /// supported (prescribed displacement) and that no cut may change. Throws InvalidArgumentError
  /// on a null mesh, a lock vector of the wrong size, or options out of range.
  SurfaceCutter(std::shared_ptr<const TriangleMesh> mesh, std::vector<char> locked_elements, CutOptions options = {});

  /// The first accepted call opens the cut at the vertex nearest `from` along the edge best
  /// aligned with `direction`; later calls extend it by one edge from its far end, along the edge
  /// best aligned with `direction` (`from` is then not used).
  CutStep step(const Eigen::Vector3d& from, const Eigen::Vector3d& direction);
  /// Lowers the bottom of the whole cut by one level (depth_fraction x local edge length).
  CutStep deepen();

  /// Current snapshot: a new object after every accepted step, the same one after a refusal.
  std::shared_ptr<const TriangleMesh> mesh() const { return mesh_; }
  /// Incremented by every accepted step.
  std::uint64_t version() const { return version_; }
  /// Locks of the current mesh's elements (new elements are not locked).
  const std::vector<char>& locked_elements() const { return locked_; }
  const CutOptions& options() const { return options_; }
  /// Whether a cut has been opened.
  bool opened() const { return !path_.empty(); }
  /// Number of depth levels of the groove (0 before opening).
  int depth_levels() const { return levels_; }
  /// Vertices of the cut path, start to end, in the current mesh: the two ends are single
  /// vertices; each inner path vertex is represented by its left rim vertex.
  std::vector<Index> path_vertices() const;

  /// Geometry of an inner cross-section of the cut (for tests and the viewer): rim vertices
  /// `left`/`right` (left[0], right[0] on the surface, deeper levels below).
  struct Section {
    bool split = false;
    Index vertex = -1;  // an end (unsplit): the vertex itself
    Vec3 center = Vec3::Zero();
    Vec3 normal = Vec3::Zero();    // outward unit normal used for the depth direction
    Vec3 left_dir = Vec3::Zero();  // unit, tangent to the surface, to the left of travel
    double width = 0.0, level_depth = 0.0, edge_length = 0.0;
    std::vector<Index> left, right;  // vertex ids per level 0..levels
  };
  const std::vector<Section>& sections() const { return path_; }

 private:
  struct Work;  // a candidate state, built fully before anything is committed
  Work start_work() const;
  CutStep refuse(std::string reason) const;
  CutStep commit(Work& w);
  // The path (cutting/impl/surface_cutter_impl.hpp).
  bool open(Work& w, const Vec3& from, const Vec3& direction, std::string& reason) const;
  bool extend(Work& w, const Vec3& direction, std::string& reason) const;
  bool touches_lock(const Work& w, Index v, std::string& reason) const;
  bool split_section(Work& w, std::size_t i, std::string& reason) const;
  bool divide_sides(const Work& w, std::size_t i, std::vector<Index>& left, std::vector<Index>& right, std::string& reason) const;
  // The groove's walls and bottom (cutting/impl/cut_groove_impl.hpp).
  void rebuild_groove(Work& w) const;
  // The checks before a step is published (cutting/impl/cut_checks_impl.hpp), in this order.
  bool check(Work& w, std::string& reason) const;
  bool check_locks(const Work& w, std::string& reason) const;
  bool check_angles(const TriangleMesh& mesh, const std::vector<Index>& changed, std::string& reason) const;
  static bool check_self_intersection(const TriangleMesh& mesh, const std::vector<Index>& changed, std::string& reason);
  static bool check_clearance(const Work& w, const TriangleMesh& mesh, std::string& reason);
  static bool check_manifold(const Work& w, const TriangleMesh& mesh, const std::vector<Index>& changed, std::string& reason);
  bool check_gap(const Work& w, std::string& reason) const;

  std::shared_ptr<const TriangleMesh> mesh_;
  std::uint64_t version_ = 0;
  std::vector<char> locked_;
  CutOptions options_;
  // The cut: path sections start to end, segment edge lengths, groove depth, and the id of
  // every groove triangle by (segment, kind, level, half) so that ids stay stable.
  std::vector<Section> path_;
  std::vector<double> segment_length_;
  int levels_ = 0;
  std::map<std::tuple<int, int, int, int>, Index> groove_faces_;
  std::vector<char> cut_vertex_;  // vertices the cut created or split (never a path candidate)
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/cutting/impl/cut_checks_impl.hpp"
#include "bemsurg/cutting/impl/cut_groove_impl.hpp"
#include "bemsurg/cutting/impl/surface_cutter_impl.hpp"
#endif
