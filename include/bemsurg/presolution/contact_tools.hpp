// bemsurg/presolution/contact_tools.hpp: surgical tools as contact constraints on the compliance
// table (docs/design.md §6; Wang et al. 2007 §5.1-5.2: prodding, pinching, retraction), solved exactly
// and together by capacitance_contact.hpp, several tools at once (two hands).
//
// Every tool is engaged at first contact with the base-state (self-weight) surface and then moved
// by a translation (the plate also by a small rotation) from that pose:
//   point   the paper's tool: the element hit first takes the tool's displacement (bonded, or its
//           normal component when frictionless). Its force depends on the element size and does
//           NOT converge under refinement (a point load on an elastic body has infinite
//           compliance); use a finite tool for forces.
//   flat    rigid flat disc of radius a, axis along the approach direction: every element under
//           the disc whose face the disc has reached moves with it (Boussinesq's punch).
//   sphere  rigid sphere of radius R: the elements it overlaps are pushed onto its surface along
//           their normals; elements whose contact traction would pull (adhesion) are released and
//           the small system solved again until the set is consistent (unilateral contact by an
//           active set, Hertz's problem).
//   plate   rigid planar polygon retractor: the elements it touches move with it.
//   pinch   grabs the element hit (and those within a jaw radius) at first contact; the contact
//           sticks and carries tension, so pulling reverses the force.
// Unilateral tools (point pushing, flat, sphere) release tensile elements; plate and pinch stick.
//
// Conventions: a unilateral row's direction w points into the body (the pushing direction) and
// its traction multiplier lambda > 0 is compression. Forces are on the tool: -sum area * traction.
//
// Threads (docs/design.md §9): engagement (engage, place, release, add_tool) allocates and throws
// and is done off the haptic thread; the per-tick path — try_set_translation / try_set_rotation
// and step() — never allocates, throws or locks and returns a ContactStatus. The mesh and table
// are shared immutable snapshots; a cut builds a new solver on the new snapshots, engages the
// tools there and hands it to the haptic thread whole (haptics/haptic_loop.hpp).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "bemsurg/mesh/bvh.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/presolution/capacitance_contact.hpp"
#include "bemsurg/presolution/greens_table.hpp"

namespace bemsurg {

/// The shape of a contact tool (ToolSpec; what each one does: the top of this header).
/// \ingroup presolution
enum class ToolShape { Point, FlatPunch, Sphere, Plate, Pinch };
/// How a tool holds the elements it touches: bonded (all three components) or frictionless (the normal one only).
/// \ingroup presolution
enum class ContactMode { Bonded, Frictionless };

/// Shape and contact mode of a surgical tool (point, flat punch, sphere, plate, pinch) and its sizes, with a factory per
/// shape; see the top of this header for what each shape does.
/// \ingroup presolution
struct ToolSpec {
  ToolShape shape = ToolShape::Point;
  ContactMode mode = ContactMode::Bonded;
  /// flat: disc radius a; sphere: R; pinch: jaw radius (0 = the element hit only).
  double radius = 0.0;
  /// plate: polygon vertices in world coordinates at engagement (planar, >= 3, convex or not).
  std::vector<Eigen::Vector3d> polygon;
  /// plate: elements whose centroid lies within this distance of the plate's plane are touched.
  double plate_tolerance = 0.0;
  /// sphere, flat: extra radius around the axis within which elements are candidates, so the
  /// tool can slide this far sideways from where it was engaged or placed before it must be
  /// placed again (0: only the elements under the tool where it was engaged).
  double slide_margin = 0.0;

