#!/usr/bin/env bash
# CI tier: the libFuzzer targets of tests/fuzz, built with Clang, ASan and UBSan in build-fuzz
# (scripts/clang_sanitized_tree.sh), each run on a copy of its checked-in corpus (tests/fuzz/corpus/<target>; the
# copy keeps the inputs found out of the source tree). A crash, sanitizer report, leak or timeout fails the tier; the
# input that caused it is left in build-fuzz/findings, and the run's whole log beside it. CI replays the same runs
# every time: a fixed seed (FUZZ_SEED, default 1), a fixed number of inputs per target (below: about 25 s each on
# CI's machine; FUZZ_SCALE multiplies them), the library's parallel loops on one thread (tests/fuzz/one_thread.cpp)
# and address randomisation off (setarch -R; where the system refuses it, the runs go on with it). A run by time
# instead followed the coverage of whatever the machine managed in 25 s, so a CI run could meet an input no earlier
# run had; now a red CI names an input anyone can replay, and a green local run of this script is the run CI makes.
# Each target also stops after FUZZ_MAX_SECONDS (default 100) so a slow machine cannot stall CI. Exploration with
# fresh seeds is done by hand, and what it finds joins the corpus:
#   FUZZ_SEED=0 FUZZ_SCALE=100 FUZZ_MAX_SECONDS=3600 scripts/ci_fuzz.sh      (seed 0: libFuzzer picks one)
set -euo pipefail
cd "$(dirname "$0")/.."
scale=${FUZZ_SCALE:-1}
max_seconds=${FUZZ_MAX_SECONDS:-100}
seed=${FUZZ_SEED:-1}
start=$(date +%s)
targets=(fuzz_ply_reader fuzz_ray_file fuzz_specs fuzz_bvh_file fuzz_differential)
declare -A runs=([fuzz_ply_reader]=600000 [fuzz_ray_file]=100000 [fuzz_specs]=350000 [fuzz_bvh_file]=80000
                 [fuzz_differential]=600)
no_aslr=(setarch "$(uname -m)" -R)
"${no_aslr[@]}" true 2>/dev/null || no_aslr=()
scripts/clang_sanitized_tree.sh "${targets[@]}"
built=$(date +%s)
export ASAN_OPTIONS=halt_on_error=1:detect_leaks=1
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
mkdir -p build-fuzz/findings
for t in "${targets[@]}"; do
  work=build-fuzz/corpus/$t
  rm -rf "$work" && mkdir -p "$work"
  cp tests/fuzz/corpus/"$t"/* "$work"/ 2>/dev/null || true
  echo "ci_fuzz: $t, $(( ${runs[$t]} * scale )) inputs"
  log=build-fuzz/findings/"$t".log
  if "${no_aslr[@]}" build-fuzz/fuzz/"$t" -seed="$seed" -runs=$(( ${runs[$t]} * scale )) \
      -max_total_time="$max_seconds" -timeout=20 -rss_limit_mb=3072 \
      -print_final_stats=1 -artifact_prefix=build-fuzz/findings/"$t"- "$work" > "$log" 2>&1; then
    tail -n 6 "$log"
  else
    tail -n 80 "$log"
    echo "ci_fuzz: $t failed (log: $log)"
    exit 1
  fi
done
end=$(date +%s)
echo "ci_fuzz: build $((built - start)) s, fuzzing $((end - built)) s"
