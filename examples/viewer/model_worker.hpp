// examples/viewer/model_worker.hpp: the viewer's simulation side (docs/design.md §9: seconds-scale
// work off the graphics and haptic threads). One background thread loads a scene (or the default
// model), runs the one-time precomputation of the compliance table (docs/design.md §6) and
// publishes the result as an immutable, versioned snapshot; the graphics thread keeps drawing the
// undeformed model meanwhile and shows the progress and the time left.
//
// Young's modulus and gravity on/off do not need a new precomputation when the scene's prescribed
// values are all zero (a held support, free elsewhere): in linear elasticity every displacement
// scales as 1/E at fixed loads, so the table's columns and the self-weight sag are rescaled by
// E_ref/E (and the sag by 0 or 1 for gravity), which is exact. Poisson's ratio changes the kernels
// themselves and recomputes in the background.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bemsurg/cutting/cut_system_update.hpp"
#include "bemsurg/material.hpp"
#include "bemsurg/mesh/mesh_delta.hpp"
#include "bemsurg/mesh/triangle_mesh.hpp"
#include "bemsurg/presolution/greens_table.hpp"

namespace bemsurg::viewer {

/// What the graphics and haptic threads read: never modified after publication.
struct PhysicsState {
  std::uint64_t version = 0;
  std::string model_name;                             // "default cuboid", the scene path, ...
  std::shared_ptr<const TriangleMesh> mesh;           // undeformed surface
  std::shared_ptr<const GreensTable> table;           // null until the precomputation is done
  Material material;                                  // E, nu, rho as used by `table`
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // as used by `table` (zero when switched off)
  std::vector<char> supported;                        // per element: some displacement component prescribed
  double mean_edge = 0.0;                             // mean element diameter (tool sizes, glyphs)
  /// While `table` is null after a cut: the displacement to draw (the previous self-weight sag,
  /// zero on the new cut walls), so the new surfaces appear at once. Empty otherwise.
  Eigen::VectorXd provisional_displacement;
  int cuts = 0;                 // accepted cut steps in this model
  Index original_elements = 0;  // elements of the model as loaded; later ids are cut walls
};

/// The model's parameters as the worker holds them, read together (ModelWorker::parameters).
struct ModelParameters {
  double young_modulus = 0.0;  // Pa, as last asked (the scene's at load)
  double poisson_ratio = 0.0;  // as last asked (the scene's at load)
  bool gravity_on = true;      // as last asked (at load: whether the scene has gravity)
  bool scene_gravity = false;  // the loaded scene's gravity is nonzero (else the switch does nothing)
  std::uint64_t loads = 0;     // scenes loaded so far: a new count is a new model
};

enum class WorkerPhase { Idle, Loading, Precomputing, Rescaling, Ready, Failed };

struct WorkerStatus {
  WorkerPhase phase = WorkerPhase::Idle;
  double progress = 0.0;      // 0..1, an estimate from the cost model (see model_worker.cpp)
  double seconds_left = 0.0;  // estimate
  double elapsed = 0.0;       // seconds in the current phase
  std::string message;        // what is being done
  std::string error;          // last load/precompute error (shown in the window), "" if none
  bool rescale_exact = true;  // E and gravity rescale without recomputing (zero prescribed values)
  double last_precompute_seconds = 0.0;
  double last_rescale_seconds = 0.0;
  double last_cut_update_seconds = 0.0;   // the system and table update of the last cut step (CutSystemUpdate), to the complete table
  double last_cut_first_seconds = 0.0;    // the same, to the first response (0: the last step took one phase)
  double last_cut_surface_seconds = 0.0;  // the surface step of the last cut step (SurfaceCutter)
  bool tables_exact = false;              // the table in use was computed for the current mesh
  bool first_response = false;            // the table in use is a cut step's first response: the complete one is on its way
  int cut_first_responses = 0;            // cut steps published in two phases so far
  int cuts = 0;                           // accepted cut steps whose mesh is in use
  int cut_steps_accepted = 0;             // every cut step so far (all models)
  int cut_steps_refused = 0;
  int cut_steps_waited = 0;  // steps asked for while an earlier step was still computing (they wait for it)
  // The cut steps' table storage (CutSystemUpdate::snapshot_buffer_counts): buffers a step had to allocate
  // (prepare_cuts' reserved ones are not counted), buffers reused, buffers held now.
  std::size_t cut_buffers_allocated = 0, cut_buffers_reused = 0, cut_buffers_held = 0;
  std::string last_cut_refusal;  // the last refused step's reason, "" if none
};

class ModelWorker {
 public:
  ModelWorker();
  ~ModelWorker();
  ModelWorker(const ModelWorker&) = delete;
  ModelWorker& operator=(const ModelWorker&) = delete;

