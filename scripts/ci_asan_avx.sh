#!/usr/bin/env bash
# CI tier: the AVX2 and AVX-512 kernels under AddressSanitizer + UndefinedBehaviorSanitizer, which the Clang tree of
# ci_asan.sh cannot check (Clang builds have the SSE kernels only). In the README's GCC tree (build, which CI has just
# built), it compiles the kernels and every structure that runs them (src/simd, src/wide, the kd-tree and the grid) once
# more with the sanitizers at -O0 (GCC's -O1 with ASan spends minutes on each structure's file; -O0 costs the tests less
# than that), and one small test executable (rayaccel_kernel_tests: the conformance tests and the wide BVH's and SIMD
# kernels' unit tests) that links them ahead of the plain library; every executable links the
# runtimes, so each heap block, wherever allocated, has ASan's red zones. It runs the conformance tier on the variants
# whose kernels are AVX: bvh_wide (the best ISA: AVX-512 where the CPU has it), bvh_wide with isa=avx2, the kd-tree and
# the grid with Triangle4 blocks (AVX2).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
[ -f build/build.ninja ] || cmake -S . -B build -G Ninja > /dev/null
cmake --build build --target rayaccel_kernel_tests
built=$(date +%s)
TIER=ci_asan_avx TESTS=build/bin/rayaccel_kernel_tests LOGS=build/logs-asan-avx
source scripts/sanitized_runs.sh
isa=sse2
grep -qw avx2 /proc/cpuinfo && isa=avx2
grep -qw avx512f /proc/cpuinfo && grep -qw avx512vl /proc/cpuinfo && grep -qw avx512dq /proc/cpuinfo &&
  grep -qw avx512bw /proc/cpuinfo && isa=avx512
echo "ci_asan_avx: this CPU's best kernels: $isa"
if [ "$isa" != avx512 ]; then echo "ci_asan_avx: warning: the AVX-512 kernels are not reached on this CPU"; fi
# The wide BVH's and SIMD kernels' unit tests: two shards.
for _ in 1 2; do echo '-Conformance*'; done | run_processes unit 2
conformance_filters bvh_wide bvh_wide_width_8_isa_avx2 kdtree_builder_sah grid_density_1_blocks_true_mailbox_false \
  grid_density_1_blocks_true_mailbox_true | run_processes conformance
end=$(date +%s)
echo "ci_asan_avx: build $((built - start)) s, tests $((end - built)) s"
