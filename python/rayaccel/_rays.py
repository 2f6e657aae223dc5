"""Ray arrays in the .rays layout and the result types of queries (Hits, TraversalStats).

A ray array has shape (..., 8), float32: ox oy oz tmin dx dy dz tmax, the 32-byte record of the CLI's .rays files.
Hit records have the 16-byte .hits layout (HIT_DTYPE), so ``hits.records.tobytes()`` is a .hits file. The double
path's rays are float64 (the 64-byte .rays64 record) and its hits the 32-byte .hits64 records (HIT64_DTYPE).
"""
import numpy as np

HIT_DTYPE = np.dtype([("t", "<f4"), ("prim_id", "<u4"), ("u", "<f4"), ("v", "<f4")])
#: The .hits64 record: float64 t, uint32 prim_id, 4 bytes of zero padding, float64 u, float64 v.
HIT64_DTYPE = np.dtype({"names": ["t", "prim_id", "u", "v"], "formats": ["<f8", "<u4", "<f8", "<f8"],
                        "offsets": [0, 8, 16, 24], "itemsize": 32})
MISS = 0xFFFFFFFF  # prim_id of a miss
_FLOATS = (np.dtype(np.float32), np.dtype(np.float64))


def _float_array(value, name):
    array = np.asarray(value)
    if array.dtype not in _FLOATS:
        raise TypeError(f"{name} must be float32 or float64, not {array.dtype}")
    return array


def as_rays(rays, directions=None, t_min=None, t_max=None, dtype=np.float32):
    """Returns (flat (N, 8) ray array, leading shape) from a (..., 8) ray array, or from origins and directions.

    origins and directions have shape (..., 3) (origins may be one point, shape (3,)); t_min and t_max are scalars
    or arrays of the leading shape (defaults 0 and +inf), assembled into a `dtype` array (float64 for the double
    path). An (N, 8) C-contiguous array of `dtype` is used as is.
    """
    if directions is None:
        if not isinstance(rays, np.ndarray):
            raise TypeError(f"rays must be a numpy array of shape (..., 8), not {type(rays).__name__}")
        if t_min is not None or t_max is not None:
            raise TypeError("t_min and t_max are columns 3 and 7 of a (..., 8) ray array; pass them only with "
                            "origins and directions")
        _float_array(rays, "rays")
        if rays.ndim < 1 or rays.shape[-1] != 8:
            raise ValueError(f"rays must have shape (..., 8) in the .rays layout (ox oy oz tmin dx dy dz tmax), "
                             f"not {rays.shape}")
        return rays.reshape(-1, 8), rays.shape[:-1]
    origins = _float_array(rays, "origins")
    directions = _float_array(directions, "directions")
    if directions.ndim < 1 or directions.shape[-1] != 3:
        raise ValueError(f"directions must have shape (..., 3), not {directions.shape}")
    if origins.shape != directions.shape and origins.shape != (3,):
        raise ValueError(f"origins must have the shape of directions {directions.shape} (or (3,) for one origin), "
                         f"not {origins.shape}")
    lead = directions.shape[:-1]
    out = np.empty(lead + (8,), dtype=dtype)
    out[..., 0:3] = origins
    out[..., 4:7] = directions
    for column, value, default, name in ((3, t_min, 0.0, "t_min"), (7, t_max, np.inf, "t_max")):
        if value is None:
            value = default
        elif isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
            value = _float_array(value, name)
            if value.ndim != 0 and value.shape != lead:
                raise ValueError(f"{name} must be a scalar or have shape {lead}, not {value.shape}")
        out[..., column] = value
    return out.reshape(-1, 8), lead


class TraversalStats:
    """Per-ray traversal cost: nodes (or cells) entered and primitives tested; cost is their sum (the heat map's)."""

    def __init__(self, counts, shape):
        self.nodes_visited = counts[:, 0].reshape(shape)
        self.primitives_tested = counts[:, 1].reshape(shape)

    @property
    def cost(self):
        return self.nodes_visited + self.primitives_tested


class Hits:
    """Closest hits of a batch, shaped like the rays' leading dimensions.

    t (inf at a miss), prim_id (MISS = 0xFFFFFFFF at a miss), u, v (barycentrics, p = (1-u-v) v0 + u v1 + v v2) are
    views of ``records`` (HIT_DTYPE, the .hits layout). points and normals ((..., 3) float32, NaN at misses) are set
    when asked for; stats (TraversalStats) too.
    """

    def __init__(self, records, shape, points=None, normals=None, stats=None, dtype=HIT_DTYPE):
        self.records = records.view(dtype).reshape(shape)
        self.points = None if points is None else points.reshape(shape + (3,))
        self.normals = None if normals is None else normals.reshape(shape + (3,))
        self.stats = stats

    t = property(lambda self: self.records["t"])
    prim_id = property(lambda self: self.records["prim_id"])
    u = property(lambda self: self.records["u"])
    v = property(lambda self: self.records["v"])

    @property
    def hit(self):
        """True where the ray hit something."""
        return self.records["prim_id"] != MISS

    def __len__(self):
        return len(self.records)

    def __repr__(self):
        return f"<rayaccel.Hits {self.records.shape}: {int(np.count_nonzero(self.hit))} hits>"

    def tobytes(self):
        """The records as a .hits file's bytes (.hits64 for the double path's hits)."""
        return self.records.tobytes()
