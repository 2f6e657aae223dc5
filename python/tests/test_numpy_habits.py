"""Inputs as numpy users pass them (issue #37): array-likes and integer arrays everywhere, numpy broadcasting of
origins, directions, t_min and t_max, Open3D's (N, 6) ray layout, and a UserWarning for a batch whose t ranges admit
no hit (a zero t_max column, or columns in np.hstack([o, d, t_min, t_max]) order)."""
import warnings

import numpy as np
import pytest

import rayaccel

QUAD_V = np.array([[-2, -2, 0], [2, -2, 0], [2, 2, 0], [-2, 2, 0]], dtype=np.float32)
QUAD_T = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)
# Rays with whole-number coordinates: hit at t = 3, miss, hit at t = 1, hit from below at t = 4.
ORIGINS = np.array([[0, 0, 3], [3, 3, 3], [-1, 0, 5], [1, 0, -4]], dtype=np.float32)
DIRECTIONS = np.array([[0, 0, -1], [0, 0, -1], [1, 0, -5], [0, 0, 1]], dtype=np.float32)


@pytest.fixture(scope="module")
def accel():
    return rayaccel.build(rayaccel.mesh(QUAD_V, QUAD_T))


def rays8(origins=ORIGINS, directions=DIRECTIONS, t_min=0.0, t_max=np.inf, dtype=np.float32):
    out = np.zeros((len(origins), 8), dtype)
    out[:, 0:3], out[:, 3], out[:, 4:7], out[:, 7] = origins, t_min, directions, t_max
    return out


@pytest.fixture(autouse=True)
def no_stray_warnings():
    """Every call of these tests that is not meant to warn must not."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        yield


def test_array_likes_and_integers_are_cast(accel):
    ref = accel.intersect(rays8())
    assert ref.hit.tolist() == [True, False, True, True]
    same = [accel.intersect(rays8().tolist()),                      # a list of lists, (N, 8)
            accel.intersect(rays8(t_max=100, dtype=np.int64)),      # integers: cast to float32
            accel.intersect(rays8(t_max=100, dtype=np.int16)),
            accel.intersect(ORIGINS.tolist(), DIRECTIONS.astype(np.int32)),
            accel.intersect(ORIGINS.tolist(), DIRECTIONS.tolist(), 0, [100, 100, 100, 100])]
    for hits in same:
        assert type(hits) is rayaccel.Hits and hits.tobytes() == ref.tobytes()
    assert accel.occluded(rays8().tolist()).tolist() == ref.hit.tolist()
    assert accel.count_hits(rays8(t_max=9, dtype=np.int32)).tolist() == ref.hit.astype(int).tolist()
    counts, records = accel.all_hits(rays8().tolist())
    assert counts.tolist() == [1, 0, 1, 1] and len(records) == 3

    points = [[0, 0, 0], [0.5, 0.5, 2], [5, 5, 5]]
    cp = accel.closest_points(points)
    np.testing.assert_array_equal(cp, accel.closest_points(np.array(points, np.float32)))
    np.testing.assert_array_equal(accel.closest_points([[0, 0, 0]])["distance"], [0.0])
    np.testing.assert_array_equal(accel.closest_points(np.array([[0, 0, 2]], np.int64))["distance"], [2.0])
    assert accel.inside([[0, 0, 0]]).shape == (1,) and accel.inside([0, 0, 1]).shape == ()
    np.testing.assert_array_equal(accel.inside(points), accel.inside(np.array(points, np.float32)))
    np.testing.assert_array_equal(accel.signed_distance(points), accel.signed_distance(np.array(points, np.float32)))
    np.testing.assert_array_equal(rayaccel.winding_numbers(accel.scene, points),
                                  rayaccel.winding_numbers(accel.scene, np.array(points, np.float32)))
    with pytest.raises(TypeError, match="real numbers"):
        accel.closest_points([["a", "b", "c"]])
    with pytest.raises(TypeError, match="real numbers"):
        accel.intersect(rays8().astype(np.complex64))


def test_scenes_from_array_likes():
    ref = rayaccel.build(rayaccel.mesh(QUAD_V, QUAD_T)).intersect(rays8())
    for vertices, triangles in ((QUAD_V.tolist(), QUAD_T.tolist()), (QUAD_V.astype(np.int64), QUAD_T)):
        assert rayaccel.build(rayaccel.mesh(vertices, triangles)).intersect(rays8()).tobytes() == ref.tobytes()
    balls = rayaccel.spheres([[0, 0, 0], [3, 0, 0]], [1, 2])
    np.testing.assert_array_equal(balls.radii, [1, 2])
    assert rayaccel.spheres([[0, 0, 0]], 1).radii.tolist() == [1.0]


def test_double_path_keeps_float64_and_casts_integers_to_it():
    big = 2**24 + 1  # not a float32: the double path must keep it
    vertices = np.array([[big, 0, 0], [big + 4, 0, 0], [big, 4, 0]], np.int64)
    scene = rayaccel.mesh_double(vertices, [[0, 1, 2]])
    accel = rayaccel.build_double(scene)
    ints = np.array([[big + 1, 1, 5, 0, 0, 0, -1, 100]], np.int64)
    wide = accel.intersect(ints.astype(np.float64))
    assert wide.hit[0] and wide.t.dtype == np.float64
    assert accel.intersect(ints).tobytes() == wide.tobytes() == accel.intersect(ints.tolist()).tobytes()
    with pytest.raises(TypeError, match="float64"):
        rayaccel.mesh_double(vertices.astype(np.float32), [[0, 1, 2]])  # float32 vertices lost their bits already


def test_broadcasting_follows_numpy(accel):
    ref = accel.intersect(rays8())
    one_direction = np.array([0, 0, -1], np.float32)
    a = accel.intersect(ORIGINS, one_direction)                   # (N, 3) origins, one (3,) direction
    b = accel.intersect(ORIGINS, np.broadcast_to(one_direction, ORIGINS.shape))
    assert a.tobytes() == b.tobytes() and a.shape == (4,)
    assert accel.intersect(ORIGINS[0], DIRECTIONS).shape == (4,)  # one origin, (N, 3) directions
    # t bounds broadcast too: one t_max per ray, or one for all
    t_max = np.array([10, 10, 10, 1], np.float32)
    assert accel.intersect(ORIGINS, DIRECTIONS, 0, t_max).hit.tolist() == [True, False, True, False]
    assert accel.intersect(ORIGINS, DIRECTIONS, t_max=[[2], [4]]).shape == (2, 4)  # (2, 1) against (4,)
    # a grid: (5, 1, 3) origins against (7, 3) directions is a (5, 7) batch, each pair a ray
    origins = np.stack([np.linspace(-2, 2, 5), np.zeros(5), np.full(5, 3.0)], axis=-1)[:, None, :]
    directions = np.stack([np.zeros(7), np.linspace(-1, 1, 7), -np.ones(7)], axis=-1)
    grid = accel.intersect(origins, directions)
    assert grid.shape == (5, 7)
    for i in range(5):
        np.testing.assert_array_equal(grid.t[i], accel.intersect(origins[i, 0], directions).t)
    # t_min and t_max alone may give the batch its shape
    assert accel.intersect(ORIGINS[0], DIRECTIONS[0], t_max=np.full((2, 3), 9.0)).shape == (2, 3)
    assert ref.tobytes() == accel.intersect(ORIGINS, DIRECTIONS, t_min=np.zeros(4)).tobytes()


@pytest.mark.parametrize("origins, directions, kwargs", [
    (np.zeros((2, 3)), np.ones((3, 3)), {}),
    (np.zeros((4, 3)), np.ones(3), {"t_max": np.ones(3)}),
    (np.zeros(3), np.ones((4, 3)), {"t_min": np.zeros((2, 3))}),
])
def test_shapes_that_do_not_broadcast(accel, origins, directions, kwargs):
    for query in (accel.intersect, accel.occluded, accel.count_hits):
        with pytest.raises(ValueError, match="do not broadcast together.*shape mismatch"):
            query(origins, directions, **kwargs)


def test_open3d_layout(accel):
    """(N, 6) rays are Open3D's: origin then direction, t from 0 to inf; t_min and t_max may be given with them."""
    ref = accel.intersect(ORIGINS, DIRECTIONS)
    rays6 = np.hstack([ORIGINS, DIRECTIONS])
    assert accel.intersect(rays6).tobytes() == ref.tobytes()
    assert accel.intersect(rays6.reshape(2, 2, 6)).shape == (2, 2)
    assert accel.intersect(rays6.tolist()).tobytes() == ref.tobytes()
    np.testing.assert_array_equal(accel.occluded(rays6), ref.hit)
    assert accel.intersect(rays6, t_max=2).hit.tolist() == [False, False, True, False]
    instanced = rayaccel.InstancedScene()
    instanced.add_instance(instanced.add_geometry(accel.scene))
    assert rayaccel.build_instanced(instanced).intersect(rays6).t.tolist() == ref.t.tolist()


