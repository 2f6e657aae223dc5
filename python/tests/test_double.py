"""The double-precision path from Python (rayaccel.mesh_double, rayaccel.build_double): agreement with the float path
near the origin, a mesh near 1e7 where double matches exact rational arithmetic (fractions) and float does not, the
.hits64 record layout, and errors naming the argument."""
import threading
from fractions import Fraction

import numpy as np
import pytest

import rayaccel


def centroid_rays(vertices, triangles, seed):
    """(M, 8) float64 rays from random points toward each triangle's centroid, and as many pointing away (misses)."""
    rng = np.random.default_rng(seed)
    centroids = vertices[triangles].mean(axis=1)
    origins = rng.uniform(-3, 3, size=centroids.shape)
    toward = np.zeros((len(centroids), 8))
    toward[:, 0:3] = origins
    toward[:, 4:7] = centroids - origins
    toward[:, 7] = np.inf
    away = toward.copy()
    away[:, 0:3] = centroids * 10 + np.sign(centroids) * 10
    away[:, 4:7] = np.sign(centroids)
    return np.concatenate([toward, away])


@pytest.fixture(scope="module")
def soup_arrays():
    """200 separate triangles in [-1, 1]^3 with float32-exact coordinates (so both paths see the same geometry)."""
    rng = np.random.default_rng(21)
    centers = rng.uniform(-1, 1, size=(200, 1, 3))
    vertices = (centers + rng.uniform(-0.2, 0.2, size=(200, 3, 3))).reshape(-1, 3).astype(np.float32)
    triangles = np.arange(600, dtype=np.int32).reshape(-1, 3)
    return vertices.astype(np.float64), triangles


@pytest.mark.parametrize("spec", ["brute_force", "bvh", "bvh:builder=ploc,leaf_size=2"])
def test_agrees_with_the_float_path_near_the_origin(soup_arrays, spec):
    vertices, triangles = soup_arrays
    rays = centroid_rays(vertices, triangles, 3).astype(np.float32).astype(np.float64)  # float-exact rays
    double_hits = rayaccel.build_double(rayaccel.mesh_double(vertices, triangles), spec).intersect(rays)
    float_hits = rayaccel.build(rayaccel.mesh(vertices.astype(np.float32), triangles), "bvh").intersect(
        rays.astype(np.float32))
    assert double_hits.t.dtype == np.float64 and double_hits.u.dtype == np.float64
    np.testing.assert_array_equal(double_hits.prim_id, float_hits.prim_id)
    assert double_hits.hit.sum() >= len(triangles) and not double_hits.hit[len(triangles):].any()
    hit = double_hits.hit
    # Float's t holds 24 bits: it agrees with double's to float precision (with the kernel's few roundings).
    np.testing.assert_allclose(float_hits.t[hit], double_hits.t[hit], rtol=2.0 ** -16)
    # Double's barycentrics name the point at t on the ray, to double precision (the scene is 2 units across).
    corners = vertices[triangles[double_hits.prim_id[hit]]]
    u, v = double_hits.u[hit, None], double_hits.v[hit, None]
    on_triangle = (1 - u - v) * corners[:, 0] + u * corners[:, 1] + v * corners[:, 2]
    on_ray = rays[hit, 0:3] + double_hits.t[hit, None] * rays[hit, 4:7]
    np.testing.assert_allclose(on_triangle, on_ray, rtol=0, atol=1e-12)
    assert np.all(np.isinf(double_hits.t[~hit])) and np.all(double_hits.prim_id[~hit] == rayaccel.MISS)


def exact_hit(triangle, origin, direction):
    """(t, u, v) of the ray's crossing of the triangle's plane by Cramer's rule in rationals, with o + t d =
    (1-u-v) v0 + u v1 + v v2; None when the crossing lies outside the triangle or behind the origin."""
    v0, v1, v2 = ([Fraction(c) for c in p] for p in triangle)
    o = [Fraction(c) for c in origin]
    d = [Fraction(c) for c in direction]
    e1 = [a - b for a, b in zip(v1, v0)]
    e2 = [a - b for a, b in zip(v2, v0)]
    s = [a - b for a, b in zip(o, v0)]
    det3 = lambda a, b, c: (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                            a[2] * (b[0] * c[1] - b[1] * c[0]))
    minus_d = [-c for c in d]
    det = det3(e1, e2, minus_d)  # s = u e1 + v e2 - t d
    u, v, t = det3(s, e2, minus_d) / det, det3(e1, s, minus_d) / det, det3(e1, e2, s) / det
    return (t, u, v) if u >= 0 and v >= 0 and u + v <= 1 and t > 0 else None


