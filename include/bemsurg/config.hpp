// bemsurg/config.hpp: how bemsurg's function definitions are compiled (docs/development.md,
// "How the build is kept small"; docs/design.md §1).
//
// Header-only (bemsurg::core, the default for a translation unit that defines nothing): every
// declaring header includes its definitions (the impl/ header beside it), marked `inline`, and a
// program needs no compiled bemsurg.
//
// Separately compiled (bemsurg::numerics, under bemsurg::bemsurg, defines BEMSURG_SEPARATE_COMPILATION for itself and its
// users): the declaring headers stop at the declarations, and the library compiles each impl/
// header once, in the source file of the same module (src/<module>/<name>.cpp). Every program that
// links the library then parses and optimises the numerical core once instead of once per file:
// the pattern of Asio's ASIO_SEPARATE_COMPILATION and spdlog's SPDLOG_COMPILED_LIB. Templates and
// small in-class functions stay in the headers either way.
//
// A program uses one mode throughout: a translation unit built header-only and one built against
// the compiled library must not both define the same function.
#pragma once

#if defined(BEMSURG_SEPARATE_COMPILATION)
#define BEMSURG_INLINE
#else
#define BEMSURG_INLINE inline
#endif
