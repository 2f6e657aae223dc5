"""Query controls from Python (skip, skip_geometry, mask / geometry_mask, enabled): each answer equals brute force over
a scene with the ruled-out triangles removed (NaN vertices, ids kept), on a structure with SIMD leaves and on brute
force; bad sizes raise ValueError naming the argument."""
import numpy as np
import pytest

import rayaccel
from conftest import random_rays


def soup(n=600, seed=3):
    rng = np.random.default_rng(seed)
    centers = rng.random((n, 1, 3))
    vertices = (centers + rng.normal(0, 0.06, (n, 3, 3))).reshape(-1, 3)
    return vertices, np.arange(3 * n).reshape(n, 3)


def expected(vertices, triangles, drop, rays):
    """Brute force over the triangles with drop[i] set made invalid (their vertices NaN)."""
    v = vertices.copy().reshape(-1, 3, 3)
    v[np.asarray(drop, bool)] = np.nan
    scene = rayaccel.mesh(v.reshape(-1, 3), triangles, allow_nonfinite=True)
    return rayaccel.build(scene, "brute_force").intersect(rays)


@pytest.mark.parametrize("spec", ["bvh_wide", "kdtree", "brute_force"])
def test_enabled_hides_half(spec):
    vertices, triangles = soup()
    scene = rayaccel.mesh(vertices, triangles)
    rays = random_rays(scene, 2000, seed=4)
    accel = rayaccel.build(scene, spec)
    enabled = (np.arange(len(triangles)) * 2654435761 >> 15) & 1 == 0
    want = expected(vertices, triangles, ~enabled, rays)
    got = accel.intersect(rays, enabled=enabled)
    np.testing.assert_array_equal(got.prim_id, want.prim_id)
    np.testing.assert_array_equal(got.t, want.t)
    np.testing.assert_array_equal(accel.occluded(rays, enabled=enabled), want.prim_id != rayaccel.MISS)
    assert (accel.intersect(rays).prim_id != got.prim_id).any()  # the switches changed answers
    # An opacity array works as well: > 0 is enabled.
    np.testing.assert_array_equal(accel.intersect(rays, enabled=enabled * 0.5).prim_id, want.prim_id)


@pytest.mark.parametrize("spec", ["bvh_wide", "bvh"])
def test_skip_the_first_hit(spec):
    vertices, triangles = soup()
    scene = rayaccel.mesh(vertices, triangles)
    rays = random_rays(scene, 1500, seed=5)
    accel = rayaccel.build(scene, spec)
    first = accel.intersect(rays)
    second = accel.intersect(rays, skip=first.prim_id)
    # Each ray's answer is brute force's with its own first hit removed.
    for i in range(0, len(rays), 50):
        drop = np.zeros(len(triangles), bool)
        if first.prim_id[i] != rayaccel.MISS:
            drop[first.prim_id[i]] = True
        want = expected(vertices, triangles, drop, rays[i:i + 1])
        assert second.prim_id[i] == want.prim_id[0] and second.t[i] == want.t[0], i
    hit = first.prim_id != rayaccel.MISS
    assert (second.prim_id[hit] != first.prim_id[hit]).all()
    assert (second.t[hit] >= first.t[hit]).all()
    np.testing.assert_array_equal(accel.occluded(rays, skip=first.prim_id), second.prim_id != rayaccel.MISS)


def test_masks_and_geometries():
    rng = np.random.default_rng(6)
    parts = [soup(200, seed=s) for s in (7, 8, 9)]
    scene, table = rayaccel.meshes(parts)
    rays = random_rays(scene, 1500, seed=10)
    accel = rayaccel.build(scene, "bvh_wide")
    geometry_mask = np.array([1, 2, 3], np.uint32)
    ray_mask = rng.integers(1, 3, len(rays)).astype(np.uint32)
    hits = accel.intersect(rays, mask=ray_mask, geometry_mask=geometry_mask, geometries=table)
    geom = table.geometry_of(hits.prim_id)
    found = hits.prim_id != rayaccel.MISS
    assert found.any()
    assert ((ray_mask[found] & geometry_mask[geom[found]]) != 0).all()
    # Against brute force over each mask value's visible geometries.
    vertices = np.concatenate([p[0] for p in parts])
    triangles = np.arange(len(vertices)).reshape(-1, 3)
    for m in (1, 2):
        drop = (m & geometry_mask[table.geometry_of(np.arange(len(triangles), dtype=np.uint32))]) == 0
        want = expected(vertices, triangles, drop, rays[ray_mask == m])
        np.testing.assert_array_equal(hits.prim_id[ray_mask == m], want.prim_id)
    # Disabling geometry 2 needs no rebuild: a mask of 0.
    off = accel.intersect(rays, geometry_mask=[~0 & 0xFFFFFFFF, 0xFFFFFFFF, 0], geometries=table)
    assert 2 not in set(table.geometry_of(off.prim_id[off.prim_id != rayaccel.MISS]))
    skip_g = accel.intersect(rays, skip_geometry=np.full(len(rays), 2), geometries=table)
    np.testing.assert_array_equal(skip_g.prim_id, off.prim_id)