def test_warns_about_a_t_max_left_at_zero(accel):
    zero_t_max = rays8(t_max=0.0)  # a zero-filled array with origins and directions written in
    with pytest.warns(UserWarning, match=r"no ray of this batch of 4 has t_max > t_min.*t_min is column 3 and "
                                         r"t_max column 7") as caught:
        assert not accel.intersect(zero_t_max).hit.any()
    assert caught[0].filename == __file__  # attributed to the caller, not to rayaccel's code
    with pytest.warns(UserWarning, match="no ray of this batch"):
        accel.occluded(zero_t_max)
    with pytest.warns(UserWarning, match=r"no ray of this batch of 4 has t_max > t_min.*\(t_min \(\) min 0.0"):
        accel.intersect(ORIGINS, DIRECTIONS, t_max=0)
    with pytest.warns(UserWarning, match="no ray"):
        accel.intersect(ORIGINS, DIRECTIONS, t_min=5, t_max=np.array([1, 2, 3, 4]))
    # One usable ray anywhere in the batch, even far past the first ones looked at, is enough: no warning.
    many = np.repeat(zero_t_max, 2000, axis=0)
    many[-1, 7] = np.inf
    assert accel.intersect(many).hit.sum() == 1
    accel.intersect(np.zeros((0, 8), np.float32))  # an empty batch is not suspicious


def test_warns_about_hstack_column_order(accel):
    """np.hstack([o, d, t_min, t_max]) with unit directions: the .rays layout reads dx as t_min; that misses where
    the right layout hits, and says so."""
    rng = np.random.default_rng(1)
    targets = np.column_stack([rng.uniform(-1, 1, (500, 2)), np.zeros(500)]).astype(np.float32)
    origins = targets + rng.normal(size=(500, 3)).astype(np.float32) * [1, 1, 0] + [0, 0, 3]
    d = targets - origins
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    wrong = np.hstack([origins, d, np.zeros((500, 1)), np.full((500, 1), np.inf)]).astype(np.float32)
    right = accel.intersect(origins, d)
    assert right.hit.all()
    with pytest.warns(UserWarning, match=r"looks like directions in the t_min column.*t_min is column 3 and t_max "
                                         r"column 7.*np.hstack"):
        assert accel.intersect(wrong).hit.sum() < 500
    accel.intersect(rays8(origins, d))  # the same rays in the right layout: no warning
