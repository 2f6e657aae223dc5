"""Rays and points as numpy users pass them: array-likes (np.asarray; integer arrays cast to floating point), numpy
broadcasting of origins, directions, t_min and t_max, and two ray layouts: the .rays record (..., 8) and Open3D's
(..., 6). A batch in which no ray can hit anything (every t_max <= t_min) draws a UserWarning.

The .rays record is ox oy oz tmin dx dy dz tmax (32 bytes in float32, the CLI's .rays files; 64 in float64, .rays64).
"""
import sys
import warnings

import numpy as np

RAYS_LAYOUT = "ox oy oz tmin dx dy dz tmax"
_FLOATS = (np.dtype(np.float32), np.dtype(np.float64))
_SAMPLE = 1024  # rays looked at before the whole batch is (a batch with a usable ray there costs nothing more)


def real_array(value, name, dtype=np.float32):
    """np.asarray(value), float32 and float64 kept as they are (the bindings convert them), integers and other float
    widths cast to `dtype`; TypeError naming `name` for anything that is not a real number."""
    array = np.asarray(value)
    if array.dtype in _FLOATS:
        return array
    if array.dtype.kind in "iuf":
        return array.astype(dtype)
    raise TypeError(f"{name} must be real numbers (float or integer), not {array.dtype}")


def as_points(points, name="points"):
    """(flat (N, 3) float32 C-contiguous array, leading shape) from (..., 3) array-like points."""
    array = real_array(points, name)
    if array.ndim < 1 or array.shape[-1] != 3:
        raise ValueError(f"{name} must have shape (..., 3), not {array.shape}")
    return np.ascontiguousarray(array.reshape(-1, 3), dtype=np.float32), array.shape[:-1]


def as_rays(rays, directions=None, t_min=None, t_max=None, dtype=np.float32):
    """Returns (flat (N, 8) ray array, leading shape) from one of:

    - rays (..., 8) in the .rays layout (an (N, 8) C-contiguous array of `dtype` is used as is, no copy);
    - rays (..., 6), Open3D's ox oy oz dx dy dz, with t_min and t_max (defaults 0 and +inf);
    - origins (..., 3) and directions (..., 3) with t_min and t_max.
    In the last two, origins, directions, t_min and t_max broadcast against each other by numpy's rules (the last
    axis of origins and directions being x y z), and are assembled into a `dtype` array (float64 for the double path).
    """
    if directions is None:
        rays = real_array(rays, "rays", dtype)
        columns = rays.shape[-1] if rays.ndim else None
        if columns == 6:
            return _assemble(rays[..., 0:3], rays[..., 3:6], t_min, t_max, dtype)
        if t_min is not None or t_max is not None:
            raise TypeError("t_min and t_max are columns 3 and 7 of a (..., 8) ray array; pass them only with "
                            "origins and directions, or with (..., 6) rays")
        if columns != 8:
            raise ValueError(f"rays must have shape (..., 8) in the .rays layout ({RAYS_LAYOUT}) or (..., 6) "
                             f"(ox oy oz dx dy dz, Open3D's, t from 0 to inf), not {rays.shape}")
        flat = rays.reshape(-1, 8)
        _warn_about_layout(flat)
        return flat, rays.shape[:-1]
    return _assemble(real_array(rays, "origins", dtype), real_array(directions, "directions", dtype), t_min, t_max,
                     dtype)


def _assemble(origins, directions, t_min, t_max, dtype):
    for array, name in ((origins, "origins"), (directions, "directions")):
        if array.ndim < 1 or array.shape[-1] != 3:
            raise ValueError(f"{name} must have shape (..., 3), not {array.shape}")
    t_min = real_array(0.0 if t_min is None else t_min, "t_min", dtype)
    t_max = real_array(np.inf if t_max is None else t_max, "t_max", dtype)
    try:
        lead = np.broadcast_shapes(origins.shape[:-1], directions.shape[:-1], t_min.shape, t_max.shape)
    except ValueError as error:
        raise ValueError(f"origins {origins.shape}, directions {directions.shape}, t_min {t_min.shape} and t_max "
                         f"{t_max.shape} do not broadcast together (numpy's rules; origins and directions without "
                         f"their last axis, x y z): {error}") from None
    out = np.empty(lead + (8,), dtype=dtype)
    out[..., 0:3] = origins
    out[..., 3] = t_min
    out[..., 4:7] = directions
    out[..., 7] = t_max
    flat = out.reshape(-1, 8)
    if not _some_range_open(flat):
        _warn(f"no ray of this batch of {len(flat)} has t_max > t_min, so none can hit anything (t_min {t_min.shape} "
              f"min {np.min(t_min) if t_min.size else 'none'}, t_max {t_max.shape} max "
              f"{np.max(t_max) if t_max.size else 'none'}; a hit counts when t_min < t <= t_max)")
    return flat, lead


def _some_range_open(flat):
    """True when some ray has t_max > t_min (or the batch is empty); reads only a sample when one is found there."""
    head = flat[:_SAMPLE]
    return len(flat) == 0 or bool(np.any(head[:, 7] > head[:, 3])) or bool(np.any(flat[:, 7] > flat[:, 3]))


def _warn_about_layout(flat):
    """Warns about a (..., 8) array that cannot be in the .rays layout: no ray with t_max > t_min (a zero-filled
    array, t_max left at 0), or unit vectors in columns 3-5 with a negative column 3 in every sampled ray (the
    directions where t_min and dx belong: np.hstack([origins, directions, t_min, t_max]))."""
    columns = (f"an (N, 8) array is read in the .rays layout, {RAYS_LAYOUT}: t_min is column 3 and t_max column 7 "
               f"(np.hstack([origins, directions, t_min, t_max]) puts the directions in columns 3-5 and t_min, t_max "
               f"in 6 and 7; pass intersect(origins, directions, t_min, t_max) for separate arrays, or (N, 6) rays "
               f"ox oy oz dx dy dz)")
    if not _some_range_open(flat):
        _warn(f"no ray of this batch of {len(flat)} has t_max > t_min, so none can hit anything: {columns}")
        return
    head = flat[:_SAMPLE].astype(np.float64)
    if np.any(head[:, 3] < 0) and np.all(np.abs(np.sum(head[:, 3:6] ** 2, axis=1) - 1.0) < 1e-3):
        _warn(f"columns 3-5 of every ray hold a unit vector and column 3 is negative in some: this looks like "
              f"directions in the t_min column; {columns}")


def _warn(message):
    """A UserWarning attributed to the first caller outside the rayaccel package."""
    frame, level = sys._getframe(1), 2
    while frame is not None and frame.f_globals.get("__name__", "").split(".")[0] == "rayaccel":
        frame, level = frame.f_back, level + 1
    warnings.warn(f"rayaccel: {message}", UserWarning, stacklevel=level)
