"""Scenes from numpy arrays (every accepted dtype, copy semantics), mesh files, built-in scenes and spheres."""
import numpy as np
import pytest

import rayaccel

QUAD_V = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], dtype=np.float32)
QUAD_T = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)


def down_ray(x, y):
    return np.array([[x, y, 5, 0, 0, 0, -1, np.inf]], dtype=np.float32)


@pytest.mark.parametrize("vdtype", [np.float32, np.float64])
@pytest.mark.parametrize("tdtype", [np.int32, np.uint32, np.int64])
def test_mesh_dtypes(vdtype, tdtype):
    scene = rayaccel.mesh(QUAD_V.astype(vdtype), QUAD_T.astype(tdtype), name="quad")
    assert (scene.name, scene.kind, scene.primitive_count, len(scene)) == ("quad", "triangles", 2, 2)
    np.testing.assert_array_equal(scene.bounds, [[-1, -1, 0], [1, 1, 0]])
    hits = rayaccel.build(scene).intersect(down_ray(0.5, -0.5))
    assert hits.prim_id[0] == 0 and hits.t[0] == 5.0


def test_mesh_accepts_strided_arrays():
    vertices = np.asfortranarray(QUAD_V)
    triangles = np.repeat(QUAD_T, 2, axis=1)[:, ::2]  # the same indices through a strided view
    assert not vertices.flags.c_contiguous and not triangles.flags.c_contiguous
    for tdtype in (np.uint32, np.int64):
        scene = rayaccel.mesh(vertices, triangles.astype(tdtype, copy=False)[:, :])
        assert rayaccel.build(scene).intersect(down_ray(-0.5, 0.5)).prim_id[0] == 1


def test_mesh_copies_its_input_once():
    # The C++ Scene owns its geometry (TriangleMesh holds std::vectors): the arrays are read once, and changing them
    # afterwards changes nothing.
    vertices, triangles = QUAD_V.copy(), QUAD_T.copy()
    accel = rayaccel.build(rayaccel.mesh(vertices, triangles))
    vertices[:] = 100
    triangles[:] = 0
    del vertices, triangles
    hits = accel.intersect(down_ray(0.5, 0.9))
    assert hits.prim_id[0] == 1 and hits.t[0] == 5.0


def test_mesh_zero_copy():
    vertices = QUAD_V.astype(np.float32)
    triangles = QUAD_T.astype(np.uint32)
    scene = rayaccel.mesh(vertices, triangles, copy=False)
    assert scene.borrows_arrays and not rayaccel.mesh(vertices, triangles).borrows_arrays
    # The scene holds no copy of the vertices (a copy would take 12 bytes a vertex) ...
    assert scene.memory_bytes < rayaccel.mesh(vertices, triangles).memory_bytes
    accel = rayaccel.build(scene)
    before = accel.intersect(down_ray(0.5, 0.9))
    assert before.prim_id[0] == 1 and before.t[0] == 5.0
    # ... and reads the caller's array in place: a vertex moved there is seen once the scene re-reads it.
    vertices[:, 2] -= 1.0
    scene.arrays_changed()
    after = rayaccel.build(scene).intersect(down_ray(0.5, 0.9))
    assert after.prim_id[0] == 1 and after.t[0] == 6.0
    # The scene keeps the arrays alive.
    del vertices, triangles
    assert rayaccel.build(scene).intersect(down_ray(0.5, 0.9)).t[0] == 6.0


def test_mesh_zero_copy_refuses_arrays_it_cannot_read_in_place():
    with pytest.raises(ValueError, match="copy=False"):
        rayaccel.mesh(QUAD_V.astype(np.float64), QUAD_T.astype(np.uint32), copy=False)
    with pytest.raises(ValueError, match="copy=False"):
        rayaccel.mesh(QUAD_V.astype(np.float32), QUAD_T.astype(np.int64), copy=False)
    with pytest.raises(ValueError, match="copy=False"):
        rayaccel.mesh(np.asfortranarray(QUAD_V.astype(np.float32)), QUAD_T.astype(np.uint32), copy=False)
    bad = QUAD_T.astype(np.int32)
    bad[0, 0] = -1
    with pytest.raises(ValueError, match=r"triangles\[0, 0\] = -1 is out of range"):
        rayaccel.mesh(QUAD_V.astype(np.float32), bad, copy=False)
    with pytest.raises(ValueError, match="triangle 1 uses vertex index 9"):
        rayaccel.mesh(QUAD_V.astype(np.float32), np.array([[0, 1, 2], [0, 2, 9]], np.uint32), copy=False)


