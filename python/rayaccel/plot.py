"""Plots of `rayaccel bench --json` output (matplotlib): per scene, Mrays/s per structure with one panel per ray
kind, the ratio to Embree (when the run compared against it; brute force left out), and build time against memory.

    /usr/bin/python3 -m rayaccel.plot BENCH.json [MORE.json ...] --out DIR

Writes DIR/<scene>-t<threads>-mrays.png, -vs-embree.png and -build-memory.png and prints their paths. Structures are
grouped and coloured by family (Embree, the default structure, the BVH family, the spatial subdivisions, brute
force), the default structure and Embree in bold.
"""
import argparse
import json
import math
import re
import sys
from pathlib import Path

KIND_ORDER = ("primary", "diffuse", "shadow", "occlusion", "light", "packet", "light_packet")
DEFAULT_STRUCTURE = "bvh_wide"  # for bench files written before they named their default structure
# Family: (order, colour, legend). The order groups the bars; the default structure and Embree come first.
FAMILIES = {
    "embree": (0, "#d95f02", "Embree (comparison)"),
    "default": (1, "#1b4f9c", "default structure"),
    "bvh": (2, "#7fa7d6", "BVH family"),
    "spatial": (3, "#5aa469", "spatial subdivisions"),
    "brute_force": (4, "#9a9a9a", "brute force"),
}
BAR_INCHES = 0.19       # height of one structure's row
PANEL_INCHES = 2.3      # width of one ray kind's panel
MAX_LABEL_CHARS = 34    # longer specs are shortened in the axis labels


def _pyplot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def load_scenes(paths):
    """Every scene report of the given bench JSON files, each with the file's thread count and default structure."""
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
            scene.setdefault("default_accel", data.get("default_accel", DEFAULT_STRUCTURE))
            scenes.append(scene)
    return scenes


def ray_kinds(rows):
    present = {kind for row in rows for kind in row.get("rays", {})}
    return [k for k in KIND_ORDER if k in present] + sorted(present - set(KIND_ORDER))


def family(row, default_spec):
    """The family a result row belongs to (a key of FAMILIES)."""
    spec = row["accel"]
    name = spec.split(":", 1)[0]
    if row.get("is_embree") or name == "embree":
        return "embree"
    if spec == default_spec:
        return "default"
    if name == "brute_force":
        return "brute_force"
    return "bvh" if name.startswith("bvh") else "spatial"


def grouped(rows, default_spec):
    """The rows ordered by family (stable within one), so that the spatial structures sit together."""
    return sorted(rows, key=lambda row: FAMILIES[family(row, default_spec)][0])


def ratio_rows(rows, default_spec):
    """Embree's row (plain "embree" first) and the rows drawn as ratios to it: every other one but brute force,
    which, thousands of times slower, would stretch the log axis over decades of nothing."""
    embree = next((r for r in rows if r.get("is_embree") and r["accel"] == "embree"), None) or \
        next((r for r in rows if r.get("is_embree")), None)
    others = [r for r in rows if r is not embree and family(r, default_spec) != "brute_force"]
    return embree, others


def _short(label):
    return label if len(label) <= MAX_LABEL_CHARS else label[:MAX_LABEL_CHARS - 3] + "..."


def _log_axis(axis):
    """Log scale with plain numbers at 1, 2 and 5 times powers of ten (no crowded minor labels)."""
    from matplotlib import ticker

    axis.set_major_locator(ticker.LogLocator(subs=(1.0, 2.0, 5.0)))
    axis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axis.set_minor_formatter(ticker.NullFormatter())


def _legend(fig, families):
    from matplotlib.patches import Patch

    handles = [Patch(color=FAMILIES[f][1], label=FAMILIES[f][2]) for f in FAMILIES if f in families]
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8, frameon=False,
               bbox_to_anchor=(0.5, 1.0))


def _panels(plt, title, rows, kinds, value, xlabel, default_spec, log=False, reference_line=None):
    """One horizontal bar panel per ray kind, side by side, sharing the structures' axis."""
    fams = [family(row, default_spec) for row in rows]
    height = 0.9 + BAR_INCHES * len(rows)
    fig, axes = plt.subplots(1, len(kinds), sharey=True, squeeze=False,
                             figsize=(1.2 + PANEL_INCHES * len(kinds), height))
    positions = list(range(len(rows)))
    for ax, kind in zip(axes[0], kinds):
        values = [value(row, kind) for row in rows]
        ax.barh(positions, [v if v is not None else 0 for v in values], height=0.75,
                color=[FAMILIES[f][1] for f in fams])
        ax.set_title(kind, fontsize=9)
        ax.set_xlabel(xlabel, fontsize=7)
        ax.grid(axis="x", alpha=0.3)
        ax.tick_params(axis="x", labelsize=7)
        if log:
            ax.set_xscale("log")
            _log_axis(ax.xaxis)
            present = [v for v in values if v]
            if present:
                low, high = min(present + [reference_line or min(present)]), max(present + [reference_line or 0])
                ax.set_xlim(low / 1.3, high * 1.3)
        if reference_line is not None:
            ax.axvline(reference_line, color="black", linewidth=0.8)
    first = axes[0][0]
    first.set_yticks(positions)
    first.set_yticklabels([_short(row["accel"]) for row in rows], fontsize=7)
    for tick, fam in zip(first.get_yticklabels(), fams):
        if fam in ("default", "embree"):
            tick.set_fontweight("bold")
    first.set_ylim(len(rows) - 0.5, -0.5)
    fig.suptitle(title, fontsize=10, y=1.0 + 0.45 / height)
    _legend(fig, set(fams))
    fig.tight_layout(pad=0.4)
    return fig


