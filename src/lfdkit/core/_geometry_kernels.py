"""Compiled inner loop of :class:`lfdkit.core.geometry.PolylineSet` (numba).

The nearest crossing of every query point's normal hyperplane with every
polyline, pruned by bounding balls over chunks of segments and, inside a
chunk, over sub-chunks. Imported lazily by :mod:`lfdkit.core.geometry`.

One compiled function serves every size: it releases the GIL, so a large
problem is split over threads by plain Python threads rather than a second,
``parallel=True`` variant (whose compilation took four times as long as this
one's, on the first large call of every fresh install). Compiling takes about
two seconds once; the machine code is then cached on disk
(:func:`lfdkit.core.kernels.cached_njit`).
"""

import itertools
import os
import threading

import numpy as np

from lfdkit.core.kernels import cached_njit

#: Problems with fewer (query, polyline) pairs run in the calling thread:
#: starting threads costs more than it saves there, and far more when the
#: cores are busy.
_THREADED_PAIRS = 20_000


@cached_njit(nogil=True)
def _scan_chunk(
    i, j, c, points, tangents, verts, v0, c0, n_seg, sub_centres, sub_radii, n_sub, sub, b,
    same_direction, tol, out_pt, best, seg,
):  # fmt: skip
    """The nearest crossing in chunk ``c`` of polyline ``j`` nearer than ``best``: (best, seg).

    Writes the crossing point into ``out_pt[i, j]`` when one is found.
    """
    q = points.shape[1]
    first = c * b
    last = min(first + b, n_seg[j])  # exclusive segment bound
    for kk in range(n_sub):
        s0 = first + kk * sub
        if s0 >= last:
            break
        # A sub-chunk whose ball the hyperplane misses has all its vertices
        # beyond tol on one side: none of its segments crosses.
        g = (c0 + c) * n_sub + kk
        along = 0.0
        for k in range(q):
            along += (sub_centres[g, k] - points[i, k]) * tangents[i, k]
        if abs(along) > sub_radii[g] + tol:
            continue
        side_a = 0.0
        for k in range(q):
            side_a += (verts[v0 + s0, k] - points[i, k]) * tangents[i, k]
        if abs(side_a) <= tol:
            side_a = 0.0
        for s in range(s0, min(s0 + sub, last)):
            side_b = 0.0
            for k in range(q):
                side_b += (verts[v0 + s + 1, k] - points[i, k]) * tangents[i, k]
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
                    x = a + u * (verts[v0 + s + 1, k] - a) - points[i, k]
                    d2 += x * x
                d = np.sqrt(d2)
                if d < best:
                    best = d
                    seg = s
                    for k in range(q):
                        a = verts[v0 + s, k]
                        out_pt[i, j, k] = a + u * (verts[v0 + s + 1, k] - a)
            side_a = side_b
    return best, seg


@cached_njit(nogil=True)
def _queries(
    points,
    tangents,
    verts,
    vert_offset,
    n_seg,
    centres,
    radii,
    chunk_offset,
    n_chunks,
    sub_centres,
    sub_radii,
    n_sub,
    sub,
    group_centres,
    group_radii,
    group_offset,
    n_groups,
    group,
    b,
    same_direction,
    tol,
    out_pt,
    out_seg,
    out_dist,
    start,
    stop,
    lower,
    group_lower,
):
    """Queries ``start`` to ``stop`` against all polylines (see :func:`nearest_crossings`).

    ``lower`` and ``group_lower`` are scratch space of at least ``max(n_chunks)``
    and ``max(n_groups)`` values. The chunks come in groups of ``group``, each
    with a ball around its chunks' balls: where the hyperplane misses a group's
    ball it misses its chunks' too, which are not tested (their bound is
    infinite either way), and a group whose least chunk bound does not beat the
    best crossing so far is passed whole (each of its chunks would be). The
    chunks are searched in the same order as one by one, so the crossings are
    the same, bit for bit.
    """
    q = points.shape[1]
    for i in range(start, stop):
        for j in range(n_seg.shape[0]):
            c0 = chunk_offset[j]
            v0 = vert_offset[j]
            h0 = group_offset[j]
            n_c = n_chunks[j]
            first_c = -1
            first_lb = np.inf
            for h in range(n_groups[j]):
                along = 0.0
                for k in range(q):
                    along += (group_centres[h0 + h, k] - points[i, k]) * tangents[i, k]
                least = np.inf
                if abs(along) <= group_radii[h0 + h] + tol:
                    for c in range(h * group, min(h * group + group, n_c)):
                        along = 0.0
                        d2 = 0.0
                        for k in range(q):
                            diff = centres[c0 + c, k] - points[i, k]
                            along += diff * tangents[i, k]
                            d2 += diff * diff
                        # Widen each ball by the on-plane tolerance so that a vertex
                        # counted as lying on the plane is never in a pruned chunk.
                        r = radii[c0 + c] + tol
                        lb = np.sqrt(d2) - r if abs(along) <= r else np.inf
                        lower[c] = lb
                        least = min(least, lb)
                        if lb < first_lb:
                            first_lb = lb
                            first_c = c
                group_lower[h] = least
            if first_c < 0:
                continue
            # The nearest candidate chunk first, then the others, in order, whose bound
            # beats the best crossing found so far.
            best, seg = _scan_chunk(
                i, j, first_c, points, tangents, verts, v0, c0, n_seg, sub_centres,
                sub_radii, n_sub, sub, b, same_direction, tol, out_pt, np.inf, -1,
            )  # fmt: skip
            for h in range(n_groups[j]):
                if group_lower[h] >= best:
                    continue
                for c in range(h * group, min(h * group + group, n_c)):
                    if c == first_c or lower[c] >= best:
                        continue
                    best, seg = _scan_chunk(
                        i, j, c, points, tangents, verts, v0, c0, n_seg, sub_centres,
                        sub_radii, n_sub, sub, b, same_direction, tol, out_pt, best, seg,
                    )  # fmt: skip
            if seg >= 0:
                out_seg[i, j] = seg
                out_dist[i, j] = best


