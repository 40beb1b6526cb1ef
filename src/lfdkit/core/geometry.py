"""Polylines in any dimension q >= 2: arc length, resampling, tangents, normal frames,
and intersections of normal hyperplanes with other polylines.

Conventions
-----------
* A path is an array of shape ``(n_points, q)``; consecutive points are joined by
  straight segments (the thesis's piecewise-linear approximation, eq. 4.4).
* The tangent at a vertex is the normalised sum of the unit directions of its two
  adjacent segments (the bisector), or of its only segment at an end. The thesis
  uses the forward segment only; the bisector is symmetric, so reversing a path
  gives the same normals, and it is second-order accurate on smooth curves.
* The normal hyperplane at point ``p`` with unit tangent ``t`` is
  ``{x : (x - p) . t = 0}`` (a line in 2-D, a plane in 3-D).
* A normal frame is a ``(q, q)`` rotation whose first row is the tangent and whose
  other rows span the normal hyperplane. In 2-D the second row is the *left*
  normal ``(-t_y, t_x)``; in higher dimensions the normal rows are parallel
  transported along the path so that distance-space coordinates vary smoothly.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lfdkit.core.validation import check_count, check_path, check_positive

__all__ = [
    "FoldedPathError",
    "NormalHits",
    "PolylineSet",
    "arc_length",
    "convex_hull_2d",
    "intersect_normals",
    "left_normals",
    "normal_frames",
    "path_length",
    "point_tangents",
    "polyline_distances",
    "project_onto_polyline",
    "remove_repeated_points",
    "resample",
    "resample_between",
    "segment_lengths",
    "segment_polyline_distance",
    "segment_tangents",
    "smooth_path",
]

_EPS = 1e-12


class FoldedPathError(ValueError):
    """A path turns back onto itself, so its tangent (and normal) is undefined there."""


def segment_lengths(path: np.ndarray) -> np.ndarray:
    """Length of each segment, shape ``(n_points - 1,)``, in the path's units."""
    return np.linalg.norm(np.diff(path, axis=0), axis=1)


def arc_length(path: np.ndarray) -> np.ndarray:
    """Cumulative arc length at each point, shape ``(n_points,)``, starting at 0."""
    return np.concatenate(([0.0], np.cumsum(segment_lengths(path))))


def path_length(path: np.ndarray) -> float:
    """Total length of the polyline, in the path's units."""
    return float(segment_lengths(path).sum())


def remove_repeated_points(path: np.ndarray, atol: float = 0.0) -> np.ndarray:
    """Drop points closer than ``atol`` to the previous kept point's predecessor segment.

    Consecutive duplicates make zero-length segments, which have no direction.
    The first point is always kept.

    Parameters
    ----------
    path : ndarray, shape (n_points, q)
    atol : float
        Segments of length ``<= atol`` are merged into their predecessor.

    Returns
    -------
    ndarray, shape (n_kept, q)
    """
    keep = np.concatenate(([True], segment_lengths(path) > atol))
    return path[keep]


def segment_tangents(path: np.ndarray) -> np.ndarray:
    """Unit direction of each segment, shape ``(n_points - 1, q)``.

    Zero-length segments get a zero vector.
    """
    d = np.diff(path, axis=0)
    n = np.linalg.norm(d, axis=1, keepdims=True)
    return np.divide(d, n, out=np.zeros_like(d), where=n > _EPS)


def point_tangents(path: np.ndarray) -> np.ndarray:
    """Unit tangent at each vertex, shape ``(n_points, q)`` (bisector of adjacent segments).

    Raises
    ------
    ValueError
        If the path has zero length, or a vertex has no defined direction
        (a hairpin that reverses exactly onto itself).
    """
    seg = segment_tangents(path)
    if not np.any(seg):
        raise ValueError("path: has zero length (all points coincide)")
    # Zero-length segments inherit the nearest defined direction so that
    # repeated samples do not leave vertices without a tangent.
    valid = np.linalg.norm(seg, axis=1) > 0
    if not valid.all():
        idx = np.where(valid, np.arange(len(seg)), -1)
        idx = np.maximum.accumulate(idx)
        first = int(np.argmax(valid))
        idx[idx < 0] = first
        seg = seg[idx]
    tan = np.empty_like(path)
    tan[0] = seg[0]
    tan[-1] = seg[-1]
    tan[1:-1] = seg[:-1] + seg[1:]
    norm = np.linalg.norm(tan, axis=1, keepdims=True)
    if np.any(norm < 1e-9):
        bad = int(np.argmin(norm[:, 0]))
        raise FoldedPathError(
            f"path: turns back onto itself at point {bad}; the tangent is undefined"
        )
    return tan / norm


