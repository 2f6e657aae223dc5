# Warnings for the project's own targets, and floating-point rules the kernels depend on.
add_library(rayaccel_warnings INTERFACE)
target_compile_options(rayaccel_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wno-unused-parameter)
# No fused multiply-add contraction: the watertight triangle test relies on edge functions of a shared edge being
# exact negatives of each other, which holds only when every product is rounded on its own. -fno-fast-math first:
# under add_subdirectory a parent's CMAKE_CXX_FLAGS (-ffast-math, -ffp-contract=fast) come before these and lose.
# Linked PRIVATE only, never part of what a consumer's own files are compiled with.
add_library(rayaccel_fp INTERFACE)
target_compile_options(rayaccel_fp INTERFACE -fno-fast-math -ffp-contract=off -fno-math-errno)
