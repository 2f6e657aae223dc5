"""Queries: ray forms (the .rays layout, origins and directions, leading shapes), results (t, prim_id, u, v, points,
normals, statistics), occlusion, packets, threads and the GIL."""
import threading

import numpy as np
import pytest

import rayaccel
from conftest import random_rays

TRI_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], dtype=np.float32)
TRI_T = np.array([[0, 1, 2]], dtype=np.int32)


@pytest.fixture(scope="module")
def triangle():
    return rayaccel.build(rayaccel.mesh(TRI_V, TRI_T), "bvh_wide")


def test_results_of_one_triangle(triangle):
    origins = np.array([[0.25, 0.5, 2], [2, 2, 2]], np.float32)
    directions = np.array([[0, 0, -2], [0, 0, -1]], np.float32)
    hits = triangle.intersect(origins, directions, points=True, normals=True)
    np.testing.assert_array_equal(hits.t, [1.0, np.inf])
    np.testing.assert_array_equal(hits.prim_id, [0, rayaccel.MISS])
    np.testing.assert_allclose([hits.u[0], hits.v[0]], [0.25, 0.5], atol=1e-7)  # p = (1-u-v) v0 + u v1 + v v2
    np.testing.assert_array_equal([hits.u[1], hits.v[1]], [0, 0])
    np.testing.assert_array_equal(hits.hit, [True, False])
    np.testing.assert_allclose(hits.points[0], [0.25, 0.5, 0], atol=1e-7)
    np.testing.assert_array_equal(hits.normals[0], [0, 0, 1])
    assert np.isnan(hits.points[1]).all() and np.isnan(hits.normals[1]).all()
    assert hits.records.dtype == rayaccel.HIT_DTYPE and len(hits.tobytes()) == 32
    assert np.shares_memory(hits.t, hits.records)  # the fields are views of the records, not copies


def test_t_range_is_exclusive_below_inclusive_above(triangle):
    o, d = np.array([0.2, 0.2, 1], np.float32), np.array([[0, 0, -1]] * 3, np.float32)
    hits = triangle.intersect(o, d, t_min=np.array([0, 1, 0], np.float32), t_max=np.array([1, 2, 0.5], np.float32))
    np.testing.assert_array_equal(hits.prim_id, [0, rayaccel.MISS, rayaccel.MISS])
    np.testing.assert_array_equal(triangle.occluded(o, d, t_min=0.0, t_max=np.array([1, 2, 0.5])), [True, True, False])


def test_ray_layout_and_shapes(soup):
    accel = rayaccel.build(soup)
    rays = random_rays(soup, 600).reshape(20, 30, 8)
    hits = accel.intersect(rays)
    assert hits.t.shape == (20, 30) and accel.occluded(rays).shape == (20, 30)
    flat = accel.intersect(rays.reshape(-1, 8))
    parts = accel.intersect(rays[..., 0:3], rays[..., 4:7], t_min=rays[..., 3], t_max=rays[..., 7])
    f64 = accel.intersect(rays.astype(np.float64))
    strided = accel.intersect(np.concatenate([rays, rays], axis=-1)[..., :8])
    for other in (flat, parts, f64, strided):
        assert other.tobytes() == hits.tobytes()
    occ = accel.occluded(rays)
    np.testing.assert_array_equal(occ, hits.hit & (hits.t <= rays[..., 7]))
    assert occ.dtype == np.bool_


def test_rays_read_in_place():
    rays = np.zeros((10, 8), np.float32)
    assert rayaccel._core._ray_buffer_address(rays) == rays.ctypes.data  # float32 C-contiguous: no copy
    as64 = rays.astype(np.float64)
    assert rayaccel._core._ray_buffer_address(as64) != as64.ctypes.data


