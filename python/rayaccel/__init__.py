"""rayaccel: exact first-hit and any-hit ray queries over triangle meshes and spheres, numpy arrays in and out.

    scene = rayaccel.load("bunny.ply")              # or rayaccel.mesh(vertices, triangles), "builtin:sphere", ...
    accel = rayaccel.build(scene, "bvh_wide")       # any spec of rayaccel.specs()
    hits = accel.intersect(origins, directions)     # hits.t, hits.prim_id, hits.u, hits.v
    blocked = accel.occluded(rays)                  # bool array
    counts, hits = accel.all_hits(rays)             # every surface crossing along each ray
    closest = accel.closest_points(points)          # closest point, triangle, barycentrics, distance
    inside = accel.inside(points)                   # crossing-parity inside test (closed meshes)
    far = rayaccel.build_double(rayaccel.mesh_double(vertices64, triangles))   # the double path (far geometry)

Batches run in C++ without the GIL on TBB's threads (rayaccel.set_threads(n) limits them). rayaccel.dask traces
dask arrays of rays on any Dask scheduler (imported on first use; needs dask). Scenes copy the arrays
they are made from once (the C++ Scene owns its geometry), so the input arrays may be changed or freed afterwards.
"""
import contextlib
import os

import numpy as np

from . import _core
from ._core import (DoubleScene, GeometryTable, Scene, __version__, default_spec, load_double, packet_tile_order,
                    set_threads, specs, threads)
from ._hits import HIT64_DTYPE, HIT_DTYPE, IHIT_DTYPE, MISS, Hits, TraversalStats
from ._rays import as_points, as_rays, real_array
from ._instances import InstancedAccelerator, InstancedScene, build_instanced
from .camera import Camera, diffuse_rays, heatmap, render, shadow_rays

__all__ = ["Accelerator", "CLOSEST_DTYPE", "Camera", "DoubleAccelerator", "DoubleScene", "GeometryTable", "HIT64_DTYPE",
           "HIT_DTYPE", "Hits", "IHIT_DTYPE", "InstancedAccelerator", "InstancedScene", "MISS", "Scene", "TraversalStats",
           "__version__", "build", "build_double", "build_instanced", "builtin", "builtin_scenes", "default_spec",
           "diffuse_rays", "heatmap", "load", "load_double", "mesh", "mesh_double", "meshes", "packet_tile_order",
           "render", "set_threads", "shadow_rays", "specs", "spheres", "structures", "thread_limit", "threads",
           "winding_numbers"]

#: One closest-point record, the 28-byte layout of the CLI's .closest file (prim_id = MISS: nothing within reach).
CLOSEST_DTYPE = np.dtype([("point", "<f4", (3,)), ("distance", "<f4"), ("prim_id", "<u4"), ("u", "<f4"),
                          ("v", "<f4")])


def winding_numbers(scene, points):
    """Generalised winding numbers (Jacobson et al. 2013) of (..., 3) points with respect to a triangle scene,
    float64 shaped like the points: 1 inside a closed outward-oriented mesh, 0 outside, 1/2 on its surface, smooth
    in between where the mesh has holes. A direct sum over every triangle (O(triangles) per point)."""
    flat, shape = as_points(points)
    return _core._winding_numbers(scene, flat).reshape(shape)


def __getattr__(name):
    """rayaccel.dask on first use, so that `import rayaccel` alone needs no dask."""
    if name == "dask":
        import importlib
        return importlib.import_module(".dask", __name__)
    raise AttributeError(f"module 'rayaccel' has no attribute '{name}'")


def mesh(vertices, triangles, name="mesh", *, allow_nonfinite=False, copy=True):
    """A triangle scene from (N, 3) float32/float64 vertices and (M, 3) int32/uint32/int64 triangles (array-likes:
    lists, and integer vertices, are converted as np.asarray does).

    Every index is checked against N; a NaN or infinite vertex raises ValueError unless allow_nonfinite (then its
    triangles are kept but never hit). Primitive id = row of triangles. By default the arrays are copied once
    (float64 is rounded to float32), so they may be changed afterwards. With copy=False they are read in place, with
    no copy: they must then be C-contiguous float32 vertices and int32/uint32 triangles (else ValueError), the scene
    keeps a reference to both, and they must not change while it is used, except for vertex positions written in
    place followed by scene.arrays_changed() and a rebuild.
    """
    if not copy:
        return _core._mesh_in_place(vertices, triangles, str(name), bool(allow_nonfinite))
    return _core._mesh(real_array(vertices, "vertices", np.float64), np.asarray(triangles), str(name),
                       bool(allow_nonfinite))


