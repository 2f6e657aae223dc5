"""Benchmark (not a test): accel.intersect() from Python against `rayaccel trace` on the same 1M rays, structure and
thread count; checks that both give the same .hits bytes before printing any figure.

    PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/intersect_vs_trace.py \
        --cli build/bin/rayaccel --scene ../shared/scenes/bunny.ply --threads 1 2

Ray kinds: primary (a 1000 x 1000 camera image, the CLI's default camera) and diffuse (the bench's cosine bounces
from the hits of larger camera images, the first 1M). Each figure is the median of --repeat passes, as the CLI's.
"""
import argparse
import json
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

import rayaccel


def make_rays(scene, kind, count):
    camera = rayaccel.Camera.framing(scene)
    side = int(np.ceil(np.sqrt(count)))
    if kind == "primary":
        return np.ascontiguousarray(camera.rays(side, side).reshape(-1, 8)[:count])
    accel = rayaccel.build(scene)
    while True:
        primary = camera.rays(side, side).reshape(-1, 8)
        diffuse = rayaccel.diffuse_rays(scene, primary, accel.intersect(primary), seed=1)
        if len(diffuse) >= count:
            return np.ascontiguousarray(diffuse[:count])
        side = int(side * 1.5)


def cli_trace(cli, scene, rays_path, accel, threads, repeat, out):
    run = subprocess.run([cli, "trace", scene, str(rays_path), "--accel", accel, "--threads", str(threads),
                          "--repeat", str(repeat), "--out", str(out)], capture_output=True, text=True, check=True)
    return json.loads(run.stdout.strip().splitlines()[-1])


def python_trace(scene, rays, accel_spec, threads, repeat):
    """Median ms of `repeat` passes of four forms: the (N, 8) array; the same writing into out= (as the CLI reuses
    its hits array); that without the NaN/zero-direction check of the rays (check=False: the CLI checks nothing);
    origins plus directions (which assembles the ray records first). Returns them and the hits."""
    with rayaccel.thread_limit(threads):
        accel = rayaccel.build(scene, accel_spec)
        forms = {
            "rays": lambda: accel.intersect(rays),
            "out": lambda: accel.intersect(rays, out=hits),
            "unchecked": lambda: accel.intersect(rays, out=hits, check=False),
            "parts": lambda: accel.intersect(rays[:, 0:3], rays[:, 4:7], t_min=rays[:, 3], t_max=rays[:, 7]),
        }
        hits = accel.intersect(rays)
        times = {name: [] for name in forms}
        for _ in range(repeat):  # the forms interleaved, so a slow spell of the machine hits them all alike
            for name, call in forms.items():
                start = time.perf_counter()
                call()
                times[name].append((time.perf_counter() - start) * 1e3)
    return {name: statistics.median(t) for name, t in times.items()}, hits


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cli", required=True)
    parser.add_argument("--scene", default="builtin:default")
    parser.add_argument("--accel", default="bvh_wide")
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--kinds", nargs="+", default=["primary", "diffuse"])
    parser.add_argument("--count", type=int, default=1_000_000)
    parser.add_argument("--rounds", type=int, default=3, help="CLI and Python alternate this many times")
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    scene = rayaccel.load(args.scene)
    print(f"scene {scene.name}: {scene.primitive_count} primitives; {args.accel}; {args.count} rays; "
          f"median of {args.repeat} passes; rayaccel {rayaccel.__version__}")
    print(f"{'rays':8} {'threads':>7} {'CLI ms':>8} {'Py ms':>8} {'Py/CLI':>7} {'out= ms':>8} {'unchecked':>9} "
          f"{'(o, d) ms':>9}  (medians over rounds; Py/CLI: median of the rounds' ratios)")
    with tempfile.TemporaryDirectory() as tmp:
        for kind in args.kinds:
            rays = make_rays(scene, kind, args.count)
            rays_path = Path(tmp) / f"{kind}.rays"
            rays.tofile(rays_path)
            for threads in args.threads:
                cli_ms, py, ratios = [], {"rays": [], "out": [], "unchecked": [], "parts": []}, []
                for _ in range(args.rounds):
                    summary = cli_trace(args.cli, args.scene, rays_path, args.accel, threads, args.repeat,
                                        Path(tmp) / "cli.hits")
                    medians, hits = python_trace(scene, rays, args.accel, threads, args.repeat)
                    if hits.tobytes() != (Path(tmp) / "cli.hits").read_bytes():
                        raise SystemExit(f"{kind} rays, {threads} threads: Python and CLI hits differ")
                    cli_ms.append(summary["trace_ms_median"])
                    for name, value in medians.items():
                        py[name].append(value)
                    ratios.append(medians["rays"] / summary["trace_ms_median"])
                med = statistics.median
                print(f"{kind:8} {threads:7d} {med(cli_ms):8.1f} {med(py['rays']):8.1f} {med(ratios):7.3f} "
                      f"{med(py['out']):8.1f} {med(py['unchecked']):9.1f} {med(py['parts']):9.1f}")
    print("every Python result equalled the CLI's .hits byte for byte")


if __name__ == "__main__":
    main()
