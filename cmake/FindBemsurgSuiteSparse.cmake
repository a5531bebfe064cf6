# FindBemsurgSuiteSparse: Debian's SuiteSparse 5.x ships neither a CMake config nor a .pc file.
# Defines BemsurgSuiteSparse::SuiteSparse (UMFPACK + CHOLMOD and their ordering libraries).
include(FindPackageHandleStandardArgs)
find_path(BemsurgSuiteSparse_INCLUDE_DIR umfpack.h PATH_SUFFIXES suitesparse)
set(_bemsurg_ss_libs umfpack cholmod amd colamd camd ccolamd suitesparseconfig)
set(BemsurgSuiteSparse_LIBRARIES)
set(_bemsurg_ss_required BemsurgSuiteSparse_INCLUDE_DIR)
foreach(_lib IN LISTS _bemsurg_ss_libs)
  find_library(BemsurgSuiteSparse_${_lib}_LIBRARY NAMES ${_lib})
  list(APPEND BemsurgSuiteSparse_LIBRARIES ${BemsurgSuiteSparse_${_lib}_LIBRARY})
  list(APPEND _bemsurg_ss_required BemsurgSuiteSparse_${_lib}_LIBRARY)
endforeach()
find_package_handle_standard_args(BemsurgSuiteSparse REQUIRED_VARS ${_bemsurg_ss_required})
if(BemsurgSuiteSparse_FOUND AND NOT TARGET BemsurgSuiteSparse::SuiteSparse)
  add_library(BemsurgSuiteSparse::SuiteSparse INTERFACE IMPORTED)
  set_target_properties(BemsurgSuiteSparse::SuiteSparse PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${BemsurgSuiteSparse_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${BemsurgSuiteSparse_LIBRARIES}")
endif()