def test_nonfinite_vertices_only_on_request():
    vertices = QUAD_V.copy()
    vertices[3, 0] = np.nan
    with pytest.raises(ValueError, match=r"vertices\[3\]"):
        rayaccel.mesh(vertices, QUAD_T)
    scene = rayaccel.mesh(vertices, QUAD_T, allow_nonfinite=True)
    assert (scene.primitive_count, scene.invalid_count, scene.valid_count) == (2, 1, 1)
    assert rayaccel.build(scene).intersect(down_ray(-0.5, 0.5)).prim_id[0] == rayaccel.MISS


def test_empty_mesh():
    scene = rayaccel.mesh(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int32))
    assert scene.primitive_count == 0 and np.isnan(scene.bounds).all()
    assert not rayaccel.build(scene).occluded(down_ray(0, 0))[0]


def test_mesh_file_equals_arrays(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in QUAD_V) + "f 1 2 3 4\n")  # fan-triangulated
    scene = rayaccel.load(path)
    assert (scene.name, scene.primitive_count, scene.source) == ("quad", 2, str(path))
    rays = np.array([down_ray(x, y)[0] for x in (-0.5, 0.5) for y in (-0.5, 0.5)])
    a = rayaccel.build(scene).intersect(rays)
    b = rayaccel.build(rayaccel.mesh(QUAD_V, QUAD_T)).intersect(rays)
    assert a.tobytes() == b.tobytes()


def test_builtin_scenes():
    names = [s["name"] for s in rayaccel.builtin_scenes()]
    assert {"sphere", "soup", "default", "sphereflake"} <= set(names)
    assert rayaccel.builtin("sphere", level=1).primitive_count == 80
    assert rayaccel.load("builtin:sphere:level=1").primitive_count == 80
    flake = rayaccel.builtin("sphereflake", level=1)
    assert flake.kind == "spheres" and flake.primitive_count == 10


def test_spheres():
    scene = rayaccel.spheres(np.array([[0, 0, 0], [3, 0, 0]], np.float64), np.array([1.0, 0.5], np.float32))
    hits = rayaccel.build(scene).intersect(np.array([[0, 0, 5], [3, 0, 5]], np.float32),
                                           np.array([[0, 0, -1], [0, 0, -1]], np.float32), normals=True)
    np.testing.assert_array_equal(hits.prim_id, [0, 1])
    np.testing.assert_allclose(hits.t, [4.0, 4.5], rtol=1e-6)
    np.testing.assert_allclose(hits.normals, [[0, 0, 1], [0, 0, 1]], atol=1e-6)
    assert rayaccel.spheres(np.zeros((3, 3), np.float32), 2.0).primitive_count == 3


def test_meshes_keep_each_meshs_geometry_id():
    rng = np.random.default_rng(11)
    parts = [(rng.uniform(-1, 1, (30, 3)), rng.integers(0, 30, (25, 3))),
             (rng.uniform(-1, 1, (3, 3)).astype(np.float32), np.zeros((0, 3), np.uint32)),  # an empty mesh
             (rng.uniform(-1, 1, (20, 3)) + [0, 0, 3], rng.integers(0, 20, (15, 3)).astype(np.int32))]
    scene, table = rayaccel.meshes(parts)
    assert scene.primitive_count == 40 and table.geometry_count == 3
    assert [table.first_primitive(k) for k in range(4)] == [0, 25, 25, 40]
    ids = np.array([0, 24, 25, 39, 40, rayaccel.MISS], np.uint32)
    np.testing.assert_array_equal(table.geometry_of(ids), [0, 0, 2, 2, rayaccel.MISS, rayaccel.MISS])
    np.testing.assert_array_equal(table.local_primitive(ids), [0, 24, 0, 14, rayaccel.MISS, rayaccel.MISS])
    # Rays down onto both meshes (the third lies 3 above the first): each hit's mesh is the one holding its triangle.
    rays = np.zeros((400, 8), np.float32)
    rays[:, 0:2] = rng.uniform(-1, 1, (400, 2))
    rays[:, 2], rays[:, 6], rays[:, 7] = 10, -1, np.inf
    hits = rayaccel.build(scene, "bvh_wide").intersect(rays)
    geom = table.geometry_of(hits.prim_id)
    found = hits.prim_id != rayaccel.MISS
    np.testing.assert_array_equal(geom[found], np.where(hits.prim_id[found] < 25, 0, 2))
    assert set(geom[found]) == {0, 2} and (geom[~found] == rayaccel.MISS).all()
    np.testing.assert_array_equal(hits.t[geom == 2] < 9, True)  # the upper mesh is nearer
    with pytest.raises(ValueError, match="mesh 1: .*5"):
        rayaccel.meshes([parts[0], (parts[0][0][:5], np.array([[0, 1, 5]]))])
    with pytest.raises(TypeError, match="integer"):
        table.geometry_of(np.zeros(2, np.float32))
    assert table.geometry_of([0, 39]).tolist() == [0, 2]  # array-likes, as numpy functions take them
