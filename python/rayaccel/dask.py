"""rayaccel.dask: closest-hit and any-hit queries over dask arrays of rays, on any Dask scheduler.

    import rayaccel.dask
    hits = rayaccel.dask.intersect("bunny.ply", rays, spec="bvh_wide")   # rays: dask (N, 8) float32, chunked on N
    records = hits.compute()                                               # == accel.intersect(rays).records
    hits = rayaccel.dask.intersect("bunny.ply", rays, structure="bunny.bvhw")  # load a saved one, do not build

The scene reaches each worker once: a mesh path or "builtin:..." string travels as text, in-memory (vertices,
triangles) arrays as one key of the graph that every chunk depends on (Dask moves it once to each worker that runs a
chunk). Each worker process builds the structure once per (scene, spec), or loads it from a file saved with
accel.save() (structure=PATH: for scenes whose build costs more than reading the file), and keeps it in a small LRU
cache (see _cache.py) for every later chunk. Every chunk runs accel.intersect / accel.occluded on its rows, so the
results are the local ones, bit for bit, whatever the chunking. Spec, path and arrays are checked on the client
before anything is submitted.
"""
import os

import numpy as np

try:
    import dask.array as da
    from dask.base import tokenize
    from dask.highlevelgraph import HighLevelGraph
except ImportError as error:  # pragma: no cover - depends on the installation
    raise ImportError("rayaccel.dask needs dask (Debian: apt-get install python3-dask python3-distributed)") \
        from error

from . import Accelerator, Scene, _core, builtin_scenes, default_spec, load, mesh
from ._cache import accelerator, cache_info, clear_cache, same_structure, set_cache_size
from ._hits import HIT_DTYPE

__all__ = ["SceneSource", "StructureFile", "cache_info", "clear_cache", "intersect", "occluded", "set_cache_size"]


def _checked_file(given, path, what):
    """os.stat of a file the client must read: FileNotFoundError or PermissionError naming `given` otherwise."""
    if not os.path.isfile(path):
        raise FileNotFoundError(f"{what} '{given}' does not exist (or is not a file)")
    if not os.access(path, os.R_OK):
        raise PermissionError(f"{what} '{given}' is not readable")
    return os.stat(path)


class SceneSource:
    """What a worker needs to make the scene: kind ("file", "builtin" or "arrays"), value (an absolute path, a
    builtin spec, or (vertices, triangles)) and token (names its content: path, size and modification time of a
    file; the bytes of arrays). Made on the client by SceneSource.of(); workers call scene()."""

    __slots__ = ("kind", "value", "token")

    def __init__(self, kind, value, token):
        self.kind, self.value, self.token = kind, value, token

    def __getstate__(self):
        return self.kind, self.value, self.token

    def __setstate__(self, state):
        self.kind, self.value, self.token = state

    def __repr__(self):
        shown = self.value if self.kind != "arrays" else f"{len(self.value[1])} triangles"
        return f"<rayaccel.dask.SceneSource {self.kind} {shown!r} {self.token[:8]}>"

    def scene(self):
        """The Scene (on a worker: loaded from the file or built-in, or copied from the arrays)."""
        if self.kind == "arrays":
            return mesh(*self.value, name="dask-arrays")
        return load(self.value)

    @classmethod
    def of(cls, source, check=True):
        """Checks source on the client and describes it; see intersect() for the accepted forms."""
        if isinstance(source, cls):
            return source
        if isinstance(source, Scene):
            if not hasattr(source, "source"):
                raise TypeError("a rayaccel.Scene made from arrays cannot be sent to workers: pass its "
                                "(vertices, triangles) arrays, a mesh path or a 'builtin:...' name instead")
            source = source.source
        if isinstance(source, (tuple, list)):
            if len(source) != 2:
                raise TypeError(f"in-memory scenes are (vertices, triangles), not {len(source)} items")
            vertices, triangles = (np.ascontiguousarray(a) for a in source)
            mesh(vertices, triangles)  # the local checks (shape, dtype, indices, NaN), raised here on the client
            return cls("arrays", (vertices, triangles), tokenize("arrays", vertices, triangles))
        if not isinstance(source, (str, os.PathLike)):
            raise TypeError(f"scene_source must be a mesh path, 'builtin:NAME[:k=v,...]' or (vertices, triangles), "
                            f"not {type(source).__name__}")
        source = os.fspath(source)
        if source.startswith("builtin:"):
            if check:
                _check_builtin(source)
            return cls("builtin", source, tokenize("builtin", source))
        path = os.path.abspath(source)
        if not check:
            return cls("file", path, tokenize("file", path))
        stat = _checked_file(source, path, "scene file")
        return cls("file", path, tokenize("file", path, stat.st_size, stat.st_mtime_ns))