@pytest.mark.parametrize("spec", ["bvh_wide", "bvh"])
def test_packets_take_the_same_controls(spec):
    # Camera-like rays in runs of eight (the packet traversal of bvh_wide; bvh traces them one by one) under every
    # control at once give the batch form's answers.
    parts = [soup(200, seed=s) for s in (11, 12)]
    scene, table = rayaccel.meshes(parts)
    accel = rayaccel.build(scene, spec)
    rays = random_rays(scene, 1203, seed=13)
    first = accel.intersect(rays)
    enabled = (np.arange(scene.primitive_count) * 2654435761 >> 13) & 3 != 0
    controls = dict(skip=first.prim_id, mask=np.where(np.arange(len(rays)) % 3 == 0, 1, 3).astype(np.uint32),
                    geometry_mask=[2, 1], geometries=table, enabled=enabled)
    want = accel.intersect(rays, **controls)
    got = accel.intersect(rays, packets=True, **controls)
    np.testing.assert_array_equal(got.prim_id, want.prim_id)
    np.testing.assert_array_equal(got.t, want.t)
    assert (got.prim_id != first.prim_id).any()
    np.testing.assert_array_equal(accel.occluded(rays, packets=True, **controls), want.prim_id != rayaccel.MISS)


def test_geometry_ids_of_a_file_of_several_meshes(tmp_path):
    # Two OBJ objects, a floor and a lamp above part of it: load(geometries=True) numbers them in file order.
    path = tmp_path / "room.obj"
    path.write_text("v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nv 0.5 0.5 1\nv 3 0.5 1\nv 0.5 3 1\n"
                    "o floor\nf 1 2 3\nf 1 3 4\no lamp\nf 5 6 7\n")
    scene, table = rayaccel.load(path, geometries=True)
    assert table.geometry_count == 2 and table.first_primitive(1) == 2
    assert isinstance(rayaccel.load(path), rayaccel.Scene)
    x, y = np.meshgrid(0.25 + 0.5 * np.arange(8), 0.3 + 0.5 * np.arange(8))
    origins = np.stack([x.ravel(), y.ravel(), np.full(x.size, 5.0)], axis=1)
    accel = rayaccel.build(scene, "bvh_wide")
    geom = table.geometry_of(accel.intersect(origins, [0, 0, -1]).prim_id)
    assert set(geom) == {0, 1}
    floor_only = accel.intersect(origins, [0, 0, -1], geometry_mask=[1, 0], geometries=table)
    np.testing.assert_array_equal(table.geometry_of(floor_only.prim_id), 0)


def test_bad_controls_are_named():
    vertices, triangles = soup(50)
    scene = rayaccel.mesh(vertices, triangles)
    accel = rayaccel.build(scene, "bvh_wide")
    rays = random_rays(scene, 10)
    with pytest.raises(ValueError, match="skip has 3 entries, expected 10"):
        accel.intersect(rays, skip=[1, 2, 3])
    with pytest.raises(ValueError, match="enabled has 2 entries, expected 50"):
        accel.occluded(rays, enabled=[True, False])
    with pytest.raises(ValueError, match="geometry_mask has 2 entries, expected 1"):
        accel.intersect(rays, geometry_mask=[1, 2])
    with pytest.raises(TypeError, match="skip must be an array of integers"):
        accel.intersect(rays, skip=np.zeros(10, np.float32))
    with pytest.raises(ValueError, match="not with stats|without stats"):
        accel.intersect(rays, skip=np.zeros(10, np.uint32), stats=True)
    _, table = rayaccel.meshes([soup(5)])
    with pytest.raises(ValueError, match="another scene"):
        accel.intersect(rays, geometries=table)
