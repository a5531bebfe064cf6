# FindBemsurgScalapack: ScaLAPACK built for Open MPI (Debian's libscalapack-openmpi-dev). Debian 12's
# scalapack-config.cmake names a library path that does not exist (/usr/lib/libscalapack-openmpi.so.2.2.1,
# not under the multiarch directory), so the library is found by name. Defines BemsurgScalapack::ScaLAPACK
# (the library, with LAPACK and BLAS after it). Used only by bemsurg::distributed (src/distributed/).
include(FindPackageHandleStandardArgs)
find_library(BemsurgScalapack_LIBRARY NAMES scalapack-openmpi scalapack)
find_package(LAPACK QUIET)
find_package_handle_standard_args(BemsurgScalapack REQUIRED_VARS BemsurgScalapack_LIBRARY LAPACK_FOUND)
if(BemsurgScalapack_FOUND AND NOT TARGET BemsurgScalapack::ScaLAPACK)
  add_library(BemsurgScalapack::ScaLAPACK INTERFACE IMPORTED)
  set_target_properties(BemsurgScalapack::ScaLAPACK PROPERTIES INTERFACE_LINK_LIBRARIES "${BemsurgScalapack_LIBRARY};${LAPACK_LIBRARIES}")
endif()
