"""The CLI's pinhole camera as ray arrays, the renderer's images, heat-map colouring and the bench's secondary rays.

Camera conventions are those of ``rayaccel render`` (shared/scenes/MANIFEST.md): image x along
normalize(cross(forward, up)), row 0 at the top, one ray through each pixel centre, unit directions, t in [0, inf).
"""
from dataclasses import dataclass

import numpy as np

from . import _core
from ._hits import HIT_DTYPE
from ._rays import as_rays


def _point(value, name):
    array = np.asarray(value, dtype=np.float64)
    if array.shape != (3,) or not np.all(np.isfinite(array)):
        raise ValueError(f"{name} must be three finite numbers, not {value!r}")
    return tuple(float(x) for x in array)


@dataclass
class Camera:
    """Pinhole camera: eye, look-at point, up hint, full vertical field of view in degrees."""

    eye: tuple = (0.0, 0.0, 1.0)
    at: tuple = (0.0, 0.0, 0.0)
    up: tuple = (0.0, 1.0, 0.0)
    fov: float = 45.0

    def _args(self):
        eye, at, up = _point(self.eye, "eye"), _point(self.at, "at"), _point(self.up, "up")
        if not (0.0 < float(self.fov) < 180.0):
            raise ValueError(f"fov must be in (0, 180) degrees, not {self.fov}")
        if eye == at:
            raise ValueError("eye and at are the same point")
        return eye, at, up, float(self.fov)

    def rays(self, width, height):
        """(height, width, 8) float32 rays, the CLI's primary rays (row-major from the top-left pixel)."""
        return _core._camera_rays(*self._args(), int(width), int(height))

    @classmethod
    def framing(cls, scene):
        """The CLI's default camera for a scene: its MANIFEST.md camera when it was loaded from a shared scene file,
        else a three-quarter view framing its bounds."""
        eye, at, up, fov = _core._default_camera(getattr(scene, "source", "") or "", scene)
        return cls(tuple(eye), tuple(at), tuple(up), fov)


def render(accel, camera=None, width=512, height=512, mode="normals", ao_samples=8, ao_distance=0.1, seed=1):
    """An image of the accelerator's scene as ``rayaccel render`` draws it: (height, width, 3) uint8.

    mode: "normals", "ao" (ambient occlusion, ao_samples rays of ao_distance times the scene diagonal) or "heatmap"
    (traversal cost per pixel with its legend). camera defaults to Camera.framing(accel.scene).
    """
    if not accel.built:
        raise ValueError(f"accelerator '{accel.spec}' is not built: call build(scene) first")
    camera = camera or Camera.framing(accel.scene)
    return accel._render(*camera._args(), int(width), int(height), str(mode), int(ao_samples), float(ao_distance),
                         int(seed))


def heatmap(cost, vmin=None, vmax=None):
    """Colours a cost array (e.g. ``hits.stats.cost``) with the CLI's heat-map ramp: (..., 3) uint8.

    The scale runs linearly from vmin (default: the cheapest ray) to vmax (default: the 99th-percentile cost, as
    the CLI's heat maps); pass the same vmin and vmax to several images to compare them by eye.
    """
    cost = np.asarray(cost)
    if cost.dtype.kind not in "uif":
        raise TypeError(f"cost must be a numeric array, not {cost.dtype}")
    flat = np.sort(cost, axis=None)
    if flat.size and vmin is None:
        vmin = flat[0]
    if flat.size and vmax is None:
        vmax = flat[int(0.99 * (flat.size - 1))]
    if not flat.size:
        return np.zeros(cost.shape + (3,), dtype=np.uint8)
    vmin, vmax = float(vmin), float(vmax)
    if vmax > vmin:
        fraction = np.clip((cost.astype(np.float64) - vmin) / (vmax - vmin), 0.0, 1.0)
    else:
        fraction = np.full(cost.shape, 0.5)
    return _core._heat_colours(fraction.astype(np.float32))


def _secondary(scene, rays, hits, kind, max_distance, seed):
    flat, _ = as_rays(rays)
    records = np.ascontiguousarray(hits.records).reshape(-1).view(np.uint8).reshape(-1, HIT_DTYPE.itemsize)
    return _core._secondary_rays(scene, flat, records, kind, float(max_distance), int(seed))


def diffuse_rays(scene, rays, hits, seed=1):
    """The bench's diffuse rays: one cosine-weighted bounce from each hit of (rays, hits), (K, 8) float32."""
    return _secondary(scene, rays, hits, "diffuse", np.inf, seed)


def shadow_rays(scene, rays, hits, max_distance, seed=1):
    """The bench's shadow (ambient-occlusion) rays: like diffuse_rays with t_max = max_distance."""
    return _secondary(scene, rays, hits, "shadow", max_distance, seed)