  /// Loads a scene file ("" = the default model) and precomputes, in the background.
  void load(const std::string& scene_path);
  /// Parameter changes (background; the newest request wins).
  void set_young_modulus(double e);
  void set_poisson_ratio(double nu);
  void set_gravity(bool on);

  std::shared_ptr<const PhysicsState> state() const;
  WorkerStatus status() const;
  /// Blocks until every request so far is done (headless mode).
  void wait_idle();
  /// One step of a cut (`new_cut`: the first step of a new groove, `gap_width` its width, 0: the
  /// cutter's default), through the one cut entry point, CutSystemUpdate (docs/design.md §7): the same
  /// locking, conditions and region rules as `bemsurg cut` and sessions. In the background: the new
  /// surface is published at once (without a table), then the exact tables follow (the delta update of
  /// the kept factorisation). A refused step changes nothing; status() counts it and gives its reason.
  void request_cut_step(bool new_cut, const Eigen::Vector3d& from, const Eigen::Vector3d& direction, double gap_width);
  /// A cut may come soon (the scalpel was picked, or a drag began): in the background, make the cut
  /// entry point for the current tables and touch the storage of its first steps' tables
  /// (CutSystemUpdate::reserve_snapshot_buffers; docs/cutting.md, "Snapshot storage"), so that the
  /// first step costs what later ones do. Skipped when a cut step is already queued (it would wait for
  /// the reservation) or the storage is ready for these tables.
  void prepare_cuts();
  /// Where the tools are, for the next cut steps (the viewer sets it every frame): with a positive
  /// `reach`, a step is published in two phases (docs/cutting.md, "First response"): first the table of
  /// the region elements within `reach` of the `points` (the tools' tips and the elements they touch),
  /// then the complete table. A step requested meanwhile waits for the completion. 0: one phase.
  void set_cut_reach(std::vector<Eigen::Vector3d> points, double reach);

  /// Threads the worker's OpenMP regions use from its next job on (0: the default). The
  /// interactive viewer sets cores - 1 while its haptic thread runs (haptics/background_threads.hpp),
  /// so that the 1 kHz tick keeps a core while a cut's tables or a new table compute.
  void set_thread_budget(int threads) { thread_budget_.store(threads); }

  double young_modulus() const;
  double poisson_ratio() const;
  bool gravity_on() const;
  /// The three above, the scene's gravity and the count of completed loads, under one lock.
  ModelParameters parameters() const;

  /// The default model when no scene is given: a brain-like scene when examples/scenes/brain.json
  /// exists beside the sources, otherwise a soft cuboid held on its bottom face (the paper's simple
  /// object). Returns the scene path ("" = built-in cuboid).
  static std::string default_scene_path();

