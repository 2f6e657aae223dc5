# Sourced by the sanitizer tiers (ci_asan.sh, ci_asan_avx.sh): runs a GoogleTest binary in a few dozen processes, two
# at a time, rather than one per test (under ASan each process costs about 0.2 s to start).
#   TIER=name TESTS=binary LOGS=dir; source scripts/sanitized_runs.sh
export ASAN_OPTIONS=halt_on_error=1:abort_on_error=1:detect_stack_use_after_return=0  # detect_leaks stays on
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
mkdir -p "$LOGS"
rm -f "$LOGS"/*.log

# run_processes NAME [SHARDS]: runs $TESTS once per GoogleTest filter read from stdin (one per line), two processes at
# a time; with SHARDS, line i runs GoogleTest's shard i of SHARDS of its filter. The first failing process prints its
# whole log and stops the tier.
run_processes() {
  local name=$1 shards=${2:-0}
  cat -n | xargs -P 2 -L 1 sh -c '
    log=$1/$2-$5.log
    if [ "$3" -gt 0 ]; then export GTEST_TOTAL_SHARDS=$3 GTEST_SHARD_INDEX=$(($5 - 1)); fi
    "$0" --gtest_filter="$6" > "$log" 2>&1 || { cat "$log"; echo "$4: $2 process $5 failed"; exit 255; }' \
    "$TESTS" "$LOGS" "$name" "$shards" "$TIER"
  grep -h '^\[  PASSED  \]' "$LOGS/$name"-*.log |
    awk -v n="$TIER: $name" '{s += $4} END {print n ": " s " tests passed"}'
}

# conformance_filters VARIANT...: one filter per parameterised Conformance test with every variant named (so the
# oracle computes brute force's answers once for them, as the normal tier does), and one for the Conformance tests
# that take no variant.
conformance_filters() {
  "$TESTS" --gtest_list_tests --gtest_filter='Conformance*' | awk -v variants="$*" '
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
    }'
}
