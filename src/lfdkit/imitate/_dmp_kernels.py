"""Compiled evaluation of the DMP's piecewise quintics (numba), for :mod:`lfdkit.imitate.dmp`.

Imported lazily: compiling costs a few seconds once, after which the machine
code is cached on disk next to this file.
"""

import numba


@numba.njit(cache=True)
def evaluate_quintic_pieces(s, spacing, pieces, out):
    """Value, slope and curvature of a uniform piecewise quintic at ``s``.

    ``pieces`` (n_pieces, 6, q) holds the monomial coefficients of each piece in
    its local ``t = s / spacing − i``; ``out`` (q, 3, len(s)) receives the value
    and the first two derivatives in ``s``. See ``lfdkit.imitate.dmp``.
    """
    last = pieces.shape[0] - 1
    q = pieces.shape[2]
    inv, inv2 = 1.0 / spacing, 1.0 / (spacing * spacing)
    for j in range(s.shape[0]):
        i = min(int(s[j] * inv), last)
        t = s[j] * inv - i
        for d in range(q):
            c0, c1, c2 = pieces[i, 0, d], pieces[i, 1, d], pieces[i, 2, d]
            c3, c4, c5 = pieces[i, 3, d], pieces[i, 4, d], pieces[i, 5, d]
            out[d, 0, j] = ((((c5 * t + c4) * t + c3) * t + c2) * t + c1) * t + c0
            out[d, 1, j] = (
                (((5.0 * c5 * t + 4.0 * c4) * t + 3.0 * c3) * t + 2.0 * c2) * t + c1
            ) * inv
            out[d, 2, j] = (((20.0 * c5 * t + 12.0 * c4) * t + 6.0 * c3) * t + 2.0 * c2) * inv2
