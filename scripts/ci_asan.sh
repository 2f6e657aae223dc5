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
# The unit tier: eight shards. Without BunnyEdgeRays (63 s under ASan): its subject is exact arithmetic on the bunny's
# edges, and the default structure's memory is checked here by the conformance tier and by the fuzzers.
for _ in 1 2 3 4 5 6 7 8; do echo '-Conformance*:Slow*:BunnyEdgeRays.*'; done | run_processes unit 8
# Conformance: one variant per structure (9 of the variants the normal tier runs). The BVH's other volumes and builders
# run under the sanitizers in the unit tier above (AllBvhVariants: every volume x builder against brute force on soups,
# closed meshes, duplicates, spheres and edge cases), and the grid with Triangle4 blocks in ci_asan_avx.sh.
conformance_filters brute_force grid grid2 kdtree_builder_sah octree bsp bvh_bv_aabb_builder_binned bvh_wide \
  bvh_wide_width_4 | run_processes conformance
end=$(date +%s)
echo "ci_asan: build $((built - start)) s, tests $((end - built)) s"
