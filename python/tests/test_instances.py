"""Instanced scenes from Python: answers against brute force over the flattened scene (every instance's vertices
mapped in float64 and rounded to float32, built as one mesh), exact against brute force of each geometry where the
geometries are placed with the identity, disabled instances, moved instances after rebuild_top()/update_top(), and
clear errors for bad transforms and arguments."""
import numpy as np
import pytest

import rayaccel
from conftest import random_rays


def _rotation(axis, angle):
    axis = np.asarray(axis, dtype=np.float64)
    x, y, z = axis / np.linalg.norm(axis)
    c, s, k = np.cos(angle), np.sin(angle), 1 - np.cos(angle)
    return np.array([[c + x * x * k, x * y * k - z * s, x * z * k + y * s],
                     [y * x * k + z * s, c + y * y * k, y * z * k - x * s],
                     [z * x * k - y * s, z * y * k + x * s, c + z * z * k]])


def _random_transform(rng):
    m = np.zeros((3, 4))
    m[:, :3] = _rotation(rng.uniform(-1, 1, 3) + [0, 0, 2], rng.uniform(-3, 3)) @ np.diag(rng.uniform(0.5, 2, 3))
    m[:, 3] = rng.uniform(-6, 6, 3)
    return m


def _uv_sphere(stacks=8, slices=12):
    """Vertices and triangles of a closed UV sphere of radius 1 (shared vertices, one per pole)."""
    theta = np.linspace(0, np.pi, stacks + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, slices, endpoint=False)
    rings = np.stack([np.outer(np.sin(theta), np.cos(phi)), np.outer(np.sin(theta), np.sin(phi)),
                      np.outer(np.cos(theta), np.ones(slices))], axis=-1).reshape(-1, 3)
    vertices = np.vstack([[0, 0, 1], rings, [0, 0, -1]]).astype(np.float32)
    south, triangles = len(vertices) - 1, []
    for j in range(slices):
        k = (j + 1) % slices
        triangles.append([0, 1 + j, 1 + k])
        triangles.append([south, 1 + (stacks - 2) * slices + k, 1 + (stacks - 2) * slices + j])
        for i in range(stacks - 2):
            a, b = 1 + i * slices, 1 + (i + 1) * slices
            triangles += [[a + j, b + j, b + k], [a + j, b + k, a + k]]
    return vertices, np.array(triangles, dtype=np.uint32)


def _meshes():
    """(scene, vertices, triangles) of a closed sphere and of a random soup."""
    rng = np.random.default_rng(4)
    soup_v = rng.uniform(-1, 1, (240, 3)).astype(np.float32)
    soup_t = np.arange(240, dtype=np.uint32).reshape(-1, 3)
    out = []
    for v, t in (_uv_sphere(), (soup_v, soup_t)):
        out.append((rayaccel.mesh(v, t), v, t))
    return out


def _flatten(geometries, placements):
    """One mesh of every (geometry, transform) in placements, and the first flat primitive id of each."""
    vertices, triangles, first, offset, count = [], [], [], 0, 0
    for g, m in placements:
        v, t = geometries[g][1].astype(np.float64), geometries[g][2]
        vertices.append((v @ m[:, :3].T + m[:, 3]).astype(np.float32))
        triangles.append(t.astype(np.int64) + offset)
        first.append(count)
        offset += len(v)
        count += len(t)
    return rayaccel.mesh(np.concatenate(vertices), np.concatenate(triangles)), np.array(first)


def _scene(count, seed):
    rng = np.random.default_rng(seed)
    geometries = _meshes()
    iscene = rayaccel.InstancedScene()
    for g in geometries:
        iscene.add_geometry(g[0])
    placements = []
    for i in range(count):
        m = _random_transform(rng)
        iscene.add_instance(i % len(geometries), m, instance_id=500 + i)
        placements.append((i % len(geometries), m))
    return iscene, geometries, placements


