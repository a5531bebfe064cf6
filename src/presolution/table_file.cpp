// Implementation of bemsurg/presolution/table_file.hpp: the keyed, checksummed table file.
#include "bemsurg/presolution/table_file.hpp"

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "bemsurg/error.hpp"
#include "bemsurg/number_text.hpp"
#include "bemsurg/version.hpp"

namespace bemsurg {

namespace {
constexpr char kMagic[8] = {'B', 'E', 'M', 'S', 'G', 'T', 'B', 'L'};
constexpr std::uint32_t kFormat = 2;  // 2: the key records the backend and its compression tolerance

class Writer {
 public:
  void raw(const void* p, std::size_t n) {
    const auto* c = static_cast<const char*>(p);
    bytes_.insert(bytes_.end(), c, c + n);
  }
  template <class T>
  void pod(const T& v) {
    raw(&v, sizeof(T));
  }
  void str(const std::string& s) {
    pod<std::uint32_t>(static_cast<std::uint32_t>(s.size()));
    raw(s.data(), s.size());
  }
  std::vector<char> bytes_;
};

class Reader {
 public:
  Reader(const std::vector<char>& b, std::size_t end, const std::string& path) : b_(b), end_(end), path_(path) {}
  void raw(void* p, std::size_t n) {
    if (n > end_ - pos_) throw IoError("table file " + path_ + " is corrupt: it ends early (truncated)");
    std::memcpy(p, b_.data() + pos_, n);
    pos_ += n;
  }
  template <class T>
  T pod() {
    T v;
    raw(&v, sizeof(T));
    return v;
  }
  std::string str() {
    const auto n = pod<std::uint32_t>();
    if (n > 4096) throw IoError("table file " + path_ + " is corrupt: a string field is too long");
    std::string s(n, '\0');
    raw(s.data(), n);
    return s;
  }
  std::size_t pos() const { return pos_; }