  static ToolSpec point(ContactMode m = ContactMode::Bonded) { return {ToolShape::Point, m, 0.0, {}, 0.0, 0.0}; }
  static ToolSpec flat(double a, ContactMode m = ContactMode::Frictionless) { return {ToolShape::FlatPunch, m, a, {}, 0.0, 0.0}; }
  static ToolSpec sphere(double r, ContactMode m = ContactMode::Frictionless) { return {ToolShape::Sphere, m, r, {}, 0.0, 0.0}; }
  static ToolSpec pinch(double jaw = 0.0) { return {ToolShape::Pinch, ContactMode::Bonded, jaw, {}, 0.0, 0.0}; }
  static ToolSpec plate(std::vector<Eigen::Vector3d> poly, double tolerance, ContactMode m = ContactMode::Bonded) {
    return {ToolShape::Plate, m, 0.0, std::move(poly), tolerance, 0.0};
  }
};

/// What the haptic-thread step returns instead of throwing.
/// \ingroup presolution
enum class ContactStatus : std::uint8_t {
  Ok = 0,
  Unsettled,         // the active set did not settle within the iteration limit (force usable)
  CapacityExceeded,  // the contact set needs more rows than reserved: set unchanged, force stale
  Singular,          // the new rows made the small system singular: set unchanged, force stale
  NonFinitePose,     // a NaN/inf pose was refused: the tool keeps its last pose
};
const char* to_string(ContactStatus status) noexcept;

/// What one update() did.
/// \ingroup presolution
struct ContactUpdateResult {
  int active_set_iterations = 0;
  bool consistent = true;  // false: the active set did not settle within the iteration limit
  Index rows = 0;
  Index elements = 0;
};
/// Deprecated name (before 0.2), kept one minor version: use ContactUpdateResult.
using ContactUpdateReport [[deprecated("renamed to ContactUpdateResult in bemsurg 0.2")]] = ContactUpdateResult;

/// Surgical tools as contact constraints on the compliance table, several at once, solved exactly and together by
/// CapacitanceContact. Engagement runs off the haptic thread; try_set_translation, try_set_rotation and step() are the haptic path.
/// \ingroup presolution
class ToolContactSolver {
 public:
  /// `capacity_rows`: the most constraint rows of all tools together (bonded elements take 3).
  /// The mesh and table are shared snapshots (throws ContactError when null or mismatched).
  ToolContactSolver(std::shared_ptr<const TriangleMesh> mesh, std::shared_ptr<const GreensTable> table, Index capacity_rows = 600);

  /// Adds a tool (not yet touching); returns its id (the tag of its rows).
  int add_tool(const ToolSpec& spec);
  Index num_tools() const { return static_cast<Index>(tools_.size()); }

  /// The tool approaches along `direction` on the line through `at` and stops at first contact
  /// with the base-state surface; returns false when the line misses the body (or, for a
  /// flat/sphere, no element faces the tool). A flat punch narrower than the elements presses the
  /// element its axis lands on; a sphere must cover at least one element centroid (within R of
  /// its axis), else false: a sphere narrower than the elements cannot be resolved by the mesh.
  /// After this the tool's translation is zero.
  bool engage(int tool, const Eigen::Vector3d& at, const Eigen::Vector3d& direction);
  /// Places the tool directly (sphere: centre; flat: a point of the disc face, disc normal along
  /// `direction`) without searching for first contact; its translation is then measured from here.
  void place(int tool, const Eigen::Vector3d& position, const Eigen::Vector3d& direction);
  void release(int tool);
  bool engaged(int tool) const { return tools_[static_cast<std::size_t>(tool)].engaged; }
  /// Where the tool's translation is zero: the first-contact point (point, pinch), the sphere's
  /// centre or the disc face's centre where it was engaged or placed, the plate's centroid.
  const Eigen::Vector3d& origin(int tool) const { return tools_[static_cast<std::size_t>(tool)].origin; }
  /// The approach direction (unit) of the last engagement or placement.
  const Eigen::Vector3d& direction(int tool) const { return tools_[static_cast<std::size_t>(tool)].direction; }
  const Eigen::Vector3d& translation(int tool) const { return tools_[static_cast<std::size_t>(tool)].delta; }
  const ToolSpec& spec(int tool) const { return tools_[static_cast<std::size_t>(tool)].spec; }

  /// Tool pose relative to where it was engaged or placed (the plate also turns by `rotation`,
  /// a small rotation vector about the polygon's centroid).
  /// Both throw ContactError for a non-finite argument (the tool keeps its pose).
  void set_translation(int tool, const Eigen::Vector3d& delta);
  void set_rotation(int tool, const Eigen::Vector3d& rotation);
  /// Convenience: translation `depth` along the approach direction (throws when not finite).
  void set_depth(int tool, double depth);
  /// Haptic-thread forms: false (pose unchanged) for a non-finite argument or a tool id out of
  /// range; never throw or allocate.
  bool try_set_translation(int tool, const Eigen::Vector3d& delta) noexcept;
  bool try_set_rotation(int tool, const Eigen::Vector3d& rotation) noexcept;

