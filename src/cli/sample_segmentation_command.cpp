// `bemsurg sample-segmentation liver|kidney -o OUT.stl`: writes an organ-like surface as a
// segmentation tool would export it (docs/cli.md, docs/organs.md): an implicit organ
// (mesh/organ_shapes.hpp) sampled by marching tetrahedra (mesh/implicit_surface.hpp) at the cell
// that gives about the requested number of triangles, then made defective the way real exports
// are (mesh/mesh_defects.hpp: segmentation_like) unless --clean, in millimetres unless --units m.
// The inputs of the mesh repair's tests, benchmark and CI are generated with it, not committed.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <string>

#include "bemsurg/meshing/implicit_surface.hpp"
#include "bemsurg/meshing/mesh_defects.hpp"
#include "bemsurg/meshing/mesh_io.hpp"
#include "bemsurg/meshing/organ_shapes.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/timing.hpp"
#include "commands.hpp"

namespace {

constexpr const char* kSampleUsage =
    "usage: bemsurg sample-segmentation liver|kidney -o OUT.stl [--triangles N] [--clean] [--units mm|m] [--seed S]\n"
    "\n"
    "Writes an organ-like surface as a segmentation tool exports it: an implicit liver (about\n"
    "200 x 150 x 90 mm) or kidney (about 60 x 40 x 110 mm) sampled by marching tetrahedra into about\n"
    "N triangles, with a realistic mix of defects (a self-intersection, a non-manifold fin, a small\n"
    "hole, a flipped patch, zero-area faces, a disjoint speck) unless --clean, in millimetres unless\n"
    "--units m. The format follows the extension: .stl (binary), .obj, .off, .ply (ASCII), .vtk.\n"
    "The same arguments write the same file byte for byte. See docs/organs.md.\n";

struct SampleOptions {
  std::string organ;
  std::string output;
  long long triangles = 100000;
  bool clean = false;
  std::string units = "mm";
  long long seed = 1;
  bool quiet = false;
};

}  // namespace

int run_sample_segmentation(int argc, char** argv) {
  using namespace bemsurg;
  SampleOptions o;
  cli::OptionParser parser("sample-segmentation", kSampleUsage);
  parser.positional("ORGAN", o.organ, "one organ per run: liver or kidney").required();
  parser.value("-o, --output", "OUT", o.output, "the mesh file to write (.stl, .obj, .off, .ply, .vtk)").required();
  parser.value("--triangles", "N", o.triangles, "about this many triangles (within a few per cent)").between(1000, 5000000);
  parser.flag("--clean", o.clean, "no defects: a closed, outward, valid surface");
  parser.value("--units", "mm|m", o.units, "unit of the written coordinates");
  parser.value("--seed", "S", o.seed, "where the defects go (the same seed, the same file)").at_least(0);
  parser.flag("-q, --quiet", o.quiet, "print nothing but errors");
  if (!parser.parse(argc, argv)) {
    std::cout << parser.help();
    return 0;
  }
  if (o.organ != "liver" && o.organ != "kidney")
    throw cli::UsageError("sample-segmentation: unknown organ '" + o.organ + "' (known: liver, kidney)");
  if (o.units != "mm" && o.units != "m") throw cli::UsageError("sample-segmentation: --units: expected mm or m, got '" + o.units + "'");
  std::string ext = std::filesystem::path(o.output).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext != ".stl" && ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".vtk")
    throw cli::UsageError("sample-segmentation: --output: unknown mesh file extension '" + ext + "' (known: .stl, .obj, .off, .ply, .vtk)");

  const SteadyClock::time_point start = SteadyClock::now();
  const OrganShape organ = organ_shape(o.organ);
  const double cell = cell_size_for_triangle_count(organ.signed_function, organ.box_lo, organ.box_hi, o.triangles);
  TriangleMesh mesh = sample_implicit_surface(organ.signed_function, organ.box_lo, organ.box_hi, cell);
  const double scale = o.units == "mm" ? 1000.0 : 1.0;
  if (o.clean) {
    if (scale != 1.0) mesh = scale_mesh(mesh, scale);
  } else {
    SegmentationDefects defects;
    defects.scale = scale;
    // A hole of about the same size (a rim of ~30 mm) at every triangle count: 12 edges at 100,000
    // triangles, fewer on coarser samples, whose edges are longer (benchmarks/bench_prepare.cpp).
    defects.hole_boundary_edges =
        std::max<Index>(4, static_cast<Index>(std::lround(12.0 * std::sqrt(static_cast<double>(o.triangles) / 100000.0))));
    mesh = segmentation_like(mesh, static_cast<std::uint64_t>(o.seed), defects);
  }
  write_mesh(o.output, mesh);
  if (!o.quiet)
    std::cout << "bemsurg sample-segmentation: " << o.organ << ", " << mesh.num_elements() << " triangles, " << mesh.num_vertices()
              << " vertices, grid cell " << general_text(cell * scale, 3) << " " << o.units << ", "
              << (o.clean ? "clean" : "with defects (seed " + std::to_string(o.seed) + ")") << "; wrote " << o.output << " in "
              << fixed_text(seconds_between(start, SteadyClock::now()), 2) << " s\n";
  // Where such an organ is held and operated on, in metres (a prepared mesh's unit), for scenes.
  if (!o.quiet) {
    const auto where = [](const Vec3& c, double r) {
      return "sphere centre [" + general_text(c(0), 4) + ", " + general_text(c(1), 4) + ", " + general_text(c(2), 4) + "] m, radius " +
             general_text(r, 3) + " m";
    };
    std::cout << "  support (ligaments): " << where(organ.support_center, organ.support_radius) << "\n"
              << "  operating region:    " << where(organ.operating_center, organ.operating_radius) << "\n";
  }
  return 0;
}
