"""The result types of queries: Hits (closest hits of a batch, plain, double or instanced) and TraversalStats.

Hit records have the 16-byte .hits layout (HIT_DTYPE), so ``hits.tobytes()`` is a .hits file; the double path's are
the 32-byte .hits64 records (HIT64_DTYPE), an instanced trace's the 24-byte .ihits records (IHIT_DTYPE).
"""
import numpy as np

HIT_DTYPE = np.dtype([("t", "<f4"), ("prim_id", "<u4"), ("u", "<f4"), ("v", "<f4")])
#: The .hits64 record: float64 t, uint32 prim_id, 4 bytes of zero padding, float64 u, float64 v.
HIT64_DTYPE = np.dtype({"names": ["t", "prim_id", "u", "v"], "formats": ["<f8", "<u4", "<f8", "<f8"],
                        "offsets": [0, 8, 16, 24], "itemsize": 32})
#: One closest hit of an instanced trace, the 24-byte layout of the CLI's .ihits file (a miss: t = inf, every id
#: MISS, u = v = 0).
IHIT_DTYPE = np.dtype([("t", "<f4"), ("prim_id", "<u4"), ("u", "<f4"), ("v", "<f4"), ("geom_id", "<u4"),
                       ("instance_id", "<u4")])
MISS = 0xFFFFFFFF  # prim_id of a miss


class TraversalStats:
    """Per-ray traversal cost: nodes (or cells) entered and primitives tested; cost is their sum (the heat map's)."""

    def __init__(self, counts, shape):
        self.nodes_visited = counts[:, 0].reshape(shape)
        self.primitives_tested = counts[:, 1].reshape(shape)

    @property
    def cost(self):
        return self.nodes_visited + self.primitives_tested


def _field(name):
    def get(self):
        if name not in self.records.dtype.names:
            raise AttributeError(f"'{name}' is a field of an instanced accelerator's hits (IHIT_DTYPE); these are "
                                 f"{self.records.dtype.names}")
        return self.records[name]
    return property(get, doc=f"The records' '{name}' field (instanced hits only).")


class Hits:
    """Closest hits of a batch, shaped like the rays' leading dimensions; every accelerator returns this type.

    t (inf at a miss), prim_id (MISS = 0xFFFFFFFF at a miss), u, v (barycentrics, p = (1-u-v) v0 + u v1 + v v2) are
    views of ``records`` (HIT_DTYPE, the .hits layout; HIT64_DTYPE for the double path; IHIT_DTYPE for an instanced
    accelerator, whose hits also have geom_id and instance_id). points and normals ((..., 3) float32, NaN at misses)
    are set when asked for; stats (TraversalStats) too. hits[key] indexes the records (hits["t"], hits[mask]).
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
    geom_id = _field("geom_id")
    instance_id = _field("instance_id")

    @property
    def hit(self):
        """True where the ray hit something."""
        return self.records["prim_id"] != MISS

    @property
    def shape(self):
        """The rays' leading shape."""
        return self.records.shape

    def __len__(self):
        return len(self.records)

    def __getitem__(self, key):
        return self.records[key]

    def __repr__(self):
        return f"<rayaccel.Hits {self.records.shape}: {int(np.count_nonzero(self.hit))} hits>"

    def tobytes(self):
        """The records as a .hits file's bytes (.hits64 for the double path's hits, .ihits for instanced ones)."""
        return self.records.tobytes()
