#!/usr/bin/env bash
# CI tier: AddressSanitizer + UndefinedBehaviorSanitizer over the unit tier and the conformance tier for one variant
# per structure and bounding-volume family (below), in build-asan. GCC, so that the AVX2 and AVX-512 kernels CI's CPU
# runs are the ones checked (the Clang fuzz tier has the SSE kernels only); -O1, as the sanitizers' authors advise:
# it compiles in about half the time of -O3 and runs fast enough. Builds only the test executable and the CLI the
# tests run; the slow tier and the package test stay out. The tests run in a few processes (shards of the GoogleTest
# binary, two at a time) rather than one per test: under ASan each process costs about 0.2 s to start.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG" \
  -DRAYACCEL_SANITIZE=ON -DRAYACCEL_BUILD_BENCH=OFF -DRAYACCEL_BUILD_PYTHON=OFF -DRAYACCEL_BUILD_SHARED=OFF \
  -DRAYACCEL_INSTALL=OFF
cmake --build build-asan --target rayaccel_tests rayaccel_cli
built=$(date +%s)
# halt_on_error: the first report fails the run; detect_leaks stays on.
export ASAN_OPTIONS=halt_on_error=1:abort_on_error=1:detect_stack_use_after_return=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
# Conformance: one variant per structure and bounding-volume family (15 of the variants the normal tier runs).
variants=(brute_force grid grid_density_1_blocks_true_mailbox_false grid2 kdtree_builder_sah octree bsp
          bvh_bv_aabb_builder_binned bvh_bv_sphere_builder_binned bvh_bv_obb_builder_sbvh bvh_bv_kdop18_builder_ploc
          bvh_bv_hull_builder_binned bvh_bv_capsule_builder_lbvh bvh_wide bvh_wide_width_4)
conformance=$(printf 'Conformance*/*/%s:' "${variants[@]}")
mkdir -p build-asan/logs
# run_shards NAME FILTER SHARDS: the tests FILTER selects, in SHARDS processes, two at a time; a failing shard's
# log is printed whole.
run_shards() {
  local name=$1 filter=$2 shards=$3
  seq 0 $((shards - 1)) | xargs -P 2 -I{} sh -c \
    "GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX={} build-asan/bin/rayaccel_tests --gtest_filter='$filter' \
       > build-asan/logs/$name-{}.log 2>&1 || { cat build-asan/logs/$name-{}.log; echo 'ci_asan: $name shard {} failed'; exit 255; }"
  grep -h '^\[  PASSED  \]' build-asan/logs/"$name"-*.log | awk -v n="$name" '{s += $4} END {print "ci_asan: " n ": " s " tests passed"}'
}
run_shards unit '-Conformance*:Slow*' 8
run_shards conformance "${conformance%:}" 4
end=$(date +%s)
echo "ci_asan: build $((built - start)) s, tests $((end - built)) s"
