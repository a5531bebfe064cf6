// examples/viewer/model_worker.cpp: background loading, precomputation and rescaling (see
// model_worker.hpp).
//
// Progress of the precomputation: GreensTable::compute is one call, so the bar shows the elapsed
// time against a cost model, t = a E^2 (assembly) + b n^3 (LU of A*) + c n^2 m (back-substitution
// of m = 3|region| columns), with n = 3E. The constants start from figures measured on the
// development machine (docs/viewer.md) and are re-fitted from the three phase timings of every
// precomputation the viewer runs, so the second estimate of a session is the machine's own. The
// bar never claims completion before the table is in (it stops at 99 %).
#include "model_worker.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bemsurg/error.hpp"
#include "bemsurg/io/scene.hpp"
#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/hierarchical_table.hpp"

namespace bemsurg::viewer {

namespace {

double now_seconds() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

/// The built-in default: a soft cuboid (12 x 10 x 5 cm, E = 3 kPa, nu = 0.45, 1000 kg/m^3) whose
/// bottom face is held on a table, sagging under its own weight.
Scene default_cuboid_scene() {
  const char* json = R"({
    "mesh": {"generator": "box", "min": [-0.06, -0.05, 0.0], "max": [0.06, 0.05, 0.05], "divisions": [12, 10, 5]},
    "material": {"young_modulus": 3000.0, "poisson_ratio": 0.45, "density": 1000.0},
    "gravity": [0.0, 0.0, -9.81],
    "boundary_conditions": {"rules": [
      {"select": {"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}}, "displacement": [0, 0, 0]}]},
    "solver": {"method": "lu"}
  })";
  return load_scene_from_string(json, ".", "default cuboid");
}

}  // namespace

struct ModelWorker::Loaded {
  Scene scene;
  std::string name;
  std::shared_ptr<const TriangleMesh> mesh;
  std::vector<char> supported;
  double mean_edge = 0.0;
  bool homogeneous = true;  // every prescribed value is zero: E and gravity rescale exactly
  Index original_elements = 0;
};

const char* phase_name(WorkerPhase p) {
  switch (p) {
    case WorkerPhase::Idle: return "idle";
    case WorkerPhase::Loading: return "loading";
    case WorkerPhase::Precomputing: return "precomputing";
    case WorkerPhase::Rescaling: return "rescaling";
    case WorkerPhase::Ready: return "ready";
    case WorkerPhase::Failed: return "failed";
  }
  return "?";
}

std::string ModelWorker::default_scene_path() {
#ifdef BEMSURG_VIEWER_SCENES_DIR
  const std::string brain = std::string(BEMSURG_VIEWER_SCENES_DIR) + "/brain.json";
  std::error_code ec;
  if (std::filesystem::exists(brain, ec)) return brain;
#endif
  return "";
}

ModelWorker::ModelWorker() : thread_([this] { run(); }) {}

ModelWorker::~ModelWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void ModelWorker::load(const std::string& path) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    pending_ = Request{};
    pending_.load = true;
    pending_.path = path;
    busy_ = true;
  }
  wake_.notify_all();
}

std::shared_ptr<PhysicsState> ModelWorker::provisional_state(const std::shared_ptr<const TriangleMesh>& mesh,
                                                             const std::shared_ptr<const PhysicsState>& previous) const {
  // New surfaces at once: the previous sag on the old elements, zero on the new walls.
  const Index before = loaded_->mesh->num_elements(), after = mesh->num_elements();
  auto s = std::make_shared<PhysicsState>();
  s->model_name = loaded_->name;
  s->mesh = mesh;
  s->supported = loaded_->supported;
  s->supported.resize(static_cast<std::size_t>(after), 0);
  s->mean_edge = loaded_->mean_edge;
  s->original_elements = loaded_->original_elements;
  s->material = previous ? previous->material : loaded_->scene.problem.material;
  s->gravity = previous ? previous->gravity : loaded_->scene.problem.gravity;
  s->cuts = (previous ? previous->cuts : 0) + 1;
  s->provisional_displacement = Eigen::VectorXd::Zero(3 * after);
  if (previous && previous->table) {
    const Index n = std::min<Index>(3 * before, previous->table->num_dofs());
    s->provisional_displacement.head(n) = previous->table->base_displacement().head(n);
  } else if (previous && previous->provisional_displacement.size() > 0) {
    const Index n = std::min<Index>(previous->provisional_displacement.size(), 3 * after);
    s->provisional_displacement.head(n) = previous->provisional_displacement.head(n);
  }
  return s;
}

void ModelWorker::follow_cut(const std::shared_ptr<const TriangleMesh>& mesh, const PhysicsState& s, const GreensTable& table,
                             bool complete) {
  // The scene follows the cut (a later recomputation, e.g. for a new Poisson's ratio, starts from it):
  // the cut surface, the conditions the cut carried over and (`complete`: not a first response's) the
  // table's region.
  auto l = std::make_shared<Loaded>(*loaded_);
  l->scene.problem.mesh = *mesh;
  l->scene.problem.boundary_conditions = table.base_conditions();
  if (complete && !l->scene.operating_elements.empty()) l->scene.operating_elements = table.region();
  l->mesh = mesh;
  l->supported = s.supported;
  loaded_ = l;
  cuts_ = s.cuts;
}

void ModelWorker::set_young_modulus(double e) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!(e > 0.0) || !std::isfinite(e)) return;
    young_ = e;
    if (status_.rescale_exact)
      pending_.rescale = true;
    else
      pending_.recompute = true;
    busy_ = true;
  }
  wake_.notify_all();
}

