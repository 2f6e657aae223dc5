"""The C API (include/rayaccel/rayaccel_c.h) through ctypes, from the shared library CTest names in RAYACCEL_C_LIBRARY:
it links, reports errors as codes plus a message, and answers as the C++ API (this package's module) does, bit for
bit, with each mesh's geometry id."""
import ctypes
import os

import numpy as np
import pytest

import rayaccel
from conftest import random_rays

MISS = 0xFFFFFFFF


class Hit(ctypes.Structure):
    _fields_ = [("t", ctypes.c_float), ("prim_id", ctypes.c_uint32), ("u", ctypes.c_float), ("v", ctypes.c_float),
                ("geom_id", ctypes.c_uint32)]


HIT_DTYPE = np.dtype([("t", "<f4"), ("prim_id", "<u4"), ("u", "<f4"), ("v", "<f4"), ("geom_id", "<u4")])


@pytest.fixture(scope="module")
def lib():
    path = os.environ.get("RAYACCEL_C_LIBRARY")
    if not path or not os.path.exists(path):
        pytest.skip("no shared library (CTest sets RAYACCEL_C_LIBRARY where rayaccel_shared is built)")
    lib = ctypes.CDLL(path)
    p = ctypes.c_void_p
    lib.rayaccel_last_error.restype = ctypes.c_char_p
    lib.rayaccel_version.restype = ctypes.c_char_p
    lib.rayaccel_scene_new.argtypes = [ctypes.POINTER(p)]
    lib.rayaccel_scene_release.argtypes = [p]
    lib.rayaccel_scene_release.restype = None
    lib.rayaccel_scene_add_mesh.argtypes = [p, p, ctypes.c_size_t, p, ctypes.c_size_t, ctypes.POINTER(ctypes.c_uint32)]
    lib.rayaccel_accel_new.argtypes = [p, ctypes.c_char_p, ctypes.POINTER(p)]
    lib.rayaccel_accel_release.argtypes = [p]
    lib.rayaccel_accel_release.restype = None
    for name in ("rayaccel_intersect", "rayaccel_intersect_packets", "rayaccel_occluded", "rayaccel_occluded_packets"):
        getattr(lib, name).argtypes = [p, p, ctypes.c_size_t, p]
    lib.rayaccel_intersect1.argtypes = [p, p, ctypes.POINTER(Hit)]
    return lib


def add_mesh(lib, scene, vertices, triangles):
    vertices = np.ascontiguousarray(vertices, dtype=np.float32)
    triangles = np.ascontiguousarray(triangles, dtype=np.uint32)
    geom = ctypes.c_uint32(99)
    status = lib.rayaccel_scene_add_mesh(scene, vertices.ctypes.data, len(vertices), triangles.ctypes.data,
                                         len(triangles), ctypes.byref(geom))
    assert status == 0, lib.rayaccel_last_error()
    return geom.value


def test_answers_as_the_cpp_api(lib):
    rng = np.random.default_rng(5)
    meshes = [(rng.uniform(-1, 1, (120, 3)), rng.integers(0, 120, (100, 3))),
              (rng.uniform(-1, 1, (80, 3)) + [1.0, 0, 0], rng.integers(0, 80, (60, 3)))]
    merged = rayaccel.mesh(np.concatenate([m[0] for m in meshes]).astype(np.float32),
                           np.concatenate([meshes[0][1], meshes[1][1] + 120]).astype(np.uint32))
    scene = ctypes.c_void_p()
    assert lib.rayaccel_scene_new(ctypes.byref(scene)) == 0
    assert [add_mesh(lib, scene, *m) for m in meshes] == [0, 1]
    rays = np.ascontiguousarray(random_rays(merged, 600, seed=2))
    geom_of = np.repeat(np.arange(2, dtype=np.uint32), [100, 60])
    first = np.array([0, 100], dtype=np.uint32)
    for spec in ("brute_force", "bvh", "bvh_wide", "kdtree:builder=sah"):
        expected = rayaccel.build(merged, spec).intersect(rays)
        accel = ctypes.c_void_p()
        assert lib.rayaccel_accel_new(scene, spec.encode(), ctypes.byref(accel)) == 0, lib.rayaccel_last_error()
        for call in ("rayaccel_intersect", "rayaccel_intersect_packets"):
            hits = np.zeros(len(rays), HIT_DTYPE)
            assert getattr(lib, call)(accel, rays.ctypes.data, len(rays), hits.ctypes.data) == 0
            found = expected.prim_id != MISS
            assert found.any() and (~found).any()
            for field in ("t", "u", "v"):  # bit for bit
                assert getattr(expected, field).astype("<f4").tobytes() == hits[field].tobytes(), (spec, call, field)
            np.testing.assert_array_equal(hits["geom_id"][found], geom_of[expected.prim_id[found]])
            np.testing.assert_array_equal(hits["prim_id"][found] + first[hits["geom_id"][found]],
                                          expected.prim_id[found])
            assert (hits["prim_id"][~found] == MISS).all() and (hits["geom_id"][~found] == MISS).all()
        occluded = np.zeros(len(rays), np.uint8)
        assert lib.rayaccel_occluded(accel, rays.ctypes.data, len(rays), occluded.ctypes.data) == 0
        np.testing.assert_array_equal(occluded.astype(bool), expected.prim_id != MISS)
        one = Hit()
        assert lib.rayaccel_intersect1(accel, rays[7].ctypes.data, ctypes.byref(one)) == 0
        assert np.float32(one.t).tobytes() == np.float32(expected.t[7]).tobytes()
        lib.rayaccel_accel_release(accel)
    lib.rayaccel_scene_release(scene)


def test_errors_are_codes_and_messages(lib):
    assert lib.rayaccel_version().decode() == rayaccel.__version__
    scene = ctypes.c_void_p()
    assert lib.rayaccel_scene_new(ctypes.byref(scene)) == 0
    vertices = np.zeros((3, 3), np.float32)
    bad = np.array([[0, 1, 7]], np.uint32)
    assert lib.rayaccel_scene_add_mesh(scene, vertices.ctypes.data, 3, bad.ctypes.data, 1, None) == 1
    assert b"vertex index 7" in lib.rayaccel_last_error()
    accel = ctypes.c_void_p()
    assert lib.rayaccel_accel_new(scene, b"no_such_structure", ctypes.byref(accel)) == 1
    assert b"no_such_structure" in lib.rayaccel_last_error() and not accel.value
    assert lib.rayaccel_intersect(None, None, 3, None) == 1
    lib.rayaccel_scene_release(scene)