def _compare(accel, geometries, placements, instance_of, rays):
    """The instanced answers against brute force over the flattened scene of placements; instance_of maps a
    placement to the instance index it is. Disagreements are allowed only near a triangle edge (rays grazing an edge
    round differently in the two), under 1% of the rays; where both name one primitive, t agrees to 1e-4."""
    flat, first = _flatten(geometries, placements)
    ref = rayaccel.build(flat, "brute_force").intersect(rays)
    hits = accel.intersect(rays)
    assert type(hits) is rayaccel.Hits and hits.records.dtype == rayaccel.IHIT_DTYPE and hits.shape == (len(rays),)
    got = hits.records
    np.testing.assert_array_equal(accel.occluded(rays), got["prim_id"] != rayaccel.MISS)
    ref_found = ref.prim_id != rayaccel.MISS
    placement = np.searchsorted(first, ref.prim_id, side="right") - 1
    ref_instance = np.where(ref_found, np.asarray(instance_of)[np.clip(placement, 0, None)], rayaccel.MISS)
    ref_prim = np.where(ref_found, ref.prim_id - first[np.clip(placement, 0, None)], rayaccel.MISS)
    same = (got["instance_id"] == np.where(ref_found, ref_instance + 500, rayaccel.MISS)) & (got["prim_id"] == ref_prim)
    got_found = got["prim_id"] != rayaccel.MISS
    near_edge = (ref_found & (np.minimum(np.minimum(ref.u, ref.v), 1 - ref.u - ref.v) < 1e-3)) | \
                (got_found & (np.minimum(np.minimum(got["u"], got["v"]), 1 - got["u"] - got["v"]) < 1e-3))
    assert np.all(same | near_edge)
    assert np.count_nonzero(~same) <= len(rays) // 100
    both = same & ref_found
    assert np.count_nonzero(both) > len(rays) // 4
    np.testing.assert_allclose(got["t"][both], ref.t[both], rtol=1e-4, atol=1e-5)
    miss = got["prim_id"] == rayaccel.MISS
    assert np.all(np.isinf(got["t"][miss])) and np.all(got["geom_id"][miss] == rayaccel.MISS)
    return got


def _rays(seed, count=3000):
    rng = np.random.default_rng(seed)
    rays = np.zeros((count, 8), dtype=np.float32)
    rays[:, 0:3] = rng.uniform(-14, 14, (count, 3))
    rays[:, 4:7] = rng.uniform(-7, 7, (count, 3)) - rays[:, 0:3]
    rays[:, 7] = np.inf
    return rays


def test_matches_flattened_brute_force():
    iscene, geometries, placements = _scene(20, 1)
    accel = rayaccel.build_instanced(iscene, bottom="bvh")
    assert accel.validate() == []
    got = _compare(accel, geometries, placements, range(20), _rays(2))
    hit = got["prim_id"] != rayaccel.MISS
    np.testing.assert_array_equal(got["geom_id"][hit], (got["instance_id"][hit] - 500) % 2)
    # origins and directions give the same answers as the ray array
    rays = _rays(2)
    np.testing.assert_array_equal(accel.intersect(rays[:, 0:3], rays[:, 4:7]).records, got)


@pytest.mark.parametrize("top", ["bvh_top", "bvh_wide", "kdtree"])
def test_top_level_structures_match_flattened_brute_force(top):
    iscene, geometries, placements = _scene(20, 3)
    accel = rayaccel.build_instanced(iscene, bottom="bvh_wide", top=top)
    assert accel.top == top and accel.validate() == []
    _compare(accel, geometries, placements, range(20), _rays(4))
    with pytest.raises(ValueError, match="no_such_top"):
        rayaccel.build_instanced(iscene, top="no_such_top")


def test_identity_geometries_side_by_side_equal_brute_force_of_each():
    geometries = [_meshes()[1][0], random_spheres()]
    iscene = rayaccel.InstancedScene()
    for g in geometries:
        iscene.add_instance(iscene.add_geometry(g))  # the identity
    accel = rayaccel.build_instanced(iscene)
    rays = random_rays(geometries[0], 3000, seed=5)
    got = accel.intersect(rays)
    refs = [rayaccel.build(g, "brute_force").intersect(rays) for g in geometries]
    closest = np.minimum(refs[0].t, refs[1].t)
    np.testing.assert_array_equal(got["t"], closest)  # the world ray itself: bit for bit
    for g, ref in enumerate(refs):
        mine = (got["geom_id"] == g) & (got["t"] == ref.t) & np.isfinite(ref.t)
        np.testing.assert_array_equal(got["prim_id"][mine], ref.prim_id[mine])
        assert np.count_nonzero(got["geom_id"] == g) > 50
    np.testing.assert_array_equal(got["instance_id"], got["geom_id"])


def random_spheres():
    rng = np.random.default_rng(3)
    return rayaccel.spheres(rng.uniform(-1, 1, (100, 3)), rng.uniform(0.02, 0.1, 100))


def test_disabled_instances_are_never_hit():
    iscene, geometries, placements = _scene(20, 3)
    accel = rayaccel.build_instanced(iscene, bottom="bvh_wide")
    enabled = [i for i in range(20) if i % 3]
    for i in range(20):
        accel.set_enabled(i, i % 3 != 0)
    assert [accel.is_enabled(i) for i in range(20)] == [i % 3 != 0 for i in range(20)]
    _compare(accel, geometries, [placements[i] for i in enabled], enabled, _rays(4))
    for i in range(20):
        accel.set_enabled(i, True)
    _compare(accel, geometries, placements, range(20), _rays(5, 1000))
    with pytest.raises(ValueError, match="instance 20 is out of range"):
        accel.set_enabled(20, False)