def test_far_from_the_origin_double_matches_fractions_and_float_does_not():
    # Two small triangles near 1e7: float's ulp there is 1, so it rounds the first to a degenerate one (all its x and
    # y round to 1e7) and moves the second; double keeps them.
    base = 1.0e7
    vertices = np.array([[base + 0.1, base + 0.1, 5.0], [base + 0.4, base + 0.1, 5.5], [base + 0.1, base + 0.4, 6.0],
                         [base + 3.1, base + 0.1, 2.0], [base + 3.9, base + 0.2, 2.5], [base + 3.2, base + 0.7, 3.0]])
    triangles = np.array([[0, 1, 2], [3, 4, 5]], dtype=np.int64)
    origins = np.array([[base + 0.2, base + 0.2, 100.0], [base + 3.3, base + 0.3, -50.0], [base + 0.35, base + 0.35,
                                                                                          100.0]])
    directions = np.array([[0.0, 0.0, -1.0], [0.001, 0.002, 1.0], [0.0, 0.0, -1.0]])
    accel = rayaccel.build_double(rayaccel.mesh_double(vertices, triangles))
    hits = accel.intersect(origins, directions)
    expected_prims = [0, 1, rayaccel.MISS]  # the third passes beside the first triangle's hypotenuse
    np.testing.assert_array_equal(hits.prim_id, expected_prims)
    for i, prim in enumerate(expected_prims):
        exact = None if prim == rayaccel.MISS else exact_hit(vertices[triangles[prim]], origins[i], directions[i])
        for p in range(len(triangles)):
            other = exact_hit(vertices[triangles[p]], origins[i], directions[i])
            assert (other is not None) == (p == prim), f"ray {i}, triangle {p}"
        if exact is None:
            continue
        t, u, v = exact
        assert abs(hits.t[i] - float(t)) <= 1e-9 * float(t), f"ray {i}"
        assert abs(hits.u[i] - float(u)) <= 1e-6 and abs(hits.v[i] - float(v)) <= 1e-6, f"ray {i}"
    # The float path with the same arrays (rounded to float32): the first triangle is lost and the second's t is off.
    float_hits = rayaccel.build(rayaccel.mesh(vertices, triangles), "bvh").intersect(origins, directions)
    assert float_hits.prim_id[0] == rayaccel.MISS
    t1 = float(exact_hit(vertices[triangles[1]], origins[1], directions[1])[0])
    assert float_hits.prim_id[1] != 1 or abs(float_hits.t[1] - t1) > 1e-3


