# Warnings for the project's own targets, and floating-point rules the kernels depend on.
add_library(rayaccel_warnings INTERFACE)
target_compile_options(rayaccel_warnings INTERFACE -Wall -Wextra -Wpedantic -Wshadow -Wno-unused-parameter)
# No fused multiply-add contraction: the watertight triangle test relies on edge functions of a shared edge being
# exact negatives of each other, which holds only when every product is rounded on its own.
add_library(rayaccel_fp INTERFACE)
target_compile_options(rayaccel_fp INTERFACE -ffp-contract=off -fno-math-errno)
