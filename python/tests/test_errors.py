"""Every bad input raises TypeError, ValueError or FileNotFoundError with a message naming the problem; none crashes
or answers silently wrong."""
import numpy as np
import pytest

import rayaccel

V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
T = np.array([[0, 1, 2]], np.uint32)
RAY = np.array([[0.2, 0.2, 1, 0, 0, 0, -1, np.inf]], np.float32)


@pytest.fixture(scope="module")
def accel():
    return rayaccel.build(rayaccel.mesh(V, T))


@pytest.mark.parametrize("vertices, triangles, error, message", [
    (V.astype(np.complex64), T, TypeError, "vertices must be real numbers .*, not complex64"),
    (V.astype(str), T, TypeError, "vertices must be real numbers"),
    ([[0, 0, 0], [1, 0]], T, ValueError, "inhomogeneous"),  # numpy's own error for a ragged list
    (V[:, :2], T, ValueError, r"vertices must have shape \(N, 3\), not \(3, 2\)"),
    (V.ravel(), T, ValueError, r"not \(9,\)"),
    (V, T.astype(np.float32), TypeError, "triangles must be int32, uint32 or int64, not float32"),
    (V, T.astype(np.int16), TypeError, "int16"),
    (V, T[:, :2], ValueError, r"triangles must have shape \(M, 3\)"),
    (V, np.array([[0, 1, 3]], np.int64), ValueError, r"triangles\[0, 2\] = 3 is out of range: there are 3 vertices"),
    (V, np.array([[0, -1, 2]], np.int32), ValueError, r"triangles\[0, 1\] = -1 is out of range"),
    (V, np.array([[0, 1, 2**32]], np.int64), ValueError, "out of range"),
    (np.array([[0, 0, 0], [1, np.inf, 0], [0, 1, 0]]), T, ValueError, r"vertices\[1\] is not finite"),
])
def test_bad_mesh(vertices, triangles, error, message):
    with pytest.raises(error, match=message):
        rayaccel.mesh(vertices, triangles)


def test_bad_spheres():
    with pytest.raises(ValueError, match="radii must be finite and > 0"):
        rayaccel.spheres(np.zeros((2, 3)), np.array([1.0, -1.0]))
    with pytest.raises(ValueError, match=r"radii must have shape \(2,\)"):
        rayaccel.spheres(np.zeros((2, 3)), np.ones(3))
    with pytest.raises(ValueError, match=r"centers\[0\] is not finite"):
        rayaccel.spheres(np.full((1, 3), np.nan), 1.0)
    with pytest.raises(ValueError, match="radii must be finite"):
        rayaccel.spheres(np.zeros((1, 3)), float("nan"))


def test_bad_scene_specs(tmp_path):
    with pytest.raises(FileNotFoundError, match="no_such.ply"):
        rayaccel.load(tmp_path / "no_such.ply")
    with pytest.raises(FileNotFoundError):
        rayaccel.load(tmp_path)  # a directory
    junk = tmp_path / "junk.ply"
    junk.write_bytes(b"not a mesh at all")
    with pytest.raises(ValueError, match="junk.ply"):
        rayaccel.load(junk)
    with pytest.raises(ValueError, match="no_such_scene"):
        rayaccel.load("builtin:no_such_scene")
    with pytest.raises(ValueError, match="level"):
        rayaccel.builtin("sphere", level=99)
    with pytest.raises(ValueError, match="bogus"):
        rayaccel.builtin("sphere", bogus=1)


def test_bad_specs():
    scene = rayaccel.mesh(V, T)
    with pytest.raises(ValueError, match="no_such_structure"):
        rayaccel.build(scene, "no_such_structure")
    with pytest.raises(ValueError, match="bogus"):
        rayaccel.build(scene, "bvh:bogus=1")
    with pytest.raises(ValueError, match="builder"):
        rayaccel.build(scene, "kdtree:builder=nonsense")
    with pytest.raises(TypeError, match="rayaccel.Scene"):
        rayaccel.build(V, "bvh")
    with pytest.raises(TypeError):
        rayaccel.Accelerator("bvh").build(None)


def test_unbuilt_structure():
    accel = rayaccel.Accelerator("bvh_wide")
    for query in (accel.intersect, accel.occluded):
        with pytest.raises(ValueError, match="'bvh_wide' is not built"):
            query(RAY)
    with pytest.raises(ValueError, match="not built"):
        accel.validate()
    with pytest.raises(ValueError, match="not built"):
        accel.memory_bytes
    with pytest.raises(ValueError, match="not built"):
        rayaccel.render(accel, width=8, height=8)


