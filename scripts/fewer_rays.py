#!/usr/bin/python3
"""Measures what the "fewer rays" techniques of `rayaccel render --mode whitted` save: adaptive anti-aliasing against
uniform supersampling (rays per pixel against error), adaptive tree depth (rays and time against error), and any-hit
against closest-hit shadow rays (node visits). The error is measured against a uniform 16 x 16 reference render.

    /usr/bin/python3 scripts/fewer_rays.py [--cli build/bin/rayaccel] [--out fewer-rays] [--res 160x120]

Writes OUT/<scene>/*.png (every image and the samples-per-pixel maps), OUT/fewer_rays.json, OUT/fewer_rays.png (a plot
of PSNR against rays per pixel) and prints Markdown tables.
"""
import argparse
import json
import subprocess
import sys
from pathlib import Path

SHARED = Path(__file__).resolve().parent.parent.parent / "shared" / "scenes"

# (label, scene spec, extra render arguments)
SCENES = [
    ("glass", "builtin:glass", ["--eye", "0,2.5,5", "--at", "0,0.8,0"]),
    ("sphereflake", "builtin:sphereflake:level=3", []),
    ("crytek_sponza", str(SHARED / "crytek_sponza.ply"), ["--mirror", "0.3"]),
]
UNIFORM = [1, 2, 4, 8]
ADAPTIVE = [0.2, 0.1, 0.05, 0.02]
MIN_WEIGHTS = [0.0, 0.01, 0.05, 0.1, 0.2]
LIGHT = []  # set by --light-radius


def render(cli, spec, extra, out_png, json_path, res, args):
    command = [cli, "render", spec, "--mode", "whitted", "--res", res, "--out", str(out_png), "--json", str(json_path)]
    command += extra + LIGHT + args
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"failed: {' '.join(command)}\n{done.stderr}")
    return json.loads(json_path.read_text())


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cli", default="build/bin/rayaccel")
    parser.add_argument("--out", default="fewer-rays")
    parser.add_argument("--res", default="160x120")
    parser.add_argument("--scenes", default=",".join(label for label, _, _ in SCENES))
    parser.add_argument("--light-radius", default="0",
                        help="light radius as a fraction of the diagonal; 0 (a point light) leaves only aliasing, "
                             "no sampling noise, for the anti-aliasing comparison")
    options = parser.parse_args()
    LIGHT.extend(["--light-radius", options.light_radius])
    out = Path(options.out)
    results = {}
    for label, spec, extra in SCENES:
        if label not in options.scenes.split(","):
            continue
        if not spec.startswith("builtin:") and not Path(spec).exists():
            print(f"skipping {label}: {spec} is missing", file=sys.stderr)
            continue
        d = out / label
        d.mkdir(parents=True, exist_ok=True)
        print(f"{label}: reference (uniform 16 x 16)", file=sys.stderr)
        reference = d / "reference.png"
        ref = render(options.cli, spec, extra, reference, d / "reference.json", options.res, ["--aa", "uniform:n=16"])
        runs = {"reference": ref, "uniform": [], "adaptive": [], "depth": [], "shadows": []}
        for n in UNIFORM:
            runs["uniform"].append(render(options.cli, spec, extra, d / f"uniform{n}.png", d / f"uniform{n}.json",
                                          options.res, ["--aa", f"uniform:n={n}", "--reference", str(reference)]))
        for t in ADAPTIVE:
            runs["adaptive"].append(render(options.cli, spec, extra, d / f"adaptive{t}.png", d / f"adaptive{t}.json",
                                           options.res, ["--aa", f"adaptive:threshold={t},max_level=4", "--reference",
                                                         str(reference), "--spp-map", str(d / f"adaptive{t}_spp.png")]))
        for w in MIN_WEIGHTS:
            runs["depth"].append(render(options.cli, spec, extra, d / f"weight{w}.png", d / f"weight{w}.json",
                                        options.res, ["--aa", "uniform:n=2", "--max-depth", "8", "--min-weight",
                                                      str(w), "--reference", str(reference)]))
        for shadows in ("any", "closest"):
            runs["shadows"].append(render(options.cli, spec, extra, d / f"shadows_{shadows}.png",
                                          d / f"shadows_{shadows}.json", options.res,
                                          ["--aa", "uniform:n=2", "--shadows", shadows]))
        results[label] = runs
    (out / "fewer_rays.json").write_text(json.dumps(results, indent=1))
    print_tables(results)
    plot(results, out / "fewer_rays.png")


def psnr(run):
    return run["psnr_db"]


def print_tables(results):
    print("\n### Anti-aliasing: rays per pixel against error (reference: uniform 16 x 16)\n")
    print("| scene | sampling | camera rays / pixel | all rays / pixel | PSNR dB | render ms |")
    print("|---|---|---|---|---|---|")
    for label, runs in results.items():
        for n, r in zip(UNIFORM, runs["uniform"]):
            print(f"| {label} | uniform {n}x{n} | {r['samples_per_pixel']:.2f} | {r['rays_per_pixel']:.2f} | "
                  f"{psnr(r):.2f} | {r['render_ms']:.0f} |")
        for t, r in zip(ADAPTIVE, runs["adaptive"]):
            print(f"| {label} | adaptive {t} (max 16x16) | {r['samples_per_pixel']:.2f} | {r['rays_per_pixel']:.2f} "
                  f"| {psnr(r):.2f} | {r['render_ms']:.0f} |")
    print("\n### Adaptive tree depth (uniform 2 x 2, max depth 8)\n")
    print("| scene | min weight | reflection + refraction rays | shadow rays | nodes visited | PSNR dB | render ms |")
    print("|---|---|---|---|---|---|---|")
    for label, runs in results.items():
        for w, r in zip(MIN_WEIGHTS, runs["depth"]):
            print(f"| {label} | {w} | {r['reflection_rays'] + r['refraction_rays']} | {r['shadow_rays']} | "
                  f"{r['nodes_visited']} | {psnr(r):.2f} | {r['render_ms']:.0f} |")
    print("\n### Shadow rays: any hit against closest hit (uniform 2 x 2)\n")
    print("| scene | shadow rays | nodes visited, any hit | nodes visited, closest hit | render ms any / closest |")
    print("|---|---|---|---|---|")
    for label, runs in results.items():
        a, c = runs["shadows"]
        print(f"| {label} | {a['shadow_rays']} | {a['nodes_visited']} | {c['nodes_visited']} | "
              f"{a['render_ms']:.0f} / {c['render_ms']:.0f} |")


def plot(results, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("no matplotlib: plot skipped", file=sys.stderr)
        return
    fig, axes = plt.subplots(2, len(results), figsize=(5 * len(results), 8), squeeze=False)
    for column, (label, runs) in enumerate(results.items()):
        for row, (field, what) in enumerate((("samples_per_pixel", "camera rays per pixel"),
                                              ("rays_per_pixel", "all rays per pixel (shadow, reflection, refraction)"))):
            ax = axes[row][column]
            for kind, marker in (("uniform", "o-"), ("adaptive", "s-")):
                ax.plot([r[field] for r in runs[kind]], [psnr(r) for r in runs[kind]], marker, label=kind)
            ax.set_xscale("log", base=2)
            ax.set_xlabel(what)
            ax.set_ylabel("PSNR against uniform 16 x 16 (dB)")
            ax.set_title(label)
            ax.grid(True, alpha=0.3)
            ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}", file=sys.stderr)


if __name__ == "__main__":
    main()
