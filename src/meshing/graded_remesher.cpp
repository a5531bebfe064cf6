// Graded remeshing of a closed surface with Gmsh (mesh/graded_remesher.hpp, docs/graded.md).
//
// The one compiled file that talks to Gmsh, so the rest of bemsurg neither includes Gmsh's headers
// nor needs libgmsh; built without BEMSURG_HAVE_GMSH it keeps the same interface and says why it
// cannot remesh. Gmsh is loaded when the first remesh asks for it (dlopen of its C API), not at
// program start: Debian's libgmsh pulls in about 90 shared libraries (OpenCASCADE, FLTK, image
// codecs), whose symbol binding cost every bemsurg program about 0.13 s at start-up, remeshing or
// not (docs/development.md, "Build profile, before and after").
#include "bemsurg/meshing/graded_remesher.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/mesh/geometry.hpp"
#include "bemsurg/mesh/mesh_topology.hpp"
#include "bemsurg/mesh/mesh_validation.hpp"
#include "bemsurg/mesh/vertex_welding.hpp"
#include "bemsurg/number_text.hpp"

#ifdef BEMSURG_HAVE_GMSH
#include <dlfcn.h>
extern "C" {        // gmshc.h declares C functions without a guard of its own
#include <gmshc.h>  // the C API's declarations only: its functions are looked up in the loaded library
}
#endif

namespace bemsurg {

namespace {

void check_options(const GradedRemeshOptions& o) {
  const double hi = o.inside_edge_length, ho = o.outside_edge_length;
  if (!(std::isfinite(hi) && hi > 0.0))
    throw InvalidArgumentError("graded remesh: inside_edge_length must be a positive length, got " + number_text(hi));
  if (!(std::isfinite(ho) && ho > 0.0))
    throw InvalidArgumentError("graded remesh: outside_edge_length must be a positive length, got " + number_text(ho));
  if (hi > ho)
    throw InvalidArgumentError("graded remesh: inside_edge_length (" + number_text(hi) + ") is larger than outside_edge_length (" +
                               number_text(ho) + "): the operating region must be the finer part (inverted target lengths?)");
  if (!(o.growth > 1.0 && o.growth <= 2.0))
    throw InvalidArgumentError("graded remesh: growth must lie in (1, 2], got " + number_text(o.growth));
  if (!(o.feature_angle_degrees > 0.0 && o.feature_angle_degrees < 180.0))
    throw InvalidArgumentError("graded remesh: feature_angle_degrees must lie in (0, 180)");
  if (!(o.planar_rim_area_loss >= 0.0 && o.planar_rim_area_loss < 1.0))
    throw InvalidArgumentError("graded remesh: planar_rim_area_loss must lie in [0, 1), got " + number_text(o.planar_rim_area_loss));
}

#ifdef BEMSURG_HAVE_GMSH
// Gmsh keeps one model per process behind its API (gmshInitialize / gmshFinalize are global); two
// threads remeshing at once would share it. This lock and the loaded library below are the one
// piece of shared state here, and exist only because the library we call has them.
std::mutex& gmsh_mutex() {
  static std::mutex m;
  return m;
}

/// A Gmsh call that failed (its ierr set): Gmsh's own message.
struct GmshFailure {
  std::string what;
};

/// The functions of Gmsh's C API that the remesher calls, looked up in libgmsh (BEMSURG_GMSH_LIBRARY:
/// its soname, else its path, as configured), which is loaded on first use and kept.
struct GmshApi {
  decltype(&::gmshInitialize) initialize = nullptr;
  decltype(&::gmshFinalize) finalize = nullptr;
  decltype(&::gmshFree) free = nullptr;
  decltype(&::gmshLoggerGetLastError) last_error = nullptr;
  decltype(&::gmshOptionSetNumber) set_number = nullptr;
  decltype(&::gmshModelAdd) add_model = nullptr;
  decltype(&::gmshModelAddDiscreteEntity) add_discrete_entity = nullptr;
  decltype(&::gmshModelMeshAddNodes) add_nodes = nullptr;
  decltype(&::gmshModelMeshAddElementsByType) add_elements_by_type = nullptr;
  decltype(&::gmshModelMeshReclassifyNodes) reclassify_nodes = nullptr;
  decltype(&::gmshModelMeshCreateTopology) create_topology = nullptr;
  decltype(&::gmshModelMeshClassifySurfaces) classify_surfaces = nullptr;
  decltype(&::gmshModelMeshCreateGeometry) create_geometry = nullptr;
  decltype(&::gmshModelMeshSetSizeCallback) set_size_callback = nullptr;
  decltype(&::gmshModelMeshGenerate) generate = nullptr;
  decltype(&::gmshModelMeshGetNodes) get_nodes = nullptr;
  decltype(&::gmshModelMeshGetElementsByType) get_elements_by_type = nullptr;

