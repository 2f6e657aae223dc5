"""Benchmark (not a test): rayaccel.dask on a distributed.LocalCluster of 1 and 2 worker processes against one local
accel.intersect; prints the per-worker build cost, the cold and warm throughput and the bytes each run moves.

    PYTHONPATH=build/python /usr/bin/python3 python/benchmarks/dask_throughput.py \
        --scene ../shared/scenes/bunny.ply --rays 4000000 --chunk 250000 --workers 1 2

Rays: the CLI's default camera over the scene (a square image of --rays pixels), made on the client and persisted on
the cluster once (32 bytes a ray, timed as "send"), so that a warm run times tracing plus the 16-byte records coming
back to the client; "kept" times the same tracing with the records left on the workers (only their hit count comes
back), as when results are written or reduced where they are made. Each worker has one Dask thread and --tbb-threads
TBB threads. Cold: the first run, each worker loading the scene and building once; warm and kept: the median of
--repeat runs on the cached structures. Every result is checked against the local one, byte for byte (the hit
count, for kept), before any figure is printed.
"""
import argparse
import json
import statistics
import time

import numpy as np

import dask.array as da
import distributed

import rayaccel
import rayaccel.dask as rd


def timed(function):
    start = time.perf_counter()
    value = function()
    return value, time.perf_counter() - start


def run_cluster(args, rays, expected, expected_hits):
    with distributed.LocalCluster(n_workers=args.workers_now, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None, silence_logs=40) as cluster, \
            distributed.Client(cluster) as client:
        client.run(lambda: rayaccel.set_threads(args.tbb_threads))  # (a pybind11 function cannot be pickled)
        start = time.perf_counter()
        lazy = client.persist(da.from_array(rays, chunks=(args.chunk, 8)))
        distributed.wait(lazy)
        send_s = time.perf_counter() - start
        hits = rd.intersect(args.scene, lazy, args.spec)
        found, cold_s = timed(hits.compute)
        assert found.tobytes() == expected, "cluster result differs from the local one"
        infos = list(client.run(rd.cache_info).values())
        count = (hits["prim_id"] != rayaccel.MISS).sum()
        warm, kept = [], []
        for _ in range(args.repeat):
            found, seconds = timed(hits.compute)
            assert found.tobytes() == expected, "cluster result differs from the local one"
            warm.append(seconds)
            hit_count, seconds = timed(count.compute)
            assert hit_count == expected_hits
            kept.append(seconds)
        return dict(workers=args.workers_now, send_s=send_s, cold_s=cold_s, warm_s=statistics.median(warm),
                    kept_s=statistics.median(kept),
                    builds=[i["builds"] for i in infos], build_s=[round(i["build_s"], 4) for i in infos])


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scene", required=True)
    parser.add_argument("--spec", default="bvh_wide")
    parser.add_argument("--rays", type=int, default=4_000_000)
    parser.add_argument("--chunk", type=int, default=250_000)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--tbb-threads", type=int, default=1, help="TBB threads in each worker (and locally)")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    scene, load_s = timed(lambda: rayaccel.load(args.scene))
    side = int(np.ceil(np.sqrt(args.rays)))
    rays = np.ascontiguousarray(rayaccel.Camera.framing(scene).rays(side, side).reshape(-1, 8)[:args.rays])
    rayaccel.set_threads(args.tbb_threads)
    accel, build_s = timed(lambda: rayaccel.build(scene, args.spec))
    local = []
    for _ in range(args.repeat):
        hits, seconds = timed(lambda: accel.intersect(rays))
        local.append(seconds)
    expected = hits.records.tobytes()
    local_s = statistics.median(local)
    print(f"scene {args.scene}: {len(scene)} primitives, {scene.memory_bytes / 1e6:.1f} MB in memory; "
          f"{len(rays)} camera rays ({rays.nbytes / 1e6:.0f} MB), chunks of {args.chunk}, spec {args.spec}, "
          f"{args.tbb_threads} TBB thread(s) per process")
    print(f"local: load {load_s * 1e3:.0f} ms, build {build_s * 1e3:.0f} ms, intersect {local_s * 1e3:.0f} ms "
          f"= {len(rays) / local_s / 1e6:.2f} Mrays/s")
    results = [dict(workers=0, load_s=load_s, build_s=build_s, warm_s=local_s)]
    for workers in args.workers:
        args.workers_now = workers
        r = run_cluster(args, rays, expected, int(np.count_nonzero(hits.hit)))
        results.append(r)
        print(f"{workers} worker(s): send rays {r['send_s'] * 1e3:.0f} ms "
              f"({rays.nbytes / r['send_s'] / 1e6:.0f} MB/s), "
              f"cold {r['cold_s'] * 1e3:.0f} ms, warm {r['warm_s'] * 1e3:.0f} ms = "
              f"{len(rays) / r['warm_s'] / 1e6:.2f} Mrays/s, kept on the workers {r['kept_s'] * 1e3:.0f} ms = "
              f"{len(rays) / r['kept_s'] / 1e6:.2f} Mrays/s ({len(rays) / r['kept_s'] / workers / 1e6:.2f} per worker)"
              f", builds per worker {r['builds']}, load+build s per worker {r['build_s']}")
    print(json.dumps(dict(scene=args.scene, rays=len(rays), chunk=args.chunk, spec=args.spec,
                          tbb_threads=args.tbb_threads, results=results)))


if __name__ == "__main__":
    main()
