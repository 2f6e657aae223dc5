"""Instanced scenes: geometries (rayaccel Scenes) placed by affine transforms, traced through a two-level structure
(one bottom-level structure per geometry, a BVH over the instances' world boxes; see the README, "Instances: two
levels").

    iscene = rayaccel.InstancedScene()
    g = iscene.add_geometry(rayaccel.load("bunny.ply"))
    iscene.add_instance(g, np.eye(4))                 # (3, 4) or (4, 4) object-to-world transform
    accel = rayaccel.build_instanced(iscene, bottom="bvh_wide", top="bvh_top")
    hits = accel.intersect(origins, directions)       # IHIT_DTYPE: t, prim_id, u, v, geom_id, instance_id
"""
import numpy as np

from . import _core
from ._rays import as_rays

#: One closest hit of an instanced trace, the 24-byte layout of the CLI's .ihits file (a miss: t = inf, every id
#: MISS, u = v = 0).
IHIT_DTYPE = np.dtype([("t", "<f4"), ("prim_id", "<u4"), ("u", "<f4"), ("v", "<f4"), ("geom_id", "<u4"),
                       ("instance_id", "<u4")])


class InstancedScene(_core._InstancedScene):
    """Geometries (rayaccel Scenes of any kind, shared, not copied) and instances placing them in the world.

    An instance whose transform is exactly the identity traces the world ray itself, so geometries placed side by
    side with the identity are watertight across each other (a ray through an edge they share hits one of them).
    """

    def add_instance(self, geometry, transform=None, instance_id=None):
        """Places geometry (an index from add_geometry) by transform ((3, 4) or (4, 4), object to world; the last
        row of a (4, 4) one must be 0 0 0 1; None: the identity). instance_id (default: the instance's index) is
        what hits report. Returns the instance's index. ValueError for a singular or non-finite transform."""
        if transform is None:
            transform = np.eye(3, 4)
        return self._add_instance(int(geometry), transform, None if instance_id is None else int(instance_id))

    def __repr__(self):
        return f"<rayaccel.InstancedScene {self.geometry_count} geometries, {self.instance_count} instances>"


class InstancedAccelerator(_core._InstancedAccelerator):
    """A two-level structure over an InstancedScene; bottom is the spec of every geometry's structure, top the top
    level's ("bvh_top", the BVH over instance boxes, or any registry spec built over one user primitive per
    instance). Rays as for Accelerator: a (..., 8) array, or origins and directions with t_min and t_max."""

    def __init__(self, bottom=_core.default_spec(), top="bvh_top"):
        super().__init__(str(bottom), str(top))

    def __repr__(self):
        return f"<rayaccel.InstancedAccelerator bottom '{self.bottom}', top '{self.top}'>"

    def intersect(self, rays, directions=None, t_min=None, t_max=None, *, check=True):
        """Closest hits: an IHIT_DTYPE array shaped like the rays (t, prim_id within the geometry, u, v, geom_id,
        instance_id; MISS ids and t = inf where nothing is hit)."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        return self._intersect(flat, bool(check)).reshape(-1).view(IHIT_DTYPE).reshape(shape)

    def occluded(self, rays, directions=None, t_min=None, t_max=None, *, check=True):
        """Any hit: a bool array shaped like the rays."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        return self._occluded(flat, bool(check)).reshape(shape)


def build_instanced(scene, bottom=_core.default_spec(), top="bvh_top"):
    """Builds an InstancedAccelerator over an InstancedScene; ValueError for an unknown bottom or top spec, or a top
    structure that cannot take user primitives."""
    if not isinstance(scene, _core._InstancedScene):
        raise TypeError(f"build_instanced() needs a rayaccel.InstancedScene, not {type(scene).__name__}")
    accel = InstancedAccelerator(bottom, top)
    accel.build(scene)
    return accel