def test_one_origin_for_many_directions(soup):
    accel = rayaccel.build(soup)
    rng = np.random.default_rng(3)
    directions = rng.normal(size=(100, 3)).astype(np.float32)
    a = accel.intersect(np.zeros(3, np.float32), directions)
    b = accel.intersect(np.zeros((100, 3), np.float32), directions)
    assert a.tobytes() == b.tobytes()


def test_statistics(soup):
    rays = random_rays(soup, 500)
    hits = rayaccel.build(soup, "brute_force").intersect(rays, stats=True)
    valid = soup.valid_count
    # brute force tests every valid primitive of every ray
    np.testing.assert_array_equal(hits.stats.primitives_tested, np.full(500, valid))
    tree = rayaccel.build(soup, "bvh")
    h = tree.intersect(rays, stats=True)
    assert h.tobytes() == tree.intersect(rays).tobytes()
    assert (h.stats.nodes_visited > 0).any() and h.stats.cost.dtype == np.uint64
    occ, stats = tree.occluded(rays, stats=True)
    np.testing.assert_array_equal(occ, tree.occluded(rays))
    assert (stats.cost <= h.stats.cost).mean() > 0.5  # any-hit stops early


def test_packets_give_the_same_hits(soup):
    accel = rayaccel.build(soup, "bvh_wide")
    rays = rayaccel.Camera.framing(soup).rays(40, 24)
    a, b = accel.intersect(rays), accel.intersect(rays, packets=True)
    np.testing.assert_array_equal(a.t, b.t)
    assert (a.prim_id == b.prim_id).mean() > 0.99  # a tie in t may name another primitive


def test_occlusion_packets_give_the_same_answers(soup):
    accel = rayaccel.build(soup, "bvh_wide")
    camera = rayaccel.Camera.framing(soup).rays(40, 24).reshape(-1, 8)
    order = rayaccel.packet_tile_order(40, 24)
    rays = camera[order]
    hits = accel.intersect(rays)
    rays[1::2, 7] = np.where(hits.hit[1::2], hits.t[1::2] * 0.5, np.inf)  # every other ray ends before its hit
    single = accel.occluded(rays)
    assert 0 < single.sum() < len(rays)
    np.testing.assert_array_equal(accel.occluded(rays, packets=True), single)
    np.testing.assert_array_equal(accel.occluded(rays[:-3], packets=True), single[:-3])  # a partial last packet
    with pytest.raises(ValueError, match="packets=True gives no per-ray statistics"):
        accel.occluded(rays, packets=True, stats=True)


