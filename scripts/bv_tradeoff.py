#!/usr/bin/python3
"""The bounding volumes' trade-off: tightness against ray-test cost, and what it does to traversal.

Runs (or reads) `rayaccel bench` over every `bvh:bv=` volume on the shared scenes and the built-in slivers scene, and
the kernel benchmark of each volume's ray test; prints one Markdown table (per scene and volume: tightness as the mean
node area over the area of the box of the node's contents, bytes per node, ns per ray test, primary nodes and primitive
tests per ray, primary and diffuse Mrays/s) and writes a plot of tightness against test cost.

    /usr/bin/python3 scripts/bv_tradeoff.py --bench-dir DIR [--kernel-json FILE] [--run] [--plot docs/images/bv_tradeoff.png]

With --run, DIR/<scene>.json and FILE are produced first (one thread, 256 x 256 camera rays, three repetitions;
kernel tests five repetitions); medians are quoted.
"""
import argparse
import json
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared" / "scenes"
VOLUMES = ["aabb", "sphere", "obb", "kdop14", "kdop18", "kdop26", "hull", "capsule"]
SCENES = [("bunny", str(SHARED / "bunny.ply")), ("dragon", str(SHARED / "dragon.ply")),
          ("crytek_sponza", str(SHARED / "crytek_sponza.ply")), ("conference", str(SHARED / "conference.ply")),
          ("slivers", "builtin:slivers")]


def run(bench_dir, kernel_json, build):
    bench_dir.mkdir(parents=True, exist_ok=True)
    accel = ",".join(f"bvh:bv={v}" for v in VOLUMES)
    for name, spec in SCENES:
        subprocess.run([str(build / "bin" / "rayaccel"), "bench", spec, "--accel", accel, "--rays", "primary,diffuse",
                        "--res", "256", "--threads", "1", "--repeat", "3", "--json", str(bench_dir / f"{name}.json")],
                       check=True)
    subprocess.run(["cmake", "--build", str(build), "--target", "rayaccel_kernel_bench"], check=True)
    with open(kernel_json, "w") as out:
        subprocess.run([str(build / "bin" / "rayaccel_kernel_bench"), "--benchmark_filter=ray_test/",
                        "--benchmark_repetitions=5", "--benchmark_format=json"], check=True, stdout=out)


def kernel_figures(kernel_json):
    """Median ns per ray test and bytes per node, by volume."""
    data = json.loads(Path(kernel_json).read_text())
    figures = {}
    for b in data["benchmarks"]:
        if b.get("aggregate_name") != "median" or not b["name"].startswith("ray_test/"):
            continue
        volume = b["name"].split("/")[1].replace("_median", "")
        # An inverted rate counter is written in seconds per item.
        figures[volume] = (b["ns_per_test"] * 1e9, b.get("bytes_per_node"))
    return figures


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--bench-dir", type=Path, required=True)
    parser.add_argument("--kernel-json", type=Path)
    parser.add_argument("--run", action="store_true")
    parser.add_argument("--build", type=Path, default=ROOT / "build")
    parser.add_argument("--plot", type=Path)
    args = parser.parse_args()
    kernel_json = args.kernel_json or args.bench_dir / "kernels.json"
    if args.run:
        run(args.bench_dir, kernel_json, args.build)
    kernels = kernel_figures(kernel_json)
    rows, tightness = [], {v: [] for v in VOLUMES}
    speedup = {v: [] for v in VOLUMES}
    print("| scene | volume | tightness | bytes/node | ns/test | primary nodes/prims per ray | primary Mrays/s | "
          "diffuse Mrays/s |")
    print("|---|---|---|---|---|---|---|---|")
    for name, _ in SCENES:
        path = args.bench_dir / f"{name}.json"
        if not path.exists():
            continue
        results = {r["accel"].split("=")[1]: r for r in json.loads(path.read_text())["scenes"][0]["results"]
                   if r["accel"].startswith("bvh:bv=")}
        base = results["aabb"]["rays"]["primary"]["mrays_s_median"]
        for v in VOLUMES:
            r = results.get(v)
            if r is None:
                continue
            p, d = r["rays"]["primary"], r["rays"]["diffuse"]
            t = r["build_statistics"]["volume_tightness"]
            tightness[v].append(t)
            speedup[v].append(p["mrays_s_median"] / base)
            ns, size = kernels.get(v, (float("nan"), float("nan")))
            print(f"| {name} | {v} | {t:.2f} | {size:.0f} | {ns:.1f} | {p['nodes_per_ray']:.1f} / "
                  f"{p['primitives_tested_per_ray']:.2f} | {p['mrays_s_median']:.3g} | {d['mrays_s_median']:.3g} |")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
        colors = plt.get_cmap("tab10")
        for i, v in enumerate(VOLUMES):
            if v not in kernels or not tightness[v]:
                continue
            ns = kernels[v][0]
            mean_t = sum(tightness[v]) / len(tightness[v])
            left.scatter([ns], [mean_t], color=colors(i), label=v)
            left.annotate(v, (ns, mean_t), textcoords="offset points", xytext=(5, 4 if i % 2 else -11), fontsize=8)
            right.scatter([ns] * len(speedup[v]), speedup[v], s=16, color=colors(i), label=v)
        right.legend(fontsize=7)
        for axis in (left, right):
            axis.set_xscale("log")
        left.set_xlabel("ns per ray/volume test (Google Benchmark, median)")
        left.set_ylabel("node area / area of the contents' box\n(mean over nodes, mean over 5 scenes)")
        left.set_title("tightness against test cost (lower left is better)")
        left.axhline(1.0, color="grey", lw=0.5)
        right.set_xlabel("ns per ray/volume test")
        right.set_ylabel("primary Mrays/s relative to the AABB BVH")
        right.set_title("what it buys: one point per scene")
        right.axhline(1.0, color="grey", lw=0.5)
        fig.suptitle("rayaccel bvh:bv=... (binned SAH, 1 thread, noisy 2-core machine: indicative)", fontsize=9)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)


if __name__ == "__main__":
    main()