def meshes(pairs, name="meshes"):
    """One triangle scene from several meshes, a list of (vertices, triangles) pairs each read as by mesh(), and its
    GeometryTable: mesh k's triangles get the primitive ids after mesh k-1's, and table.geometry_of(hits.prim_id) /
    table.local_primitive(hits.prim_id) give each hit's mesh and its triangle within that mesh (MISS for a miss)."""
    return _core._meshes(list(pairs), str(name))


def spheres(centers, radii, name="spheres"):
    """A scene of analytic spheres: (N, 3) float centers, radii a float or an (N,) float array (finite, > 0)."""
    radii = real_array(radii, "radii")
    return _core._spheres(real_array(centers, "centers"), float(radii) if radii.ndim == 0 else radii, str(name))


def load(spec, *, geometries=False):
    """A scene from a mesh file the CLI reads (PLY, OBJ, glTF, STL, ... through assimp) or "builtin:NAME[:k=v,...]".

    geometries=True returns (scene, GeometryTable): each mesh of a file of several (OBJ objects, glTF nodes, ...) is a
    geometry, numbered in the order the file's meshes are concatenated (a PLY file or builtin scene is one), for
    table.geometry_of(hits.prim_id) and the geometry_mask / skip_geometry controls.
    Raises FileNotFoundError for a missing file, ValueError for one that is not a mesh or a bad builtin parameter.
    """
    spec = os.fspath(spec)
    scene, table = _core._load_with_geometries(spec) if geometries else (_core._load(spec), None)
    scene.source = spec
    return (scene, table) if geometries else scene


def builtin(name, **params):
    """A built-in procedural scene, e.g. builtin("sphere", level=3) (see builtin_scenes() for names and keys)."""
    spec = f"builtin:{name}" + (":" + ",".join(f"{k}={v}" for k, v in params.items()) if params else "")
    return load(spec)


def builtin_scenes():
    """Every built-in scene: dicts with name, description and defaults (parameter -> default value)."""
    return _core._builtin_scenes()


def structures():
    """Every registered structure: dicts with name, description, options (key, type, default, description,
    choices, range: the allowed interval of a number, else "") and variants (the specs `rayaccel list --names` prints for it)."""
    return _core._structures()


@contextlib.contextmanager
def thread_limit(count):
    """Within the block, builds and batches use at most `count` threads."""
    before = threads()
    set_threads(count)
    try:
        yield
    finally:
        set_threads(before)


def _controls(skip, skip_geometry, mask, geometry_mask, geometries, enabled):
    """The query controls as the C++ side takes them (flat uint32 per-ray arrays, enabled as bool), or None when
    none is given."""
    if all(c is None for c in (skip, skip_geometry, mask, geometry_mask, geometries, enabled)):
        return None
    if geometries is not None and not isinstance(geometries, GeometryTable):
        raise TypeError(f"geometries must be a rayaccel.GeometryTable, not {type(geometries).__name__}")

    def ids(a, name):
        if a is None:
            return None
        a = np.asarray(a)
        if a.dtype.kind not in "iu":
            raise TypeError(f"{name} must be an array of integers, not {a.dtype}")
        if a.size and (a.min() < -1 or a.max() > 2**32 - 1):
            raise ValueError(f"{name} holds values outside [0, 2**32 - 1] (-1 also means none)")
        return np.ascontiguousarray(a.astype(np.int64) & 0xFFFFFFFF, dtype=np.uint32).reshape(-1)

    on = None if enabled is None else np.ascontiguousarray(np.asarray(enabled) != 0, dtype=np.uint8).reshape(-1)
    return (ids(skip, "skip"), ids(skip_geometry, "skip_geometry"), ids(mask, "mask"),
            ids(geometry_mask, "geometry_mask"), geometries, on)