class StructureFile:
    """A structure saved once with accel.save(), for workers to load instead of building it: path (absolute), spec
    (read from the file's header on the client; None when unchecked) and token (path, size and modification time, so
    a file saved anew is loaded anew). Made on the client by StructureFile.of()."""

    __slots__ = ("path", "spec", "token")

    def __init__(self, path, spec, token):  # pickled by slots, as any class with __slots__ is
        self.path, self.spec, self.token = path, spec, token

    def __repr__(self):
        return f"<rayaccel.dask.StructureFile {self.path!r} {self.spec!r}>"

    @classmethod
    def of(cls, structure, check=True):
        """Checks the file on the client (exists, readable, a saved structure); check=False only makes it absolute."""
        if isinstance(structure, cls):
            return structure
        if not isinstance(structure, (str, os.PathLike)):
            raise TypeError(f"structure must be the path of a file saved with accel.save(), not "
                            f"{type(structure).__name__}")
        path = os.path.abspath(os.fspath(structure))
        if not check:
            return cls(path, None, tokenize("structure", path))
        stat = _checked_file(structure, path, "structure file")
        return cls(path, _core._saved_spec(path), tokenize("structure", path, stat.st_size, stat.st_mtime_ns))


def _check_builtin(spec):
    """Raises ValueError for an unknown built-in scene name or parameter key (values are checked by the worker)."""
    name, _, params = spec[len("builtin:"):].partition(":")
    known = {info["name"]: info["defaults"] for info in builtin_scenes()}
    if name not in known:
        raise ValueError(f"unknown built-in scene '{name}' in '{spec}': known are {', '.join(sorted(known))}")
    for item in filter(None, params.split(",")):
        key = item.partition("=")[0]
        if key not in known[name]:
            raise ValueError(f"built-in scene '{name}' has no parameter '{key}' (it has "
                             f"{', '.join(sorted(known[name])) or 'none'})")


def _ray_array(rays):
    """rays as a dask array of shape (N, 8), one chunk across the 8 columns (a numpy array is wrapped)."""
    if isinstance(rays, np.ndarray):
        rays = da.from_array(rays, chunks=("auto", -1))
    elif not isinstance(rays, da.Array):
        raise TypeError(f"rays must be a dask array (or a numpy array) of shape (N, 8), not {type(rays).__name__}")
    if rays.dtype not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise TypeError(f"rays must be float32 or float64, not {rays.dtype}")
    if rays.ndim != 2 or rays.shape[1] != 8:
        raise ValueError(f"rays must have shape (N, 8) in the .rays layout (ox oy oz tmin dx dy dz tmax), "
                         f"not {rays.shape}")
    return rays if rays.numblocks[1] == 1 else rays.rechunk({1: -1})


def _scene_value(source):
    return source


def _intersect_chunk(rays, source, spec, structure, check, packets):
    return accelerator(source, spec, len(rays), structure).intersect(rays, check=check, packets=packets).records


def _occluded_chunk(rays, source, spec, structure, check):
    return accelerator(source, spec, len(rays), structure).occluded(rays, check=check)


def _trace(query, function, scene_source, rays, spec, structure, dtype, options, check_source):
    source = SceneSource.of(scene_source, check_source)
    spec = Accelerator(spec).spec  # parses the spec: ValueError here, on the client, for a bad one
    if structure is not None:
        structure = StructureFile.of(structure, check_source)
        if structure.spec is not None:
            same_structure(spec, structure.spec, structure.path)
    rays = _ray_array(rays)
    scene_key = f"rayaccel-scene-{source.token}"
    token = tokenize(source.token, spec, None if structure is None else structure.token, rays.name, options)
    name = f"rayaccel-{query}-{token}"
    layer = {(name, i): (function, (rays.name, i, 0), scene_key, spec, structure, *options)
             for i in range(rays.numblocks[0])}
    layers = dict(rays.dask.layers)
    dependencies = dict(rays.dask.dependencies)
    layers[scene_key] = {scene_key: (_scene_value, source)}
    dependencies[scene_key] = set()
    layers[name] = layer
    dependencies[name] = {rays.name, scene_key}
    return da.Array(HighLevelGraph(layers, dependencies), name, chunks=(rays.chunks[0],), dtype=dtype)


def intersect(scene_source, rays, spec=default_spec(), *, structure=None, check=True, packets=False, check_source=True):
    """Closest hits of every ray, as a dask array of shape (N,) and dtype HIT_DTYPE (t, prim_id, u, v: the
    records of accel.intersect(rays), the .hits layout), chunked as the rays along N.

    scene_source: a mesh path every worker can read (made absolute; checked on the client unless
    check_source=False, for clusters whose client cannot see it), "builtin:NAME[:k=v,...]", (vertices, triangles)
    arrays as for rayaccel.mesh, or a Scene from rayaccel.load. rays: a dask (or numpy) array (N, 8), float32 or
    float64, in the .rays layout. spec: any spec of rayaccel.specs(). check and packets: as for accel.intersect.
    structure: the path of a structure saved once with accel.save() over this scene, which each worker loads (with
    load()'s check that it was saved over this very scene: ValueError from compute() otherwise) instead of building
    spec; spec must then name the saved structure (its options are the file's). The client checks that the file is
    a saved structure unless check_source=False. Tasks are named rayaccel-intersect-<token> (progress bars and the
    dashboard group them under that prefix).
    """
    return _trace("intersect", _intersect_chunk, scene_source, rays, spec, structure, HIT_DTYPE,
                  (bool(check), bool(packets)), check_source)


def occluded(scene_source, rays, spec=default_spec(), *, structure=None, check=True, check_source=True):
    """Any hit: a dask bool array of shape (N,) chunked as the rays (accel.occluded(rays)); arguments as intersect()."""
    return _trace("occluded", _occluded_chunk, scene_source, rays, spec, structure, np.dtype(bool), (bool(check),),
                  check_source)

