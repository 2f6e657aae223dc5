#!/usr/bin/python3
"""Independent reference tracer: closest hits of a .rays file against a binary PLY triangle mesh, written as .hits.

Follows Woop, Benthin and Wald, "Watertight Ray/Triangle Intersection" (JCGT 2(1), 2013): the ray's dominant axis
becomes z, the triangle is sheared so the ray runs along +z through the origin, and the three 2D edge functions
decide the hit. Every step is float32 arithmetic in numpy with the operation order of the C++ kernel (no fused
multiply-add), with the C++ kernel's bound on the edge functions' rounding error: edge functions of opposite signs
beyond it are a miss; when one lies within it, or the bound is large against the determinant, all three are
recomputed from the float inputs in float64 with a static error bound, or exactly with Python's Fraction when that
bound exceeds 2^-30 of the value, and rounded to float32 (a nonzero value keeping its sign). The hit rule is
t_min < t <= t_max with t clearing t_min by more than the kernel's bound on the error of t, and of equal t the lowest
triangle index wins. The output is meant to be byte-identical to `rayaccel trace --accel brute_force`.

Usage: reference_trace.py MESH.ply RAYS.rays OUT.hits
"""
import sys
from fractions import Fraction

import numpy as np

F32 = np.float32
MISS_PRIM = 0xFFFFFFFF
SMALLEST_SUBNORMAL = np.float32(2.0 ** -149)


def to_float_keeping_sign(e):
    """float64 edge functions rounded to float32, except that a nonzero value too small for float32 becomes the
    smallest subnormal of its sign rather than zero (which would put the ray on the edge)."""
    f = e.astype(F32)
    lost = (f == 0) & (e != 0)
    f[lost] = np.where(e[lost] > 0, SMALLEST_SUBNORMAL, -SMALLEST_SUBNORMAL)
    return f


def read_binary_ply(path):
    """Vertices (N x 3 float32) and triangles (M x 3 int64) of a binary little-endian PLY with triangle faces."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise SystemExit(f"{path}: not a PLY file")
    body = data.index(b"\n", end) + 1
    elements = []  # [name, count, [(property name, type or (list count type, item type))]]
    for line in data[:body].decode("ascii").splitlines():
        words = line.split()
        if not words:
            continue
        if words[0] == "format" and words[1] != "binary_little_endian":
            raise SystemExit(f"{path}: only binary_little_endian PLY is supported")
        if words[0] == "element":
            elements.append([words[1], int(words[2]), []])
        elif words[0] == "property":
            kind = (words[2], words[3]) if words[1] == "list" else words[1]
            elements[-1][2].append((words[-1], kind))
    types = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "<i2", "int16": "<i2",
             "ushort": "<u2", "uint16": "<u2", "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
             "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8"}
    offset = body
    vertices = faces = None
    for name, count, props in elements:
        if all(not isinstance(kind, tuple) for _, kind in props):
            record = np.dtype([(p, types[kind]) for p, kind in props])
            table = np.frombuffer(data, dtype=record, count=count, offset=offset)
            offset += record.itemsize * count
            if name == "vertex":
                vertices = np.stack([table["x"], table["y"], table["z"]], axis=1).astype(F32)
        elif name == "face" and len(props) == 1:
            count_type, item_type = (types[t] for t in props[0][1])
            count_size, item_size = np.dtype(count_type).itemsize, np.dtype(item_type).itemsize
            first = np.frombuffer(data, dtype=count_type, count=1, offset=offset)[0] if count else 3
            if first != 3:
                raise SystemExit(f"{path}: only triangle faces are supported")
            record = np.dtype([("n", count_type), ("i", item_type, (3,))])
            if record.itemsize != count_size + 3 * item_size:
                raise SystemExit(f"{path}: unexpected face layout")
            table = np.frombuffer(data, dtype=record, count=count, offset=offset)
            if np.any(table["n"] != 3):
                raise SystemExit(f"{path}: only triangle faces are supported")
            faces = table["i"].astype(np.int64)
            offset += record.itemsize * count
        else:
            raise SystemExit(f"{path}: element '{name}' has a layout this reader does not handle")
    if vertices is None or faces is None:
        raise SystemExit(f"{path}: needs vertex and face elements")
    return vertices, faces


class Mesh:
    """Per-axis float32 vertex columns of every valid triangle (finite vertices, non-zero area), with their ids.

    Zero area is decided exactly: edge vectors and their cross product in float64 from the stored float32 vertices."""

    def __init__(self, vertices, faces):
        corners = vertices[faces]  # M x 3 (corner) x 3 (axis)
        valid = np.all(np.isfinite(corners), axis=(1, 2))
        wide = corners.astype(np.float64)
        with np.errstate(invalid="ignore", over="ignore"):
            normal = np.cross(wide[:, 1] - wide[:, 0], wide[:, 2] - wide[:, 0])
        valid &= np.any(normal != 0, axis=1)
        self.ids = np.nonzero(valid)[0]
        corners = corners[valid]
        self.v = [[np.ascontiguousarray(corners[:, c, axis]) for axis in range(3)] for c in range(3)]


def dominant_axis(ad):
    """Index of the largest component, ties to the lower axis (the C++ max_axis)."""
    if ad[0] >= ad[1] and ad[0] >= ad[2]:
        return 0
    return 1 if ad[1] >= ad[2] else 2


def gamma(n):
    """gamma(n) = n u / (1 - n u), u = 2^-24, in float32 as the C++ float_gamma() computes it."""
    nu = F32(n) * F32(2.0 ** -24)
    return nu / (F32(1) - nu)


SLACK = F32(1.0 + 2.0 ** -16)
EDGE_FLOOR = F32(2.0 ** -100)
ILL_CONDITIONED = F32(192)
EXACT_RELATIVE = F32(2.0 ** -22)
EXACT_FLOOR = F32(2.0 ** -148)


def round_up_to_float(x):
    """The smallest float32 >= the float64 x."""
    f = F32(x)
    return np.nextafter(f, F32(np.inf)) if float(f) < x else f


def edge_in_double(origin, direction, axes, p, q):
    """G = E d_z for the edge of vertices p, q, in float64 with the C++ kernel's operations and static error bound."""
    pa = [float(p[a]) - float(origin[a]) for a in axes]
    qa = [float(q[a]) - float(origin[a]) for a in axes]
    d = [float(direction[a]) for a in axes]
    g = permanent = 0.0
    for c, i, j in ((2, 0, 1), (0, 1, 2), (1, 2, 0)):
        left, right = pa[i] * qa[j], pa[j] * qa[i]
        g += d[c] * (left - right)
        permanent += abs(d[c]) * (abs(left) + abs(right))
    return g, (10.0 * 2.0 ** -53) * permanent