class Accelerator(_core._Accelerator):
    """One acceleration structure from a spec ("bvh_wide", "kdtree:builder=sah", ...), built over one Scene.

    The structure keeps its scene alive. Queries on an unbuilt one raise ValueError. Rays are a (..., 8) array in
    the .rays layout (float32, ox oy oz tmin dx dy dz tmax; an (N, 8) float32 C-contiguous array is read in place),
    a (..., 6) array in Open3D's layout (ox oy oz dx dy dz), or origins and directions ((..., 3)) with t_min and
    t_max (defaults 0 and inf); origins, directions, t_min and t_max broadcast as numpy arrays do. Any array-like
    works (lists; integers are cast to float). A hit counts when t_min < t <= t_max; a batch in which no ray has
    t_max > t_min draws a UserWarning (a zero-filled array, or columns in another order). Rays with a NaN or
    infinite origin or direction, a zero direction or a NaN t bound raise ValueError; with check=False they are
    traced as misses, as the C++ library and CLI do.
    """

    def __init__(self, spec=default_spec()):
        super().__init__(str(spec))

    def __repr__(self):
        state = f"built over {self.scene!r}" if self.built else "not built"
        return f"<rayaccel.Accelerator '{self.spec}' {state}>"

    def intersect(self, rays, directions=None, t_min=None, t_max=None, *, points=False, normals=False,
                  stats=False, packets=False, check=True, out=None, skip=None, skip_geometry=None, mask=None,
                  geometry_mask=None, geometries=None, enabled=None):
        """Closest hits as Hits (t, prim_id, u, v shaped like the rays; points and normals, per-ray statistics on
        request). packets=True traces each run of eight rays as one packet (intersect_packets(): for coherent rays,
        such as camera rays in 4 x 2 pixel tiles, see packet_tile_order(); same closest hits, no statistics). out: the Hits of an earlier
        call with as many rays, overwritten instead of allocating new records (for loops over same-sized batches).

        Query controls (tested in C++ before the exact primitive test; see README, "Skip, masks and filters"):
        skip / skip_geometry: per ray, a primitive / geometry id the ray ignores (MISS: none), e.g. the surface a
        secondary ray leaves; mask: per-ray uint32 masks and geometry_mask: per-geometry masks (geometries: the
        GeometryTable of rayaccel.meshes(); without it the scene is one geometry), a geometry being seen when
        mask & geometry_mask != 0 (Embree's rule; a geometry mask of 0 disables it without a rebuild); enabled: per
        primitive, False hides it (cut-outs, an opacity array > 0). Not with stats; with packets=True through the
        packet traversal."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        if out is not None:
            if not isinstance(out, Hits):
                raise TypeError(f"out must be the Hits of an earlier intersect(), not {type(out).__name__}")
            out = out.records.reshape(-1).view(np.uint8).reshape(-1, HIT_DTYPE.itemsize)
        controls = _controls(skip, skip_geometry, mask, geometry_mask, geometries, enabled)
        if controls is not None:
            if stats:
                raise ValueError("skip, skip_geometry, mask, geometry_mask and enabled work without stats")
            records, counts = self._trace_in_context(flat, False, bool(packets), bool(check), out, *controls), None
        else:
            records, counts = self._intersect(flat, bool(stats), bool(packets), bool(check), out)
        p = n = None
        if points or normals:
            p, n = self._surface(flat, records)
        return Hits(records, shape, p if points else None, n if normals else None,
                    None if counts is None else TraversalStats(counts, shape))

    def occluded(self, rays, directions=None, t_min=None, t_max=None, *, stats=False, packets=False, check=True,
                 skip=None, skip_geometry=None, mask=None, geometry_mask=None, geometries=None, enabled=None):
        """Any hit: a bool array shaped like the rays (True: something lies at t_min < t <= t_max). With stats=True,
        returns (occluded, TraversalStats). packets=True traces each run of eight rays as one packet
        (occluded_packets(): for coherent rays, such as shadow rays of neighbouring pixels to one light; the same
        answers, no statistics). skip, skip_geometry, mask, geometry_mask, geometries, enabled: as for intersect()."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        controls = _controls(skip, skip_geometry, mask, geometry_mask, geometries, enabled)
        if controls is not None:
            if stats:
                raise ValueError("skip, skip_geometry, mask, geometry_mask and enabled work without stats")
            return self._trace_in_context(flat, True, bool(packets), bool(check), None, *controls).reshape(shape)
        answers, counts = self._occluded(flat, bool(stats), bool(packets), bool(check))
        answers = answers.reshape(shape)
        return (answers, TraversalStats(counts, shape)) if stats else answers


    def all_hits(self, rays, directions=None, t_min=None, t_max=None, *, max_hits=2**32 - 1, check=True):
        """Every surface crossing with t_min < t <= t_max (brute_force, bvh and bvh_wide structures; triangle scenes).

        Returns (counts, hits): counts (uint32, shaped like the rays) is each ray's number of crossings before the
        cap, hits a HIT_DTYPE array of the kept ones (the max_hits nearest of each ray), ray after ray, each ray's
        sorted by t; ray i's are hits[offsets[i]:offsets[i + 1]] with offsets = cumsum of min(counts, max_hits).
        A ray through an edge or vertex crosses there once, so a ray from outside to outside crosses a closed mesh
        an even number of times."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        if int(max_hits) < 0:
            raise ValueError(f"max_hits must be >= 0, not {max_hits}")
        counts, records = self._all_hits(flat, int(max_hits), bool(check))
        return counts.reshape(shape), records.reshape(-1).view(HIT_DTYPE)

    def count_hits(self, rays, directions=None, t_min=None, t_max=None, *, check=True):
        """The number of surface crossings of each ray (all_hits() without the hits), uint32 shaped like the rays."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        return self._count_hits(flat, bool(check)).reshape(shape)

    def closest_points(self, points, max_distance=np.inf):
        """The closest point of the scene to each of (..., 3) points within max_distance: a CLOSEST_DTYPE array
        shaped like the points (point, distance, prim_id, u, v; prim_id = MISS and distance = inf when nothing is
        within reach). Branch and bound over the structure; the same distances as brute force, bit for bit."""
        flat, shape = as_points(points)
        return self._closest_points(flat, float(max_distance)).reshape(-1).view(CLOSEST_DTYPE).reshape(shape)

    def inside(self, points, ray_count=3):
        """Crossing-parity inside test of (..., 3) points (majority of ray_count rays, odd, 1..7): bool shaped like
        the points. Exact for closed meshes off their surface; see winding_numbers() for open ones."""
        flat, shape = as_points(points)
        return self._inside(flat, int(ray_count)).reshape(shape)

    def signed_distance(self, points, ray_count=3):
        """Distance to the scene of (..., 3) points, negative inside (inside() decides): float32 shaped like the
        points. Meant for closed meshes."""
        flat, shape = as_points(points)
        return self._signed_distance(flat, int(ray_count)).reshape(shape)


