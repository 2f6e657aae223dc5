# CTest test of the package (cmake -P): installs the build tree into a fresh prefix, checks the installed files and
# `rayaccel --version`, then configures, builds and runs examples/consumer/main.cpp three ways: find_package (-O3,
# with Embree and assimp hidden from it: a consumer needs neither) and add_subdirectory (-O0, unity build, library
# included), both with -ffast-math -ffp-contract=fast and the CLI's hits to match bit for bit on rays aimed at
# edges, and pkg-config's flags alone against the shared library (run through the rpath README shows; also the C
# API's example, examples/capi/main.c, compiled as C11). No consumer links Embree or gets RAYACCEL_HAVE_EMBREE;
# the components load on request (tests/package/components). Also checks that
# the README shows the consumer's code.
cmake_minimum_required(VERSION 3.21)
foreach(var SOURCE_DIR BUILD_DIR WORK_DIR GENERATOR CXX LIBDIR VERSION COMPONENTS)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "consumers.cmake: -D${var}=... is missing")
  endif()
endforeach()

function(run)
  string(REPLACE ";" " " shown "${ARGN}")
  message(STATUS "run: ${shown}")
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${shown}")
  endif()
endfunction()

# Fails naming `what` when the dynamic section of `binary` lists Embree or assimp.
function(check_needs_neither binary what)
  execute_process(COMMAND readelf -d ${binary} OUTPUT_VARIABLE dynamic RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "readelf -d ${binary} failed (${rc})")
  endif()
  if(dynamic MATCHES "embree")
    message(FATAL_ERROR "${what} needs Embree:\n${dynamic}")
  endif()
  if(what MATCHES "consumer" AND dynamic MATCHES "assimp")
    message(FATAL_ERROR "${what} needs assimp:\n${dynamic}")
  endif()
endfunction()

set(consumer_source ${SOURCE_DIR}/examples/consumer/main.cpp)
# With FMA instructions allowed, -ffp-contract=fast really fuses products (x86-64's baseline has no FMA).
set(fast_math "-ffast-math -ffp-contract=fast")
file(READ /proc/cpuinfo cpuinfo)
if(cpuinfo MATCHES " fma ")
  string(APPEND fast_math " -mfma")
endif()

# The README's "Use it from your project" code is the consumer's, between its README markers.
file(READ ${consumer_source} source)
string(FIND "${source}" "  // README: begin\n" begin)
string(FIND "${source}" "  // README: end\n" end)
if(begin EQUAL -1 OR end EQUAL -1)
  message(FATAL_ERROR "no README markers in ${consumer_source}")
endif()
string(LENGTH "  // README: begin\n" marker_length)
math(EXPR begin "${begin} + ${marker_length}")
math(EXPR length "${end} - ${begin}")
string(SUBSTRING "${source}" ${begin} ${length} snippet)
string(REPLACE "\n  " "\n" snippet "\n${snippet}")
string(SUBSTRING "${snippet}" 1 -1 snippet)
file(READ ${SOURCE_DIR}/README.md readme)
string(FIND "${readme}" "${snippet}" found)
if(found EQUAL -1)
  message(FATAL_ERROR "README.md does not show the consumer's code verbatim; it should contain:\n${snippet}")
endif()

# Fresh every run, except the add_subdirectory build, which only recompiles what changed since the last run.
set(prefix ${WORK_DIR}/prefix)
file(REMOVE_RECURSE ${prefix} ${WORK_DIR}/find_package ${WORK_DIR}/pkg_config)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(file include/rayaccel/version.h include/rayaccel/accel/registry.h include/rayaccel/rayaccel_c.h
             ${LIBDIR}/librayaccel.a
             ${LIBDIR}/librayaccel.so ${LIBDIR}/cmake/rayaccel/rayaccelConfig.cmake
             ${LIBDIR}/cmake/rayaccel/rayaccelConfigVersion.cmake ${LIBDIR}/pkgconfig/rayaccel.pc bin/rayaccel)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "cmake --install did not install ${file}")
  endif()
endforeach()
check_needs_neither(${prefix}/${LIBDIR}/librayaccel.so "the installed librayaccel.so")
set(cli ${prefix}/bin/rayaccel)
execute_process(COMMAND ${cli} --version OUTPUT_VARIABLE version_output RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT version_output STREQUAL "rayaccel ${VERSION}\n")
  message(FATAL_ERROR "rayaccel --version exited ${rc} and printed '${version_output}', not 'rayaccel ${VERSION}'")
endif()