@cached_njit(nogil=True)
def chunk_balls(verts, vert_offset, n_seg, chunk_offset, n_chunks, b, sub, n_sub, out):
    """Bounding balls of the chunks and their sub-chunks of 2-D polylines, unwidened.

    Chunk ``c`` of polyline ``j`` spans its vertices ``c b`` to ``(c + 1) b``
    (cut at its last), sub-chunk ``k`` of a chunk its vertices ``k sub`` to
    ``(k + 1) sub`` (cut at the chunk's last). A ball's centre is the middle of
    its vertices' box, its radius the largest distance from it (``√(x² + y²)``,
    einsum's sum of two squares). ``out``: the (centres (C, 2), radii (C,),
    sub_centres (C * n_sub, 2), sub_radii (C * n_sub,)) to fill; the numbers of
    :class:`lfdkit.core.geometry.PolylineSet`'s vectorised version, which
    gathered every chunk's vertices into (C, b + 1, 2) copies.
    """
    centres, radii, sub_centres, sub_radii = out
    for j in range(n_seg.shape[0]):
        v0 = vert_offset[j]
        last_vertex = n_seg[j]
        for c in range(n_chunks[j]):
            cc = chunk_offset[j] + c
            start = c * b
            mx, my, far = _vertex_ball(
                verts, v0 + min(start, last_vertex), v0 + min(start + b, last_vertex)
            )
            centres[cc, 0] = mx
            centres[cc, 1] = my
            radii[cc] = far
            for kk in range(n_sub):
                g = cc * n_sub + kk
                first = start + min(kk * sub, b)
                stop = start + min(min(kk * sub, b) + sub, b)
                mx, my, far = _vertex_ball(
                    verts, v0 + min(first, last_vertex), v0 + min(stop, last_vertex)
                )
                sub_centres[g, 0] = mx
                sub_centres[g, 1] = my
                sub_radii[g] = far


@cached_njit(nogil=True)
def _vertex_ball(verts, first, last):
    """The bounding ball of ``verts[first:last + 1]``: its box's middle and largest distance."""
    lo_x = lo_y = np.inf
    hi_x = hi_y = -np.inf
    for v in range(first, last + 1):
        lo_x = min(lo_x, verts[v, 0])
        hi_x = max(hi_x, verts[v, 0])
        lo_y = min(lo_y, verts[v, 1])
        hi_y = max(hi_y, verts[v, 1])
    mx = 0.5 * (lo_x + hi_x)
    my = 0.5 * (lo_y + hi_y)
    far = 0.0
    for v in range(first, last + 1):
        dx = verts[v, 0] - mx
        dy = verts[v, 1] - my
        far = max(far, np.sqrt(dx * dx + dy * dy))
    return mx, my, far


def _n_threads() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def nearest_crossings(points, tangents, polylines, b, same_direction, tol, out) -> None:
    """Nearest crossing of each query's normal hyperplane with each polyline.

    See :class:`lfdkit.core.geometry.PolylineSet` for the method. ``polylines`` is the
    tuple (verts, vert_offset, n_seg, centres, radii, chunk_offset, n_chunks,
    sub_centres, sub_radii, n_sub, sub, group_centres, group_radii, group_offset,
    n_groups, group);
    results are written in place into ``out`` = (points (m, n, q), segment
    (m, n), distance (m, n)). Large problems are split over the available
    cores, each thread taking a block of queries.
    """
    m = points.shape[0]
    most = max(1, int(polylines[6].max(initial=0)))
    most_groups = max(1, int(polylines[14].max(initial=0)))
    threads = min(_n_threads(), m) if m * polylines[2].shape[0] >= _THREADED_PAIRS else 1

    def run(start: int, stop: int) -> None:
        _queries(
            points,
            tangents,
            *polylines,
            b,
            same_direction,
            tol,
            *out,
            start,
            stop,
            np.empty(most),
            np.empty(most_groups),
        )

    if threads <= 1:
        run(0, m)
        return
    bounds = np.linspace(0, m, threads + 1).astype(int)
    errors: list[BaseException] = []

    def work(start: int, stop: int) -> None:
        try:
            run(start, stop)
        except BaseException as exc:  # re-raised in the calling thread
            errors.append(exc)

    workers = [
        threading.Thread(target=work, args=(int(lo), int(hi)), daemon=True)
        for lo, hi in itertools.pairwise(bounds[1:])
    ]
    for worker in workers:
        worker.start()
    run(int(bounds[0]), int(bounds[1]))
    for worker in workers:
        worker.join()
    if errors:
        raise errors[0]


__all__ = ["chunk_balls", "nearest_crossings"]
