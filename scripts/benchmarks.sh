#!/usr/bin/env bash
# Reproduces the figures in BENCHMARKS.md: the default structure (bvh_wide) and the binary BVH against Embree 3 on
# the shared scenes and the built-in stress scenes, at 1 and 2 threads, every answer checked before timing.
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
  "$bin" bench "${scenes[@]}" --accel bvh_wide,bvh --compare embree --res "$res" --threads "$threads" --repeat 5 \
    --json "$out/threads$threads.json" | tee "$out/threads$threads.txt"
done
