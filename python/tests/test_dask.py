"""rayaccel.dask: results equal to local tracing, bit for bit, on Dask's local schedulers and on a two-process
distributed.LocalCluster (loopback only), whatever the chunking; one build per process; clear errors on the client;
a worker killed mid-run loses nothing. Skipped when dask (or, for the cluster tests, distributed) is missing, unless
RAYACCEL_REQUIRE_DASK=1 is set (.ci/run sets it; scripts/setup.sh installs both): then a missing one fails the run."""
import importlib
import os
import signal
import threading
import time

import numpy as np
import pytest



def require(module, reason):
    """The module; when it is missing, a skip naming `reason`, or under RAYACCEL_REQUIRE_DASK=1 an ImportError."""
    if os.environ.get("RAYACCEL_REQUIRE_DASK") == "1":
        return importlib.import_module(module)
    return pytest.importorskip(module, reason=reason)


require("dask.array", "dask is not installed (Debian python3-dask; scripts/setup.sh installs it)")
import dask  # noqa: E402
import dask.array as da  # noqa: E402

import rayaccel  # noqa: E402
import rayaccel.dask as rd  # noqa: E402
from conftest import random_rays  # noqa: E402

# Debian's tornado warns inside distributed's own event loop set-up; not ours to fix.
pytestmark = pytest.mark.filterwarnings("ignore:make_current is deprecated:DeprecationWarning")
SPEC = "bvh_wide"
BUILTIN = "builtin:sphere:level=3"


@pytest.fixture(scope="module")
def soup_arrays():
    rng = np.random.default_rng(11)
    vertices = rng.uniform(-1, 1, size=(500, 3)).astype(np.float32)
    triangles = rng.integers(0, len(vertices), size=(400, 3)).astype(np.uint32)
    return vertices, triangles


@pytest.fixture(scope="module")
def ply_path(tmp_path_factory, soup_arrays):
    """The soup as a binary little-endian PLY file."""
    vertices, triangles = soup_arrays
    path = tmp_path_factory.mktemp("dask") / "soup.ply"
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\nproperty float x\n"
              f"property float y\nproperty float z\nelement face {len(triangles)}\n"
              f"property list uchar uint vertex_indices\nend_header\n").encode()
    faces = np.zeros(len(triangles), dtype=[("n", "u1"), ("i", "<u4", 3)])
    faces["n"], faces["i"] = 3, triangles
    path.write_bytes(header + vertices.astype("<f4").tobytes() + faces.tobytes())
    return str(path)


def local_answers(scene, rays, spec=SPEC):
    accel = rayaccel.build(scene, spec)
    return accel.intersect(rays).records, accel.occluded(rays)


def assert_same(dask_records, dask_blocked, records, blocked):
    assert dask_records.dtype == rayaccel.HIT_DTYPE and dask_records.shape == records.shape
    assert dask_records.tobytes() == records.tobytes()
    assert dask_blocked.dtype == np.bool_ and np.array_equal(dask_blocked, blocked)


@pytest.mark.parametrize("scheduler", ["synchronous", "threads"])
@pytest.mark.parametrize("chunks", [5000, 1237, (1, 0, 2999, 2000)])
def test_local_schedulers_match_local_tracing(scheduler, chunks):
    scene = rayaccel.load(BUILTIN)
    rays = random_rays(scene, 5000, seed=3)
    records, blocked = local_answers(scene, rays)
    lazy = da.from_array(rays, chunks=(chunks, 8))
    hits, occ = rd.intersect(BUILTIN, lazy, SPEC), rd.occluded(BUILTIN, lazy, SPEC)
    assert hits.chunks == (lazy.chunks[0],) and occ.chunks == (lazy.chunks[0],)
    assert_same(*dask.compute(hits, occ, scheduler=scheduler), records, blocked)
    assert np.array_equal(hits["t"].compute(scheduler=scheduler), records["t"])


def test_every_source_kind_and_spec(soup_arrays, ply_path):
    rays = random_rays(rayaccel.mesh(*soup_arrays), 3000, seed=4)
    lazy = da.from_array(rays, chunks=(700, 4))  # split across columns too: joined before tracing
    for spec in ("bvh_wide", "kdtree", "grid", "bvh:bv=obb"):
        for source, scene in ((soup_arrays, rayaccel.mesh(*soup_arrays)), (ply_path, rayaccel.load(ply_path)),
                              (rayaccel.load(ply_path), rayaccel.load(ply_path))):
            records, blocked = local_answers(scene, rays, spec)
            found = dask.compute(rd.intersect(source, lazy, spec), rd.occluded(source, lazy, spec),
                                 scheduler="synchronous")
            assert_same(*found, records, blocked)
    # float64 rays and packets: as the local call
    wide = rays.astype(np.float64)
    accel = rayaccel.build(rayaccel.mesh(*soup_arrays))
    assert rd.intersect(soup_arrays, da.from_array(wide, chunks=(1000, 8))).compute().tobytes() == \
        accel.intersect(wide).records.tobytes()
    assert rd.intersect(soup_arrays, da.from_array(rays, chunks=(1000, 8)), packets=True).compute().tobytes() == \
        accel.intersect(rays, packets=True).records.tobytes()