void ModelWorker::set_poisson_ratio(double nu) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!(nu > -1.0 && nu < 0.5)) return;
    poisson_ = nu;
    pending_.recompute = true;
    busy_ = true;
  }
  wake_.notify_all();
}

void ModelWorker::set_gravity(bool on) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    gravity_on_ = on;
    if (status_.rescale_exact)
      pending_.rescale = true;
    else
      pending_.recompute = true;
    busy_ = true;
  }
  wake_.notify_all();
}

double ModelWorker::young_modulus() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return young_;
}
double ModelWorker::poisson_ratio() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return poisson_;
}
bool ModelWorker::gravity_on() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return gravity_on_;
}
ModelParameters ModelWorker::parameters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return ModelParameters{young_, poisson_, gravity_on_, scene_gravity_, loads_};
}

std::shared_ptr<const PhysicsState> ModelWorker::state() const { return std::atomic_load(&state_); }

WorkerStatus ModelWorker::status() const {
  std::lock_guard<std::mutex> lock(mutex_);
  WorkerStatus s = status_;
  if (s.phase == WorkerPhase::Precomputing || s.phase == WorkerPhase::Loading || s.phase == WorkerPhase::Rescaling) {
    s.elapsed = now_seconds() - phase_start_;
    if (phase_predicted_ > 0.0) {
      s.progress = std::min(0.99, s.elapsed / phase_predicted_);
      s.seconds_left = std::max(0.0, phase_predicted_ - s.elapsed);
    }
  }
  return s;
}

void ModelWorker::wait_idle() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return !busy_; });
}

void ModelWorker::set_status(WorkerPhase p, const std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  status_.phase = p;
  status_.message = message;
  phase_start_ = now_seconds();
  phase_predicted_ = 0.0;
}

void ModelWorker::publish(std::shared_ptr<PhysicsState> s) {
  s->version = ++version_;
  std::atomic_store(&state_, std::shared_ptr<const PhysicsState>(std::move(s)));
}

double ModelWorker::predict_seconds(Index elements, Index region_elements) const {
  const double e = double(elements), n = 3.0 * e, m = 3.0 * double(region_elements);
  return c_assembly_ * e * e + c_factor_ * n * n * n + c_table_ * n * n * m;
}

void ModelWorker::run() {
  for (;;) {
    Request r;
    std::vector<CutRequest> cuts;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || has_work(); });
      if (stop_) return;
      r = pending_;
      pending_ = Request{};
      cuts.swap(cuts_pending_);
      if (r.load) cuts.clear();  // a new model: cuts of the old one are void
    }
    // The thread budget, if one is set, for this job (OpenMP's setting is per thread: this one's).
#ifdef _OPENMP
    static thread_local const int default_threads = omp_get_max_threads();
    const int budget = thread_budget_.load();
    omp_set_num_threads(budget > 0 ? std::min(budget, default_threads) : default_threads);
