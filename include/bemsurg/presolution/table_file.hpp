// bemsurg/presolution/table_file.hpp: saving and loading a Green's-function table (docs/design.md §6),
// so the one-time precomputation (minutes at large n) is paid once per scene.
//
// Binary, little-endian as written by this machine. Header: magic "BEMSGTBL", format version,
// library version, then the key: mesh hash, boundary-condition hash, quadrature hash, element
// count, material (E, nu, rho), gravity, backend (0 dense, 1 hierarchical) and its compression
// tolerance (format 2); then region, base kinds, base state and the columns;
// last a 64-bit FNV-1a checksum of everything before it. A stale file (its key differs from the
// scene's) or a corrupt one (checksum, size, magic) is rejected with IoError saying which,
// never used: a silently wrong table gives silently wrong forces (cf. SOFA issue 1809).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "bemsurg/presolution/greens_table.hpp"

namespace bemsurg {

/// Writes the table; throws IoError when the file cannot be written.
void save_greens_table(const std::string& path, const GreensTable& table);

/// Reads a table and checks it against `expected` (make_greens_table_key of the scene at hand).
/// Throws IoError naming the path and the reason: unreadable, not a table file, another
/// format or library version, corrupt (checksum or truncation), or stale (which key differs).
GreensTable load_greens_table(const std::string& path, const GreensTableKey& expected);

/// As above, and the table's region must be `expected_region` (GreensTableOptions::region of the
/// table the caller would compute; empty: every free element): a table for other columns is
/// stale too (IoError), since a tool landing outside its region would feel part of its contact.
GreensTable load_greens_table(const std::string& path, const GreensTableKey& expected, const std::vector<Index>& expected_region);

/// How load_or_compute_greens_table treats its file.
/// \ingroup presolution
struct TableCacheOptions {
  /// Compute even when a matching file exists: the table will be updated after cuts, which needs the
  /// factorisation a file does not keep.
  bool for_cuts = false;
  /// With for_cuts on the dense backend: keep A*^-1 instead of its LU (GreensTableOptions::explicit_inverse),
  /// for work that cuts in two phases (sessions, the viewer), whose first response then reads rows of it.
  bool explicit_inverse = false;
  /// Compute even when a matching file exists, and replace it (`bemsurg table`: the file is the product).
  bool recompute = false;
  /// Save a computed table to the file (written to a private name and renamed into place, so processes that
  /// compute the same table at once never read a half-written file).
  bool save = true;
  /// The backend the table is computed on (the scene's solver method) and its compression tolerance:
  /// part of the key a file must match, so a compressed table never loads in place of a dense one.
  SolverBackend backend = SolverBackend::Dense;
  double compression_tolerance = 0.0;
  /// Computes the table when no file is read (its third argument: for_cuts, keep the factorisation);
  /// null: GreensTable::compute (dense). Another backend needs its own:
  /// compute_greens_table_hierarchical (presolution/hierarchical_table.hpp, in the optional library
  /// bemsurg::hmatrix, which the header-only core does not link). With for_cuts, a table it returns
  /// without a factorisation is refused (SolverError).
  std::function<GreensTable(const ElastostaticProblem&, const std::vector<Index>&, bool for_cuts)> compute;
};

/// What load_or_compute_greens_table did: the table, whether it came from the file, and what a program should tell
/// its user (a stale or corrupt file recomputed, a file left unread because of cuts).
/// \ingroup presolution
struct CachedGreensTable {
  GreensTable table;
  bool loaded_from_file = false;
  std::vector<std::string> warnings;  // e.g. "FILE: stale (...); recomputed"
  std::vector<std::string> notes;     // e.g. the file was not read because the table will be cut
};

/// The one load-or-compute of a problem's table on `region` (empty: every free element), used by the command line,
/// sessions, the viewer and the tests: with `path` empty the table is computed; with a file there whose key and
/// region match, it is read (unless options.for_cuts); a stale or corrupt file is recomputed and replaced (with a
/// warning saying why); a computed table is saved to `path` when options.save.
CachedGreensTable load_or_compute_greens_table(const ElastostaticProblem& problem, const std::vector<Index>& region,
                                               const std::string& path, const TableCacheOptions& options = {});

}  // namespace bemsurg
