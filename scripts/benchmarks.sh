#!/usr/bin/env bash
# Reproduces the figures in BENCHMARKS.md: the default structure (bvh_wide, with and without triangle pre-splitting),
# the SAH kd-tree and the uniform grid (default and SIMD-block variant) against Embree 3 on the shared scenes and the
# built-in stress scenes, at 1 and 2 threads, every answer checked before timing.
# Usage: scripts/benchmarks.sh [RESOLUTION] [OUTPUT_DIR]   (defaults: 512, bench-results)
set -euo pipefail
cd "$(dirname "$0")/.."
res=${1:-512}
out=${2:-bench-results}
bin=./build/bin/rayaccel
shared=../shared/scenes
mkdir -p "$out"
scenes=("$shared/bunny.ply" "$shared/dragon.ply" "$shared/crytek_sponza.ply" "$shared/conference.ply"
        builtin:teapot_stadium builtin:slivers builtin:soup)
for threads in 1 2; do
  "$bin" bench "${scenes[@]}" \
    --accel bvh_wide,bvh_wide:presplit=0,kdtree:builder=sah,grid,grid:density=1,blocks=true,mailbox=false \
    --compare embree --res "$res" --threads "$threads" --repeat 5 \
    --json "$out/threads$threads.json" | tee "$out/threads$threads.txt"
done
# The summary tables of BENCHMARKS.md (ratios to Embree, spatial structures against bvh_wide).
python3 scripts/bench_summary.py "$out" | tee "$out/summary.md"