def build(scene, spec=default_spec()):
    """Builds the structure named by spec over scene; raises ValueError for an unknown spec, key or value."""
    if not isinstance(scene, Scene):
        raise TypeError(f"build() needs a rayaccel.Scene (rayaccel.mesh, load, builtin, spheres), not "
                        f"{type(scene).__name__}")
    accel = Accelerator(spec)
    accel.build(scene)
    return accel


def mesh_double(vertices, triangles):
    """A DoubleScene for the double-precision path: (N, 3) float64 vertices, kept bit for bit, and (M, 3)
    int32/uint32/int64 triangles (copied once; lists and integer vertices are converted). TypeError for another
    dtype, ValueError for a bad shape, an index out of range, or a coordinate outside the double domain (NaN,
    infinite, or nonzero with magnitude outside [2^-64, 2^64]), naming it."""
    vertices = np.asarray(vertices)
    if vertices.dtype.kind in "iu":  # exact in float64; float32 stays refused (its bits are lost already)
        vertices = vertices.astype(np.float64)
    return _core._mesh_double(vertices, np.asarray(triangles))


class DoubleAccelerator(_core._DoubleAccelerator):
    """A double-precision structure ("brute_force", or "bvh[:key=value,...]" with bv=aabb) over one DoubleScene.

    Rays are a (..., 8) array in the .rays64 layout (float64; float32 is converted exactly), or origins and
    directions ((..., 3)) with t_min and t_max, all in float64. A hit counts when t_min < t <= t_max. Rays with a
    component outside the double domain, a zero direction or a NaN t bound raise ValueError; with check=False they
    are traced as misses.
    """

    def __init__(self, spec="bvh"):
        super().__init__(str(spec))

    def __repr__(self):
        state = f"built over {self.scene!r}" if self.scene is not None else "not built"
        return f"<rayaccel.DoubleAccelerator '{self.spec}' {state}>"

    def intersect(self, rays, directions=None, t_min=None, t_max=None, *, check=True):
        """Closest hits as Hits over HIT64_DTYPE records (t float64, prim_id, u, v float64, shaped like the rays;
        hits.tobytes() is a .hits64 file)."""
        flat, shape = as_rays(rays, directions, t_min, t_max, dtype=np.float64)
        return Hits(self._intersect(flat, bool(check)), shape, dtype=HIT64_DTYPE)

    def occluded(self, rays, directions=None, t_min=None, t_max=None, *, check=True):
        """Any hit: a bool array shaped like the rays."""
        flat, shape = as_rays(rays, directions, t_min, t_max, dtype=np.float64)
        return self._occluded(flat, bool(check)).reshape(shape)


def build_double(scene, spec="bvh"):
    """Builds the double structure named by spec over a DoubleScene (mesh_double()); ValueError for a structure
    without a double version or a bad option."""
    if not isinstance(scene, DoubleScene):
        raise TypeError(f"build_double() needs a rayaccel.DoubleScene (rayaccel.mesh_double), not "
                        f"{type(scene).__name__}")
    accel = DoubleAccelerator(spec)
    accel.build(scene)
    return accel
