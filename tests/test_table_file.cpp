// Tests for saving and loading Green's-function tables (presolution/table_file.hpp, docs/design.md §6):
// exact round trip; stale (other mesh, material, supports) and corrupt files are rejected.
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "bemsurg/mesh/mesh_generators.hpp"
#include "bemsurg/presolution/greens_table.hpp"
#include "bemsurg/presolution/table_file.hpp"

using namespace bemsurg;

TEST_CASE("table files round-trip exactly and reject stale or corrupt files", "[contact][table-file]") {
  const TriangleMesh mesh = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), 3, 3, 3);
  const Material material{500.0, 0.35, 1000.0};
  std::vector<Index> bottom, top;
  for (Index e = 0; e < mesh.num_elements(); ++e) {
    if (mesh.normal(e).z() < -0.99) bottom.push_back(e);
    if (mesh.normal(e).z() > 0.99) top.push_back(e);
  }
  const BoundaryConditions base = supported_base_conditions(mesh.num_elements(), bottom);
  GreensTableOptions options;
  options.region = top;
  options.gravity = Vec3(0, 0, -9.81);
  const GreensTable table = GreensTable::compute(mesh, material, base, options);
  const GreensTableKey key = make_greens_table_key(mesh, material, base, options.gravity, options.quadrature);

  const std::string path = (std::filesystem::temp_directory_path() / "bemsurg_test_table.bin").string();
  save_greens_table(path, table);
  const GreensTable loaded = load_greens_table(path, key);
  CHECK(loaded.region() == table.region());
  CHECK(loaded.columns().cwiseEqual(table.columns()).all());  // bit for bit
  CHECK(loaded.base_displacement().cwiseEqual(table.base_displacement()).all());
  CHECK(loaded.base_traction().cwiseEqual(table.base_traction()).all());
  CHECK(loaded.region_slot(top[2]) == 2);

  // The region is part of the table: loaded with the region asked for, refused for another one
  // (a tool landing outside the stored columns would feel only part of its contact) and for the
  // default "every free element", which is not what this file holds.
  CHECK(load_greens_table(path, key, top).region() == top);
  std::vector<Index> fewer(top.begin(), top.end() - 1);
  CHECK_THROWS_WITH(load_greens_table(path, key, fewer),
                    Catch::Contains("stale") && Catch::Contains("different table region") && Catch::Contains("operating_region"));
  CHECK_THROWS_WITH(load_greens_table(path, key, std::vector<Index>{}), Catch::Contains("different table region"));
  {
    GreensTableOptions all_free = options;
    all_free.region.clear();
    const std::string path_all = path + ".all";
    save_greens_table(path_all, GreensTable::compute(mesh, material, base, all_free));
    const GreensTable every = load_greens_table(path_all, key, std::vector<Index>{});
    CHECK(static_cast<Index>(every.region().size()) == mesh.num_elements() - static_cast<Index>(bottom.size()));
    CHECK_THROWS_WITH(load_greens_table(path_all, key, top), Catch::Contains("different table region"));
    std::filesystem::remove(path_all);
  }

  // Stale: another material, another support, another mesh.
  Material softer = material;
  softer.young_modulus = 400.0;
  CHECK_THROWS_WITH(load_greens_table(path, make_greens_table_key(mesh, softer, base, options.gravity, options.quadrature)),
                    Catch::Contains("stale") && Catch::Contains("material"));
  BoundaryConditions other = base;
  other.prescribe_displacement(top[0], Vec3::Zero());
  CHECK_THROWS_WITH(load_greens_table(path, make_greens_table_key(mesh, material, other, options.gravity, options.quadrature)),
                    Catch::Contains("stale") && Catch::Contains("boundary conditions"));
  const TriangleMesh finer = box_mesh(Vec3(0, 0, 0), Vec3(1, 1, 1), 4, 3, 3);
  CHECK_THROWS_WITH(load_greens_table(path, make_greens_table_key(finer, material, supported_base_conditions(finer.num_elements(), {}),
                                                                  options.gravity, options.quadrature)),
                    Catch::Contains("different mesh"));

  // Corrupt: one flipped byte in the middle of the columns, then a truncated file.
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(std::filesystem::file_size(path) / 2));
    char c = 0;
    f.read(&c, 1);
    f.seekp(static_cast<std::streamoff>(std::filesystem::file_size(path) / 2));
    c = static_cast<char>(c ^ 0x10);
    f.write(&c, 1);
  }
  CHECK_THROWS_WITH(load_greens_table(path, key), Catch::Contains("corrupt") && Catch::Contains("checksum"));
  save_greens_table(path, table);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 100);
  CHECK_THROWS_AS(load_greens_table(path, key), IoError);
  {
    std::ofstream junk(path, std::ios::binary | std::ios::trunc);
    junk << "not a table at all";
  }
  CHECK_THROWS_WITH(load_greens_table(path, key), Catch::Contains("not a bemsurg table file"));
  std::filesystem::remove(path);
  CHECK_THROWS_WITH(load_greens_table(path, key), Catch::Contains("cannot open"));
}
