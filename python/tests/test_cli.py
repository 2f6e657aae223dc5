"""Python results equal the CLI's files byte for byte: `rayaccel trace SCENE RAYS --out` (.hits, .occ, --packets)
on the same scene and rays."""
import json
import subprocess

import numpy as np
import pytest

import rayaccel
from conftest import random_rays


def trace(cli, scene, rays_path, out, *flags):
    run = subprocess.run([cli, "trace", scene, str(rays_path), "--repeat", "1", "--out", str(out), *flags],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("scene_spec", ["builtin:default", "builtin:sphereflake:level=2"])
@pytest.mark.parametrize("spec", ["bvh_wide", "kdtree:builder=sah", "grid"])
def test_hits_equal_the_cli(cli, tmp_path, scene_spec, spec):
    scene = rayaccel.load(scene_spec)
    rays = np.concatenate([random_rays(scene, 3000, seed=5),
                           rayaccel.Camera.framing(scene).rays(40, 30).reshape(-1, 8)])
    rays_path = tmp_path / "in.rays"
    rays.tofile(rays_path)
    accel = rayaccel.build(scene, spec)

    summary = trace(cli, scene_spec, rays_path, tmp_path / "out.hits", "--accel", spec)
    hits = accel.intersect(np.fromfile(rays_path, dtype=np.float32).reshape(-1, 8))
    assert summary["hit_count"] == int(hits.hit.sum()) > 0
    assert hits.tobytes() == (tmp_path / "out.hits").read_bytes()

    trace(cli, scene_spec, rays_path, tmp_path / "out.occ", "--accel", spec, "--occlusion")
    assert accel.occluded(rays).tobytes() == (tmp_path / "out.occ").read_bytes()

    trace(cli, scene_spec, rays_path, tmp_path / "packets.hits", "--accel", spec, "--packets")
    assert accel.intersect(rays, packets=True).tobytes() == (tmp_path / "packets.hits").read_bytes()

    trace(cli, scene_spec, rays_path, tmp_path / "packets.occ", "--accel", spec, "--occlusion", "--packets")
    assert accel.occluded(rays, packets=True).tobytes() == (tmp_path / "packets.occ").read_bytes()


def test_mesh_file_equals_the_cli(cli, tmp_path):
    rng = np.random.default_rng(11)
    vertices = rng.uniform(-1, 1, size=(200, 3)).astype(np.float32)
    triangles = rng.integers(0, 200, size=(150, 3))
    path = tmp_path / "soup.obj"
    path.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in vertices.tolist())
                    + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles))
    scene = rayaccel.mesh(vertices, triangles)
    rays = random_rays(scene, 2000, seed=6)
    rays.tofile(tmp_path / "in.rays")
    trace(cli, str(path), tmp_path / "in.rays", tmp_path / "out.hits")
    expected = (tmp_path / "out.hits").read_bytes()
    assert rayaccel.build(scene).intersect(rays).tobytes() == expected
    assert rayaccel.build(rayaccel.load(path)).intersect(rays).tobytes() == expected


def test_specs_equal_the_cli_list(cli):
    run = subprocess.run([cli, "list", "--names"], capture_output=True, text=True, timeout=60, check=True)
    assert rayaccel.specs() == run.stdout.split()