def test_threads_and_gil(soup):
    accel = rayaccel.build(soup, "bvh_wide")
    rays = random_rays(soup, 20000)
    reference = accel.intersect(rays).tobytes()
    with rayaccel.thread_limit(1):
        assert rayaccel.threads() == 1
        assert accel.intersect(rays).tobytes() == reference
    assert rayaccel.threads() >= 1
    results = []
    workers = [threading.Thread(target=lambda: results.append(accel.intersect(rays).tobytes())) for _ in range(4)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert results == [reference] * 4


def test_rebuild_and_validate(soup):
    accel = rayaccel.Accelerator("kdtree:builder=sah")
    assert not accel.built and "not built" in repr(accel)
    accel.build(soup)
    assert accel.built and accel.scene is soup
    assert accel.validate() == [] and accel.memory_bytes > 0 and accel.build_ms >= 0
    assert isinstance(accel.build_statistics(), dict)
    accel.build(rayaccel.builtin("sphere", level=1))
    assert accel.scene.primitive_count == 80


def test_camera_render_and_heatmap(soup):
    accel = rayaccel.build(soup)
    camera = rayaccel.Camera.framing(soup)
    rays = camera.rays(32, 16)
    assert rays.shape == (16, 32, 8) and rays.dtype == np.float32
    np.testing.assert_allclose(np.linalg.norm(rays[..., 4:7], axis=-1), 1, rtol=1e-6)
    custom = rayaccel.Camera(eye=(0, 0, 5), at=(0, 0, 0), up=(0, 1, 0), fov=30)
    centre = custom.rays(3, 3)[1, 1]
    np.testing.assert_allclose(centre[4:7], [0, 0, -1], atol=1e-6)
    for mode in ("normals", "ao", "heatmap"):
        image = rayaccel.render(accel, camera, 24, 20, mode=mode)
        assert image.shape == (20, 24, 3) and image.dtype == np.uint8
    cost = accel.intersect(rays, stats=True).stats.cost
    colours = rayaccel.heatmap(cost)
    assert colours.shape == (16, 32, 3) and colours.dtype == np.uint8
    shared = rayaccel.heatmap(cost, vmin=0, vmax=10 * cost.max())
    assert shared.astype(int).sum() < colours.astype(int).sum()  # a wider shared scale is darker


def test_secondary_rays(soup):
    accel = rayaccel.build(soup)
    rays = rayaccel.Camera.framing(soup).rays(32, 32)
    hits = accel.intersect(rays)
    diffuse = rayaccel.diffuse_rays(soup, rays, hits, seed=2)
    shadow = rayaccel.shadow_rays(soup, rays, hits, max_distance=0.5, seed=2)
    assert diffuse.shape == shadow.shape == (int(hits.hit.sum()), 8)
    assert (shadow[:, 7] == np.float32(0.5)).all() and np.isinf(diffuse[:, 7]).all()
    assert accel.occluded(shadow).dtype == np.bool_


def test_out_reuses_the_records(soup):
    accel = rayaccel.build(soup)
    rays = random_rays(soup, 300)
    first = accel.intersect(rays)
    expected = first.tobytes()
    again = accel.intersect(rays, out=first)
    assert np.shares_memory(again.records, first.records) and again.tobytes() == expected
    with pytest.raises(ValueError, match="out must hold one writable"):
        accel.intersect(rays[:10], out=first)
    with pytest.raises(TypeError, match="out must be the Hits"):
        accel.intersect(rays, out=np.zeros((300, 16), np.uint8))


def test_empty_batches_and_single_rays(triangle):
    assert triangle.intersect(np.zeros((0, 8), np.float32)).t.shape == (0,)
    assert triangle.occluded(np.zeros((0, 3)), np.zeros((0, 3))).shape == (0,)
    one = triangle.intersect(np.array([0.2, 0.2, 1, 0, 0, 0, -1, np.inf], np.float32), points=True, stats=True)
    assert one.t.shape == () and one.t == 1.0 and one.points.shape == (3,) and one.stats.cost.shape == ()
    assert triangle.occluded(np.array([0.2, 0.2, 1.0]), np.array([0, 0, -1.0])) == np.True_


def test_packets_in_tile_order(soup):
    accel = rayaccel.build(soup, "bvh_wide")
    rays = rayaccel.Camera.framing(soup).rays(30, 21).reshape(-1, 8)
    order = rayaccel.packet_tile_order(30, 21)
    assert sorted(order) == list(range(30 * 21))
    tiled = accel.intersect(rays[order], packets=True)
    np.testing.assert_array_equal(tiled.t, accel.intersect(rays).t[order])


def test_queries_while_another_thread_rebuilds(soup):
    accel = rayaccel.build(soup, "bvh_wide")
    rays = random_rays(soup, 5000)
    expected = accel.intersect(rays).tobytes()
    other = rayaccel.builtin("sphere", level=2)
    errors = []

    def rebuild():
        try:
            for scene in (other, soup) * 3:
                accel.build(scene)
        except Exception as error:  # noqa: BLE001 - reported below
            errors.append(error)

    worker = threading.Thread(target=rebuild)
    worker.start()
    while worker.is_alive():  # each query runs under one build or the next, never during one
        hits = accel.intersect(rays)
        assert hits.t.shape == (5000,) and accel.scene.name in ("sphere", "soup")
    worker.join()
    assert not errors and accel.scene is soup and accel.intersect(rays).tobytes() == expected
