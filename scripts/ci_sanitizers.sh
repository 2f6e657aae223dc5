#!/usr/bin/env bash
# CI tier: the unit tests and a subset of the conformance variants (below) under AddressSanitizer +
# UndefinedBehaviorSanitizer (GCC), in build-asan. Builds only the test executable and the CLI it runs; the slow
# tier and the package test stay out.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DRAYACCEL_SANITIZE=ON \
  -DRAYACCEL_BUILD_BENCH=OFF -DRAYACCEL_BUILD_PYTHON=OFF -DRAYACCEL_BUILD_SHARED=OFF -DRAYACCEL_INSTALL=OFF
cmake --build build-asan --target rayaccel_tests rayaccel_cli
built=$(date +%s)
# halt_on_error: the first report fails the test; detect_leaks stays on.
export ASAN_OPTIONS=halt_on_error=1:abort_on_error=1:detect_stack_use_after_return=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
ctest --test-dir build-asan --output-on-failure -j2 -L unit --timeout 900
# Conformance: one variant per structure and bounding-volume family (15 of the 60 variants the normal tier runs,
# 556 of its 2,269 tests), so the tier fits CI's time; the normal tier runs every variant without sanitizers. Each
# variant is one CTest test, conformance/<variant> (tests/conformance_variants.cmake).
variants='brute_force|grid|grid_density_1_blocks_true_mailbox_false|grid2|kdtree_builder_sah|octree|bsp'
variants+='|bvh_bv_aabb_builder_binned|bvh_bv_sphere_builder_binned|bvh_bv_obb_builder_sbvh|bvh_bv_kdop18_builder_ploc'
variants+='|bvh_bv_hull_builder_binned|bvh_bv_capsule_builder_lbvh|bvh_wide|bvh_wide_width_4'
ctest --test-dir build-asan --output-on-failure -j2 -L conformance -R "^conformance/($variants)\$" --timeout 900
end=$(date +%s)
echo "ci_sanitizers: build $((built - start)) s, tests $((end - built)) s"