 private:
  const std::vector<char>& b_;
  std::size_t end_;
  std::size_t pos_ = 0;
  const std::string& path_;
};
}  // namespace

/// "dense backend" or "hierarchical backend (compression tolerance 0.0001)", for the stale message.
static std::string backend_text(const GreensTableKey& k) {
  if (k.backend == SolverBackend::Dense) return "dense backend";
  return "hierarchical backend (compression tolerance " + number_text(k.compression_tolerance) + ")";
}

void save_greens_table(const std::string& path, const GreensTable& table) {
  if (table.empty()) throw InvalidArgumentError("save_greens_table: the table is empty");
  Writer w;
  w.raw(kMagic, 8);
  w.pod(kFormat);
  w.str(version_string());
  const GreensTableKey& k = table.key();
  w.pod(k.mesh_hash);
  w.pod(k.conditions_hash);
  w.pod(k.quadrature_hash);
  w.pod<std::int64_t>(k.num_elements);
  w.pod(k.material.young_modulus);
  w.pod(k.material.poisson_ratio);
  w.pod(k.material.density);
  w.raw(k.gravity.data(), 3 * sizeof(double));
  w.pod<std::uint8_t>(k.backend == SolverBackend::HMatrix ? 1 : 0);
  w.pod(k.compression_tolerance);
  w.pod<std::int64_t>(static_cast<std::int64_t>(table.region().size()));
  for (Index e : table.region()) w.pod<std::int64_t>(e);
  for (BcKind kind : table.base_kinds()) w.pod<std::uint8_t>(static_cast<std::uint8_t>(kind));
  w.raw(table.base_displacement().data(), static_cast<std::size_t>(table.base_displacement().size()) * sizeof(double));
  w.raw(table.base_traction().data(), static_cast<std::size_t>(table.base_traction().size()) * sizeof(double));
  const std::uint64_t head = fnv1a64(w.bytes_.data(), w.bytes_.size());
  const std::size_t col_bytes = static_cast<std::size_t>(table.columns().size()) * sizeof(double);
  const std::uint64_t sum = fnv1a64(table.columns().data(), col_bytes, head);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError("cannot write table file " + path);
  out.write(w.bytes_.data(), static_cast<std::streamsize>(w.bytes_.size()));
  out.write(reinterpret_cast<const char*>(table.columns().data()), static_cast<std::streamsize>(col_bytes));
  out.write(reinterpret_cast<const char*>(&sum), sizeof(sum));
  if (!out) throw IoError("writing table file " + path + " failed (disk full?)");
}

// Both overloads: `expected_region` null means the region is not checked.
static GreensTable load_checked(const std::string& path, const GreensTableKey& expected, const std::vector<Index>* expected_region) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open table file " + path);
  std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 8 + sizeof(std::uint64_t) || std::memcmp(bytes.data(), kMagic, 8) != 0)
    throw IoError("file " + path + " is not a bemsurg table file (bad magic)");
  const std::size_t end = bytes.size() - sizeof(std::uint64_t);
  std::uint64_t stored = 0;
  std::memcpy(&stored, bytes.data() + end, sizeof(stored));
  if (fnv1a64(bytes.data(), end) != stored)
    throw IoError("table file " + path + " is corrupt: its checksum does not match (recompute the table)");
  Reader r(bytes, end, path);
  char magic[8];
  r.raw(magic, 8);
  const auto format = r.pod<std::uint32_t>();
  if (format != kFormat)
    throw IoError("table file " + path + " has format " + std::to_string(format) + ", this library reads " + std::to_string(kFormat));
  const std::string version = r.str();
  if (version != version_string())
    throw IoError("table file " + path + " is stale: written by bemsurg " + version + ", this is " + version_string());
  GreensTableKey k;
  k.mesh_hash = r.pod<std::uint64_t>();
  k.conditions_hash = r.pod<std::uint64_t>();
  k.quadrature_hash = r.pod<std::uint64_t>();
  k.num_elements = static_cast<Index>(r.pod<std::int64_t>());
  k.material.young_modulus = r.pod<double>();
  k.material.poisson_ratio = r.pod<double>();
  k.material.density = r.pod<double>();
  r.raw(k.gravity.data(), 3 * sizeof(double));
  const auto backend = r.pod<std::uint8_t>();
  if (backend > 1) throw IoError("table file " + path + " is corrupt: bad backend");
  k.backend = backend == 1 ? SolverBackend::HMatrix : SolverBackend::Dense;
  k.compression_tolerance = r.pod<double>();
  const std::string stale = "table file " + path + " is stale: it was computed for ";
  if (k.mesh_hash != expected.mesh_hash || k.num_elements != expected.num_elements)
    throw IoError(stale + "a different mesh (" + std::to_string(k.num_elements) + " elements, hash " + std::to_string(k.mesh_hash) +
                  "; expected " + std::to_string(expected.num_elements) + ", hash " + std::to_string(expected.mesh_hash) + ")");
  if (k.material.young_modulus != expected.material.young_modulus || k.material.poisson_ratio != expected.material.poisson_ratio ||
      k.material.density != expected.material.density)
    throw IoError(stale + "a different material (E = " + number_text(k.material.young_modulus) +
                  ", nu = " + number_text(k.material.poisson_ratio) + ", rho = " + number_text(k.material.density) + ")");
  if (k.conditions_hash != expected.conditions_hash) throw IoError(stale + "different supports / boundary conditions");
  if (k.gravity != expected.gravity) throw IoError(stale + "a different gravity");
  if (k.quadrature_hash != expected.quadrature_hash) throw IoError(stale + "different quadrature options");
  if (k.backend != expected.backend || k.compression_tolerance != expected.compression_tolerance)
    throw IoError(stale + "the " + backend_text(k) + "; the scene asks for the " + backend_text(expected));
  const auto R = r.pod<std::int64_t>();
  if (R < 0 || R > k.num_elements) throw IoError("table file " + path + " is corrupt: bad region size");
  std::vector<Index> region(static_cast<std::size_t>(R));
  for (auto& e : region) e = static_cast<Index>(r.pod<std::int64_t>());
  const Index n = 3 * k.num_elements;
  std::vector<BcKind> kinds(static_cast<std::size_t>(n));
  for (auto& kind : kinds) {
    const auto v = r.pod<std::uint8_t>();
    if (v > 1) throw IoError("table file " + path + " is corrupt: bad boundary-condition kind");
    kind = static_cast<BcKind>(v);
  }
  if (expected_region) {
    // The region is part of what the table is: a table of other columns would make a tool that
    // lands outside them feel only part of its contact (silently wrong forces), so it is stale.
    std::vector<Index> want = *expected_region;
    if (want.empty())  // every free element, in order, as GreensTable::compute chooses
      for (Index e = 0; e < k.num_elements; ++e)
        if (BoundaryConditions::is_free_element(kinds, e)) want.push_back(e);
    if (want != region)
      throw IoError(stale + "a different table region (" + std::to_string(region.size()) + " elements; the scene asks for " +
                    std::to_string(want.size()) + ": its operating_region changed)");
  }
  Eigen::VectorXd ug(n), tg(n);
  r.raw(ug.data(), static_cast<std::size_t>(n) * sizeof(double));
  r.raw(tg.data(), static_cast<std::size_t>(n) * sizeof(double));
  Eigen::MatrixXd columns(n, 3 * R);
  r.raw(columns.data(), static_cast<std::size_t>(columns.size()) * sizeof(double));
  if (r.pos() != end) throw IoError("table file " + path + " is corrupt: unexpected trailing bytes");
  return GreensTable(k, std::move(region), std::move(ug), std::move(tg), std::move(kinds), std::move(columns));
}

