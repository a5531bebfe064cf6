# FindBemsurgGmsh: Debian's libgmsh-dev (Gmsh 4.8) ships gmshc.h (the C API) and libgmsh.so but no
# CMake config. Sets BemsurgGmsh_INCLUDE_DIR and BemsurgGmsh_RUNTIME_NAME for the graded remesher
# (src/meshing/graded_remesher.cpp), which opens the library when a remesh first needs it.
include(FindPackageHandleStandardArgs)
find_path(BemsurgGmsh_INCLUDE_DIR gmshc.h)
find_library(BemsurgGmsh_LIBRARY NAMES gmsh)
find_package_handle_standard_args(BemsurgGmsh REQUIRED_VARS BemsurgGmsh_LIBRARY BemsurgGmsh_INCLUDE_DIR)
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

