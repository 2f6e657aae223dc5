#!/usr/bin/env bash
# CI tier: AddressSanitizer + UndefinedBehaviorSanitizer over the unit tier and the conformance tier for one variant
# per structure and bounding-volume family (below), in the Clang tree the fuzz tier builds (build-fuzz,
# scripts/clang_sanitized_tree.sh), so only the tests and the CLI they run are compiled here. Clang builds have the
# SSE kernels only (README, "Supported"); a GCC build with -DRAYACCEL_SANITIZE=ON checks the AVX2 and AVX-512
# kernels too, by hand: it compiles the library and the tests once more, at about twice the normal build's CPU time
# (kd_tree.cpp: 122 s under GCC's ASan + UBSan at -O1, 67 s in the normal build), more than CI's time allows next to
# the other tiers. The slow tier and the package test stay out. The tests run in a few dozen processes, two at a
# time, rather than one per test (under ASan each process costs about 0.2 s to start).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
scripts/clang_sanitized_tree.sh rayaccel_tests rayaccel_cli
built=$(date +%s)
# halt_on_error: the first report fails the run; detect_leaks stays on.
export ASAN_OPTIONS=halt_on_error=1:abort_on_error=1:detect_stack_use_after_return=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
tests=build-fuzz/bin/rayaccel_tests
mkdir -p build-fuzz/logs
rm -f build-fuzz/logs/*.log
# run_processes NAME [SHARDS]: runs the test binary once per GoogleTest filter read from stdin (one per line), two
# processes at a time; with SHARDS, line i runs GoogleTest's shard i of SHARDS of its filter. The first failing
# process prints its whole log and stops the tier.
run_processes() {
  local name=$1 shards=${2:-0}
  cat -n | xargs -P 2 -L 1 sh -c '
    log=build-fuzz/logs/$1-$3.log
    if [ "$2" -gt 0 ]; then export GTEST_TOTAL_SHARDS=$2 GTEST_SHARD_INDEX=$(($3 - 1)); fi
    "$0" --gtest_filter="$4" > "$log" 2>&1 || { cat "$log"; echo "ci_asan: $1 process $3 failed"; exit 255; }' \
    "$tests" "$name" "$shards"
  grep -h '^\[  PASSED  \]' build-fuzz/logs/"$name"-*.log |
    awk -v n="$name" '{s += $4} END {print "ci_asan: " n ": " s " tests passed"}'
}
# The unit tier: eight shards.
for _ in 1 2 3 4 5 6 7 8; do echo '-Conformance*:Slow*'; done | run_processes unit 8
# Conformance: one variant per structure and bounding-volume family (15 of the variants the normal tier runs); one
# process per Conformance test with all 15 variants, so that the oracle computes brute force's answers once for them
# (as the normal tier does), and one process for the Conformance tests that take no variant.
variants=(brute_force grid grid_density_1_blocks_true_mailbox_false grid2 kdtree_builder_sah octree bsp
          bvh_bv_aabb_builder_binned bvh_bv_sphere_builder_binned bvh_bv_obb_builder_sbvh bvh_bv_kdop18_builder_ploc
          bvh_bv_hull_builder_binned bvh_bv_capsule_builder_lbvh bvh_wide bvh_wide_width_4)
"$tests" --gtest_list_tests --gtest_filter='Conformance*' | awk -v variants="${variants[*]}" '
  BEGIN { n = split(variants, v, " ") }
  /^[^ ]/ { suite = $1 }
  /^  [^ ]+\// { split($1, part, "/"); if (!((suite part[1]) in seen)) order[++count] = suite part[1]; seen[suite part[1]] = 1 }
  /^  [^ \/]+( |$)/ { plain = plain (plain == "" ? "" : ":") suite $1 }
  END {
    for (k = 1; k <= count; ++k) {
      line = ""
      for (i = 1; i <= n; ++i) line = line (i > 1 ? ":" : "") order[k] "/" v[i]
      print line
    }
    if (plain != "") print plain
  }' | run_processes conformance
end=$(date +%s)
echo "ci_asan: build $((built - start)) s, tests $((end - built)) s"
