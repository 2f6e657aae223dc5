"""Instanced scenes: geometries (rayaccel Scenes) placed by affine transforms, traced through a two-level structure
(one bottom-level structure per geometry, a BVH over the instances' world boxes; see the README, "Instances: two
levels").

    iscene = rayaccel.InstancedScene()
    g = iscene.add_geometry(rayaccel.load("bunny.ply"))
    iscene.add_instance(g, np.eye(4))                 # (3, 4) or (4, 4) object-to-world transform
    accel = rayaccel.build_instanced(iscene, bottom="bvh_wide", top="bvh_top")
    hits = accel.intersect(origins, directions)       # Hits: t, prim_id, u, v, geom_id, instance_id
"""
import numpy as np

from . import _core
from ._hits import IHIT_DTYPE, Hits
from ._rays import as_rays


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

    def flatten(self):
        """Every instance's triangles in world space as one triangle Scene (vertices mapped by the instance's
        transform in float64, rounded to float32), instance after instance: instance i's primitive p has id
        offsets[i] + p, offsets = cumsum of the placed geometries' primitive counts, starting at 0. For the queries
        a two-level structure does not answer (closest_points, inside, ...). ValueError for a sphere geometry."""
        vertices, triangles, base = [], [], 0
        for i in range(self.instance_count):
            geometry = self.geometry(self.geometry_of(i))
            if geometry.kind != "triangles":
                raise ValueError(f"flatten() maps triangles; instance {i} places a {geometry.kind} geometry")
            m = self.transform(i)
            vertices.append((geometry.vertices.astype(np.float64) @ m[:, :3].T + m[:, 3]).astype(np.float32))
            triangles.append(geometry.triangles.astype(np.int64) + base)
            base += len(geometry.vertices)
        if not vertices:
            return _core._mesh(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.uint32), "flattened", False)
        return _core._mesh(np.concatenate(vertices), np.concatenate(triangles), "flattened", True)

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
        """Closest hits as Hits over IHIT_DTYPE records, shaped like the rays: t, prim_id within the geometry, u, v,
        and geom_id, instance_id (MISS ids and t = inf where nothing is hit; hits.tobytes() is an .ihits file)."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        return Hits(self._intersect(flat, bool(check)), shape, dtype=IHIT_DTYPE)

    def occluded(self, rays, directions=None, t_min=None, t_max=None, *, check=True):
        """Any hit: a bool array shaped like the rays."""
        flat, shape = as_rays(rays, directions, t_min, t_max)
        return self._occluded(flat, bool(check)).reshape(shape)

    def _not_two_level(self, query):
        raise NotImplementedError(
            f"{query}() is not answered by a two-level structure (InstancedAccelerator answers intersect() and "
            f"occluded()); build a plain structure over the flattened instances instead: "
            f"rayaccel.build(instanced_scene.flatten()).{query}(...)")

    def closest_points(self, points, max_distance=np.inf):
        """Not answered by a two-level structure: raises NotImplementedError (see InstancedScene.flatten())."""
        self._not_two_level("closest_points")

    def inside(self, points, ray_count=3):
        """Not answered by a two-level structure: raises NotImplementedError (see InstancedScene.flatten())."""
        self._not_two_level("inside")

    def signed_distance(self, points, ray_count=3):
        """Not answered by a two-level structure: raises NotImplementedError (see InstancedScene.flatten())."""
        self._not_two_level("signed_distance")

    def all_hits(self, rays, directions=None, t_min=None, t_max=None, *, max_hits=2**32 - 1, check=True):
        """Not answered by a two-level structure: raises NotImplementedError (see InstancedScene.flatten())."""
        self._not_two_level("all_hits")

    def count_hits(self, rays, directions=None, t_min=None, t_max=None, *, check=True):
        """Not answered by a two-level structure: raises NotImplementedError (see InstancedScene.flatten())."""
        self._not_two_level("count_hits")


def build_instanced(scene, bottom=_core.default_spec(), top="bvh_top"):
    """Builds an InstancedAccelerator over an InstancedScene; ValueError for an unknown bottom or top spec, or a top
    structure that cannot take user primitives."""
    if not isinstance(scene, _core._InstancedScene):
        raise TypeError(f"build_instanced() needs a rayaccel.InstancedScene, not {type(scene).__name__}")
    accel = InstancedAccelerator(bottom, top)
    accel.build(scene)
    return accel