def left_normals(path: np.ndarray) -> np.ndarray:
    """Unit left normal ``(-t_y, t_x)`` at each vertex of a 2-D path, shape ``(n_points, 2)``."""
    if path.shape[1] != 2:
        raise ValueError(f"path: left normals are defined in 2-D only, got {path.shape[1]} dims")
    t = point_tangents(path)
    return np.column_stack((-t[:, 1], t[:, 0]))


def normal_frames(tangents: np.ndarray) -> np.ndarray:
    """Orthonormal frames whose first row is the tangent, shape ``(n_points, q, q)``.

    Parameters
    ----------
    tangents : ndarray, shape (n_points, q)
        Unit tangents along a path.

    Returns
    -------
    ndarray, shape (n_points, q, q)
        ``R[i] @ v`` expresses a vector ``v`` in the local frame of point ``i``:
        component 0 along the tangent, components ``1..q-1`` in the normal
        hyperplane. In 2-D, component 1 is along the left normal. In q > 2
        dimensions the normals are parallel transported from the first point.
    """
    n, q = tangents.shape
    frames = np.empty((n, q, q))
    frames[:, 0] = tangents
    if q == 2:
        frames[:, 1, 0] = -tangents[:, 1]
        frames[:, 1, 1] = tangents[:, 0]
        return frames
    # Start from any basis completing the first tangent, then transport: project
    # the previous normals onto the new normal hyperplane and re-orthonormalise.
    basis = np.linalg.qr(np.column_stack((tangents[0], np.eye(q))))[0]
    basis[:, 0] = tangents[0]
    if np.linalg.det(basis) < 0:
        basis[:, -1] *= -1.0  # right-handed: a rotation, not a reflection
    normals = basis[:, 1:].T
    for i in range(n):
        t = tangents[i]
        frame = _gram_schmidt(t, normals)
        if frame is None:  # a degenerate transport (sharp turn): QR decides
            projected = normals - np.outer(normals @ t, t)
            qmat, rmat = np.linalg.qr(np.vstack((t, projected)).T)
            frame = (qmat * np.sign(np.diag(rmat) + (np.diag(rmat) == 0))).T
        frames[i] = frame
        if np.linalg.det(frames[i]) < 0:
            frames[i, -1] *= -1.0  # a sharp turn can degenerate the transport; stay a rotation
        normals = frames[i, 1:]
    return frames


def _gram_schmidt(tangent: np.ndarray, normals: np.ndarray) -> np.ndarray | None:
    """``tangent`` then ``normals`` orthonormalised in order (QR with a positive diagonal).

    Plain Gram–Schmidt on a few short vectors, many times cheaper than a QR
    call per point; None when a vector is (nearly) dependent on the earlier ones.
    A vector that lost more than half its length to the projections is
    projected once more ("twice is enough", Kahan's test): one pass leaves it
    off orthogonal by about the rounding over what is left, 3e-12 where a
    sharp turn left a normal 1e-4 of its length (a jagged 3-D path, seed
    1480 of the frames' property test). Where nothing turns sharply no
    vector is so shortened, and the frames are the one pass's, to the bit.
    """
    rows = [tangent]
    for v in normals:
        before = float(np.sqrt(v @ v))
        for u in rows:
            v = v - (v @ u) * u
        norm = float(np.sqrt(v @ v))
        if norm < 0.5 * before:
            for u in rows:
                v = v - (v @ u) * u
            norm = float(np.sqrt(v @ v))
        if norm < 1e-8:
            return None
        rows.append(v / norm)
    return np.array(rows)


