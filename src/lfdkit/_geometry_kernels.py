"""Compiled inner loop of :class:`lfdkit.geometry.PolylineSet` (numba).

The nearest crossing of every query point's normal hyperplane with every
polyline, pruned by bounding balls over chunks of segments. Imported lazily
by :mod:`lfdkit.geometry`: compiling costs a few seconds once, after which the
machine code is cached on disk next to this file.
"""

import numba
import numpy as np


@numba.njit(cache=True, inline="always")
def _check_chunk(p, t, verts, v0, n_seg, c, b, same_direction, tol, best, out_pt_row):
    """Best crossing of chunk ``c``; returns (distance, segment) improving on ``best``."""
    q = p.shape[0]
    best_seg = -1
    first = c * b
    last = min(first + b, n_seg)  # exclusive segment bound
    side_a = 0.0
    for k in range(q):
        side_a += (verts[v0 + first, k] - p[k]) * t[k]
    if abs(side_a) <= tol:
        side_a = 0.0
    for s in range(first, last):
        side_b = 0.0
        for k in range(q):
            side_b += (verts[v0 + s + 1, k] - p[k]) * t[k]
        if abs(side_b) <= tol:
            side_b = 0.0
        if same_direction:
            crosses = side_a <= 0.0 and side_b >= 0.0 and side_b > side_a
        else:
            crosses = (side_a <= 0.0 and side_b >= 0.0) or (side_a >= 0.0 and side_b <= 0.0)
        if crosses:
            ds = side_b - side_a
            u = -side_a / ds if ds != 0.0 else 0.0
            d2 = 0.0
            for k in range(q):
                a = verts[v0 + s, k]
                x = a + u * (verts[v0 + s + 1, k] - a) - p[k]
                d2 += x * x
            d = np.sqrt(d2)
            if d < best:
                best = d
                best_seg = s
                for k in range(q):
                    a = verts[v0 + s, k]
                    out_pt_row[k] = a + u * (verts[v0 + s + 1, k] - a)
        side_a = side_b
    return best, best_seg


@numba.njit(cache=True, inline="always")
def _one_query(i, max_chunks, points, tangents, polylines, b, same_direction, tol, out):
    """All polylines for query ``i`` (see :func:`nearest_crossings`)."""
    verts, vert_offset, n_seg, centres, radii, chunk_offset, n_chunks = polylines
    out_pt, out_seg, out_dist = out
    q = points.shape[1]
    n = n_seg.shape[0]
    p = points[i]
    t = tangents[i]
    lower = np.empty(max_chunks)
    for j in range(n):
        c0 = chunk_offset[j]
        first_c = -1
        first_lb = np.inf
        for c in range(n_chunks[j]):
            along = 0.0
            d2 = 0.0
            for k in range(q):
                diff = centres[c0 + c, k] - p[k]
                along += diff * t[k]
                d2 += diff * diff
            # Widen each ball by the on-plane tolerance so that a vertex counted
            # as lying on the plane is never in a pruned chunk.
            r = radii[c0 + c] + tol
            lb = np.sqrt(d2) - r if abs(along) <= r else np.inf
            lower[c] = lb
            if lb < first_lb:
                first_lb = lb
                first_c = c
        if first_c < 0:
            continue
        best, seg = _check_chunk(
            p,
            t,
            verts,
            vert_offset[j],
            n_seg[j],
            first_c,
            b,
            same_direction,
            tol,
            np.inf,
            out_pt[i, j],
        )
        for c in range(n_chunks[j]):
            if c != first_c and lower[c] < best:
                d, s = _check_chunk(
                    p,
                    t,
                    verts,
                    vert_offset[j],
                    n_seg[j],
                    c,
                    b,
                    same_direction,
                    tol,
                    best,
                    out_pt[i, j],
                )
                if s >= 0:
                    best, seg = d, s
        if seg >= 0:
            out_seg[i, j] = seg
            out_dist[i, j] = best


@numba.njit(cache=True)
def _max_chunks(n_chunks):
    out = 0
    for j in range(n_chunks.shape[0]):
        out = max(out, n_chunks[j])
    return out


@numba.njit(cache=True)
def _serial(points, tangents, polylines, b, same_direction, tol, out):
    max_chunks = _max_chunks(polylines[6])
    for i in range(points.shape[0]):
        _one_query(i, max_chunks, points, tangents, polylines, b, same_direction, tol, out)


@numba.njit(parallel=True, cache=True)
def _parallel(points, tangents, polylines, b, same_direction, tol, out):
    max_chunks = _max_chunks(polylines[6])
    for i in numba.prange(points.shape[0]):
        _one_query(i, max_chunks, points, tangents, polylines, b, same_direction, tol, out)


def nearest_crossings(points, tangents, polylines, b, same_direction, tol, out) -> None:
    """Nearest crossing of each query's normal hyperplane with each polyline.

    See :class:`lfdkit.geometry.PolylineSet` for the method. ``polylines`` is the
    tuple (verts, vert_offset, n_seg, centres, radii, chunk_offset, n_chunks);
    results are written in place into ``out`` = (points (m, n, q), segment
    (m, n), distance (m, n)). Small problems run serially: starting threads costs
    more than it saves there, and far more when the cores are busy.
    """
    kernel = _parallel if points.shape[0] * polylines[2].shape[0] >= 20_000 else _serial
    kernel(points, tangents, polylines, b, same_direction, tol, out)
