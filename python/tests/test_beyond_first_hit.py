"""All hits, closest points, inside tests, signed distances and winding numbers from numpy, against brute force and
closed forms on the cube [-1, 1]^3 (12 triangles): its signed distance and inside-ness are known exactly."""
import numpy as np
import pytest

import rayaccel

CUBE_V = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float32)
# Two triangles per face, counter-clockwise seen from outside (vertex index = 4 x + 2 y + z over {0, 1}).
CUBE_T = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                   [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], dtype=np.int32)


@pytest.fixture(scope="module")
def cube():
    return rayaccel.mesh(CUBE_V, CUBE_T, name="cube")


def cube_signed_distance(p):
    q = np.abs(p) - 1.0
    outside = np.linalg.norm(np.maximum(q, 0.0), axis=-1)
    return outside + np.minimum(q.max(axis=-1), 0.0)


def test_rays_through_vertices_and_edges_cross_the_cube_twice(cube):
    # From outside through every vertex, edge midpoint and face centre, along skew integer directions.
    grid = np.array([[x, y, z] for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1)
                     if (x, y, z) != (0, 0, 0)], dtype=np.float32)
    directions = np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1], [1, 2, 3], [-2, 1, 1]], dtype=np.float32)
    origins = (grid[:, None, :] - 4 * directions[None, :, :]).reshape(-1, 3)
    dirs = np.broadcast_to(directions, (len(grid), 5, 3)).reshape(-1, 3)
    reference = rayaccel.build(cube, "brute_force")
    counts, hits = reference.all_hits(origins, dirs)
    assert np.all(counts % 2 == 0)
    assert np.count_nonzero(counts) > len(counts) // 2
    for spec in ("bvh", "bvh_wide", "bvh:builder=sbvh"):
        other_counts, other_hits = rayaccel.build(cube, spec).all_hits(origins, dirs)
        np.testing.assert_array_equal(other_counts, counts)
        assert other_hits.tobytes() == hits.tobytes()
    np.testing.assert_array_equal(reference.count_hits(origins, dirs), counts)
    capped_counts, capped = reference.all_hits(origins, dirs, max_hits=1)
    np.testing.assert_array_equal(capped_counts, counts)
    assert len(capped) == np.count_nonzero(counts)


def test_closest_points_and_signed_distances_match_the_closed_form(cube):
    rng = np.random.default_rng(3)
    points = rng.uniform(-2, 2, size=(40, 50, 3)).astype(np.float32)
    accel = rayaccel.build(cube, "bvh_wide")
    closest = accel.closest_points(points)
    assert closest.shape == (40, 50) and closest.dtype == rayaccel.CLOSEST_DTYPE
    exact = cube_signed_distance(points.astype(np.float64))
    np.testing.assert_allclose(closest["distance"], np.abs(exact), rtol=1e-6, atol=1e-6)
    reference = rayaccel.build(cube, "brute_force").closest_points(points)
    np.testing.assert_array_equal(closest["distance"], reference["distance"])
    # The closest point lies on the triangle it names, at its barycentrics.
    v = CUBE_V[CUBE_T[closest["prim_id"]]]
    u, w = closest["u"][..., None], closest["v"][..., None]
    np.testing.assert_allclose((1 - u - w) * v[..., 0, :] + u * v[..., 1, :] + w * v[..., 2, :], closest["point"],
                               atol=1e-6)
    off_surface = np.abs(exact) > 1e-3
    np.testing.assert_array_equal(accel.inside(points)[off_surface], (exact < 0)[off_surface])
    signed = accel.signed_distance(points)
    np.testing.assert_allclose(signed[off_surface], exact[off_surface], rtol=1e-6, atol=1e-6)
    winding = rayaccel.winding_numbers(cube, points)
    np.testing.assert_allclose(winding[off_surface], (exact < 0)[off_surface].astype(float), atol=1e-9)
    far = accel.closest_points(np.array([[10, 0, 0]], np.float32), max_distance=1.0)
    assert far["prim_id"][0] == rayaccel.MISS and np.isinf(far["distance"][0])


def test_bad_queries_raise_naming_the_problem(cube):
    with pytest.raises(ValueError, match="kdtree"):
        rayaccel.build(cube, "kdtree").closest_points(np.zeros((1, 3), np.float32))
    accel = rayaccel.build(cube, "bvh")
    with pytest.raises(ValueError, match=r"\(\.\.\., 3\)"):
        accel.inside(np.zeros((4, 2), np.float32))
    with pytest.raises(ValueError, match="point 1"):
        accel.closest_points(np.array([[0, 0, 0], [np.nan, 0, 0]], np.float32))
    with pytest.raises(ValueError, match="ray_count"):
        accel.inside(np.zeros((1, 3), np.float32), ray_count=4)
    with pytest.raises(ValueError, match="spheres"):
        rayaccel.build(rayaccel.spheres(np.zeros((1, 3)), np.ones(1)), "bvh").count_hits(
            np.zeros((1, 3), np.float32), np.ones((1, 3), np.float32))
