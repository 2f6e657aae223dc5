"""The per-process cache of structures behind rayaccel.dask: one Accelerator per (scene token, spec, structure file).

A worker process (or the client, under the threads and synchronous schedulers) builds each structure once, or loads
it once from a file saved with accel.save(), and reuses it for every chunk. The cache is an LRU of at most
`set_cache_size(n)` entries (default 4, or the environment variable RAYACCEL_DASK_CACHE_SIZE), so a long-lived
worker that sees many scenes keeps only the latest few. Thread safe: concurrent chunks of the same (scene, spec) in
one process wait for one build instead of building twice; different structures build concurrently. cache_info()
reports the counts the tests and benchmarks read.
"""
import collections
import os
import threading
import time

from . import Accelerator

_lock = threading.Lock()               # guards everything below; never held while building
_entries = collections.OrderedDict()  # (token, spec, file token) -> Accelerator, least recently used first
_building = {}                        # (token, spec, file token) -> Lock held by the one thread making it
_limit = max(1, int(os.environ.get("RAYACCEL_DASK_CACHE_SIZE", "4")))
_ZERO = dict(builds=0, build_s=0.0, loads=0, load_s=0.0, chunks=0, rays=0, evictions=0)
_counts = dict(_ZERO)


def same_structure(spec, saved_spec, path):
    """ValueError unless spec names the structure saved in path (whose header gives saved_spec); the options are the
    file's, so only the names are compared."""
    name, saved = spec.partition(":")[0].strip(), saved_spec.partition(":")[0].strip()
    if name != saved:
        raise ValueError(f"structure file '{path}' holds '{saved_spec}', not '{spec}': pass spec='{saved}' with it "
                         f"(or no structure, to build '{spec}' on every worker)")


def _make(source, spec, structure):
    """A new structure: built over source.scene(), or loaded from the structure file over it."""
    accel = Accelerator(spec)
    if structure is None:
        accel.build(source.scene())
        return accel
    accel.load(structure.path, source.scene())  # ValueError naming the file when it was saved over another scene
    same_structure(spec, accel.spec, structure.path)
    return accel


def accelerator(source, spec, rays=0, structure=None):
    """The structure `spec` over source.scene(), built (or, given a StructureFile, loaded) on the first call in this
    process and cached. Each call counts as one chunk of `rays` rays in cache_info()."""
    key = (source.token, spec, None if structure is None else structure.token)
    with _lock:
        _counts["chunks"] += 1
        _counts["rays"] += rays
        if key in _entries:
            _entries.move_to_end(key)
            return _entries[key]
        gate = _building.setdefault(key, threading.Lock())
    with gate:
        with _lock:
            if key in _entries:  # built by the thread this one waited for
                _entries.move_to_end(key)
                return _entries[key]
        try:
            start = time.perf_counter()
            accel = _make(source, spec, structure)
            elapsed = time.perf_counter() - start
        finally:
            with _lock:
                _building.pop(key, None)
        count, seconds = ("builds", "build_s") if structure is None else ("loads", "load_s")
        with _lock:
            _counts[count] += 1
            _counts[seconds] += elapsed
            _entries[key] = accel
            while len(_entries) > _limit:
                _entries.popitem(last=False)
                _counts["evictions"] += 1
        return accel


def set_cache_size(entries):
    """Keeps at most `entries` (>= 1) structures in this process; returns the previous limit."""
    global _limit
    if int(entries) < 1:
        raise ValueError(f"the cache holds at least one structure, not {entries}")
    with _lock:
        previous, _limit = _limit, int(entries)
        while len(_entries) > _limit:
            _entries.popitem(last=False)
            _counts["evictions"] += 1
    return previous


def clear_cache():
    """Drops every cached structure of this process and zeroes its counts."""
    with _lock:
        _entries.clear()
        _counts.update(_ZERO)


def cache_info():
    """This process's counts: pid, builds (structures built), build_s (their total seconds), loads and load_s (the
    same for structures loaded from files), chunks and rays traced, evictions, limit, and entries ([spec, scene
    token] of each cached structure, least recently used first)."""
    with _lock:
        return dict(_counts, pid=os.getpid(), limit=_limit,
                    entries=[[spec, token] for token, spec, _ in _entries])
