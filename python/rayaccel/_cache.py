"""The per-process cache of built structures behind rayaccel.dask: one Accelerator per (scene token, spec).

A worker process (or the client, under the threads and synchronous schedulers) builds each structure once and reuses
it for every chunk. The cache is an LRU of at most `set_cache_size(n)` entries (default 4, or the environment
variable RAYACCEL_DASK_CACHE_SIZE), so a long-lived worker that sees many scenes keeps only the latest few. Thread
safe: concurrent chunks of the same (scene, spec) in one process wait for one build instead of building twice;
different structures build concurrently. cache_info() reports the counts the tests and benchmarks read.
"""
import collections
import os
import threading
import time

from . import Accelerator

_lock = threading.Lock()               # guards everything below; never held while building
_entries = collections.OrderedDict()  # (token, spec) -> Accelerator, least recently used first
_building = {}                        # (token, spec) -> Lock held by the one thread building it
_limit = max(1, int(os.environ.get("RAYACCEL_DASK_CACHE_SIZE", "4")))
_counts = dict(builds=0, build_s=0.0, chunks=0, rays=0, evictions=0)


def accelerator(source, spec, rays=0):
    """The structure `spec` over source.scene(), built on the first call in this process and cached. Each call
    counts as one chunk of `rays` rays in cache_info()."""
    key = (source.token, spec)
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
            accel = Accelerator(spec)
            accel.build(source.scene())
            elapsed = time.perf_counter() - start
        finally:
            with _lock:
                _building.pop(key, None)
        with _lock:
            _counts["builds"] += 1
            _counts["build_s"] += elapsed
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
        _counts.update(builds=0, build_s=0.0, chunks=0, rays=0, evictions=0)


def cache_info():
    """This process's counts: pid, builds (structures built), build_s (their total seconds), chunks and rays traced,
    evictions, limit, and entries ([spec, scene token] of each cached structure, least recently used first)."""
    with _lock:
        return dict(_counts, pid=os.getpid(), limit=_limit,
                    entries=[[spec, token] for token, spec in _entries])
