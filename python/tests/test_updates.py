"""Accelerator.update() after the scene's arrays move in place, and save / load (issue #20)."""
import numpy as np
import pytest

import rayaccel


def _grid(n=12):
    xs, zs = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
    vertices = np.stack([xs.ravel(), np.zeros(xs.size), zs.ravel()], axis=1).astype(np.float32)
    tris = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            tris += [(a, a + 1, a + n + 1), (a + 1, a + n + 2, a + n + 1)]
    return vertices, np.array(tris, dtype=np.uint32)


def _rays(count=500, seed=1):
    rng = np.random.default_rng(seed)
    origins = rng.uniform(-0.2, 1.2, (count, 3)).astype(np.float32)
    origins[:, 1] = 2.0
    directions = np.tile(np.array([0, -1, 0], np.float32), (count, 1)) + rng.normal(0, 0.2, (count, 3)).astype(np.float32)
    return origins, directions


@pytest.mark.parametrize("spec,expected", [("bvh_wide", "refitted"), ("bvh:bv=obb", "refitted"), ("kdtree", "rebuilt")])
def test_update_after_arrays_moved_matches_brute_force(spec, expected):
    vertices, tris = _grid()
    scene = rayaccel.mesh(vertices, tris, copy=False)
    accel = rayaccel.Accelerator(spec)
    accel.build(scene)
    assert accel.supports_refit == (expected == "refitted")
    origins, directions = _rays()
    for frame in range(1, 4):
        vertices[:, 1] = 0.3 * np.sin(4 * vertices[:, 0] + frame) * np.cos(3 * vertices[:, 2] - frame)
        scene.arrays_changed()
        assert accel.update() == expected
        assert accel.validate() == []
        reference = rayaccel.Accelerator("brute_force")
        reference.build(scene)
        got, want = accel.intersect(origins, directions), reference.intersect(origins, directions)
        np.testing.assert_array_equal(got.prim_id, want.prim_id)
        np.testing.assert_array_equal(got.t, want.t)


def test_save_load_round_trip_and_stale_file(tmp_path):
    vertices, tris = _grid()
    scene = rayaccel.mesh(vertices, tris)
    accel = rayaccel.Accelerator("bvh_wide")
    accel.build(scene)
    path = tmp_path / "grid.wbvh"
    accel.save(str(path))
    loaded = rayaccel.Accelerator("brute_force")
    loaded.load(str(path), scene)
    assert loaded.spec.startswith("bvh_wide")
    origins, directions = _rays()
    np.testing.assert_array_equal(accel.intersect(origins, directions).t, loaded.intersect(origins, directions).t)
    moved = vertices.copy()
    moved[:, 1] += 0.5
    with pytest.raises(ValueError, match="another scene"):
        loaded.load(str(path), rayaccel.mesh(moved, tris))
    with pytest.raises(ValueError, match="does not support"):
        kd = rayaccel.Accelerator("kdtree")
        kd.build(scene)
        kd.save(str(tmp_path / "kd.bin"))