GreensTable load_greens_table(const std::string& path, const GreensTableKey& expected) { return load_checked(path, expected, nullptr); }

GreensTable load_greens_table(const std::string& path, const GreensTableKey& expected, const std::vector<Index>& expected_region) {
  return load_checked(path, expected, &expected_region);
}

CachedGreensTable load_or_compute_greens_table(const ElastostaticProblem& problem, const std::vector<Index>& region,
                                               const std::string& path, const TableCacheOptions& options) {
  if (options.backend != SolverBackend::Dense && !options.compute)
    throw InvalidArgumentError("load_or_compute_greens_table: the " + std::string(to_string(options.backend)) +
                               " backend computes its table through TableCacheOptions::compute (presolution/hierarchical_table.hpp)");
  CachedGreensTable out;
  std::error_code ec;
  const bool exists = !path.empty() && std::filesystem::exists(path, ec);
  if (exists && options.for_cuts)
    out.notes.push_back("cuts will update the table, so the table is computed rather than read from " + path +
                        " (a table read from a file keeps no factorisation for the exact updates after a cut)");
  if (exists && !options.for_cuts && !options.recompute) {
    try {
      GreensTableKey key =
          make_greens_table_key(problem.mesh, problem.material, problem.boundary_conditions, problem.gravity, problem.quadrature);
      key.backend = options.backend;
      key.compression_tolerance = options.backend == SolverBackend::Dense ? 0.0 : options.compression_tolerance;
      out.table = load_greens_table(path, key, region);
      out.loaded_from_file = true;
      return out;
    } catch (const IoError& e) {  // stale or corrupt: recompute
      out.warnings.push_back(std::string(e.what()) + "; recomputing");
    }
  }
  out.table = options.compute ? options.compute(problem, region, options.for_cuts)
                              : GreensTable::compute(problem, region, 0.0, options.for_cuts && options.explicit_inverse);
  if (options.for_cuts && !out.table.has_factorization())
    throw SolverError("load_or_compute_greens_table: the " + std::string(to_string(options.backend)) +
                      " backend's table kept no factorisation, which the exact updates after a cut need");
  if (!path.empty() && options.save) {
    // A private name per process, renamed into place: rename is atomic, so a reader never sees half a file.
    const std::string temporary = path + ".tmp" + std::to_string(static_cast<long long>(::getpid()));
    save_greens_table(temporary, out.table);
    std::filesystem::rename(temporary, path, ec);
    if (ec) {
      std::filesystem::remove(temporary, ec);
      throw IoError("cannot write the table file " + path + ": " + ec.message());
    }
  }
  return out;
}

}  // namespace bemsurg
