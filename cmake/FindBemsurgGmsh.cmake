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