def resample(path: np.ndarray, n_points: int) -> np.ndarray:
    """Resample a polyline to ``n_points`` points equally spaced in arc length.

    Parameters
    ----------
    path : array_like, shape (n, q)
    n_points : int
        Number of output points, at least 2.

    Returns
    -------
    ndarray, shape (n_points, q)
        First and last points equal those of ``path``.

    Raises
    ------
    ValueError
        If the path has zero length or ``n_points < 2``.
    """
    path = check_path(path, "path")
    n_points = check_positive(n_points, "n_points", integer=True)
    if n_points < 2:
        raise ValueError(f"n_points: needs at least 2, got {n_points}")
    check_count(n_points, "n_points", minimum=2)  # at most MAX_POINTS
    s = arc_length(path)
    if s[-1] <= 0:
        raise ValueError("path: has zero length (all points coincide); cannot resample")
    return _interp_path(path, s, np.linspace(0.0, s[-1], n_points))


def smooth_path(path: np.ndarray, width: float, n_points: int | None = None) -> np.ndarray:
    """Round a polyline's corners: Gaussian smoothing in arc length, ends kept.

    The path is resampled evenly (about 20 points per ``width``, at least as
    many as it has), extended past each end by its point reflection through
    the end (so the ends stay where they are and straight stretches stay
    straight), convolved with a Gaussian of standard deviation ``width``
    and resampled to ``n_points``. A corner is cut by about ``0.8 · width ·
    sin(turn/2)``; for a planned path around obstacles, keep ``width`` well
    below the clearance.

    Parameters
    ----------
    path : array_like, shape (n, q)
    width : float
        Standard deviation of the smoothing kernel, in units of the path.
    n_points : int, optional
        Points of the result (default ``n``).

    Returns
    -------
    ndarray, shape (n_points, q)
        Evenly spaced in arc length; first and last points equal the path's.

    Raises
    ------
    ValueError
        For a path with zero length or fewer than 2 points, NaN/inf, or a
        width that is not positive.
    """
    from scipy.ndimage import gaussian_filter1d

    path = check_path(path, "path", min_points=2)
    width = check_positive(width, "width")
    n_out = (
        path.shape[0] if n_points is None else check_positive(n_points, "n_points", integer=True)
    )
    if n_out < 2:
        raise ValueError(f"n_points: needs at least 2, got {n_out}")
    check_count(n_out, "n_points", minimum=2)  # at most MAX_POINTS
    length = path_length(path)
    if length <= 0:
        raise ValueError("path: has zero length (all points coincide); cannot smooth")
    n_fine = int(min(max(path.shape[0], 20.0 * length / width, 2), 200_000))
    fine = resample(path, n_fine)
    pad = min(n_fine - 1, int(np.ceil(4.0 * width / (length / (n_fine - 1)))))
    head = 2.0 * fine[0] - fine[pad:0:-1]
    tail = 2.0 * fine[-1] - fine[-2 : -pad - 2 : -1]
    sigma = width / (length / (n_fine - 1))
    padded = np.vstack([head, fine, tail])
    smooth = gaussian_filter1d(padded, sigma, axis=0, mode="nearest")[pad : pad + n_fine]
    smooth[0], smooth[-1] = fine[0], fine[-1]
    return resample(smooth, n_out)


def resample_between(path: np.ndarray, s_start: float, s_end: float, n_points: int) -> np.ndarray:
    """Resample the stretch of a polyline between two arc-length positions.

    Positions outside ``[0, length]`` extend the path straight along its end
    tangents, so a path can be lengthened as well as shortened.

    Parameters
    ----------
    path : ndarray, shape (n, q)
    s_start, s_end : float
        Arc-length positions of the first and last output point, ``s_start < s_end``.
    n_points : int

    Returns
    -------
    ndarray, shape (n_points, q)
    """
    s = arc_length(path)
    n_points = check_count(n_points, "n_points", minimum=2)
    return _interp_path(path, s, np.linspace(s_start, s_end, n_points))