def edge_exactly(origin, direction, axes, p, q):
    """The edge function E = X_p Y_q - Y_p X_q of the float ray and vertices, as (value, error bound): in float64
    when its error bound is below 2^-30 of the value (t is computed from these values, so a decided sign alone is
    not enough), else exactly (the value rounded)."""
    dz = float(direction[axes[2]])
    g, error = edge_in_double(origin, direction, axes, p, q)
    if abs(g) * 2.0 ** -30 > error:
        return g / dz, error / abs(dz)
    fr = [Fraction(float(v)) for v in origin], [Fraction(float(v)) for v in direction]
    pa = [Fraction(float(p[a])) - fr[0][a] for a in axes]
    qa = [Fraction(float(q[a])) - fr[0][a] for a in axes]
    d = [fr[1][a] for a in axes]
    exact = (d[2] * (pa[0] * qa[1] - pa[1] * qa[0]) + d[0] * (pa[1] * qa[2] - pa[2] * qa[1])
             + d[1] * (pa[2] * qa[0] - pa[0] * qa[2]))
    value = 0.0 if exact == 0 else float(exact) / dz
    return value, abs(value) * 2.0 ** -50


def trace_ray(mesh, ray):
    """(t, prim, u, v) of the closest hit with t_min < t <= t_max, or the miss record."""
    origin, t_min, direction, t_max = ray[0:3], ray[3], ray[4:7], ray[7]
    # Subnormal direction components read as zero of their sign (their reciprocals overflow float).
    direction = np.where(np.abs(direction) < np.finfo(np.float32).tiny, np.copysign(F32(0), direction), direction)
    miss = (F32(np.inf), MISS_PRIM, F32(0), F32(0))
    valid = (np.all(np.isfinite(origin)) and np.all(np.isfinite(direction)) and np.any(direction != 0)
             and not np.isnan(t_min) and not np.isnan(t_max) and t_min <= t_max)
    if not valid or mesh.ids.size == 0:
        return miss
    kz = dominant_axis(np.abs(direction))
    kx = (kz + 1) % 3
    ky = (kx + 1) % 3
    if direction[kz] < 0:
        kx, ky = ky, kx
    dz = direction[kz]
    sx = F32(direction[kx] / dz)
    sy = F32(direction[ky] / dz)
    sz = F32(F32(1) / dz)

    # Vertices relative to the origin, then sheared: p_x - s_x * p_z (each product rounded on its own).
    rel = [[mesh.v[c][axis] - origin[axis] for axis in range(3)] for c in range(3)]
    px = [rel[c][kx] - sx * rel[c][kz] for c in range(3)]
    py = [rel[c][ky] - sy * rel[c][kz] for c in range(3)]
    pz = [rel[c][kz] for c in range(3)]
    (ax, bx, cx), (ay, by, cy) = px, py
    # The C++ kernel rescales triangles whose sheared coordinates leave [2^-40, 2^40]; this reference does not model
    # that path, so it refuses rays that would need it rather than answer differently.
    magnitude = np.max(np.abs(np.stack(px + py + pz)), axis=0)
    if np.any((magnitude > 2.0 ** 40) | (magnitude < 2.0 ** -40)):
        raise SystemExit("a triangle is outside the float kernel's safe range for this ray; not modelled here")
    eu = cx * by - cy * bx
    ev = ax * cy - ay * cx
    ew = bx * ay - by * ax
    # The bound on the edge functions' error (TriangleErrorBounds in ray_triangle.h, operation for operation).
    max_x = np.maximum(np.abs(ax), np.maximum(np.abs(bx), np.abs(cx)))
    max_y = np.maximum(np.abs(ay), np.maximum(np.abs(by), np.abs(cy)))
    max_z = np.maximum(np.abs(pz[0]), np.maximum(np.abs(pz[1]), np.abs(pz[2])))
    lo_z = np.minimum(pz[0], np.minimum(pz[1], pz[2]))
    hi_z = np.maximum(pz[0], np.maximum(pz[1], pz[2]))
    dx = gamma(3) * max_x + (gamma(5) * np.abs(sx)) * max_z
    dy = gamma(3) * max_y + (gamma(5) * np.abs(sy)) * max_z
    edge_error = ((F32(2) * gamma(2)) * max_x * max_y + F32(2) * ((dx * max_y + dy * max_x) + dx * dy)) * SLACK
    edge_error = edge_error + EDGE_FLOOR
    lo_e = np.minimum(eu, np.minimum(ev, ew))
    hi_e = np.maximum(eu, np.maximum(ev, ew))
    surely_mixed = (lo_e < -edge_error) & (hi_e > edge_error)
    det = (eu + ev) + ew
    in_band = (np.abs(eu) <= edge_error) | (np.abs(ev) <= edge_error) | (np.abs(ew) <= edge_error)
    ill = edge_error * ILL_CONDITIONED >= np.abs(det)
    redo = np.nonzero((in_band | ill) & ~surely_mixed)[0]
    axes = (kx, ky, kz)
    for i in redo:
        # All three edge functions from the float inputs, exactly signed (edge_exactly), rounded to float32.
        verts = [np.array([mesh.v[c][a][i] for a in range(3)]) for c in range(3)]
        error = 0.0
        values = []
        for p, q in ((verts[2], verts[1]), (verts[0], verts[2]), (verts[1], verts[0])):
            value, err = edge_exactly(origin, direction, axes, p, q)
            error = max(error, err)
            values.append(value)
        e = to_float_keeping_sign(np.array(values, dtype=np.float64))
        eu[i], ev[i], ew[i] = e
        max_e = np.maximum(np.abs(e[0]), np.maximum(np.abs(e[1]), np.abs(e[2])))
        edge_error[i] = (round_up_to_float(error) + max_e * EXACT_RELATIVE) * SLACK + EXACT_FLOOR
        det[i] = (e[0] + e[1]) + e[2]
    negative = (eu < 0) | (ev < 0) | (ew < 0)
    positive = (eu > 0) | (ev > 0) | (ew > 0)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        # The depth along the dominant axis first, brought to t by the one multiplication by sz last.
        scaled_depth = (eu * pz[0] + ev * pz[1]) + ew * pz[2]
        inv_det = F32(1) / det
        t = (scaled_depth * inv_det) * sz
        # The bound on t's error: t_error_bound() in ray_triangle.h, operation for operation.
        depth_error = (((F32(3) * edge_error) * np.abs(inv_det)) * (hi_z - lo_z) + gamma(12) * max_z) * SLACK
        bound = depth_error * np.abs(sz)
        clears_t_min = t > F32(t_min) + bound
    upper = np.nextafter(F32(t_max), F32(np.inf))  # exclusive bound, as Hit::begin sets it
    accept = ~surely_mixed & ~(negative & positive) & (det != 0) & (t > t_min) & (t < upper) & clears_t_min
    if not np.any(accept):
        return miss
    candidates = np.nonzero(accept)[0]
    best = candidates[np.argmin(t[candidates])]  # argmin keeps the first (lowest id) of equal t
    return (t[best], int(mesh.ids[best]), ev[best] * inv_det[best], ew[best] * inv_det[best])


def main(argv):
    if len(argv) != 4:
        raise SystemExit(__doc__)
    vertices, faces = read_binary_ply(argv[1])
    mesh = Mesh(vertices, faces)
    rays = np.fromfile(argv[2], dtype="<f4")
    if rays.size % 8:
        raise SystemExit(f"{argv[2]}: size is not a multiple of 32 bytes")
    rays = rays.reshape(-1, 8).astype(F32)
    record = np.dtype([("t", "<f4"), ("prim", "<u4"), ("u", "<f4"), ("v", "<f4")])
    hits = np.zeros(len(rays), dtype=record)
    for i, ray in enumerate(rays):
        hits[i] = trace_ray(mesh, ray)
    hits.tofile(argv[3])


if __name__ == "__main__":
    main(sys.argv)
