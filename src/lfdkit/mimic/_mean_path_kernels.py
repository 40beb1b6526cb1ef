"""Compiled inner loop of Mean-Path's adaptive centre (numba).

One reweighting step of :func:`lfdkit.mimic.mean_path._adaptive` over the
rows still moving, fused: distances, weights, their sum and the weighted
sum in one pass over each row, where NumPy takes a dozen passes over
(m, n) temporaries and gathered copies of the moving rows. The numbers are
NumPy's to the bit: each row's sum of weights is NumPy's pairwise sum
(eight accumulators, blocks halved above 128 values) and the weighted sum
``einsum("mn,mnq->mq")``'s sequential one (tested against both). 100
demonstrations x 1000 normals: 0.6 ms a step against 3.4 (loaded machine).
Also each row's shortest half and median distance from it after NumPy's
sort (:func:`shortest_halves`), the run replicas' stretch averages
(:func:`run_averages`), a line's direction and projections (:func:`on_line`),
distances from each row's start (:func:`found_distances`) and orientation's
all-pairs mean distances (:func:`pair_distances`): each NumPy's numbers, one
pass without (m, n, 2) temporaries. Imported lazily; compiled once, then
cached on disk.
"""

import numpy as np

from lfdkit.core.kernels import cached_njit


@cached_njit(nogil=True)
def _block_sum(a, first, count):
    """NumPy's pairwise sum of a block of at most 128 values: eight accumulators."""
    if count < 8:
        total = 0.0
        for i in range(count):
            total += a[first + i]
        return total
    r0, r1, r2, r3 = a[first], a[first + 1], a[first + 2], a[first + 3]
    r4, r5, r6, r7 = a[first + 4], a[first + 5], a[first + 6], a[first + 7]
    i = 8
    whole = count - count % 8
    while i < whole:
        r0 += a[first + i]
        r1 += a[first + i + 1]
        r2 += a[first + i + 2]
        r3 += a[first + i + 3]
        r4 += a[first + i + 4]
        r5 += a[first + i + 5]
        r6 += a[first + i + 6]
        r7 += a[first + i + 7]
        i += 8
    total = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < count:
        total += a[first + i]
        i += 1
    return total


@cached_njit(nogil=True)
def _pairwise_sum(a, first, count):
    """NumPy's pairwise sum of ``a[first:first + count]`` (contiguous), bit for bit.

    Above 128 values NumPy sums each half (the first a multiple of 8 long) and
    adds the two; the recursion is unrolled onto a stack here (numba's cache
    cannot load a recursive function).
    """
    if count <= 128:
        return _block_sum(a, first, count)
    starts = np.empty(64, dtype=np.int64)
    counts = np.empty(64, dtype=np.int64)
    waiting = np.zeros(64, dtype=np.int64)  # 0: for the left half's sum, 1: the right's
    left = np.empty(64)
    top = 0
    starts[0], counts[0] = first, count
    while True:
        c = counts[top]
        if c > 128:  # descend into the left half
            half = c // 2
            half -= half % 8
            top += 1
            starts[top], counts[top], waiting[top] = starts[top - 1], half, 0
            continue
        value = _block_sum(a, starts[top], c)
        top -= 1
        while top >= 0 and waiting[top] == 1:  # both halves done: their sum goes up
            value = left[top] + value
            top -= 1
        if top < 0:
            return value
        left[top] = value  # the left half done: the right one next
        waiting[top] = 1
        half = counts[top] // 2
        half -= half % 8
        top += 1
        starts[top], counts[top], waiting[top] = starts[top - 1] + half, counts[top - 1] - half, 0


