#!/usr/bin/env python3
"""Summary tables of BENCHMARKS.md from the JSON that scripts/benchmarks.sh writes.

Usage: scripts/bench_summary.py DIR [DIR...]   (each DIR holds one run: threads1.json and threads2.json)

Every ratio is taken within one run (a structure against Embree measured in the same process), then the median over
the runs is printed, so one noisy run does not decide a cell.
Ray kinds, each shown when every result of every run has it: P primary, D diffuse, S shadow (short AO rays), O
occlusion (a quarter of the diagonal from origins offset along the normal), L light (rays to a point light), Pk packet
(the primary rays in 4x2 pixel tiles traced eight at a time: intersect_packets(), Embree's rtcIntersect8), LPk
light_packet (the light rays in that tile order traced eight at a time: occluded_packets(), Embree's rtcOccluded8).
Table 1: the default structure and bvh_wide:presplit=0 as ratios to Embree's default; Embree's own figures are
medians too. Memory twice: the structure alone (memory_bytes), and with the scene arrays its queries read
(memory_bytes + input_memory_bytes; Embree's structure holds its own copy of the vertices, so this is like for like). Table 1b: the default against Embree's other modes the runs have (embree:robust=1,
embree:quality=high), one column each.
Table 2: the lowest and highest of the default structure's ratios over the runs (only with two or more runs).
Table 3: the spatial structures as slowdowns against the default bvh_wide (1 thread).
Table 4: when the run directories hold large1.json and large2.json (the 8.4-million-triangle scene), the default
against Embree's default there.
"""
import json
import statistics
import sys
from pathlib import Path

LETTERS = {"primary": "P", "diffuse": "D", "shadow": "S", "occlusion": "O", "light": "L", "packet": "Pk",
           "light_packet": "LPk"}
KINDS = tuple(LETTERS)  # set by main() to the kinds every result of every run has, in this order
DEFAULT = "bvh_wide"
EMBREE = "embree"
EMBREE_MODES = ("embree:robust=1", "embree:quality=high")
NO_PRESPLIT = "bvh_wide:presplit=0"
SPATIAL = ("kdtree:builder=sah", "grid", "grid:density=1,blocks=true,mailbox=false")


def rows_by_accel(scene):
    return {row["accel"]: row for row in scene["results"]}


def mrays(row, kind):
    return row["rays"][kind]["mrays_s_median"]


def memory_with_scene(row):
    """The structure's bytes plus those of the scene arrays its queries read (input_memory_bytes: the like-for-like
    figure, as Embree's structure holds its own copy of the vertices); NaN for a run that did not record them."""
    extra = row.get("input_memory_bytes")
    return float("nan") if extra is None else row["memory_bytes"] + extra


def ratios_to_embree(row, embree):
    """build, memory (structure only), memory with the scene arrays, Mrays/s per kind (P, D, S[, Pk]) as ratios: < 1
    is better for build and memory, > 1 for rays."""
    parts = [row["build_ms_median"] / embree["build_ms_median"], row["memory_bytes"] / embree["memory_bytes"],
             memory_with_scene(row) / memory_with_scene(embree)]
    return parts + [mrays(row, k) / mrays(embree, k) for k in KINDS]


def embree_figures(embree):
    """build ms, MiB (as rayaccel bench prints) of the structure and with the scene arrays, Mrays/s per kind."""
    return ([embree["build_ms_median"], embree["memory_bytes"] / 2**20, memory_with_scene(embree) / 2**20]
            + [mrays(embree, k) for k in KINDS])


def slowdowns(rows):
    best = rows[DEFAULT]
    return [[mrays(best, k) / mrays(rows[spec], k) for k in KINDS] for spec in SPATIAL]


def median_of(values):
    """Elementwise median of equally shaped (nested) lists of numbers."""
    if isinstance(values[0], list):
        return [median_of([v[i] for v in values]) for i in range(len(values[0]))]
    return statistics.median(values)


def common_kinds(runs):
    rows = [row for run in runs for threads in (1, 2) for scene in run[threads]["scenes"] for row in scene["results"]
            if not row.get("failure")]
    return tuple(k for k in LETTERS if all(k in row["rays"] for row in rows))


def letters(separator=" / "):
    return separator.join(LETTERS[k] for k in KINDS)


def load(directory):
    run = {}
    for threads in (1, 2):
        path = directory / f"threads{threads}.json"
        try:
            run[threads] = json.loads(path.read_text())
        except (OSError, json.JSONDecodeError) as error:
            sys.exit(f"bench_summary: cannot read {path}: {error}")
    return run


