// "mesh": {"file": ..., "prepare": {...}} (docs/scene-format.md#prepare, docs/organs.md): a raw
// segmentation surface repaired and remeshed as `bemsurg prepare` does, when the scene loads.
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <system_error>

#include <unistd.h>

#include "bemsurg/error.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/meshing/mesh_preparation.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/version.hpp"
#include "scene_sections.hpp"

namespace bemsurg::io {
namespace {

MeshPreparationOptions read_preparation_options(const JsonReader& p, double graded_inside_edge, bool outer_scale, Index default_elements) {
  p.object().warn_unknown_keys(
      {"units", "scale", "target_elements", "edge_length", "max_hole", "wrap_alpha", "wrap_offset", "rebuild", "keep_all"});
  MeshPreparationOptions o;
  o.default_elements = default_elements;
  if (p.has("units") && p.has("scale")) p.fail("give \"units\" or \"scale\", not both");
  if (const std::optional<JsonReader> u = p.optional("units")) {
    const std::string unit = u->string();
    if (unit != "mm" && unit != "cm" && unit != "m") u->fail("expected \"mm\", \"cm\" or \"m\", got \"" + unit + "\"");
    o.scale = length_unit_to_metres(unit);
    o.scale_given = true;
  }
  if (const std::optional<JsonReader> s = p.optional("scale")) {
    o.scale = s->positive();
    o.scale_given = true;
  }
  if (const std::optional<JsonReader> t = p.optional("target_elements")) o.target_elements = t->integer_in(1, kMaxPreparedElements);
  if (const std::optional<JsonReader> l = p.optional("edge_length")) o.edge_length = l->positive();
  if (const std::optional<JsonReader> h = p.optional("max_hole")) o.max_hole_fraction = h->positive();
  if (const std::optional<JsonReader> a = p.optional("wrap_alpha")) o.wrap_alpha_fraction = a->positive();
  if (const std::optional<JsonReader> f = p.optional("wrap_offset")) o.wrap_offset_fraction = f->positive();
  if (const std::optional<JsonReader> r = p.optional("rebuild")) o.force_wrap = r->boolean();
  if (const std::optional<JsonReader> k = p.optional("keep_all")) o.keep_all = k->boolean();
  if (o.target_elements > 0 && o.edge_length > 0.0) p.fail("give \"target_elements\" or \"edge_length\", not both");
  // A mesh.scale says the file's unit too (applied after preparing): no millimetre warning then.
  o.scale_given = o.scale_given || outer_scale;
  if (graded_inside_edge > 0.0) {
    // The scene's operating region grades the repaired surface itself (scene.cpp): prepare only
    // repairs, and coarsens a very fine input for that remesh.
    if (o.target_elements > 0 || o.edge_length > 0.0)
      p.fail("the operating region's edge lengths remesh this mesh: drop \"target_elements\" / \"edge_length\"");
    o.no_remesh = true;
    o.graded_options.inside_edge_length = graded_inside_edge;
  }
  return o;
}

// What prepare_mesh does, as a number: raised with any change to its result, so that a cache
// written by an earlier build of the same version is not served.
constexpr int kPreparationRevision = 2;

// The prepared mesh is cached (docs/organs.md, "Cache"): prepare_mesh is deterministic, so the
// same file bytes, options and bemsurg version give the same mesh, and every command after the
// first that loads the scene (solve, press, cut, session, the viewer) reads it in a tenth of a
// second instead of repairing again for seconds. The cache is $BEMSURG_CACHE_DIR, else
// $XDG_CACHE_HOME/bemsurg, else ~/.cache/bemsurg; BEMSURG_CACHE_DIR=off switches it off. A cache
// that cannot be written is skipped, never an error.
std::filesystem::path cache_directory() {
  const char* own = std::getenv("BEMSURG_CACHE_DIR");
  if (own && std::string(own) == "off") return {};
  if (own && *own) return own;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::filesystem::path(xdg) / "bemsurg";
  if (const char* home = std::getenv("HOME"); home && *home) return std::filesystem::path(home) / ".cache" / "bemsurg";
  return {};
}

/// FNV-1a over the file's bytes and the options that change the result.
std::string cache_key(const std::string& path, const MeshPreparationOptions& o) {
  std::ifstream in(path, std::ios::binary);
  std::uint64_t h = 1469598103934665603ull;
  const auto mix = [&h](const std::string& bytes) {
    for (const unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  };
  mix(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
  mix(std::string(version_string()) + "|" + std::to_string(kPreparationRevision) + "|" + number_text(o.scale) + "|" +
      number_text(o.wrap_alpha_fraction) + "|" + number_text(o.wrap_offset_fraction) + "|" + number_text(o.max_hole_fraction) + "|" +
      std::to_string(o.force_wrap) + std::to_string(o.keep_all) + std::to_string(o.no_remesh) + "|" + std::to_string(o.target_elements) +
      // the default target only where it is not the dense one, so that existing keys stay valid
      (o.default_elements != kDefaultPreparedElements ? "/" + std::to_string(o.default_elements) : std::string()) + "|" +
      number_text(o.edge_length) + "|" + number_text(o.graded_options.inside_edge_length));
  std::ostringstream key;
  key << std::hex << h;
  return key.str();
}

}  // namespace

TriangleMesh prepare_in_scene(const JsonReader& p, const TriangleMesh& raw, double graded_inside_edge, bool outer_scale,
                              Index default_elements, std::string& source) {
  const MeshPreparationOptions options = read_preparation_options(p, graded_inside_edge, outer_scale, default_elements);
  const std::filesystem::path dir = cache_directory();
  const std::string key = dir.empty() ? std::string() : cache_key(source, options);
  std::error_code ec;
  if (!dir.empty() && std::filesystem::exists(dir / (key + ".obj"), ec) && std::filesystem::exists(dir / (key + ".txt"), ec)) {
    try {
      TriangleMesh cached = read_obj((dir / (key + ".obj")).string());
      std::ifstream note(dir / (key + ".txt"));
      std::string summary;
      std::getline(note, summary);
      source += summary + " [cached: " + (dir / (key + ".obj")).string() + "]";
      return cached;
    } catch (const Error&) {}  // unreadable: prepare again below and overwrite it
  }
  PreparedMesh prepared;
  try {
    prepared = prepare_mesh(raw, options);
  } catch (const InvalidArgumentError& e) { p.fail(e.what()); } catch (const InvalidMeshError& e) {
    p.fail(std::string("cannot make a body of '") + source + "': " + e.what());
  } catch (const ResourceError&) { throw; } catch (const Error& e) {
    p.fail(e.what());
  }
  const MeshPreparationReport& r = prepared.report;
  const std::string summary = ", prepared (" + std::to_string(r.defects.total()) + " defects" + (r.rebuilt ? ", rebuilt" : "") + ", " +
                              std::to_string(r.elements) + " elements, Hausdorff " + general_text(100.0 * r.hausdorff_relative, 2) +
                              " % of the size)";
  source += summary;
  for (const std::string& w : r.warnings) p.warn(w);
  if (!dir.empty() && r.warnings.empty()) {  // a warned-about result is prepared (and warned) again each time
    try {
      std::filesystem::create_directories(dir, ec);
      const std::filesystem::path tmp = dir / (key + ".obj." + std::to_string(::getpid()) + ".tmp");  // one per process
      write_obj(tmp.string(), prepared.mesh);
      std::ofstream(dir / (key + ".txt")) << summary << "\n";
      std::filesystem::rename(tmp, dir / (key + ".obj"), ec);
    } catch (const Error&) {}
  }
  return std::move(prepared.mesh);
}

}  // namespace bemsurg::io