  /// The haptic-rate step: brings the contact set up to date with the poses (incremental
  /// capacitance updates), solves, and runs the active set of unilateral tools. Allocation-free
  /// once the tools are engaged (buffers are reserved for the capacity).
  /// Throws bemsurg::Error when the contact set would exceed the capacity (or SolverError for a
  /// singular small system); the contact set and the solver's bookkeeping are then left as they
  /// were before the failed additions, so a later update() at a reachable pose is correct.
  ContactUpdateResult update(int max_active_set_iterations = 50);
  /// The same step for the haptic thread: never allocates, throws, locks or builds a message.
  /// CapacityExceeded / Singular leave the contact set as it was before the failed additions (the
  /// force of the last good step stays in force()); Unsettled means the iteration limit was hit.
  ContactStatus step(ContactUpdateResult& report, int max_active_set_iterations = 50) noexcept;

  /// Force on one tool (after update()).
  Eigen::Vector3d force(int tool) const { return contact_.force_of_tag(tool); }
  /// Rows the last failed step needed in all (CapacityExceeded), for the caller's message.
  Index rows_needed() const { return rows_needed_; }
  Index contact_elements(int tool) const;
  /// Elements in contact with `tool`, appended to out.
  void contact_element_list(int tool, std::vector<Index>& out) const;

  const CapacitanceContact& contact() const { return contact_; }
  CapacitanceContact& contact() { return contact_; }
  /// Full field (graphics rate, O(n k)); u must have n entries.
  void displacement_field(Eigen::VectorXd& u) const { contact_.displacement_field(u); }
  /// The base-state surface the tools are engaged on.
  const TriangleBvh& base_surface() const { return bvh_; }

 private:
  struct Tool {
    ToolSpec spec;
    bool engaged = false;
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();      // reference point (contact point / centre / disc face)
    Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // approach direction, unit
    Eigen::Vector3d delta = Eigen::Vector3d::Zero();
    Eigen::Vector3d rotation = Eigen::Vector3d::Zero();
    Eigen::Vector3d pivot = Eigen::Vector3d::Zero();
    // Radius within which element centroids count as under a flat punch: the punch's radius, or,
    // when the punch is narrower than the elements and covers no centroid, just enough to hold
    // the element its axis lands on (so a fine tool on a coarse mesh still presses something).
    double reach = 0.0;
    std::vector<Index> candidates;  // elements the tool can reach (fixed at engagement)
    std::vector<char> released;     // per candidate: released by the active set
    std::vector<char> wanted;       // per candidate: scratch
  };
  bool unilateral(const Tool& t) const {
    return t.spec.shape == ToolShape::FlatPunch || t.spec.shape == ToolShape::Sphere || t.spec.shape == ToolShape::Point;
  }
  Eigen::Vector3d base_position(Index e) const { return mesh_->centroid(e) + table_->base_displacement().segment<3>(3 * e); }
  /// Whether candidate element e of tool t is geometrically in contact at the current pose, and
  /// the displacement target: the displacement change from the base state it must undergo.
  /// `held`: e is in contact with t now (a sphere keeps a face it took as its centre passes the
  /// face's plane; it takes one only while the face looks at it).
  bool geometric_contact(const Tool& t, Index e, Eigen::Vector3d& push, Eigen::Vector3d& row_direction, bool held) const;
  void collect_candidates(Tool& t);
  void add_element_rows(const Tool& t, int tag, Index e, const Eigen::Vector3d& row_direction);
  void set_targets();
  void rollback_additions();  // after a failed addition: unclaim the elements in add_buffer_
  // The steps of one active-set iteration of step(), in order. Inline (defined with step(), used
  // only there) so that the haptic path costs what it cost as one function.
  inline void remove_unwanted_rows();
  inline bool gather_additions();  // false: capacity exceeded (rows_needed_ set, additions rolled back)
  inline bool release_tension();
  inline bool readmit_penetrating();

  std::shared_ptr<const TriangleMesh> mesh_;
  std::shared_ptr<const GreensTable> table_;
  CapacitanceContact contact_;
  Index rows_needed_ = 0;
  TriangleBvh bvh_;
  std::vector<Tool> tools_;
  std::vector<int> owner_;              // per element: tool id in contact, or -1
  std::vector<ContactRow> add_buffer_;  // reserved to the capacity: rows joining in one update
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/presolution/impl/contact_tools_impl.hpp"
#endif