#endif
    try {
      if (r.load) {
        do_load(r.path);
        do_precompute();
      }
      // Reserving waits for no one only when no step does: a step already queued allocates as it goes.
      if (r.prepare_cuts && cuts.empty() && !r.load) do_prepare_cuts();
      set_cutting(!cuts.empty());  // steps asked for from now on wait for these
      for (const CutRequest& c : cuts) do_cut(c);
      set_cutting(false);
      if (!r.load) {
        if (r.recompute)
          do_precompute();
        else if (r.rescale)
          do_rescale();
      }
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lock(mutex_);
      status_.phase = WorkerPhase::Failed;
      status_.error = e.what();
      status_.message = "failed";
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      cutting_ = false;  // also after a failed step
      if (!has_work()) {
        busy_ = false;
        idle_.notify_all();
      }
    }
  }
}

void ModelWorker::do_load(const std::string& path) {
  set_status(WorkerPhase::Loading, path.empty() ? "building the default cuboid" : "loading " + path);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.error.clear();
  }
  std::atomic_store(&state_, std::shared_ptr<const PhysicsState>());
  loaded_.reset();
  cut_system_.reset();
  reference_.reset();
  cuts_ = 0;
  auto l = std::make_shared<Loaded>();
  try {
    l->scene = require_constant_elements(path.empty() ? default_cuboid_scene() : load_scene(path), "the viewer");
  } catch (const SceneError& e) {
    // Name the file in every message (the window shows it without the command line beside it).
    const std::string what = e.what();
    if (what.rfind(path, 0) == 0) throw;
    throw SceneError(path + ": " + what);
  }
  l->name = path.empty() ? "default cuboid (12 x 10 x 5 cm, bottom held)" : path;
  const ElastostaticProblem& p = l->scene.problem;
  l->mesh = std::make_shared<const TriangleMesh>(p.mesh);
  const Index E = p.mesh.num_elements();
  l->supported.assign(static_cast<std::size_t>(E), 0);
  bool any_support = false;
  for (Index e = 0; e < E; ++e)
    for (int k = 0; k < 3; ++k)
      if (p.boundary_conditions.kind(3 * e + k) == BcKind::Displacement) {
        l->supported[static_cast<std::size_t>(e)] = 1;
        any_support = true;
      }
  if (!any_support)
    throw BoundaryConditionError((path.empty() ? std::string("default model") : path) +
                                 ": no element is held (no displacement prescribed): the body would float away; "
                                 "add a support rule to boundary_conditions");
  l->mean_edge = p.mesh.diameters().mean();
  l->original_elements = p.mesh.num_elements();
  l->homogeneous = p.boundary_conditions.values().cwiseAbs().maxCoeff() == 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    // The panel's controls start from these (ParameterControls::follow): the scene's material,
    // and gravity on exactly when the scene has some (off or on, a zero gravity computes the same).
    young_ = p.material.young_modulus;
    poisson_ = p.material.poisson_ratio;
    scene_gravity_ = !p.gravity.isZero(0.0);
    gravity_on_ = scene_gravity_;
    ++loads_;
    status_.rescale_exact = l->homogeneous;
  }
  loaded_ = l;
  // Publish the undeformed model at once: the window draws it while the table is computed.
  auto s = std::make_shared<PhysicsState>();
  s->model_name = l->name;
  s->mesh = l->mesh;
  s->material = p.material;
  s->gravity = p.gravity;
  s->supported = l->supported;
  s->mean_edge = l->mean_edge;
  s->original_elements = l->original_elements;
  publish(s);
}

