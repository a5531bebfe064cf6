# FindBemsurgGmsh: Debian's libgmsh-dev (Gmsh 4.8) ships gmsh.h and libgmsh.so but no CMake config.
# Defines BemsurgGmsh::Gmsh. Used only by the graded remesher (src/meshing/graded_remesher.cpp).
include(FindPackageHandleStandardArgs)
find_path(BemsurgGmsh_INCLUDE_DIR gmsh.h)
find_library(BemsurgGmsh_LIBRARY NAMES gmsh)
find_package_handle_standard_args(BemsurgGmsh REQUIRED_VARS BemsurgGmsh_LIBRARY BemsurgGmsh_INCLUDE_DIR)
if(BemsurgGmsh_FOUND AND NOT TARGET BemsurgGmsh::Gmsh)
  add_library(BemsurgGmsh::Gmsh INTERFACE IMPORTED)
  set_target_properties(BemsurgGmsh::Gmsh PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${BemsurgGmsh_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${BemsurgGmsh_LIBRARY}")
endif()
# The name the remesher dlopens: the library's soname (libgmsh.so.4.8, from the runtime package),
# else the path found (the -dev package's link).
if(BemsurgGmsh_FOUND AND NOT BemsurgGmsh_RUNTIME_NAME)
  set(BemsurgGmsh_RUNTIME_NAME "${BemsurgGmsh_LIBRARY}")
  find_program(BemsurgGmsh_OBJDUMP NAMES objdump)
  mark_as_advanced(BemsurgGmsh_OBJDUMP)
  if(BemsurgGmsh_OBJDUMP)
    execute_process(COMMAND "${BemsurgGmsh_OBJDUMP}" -p "${BemsurgGmsh_LIBRARY}" OUTPUT_VARIABLE _bemsurg_gmsh_headers ERROR_QUIET)
    if(_bemsurg_gmsh_headers MATCHES "SONAME +([^ \n]+)")
      set(BemsurgGmsh_RUNTIME_NAME "${CMAKE_MATCH_1}")
    endif()
  endif()
endif()