def test_processes_scheduler(soup_arrays):
    rays = random_rays(rayaccel.mesh(*soup_arrays), 4000, seed=5)
    records, blocked = local_answers(rayaccel.mesh(*soup_arrays), rays)
    lazy = da.from_array(rays, chunks=(1000, 8))
    found = dask.compute(rd.intersect(soup_arrays, lazy), rd.occluded(soup_arrays, lazy), scheduler="processes",
                         num_workers=2)
    assert_same(*found, records, blocked)


def test_threads_build_once_per_process():
    rd.clear_cache()
    scene = rayaccel.load(BUILTIN)
    rays = random_rays(scene, 16000, seed=6)
    records = rd.intersect(BUILTIN, da.from_array(rays, chunks=(1000, 8)), "kdtree").compute(
        scheduler="threads", num_workers=4)
    assert records.tobytes() == rayaccel.build(scene, "kdtree").intersect(rays).records.tobytes()
    info = rd.cache_info()
    assert (info["builds"], info["chunks"], info["rays"]) == (1, 16, 16000)

    # Eight threads asking at once for a structure nobody built yet: one build, one object for all.
    source = rd.SceneSource.of("builtin:soup:count=20000")
    barrier, got = threading.Barrier(8), []

    def ask():
        barrier.wait()
        got.append(rd.accelerator(source, "bvh"))

    threads = [threading.Thread(target=ask) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(got) == 8 and all(a is got[0] for a in got)
    assert rd.cache_info()["builds"] == 2


def test_cache_is_a_bounded_lru():
    rd.clear_cache()
    previous = rd.set_cache_size(2)
    try:
        source = rd.SceneSource.of(BUILTIN)
        first = rd.accelerator(source, "bvh_wide")
        rd.accelerator(source, "kdtree")
        assert rd.accelerator(source, "bvh_wide") is first  # used last, so grid evicts kdtree
        rd.accelerator(source, "grid")
        info = rd.cache_info()
        assert (info["builds"], info["evictions"], info["limit"]) == (3, 1, 2)
        assert [spec for spec, _ in info["entries"]] == ["bvh_wide", "grid"]
        rd.accelerator(source, "kdtree")
        assert rd.cache_info()["builds"] == 4
        with pytest.raises(ValueError, match="at least one"):
            rd.set_cache_size(0)
    finally:
        rd.set_cache_size(previous)


def test_client_side_errors(tmp_path, soup_arrays):
    rays = da.zeros((100, 8), chunks=(50, 8), dtype=np.float32)
    with pytest.raises(FileNotFoundError, match="no/such/scene.ply"):
        rd.intersect("no/such/scene.ply", rays)
    with pytest.raises(FileNotFoundError, match="not a file"):
        rd.occluded(str(tmp_path), rays)
    with pytest.raises(ValueError, match="nonsense"):
        rd.intersect(BUILTIN, rays, spec="nonsense")
    with pytest.raises(ValueError):
        rd.intersect(BUILTIN, rays, spec="bvh:bv=nonsense")
    with pytest.raises(ValueError, match="unknown built-in scene 'nope'"):
        rd.intersect("builtin:nope", rays)
    with pytest.raises(ValueError, match="no parameter 'lvl'"):
        rd.intersect("builtin:sphere:lvl=3", rays)
    with pytest.raises(ValueError, match="out of range"):
        rd.intersect((soup_arrays[0], soup_arrays[1] + 1000), rays)
    with pytest.raises(TypeError, match="mesh path"):
        rd.intersect(42, rays)
    with pytest.raises(TypeError, match="cannot be sent"):
        rd.intersect(rayaccel.mesh(*soup_arrays), rays)
    with pytest.raises(ValueError, match=r"shape \(N, 8\)"):
        rd.intersect(BUILTIN, da.zeros((100, 7), chunks=(50, 7), dtype=np.float32))
    with pytest.raises(TypeError, match="float32 or float64"):
        rd.intersect(BUILTIN, rays.astype(np.int32))
    with pytest.raises(TypeError, match="dask array"):
        rd.intersect(BUILTIN, [[0.0] * 8])


@pytest.mark.filterwarnings("ignore:rayaccel. no ray of this batch:UserWarning")  # zero rays, on purpose
def test_worker_side_errors_reach_the_client(tmp_path):
    garbage = tmp_path / "garbage.ply"
    garbage.write_text("this is not a mesh\n")
    rays = da.from_array(np.zeros((10, 8), dtype=np.float32), chunks=(5, 8))
    with pytest.raises(ValueError):
        rd.intersect(str(garbage), rays).compute(scheduler="synchronous")
    with pytest.raises(ValueError, match="level"):  # a bad value is only found by the worker that loads it
        rd.intersect("builtin:sphere:level=banana", rays).compute(scheduler="threads")
    with pytest.raises(ValueError):  # zero-length directions: refused as locally
        rd.occluded(BUILTIN, rays).compute(scheduler="synchronous")
    assert rd.occluded(BUILTIN, rays, check=False).compute(scheduler="synchronous").tolist() == [False] * 10


def test_saved_structure_is_loaded_not_built(tmp_path, ply_path):
    """structure=PATH: every process loads the file saved once (load()'s scene check included) instead of building."""
    scene = rayaccel.load(ply_path)
    rays = random_rays(scene, 3000, seed=12)
    accel = rayaccel.build(scene, "bvh_wide")
    saved = tmp_path / "soup.bvhw"
    accel.save(str(saved))
    lazy = da.from_array(rays, chunks=(1000, 8))
    rd.clear_cache()
    found = dask.compute(rd.intersect(ply_path, lazy, structure=saved),
                         rd.occluded(ply_path, lazy, structure=str(saved)), scheduler="threads")
    assert_same(*found, accel.intersect(rays).records, accel.occluded(rays))
    info = rd.cache_info()
    assert (info["builds"], info["loads"], info["chunks"]) == (0, 1, 6) and info["load_s"] > 0
    rd.intersect(ply_path, lazy).compute(scheduler="synchronous")
    assert (rd.cache_info()["builds"], rd.cache_info()["loads"]) == (1, 1)  # without it: built, as before

    other = tmp_path / "soup.bvh"
    rayaccel.build(scene, "bvh").save(str(other))
    assert rd.intersect(ply_path, lazy, spec="bvh", structure=other).compute(scheduler="synchronous").tobytes() == \
        rayaccel.build(scene, "bvh").intersect(rays).records.tobytes()
    # On the client: a spec that names another structure, a missing file, a file that is not a saved structure.
    with pytest.raises(ValueError, match=r"holds 'bvh.*not 'bvh_wide'.*pass spec='bvh'"):
        rd.intersect(ply_path, lazy, structure=other)
    with pytest.raises(FileNotFoundError, match="structure file .*missing.bvh"):
        rd.occluded(ply_path, lazy, structure=tmp_path / "missing.bvh")
    with pytest.raises(ValueError, match="soup.ply' is not one"):
        rd.intersect(ply_path, lazy, structure=ply_path)
    with pytest.raises(TypeError, match="structure must be the path"):
        rd.intersect(ply_path, lazy, structure=42)
    # On the worker: saved over another scene (load()'s check), and the spec when the client did not read the file.
    with pytest.raises(ValueError, match="soup.bvhw"):
        rd.intersect(BUILTIN, lazy, structure=saved).compute(scheduler="synchronous")
    with pytest.raises(ValueError, match=r"holds 'bvh"):
        rd.intersect(ply_path, lazy, structure=other, check_source=False).compute(scheduler="synchronous")


def test_task_names_and_progress_bar(capsys):
    from dask.diagnostics import ProgressBar
    from dask.utils import key_split
    rays = da.from_array(random_rays(rayaccel.load(BUILTIN), 400), chunks=(100, 8))
    hits = rd.intersect(BUILTIN, rays)
    assert key_split(hits.name) == "rayaccel-intersect" and key_split(rd.occluded(BUILTIN, rays).name) == \
        "rayaccel-occluded"
    graph = dict(hits.__dask_graph__())
    assert sum(1 for k in graph if isinstance(k, str) and k.startswith("rayaccel-scene-")) == 1
    assert hits.name == rd.intersect(BUILTIN, rays).name  # deterministic: same inputs, same keys
    with ProgressBar():
        hits.compute(scheduler="synchronous")
    assert "100%" in capsys.readouterr().out


# --- distributed.LocalCluster: two worker processes, one thread each, loopback only ---------------------------------

@pytest.fixture(scope="module")
def client():
    distributed = require("distributed", "distributed is not installed (Debian python3-distributed; scripts/setup.sh)")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None, silence_logs=50) as cluster, \
            distributed.Client(cluster) as c:
        yield c