def _place_labels(fig, ax, points):
    """Annotates points (x, y, text), in the given order of priority, skipping any label that would overlap one
    already placed or leave the axes; returns the Text objects placed."""
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    placed, boxes = [], []
    for x, y, text in points:
        label = ax.annotate(text, (x, y), fontsize=7, xytext=(4, 3), textcoords="offset points")
        box = label.get_window_extent(renderer)
        inside = frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1
        if not inside or any(box.overlaps(other) for other in boxes):
            label.remove()
        else:
            placed.append(label)
            boxes.append(box)
    return placed


def _pareto(points):
    """Indices of the points no other point beats in both coordinates (less memory and a faster build)."""
    return [i for i, (x, y) in enumerate(points)
            if not any(ox <= x and oy <= y and (ox, oy) != (x, y) for ox, oy in points)]


def _build_memory(plt, title, rows, default_spec):
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    points, shown, fams = [], [], []
    for row in rows:
        x = (row["memory_bytes"] + row.get("input_memory_bytes", 0)) / 2**20
        y = row["build_ms_median"]
        if x > 0 and y > 0:  # a log axis has no place for zero
            points.append((x, y))
            shown.append(row)
            fams.append(family(row, default_spec))
    for (x, y), fam in zip(points, fams):
        picked = fam in ("default", "embree")
        ax.scatter([x], [y], color=FAMILIES[fam][1], marker="*" if fam == "embree" else "o", s=90 if picked else 28,
                   edgecolors="black" if picked else "none", zorder=3 if picked else 2)
    ax.set_xscale("log")
    ax.set_yscale("log")
    _log_axis(ax.xaxis)
    _log_axis(ax.yaxis)
    ax.set_xlabel("memory with the input its queries read (MiB, log scale)", fontsize=9)
    ax.set_ylabel("build time (ms, median, log scale)", fontsize=9)
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3, which="both")
    _legend(fig, set(fams))
    fig.tight_layout(pad=0.4)
    # Labels: the default structure and Embree first, then the best trade-offs, then the rest where room is left.
    front = set(_pareto(points))
    order = sorted(range(len(points)), key=lambda i: (fams[i] not in ("default", "embree"), i not in front, i))
    _place_labels(fig, ax, [(points[i][0], points[i][1], _short(shown[i]["accel"])) for i in order])
    return fig


def plot_scene(plt, scene, out_dir):
    """Writes the scene's figures; returns their paths."""
    default_spec = scene.get("default_accel", DEFAULT_STRUCTURE)
    rows = grouped([r for r in scene.get("results", []) if "failure" not in r], default_spec)
    if not rows:
        return []
    stem = re.sub(r"[^A-Za-z0-9_.-]+", "_", f"{scene.get('scene', 'scene')}-t{scene.get('threads', 0)}")
    what = f"{scene.get('scene')} ({scene.get('primitives')} {scene.get('kind', 'primitives')}, " \
           f"{scene.get('threads')} threads, {scene.get('resolution')}^2 rays)"
    kinds = ray_kinds(rows)

    def mrays(row, kind):
        entry = row.get("rays", {}).get(kind)
        return entry["mrays_s_median"] if entry else None

    written = [_save(plt, _panels(plt, f"Mrays/s (median): {what}", rows, kinds, mrays, "Mrays/s", default_spec),
                     out_dir / f"{stem}-mrays.png")]
    embree, others = ratio_rows(rows, default_spec)
    if embree is not None:

        def ratio(row, kind):
            a, b = mrays(row, kind), mrays(embree, kind)
            return a / b if a and b and math.isfinite(a / b) else None

        if others:
            fig = _panels(plt, f"Mrays/s relative to Embree's (> 1: faster): {what}", others, kinds, ratio,
                          "ratio (log scale)", default_spec, log=True, reference_line=1.0)
            written.append(_save(plt, fig, out_dir / f"{stem}-vs-embree.png"))
    fig = _build_memory(plt, f"Build time against memory: {what}", rows, default_spec)
    written.append(_save(plt, fig, out_dir / f"{stem}-build-memory.png"))
    return written


def _save(plt, fig, path):
    fig.savefig(path, dpi=100, bbox_inches="tight", pad_inches=0.08)
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
