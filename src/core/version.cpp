// Anchors the compiled part of bemsurg::bemsurg; the library's version as linked (not as included).
#include "bemsurg/version.hpp"

namespace bemsurg {
const char* linked_version() { return BEMSURG_VERSION_STRING; }
}  // namespace bemsurg