def joined(values, digits=2):
    return " / ".join(f"{x:.{digits}f}" for x in values)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    runs = [load(Path(d)) for d in sys.argv[1:]]
    global KINDS
    KINDS = common_kinds(runs)
    modes = [m for m in EMBREE_MODES
             if all(m in rows_by_accel(scene) for run in runs for t in (1, 2) for scene in run[t]["scenes"])]
    # (threads, scene) -> per-run figures, in the first run's order.
    keys = [(t, s["scene"]) for t in (1, 2) for s in runs[0][t]["scenes"]]
    figures = {key: {"embree": [], "default": [], "no_presplit": [], "modes": [], "spatial": []} for key in keys}
    for run in runs:
        for threads in (1, 2):
            for scene in run[threads]["scenes"]:
                key = (threads, scene["scene"])
                if key not in figures:
                    sys.exit(f"bench_summary: scene {key[1]} is not in every run")
                rows = rows_by_accel(scene)
                embree = rows[EMBREE]
                figures[key]["embree"].append(embree_figures(embree))
                figures[key]["default"].append(ratios_to_embree(rows[DEFAULT], embree))
                figures[key]["no_presplit"].append(ratios_to_embree(rows[NO_PRESPLIT], embree))
                figures[key]["spatial"].append(slowdowns(rows))
                figures[key]["modes"].append([ratios_to_embree(rows[DEFAULT], rows[m]) for m in modes])

    print(f"Medians over {len(runs)} run(s).")
    print()
    print(f"| scene | threads | Embree build ms / MB / MB with scene / Mrays/s {letters('/')} "
          f"| {DEFAULT} build / memory / with scene / {letters()} "
          f"| {NO_PRESPLIT} build / memory / with scene / {letters()} |")
    print("|---|---|---|---|---|")
    for threads, scene in keys:
        f = figures[(threads, scene)]
        embree = median_of(f["embree"])
        embree_text = f"{embree[0]:.0f} / {embree[1]:.1f} / {embree[2]:.1f} / {joined(embree[3:])}"
        print(f"| {scene} | {threads} | {embree_text} | {joined(median_of(f['default']))} "
              f"| {joined(median_of(f['no_presplit']))} |")

    if modes:
        print()
        print("| scene | threads | "
              + " | ".join(f"{DEFAULT} against {m}: build / memory / with scene / {letters()}" for m in modes) + " |")
        print("|---|---|" + "---|" * len(modes))
        for threads, scene in keys:
            cells = median_of(figures[(threads, scene)]["modes"])
            print(f"| {scene} | {threads} | " + " | ".join(joined(c) for c in cells) + " |")

    if len(runs) > 1:
        print()
        print(f"| scene | threads | {DEFAULT} lowest-highest over the runs: build / memory / with scene / "
              f"{letters()} |")
        print("|---|---|---|")
        for threads, scene in keys:
            per_run = figures[(threads, scene)]["default"]
            spans = [f"{min(r[i] for r in per_run):.2f}-{max(r[i] for r in per_run):.2f}"
                     for i in range(len(per_run[0]))]
            print(f"| {scene} | {threads} | {' / '.join(spans)} |")

    print()
    print("| scene | " + " | ".join(f"{s} {letters()}" for s in SPATIAL) + " |")
    print("|---|" + "---|" * len(SPATIAL))
    for threads, scene in keys:
        if threads != 1:
            continue
        cells = median_of(figures[(threads, scene)]["spatial"])
        print(f"| {scene} | " + " | ".join(joined(c) for c in cells) + " |")
    print_large(sys.argv[1:])


def print_large(directories):
    """Table 4: the default against Embree on the large scene, when every run directory has it."""
    paths = [Path(d) / f"large{t}.json" for d in directories for t in (1, 2)]
    if not all(path.exists() for path in paths):
        return
    rows = {}
    for d in directories:
        for threads in (1, 2):
            for scene in json.loads((Path(d) / f"large{threads}.json").read_text())["scenes"]:
                by_accel = rows_by_accel(scene)
                entry = rows.setdefault((threads, scene["scene"]), {"embree": [], "default": []})
                entry["embree"].append(embree_figures(by_accel[EMBREE]))
                entry["default"].append(ratios_to_embree(by_accel[DEFAULT], by_accel[EMBREE]))
    print()
    print(f"| scene | threads | Embree build ms / MB / MB with scene / Mrays/s {letters('/')} "
          f"| {DEFAULT} build / memory / with scene / {letters()} |")
    print("|---|---|---|---|")
    for (threads, scene), entry in rows.items():
        embree = median_of(entry["embree"])
        print(f"| {scene} | {threads} | {embree[0]:.0f} / {embree[1]:.1f} / {embree[2]:.1f} / {joined(embree[3:])} "
              f"| {joined(median_of(entry['default']))} |")


if __name__ == "__main__":
    main()