def _interp_path(path: np.ndarray, s: np.ndarray, query: np.ndarray) -> np.ndarray:
    """Evaluate the arc-length parametrised polyline at ``query`` (extrapolating linearly)."""
    keep = np.concatenate(([True], np.diff(s) > 0))
    s, path = s[keep], path[keep]
    seg = np.clip(np.searchsorted(s, query, side="right") - 1, 0, len(s) - 2)
    u = (query - s[seg]) / (s[seg + 1] - s[seg])
    return path[seg] + u[:, None] * (path[seg + 1] - path[seg])


def project_onto_polyline(
    points: np.ndarray, polyline: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closest point on a polyline to each query point.

    Parameters
    ----------
    points : ndarray, shape (m, q)
    polyline : ndarray, shape (n, q)

    Returns
    -------
    s : ndarray, shape (m,)
        Arc-length position of the closest point along ``polyline``.
    closest : ndarray, shape (m, q)
    distance : ndarray, shape (m,)
    """
    a = polyline[:-1]
    d = np.diff(polyline, axis=0)
    len2 = np.einsum("ij,ij->i", d, d)
    # Everything as (m, n_segments) matrix products: |p - a - u d|^2 expanded.
    p_dot_d = points @ d.T - np.einsum("ij,ij->i", a, d)  # (p - a) . d
    u = np.clip(np.divide(p_dot_d, len2, out=np.zeros_like(p_dot_d), where=len2 > 0), 0.0, 1.0)
    rel2 = (
        np.einsum("mq,mq->m", points, points)[:, None]
        - 2.0 * (points @ a.T)
        + np.einsum("ij,ij->i", a, a)
    )
    dist2 = rel2 - 2.0 * u * p_dot_d + u * u * len2
    # The expansion cancels: its error is about eps times the squared coordinates, so a
    # point on the polyline can pick a segment 1e-8 of the scale away (sqrt of the
    # error). Segments within that error of the best are compared by exact distances.
    bound = np.einsum("mq,mq->m", points, points) + np.max(np.einsum("ij,ij->i", a, a) + len2)
    near = dist2 <= dist2.min(axis=1, keepdims=True) + (64.0 * np.finfo(float).eps) * bound[:, None]
    rows, segments = np.nonzero(near)
    offsets = points[rows] - a[segments] - u[rows, segments, None] * d[segments]
    exact = np.einsum("ij,ij->i", offsets, offsets)
    order = np.lexsort((exact, rows))  # by row, nearest first (ties: the first segment)
    first = order[np.flatnonzero(np.r_[True, np.diff(rows[order]) > 0])]
    k = segments[first]
    uk = u[np.arange(len(points)), k]
    closest = a[k] + uk[:, None] * d[k]
    s = arc_length(polyline)[k] + uk * np.sqrt(len2[k])
    return s, closest, np.linalg.norm(points - closest, axis=1)


def polyline_distances(points: np.ndarray, polyline: np.ndarray) -> np.ndarray:
    """Distance from each point to a polyline (its segments; a single point is accepted).

    Parameters
    ----------
    points : ndarray, shape (m, q)
    polyline : ndarray, shape (n, q), n ≥ 1

    Returns
    -------
    ndarray, shape (m,)
    """
    if polyline.shape[0] == 1:
        return np.linalg.norm(points - polyline[0], axis=1)
    return project_onto_polyline(points, polyline)[2]


def segment_polyline_distance(start: np.ndarray, end: np.ndarray, polyline: np.ndarray) -> float:
    """Smallest distance between the segment ``start``–``end`` and a polyline.

    The squared distance between two segments is convex in their two
    parameters, so its minimum over the unit square is either the lines'
    closest pair (when both parameters fall inside) or on the square's border,
    where one of the segments is reduced to an end point.

    Parameters
    ----------
    start, end : ndarray, shape (q,)
        The segment (they may coincide: a point).
    polyline : ndarray, shape (n, q), n ≥ 1

    Returns
    -------
    float
    """
    ends = np.stack([start, end])
    best = float(polyline_distances(ends, polyline).min())
    if np.any(end != start):
        best = min(best, float(project_onto_polyline(polyline, ends)[2].min()))
    if polyline.shape[0] == 1:
        return best
    u = end - start
    v = np.diff(polyline, axis=0)
    w = start[None] - polyline[:-1]
    a, b, c = float(u @ u), v @ u, np.einsum("ij,ij->i", v, v)
    d, e = w @ u, np.einsum("ij,ij->i", v, w)
    det = a * c - b * b
    regular = det > 1e-12 * a * c  # parallel segments: the border holds the minimum
    s = np.divide(b * e - c * d, det, out=np.zeros_like(det), where=regular)
    t = np.divide(a * e - b * d, det, out=np.zeros_like(det), where=regular)
    inside = regular & (s > 0.0) & (s < 1.0) & (t > 0.0) & (t < 1.0)
    if inside.any():
        gap = w[inside] + s[inside, None] * u - t[inside, None] * v[inside]
        best = min(best, float(np.linalg.norm(gap, axis=1).min()))
    return best


@dataclass(frozen=True)
class NormalHits:
    """Where the normal hyperplanes of some points meet one or more polylines.

    Arrays have a leading query axis ``m`` and, for a :class:`PolylineSet`, a
    second axis over its ``n_polylines`` polylines.

    Attributes
    ----------
    points : ndarray, shape (m, [n_polylines,] q)
        Intersection point for each query, NaN where the hyperplane misses.
    segment : ndarray of int, shape (m, [n_polylines])
        Index of the polyline segment hit, -1 where missed.
    distance : ndarray, shape (m, [n_polylines])
        Euclidean distance from the query point to its intersection, ``inf`` where missed.
    """

    points: np.ndarray
    segment: np.ndarray
    distance: np.ndarray

    @property
    def found(self) -> np.ndarray:
        """Boolean mask of the queries whose hyperplane meets the polyline."""
        return self.segment >= 0


class PolylineSet:
    """Several fixed polylines, intersected with many normal hyperplanes at once.

    Each polyline is cut into chunks of ``chunk_size`` consecutive segments with a
    bounding ball (centre ``c``, radius ``r``). A chunk can hold a crossing of the
    hyperplane through ``p`` with unit normal ``t`` only if ``|(c - p) . t| <= r``,
    and any such crossing is at least ``|c - p| - r`` away. For each (query,
    polyline) pair the segments of the nearest candidate chunk are checked first,
    then only the chunks whose lower bound beats the best crossing found, which
    for slender paths is almost never. Inside a chunk, sub-chunks of about
    ``sqrt(chunk_size)`` segments have balls of their own, and the segments of one
    the hyperplane misses are not tested (none of them can cross it: the same
    crossings, bit for bit, from about a third of the segment tests; 100 polylines
    of 1000 points against 1000 normals, 38 ms against 56). The result is the exact
    nearest crossing at a cost of about ``n_segments / chunk_size + chunk_size``
    per pair instead of ``n_segments``. The loop is compiled with numba and runs in
    parallel over the queries.

    Parameters
    ----------
    polylines : sequence of ndarray, each shape (n_j, q)
        Already validated polylines (at least 2 points each, same ``q``).
    chunk_size : int, optional
        Segments per chunk; about the square root of the longest polyline's
        number of segments when omitted.
    """

    def __init__(self, polylines: list[np.ndarray], chunk_size: int | None = None) -> None:
        self.polylines = list(polylines)
        n_seg = np.array([len(p) - 1 for p in self.polylines], dtype=np.int64)
        if chunk_size is None:
            chunk_size = int(np.clip(np.sqrt(n_seg.max()), 4, 64))
        b = chunk_size
        n_chunks = -(-n_seg // b)
        self._verts = np.ascontiguousarray(np.concatenate(self.polylines))
        self._vert_offset = np.concatenate(([0], np.cumsum(n_seg + 1)[:-1])).astype(np.int64)
        self._chunk_offset = np.concatenate(([0], np.cumsum(n_chunks)[:-1])).astype(np.int64)
        self._n_seg = n_seg
        self._n_chunks = n_chunks.astype(np.int64)
        self._b = b
        self._scale = float(np.abs(self._verts).max()) + 1.0
        # Chunk c of polyline j spans its vertices c*b .. min((c+1)*b, n_seg) inclusive.
        # Each chunk's segments in sub-chunks of about sqrt(chunk_size), each with its
        # ball: a sub-chunk whose ball the hyperplane misses holds no crossing, and its
        # segments are not tested (the same crossings, a third of the tests).
        # Sub-chunk k of a chunk spans its vertices k*sub .. (k+1)*sub inclusive.
        sub = max(2, int(np.ceil(np.sqrt(b))))
        n_sub = -(-b // sub)
        q = self._verts.shape[1]
        if q == 2:
            # Compiled, the same numbers (100 polylines of 1050 points: 2 ms against 20).
            from lfdkit.core._geometry_kernels import chunk_balls  # compiled on first use

            n_total = int(n_chunks.sum())
            centres, radii = np.empty((n_total, 2)), np.empty(n_total)
            sub_centres, sub_radii = np.empty((n_total * n_sub, 2)), np.empty(n_total * n_sub)
            chunk_balls(
                self._verts,
                self._vert_offset,
                n_seg,
                self._chunk_offset,
                self._n_chunks,
                b,
                sub,
                n_sub,
                (centres, radii, sub_centres, sub_radii),
            )
        else:
            owner = np.repeat(np.arange(len(n_seg)), n_chunks)
            local = np.arange(len(owner)) - self._chunk_offset[owner]
            vert_idx = np.minimum(local[:, None] * b + np.arange(b + 1), n_seg[owner, None])
            verts = self._verts[vert_idx + self._vert_offset[owner, None]]
            centres = 0.5 * (verts.min(axis=1) + verts.max(axis=1))
            apart = verts - centres[:, None]
            radii = np.sqrt(np.einsum("cvq,cvq->cv", apart, apart)).max(axis=1)
            first = np.minimum(np.arange(n_sub) * sub, b)  # (n_sub,) in the chunk
            sub_idx = np.minimum(first[:, None] + np.arange(sub + 1), b)  # (n_sub, sub + 1)
            sub_verts = verts[:, sub_idx]  # (chunks, n_sub, sub + 1, q)
            sub_centres = 0.5 * (sub_verts.min(axis=2) + sub_verts.max(axis=2))
            apart = sub_verts - sub_centres[:, :, None]
            sub_radii = np.sqrt(np.einsum("cksq,cksq->cks", apart, apart)).max(axis=2)
            sub_centres, sub_radii = sub_centres.reshape(-1, q), sub_radii.reshape(-1)
        self._centres = np.ascontiguousarray(centres)
        # Inflate the balls by more than any rounding in the tests below.
        self._radii = radii + 1e-9 * self._scale
        self._sub_centres = np.ascontiguousarray(sub_centres)
        self._sub_radii = np.ascontiguousarray(sub_radii + 1e-9 * self._scale)
        # The chunks in groups of about sqrt(chunks), each with a ball around theirs: a
        # group whose ball the hyperplane misses holds no candidate chunk (the same
        # crossings, about half the chunk tests; 100 x 1000 against 1000 normals, 26 ms
        # against 45 on a loaded machine).
        group = max(2, int(np.ceil(np.sqrt(self._n_chunks.max()))))
        n_groups = -(-self._n_chunks // group)
        group_offset = np.concatenate(([0], np.cumsum(n_groups)[:-1])).astype(np.int64)
        owner = np.repeat(np.arange(len(n_seg)), n_groups)
        first = self._chunk_offset[owner] + (np.arange(len(owner)) - group_offset[owner]) * group
        last = (self._chunk_offset + self._n_chunks - 1)[owner]
        members = np.minimum(first[:, None] + np.arange(group), last[:, None])
        member_centres = self._centres[members]  # (groups, group, q)
        group_centres = 0.5 * (member_centres.min(axis=1) + member_centres.max(axis=1))
        apart = member_centres - group_centres[:, None]
        reach = np.sqrt(np.einsum("gkq,gkq->gk", apart, apart)) + self._radii[members]
        self._group_centres = np.ascontiguousarray(group_centres)
        self._group_radii = reach.max(axis=1) + 1e-9 * self._scale
        self._kernel_data = (
            self._verts,
            self._vert_offset,
            self._n_seg,
            self._centres,
            self._radii,
            self._chunk_offset,
            self._n_chunks,
            self._sub_centres,
            self._sub_radii,
            n_sub,
            sub,
            self._group_centres,
            self._group_radii,
            group_offset,
            n_groups.astype(np.int64),
            group,
        )

    def intersect(
        self, points: np.ndarray, tangents: np.ndarray, *, same_direction: bool = False
    ) -> NormalHits:
        """Nearest crossing of each point's normal hyperplane with each polyline.

        Parameters
        ----------
        points : ndarray, shape (m, q)
        tangents : ndarray, shape (m, q)
            Unit normals of the hyperplanes (the tangents of the reference path).
        same_direction : bool
            Accept only segments traversed along the tangent (crossing the
            hyperplane from behind to ahead): the thesis's "associated segments"
            (Definition 1). Keeps the backward leg of a loop or hairpin, or a
            demonstration recorded in reverse, from being taken as the match.

        Returns
        -------
        NormalHits
            Arrays of shape ``(m, n_polylines[, q])``. A polyline vertex within
            ``1e-12`` (relative to the coordinates' magnitude) of a hyperplane
            counts as lying on it.
        """
        m, q = points.shape
        n = len(self.polylines)
        out_pt = np.full((m, n, q), np.nan)
        out_seg = np.full((m, n), -1, dtype=np.int64)
        out_dist = np.full((m, n), np.inf)
        scale = max(self._scale, float(np.abs(points).max()) + 1.0)
        from lfdkit.core._geometry_kernels import nearest_crossings  # numba compiles on first use

        nearest_crossings(
            np.ascontiguousarray(points, dtype=np.float64),
            np.ascontiguousarray(tangents, dtype=np.float64),
            self._kernel_data,
            self._b,
            bool(same_direction),
            1e-12 * scale,
            (out_pt, out_seg, out_dist),
        )
        return NormalHits(points=out_pt, segment=out_seg, distance=out_dist)


def intersect_normals(
    points: np.ndarray,
    tangents: np.ndarray,
    polyline: np.ndarray,
    *,
    same_direction: bool = False,
) -> NormalHits:
    """Nearest crossing of each point's normal hyperplane with a polyline.

    One-off convenience around :class:`PolylineSet`; build the set once when
    intersecting the same polylines repeatedly.

    Parameters
    ----------
    points : array_like, shape (m, q)
        Points through which the hyperplanes pass.
    tangents : array_like, shape (m, q)
        Hyperplane normals (need not be unit length; they are normalised).
    polyline : array_like, shape (n, q)
    same_direction : bool
        See :meth:`PolylineSet.intersect`.

    Returns
    -------
    NormalHits
        Misses are reported as NaN points, segment -1 and infinite distance.
    """
    points = check_path(points, "points", min_points=1)
    q = points.shape[1]
    tangents = check_path(tangents, "tangents", min_points=1, n_dims=q)
    polyline = check_path(polyline, "polyline", n_dims=q)
    if len(tangents) != len(points):
        raise ValueError(
            f"tangents: expected {len(points)} rows (one per point), got {len(tangents)}"
        )
    norm = np.linalg.norm(tangents, axis=1, keepdims=True)
    if np.any(norm == 0):
        raise ValueError(f"tangents: row {int(np.argmin(norm[:, 0]))} is the zero vector")
    hits = PolylineSet([polyline]).intersect(points, tangents / norm, same_direction=same_direction)
    return NormalHits(hits.points[:, 0], hits.segment[:, 0], hits.distance[:, 0])


def convex_hull_2d(points: np.ndarray) -> np.ndarray:
    """Vertices of the convex hull of 2-D points (n, 2), anticlockwise (Andrew's monotone chain)."""
    unique = np.unique(points, axis=0)
    if len(unique) < 3:
        return unique

    def half_hull(ordered: np.ndarray) -> list[np.ndarray]:
        chain: list[np.ndarray] = []
        for p in ordered:
            while len(chain) >= 2:
                a, b = chain[-2], chain[-1]
                if (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]) > 0:
                    break
                chain.pop()
            chain.append(p)
        return chain

    lower = half_hull(unique)
    upper = half_hull(unique[::-1])
    return np.array(lower[:-1] + upper[:-1])
