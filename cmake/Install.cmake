# cmake --install: headers (with the generated version.h), the static and shared libraries, the CLI (installed by
# apps/rayaccel), the CMake package (rayaccelConfig.cmake, rayaccelConfigVersion.cmake, exported targets
# rayaccel::rayaccel and rayaccel::rayaccel_shared, and per component rayaccel::mesh_import and rayaccel::compare in
# export sets of their own, loaded only when asked for) and rayaccel.pc. Everything is relocatable: --prefix may
# differ from CMAKE_INSTALL_PREFIX.
include(CMakePackageConfigHelpers)
set(RAYACCEL_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/rayaccel)

install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/rayaccel DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${RAYACCEL_GENERATED_INCLUDE_DIR}/rayaccel/version.h DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rayaccel)
set(RAYACCEL_INSTALLED_LIBRARIES rayaccel)
if(RAYACCEL_BUILD_SHARED)
  list(APPEND RAYACCEL_INSTALLED_LIBRARIES rayaccel_shared)
endif()
install(TARGETS ${RAYACCEL_INSTALLED_LIBRARIES} EXPORT rayaccelTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(EXPORT rayaccelTargets NAMESPACE rayaccel:: DESTINATION ${RAYACCEL_CMAKE_DIR})
# Components: mesh_import (assimp) and compare (Embree), so that a consumer of the libraries needs neither.
set(RAYACCEL_COMPONENTS)
foreach(component mesh_import compare)
  if(TARGET rayaccel_${component})
    list(APPEND RAYACCEL_COMPONENTS ${component})
    install(TARGETS rayaccel_${component} EXPORT rayaccel_${component}Targets
      ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
    install(EXPORT rayaccel_${component}Targets NAMESPACE rayaccel:: DESTINATION ${RAYACCEL_CMAKE_DIR})
  endif()
endforeach()

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/rayaccelConfig.cmake.in
  ${PROJECT_BINARY_DIR}/rayaccelConfig.cmake INSTALL_DESTINATION ${RAYACCEL_CMAKE_DIR})
# 0.x: a new minor version may break the API, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rayaccelConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/rayaccelConfig.cmake ${PROJECT_BINARY_DIR}/rayaccelConfigVersion.cmake
  DESTINATION ${RAYACCEL_CMAKE_DIR})

# pkg-config: the prefix is found from the .pc file's own place, so the file stays right under any --prefix.
file(RELATIVE_PATH RAYACCEL_PC_TO_PREFIX /prefix/${CMAKE_INSTALL_LIBDIR}/pkgconfig /prefix)
# The headers need C++20, so Cflags carry -std=c++20; assimp is only for `pkg-config --static` (mesh import).
set(RAYACCEL_PC_REQUIRES_PRIVATE "")
if(RAYACCEL_WITH_ASSIMP)
  string(APPEND RAYACCEL_PC_REQUIRES_PRIVATE "assimp")
endif()
configure_file(${CMAKE_CURRENT_LIST_DIR}/rayaccel.pc.in ${PROJECT_BINARY_DIR}/rayaccel.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/rayaccel.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