@cached_njit(nogil=True, error_model="numpy")
def adaptive_step(pts, found, scale, prior, start, centre, rows, core, lo, hi, out):
    """One reweighting of the adaptive centre on ``rows``, written to ``out`` (len(rows), q).

    ``pts`` (m, n, q): the vectors, zero where not ``found`` (m, n); ``scale``
    (m,): robust scales (1 where degenerate); ``prior`` (m, n) fixed weights,
    or shape (0, 0) for none; ``start`` and ``centre`` (m, q): the start (taken
    where no weight is left) and the current centre; ``core, lo, hi``: the
    tuning (Huber's within ``core`` when ``core < lo``, the taper from ``lo``
    to none at ``hi``).
    """
    n = pts.shape[1]
    q = pts.shape[2]
    h = hi - lo
    huber = core < lo
    weighted_prior = prior.shape[0] > 0
    w = np.empty(n)
    acc = np.empty(q)
    for r in range(rows.shape[0]):
        i = rows[r]
        for k in range(q):
            acc[k] = 0.0
        for j in range(n):
            d2 = 0.0
            for k in range(q):
                d = pts[i, j, k] - centre[i, k]
                d2 += d * d
            z = np.sqrt(d2) / scale[i]
            weight = 1.0
            if not z <= lo:
                v = (z - lo) / h
                v = min(max(v, 0.0), 1.0)
                t = 1.0 - v * v
                weight = t * t
            if huber:
                weight = min(1.0, core / z) * weight
            if not found[i, j]:
                weight = 0.0
            if weighted_prior:
                weight = weight * prior[i, j]
            w[j] = weight
            for k in range(q):
                acc[k] += weight * pts[i, j, k]
        total = _pairwise_sum(w, 0, n)
        for k in range(q):
            out[r, k] = acc[k] / max(total, 1e-300) if total > 0.0 else start[i, k]


