#!/usr/bin/env python3
"""A/B timing of two or more builds of the rayaccel CLI, for changes smaller than the full bench's noise.

On a shared machine single `rayaccel bench` figures swing by 10-25% from run to run, so a change worth a few per cent
only shows when the builds run alternately, close in time, and are compared round by round. This script runs
`rayaccel bench --json` for every binary on every scene, the binaries' order reversed each round, and prints for each
scene and ray kind the median Mrays/s of each binary and the median over the rounds of each binary's ratio to the
first (with the lowest and highest of those ratios). The BENCHMARKS.md history steps that quote "ratio after /
before" were measured this way.

Usage: scripts/ab_bench.py [--rounds N] [--rays KINDS] [--accel SPEC] [--threads T] [--res N] [--repeat N]
                           --bin BEFORE --bin AFTER [--bin ...] SCENE...
Copy each build's build/bin/rayaccel somewhere first (e.g. /tmp/rayaccel.before): rebuilding while this runs would
replace the binary under it.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile


def run_bench(binary, scene, args):
    """One `rayaccel bench` process; returns {kind: Mrays/s} of the structure's row."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "bench.json")
        command = [binary, "bench", "--accel", args.accel, "--rays", args.rays, "--threads", str(args.threads),
                   "--res", str(args.res), "--repeat", str(args.repeat), "--json", out, scene]
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode != 0:
            sys.exit(f"ab_bench: {' '.join(command)} failed ({result.returncode}):\n{result.stderr}")
        with open(out) as f:
            data = json.load(f)
    rows = data["scenes"][0]["results"]
    if len(rows) != 1:
        sys.exit(f"ab_bench: expected one structure's row for --accel {args.accel}, got {len(rows)}")
    return {kind: figures["mrays_s_median"] for kind, figures in rows[0]["rays"].items()}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bin", action="append", required=True, help="a rayaccel binary (the first is the baseline)")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--rays", default="primary,diffuse,shadow,occlusion")
    parser.add_argument("--accel", default="bvh_wide")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--res", type=int, default=384)
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("scenes", nargs="+")
    args = parser.parse_args()
    if len(args.bin) < 2:
        parser.error("give at least two --bin")
    if args.rounds < 1:
        parser.error("--rounds must be at least 1")
    for binary in args.bin:
        if not os.access(binary, os.X_OK):
            parser.error(f"--bin {binary}: not an executable file")

    speeds = {}  # (scene, kind, binary) -> Mrays/s per round
    for round_index in range(args.rounds):
        order = args.bin if round_index % 2 == 0 else args.bin[::-1]
        for scene in args.scenes:
            for binary in order:
                for kind, mrays in run_bench(binary, scene, args).items():
                    speeds.setdefault((scene, kind, binary), []).append(mrays)
        print(f"ab_bench: round {round_index + 1} of {args.rounds} done", file=sys.stderr, flush=True)

    base = args.bin[0]
    for scene in args.scenes:
        for kind in args.rays.split(","):
            base_runs = speeds.get((scene, kind, base))
            if not base_runs:
                continue
            line = f"{os.path.basename(scene):24s} {kind:12s}"
            line += f" {os.path.basename(base)} {statistics.median(base_runs):7.2f}"
            for binary in args.bin[1:]:
                runs = speeds[(scene, kind, binary)]
                ratios = [b / a for a, b in zip(base_runs, runs)]
                line += (f" | {os.path.basename(binary)} {statistics.median(runs):7.2f}"
                         f" ratio {statistics.median(ratios):.3f} ({min(ratios):.2f}-{max(ratios):.2f})")
            print(line)


if __name__ == "__main__":
    main()
