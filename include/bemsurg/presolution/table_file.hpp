// bemsurg/presolution/table_file.hpp: saving and loading a Green's-function table (docs/design.md §6),
// so the one-time precomputation (minutes at large n) is paid once per scene.
//
// Binary, little-endian as written by this machine. Header: magic "BEMSGTBL", format version,
// library version, then the key: mesh hash, boundary-condition hash, quadrature hash, element
// count, material (E, nu, rho), gravity; then region, base kinds, base state and the columns;
// last a 64-bit FNV-1a checksum of everything before it. A stale file (its key differs from the
// scene's) or a corrupt one (checksum, size, magic) is rejected with IoError saying which,
// never used: a silently wrong table gives silently wrong forces (cf. SOFA issue 1809).
#pragma once

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

}  // namespace bemsurg
