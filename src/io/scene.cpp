// Scene files (bemsurg/io/scene.hpp, docs/scene-format.md): JSON and CSV in, a checked
// ElastostaticProblem out. This file puts the sections together in the order the physics needs
// (scene_sections.hpp) and resolves the files a scene names; each section is read by a file of
// its own. Every check throws SceneError whose message starts with the key path
// ("boundary_conditions.rules[1].select.plane.normal") or the file and line.
#include "bemsurg/io/scene.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bemsurg/elastostatics/hierarchical_solver.hpp"
#include "bemsurg/error.hpp"
#include "bemsurg/memory_budget.hpp"
#include "bemsurg/mesh/mesh_quality.hpp"
#include "bemsurg/mesh/mesh_thickness.hpp"
#include "bemsurg/meshing/mesh_preparation.hpp"
#include "bemsurg/number_text.hpp"
#include "json_reader.hpp"
#include "scene_sections.hpp"

namespace bemsurg {
namespace io {

std::string resolve_existing(const std::string& directory, const JsonReader& file) {
  namespace fs = std::filesystem;
  const std::string name = file.string();
  if (name.empty()) file.fail("expected a file name, got an empty string");
  const fs::path p(name);
  const std::string path = (p.is_absolute() || directory.empty() ? p : fs::path(directory) / p).lexically_normal().string();
  std::error_code ec;
  if (!fs::exists(path, ec)) file.fail("cannot read '" + path + "': no such file");
  if (fs::is_directory(path, ec)) file.fail("cannot read '" + path + "': it is a directory");
  return path;
}

}  // namespace io

namespace {

/// The selected elements that are free: where a Green's table is computed (docs/graded.md).
void collect_operating_elements(Scene& scene) {
  const ElastostaticProblem& problem = scene.problem;
  // A remeshed element set is matched by distance: the new elements covering the old ones have
  // their centroids on (within a tenth of an element of) the old triangles.
  // Otherwise a slack of rounding only (a centroid's distance to its own triangle is ~1e-18, not 0).
  const double slack = scene.graded && scene.operating_region.kind() == OperatingRegion::Kind::Elements
                           ? 0.1 * scene.mesh_quality.min_size
                           : 1e-9 * (problem.mesh.bounding_box().col(1) - problem.mesh.bounding_box().col(0)).norm();
  std::size_t held = 0;
  for (Index e : scene.operating_region.elements_of(problem.mesh, slack)) {
    if (problem.boundary_conditions.is_free(e))
      scene.operating_elements.push_back(e);
    else
      ++held;
  }
  if (scene.operating_elements.empty())
    io::fail_at("operating_region", "holds no free element of the mesh (" + std::to_string(held) +
                                        " elements inside are displacement-prescribed, and a Green's table needs free ones)");
}

/// The safe-grading rule (docs/graded.md, "Safe gradings"): a graded or locally refined mesh whose
/// held elements are much coarser than its finest ones is warned about.
void warn_unsafe_grading(Scene& scene) {
  if (!scene.graded && scene.mesh_source.find("red-green") == std::string::npos) return;
  const ElastostaticProblem& p = scene.problem;
  std::vector<char> held(static_cast<std::size_t>(p.mesh.num_elements()));
  for (Index e = 0; e < p.mesh.num_elements(); ++e) held[static_cast<std::size_t>(e)] = !p.boundary_conditions.is_free(e);
  const std::string w = grading_rule_warning(p.mesh, held, scene.element_grading_size);
  if (!w.empty()) scene.warnings.push_back("mesh: " + w);
}

/// A displacement rule whose region the solved surface holds less than 90 % of (docs/scene-format.md,
/// "boundary_rules"): elements whose centroid lies outside the region are free, so the support is
/// smaller than the scene says; "conform" splits them along a sphere's or box's boundary.
void warn_partial_supports(Scene& scene) {
  for (const BoundaryRuleArea& r : scene.boundary_rules) {
    if (!r.displacement || !r.has_region || !(r.region_area > 0.0) || r.area >= 0.9 * r.region_area) continue;
    scene.warnings.push_back(r.key + ": holds " + general_text(r.area, 4) + " m^2 of the " + general_text(r.region_area, 4) +
                             " m^2 of surface inside its region (" + general_text(100.0 * r.area / r.region_area, 3) + " %): " +
                             (r.conform       ? std::string("later rules or the boundary-condition file override part of it")
                              : r.can_conform ? "elements whose centroid lies outside it are not held; add \"conform\": true to the rule "
                                                "to split them along its sphere's or box's boundary (docs/scene-format.md, \"conform\")"
                                              : "elements whose centroid lies outside it are not held; where a remesh rounded off the rim "
                                                "of a flat face, keep operating_region.keep_flat_faces on (docs/graded.md, \"What a remesh "
                                                "keeps\")"));
  }
}

/// Whether the mesh solved is not the one read or generated (a graded remesh, a red-green
/// refinement): its element numbers are then its own, and messages must say so.
bool mesh_rebuilt(const Scene& scene) {
  return scene.graded || !scene.element_origin.empty() || scene.mesh_source.find("red-green") != std::string::npos ||
         scene.mesh_source.find("prepared") != std::string::npos;
}

/// The command that makes a mesh file too large for the dense solve solvable (docs/organs.md):
/// `bemsurg prepare` remeshes it to a few thousand elements, in metres.
std::string prepare_hint(const io::JsonReader& mesh, const std::string& path) {
  const std::optional<io::JsonReader> scale = mesh.optional("scale");
  const double s = scale ? scale->positive() : 1.0;
  return "; to make it solvable, remesh it: bemsurg prepare '" + path + "' -o prepared.obj" +
         (s != 1.0 ? " --scale " + io::json_number_text(s) : std::string()) +
         " --target-elements 3000, then set mesh.file to prepared.obj" +
         (s != 1.0 ? " and remove mesh.scale (prepared.obj is in metres)" : std::string()) + " (docs/organs.md), or add \"prepare\": {" +
         (s != 1.0 ? "\"scale\": " + io::json_number_text(s) : std::string()) + "} to the scene's mesh section" +
         (s != 1.0 ? " and remove mesh.scale" : std::string());
}

/// A "prepare" section's target when it gives none: the backend that will solve decides
/// (docs/organs.md, "How big"; "auto" keeps the dense default).
Index prepare_default_elements(const Scene& scene) {
  return scene.solver.backend == SolverBackend::HMatrix ? kDefaultPreparedElementsHierarchical : kDefaultPreparedElements;
}

/// The dense solve of the final mesh (as read, generated, refined or remeshed) must fit in memory
/// (docs/design.md §10): refused here, before any command allocates a matrix. A mesh file as read
/// is told the command that remeshes it; a generated or graded one with constant elements is left
/// to the generators' own checks and solve_elastostatic's, and linear elements (9 unknowns per
/// element, not 3) are refused whatever the mesh's origin.
void require_solvable_size(const Scene& scene, const io::JsonReader& mesh, const std::string& directory) {
  const Index E = scene.problem.mesh.num_elements();
  const bool linear = scene.problem.elements == ElementType::Linear;
  // A scalapack solve holds a rank's share of A*, which depends on the ranks of the run: the solve
  // checks its rank's need itself (distributed/scalapack_solver.hpp).
  if (scene.solver.backend == SolverBackend::ScaLapack) return;
  // The hierarchical backend's estimate where the scene asks for it or may get it ("auto": a mesh
  // too large for dense is solved hierarchically where that backend is built). A command that
  // computes a dense table checks its own need before it starts.
  const bool hierarchical = scene.solver.backend == SolverBackend::HMatrix || scene.solver.automatic_backend;
  const double need =
      hierarchical ? estimate_hierarchical_bytes(E, scene.problem.elements) : estimate_elastostatic_bytes(E, scene.problem.elements);
  const double limit = default_memory_limit_bytes();
  if (need <= limit) return;
  const std::string fits = std::string(hierarchical ? "the hierarchical solve needs about " : "the dense solve needs about ") +
                           format_gib(need) + ", more than the limit of " + format_gib(limit) + " (80 % of physical memory)";
  if (!scene.element_origin.empty()) {  // the rules' splits made it too large: their keys are at fault
    const Index given = *std::max_element(scene.element_origin.begin(), scene.element_origin.end()) + 1;
    throw ResourceError("boundary_conditions.rules: \"refine_rim\" and \"conform\" made the mesh of " + std::to_string(given) +
                        " elements " + std::to_string(E) + (linear ? " linear" : "") + " elements (" +
                        std::to_string(3 * nodes_per_element(scene.problem.elements) * E) + " unknowns); " + fits +
                        "; ask for fewer refine_rim levels" +
                        (linear ? "" : " (with constant elements refine_rim refines the whole surface once first)") +
                        (hierarchical ? "" : ", or solve with \"method\": \"auto\" or \"hmatrix\""));
  }
  if (mesh.has("prepare") && !scene.graded) {  // the prepared mesh is too large: its target is at fault
    const io::JsonReader p = mesh.required("prepare");
    throw ResourceError(p.path() + ": the prepared mesh has " + std::to_string(E) + " elements (" +
                        std::to_string(3 * nodes_per_element(scene.problem.elements) * E) + " unknowns); " + fits +
                        "; ask for fewer (prepare.target_elements, a longer prepare.edge_length; the default is " +
                        std::to_string(prepare_default_elements(scene)) + ")");
  }
  if (mesh.has("file") && !scene.graded) {
    const std::string path = io::resolve_existing(directory, mesh.required("file"));
    throw ResourceError("mesh.file: the mesh '" + path + "' has " + std::to_string(E) + (linear ? " linear" : "") + " elements (" +
                        std::to_string(3 * nodes_per_element(scene.problem.elements) * E) + " unknowns); " + fits +
                        prepare_hint(mesh, path));
  }
  if (!linear) return;
  throw ResourceError("elements: the mesh has " + std::to_string(E) + " linear elements (" + std::to_string(9 * E) + " unknowns); " + fits +
                      "; coarsen the mesh or use constant elements");
}

/// Legal but unreliable: a body thinner than its elements (docs/design.md §2, docs/stability.md
/// study (g)), judged on the mesh solved. When that is not the mesh read or generated, the
/// warning says which mesh its element numbers refer to and where the commands write it.
void warn_thin_elements(Scene& scene) {
  const ThinElements thin = find_thin_elements(scene.problem.mesh);
  if (thin.count == 0) return;
  std::string w = "mesh: " + thin_elements_warning(thin);
  if (mesh_rebuilt(scene))
    w += " (element numbers refer to the solved mesh, " + std::to_string(scene.problem.mesh.num_elements()) + " elements after the " +
         (scene.graded                                              ? "graded remesh"
          : scene.mesh_source.find("prepared") != std::string::npos ? "preparation"
                                                                    : "red-green refinement") +
         ", not to the input; bemsurg solve, press, cut and session write it to OUTDIR/solved_mesh.obj)";
  scene.warnings.push_back(std::move(w));
}

Scene build_scene(const io::JsonDocument& document, const std::string& directory, const std::string& name) {
  Scene scene;
  scene.path = name;
  scene.directory = directory;
  const io::JsonSource source{"", &scene.warnings};  // scene messages start with the key path
  const io::JsonReader root(document.root(), source);
  if (!root.is_object()) throw SceneError(name + ": expected a JSON object at the top level, got " + root.type_name());
  root.warn_unknown_keys(
      {"mesh", "material", "gravity", "boundary_conditions", "interior_points", "solver", "quadrature", "operating_region", "elements"});

  ElastostaticProblem& problem = scene.problem;
  if (const std::optional<io::JsonReader> t = root.optional("elements")) {
    const std::string type = t->string();
    if (type != "constant" && type != "linear") t->fail("expected \"constant\" or \"linear\", got \"" + type + "\"");
    problem.elements = parse_element_type(type);
  }
  if (const std::optional<io::JsonReader> g = root.optional("gravity")) problem.gravity = g->vec3();
  problem.material = io::load_material(root.required("material"), !problem.gravity.isZero(0.0));
  // Before the mesh: the size a mesh may have follows the solver's backend (require_solvable_size).
  if (const std::optional<io::JsonReader> s = root.optional("solver")) scene.solver = io::load_solver(*s);
  // A graded operating region remeshes the mesh itself: a "prepare" section then only repairs.
  double graded_inside_edge = 0.0;
  if (const std::optional<io::JsonReader> r = root.optional("operating_region"); r && r->is_object())
    if (const std::optional<io::JsonReader> h = r->optional("inside_edge_length")) graded_inside_edge = h->positive();
  problem.mesh = io::load_mesh(root.required("mesh"), directory, scene.mesh_source, graded_inside_edge, prepare_default_elements(scene));
  scene.input_elements = problem.mesh.num_elements();
  const TriangleMesh as_read = problem.mesh;  // where the rules' regions are measured ("region_area")
  // The operating region comes before the boundary conditions: it may remesh, and the rules then
  // select on the mesh that is solved.
  if (const std::optional<io::JsonReader> r = root.optional("operating_region")) {
    const io::OperatingRegionRequest request = io::parse_operating_region(*r, problem.mesh);
    scene.operating_region = request.region;
    scene.has_operating_region = true;
    io::remesh_for_operating_region(request, scene);
  }
  require_solvable_size(scene, root.required("mesh"), directory);
  io::LoadedBoundaryConditions bcs =
      io::load_boundary_conditions(root.required("boundary_conditions"), directory, problem.mesh, as_read, problem.elements);
  problem.boundary_conditions = std::move(bcs.conditions);
  scene.boundary_rules = std::move(bcs.rules);
  scene.element_origin = std::move(bcs.origin);
  scene.element_grading_size = std::move(bcs.grading_size);
  for (const std::string& change : bcs.mesh_changes) scene.mesh_source += ", " + change;
  scene.warnings.insert(scene.warnings.end(), bcs.warnings.begin(), bcs.warnings.end());
  if (!scene.element_origin.empty()) require_solvable_size(scene, root.required("mesh"), directory);  // the rules' splits added elements
  scene.mesh_quality = measure_mesh_quality(problem.mesh);
  warn_thin_elements(scene);
  // Slivers at load, so that every command warns before its work (solve's own check_before_solve
  // warning is then not repeated; docs/stability.md (c)).
  if (std::string w = sliver_warning(problem.mesh); !w.empty()) scene.warnings.push_back("mesh: " + w);
  warn_partial_supports(scene);
  if (problem.elements == ElementType::Linear) {
    // Values at the nodes: as given by the node variant of the file, else the linear interpolation
    // of the corners' (docs/elements.md: a field sampled at the nodes is what the elements collocate).
    const RowMatrixX3d& corners = bcs.corner_values;
    problem.node_values.resize(corners.rows(), 3);
    for (Index e = 0; e < problem.mesh.num_elements(); ++e)
      problem.node_values.middleRows<3>(3 * e) =
          bcs.at_nodes ? Eigen::Matrix3d(corners.middleRows<3>(3 * e)) : linear_corners_to_nodes(corners.middleRows<3>(3 * e));
  }
  if (scene.has_operating_region) collect_operating_elements(scene);
  warn_unsafe_grading(scene);
  if (const std::optional<io::JsonReader> q = root.optional("quadrature")) problem.quadrature = io::load_quadrature(*q);
  if (const std::optional<io::JsonReader> ip = root.optional("interior_points")) {
    scene.interior_points = io::load_interior_points(*ip, directory, problem.mesh, problem.quadrature);
    scene.has_interior_points = true;
  }
  return scene;
}

}  // namespace

Scene load_scene_from_string(const std::string& json_text, const std::string& directory, const std::string& name) {
  return build_scene(io::JsonDocument(json_text, name), directory, name);
}

namespace {

std::string read_scene_text(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw SceneError(path + ": cannot read the scene: it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot read the scene: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string scene_directory(const std::string& path) {
  const std::string directory = std::filesystem::path(path).parent_path().string();
  return directory.empty() ? "." : directory;
}

}  // namespace

Scene load_scene(const std::string& path) {
  return build_scene(io::JsonDocument(read_scene_text(path), path), scene_directory(path), path);
}

const Scene& require_constant_elements(const Scene& scene, const std::string& command) {
  if (scene.problem.elements == ElementType::Constant) return scene;
  throw SceneError(scene.path + ": elements: \"" + std::string(to_string(scene.problem.elements)) + "\" is not supported by " + command +
                   ": contact tables, cutting, the haptic session and the viewer use constant elements (docs/elements.md); "
                   "remove the key or set \"elements\": \"constant\"");
}

Scene require_constant_elements(Scene&& scene, const std::string& command) {
  require_constant_elements(static_cast<const Scene&>(scene), command);
  return std::move(scene);
}

Scene load_scene_with_mesh(const std::string& path, const std::string& mesh_file) {
  const io::JsonDocument original(read_scene_text(path), path);
  nlohmann::json root = original.root();
  if (!root.is_object()) throw SceneError(path + ": expected a JSON object at the top level");
  root["mesh"] = {{"file", std::filesystem::absolute(mesh_file).string()}};
  // The file is the mesh to solve (a cut's mesh.obj is the graded mesh, cut): not graded again.
  if (root.contains("operating_region") && root["operating_region"].is_object())
    for (const char* key : {"inside_edge_length", "outside_edge_length", "growth", "feature_angle", "supported"})
      root["operating_region"].erase(key);
  // Nor split again by the rules: their "conform" and "refine_rim" made the mesh given.
  if (root.contains("boundary_conditions") && root["boundary_conditions"].is_object() && root["boundary_conditions"].contains("rules") &&
      root["boundary_conditions"]["rules"].is_array())
    for (nlohmann::json& rule : root["boundary_conditions"]["rules"])
      if (rule.is_object()) {
        rule.erase("conform");
        rule.erase("refine_rim");
      }
  return build_scene(io::JsonDocument(root.dump(), path), scene_directory(path), path);
}

}  // namespace bemsurg