@pytest.mark.parametrize("args, kwargs, error, message", [
    (([["a"] * 8],), {}, TypeError, "rays must be real numbers"),
    ((np.zeros((1, 8), np.complex64),), {}, TypeError, r"rays must be real numbers \(float or integer\), not complex64"),
    ((RAY[:, :7],), {}, ValueError, r"rays must have shape \(\.\.\., 8\)"),
    ((RAY,), {"t_max": 1.0}, TypeError, "t_min and t_max are columns"),
    ((np.zeros((2, 3)), np.zeros((3, 3))), {}, ValueError, r"origins \(2, 3\), directions \(3, 3\), t_min \(\) and "
                                                          r"t_max \(\) do not broadcast together"),
    ((np.zeros(3), np.zeros((2, 2))), {}, ValueError, r"directions must have shape \(\.\.\., 3\)"),
    ((np.zeros(3), np.ones((2, 3), bool)), {}, TypeError, "directions must be real numbers .*, not bool"),
    ((np.zeros(3), np.ones((2, 3))), {"t_max": np.ones(3)}, ValueError, r"t_max \(3,\) do not broadcast together"),
    ((np.zeros(3), np.ones((2, 3))), {"t_min": "x"}, TypeError, "t_min must be real numbers"),
])
def test_bad_ray_arrays(accel, args, kwargs, error, message):
    for query in (accel.intersect, accel.occluded):
        with pytest.raises(error, match=message):
            query(*args, **kwargs)


@pytest.mark.parametrize("column, value, message", [
    (0, np.nan, "ray 1 has a NaN or infinite origin"),
    (5, np.inf, "ray 1 has a NaN or infinite direction"),
    (3, np.nan, "ray 1 has a NaN t_min"),
    (7, np.nan, "ray 1 has a NaN t_max"),
])
def test_bad_ray_values(accel, column, value, message):
    rays = np.repeat(RAY, 3, axis=0)
    rays[1, column] = value
    for query in (accel.intersect, accel.occluded):
        with pytest.raises(ValueError, match=message):
            query(rays)
    # check=False traces them as the C++ library does: a bad ray is a miss, the others are unaffected
    hits = accel.intersect(rays, check=False)
    np.testing.assert_array_equal(hits.prim_id, [0, rayaccel.MISS, 0])
    np.testing.assert_array_equal(accel.occluded(rays, check=False), [True, False, True])


def test_zero_direction(accel):
    with pytest.raises(ValueError, match="ray 0 has a zero direction"):
        accel.intersect(np.zeros(3), np.zeros((1, 3)))


def test_bad_camera_and_render(accel):
    with pytest.raises(ValueError, match="image size must be positive"):
        rayaccel.Camera().rays(0, 10)
    with pytest.raises(ValueError, match="eye and at are the same point"):
        rayaccel.Camera(eye=(1, 1, 1), at=(1, 1, 1)).rays(4, 4)
    # Beyond the CLI's limit (16384 a side): a ValueError before anything is allocated, not MemoryError.
    with pytest.raises(ValueError, match="100000 x 100000 is too large.*at most 16384"):
        rayaccel.Camera().rays(100000, 100000)
    with pytest.raises(ValueError, match="16385 x 1 is too large"):
        rayaccel.render(accel, width=16385, height=1)
    with pytest.raises(ValueError, match="fov"):
        rayaccel.Camera(fov=180).rays(4, 4)
    with pytest.raises(ValueError, match="eye must be three finite numbers"):
        rayaccel.Camera(eye=(0, np.nan, 1)).rays(4, 4)
    with pytest.raises(ValueError, match="sepia"):
        rayaccel.render(accel, width=8, height=8, mode="sepia")
    with pytest.raises(ValueError, match="ao_samples"):
        rayaccel.render(accel, width=8, height=8, mode="ao", ao_samples=0)
    with pytest.raises(TypeError, match="cost must be a numeric array"):
        rayaccel.heatmap(np.array(["a"]))


def test_bad_thread_count():
    with pytest.raises(ValueError, match="threads must be >= 0"):
        rayaccel.set_threads(-1)


def test_first_bad_ray_of_a_large_batch(accel):
    rays = np.repeat(RAY, 20000, axis=0)
    rays[[12345, 19999], 4] = np.nan  # in later blocks of the checked batch, which run in parallel
    for query in (accel.intersect, accel.occluded):
        with pytest.raises(ValueError, match="ray 12345 has a NaN or infinite direction"):
            query(rays)
    with pytest.raises(ValueError, match="ray 12345"):
        accel.intersect(rays, packets=True)
    assert int(accel.intersect(rays, check=False).hit.sum()) == 19998
