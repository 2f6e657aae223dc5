"""rayaccel: exact first-hit and any-hit ray queries over triangle meshes and spheres, numpy arrays in and out.

    scene = rayaccel.load("bunny.ply")              # or rayaccel.mesh(vertices, triangles), "builtin:sphere", ...
    accel = rayaccel.build(scene, "bvh_wide")       # any spec of rayaccel.specs()
    hits = accel.intersect(origins, directions)     # hits.t, hits.prim_id, hits.u, hits.v
    blocked = accel.occluded(rays)                  # bool array

Batches run in C++ without the GIL on TBB's threads (rayaccel.set_threads(n) limits them). rayaccel.dask traces
dask arrays of rays on any Dask scheduler (imported on first use; needs dask). Scenes copy the arrays
they are made from once (the C++ Scene owns its geometry), so the input arrays may be changed or freed afterwards.
"""
import contextlib
import os

import numpy as np

from . import _core
from ._core import Scene, __version__, packet_tile_order, set_threads, specs, threads
from ._rays import HIT_DTYPE, MISS, Hits, TraversalStats, as_rays
from .camera import Camera, diffuse_rays, heatmap, render, shadow_rays

__all__ = ["Accelerator", "Camera", "HIT_DTYPE", "Hits", "MISS", "Scene", "TraversalStats", "__version__", "build",
           "builtin", "builtin_scenes", "diffuse_rays", "heatmap", "load", "mesh", "packet_tile_order", "render",
           "set_threads", "shadow_rays", "specs", "spheres", "structures", "thread_limit", "threads"]


def __getattr__(name):
    """rayaccel.dask on first use, so that `import rayaccel` alone needs no dask."""
    if name == "dask":
        import importlib
        return importlib.import_module(".dask", __name__)
    raise AttributeError(f"module 'rayaccel' has no attribute '{name}'")


def mesh(vertices, triangles, name="mesh", *, allow_nonfinite=False, copy=True):
    """A triangle scene from (N, 3) float32/float64 vertices and (M, 3) int32/uint32/int64 triangles.

    Every index is checked against N; a NaN or infinite vertex raises ValueError unless allow_nonfinite (then its
    triangles are kept but never hit). Primitive id = row of triangles. By default the arrays are copied once
    (float64 is rounded to float32), so they may be changed afterwards. With copy=False they are read in place, with
    no copy: they must then be C-contiguous float32 vertices and int32/uint32 triangles (else ValueError), the scene
    keeps a reference to both, and they must not change while it is used, except for vertex positions written in
    place followed by scene.arrays_changed() and a rebuild.
    """
    if not copy:
        return _core._mesh_in_place(vertices, triangles, str(name), bool(allow_nonfinite))
    return _core._mesh(vertices, triangles, str(name), bool(allow_nonfinite))


def spheres(centers, radii, name="spheres"):
    """A scene of analytic spheres: (N, 3) float centers, radii a float or an (N,) float array (finite, > 0)."""
    return _core._spheres(centers, radii, str(name))


def load(spec):
    """A scene from a mesh file the CLI reads (PLY, OBJ, glTF, STL, ... through assimp) or "builtin:NAME[:k=v,...]".

    Raises FileNotFoundError for a missing file, ValueError for one that is not a mesh or a bad builtin parameter.
    """
    spec = os.fspath(spec)
    scene = _core._load(spec)
    scene.source = spec
    return scene


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


class Accelerator(_core._Accelerator):
    """One acceleration structure from a spec ("bvh_wide", "kdtree:builder=sah", ...), built over one Scene.

    The structure keeps its scene alive. Queries on an unbuilt one raise ValueError. Rays are a (..., 8) array in
    the .rays layout (float32, ox oy oz tmin dx dy dz tmax; an (N, 8) float32 C-contiguous array is read in place),
    or origins and directions ((..., 3), origins possibly one (3,) point) with t_min and t_max (scalars or arrays).
    A hit counts when t_min < t <= t_max. Rays with a NaN or infinite origin or direction, a zero direction or a NaN
    t bound raise ValueError; with check=False they are traced as misses, as the C++ library and CLI do.
    """

    def __init__(self, spec="bvh_wide"):
        super().__init__(str(spec))

    def __repr__(self):
        state = f"built over {self.scene!r}" if self.built else "not built"
        return f"<rayaccel.Accelerator '{self.spec}' {state}>"

    def intersect(self, rays, directions=None, t_min=None, t_max=None, *, points=False, normals=False,
                  stats=False, packets=False, check=True, out=None):
        """Closest hits as Hits (t, prim_id, u, v shaped like the rays; points and normals, per-ray statistics on
        request). packets=True traces each run of eight rays as one packet (intersect_packets(): for coherent rays,
        such as camera rays in 4 x 2 pixel tiles, see packet_tile_order(); same closest hits, no statistics). out: the Hits of an earlier
        call with as many rays, overwritten instead of allocating new records (for loops over same-sized batches)."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        if out is not None:
            if not isinstance(out, Hits):
                raise TypeError(f"out must be the Hits of an earlier intersect(), not {type(out).__name__}")
            out = out.records.reshape(-1).view(np.uint8).reshape(-1, HIT_DTYPE.itemsize)
        records, counts = self._intersect(flat, bool(stats), bool(packets), bool(check), out)
        p = n = None
        if points or normals:
            p, n = self._surface(flat, records)
        return Hits(records, shape, p if points else None, n if normals else None,
                    None if counts is None else TraversalStats(counts, shape))

    def occluded(self, rays, directions=None, t_min=None, t_max=None, *, stats=False, check=True):
        """Any hit: a bool array shaped like the rays (True: something lies at t_min < t <= t_max). With stats=True,
        returns (occluded, TraversalStats)."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        answers, counts = self._occluded(flat, bool(stats), bool(check))
        answers = answers.reshape(shape)
        return (answers, TraversalStats(counts, shape)) if stats else answers


def build(scene, spec="bvh_wide"):
    """Builds the structure named by spec over scene; raises ValueError for an unknown spec, key or value."""
    if not isinstance(scene, Scene):
        raise TypeError(f"build() needs a rayaccel.Scene (rayaccel.mesh, load, builtin, spheres), not "
                        f"{type(scene).__name__}")
    accel = Accelerator(spec)
    accel.build(scene)
    return accel