# 1. find_package against the installed prefix, as a project that has neither Embree nor assimp would.
set(dir ${WORK_DIR}/find_package)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/consumer -B ${dir} -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS=${fast_math} -O3"
    -DCMAKE_DISABLE_FIND_PACKAGE_embree=TRUE -DCMAKE_DISABLE_FIND_PACKAGE_assimp=TRUE
    -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
run(${CMAKE_COMMAND} --build ${dir})
file(READ ${dir}/compile_commands.json commands)
if(commands MATCHES "RAYACCEL_HAVE_EMBREE")
  message(FATAL_ERROR "RAYACCEL_HAVE_EMBREE reached the find_package consumer's flags:\n${commands}")
endif()
check_needs_neither(${dir}/consumer "the find_package consumer (static)")
run(${dir}/consumer ${cli} ${dir})

# The components: each loads its targets on request, one not built is a clear error (configure only).
foreach(case "${COMPONENTS}" "no_such_component")
  set(dir ${WORK_DIR}/components)
  file(REMOVE_RECURSE ${dir})
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/components -B ${dir} -G ${GENERATOR}
                          -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_PREFIX_PATH=${prefix} "-DCOMPONENTS=${case}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(case STREQUAL "no_such_component")
    if(rc EQUAL 0 OR NOT out MATCHES "rayaccel has no component 'no_such_component'")
      message(FATAL_ERROR "find_package(rayaccel COMPONENTS no_such_component) gave (${rc}):\n${out}")
    endif()
  elseif(NOT rc EQUAL 0)
    message(FATAL_ERROR "find_package(rayaccel COMPONENTS ${case}) failed (${rc}):\n${out}")
  endif()
endforeach()

# 2. pkg-config, by hand: the flags it prints (the C++ standard included) and nothing else, linked against the
#    shared library with README's rpath, so the program starts without LD_LIBRARY_PATH.
find_program(PKG_CONFIG pkg-config REQUIRED)
set(dir ${WORK_DIR}/pkg_config)
file(MAKE_DIRECTORY ${dir})
set(ENV{PKG_CONFIG_PATH} ${prefix}/${LIBDIR}/pkgconfig)
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs rayaccel OUTPUT_VARIABLE flags RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config --cflags --libs rayaccel failed (${rc})")
endif()
if(NOT flags MATCHES "-std=c\\+\\+20" OR flags MATCHES "EMBREE|embree")
  message(FATAL_ERROR "pkg-config --cflags --libs rayaccel: '${flags}' (-std=c++20 expected, Embree not)")
endif()
execute_process(COMMAND ${PKG_CONFIG} --variable=libdir rayaccel OUTPUT_VARIABLE pc_libdir
                OUTPUT_STRIP_TRAILING_WHITESPACE)
separate_arguments(flags UNIX_COMMAND "${flags}")
run(${CXX} -O2 ${consumer_source} ${flags} -Wl,-rpath,${pc_libdir} -o ${dir}/consumer)
execute_process(COMMAND readelf -d ${dir}/consumer OUTPUT_VARIABLE dynamic)
if(NOT dynamic MATCHES "librayaccel\\.so")
  message(FATAL_ERROR "the pkg-config consumer did not link the shared library:\n${dynamic}")
endif()
check_needs_neither(${dir}/consumer "the pkg-config consumer (shared)")
run(${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH ${dir}/consumer ${cli} ${dir})
# 2b. The C API from a C compiler through the same flags: the README's C example (examples/capi/main.c) as C11.
find_program(C_COMPILER NAMES cc gcc REQUIRED)
#     The .pc's -std=c++20 is for C++ consumers: a C compiler takes the rest.
set(c_flags ${flags})
list(FILTER c_flags EXCLUDE REGEX "^-std=")
run(${C_COMPILER} -std=c11 -O2 ${SOURCE_DIR}/examples/capi/main.c ${c_flags} -Wl,-rpath,${pc_libdir} -o ${dir}/c_consumer)
run(${CMAKE_COMMAND} -E env --unset=LD_LIBRARY_PATH ${dir}/c_consumer)

# 3. add_subdirectory of the source tree, library-only, no build type given: the library is compiled at -O0 under
#    the consumer's -ffast-math -ffp-contract=fast, and must still give the CLI's bits. The consumer builds with
#    CMAKE_UNITY_BUILD=ON, which checks that the library compiles as a unity build too and costs CI's two cores far
#    less time than compiling its sources one by one.
set(dir ${WORK_DIR}/add_subdirectory)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/add_subdirectory -B ${dir} -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX} -DRAYACCEL_SOURCE_DIR=${SOURCE_DIR} -DCMAKE_CXX_FLAGS=${fast_math}
    -DCMAKE_UNITY_BUILD=ON)
run(${CMAKE_COMMAND} --build ${dir})
run(${dir}/consumer ${cli} ${dir})