@cached_njit(nogil=True)
def shortest_halves(ordered, counts, mid, width, firsts, median):
    """Each row's shortest half and median distance from its midpoint, from sorted values.

    ``ordered`` (m, n): each row's ``counts[r]`` found values sorted first (the
    rest inf). The half holds ``h = max(2, ceil(k / 2))`` of ``k`` values (all
    of one or two); of equally short ones the middle is taken. Writes its
    midpoint ``mid``, ``width`` and first index ``firsts``, and ``median``,
    the median distance of the row's values from ``mid`` (the farther end of
    the half for odd ``k``, else the mean of that and the nearest value
    outside it; the mean of both distances for ``k = 2``; NaN for ``k = 0``).
    The arithmetic of :func:`lfdkit.mimic.mean_path._sorted_shortest_half`
    and :func:`~lfdkit.mimic.mean_path._line_run`, so the same numbers.
    """
    for r in range(ordered.shape[0]):
        k = counts[r]
        if k == 0:
            mid[r] = 0.0
            width[r] = 0.0
            firsts[r] = 0
            median[r] = np.nan
            continue
        h = min(k, max(2, -(-k // 2)))
        least = np.inf
        first = 0
        for t in range(k - h + 1):
            w = ordered[r, t + h - 1] - ordered[r, t]
            if w < least:
                least = w
                first = t
        n_tied = 0
        for t in range(k - h + 1):
            if ordered[r, t + h - 1] - ordered[r, t] <= least:
                n_tied += 1
        if n_tied > 1:  # of equally short intervals, the middle one
            middle = (n_tied + 1) // 2
            rank = 0
            for t in range(k - h + 1):
                if ordered[r, t + h - 1] - ordered[r, t] <= least:
                    rank += 1
                    if rank >= middle:
                        first = t
                        break
        lo = ordered[r, first]
        hi = ordered[r, first + h - 1]
        centre = 0.5 * (lo + hi)
        mid[r] = centre
        width[r] = hi - lo
        firsts[r] = first
        if k == 2:
            median[r] = 0.5 * (abs(ordered[r, 0] - centre) + abs(ordered[r, 1] - centre))
            continue
        inner = max(abs(lo - centre), abs(hi - centre))
        if k % 2 == 1:
            median[r] = inner
            continue
        outer = np.inf
        if first > 0:
            outer = abs(ordered[r, first - 1] - centre)
        if first + h < k:
            outer = min(outer, abs(ordered[r, first + h] - centre))
        median[r] = 0.5 * (inner + outer)


@cached_njit(nogil=True)
def _insert_sorted(buf, count, value):
    """Insert ``value`` into the sorted ``buf[:count]``; returns the new count."""
    i = count
    while i > 0 and buf[i - 1] > value:
        buf[i] = buf[i - 1]
        i -= 1
    buf[i] = value
    return count + 1


@cached_njit(nogil=True)
def running_median_ends(values, half, out):
    """The first and last ``half`` of a running median whose windows the ends cut short.

    ``out[r]`` for ``r < half`` is the median of ``values[:r + half + 1]``, and
    for ``r >= m - half`` that of ``values[r - half:]`` (``values`` without
    NaN, ``m > 2 half``): each window is the previous one and one value more,
    kept sorted by insertion, its median the mean of its middle two as
    :func:`lfdkit.mimic.mean_path._nanmedian` takes it (the same numbers).
    """
    m = values.shape[0]
    buf = np.empty(2 * half + 1)
    count = 0
    for v in range(half):
        count = _insert_sorted(buf, count, values[v])
    for r in range(half):
        count = _insert_sorted(buf, count, values[r + half])
        out[r] = (buf[(count - 1) // 2] + buf[count // 2]) / 2.0
    count = 0
    for v in range(m - half, m):
        count = _insert_sorted(buf, count, values[v])
    for r in range(m - 1, m - 1 - half, -1):
        count = _insert_sorted(buf, count, values[r - half])
        out[r] = (buf[(count - 1) // 2] + buf[count // 2]) / 2.0


__all__ = ["adaptive_step", "running_median_ends", "shortest_halves"]


@cached_njit(nogil=True)
def pair_distances(stack, fwd, bwd):
    """Mean distances between every pair of 2-D demonstrations, as recorded and one reversed.

    ``stack`` (m, s, 2): the demonstrations sampled at ``s <= 128`` points
    (NumPy's pairwise sum is then one block of eight accumulators). Writes,
    for ``a < b``, ``fwd[a, b]`` the mean over samples of the distance from
    ``stack[a]`` to ``stack[b]`` and ``bwd[a, b]`` to ``stack[b]`` reversed:
    :func:`lfdkit.mimic.orientation._mean_distances`'s numbers (``x² + y²``,
    its square root, NumPy's pairwise sum, divided by ``s``) without its
    (m - a, s, 2) temporaries.
    """
    m, s = stack.shape[0], stack.shape[1]
    d = np.empty(s)
    e = np.empty(s)
    for a in range(m - 1):
        for b in range(a + 1, m):
            for i in range(s):
                dx = stack[b, i, 0] - stack[a, i, 0]
                dy = stack[b, i, 1] - stack[a, i, 1]
                d[i] = np.sqrt(dx * dx + dy * dy)
                rx = stack[b, s - 1 - i, 0] - stack[a, i, 0]
                ry = stack[b, s - 1 - i, 1] - stack[a, i, 1]
                e[i] = np.sqrt(rx * rx + ry * ry)
            fwd[a, b] = _block_sum(d, 0, s) / s
            bwd[a, b] = _block_sum(e, 0, s) / s


@cached_njit(nogil=True)
def run_averages(values, found, half, taken, total, out):
    """Each value's average over the ``2 half + 1`` rows about it, cut at the ends.

    ``values`` (m, n), counted where ``found``; ``taken`` (m, n) how many
    found values each average takes (at least 1); ``total`` (m + 1, n) the
    running sums along the rows, zero first, computed here when ``half`` is
    negative (then ``-half - 1`` is the half-width) and reused otherwise.
    Writes ``out[r] = (total[min(r + half + 1, m)] - total[max(r - half, 0)])
    / taken[r]``: :func:`lfdkit.mimic.mean_path._window_sums` of NumPy's
    cumulative sum (sequential along each column), divided, the same numbers
    without the (m, n) temporaries.
    """
    m, n = values.shape
    if half < 0:
        half = -half - 1
        for j in range(n):
            total[0, j] = 0.0
            total[1, j] = values[0, j] if found[0, j] else 0.0
        for r in range(1, m):
            for j in range(n):
                total[r + 1, j] = total[r, j] + (values[r, j] if found[r, j] else 0.0)
    for r in range(m):
        hi = min(r + half + 1, m)
        lo = max(r - half, 0)
        for j in range(n):
            out[r, j] = (total[hi, j] - total[lo, j]) / taken[r, j]


@cached_njit(nogil=True)
def on_line(offsets, found, signed, unit):
    """2-D offsets' signed lengths along each row's common line, in one pass per row.

    ``offsets`` (m, n, 2), counted where ``found``; writes ``unit`` (m, 2),
    the direction of the found offsets' mean (the first found offset where
    that mean is ~zero; zero where there is none), and ``signed`` (m, n),
    each offset's projection on it. :func:`lfdkit.mimic.mean_path._on_line`'s
    numbers: the row sums in order, ``x² + y²`` under the square roots, and
    einsum's ``x u + y v``.
    """
    m, n = found.shape
    for r in range(m):
        # NumPy's sum over the row of the offsets, zero where not found: in order.
        sx = offsets[r, 0, 0] if found[r, 0] else 0.0
        sy = offsets[r, 0, 1] if found[r, 0] else 0.0
        count = 1 if found[r, 0] else 0
        first = 0 if found[r, 0] else -1
        for j in range(1, n):
            if found[r, j]:
                sx += offsets[r, j, 0]
                sy += offsets[r, j, 1]
                if first < 0:
                    first = j
                count += 1
            else:
                sx += 0.0
                sy += 0.0
        dx = sx / count if count else np.nan
        dy = sy / count if count else np.nan
        norm = np.sqrt(dx * dx + dy * dy)
        if not norm > 1e-15:
            if first >= 0:
                dx = offsets[r, first, 0]
                dy = offsets[r, first, 1]
            else:
                dx = 0.0
                dy = 0.0
            norm = np.sqrt(dx * dx + dy * dy)
        if norm > 0:
            ux = dx / norm
            uy = dy / norm
        else:
            ux = 0.0
            uy = 0.0
        unit[r, 0] = ux
        unit[r, 1] = uy
        for j in range(n):
            signed[r, j] = offsets[r, j, 0] * ux + offsets[r, j, 1] * uy


@cached_njit(nogil=True)
def found_distances(offsets, found, start, fill, dist):
    """Distances of 2-D offsets from each row's start, and their largest coordinate.

    ``offsets`` (m, n, 2), ``start`` (m, 2): writes ``dist[r, j]``, the
    distance of ``offsets[r, j]`` from ``start[r]`` where ``found`` (``fill``
    elsewhere), and returns the largest absolute coordinate of the found
    offsets, zero for the others (NaN if any is NaN): the numbers of
    :func:`lfdkit.mimic.mean_path._own_start_and_scale`'s NumPy (``x² + y²``
    under the root) without its (m, n, 2) temporaries.
    """
    m, n = found.shape
    largest = 0.0 if m * n else -np.inf
    nan = False
    for r in range(m):
        s0 = start[r, 0]
        s1 = start[r, 1]
        for j in range(n):
            if found[r, j]:
                x = offsets[r, j, 0]
                y = offsets[r, j, 1]
                dx = x - s0
                dy = y - s1
                dist[r, j] = np.sqrt(dx * dx + dy * dy)
                ax = abs(x)
                ay = abs(y)
                if np.isnan(ax) or np.isnan(ay):
                    nan = True
                largest = max(largest, ax, ay)
            else:
                dist[r, j] = fill
    return np.nan if nan else largest
