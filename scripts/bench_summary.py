#!/usr/bin/env python3
"""Summary tables of BENCHMARKS.md from the JSON that scripts/benchmarks.sh writes.

Usage: scripts/bench_summary.py DIR   (reads DIR/threads1.json and DIR/threads2.json, prints Markdown)

Table 1: the default structure and bvh_wide:presplit=0 as ratios to Embree measured in the same run.
Table 2: the spatial structures as slowdowns against the default bvh_wide (1 thread).
"""
import json
import sys
from pathlib import Path

KINDS = ("primary", "diffuse", "shadow")
DEFAULT = "bvh_wide"
NO_PRESPLIT = "bvh_wide:presplit=0"
SPATIAL = ("kdtree:builder=sah", "grid", "grid:density=1,blocks=true,mailbox=false")


def rows_by_accel(scene):
    return {row["accel"]: row for row in scene["results"]}


def mrays(row, kind):
    return row["rays"][kind]["mrays_s_median"]


def ratios_to_embree(row, embree):
    """build / memory / P / D / S as ratios: < 1 is better for build and memory, > 1 for rays per second."""
    parts = [row["build_ms_median"] / embree["build_ms_median"], row["memory_bytes"] / embree["memory_bytes"]]
    parts += [mrays(row, k) / mrays(embree, k) for k in KINDS]
    return " / ".join(f"{x:.2f}" for x in parts)


def embree_figures(embree):
    mb = embree["memory_bytes"] / 2**20  # MiB, as rayaccel bench prints
    speeds = " / ".join(f"{mrays(embree, k):.2f}" for k in KINDS)
    return f"{embree['build_ms_median']:.0f} / {mb:.1f} / {speeds}"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    directory = Path(sys.argv[1])
    runs = []
    for threads in (1, 2):
        path = directory / f"threads{threads}.json"
        try:
            runs.append((threads, json.loads(path.read_text())))
        except (OSError, json.JSONDecodeError) as error:
            sys.exit(f"bench_summary: cannot read {path}: {error}")

    print(f"| scene | threads | Embree build ms / MB / Mrays/s P/D/S | {DEFAULT} build / memory / P / D / S "
          f"| {NO_PRESPLIT} build / memory / P / D / S |")
    print("|---|---|---|---|---|")
    for threads, run in runs:
        for scene in run["scenes"]:
            rows = rows_by_accel(scene)
            embree = next(r for r in scene["results"] if r.get("is_embree"))
            print(f"| {scene['scene']} | {threads} | {embree_figures(embree)} "
                  f"| {ratios_to_embree(rows[DEFAULT], embree)} | {ratios_to_embree(rows[NO_PRESPLIT], embree)} |")

    print()
    print("| scene | " + " | ".join(f"{s} P / D / S" for s in SPATIAL) + " |")
    print("|---|" + "---|" * len(SPATIAL))
    threads, run = runs[0]
    for scene in run["scenes"]:
        rows = rows_by_accel(scene)
        best = rows[DEFAULT]
        cells = []
        for spec in SPATIAL:
            cells.append(" / ".join(f"{mrays(best, k) / mrays(rows[spec], k):.2f}" for k in KINDS))
        print(f"| {scene['scene']} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