@pytest.mark.parametrize("update", ["rebuild_top", "update_top"])
def test_moved_instances(update):
    iscene, geometries, placements = _scene(20, 6)
    accel = rayaccel.build_instanced(iscene)
    rng = np.random.default_rng(7)
    for i in range(0, 20, 2):
        m = _random_transform(rng)
        iscene.set_transform(i, np.vstack([m, [0, 0, 0, 1]]))  # (4, 4) accepted
        placements[i] = (placements[i][0], m)
        np.testing.assert_array_equal(iscene.transform(i), m)
    result = getattr(accel, update)()
    if update == "update_top":
        assert result == "refitted"
    assert accel.validate() == []
    _compare(accel, geometries, placements, range(20), _rays(8))


def test_bad_input_is_a_clear_error():
    iscene = rayaccel.InstancedScene()
    g = iscene.add_geometry(rayaccel.builtin("sphere", level=1))
    with pytest.raises(ValueError, match="last row must be 0 0 0 1"):
        iscene.add_instance(g, np.eye(4) * 2)
    with pytest.raises(ValueError, match=r"shape \(3, 4\) or \(4, 4\), not \(3, 3\)"):
        iscene.add_instance(g, np.eye(3))
    with pytest.raises(ValueError, match="instance 0: transform is singular"):
        iscene.add_instance(g, np.zeros((3, 4)))
    with pytest.raises(ValueError, match="geometry index 1 is out of range"):
        iscene.add_instance(1)
    with pytest.raises(TypeError):
        iscene.add_instance(g, "identity")
    with pytest.raises(TypeError):
        iscene.add_geometry(None)
    with pytest.raises(TypeError, match="InstancedScene"):
        rayaccel.build_instanced(rayaccel.builtin("sphere"))
    with pytest.raises(ValueError, match="no_such_structure"):
        rayaccel.InstancedAccelerator("no_such_structure")
    with pytest.raises(ValueError, match="not built"):
        rayaccel.InstancedAccelerator().intersect(_rays(1, 4))
    assert iscene.instance_count == 0  # failed calls add nothing
    iscene.add_instance(g, instance_id=42)
    accel = rayaccel.build_instanced(iscene)
    with pytest.raises(ValueError, match="another InstancedScene"):
        accel.build(rayaccel.InstancedScene())
    bad = _rays(1, 4)
    bad[2, 4:7] = np.nan
    with pytest.raises(ValueError, match="ray 2"):
        accel.intersect(bad)
    assert accel.intersect(bad, check=False)["prim_id"][2] == rayaccel.MISS
    hit = accel.intersect(np.array([[0, 0, -5, 0, 0, 0, 1, np.inf]], dtype=np.float32))
    assert hit["instance_id"][0] == 42 and hit["geom_id"][0] == 0


def test_one_result_type_and_the_other_queries_through_flatten():
    """Instanced hits are the plain accelerator's Hits type with geom_id and instance_id besides; the queries a
    two-level structure does not answer raise NotImplementedError naming what works, and flatten() gives the one
    triangle scene to answer them with."""
    iscene, geometries, placements = _scene(6, 9)
    accel = rayaccel.build_instanced(iscene)
    rays = _rays(3, 800)
    hits, plain = accel.intersect(rays), rayaccel.build(geometries[0][0]).intersect(rays)
    assert type(hits) is type(plain) is rayaccel.Hits and hits.shape == plain.shape == (800,)
    for field in rayaccel.IHIT_DTYPE.names:
        np.testing.assert_array_equal(getattr(hits, field), hits.records[field])
        np.testing.assert_array_equal(hits[field], hits.records[field])
    assert 0 < np.count_nonzero(hits.hit) < 800 and len(hits.tobytes()) == 800 * 24
    with pytest.raises(AttributeError, match="instanced"):
        plain.geom_id
    points = np.random.default_rng(2).uniform(-8, 8, (300, 3))
    for query, args in (("closest_points", (points,)), ("inside", (points,)), ("signed_distance", (points,)),
                        ("all_hits", (rays,)), ("count_hits", (rays,))):
        with pytest.raises(NotImplementedError, match=rf"{query}\(\) .*intersect\(\) and occluded\(\).*flatten"):
            getattr(accel, query)(*args)

    flat = iscene.flatten()
    ref, _ = _flatten(geometries, placements)
    np.testing.assert_array_equal(flat.vertices, ref.vertices)
    np.testing.assert_array_equal(flat.triangles, ref.triangles)
    np.testing.assert_array_equal(rayaccel.build(flat).closest_points(points)["distance"],
                                  rayaccel.build(ref, "brute_force").closest_points(points)["distance"])
    assert rayaccel.InstancedScene().flatten().primitive_count == 0
    spheres = rayaccel.InstancedScene()
    spheres.add_instance(spheres.add_geometry(random_spheres()))
    with pytest.raises(ValueError, match="instance 0 places a spheres geometry"):
        spheres.flatten()
