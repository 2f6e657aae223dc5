# CTest test of the package (cmake -P): installs the build tree into a fresh prefix, checks the installed files and
# `rayaccel --version`, then configures, builds and runs examples/consumer/main.cpp three ways: find_package (-O3)
# and add_subdirectory (-O0, library included), both with -ffast-math -ffp-contract=fast and the CLI's hits to match
# bit for bit on rays aimed at edges, and pkg-config against the shared library (also the C API's example,
# examples/capi/main.c, compiled as C11). Also checks that the README shows
# the consumer's code.
cmake_minimum_required(VERSION 3.21)
foreach(var SOURCE_DIR BUILD_DIR WORK_DIR GENERATOR CXX LIBDIR VERSION)
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
set(cli ${prefix}/bin/rayaccel)
execute_process(COMMAND ${cli} --version OUTPUT_VARIABLE version_output RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR NOT version_output STREQUAL "rayaccel ${VERSION}\n")
  message(FATAL_ERROR "rayaccel --version exited ${rc} and printed '${version_output}', not 'rayaccel ${VERSION}'")
endif()

# 1. find_package against the installed prefix.
set(dir ${WORK_DIR}/find_package)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/consumer -B ${dir} -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX}
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS=${fast_math} -O3")
run(${CMAKE_COMMAND} --build ${dir})
run(${dir}/consumer ${cli} ${dir})

# 2. pkg-config, by hand: the flags it prints and nothing else (links the shared library).
find_program(PKG_CONFIG pkg-config REQUIRED)
set(dir ${WORK_DIR}/pkg_config)
file(MAKE_DIRECTORY ${dir})
set(ENV{PKG_CONFIG_PATH} ${prefix}/${LIBDIR}/pkgconfig)
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs rayaccel OUTPUT_VARIABLE flags RESULT_VARIABLE rc
                OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config --cflags --libs rayaccel failed (${rc})")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
run(${CXX} -std=c++20 -O2 ${consumer_source} ${flags} -o ${dir}/consumer)
execute_process(COMMAND readelf -d ${dir}/consumer OUTPUT_VARIABLE dynamic)
if(NOT dynamic MATCHES "librayaccel\\.so")
  message(FATAL_ERROR "the pkg-config consumer did not link the shared library:\n${dynamic}")
endif()
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/${LIBDIR} ${dir}/consumer ${cli} ${dir})
# 2b. The C API from a C compiler through the same flags: the README's C example (examples/capi/main.c) as C11.
find_program(C_COMPILER NAMES cc gcc REQUIRED)
run(${C_COMPILER} -std=c11 -O2 ${SOURCE_DIR}/examples/capi/main.c ${flags} -o ${dir}/c_consumer)
run(${CMAKE_COMMAND} -E env LD_LIBRARY_PATH=${prefix}/${LIBDIR} ${dir}/c_consumer)

# 3. add_subdirectory of the source tree, library-only, no build type given: the library is compiled at -O0 under
#    the consumer's -ffast-math -ffp-contract=fast, and must still give the CLI's bits.
set(dir ${WORK_DIR}/add_subdirectory)
run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/tests/package/add_subdirectory -B ${dir} -G ${GENERATOR}
    -DCMAKE_CXX_COMPILER=${CXX} -DRAYACCEL_SOURCE_DIR=${SOURCE_DIR} -DCMAKE_CXX_FLAGS=${fast_math})
run(${CMAKE_COMMAND} --build ${dir})
run(${dir}/consumer ${cli} ${dir})