void ModelWorker::do_precompute() {
  if (!loaded_) return;
  const ElastostaticProblem& p = loaded_->scene.problem;
  Material m = p.material;
  bool gravity_on;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    m.poisson_ratio = poisson_;
    m.young_modulus = young_;
    gravity_on = gravity_on_;
  }
  m.validate();
  // With zero prescribed values the reference is computed with the scene's gravity and rescaled
  // for E and gravity on/off; otherwise it is computed exactly as asked.
  const Eigen::Vector3d g = (loaded_->homogeneous || gravity_on) ? p.gravity : Eigen::Vector3d::Zero();
  // The scene's operating_region, when it has one, is where tools may act: the table holds only
  // its columns (empty: every free element), as in `bemsurg press` and `session` (docs/graded.md).
  const std::vector<Index>& operating = loaded_->scene.operating_elements;
  Index region = static_cast<Index>(operating.size());
  if (operating.empty())
    for (Index e = 0; e < p.mesh.num_elements(); ++e) region += p.boundary_conditions.is_free(e) ? 1 : 0;
  // The scene's backend: a cut updates whichever factorisation the table keeps, the dense LU or the
  // H-LU (docs/cutting.md, "On either backend"); the status line names the hierarchical one.
  const bool hierarchical = loaded_->scene.solver.backend == SolverBackend::HMatrix;
  set_status(WorkerPhase::Precomputing, "precomputing the compliance table (" + std::to_string(p.mesh.num_elements()) + " elements, " +
                                            std::to_string(3 * p.mesh.num_elements()) + " equations" +
                                            (hierarchical ? "; hierarchical backend)" : ")"));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    phase_predicted_ = predict_seconds(p.mesh.num_elements(), region);
  }
  GreensTableOptions options;
  options.gravity = g;
  options.quadrature = p.quadrature;
  options.region = operating;
  options.explicit_inverse = true;  // the viewer cuts in two phases: first responses read rows of A*^-1 (docs/cutting.md)
  const double t0 = now_seconds();
  // The shared-mesh forms keep the factorisation and the mesh, so cuts can update the table.
  std::shared_ptr<const GreensTable> table;
  if (hierarchical) {
    ElastostaticProblem problem = p;
    problem.material = m;
    problem.gravity = g;
    table = std::make_shared<const GreensTable>(
        compute_greens_table_hierarchical(loaded_->mesh, problem, operating, loaded_->scene.solver, nullptr, true));
  } else {
    table = std::make_shared<const GreensTable>(GreensTable::compute(loaded_->mesh, m, p.boundary_conditions, options));
  }
  const double seconds = now_seconds() - t0;
  // Re-fit the cost model (the dense one's n^2, n^3 and n^2 m terms) from this machine's timings.
  const PrecomputeTimings& t = table->timings();
  const double e = double(p.mesh.num_elements()), n = 3.0 * e, mm = 3.0 * double(table->region().size());
  if (!hierarchical && t.assembly_seconds > 0.0) c_assembly_ = t.assembly_seconds / (e * e);
  if (!hierarchical && t.factorization_seconds > 0.0) c_factor_ = (t.factorization_seconds + t.inversion_seconds) / (n * n * n);
  if (!hierarchical && t.table_seconds > 0.0) c_table_ = t.table_seconds / (n * n * mm);
  cut_system_.reset();  // a new reference: the next cut step starts from it
  reference_ = table;
  reference_young_ = m.young_modulus;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.last_precompute_seconds = seconds;
  }
  do_rescale();
}

void ModelWorker::do_rescale() {
  if (!loaded_ || !reference_) return;
  set_status(WorkerPhase::Rescaling, "rescaling the table for E (no recomputation)");
  const double t0 = now_seconds();
  auto s = state_for(reference_);
  publish(s);
  std::lock_guard<std::mutex> lock(mutex_);
  status_.last_rescale_seconds = now_seconds() - t0;
  status_.phase = WorkerPhase::Ready;
  status_.message = "ready";
  status_.tables_exact = true;
  status_.cuts = cuts_;
}

std::shared_ptr<PhysicsState> ModelWorker::state_for(const std::shared_ptr<const GreensTable>& table) const {
  // The state the tools and the frame read for `table` (the reference, or a cut step's first
  // response, computed for the scene's E and gravity), rescaled to the E and gravity asked for.
  const ElastostaticProblem& p = loaded_->scene.problem;
  double young;
  bool gravity_on;
  double nu;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    young = young_;
    gravity_on = gravity_on_;
    nu = poisson_;
  }
  auto s = std::make_shared<PhysicsState>();
  s->model_name = loaded_->name;
  s->mesh = loaded_->mesh;
  s->supported = loaded_->supported;
  s->mean_edge = loaded_->mean_edge;
  s->original_elements = loaded_->original_elements;
  s->cuts = cuts_;
  s->material = p.material;
  s->material.poisson_ratio = nu;
  if (!loaded_->homogeneous) {
    // Computed exactly for these parameters (do_precompute); nothing to scale.
    s->material.young_modulus = reference_young_;
    s->gravity = table->gravity();
    s->table = table;
  } else {
    // Linear elasticity with zero prescribed values: displacement per unit traction and the sag
    // under fixed gravity both scale as 1/E; the reaction tractions of the self-weight do not
    // (GreensTable::with_young_modulus).
    const double g = gravity_on ? 1.0 : 0.0;
    std::shared_ptr<const GreensTable> scaled = table->with_young_modulus(young, g);
    s->material.young_modulus = young;
    s->gravity = scaled->gravity();
    s->table = scaled;
  }
  return s;
}

}  // namespace bemsurg::viewer
