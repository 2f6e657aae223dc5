# The generated header rayaccel/version.h: version numbers and the optional parts this build has.
set(RAYACCEL_HAVE_MESH_IMPORT 0)
if(RAYACCEL_WITH_ASSIMP)
  set(RAYACCEL_HAVE_MESH_IMPORT 1)
endif()
set(RAYACCEL_GENERATED_INCLUDE_DIR ${PROJECT_BINARY_DIR}/generated/include)
configure_file(${CMAKE_CURRENT_LIST_DIR}/version.h.in ${RAYACCEL_GENERATED_INCLUDE_DIR}/rayaccel/version.h @ONLY)
