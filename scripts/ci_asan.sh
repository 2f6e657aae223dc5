#!/usr/bin/env bash
# CI tier: AddressSanitizer + UndefinedBehaviorSanitizer over the unit tier and the conformance tier for one variant
# per structure and bounding-volume family (below), in the Clang tree the fuzz tier builds (build-fuzz,
# scripts/clang_sanitized_tree.sh), so only the tests and the CLI they run are compiled here. Clang builds have the
# SSE kernels only (README, "Supported"); scripts/ci_asan_avx.sh checks the AVX2 and AVX-512 kernels in a GCC tree.
# The slow tier and the package test stay out.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
scripts/clang_sanitized_tree.sh rayaccel_tests rayaccel_cli
built=$(date +%s)
TIER=ci_asan TESTS=build-fuzz/bin/rayaccel_tests LOGS=build-fuzz/logs
source scripts/sanitized_runs.sh
# The unit tier: eight shards.
for _ in 1 2 3 4 5 6 7 8; do echo '-Conformance*:Slow*'; done | run_processes unit 8
# Conformance: one variant per structure and per bounding volume with memory of its own or its own builder (13 of the
# variants the normal tier runs; the grid with Triangle4 blocks runs in ci_asan_avx.sh, the sphere volume is a
# centre and a radius tested as the box is).
conformance_filters brute_force grid grid2 kdtree_builder_sah octree bsp bvh_bv_aabb_builder_binned \
  bvh_bv_obb_builder_sbvh bvh_bv_kdop18_builder_ploc bvh_bv_hull_builder_binned bvh_bv_capsule_builder_lbvh bvh_wide \
  bvh_wide_width_4 | run_processes conformance
end=$(date +%s)
echo "ci_asan: build $((built - start)) s, tests $((end - built)) s"