  /// Throws GmshFailure with Gmsh's last error when a call set `ierr`.
  void check(int ierr) const {
    if (ierr == 0) return;
    std::string message = "error " + std::to_string(ierr);
    char* text = nullptr;
    int ignored = 0;
    last_error(&text, &ignored);
    if (text) {
      if (*text) message = text;
      free(text);
    }
    throw GmshFailure{message};
  }
};

/// Loads libgmsh and its functions once; throws Error naming the library when it cannot.
const GmshApi& gmsh_api() {
  static const GmshApi api = [] {
    void* library = dlopen(BEMSURG_GMSH_LIBRARY, RTLD_NOW | RTLD_LOCAL);
    if (!library) {
      const char* why = dlerror();
      throw Error(std::string("graded remesh: cannot load Gmsh (") + BEMSURG_GMSH_LIBRARY + "): " + (why ? why : "unknown reason") +
                  "; install libgmsh (scripts/setup-deps.sh)");
    }
    GmshApi a;
    const auto find = [library](auto& function, const char* name) {
      void* symbol = dlsym(library, name);
      if (!symbol) {
        dlclose(library);  // the next call tries again from the start
        throw Error(std::string("graded remesh: ") + BEMSURG_GMSH_LIBRARY + " has no " + name + " (not Gmsh 4.8's C API?)");
      }
      function = reinterpret_cast<std::remove_reference_t<decltype(function)>>(symbol);
    };
    find(a.initialize, "gmshInitialize");
    find(a.finalize, "gmshFinalize");
    find(a.free, "gmshFree");
    find(a.last_error, "gmshLoggerGetLastError");
    find(a.set_number, "gmshOptionSetNumber");
    find(a.add_model, "gmshModelAdd");
    find(a.add_discrete_entity, "gmshModelAddDiscreteEntity");
    find(a.add_nodes, "gmshModelMeshAddNodes");
    find(a.add_elements_by_type, "gmshModelMeshAddElementsByType");
    find(a.reclassify_nodes, "gmshModelMeshReclassifyNodes");
    find(a.create_topology, "gmshModelMeshCreateTopology");
    find(a.classify_surfaces, "gmshModelMeshClassifySurfaces");
    find(a.create_geometry, "gmshModelMeshCreateGeometry");
    find(a.set_size_callback, "gmshModelMeshSetSizeCallback");
    find(a.generate, "gmshModelMeshGenerate");
    find(a.get_nodes, "gmshModelMeshGetNodes");
    find(a.get_elements_by_type, "gmshModelMeshGetElementsByType");
    return a;  // the library stays loaded: Gmsh's state lives in it
  }();
  return api;
}

/// An array Gmsh allocated, copied out and given back to Gmsh's allocator.
template <class T>
std::vector<T> take_gmsh_array(const GmshApi& gmsh, T* data, std::size_t n) {
  std::vector<T> out(data, data + (data ? n : 0));
  if (data) gmsh.free(data);
  return out;
}

// Gmsh meshes each patch in its own parametrisation, so patches need not come back with the
// input's orientation. Written here because no Gmsh call re-orients a discrete surface mesh to
// match another: orient every shell consistently by a walk across its edges, then flip the shells
// whose faces disagree with the nearest faces of the input (a vote over sample faces).
void orient_like_input(const TriangleMesh& input, RowMatrixX3d& V, RowMatrixX3i& F) {
  {
    const TriangleMesh m(V, F);
    const MeshTopology topo(m);
    std::vector<char> done(static_cast<std::size_t>(F.rows()), 0);
    std::vector<Index> stack;
    for (Index seed = 0; seed < F.rows(); ++seed) {
      if (done[static_cast<std::size_t>(seed)]) continue;
      done[static_cast<std::size_t>(seed)] = 1;
      stack.push_back(seed);
      while (!stack.empty()) {
        const Index f = stack.back();
        stack.pop_back();
        for (int k = 0; k < 3; ++k) {
          const Index g = topo.neighbour(f, k);
          if (g < 0 || done[static_cast<std::size_t>(g)]) continue;
          // f runs a -> b on this edge; a consistently oriented g runs b -> a.
          const int a = F(f, k), b = F(f, (k + 1) % 3);
          bool same_direction = false;
          for (int j = 0; j < 3; ++j)
            if (F(g, j) == a && F(g, (j + 1) % 3) == b) same_direction = true;
          if (same_direction) std::swap(F(g, 1), F(g, 2));
          done[static_cast<std::size_t>(g)] = 1;
          stack.push_back(g);
        }
      }
    }
  }
  const TriangleMesh m(V, F);
  const MeshTopology topo(m);
  for (Index s = 0; s < topo.num_shells(); ++s) {
    const std::vector<Index>& faces = topo.shell(s);
    const std::size_t stride = std::max<std::size_t>(1, faces.size() / 64);
    double vote = 0.0;
    for (std::size_t i = 0; i < faces.size(); i += stride) {
      const Index f = faces[i];
      Index nearest = 0;
      double best = std::numeric_limits<double>::infinity();
      for (Index e = 0; e < input.num_elements(); ++e) {
        const double d = (input.centroid(e) - m.centroid(f)).squaredNorm();
        if (d < best) best = d, nearest = e;
      }
      vote += m.normal(f).dot(input.normal(nearest));
    }
    if (vote < 0.0)
      for (Index f : faces) std::swap(F(f, 1), F(f, 2));
  }
}

/// The surface of each face when the input has flat faces: planar region i is surface i, and the
/// rest is split into parts bounded by creases sharper than the feature angle (flood fill across
/// the smoother edges). Done here rather than by Gmsh's classifySurfaces because the triangles
/// along a flat face's rim zigzag (a faceted round body cut by a plane): edges between them meet
/// at 40-60 degrees, and Gmsh, asked to keep them, cut the sides into slivers along the rim (min
/// angle 4 degrees, neighbouring sizes 8:1 on the brain). An edge with a corner on a rim is
/// therefore never a crease: the rim itself is kept as the border of the flat face.
std::vector<int> surface_of_faces(const TriangleMesh& input, const std::vector<PlanarRegion>& planes, double feature_angle_degrees) {
  const auto n = static_cast<std::size_t>(input.num_elements());
  std::vector<int> surface(n, -1);
  for (std::size_t i = 0; i < planes.size(); ++i)
    for (const Index f : planes[i].faces) surface[static_cast<std::size_t>(f)] = static_cast<int>(i);
  const MeshTopology topo(input);
  std::vector<char> on_rim(static_cast<std::size_t>(input.num_vertices()), 0);
  for (Index f = 0; f < input.num_elements(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index g = topo.neighbour(f, k);
      if (g >= 0 && surface[static_cast<std::size_t>(f)] != surface[static_cast<std::size_t>(g)])
        on_rim[static_cast<std::size_t>(input.faces()(f, k))] = on_rim[static_cast<std::size_t>(input.faces()(f, (k + 1) % 3))] = 1;
    }
  const double crease_cos = std::cos(feature_angle_degrees * numbers::pi / 180.0);
  int next = static_cast<int>(planes.size());
  std::vector<Index> stack;
  for (Index seed = 0; seed < input.num_elements(); ++seed) {
    if (surface[static_cast<std::size_t>(seed)] >= 0) continue;
    surface[static_cast<std::size_t>(seed)] = next;
    stack.push_back(seed);
    while (!stack.empty()) {
      const Index f = stack.back();
      stack.pop_back();
      for (int k = 0; k < 3; ++k) {
        const Index g = topo.neighbour(f, k);
        if (g < 0 || surface[static_cast<std::size_t>(g)] >= 0) continue;
        const bool rim =
            on_rim[static_cast<std::size_t>(input.faces()(f, k))] || on_rim[static_cast<std::size_t>(input.faces()(f, (k + 1) % 3))];
        if (!rim && input.normal(f).dot(input.normal(g)) < crease_cos) continue;  // a crease: the border of a part
        surface[static_cast<std::size_t>(g)] = next;
        stack.push_back(g);
      }
    }
    ++next;
  }
  return surface;
}

/// The target size near the rims of flat faces. Gmsh resamples a rim with chords, and a chord
/// leaves the sliver between itself and the rim to the sides: for a convex rim of total turning 2 pi
/// meshed at h the flat face loses about pi h^2 / (6 A) of its area A (the polygon inscribed in a
/// circle). Meshing the rim at h_rim = sqrt(6 loss A / pi) keeps that loss near `loss`
/// (GradedRemeshOptions::planar_rim_area_loss); the size grows away from the rim by the grading's
/// factor, as it does away from an operating region.
class RimSizes {
 public:
  RimSizes(const TriangleMesh& input, const std::vector<PlanarRegion>& planes, const GradedRemeshOptions& o) : growth_(o.growth) {
    if (planes.empty() || !(o.planar_rim_area_loss > 0.0)) return;
    const MeshTopology topo(input);
    std::vector<int> region_of(static_cast<std::size_t>(input.num_elements()), -1);
    for (std::size_t i = 0; i < planes.size(); ++i)
      for (const Index f : planes[i].faces) region_of[static_cast<std::size_t>(f)] = static_cast<int>(i);
    for (std::size_t i = 0; i < planes.size(); ++i) {
      const double h = std::sqrt(6.0 * o.planar_rim_area_loss * planes[i].area / numbers::pi);
      if (h >= o.outside_edge_length) continue;
      for (const Index f : planes[i].faces)
        for (int k = 0; k < 3; ++k) {
          const Index g = topo.neighbour(f, k);
          if (g >= 0 && region_of[static_cast<std::size_t>(g)] == static_cast<int>(i)) continue;
          segments_.push_back({input.vertex(input.faces()(f, k)), input.vertex(input.faces()(f, (k + 1) % 3)), h});
        }
    }
  }

  /// min over rim segments of h_rim + (growth - 1) * distance; infinite without rims.
  double at(const Vec3& x) const {
    double h = std::numeric_limits<double>::infinity();
    for (const Segment& s : segments_) {
      const Vec3 d = s.b - s.a;
      const double t = std::clamp((x - s.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
      h = std::min(h, s.size + (growth_ - 1.0) * (x - s.a - t * d).norm());
    }
    return h;
  }

 private:
  struct Segment {
    Vec3 a, b;
    double size;
  };
  double growth_;
  std::vector<Segment> segments_;
};

/// Hands the input to Gmsh as discrete surfaces and makes them geometry Gmsh can parametrise.
/// Without flat faces, one surface that Gmsh's classifySurfaces splits at creases sharper than
/// the feature angle. With them, the parts of surface_of_faces: createTopology makes their common
/// borders discrete curves, and classifySurfaces (no angle of its own) keeps existing curves as
/// borders, so the rim of a flat face survives however shallow the angle at which the input's
/// triangles meet it there.
void add_input_surfaces(const GmshApi& gmsh, const TriangleMesh& input, const std::vector<PlanarRegion>& planes,
                        double feature_angle_degrees) {
  int ierr = 0;
  const std::vector<int> entity_of_face = planes.empty() ? std::vector<int>(static_cast<std::size_t>(input.num_elements()), 0)
                                                         : surface_of_faces(input, planes, feature_angle_degrees);
  const auto surfaces_count = static_cast<std::size_t>(*std::max_element(entity_of_face.begin(), entity_of_face.end()) + 1);
  std::vector<std::vector<std::size_t>> element_tags(surfaces_count), element_nodes(surfaces_count);
  for (Index e = 0; e < input.num_elements(); ++e) {
    const auto k = static_cast<std::size_t>(entity_of_face[static_cast<std::size_t>(e)]);
    element_tags[k].push_back(static_cast<std::size_t>(e) + 1);
    for (int c = 0; c < 3; ++c) element_nodes[k].push_back(static_cast<std::size_t>(input.faces()(e, c)) + 1);
  }
  std::vector<int> surfaces;
  for (std::size_t k = 0; k < element_tags.size(); ++k)
    if (!element_tags[k].empty()) {
      surfaces.push_back(gmsh.add_discrete_entity(2, static_cast<int>(k) + 1, nullptr, 0, &ierr));
      gmsh.check(ierr);
    }
  // All nodes go to the first surface; reclassifyNodes moves them to where their elements are.
  std::vector<std::size_t> node_tags(static_cast<std::size_t>(input.num_vertices()));
  std::vector<double> coords(3 * node_tags.size());
  for (Index v = 0; v < input.num_vertices(); ++v) {
    node_tags[static_cast<std::size_t>(v)] = static_cast<std::size_t>(v) + 1;
    for (int k = 0; k < 3; ++k) coords[static_cast<std::size_t>(3 * v + k)] = input.vertices()(v, k);
  }
  gmsh.add_nodes(2, surfaces.front(), node_tags.data(), node_tags.size(), coords.data(), coords.size(), nullptr, 0, &ierr);
  gmsh.check(ierr);
  for (std::size_t k = 0; k < element_tags.size(); ++k)
    if (!element_tags[k].empty()) {  // type 2: 3-node triangles
      gmsh.add_elements_by_type(static_cast<int>(k) + 1, 2, element_tags[k].data(), element_tags[k].size(), element_nodes[k].data(),
                                element_nodes[k].size(), &ierr);
      gmsh.check(ierr);
    }
  if (surfaces.size() > 1) {
    gmsh.reclassify_nodes(&ierr);
    gmsh.check(ierr);
    gmsh.create_topology(1, 1, &ierr);  // simply connected, discrete entities exported (the C++ API's defaults)
    gmsh.check(ierr);
  }
  const double angle = planes.empty() ? feature_angle_degrees * numbers::pi / 180.0 : numbers::pi;
  gmsh.classify_surfaces(angle, 1, 1, numbers::pi, 1, &ierr);  // boundary, for reparametrisation, export discrete
  gmsh.check(ierr);
  gmsh.create_geometry(nullptr, 0, &ierr);
  gmsh.check(ierr);
}

/// Gmsh's triangles as a mesh of the nodes they use.
void read_gmsh_triangles(const GmshApi& gmsh, RowMatrixX3d& V, RowMatrixX3i& F) {
  int ierr = 0;
  std::size_t *tag_data = nullptr, *tri_tag_data = nullptr, *tri_node_data = nullptr;
  double *xyz_data = nullptr, *param_data = nullptr;
  std::size_t tags_n = 0, xyz_n = 0, param_n = 0, tri_tags_n = 0, tri_nodes_n = 0;
  gmsh.get_nodes(&tag_data, &tags_n, &xyz_data, &xyz_n, &param_data, &param_n, -1, -1, 1, 0, &ierr);
  const std::vector<std::size_t> tags = take_gmsh_array(gmsh, tag_data, tags_n);
  const std::vector<double> xyz = take_gmsh_array(gmsh, xyz_data, xyz_n);
  take_gmsh_array(gmsh, param_data, param_n);
  gmsh.check(ierr);
  gmsh.get_elements_by_type(2, &tri_tag_data, &tri_tags_n, &tri_node_data, &tri_nodes_n, -1, 0, 1, &ierr);
  const std::vector<std::size_t> tri_tags = take_gmsh_array(gmsh, tri_tag_data, tri_tags_n);
  const std::vector<std::size_t> tri_nodes = take_gmsh_array(gmsh, tri_node_data, tri_nodes_n);
  gmsh.check(ierr);
  if (xyz.size() < 3 * tags.size() || tri_nodes.size() < 3 * tri_tags.size()) throw Error("graded remesh: Gmsh returned short arrays");
  if (tri_tags.empty()) throw Error("graded remesh: Gmsh produced no triangles");
  std::unordered_map<std::size_t, std::size_t> position;
  for (std::size_t i = 0; i < tags.size(); ++i) position.emplace(tags[i], i);
  std::unordered_map<std::size_t, int> index;  // Gmsh node tag -> our vertex index (used nodes only)
  std::vector<Vec3> points;
  F.resize(static_cast<Index>(tri_tags.size()), 3);
  for (std::size_t t = 0; t < tri_tags.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::size_t tag = tri_nodes[3 * t + static_cast<std::size_t>(k)];
      auto it = index.find(tag);
      if (it == index.end()) {
        const auto p = position.find(tag);
        if (p == position.end()) throw Error("graded remesh: Gmsh returned a triangle with an unknown node");
        const std::size_t i = p->second;
        points.emplace_back(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
        it = index.emplace(tag, static_cast<int>(points.size() - 1)).first;
      }
      F(static_cast<Index>(t), k) = it->second;
    }
  V.resize(static_cast<Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i) V.row(static_cast<Index>(i)) = points[i].transpose();
}

TriangleMesh remesh_with_gmsh(const TriangleMesh& input, const OperatingRegion& region, const GradedRemeshOptions& o) {
  const std::vector<PlanarRegion> planes =
      o.keep_planar_regions ? find_planar_regions(input, o.planar_regions) : std::vector<PlanarRegion>();
  std::lock_guard<std::mutex> lock(gmsh_mutex());
  const GmshApi& gmsh = gmsh_api();
  int ierr = 0;
  gmsh.initialize(0, nullptr, 0, &ierr);
  gmsh.check(ierr);
  struct Finalize {
    const GmshApi& gmsh;
    ~Finalize() {
      int ignored = 0;
      gmsh.finalize(&ignored);
    }
  } finalize{gmsh};
  const auto set = [&gmsh, &ierr](const char* name, double value) {
    gmsh.set_number(name, value, &ierr);
    gmsh.check(ierr);
  };
  set("General.Terminal", 0);
  set("General.Verbosity", 0);
  gmsh.add_model("bemsurg_graded", &ierr);
  gmsh.check(ierr);
  add_input_surfaces(gmsh, input, planes, o.feature_angle_degrees);

  set("Mesh.MeshSizeFromPoints", 0);
  set("Mesh.MeshSizeFromCurvature", 0);
  set("Mesh.MeshSizeExtendFromBoundary", 0);
  set("Mesh.Algorithm", 6);  // Frontal-Delaunay: the best-shaped triangles
  set("Mesh.MeshSizeMin", o.inside_edge_length);
  set("Mesh.MeshSizeMax", o.outside_edge_length);
  struct Sizes {
    const OperatingRegion& region;
    const GradedRemeshOptions& o;
    RimSizes rims;
  } sizes{region, o, RimSizes(input, planes, o)};
  // A C callback: nothing may be thrown through Gmsh. graded_target_size and RimSizes::at do not
  // throw; should they ever, the point gets the outside length (the coarsest, always valid).
  const auto size_at = [](int, int, double x, double y, double z, void* data) noexcept -> double {
    const Sizes& s = *static_cast<const Sizes*>(data);
    try {
      const Vec3 p(x, y, z);
      const double h = graded_target_size(s.region, s.o, p);
      return h > s.o.inside_edge_length ? std::min(h, std::max(s.o.inside_edge_length, s.rims.at(p))) : h;
    } catch (...) { return s.o.outside_edge_length; }
  };
  gmsh.set_size_callback(size_at, &sizes, &ierr);
  gmsh.check(ierr);
  gmsh.generate(2, &ierr);
  gmsh.check(ierr);

  RowMatrixX3d V;
  RowMatrixX3i F;
  read_gmsh_triangles(gmsh, V, F);
  // Gmsh's points on a flat surface lie on the input's triangles up to rounding; put them (and the
  // rim's) exactly onto the fitted plane, so the face is flat to the last digit.
  snap_to_planar_regions(V, F, input, planes, o.planar_regions.distance_tolerance * bounding_box_diagonal(input.vertices()));
  orient_like_input(input, V, F);
  return TriangleMesh(std::move(V), std::move(F));
}
#endif

}  // namespace

double graded_target_size(const OperatingRegion& region, const GradedRemeshOptions& o, const Vec3& x) {
  double d = region.distance(x);
  for (const OperatingRegion& s : o.supported_regions) d = std::min(d, s.distance(x));
  return std::min(o.outside_edge_length, o.inside_edge_length + (o.growth - 1.0) * d);
}

double support_size_ratio(const TriangleMesh& mesh, const std::vector<char>& displacement_prescribed) {
  std::vector<double> sizes(static_cast<std::size_t>(mesh.num_elements()));
  for (Index e = 0; e < mesh.num_elements(); ++e) sizes[static_cast<std::size_t>(e)] = element_size(mesh, e);
  return support_size_ratio(sizes, displacement_prescribed);
}

double support_size_ratio(const std::vector<double>& element_sizes, const std::vector<char>& displacement_prescribed) {
  // Percentiles, not extremes: a uniform Gmsh mesh's element sizes spread by about 1.4 between the
  // largest and the smallest (docs/graded.md), which says nothing about its grading.
  std::vector<double> all = element_sizes, held;
  for (std::size_t e = 0; e < all.size(); ++e)
    if (e < displacement_prescribed.size() && displacement_prescribed[e]) held.push_back(all[e]);
  if (held.empty()) return 0.0;
  const auto percentile = [](std::vector<double>& v, double q) {
    const auto k = v.begin() + static_cast<std::ptrdiff_t>(q * static_cast<double>(v.size() - 1));
    std::nth_element(v.begin(), k, v.end());
    return *k;
  };
  return percentile(held, 0.9) / percentile(all, 0.1);
}

std::string grading_rule_warning(const TriangleMesh& mesh, const std::vector<char>& displacement_prescribed,
                                 const std::vector<double>& element_sizes) {
  const double ratio = element_sizes.empty() ? support_size_ratio(mesh, displacement_prescribed)
                                             : support_size_ratio(element_sizes, displacement_prescribed);
  if (ratio <= kMaxSupportSizeRatio) return {};
  return "the displacement-prescribed (supported) elements are up to " + number_text(std::round(100.0 * ratio) / 100.0) +
         " times the size of the finest elements (limit " + number_text(kMaxSupportSizeRatio) +
         "): with constant elements such a grading can be less accurate than no refinement; refine the held region too "
         "(scene: operating_region.supported, or a mesh.refine that covers it; docs/graded.md, section Safe gradings)";
}

bool graded_remesher_available() {
#ifdef BEMSURG_HAVE_GMSH
  try {
    gmsh_api();  // built with the remesher, and Gmsh loads (callers ask just before they remesh)
    return true;
  } catch (const Error&) { return false; }
#else
  return false;
#endif
}

GradedRemeshResult graded_remesh(const TriangleMesh& input, const OperatingRegion& region, const GradedRemeshOptions& options) {
  check_options(options);
  try {
    // Slivers are what a remesh removes: the input must be a closed, oriented body, but its faces
    // may be of any shape (a segmentation's marching cubes or decimation leaves slivers; issue 37).
    MeshValidationOptions closed_body;
    closed_body.max_aspect_ratio = std::numeric_limits<double>::infinity();
    require_valid_mesh(input, closed_body);
  } catch (const InvalidMeshError& e) {
    throw InvalidMeshError(std::string("graded remesh: the input surface is not a closed, oriented mesh: ") + e.what());
  }
  region.require_meets_surface(input, 0.5 * options.inside_edge_length);
#ifdef BEMSURG_HAVE_GMSH
  const auto start = std::chrono::steady_clock::now();
  GradedRemeshResult result;
  try {
    result.mesh = remesh_with_gmsh(input, region, options);
  } catch (const Error&) { throw; } catch (const GmshFailure& failure) {  // a Gmsh call set its error code: Gmsh's own message
    throw Error("graded remesh: Gmsh failed: " + failure.what +
                " (a crease the input mesh does not follow? try a finer input mesh or another feature angle)");
  } catch (const std::exception& e) { throw Error(std::string("graded remesh: Gmsh failed: ") + e.what()); }
  try {
    require_valid_mesh(result.mesh);
  } catch (const InvalidMeshError& e) {
    throw Error(std::string("graded remesh: Gmsh's mesh is not a valid closed surface (") + e.what() +
                "); try a finer input mesh or a larger feature angle");
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.quality = measure_mesh_quality(result.mesh);
  return result;
#else
  throw Error(
      "graded remesh: this build of bemsurg has no remesher (configured with BEMSURG_WITH_REMESHER=OFF or "
      "without libgmsh-dev; see docs/graded.md)");
#endif
}

}  // namespace bemsurg