 private:
  struct Request {
    bool load = false;
    std::string path;
    bool recompute = false;
    bool rescale = false;
    bool prepare_cuts = false;
  };
  struct CutRequest {
    bool new_cut = false;
    Eigen::Vector3d from = Eigen::Vector3d::Zero(), direction = Eigen::Vector3d::UnitX();
    double gap_width = 0.0;
  };
  void run();
  void do_load(const std::string& path);
  void do_precompute();
  void do_rescale();
  std::shared_ptr<PhysicsState> state_for(const std::shared_ptr<const GreensTable>& table) const;
  void do_cut(const CutRequest& cut);
  void do_prepare_cuts();
  /// cut_system_ for reference_: kept while it cuts that table, else made anew (not yet prepared).
  void use_cut_system_of_reference();
  void count_cut_buffers();
  void set_cutting(bool on);
  std::shared_ptr<PhysicsState> provisional_state(const std::shared_ptr<const TriangleMesh>& mesh,
                                                  const std::shared_ptr<const PhysicsState>& previous) const;
  void follow_cut(const std::shared_ptr<const TriangleMesh>& mesh, const PhysicsState& s, const GreensTable& table, bool complete);
  bool has_work() const {
    return pending_.load || pending_.recompute || pending_.rescale || pending_.prepare_cuts || !cuts_pending_.empty();
  }
  void publish(std::shared_ptr<PhysicsState> s);
  void set_status(WorkerPhase p, const std::string& message);
  double predict_seconds(Index elements, Index region_elements) const;

  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  Request pending_;
  std::vector<CutRequest> cuts_pending_;       // in order
  bool cutting_ = false;                       // a cut step is being computed (under mutex_)
  std::vector<Eigen::Vector3d> reach_points_;  // set_cut_reach
  double reach_ = 0.0;
  bool busy_ = false;
  bool stop_ = false;
  WorkerStatus status_;
  double phase_start_ = 0.0;
  double phase_predicted_ = 0.0;

  std::shared_ptr<const PhysicsState> state_;  // accessed with std::atomic_load/store
  std::uint64_t version_ = 0;

  // Worker-thread data: the loaded problem and the reference table (scene gravity, E_ref).
  struct Loaded;
  std::shared_ptr<Loaded> loaded_;
  std::shared_ptr<const GreensTable> reference_;
  std::unique_ptr<CutSystemUpdate> cut_system_;  // cuts of reference_ (made by prepare_cuts or the first cut step)
  bool cuts_prepared_ = false;                   // cut_system_ has reserved its first steps' storage
  void refuse_cut(const std::string& reason);
  double reference_young_ = 0.0;
  double young_ = 0.0, poisson_ = 0.0;
  bool gravity_on_ = true, scene_gravity_ = false;
  std::uint64_t loads_ = 0;
  int cuts_ = 0;
  // Cost model (seconds per E^2, per n^3, per n^2 m), refined by every precomputation done here.
  double c_assembly_ = 2.0e-7, c_factor_ = 1.0e-10, c_table_ = 1.0e-10;

  std::atomic<int> thread_budget_{0};
  std::thread thread_;
};

const char* phase_name(WorkerPhase p);

/// The parameters panel's controls (docs/viewer.md): E in kPa, nu and gravity on/off. They start
/// from the loaded scene's material and gravity, again after every load; between loads they hold
/// what the user set (and sent to the worker).
struct ParameterControls {
  float young_kpa = 0.0f, poisson = 0.0f;
  bool gravity = true;
  bool scene_gravity = false;
  std::uint64_t loads_seen = 0;

  /// Takes the worker's parameters when a scene was loaded since the last call: true then.
  bool follow(const ModelWorker& worker) {
    const ModelParameters p = worker.parameters();
    if (p.loads == loads_seen) return false;
    loads_seen = p.loads;
    young_kpa = static_cast<float>(1e-3 * p.young_modulus);
    poisson = static_cast<float>(p.poisson_ratio);
    gravity = p.gravity_on;
    scene_gravity = p.scene_gravity;
    return true;
  }
  /// Slider ranges that hold the scene's value: 0.3 to 100 kPa, 0 to 0.49, widened to include it.
  float young_min() const { return std::min(0.3f, young_kpa); }
  float young_max() const { return std::max(100.0f, young_kpa); }
  float poisson_min() const { return std::min(0.0f, poisson); }
  float poisson_max() const { return std::max(0.49f, poisson); }
};

}  // namespace bemsurg::viewer