def test_ray_forms_records_and_occlusion(soup_arrays):
    vertices, triangles = soup_arrays
    accel = rayaccel.build_double(rayaccel.mesh_double(vertices, triangles), "bvh")
    rays = centroid_rays(vertices, triangles, 5).reshape(2, -1, 8)
    hits = accel.intersect(rays)
    assert hits.t.shape == (2, len(triangles))
    same = accel.intersect(rays[..., 0:3], rays[..., 4:7], t_min=0.0, t_max=np.inf)
    assert same.tobytes() == hits.tobytes()
    assert hits.records.dtype == rayaccel.HIT64_DTYPE and rayaccel.HIT64_DTYPE.itemsize == 32
    raw = hits.records.reshape(-1).view(np.uint8).reshape(-1, 32)
    assert not raw[:, 12:16].any(), "the padding word after prim_id is zero, as in .hits64 files"
    np.testing.assert_array_equal(accel.occluded(rays), hits.hit)
    # t_max just below each hit's t: nothing is found any more (a hit counts when t_min < t <= t_max).
    short = rays.copy()
    short[..., 7] = np.where(hits.hit, np.nextafter(hits.t, 0), np.inf)
    assert not accel.occluded(short).any()
    # Batches release the GIL: threads tracing at once get the same answers.
    results = []
    workers = [threading.Thread(target=lambda: results.append(accel.intersect(rays).tobytes())) for _ in range(4)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert results == [hits.tobytes()] * 4


def test_errors_name_the_argument(soup_arrays):
    vertices, triangles = soup_arrays
    with pytest.raises(TypeError, match="float64"):
        rayaccel.mesh_double(vertices.astype(np.float32), triangles)
    with pytest.raises(ValueError, match=r"vertices must have shape \(N, 3\)"):
        rayaccel.mesh_double(vertices[:, :2].copy(), triangles)
    bad = triangles.copy()
    bad[4, 1] = len(vertices)
    with pytest.raises(ValueError, match=r"triangles\[4, 1\] = 600 is out of range"):
        rayaccel.mesh_double(vertices, bad)
    with pytest.raises(TypeError, match="int32, uint32 or int64"):
        rayaccel.mesh_double(vertices, triangles.astype(np.float64))
    huge = vertices.copy()
    huge[7, 2] = 1e300
    with pytest.raises(ValueError, match="vertex 7"):
        rayaccel.mesh_double(huge, triangles)
    huge[7, 2] = np.nan
    with pytest.raises(ValueError, match="vertex 7"):
        rayaccel.mesh_double(huge, triangles)

    scene = rayaccel.mesh_double(vertices, triangles)
    with pytest.raises(ValueError, match="kdtree"):
        rayaccel.build_double(scene, "kdtree")
    with pytest.raises(ValueError, match="bv must be aabb"):
        rayaccel.build_double(scene, "bvh:bv=obb")
    with pytest.raises(TypeError, match="DoubleScene"):
        rayaccel.build_double(rayaccel.mesh(vertices, triangles))
    with pytest.raises(ValueError, match="not built"):
        rayaccel.DoubleAccelerator("bvh").intersect([[0, 0, 0, 0, 0, 0, 1, np.inf]])

    accel = rayaccel.build_double(scene)
    rays = centroid_rays(vertices, triangles, 9)[:4].copy()
    with pytest.raises(ValueError, match=r"shape \(N, 8\)|shape \(\.\.\., 8\)"):
        accel.intersect(rays[:, :7])
    with pytest.raises(TypeError, match="real numbers"):
        accel.intersect(np.zeros((4, 8), dtype=np.complex128))
    rays[2, 1] = np.nan
    with pytest.raises(ValueError, match="ray 2 has an origin component outside the double domain"):
        accel.intersect(rays)
    rays[2, 1] = 0.0
    rays[2, 4:7] = 0.0
    with pytest.raises(ValueError, match="ray 2 has a zero direction"):
        accel.occluded(rays)
    unchecked = accel.intersect(rays, check=False)
    assert unchecked.prim_id[2] == rayaccel.MISS and unchecked.hit[[0, 1, 3]].all()


def write_ply_double(path, vertices, triangles):
    """A binary little-endian PLY file with `property double` coordinates."""
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\nproperty double x\n"
              f"property double y\nproperty double z\nelement face {len(triangles)}\n"
              "property list uchar int vertex_indices\nend_header\n").encode()
    faces = np.zeros(len(triangles), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"] = 3
    faces["i"] = triangles
    path.write_bytes(header + np.ascontiguousarray(vertices, dtype="<f8").tobytes() + faces.tobytes())


def test_load_double_keeps_a_ply_files_double_coordinates(tmp_path):
    # The far scene of the test above, as a PLY file: load_double() reads its 53-bit coordinates, so it answers as
    # mesh_double() over the same arrays, record for record; the float loader would have lost the first triangle.
    base = 1.0e7
    vertices = np.array([[base + 0.1, base + 0.1, 5.0], [base + 0.4, base + 0.1, 5.5], [base + 0.1, base + 0.4, 6.0],
                         [base + 3.1, base + 0.1, 2.0], [base + 3.9, base + 0.2, 2.5], [base + 3.2, base + 0.7, 3.0]])
    triangles = np.array([[0, 1, 2], [3, 4, 5]], dtype=np.int32)
    path = tmp_path / "far.ply"
    write_ply_double(path, vertices, triangles)
    origins = np.array([[base + 0.2, base + 0.2, 100.0], [base + 3.3, base + 0.3, -50.0]])
    directions = np.array([[0.0, 0.0, -1.0], [0.001, 0.002, 1.0]])
    expected = rayaccel.build_double(rayaccel.mesh_double(vertices, triangles)).intersect(origins, directions)
    assert list(expected.prim_id) == [0, 1]
    for source in (path, str(path)):
        scene = rayaccel.load_double(source)
        assert isinstance(scene, rayaccel.DoubleScene) and len(scene) == 2
        hits = rayaccel.build_double(scene).intersect(origins, directions)
        assert hits.tobytes() == expected.tobytes()
    # offset moves every vertex (in double): the same rays moved by it find the same triangles.
    offset = (-base, -base, 1.0)
    moved = rayaccel.build_double(rayaccel.load_double(path, offset=offset))
    shifted = moved.intersect(origins + np.array(offset), directions)
    np.testing.assert_array_equal(shifted.prim_id, [0, 1])
    np.testing.assert_allclose(shifted.t, expected.t, rtol=1e-9)


def test_load_double_reads_builtins_and_names_its_errors(tmp_path):
    sphere = rayaccel.load("builtin:sphere")
    scene = rayaccel.load_double("builtin:sphere")
    assert len(scene) == len(sphere)
    with pytest.raises(FileNotFoundError, match="missing.ply"):
        rayaccel.load_double(tmp_path / "missing.ply")
    (tmp_path / "empty.ply").write_text("ply\nformat ascii 1.0\nelement vertex 0\nelement face 0\n"
                                         "property list uchar int vertex_indices\nend_header\n")
    with pytest.raises(ValueError, match="empty.ply"):
        rayaccel.load_double(tmp_path / "empty.ply")
    with pytest.raises(ValueError, match="triangle meshes only"):
        rayaccel.load_double("builtin:sphereflake:level=1")
