"""Plots of `rayaccel bench --json` output (matplotlib): per scene, Mrays/s per structure and ray kind, the ratio to
Embree (when the run compared against it), and build time against memory.

    /usr/bin/python3 -m rayaccel.plot BENCH.json [MORE.json ...] --out DIR

Writes DIR/<scene>-t<threads>-mrays.png, -vs-embree.png and -build-memory.png and prints their paths.
"""
import argparse
import json
import re
import sys
from pathlib import Path

KIND_ORDER = ("primary", "diffuse", "shadow", "occlusion", "light", "packet")


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def load_scenes(paths):
    """Every scene report of the given bench JSON files, each with the file's thread count."""
    scenes = []
    for path in paths:
        try:
            data = json.loads(Path(path).read_text())
        except FileNotFoundError:
            raise FileNotFoundError(f"bench file '{path}' does not exist") from None
        except json.JSONDecodeError as error:
            raise ValueError(f"'{path}' is not JSON: {error}") from None
        if not isinstance(data, dict) or not isinstance(data.get("scenes"), list):
            raise ValueError(f"'{path}' is not `rayaccel bench --json` output (no 'scenes' list)")
        for scene in data["scenes"]:
            scene.setdefault("threads", data.get("threads", 0))
            scenes.append(scene)
    return scenes


def ray_kinds(rows):
    present = {kind for row in rows for kind in row.get("rays", {})}
    return [k for k in KIND_ORDER if k in present] + sorted(present - set(KIND_ORDER))


def _log_axis(axis):
    """Log scale with plain numbers at 1, 2 and 5 times powers of ten (no crowded minor labels)."""
    from matplotlib import ticker

    axis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(ticker.NullFormatter())


def _grouped_bars(plt, title, labels, kinds, value, xlabel, log=False, reference_line=None):
    """Horizontal bars: one group per label (structure), one bar per ray kind."""
    height = 0.8 / max(len(kinds), 1)
    fig, ax = plt.subplots(figsize=(9, 1.2 + 0.28 * len(labels) * max(len(kinds), 1)))
    for k, kind in enumerate(kinds):
        values = [value(label, kind) for label in labels]
        positions = [i + (k - (len(kinds) - 1) / 2) * height for i in range(len(labels))]
        ax.barh(positions, [v if v is not None else 0 for v in values], height=height, label=kind)
    ax.set_yticks(range(len(labels)))
    ax.set_yticklabels(labels, fontsize=8)
    ax.invert_yaxis()
    if log:
        ax.set_xscale("log")
        _log_axis(ax.xaxis)
    if reference_line is not None:
        ax.axvline(reference_line, color="black", linewidth=1)
    ax.set_xlabel(xlabel)
    ax.set_title(title, fontsize=10)
    ax.legend(fontsize=8, loc="best")
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()
    return fig


def plot_scene(plt, scene, out_dir):
    """Writes the scene's figures; returns their paths."""
    rows = [r for r in scene.get("results", []) if "failure" not in r]
    if not rows:
        return []
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", f"{scene.get('scene', 'scene')}-t{scene.get('threads', 0)}")
    what = f"{scene.get('scene')} ({scene.get('primitives')} {scene.get('kind', 'primitives')}, " \
           f"{scene.get('threads')} threads, {scene.get('resolution')}^2 rays)"
    kinds = ray_kinds(rows)
    by_accel = {r["accel"]: r for r in rows}
    labels = list(by_accel)

    def mrays(label, kind):
        entry = by_accel[label].get("rays", {}).get(kind)
        return entry["mrays_s_median"] if entry else None

    written = []
    fig = _grouped_bars(plt, f"Mrays/s: {what}", labels, kinds, mrays, "Mrays/s (median)")
    written.append(_save(plt, fig, out_dir / f"{stem}-mrays.png"))

    embree = next((r for r in rows if r.get("is_embree")), None)
    if embree is not None:
        others = [label for label in labels if not by_accel[label].get("is_embree")]

        def ratio(label, kind):
            a, b = mrays(label, kind), mrays(embree["accel"], kind)
            return a / b if a and b else None

        fig = _grouped_bars(plt, f"Speed relative to Embree (>1 faster): {what}", others, kinds, ratio,
                            "Mrays/s ratio to Embree (log scale)", log=True, reference_line=1.0)
        written.append(_save(plt, fig, out_dir / f"{stem}-vs-embree.png"))

    fig, ax = plt.subplots(figsize=(8, 6))
    for label in labels:
        row = by_accel[label]
        x, y = row["memory_bytes"] / 2**20, row["build_ms_median"]
        ax.scatter([x], [y], marker="*" if row.get("is_embree") else "o", s=50)
        ax.annotate(label, (x, y), fontsize=7, xytext=(4, 3), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    _log_axis(ax.xaxis)
    _log_axis(ax.yaxis)
    ax.set_xlabel("memory (MiB, log scale)")
    ax.set_ylabel("build time (ms, median, log scale)")
    ax.set_title(f"Build time against memory: {what}", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    written.append(_save(plt, fig, out_dir / f"{stem}-build-memory.png"))
    return written


def _save(plt, fig, path):
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m rayaccel.plot", description=__doc__.split("\n\n")[0])
    parser.add_argument("bench", nargs="+", help="JSON written by `rayaccel bench --json FILE`")
    parser.add_argument("--out", required=True, help="directory for the PNG files (created)")
    args = parser.parse_args(argv)
    try:
        scenes = load_scenes(args.bench)
    except (FileNotFoundError, ValueError) as error:
        parser.exit(2, f"error: {error}\n")
    out_dir = Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    plt = _pyplot()
    written = [path for scene in scenes for path in plot_scene(plt, scene, out_dir)]
    for path in written:
        print(path)
    if not written:
        parser.exit(1, "error: no scene with results in the bench files\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
