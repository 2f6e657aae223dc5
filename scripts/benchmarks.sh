#!/usr/bin/env bash
# Reproduces the figures in BENCHMARKS.md: the default structure (bvh_wide, with and without triangle pre-splitting),
# the SAH kd-tree and the uniform grid (default and SIMD-block variant) against Embree 3 on the shared scenes and the
# built-in stress scenes, at 1 and 2 threads, and Embree in robust mode and at high build quality beside its default,
# then the default structure against Embree on a scene of 8.4 million triangles, every answer checked
# before timing. The whole set runs RUNS times
# (the machine is shared and noisy); the summary gives the median over the runs of each ratio taken within one run.
# Usage: scripts/benchmarks.sh [RESOLUTION] [OUTPUT_DIR] [RUNS]   (defaults: 512, bench-results, 3)
set -euo pipefail
cd "$(dirname "$0")/.."
res=${1:-512}
out=${2:-bench-results}
runs=${3:-3}
bin=./build/bin/rayaccel
shared=../shared/scenes
scenes=("$shared/bunny.ply" "$shared/dragon.ply" "$shared/crytek_sponza.ply" "$shared/conference.ply"
        builtin:teapot_stadium builtin:slivers builtin:soup)
run_dirs=()
for run in $(seq "$runs"); do
  dir="$out/run$run"
  mkdir -p "$dir"
  run_dirs+=("$dir")
  for threads in 1 2; do
    echo "== run $run of $runs, $threads thread(s)" >&2
    "$bin" bench "${scenes[@]}" \
      --accel bvh_wide,bvh_wide:presplit=0,kdtree:builder=sah,grid,grid:density=1,blocks=true,mailbox=false,embree:robust=1,embree:quality=high \
      --compare embree --res "$res" --threads "$threads" --repeat 5 \
      --json "$dir/threads$threads.json" | tee "$dir/threads$threads.txt"
    # Millions of triangles: the fractal mountain at level 11 (8.4M triangles), the default structure and Embree only.
    "$bin" bench builtin:mountain:level=11 --accel bvh_wide,embree:quality=high --compare embree \
      --res "$res" --threads "$threads" --repeat 5 \
      --json "$dir/large$threads.json" | tee "$dir/large$threads.txt"
  done
done
# The summary tables of BENCHMARKS.md (ratios to Embree, spatial structures against bvh_wide).
python3 scripts/bench_summary.py "${run_dirs[@]}" | tee "$out/summary.md"