def worker_infos(client):
    return list(client.run(rd.cache_info).values())


def slow_block(block):
    """Passes block through after a pause, so that a run lasts long enough to lose a worker in the middle."""
    time.sleep(0.15)
    return block


@pytest.mark.parametrize("chunks", [20000, 6000, 777])
def test_cluster_matches_local_tracing_and_builds_once(client, chunks):
    scene = rayaccel.load(BUILTIN)
    rays = random_rays(scene, 20000, seed=8)
    records, blocked = local_answers(scene, rays)
    client.run(rd.clear_cache)
    lazy = da.from_array(rays, chunks=(chunks, 8))
    found = dask.compute(rd.intersect(BUILTIN, lazy), rd.occluded(BUILTIN, lazy))
    assert_same(*found, records, blocked)
    infos = worker_infos(client)
    assert sum(i["chunks"] for i in infos) == 2 * lazy.numblocks[0] and sum(i["rays"] for i in infos) == 40000
    assert all(i["builds"] == (1 if i["chunks"] else 0) for i in infos)  # one structure per worker, every chunk


def test_cluster_arrays_reach_each_worker_once(client, soup_arrays, capsys):
    from distributed import progress
    rays = random_rays(rayaccel.mesh(*soup_arrays), 12000, seed=9)
    records, blocked = local_answers(rayaccel.mesh(*soup_arrays), rays)
    client.run(rd.clear_cache)
    lazy = da.from_array(rays, chunks=(1000, 8))
    hits, occ = rd.intersect(soup_arrays, lazy), rd.occluded(soup_arrays, lazy)
    persisted = client.persist([hits, occ])
    progress(persisted)  # distributed's text progress bar
    assert "100% Completed" in capsys.readouterr().out
    assert_same(*dask.compute(*persisted), records, blocked)
    infos = worker_infos(client)
    assert sum(i["chunks"] for i in infos) == 24 and all(i["builds"] <= 1 for i in infos)
    # The arrays are one task of the graph (a key every chunk depends on), not an argument of each chunk's task.
    graph = dict(hits.__dask_graph__())
    scene_keys = [k for k in graph if isinstance(k, str) and k.startswith("rayaccel-scene-")]
    assert len(scene_keys) == 1
    assert all(scene_keys[0] in task for k, task in graph.items() if isinstance(k, tuple) and k[0] == hits.name)


def test_cluster_loads_a_saved_structure_once_per_worker(client, tmp_path, ply_path):
    scene = rayaccel.load(ply_path)
    accel = rayaccel.build(scene)
    saved = tmp_path / "cluster.bvhw"
    accel.save(str(saved))
    rays = random_rays(scene, 8000, seed=13)
    client.run(rd.clear_cache)
    found = rd.intersect(ply_path, da.from_array(rays, chunks=(1000, 8)), structure=saved).compute()
    assert found.tobytes() == accel.intersect(rays).records.tobytes()
    infos = worker_infos(client)
    assert sum(i["chunks"] for i in infos) == 8
    assert all(i["builds"] == 0 and i["loads"] == (1 if i["chunks"] else 0) for i in infos)


def test_cluster_errors_are_raised_on_the_client(client, tmp_path):
    rays = da.from_array(np.ones((10, 8), dtype=np.float32), chunks=(5, 8))
    with pytest.raises(FileNotFoundError):
        rd.intersect(str(tmp_path / "missing.ply"), rays)
    with pytest.raises(ValueError):
        rd.intersect(BUILTIN, rays, spec="bvh:builder=nope")
    garbage = tmp_path / "garbage.obj"
    garbage.write_text("v 0 0 0\nf 1 2 3\n")  # an index past the vertices: the worker's load fails
    future = client.compute(rd.intersect(str(garbage), rays))
    with pytest.raises(ValueError):
        future.result(timeout=30)


def test_cluster_worker_killed_mid_run(client):
    """One worker is killed (SIGKILL) while it holds finished chunks; they are recomputed and the answer is whole."""
    scene = rayaccel.load(BUILTIN)
    rays = random_rays(scene, 24000, seed=10)
    records, _ = local_answers(scene, rays)
    client.run(rd.clear_cache)
    lazy = da.from_array(rays, chunks=(1000, 8)).map_blocks(slow_block, dtype=rays.dtype)
    hits = rd.intersect(BUILTIN, lazy)
    future = client.compute(hits)
    victim, deadline = None, time.monotonic() + 30
    while victim is None and time.monotonic() < deadline:
        for worker, keys in client.has_what().items():
            if any(hits.name in str(k) for k in keys):
                victim = worker
                break
        time.sleep(0.02)
    assert victim is not None and not future.done(), "no worker held a finished chunk while the run went on"
    before = client.run(rd.cache_info, workers=[victim])[victim]
    os.kill(before["pid"], signal.SIGKILL)
    found = future.result(timeout=60)
    assert found.tobytes() == records.tobytes()
    client.wait_for_workers(2, timeout=30)  # the nanny started a new process in its place
    after = worker_infos(client)
    assert before["pid"] not in [i["pid"] for i in after]
    # The victim's finished chunks died with it and were traced again elsewhere: more chunks traced than exist.
    assert before["chunks"] + sum(i["chunks"] for i in after) > lazy.numblocks[0]
