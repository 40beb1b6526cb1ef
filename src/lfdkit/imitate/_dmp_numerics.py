"""The DMP's numerics apart from the estimator: transitions, quadrature, bases, pieces.

:class:`lfdkit.imitate.DMP` is the estimator (parameters, fit, rollout, step);
what it computes with lives here, each a plain function of arrays: the exact
transition of the critically damped spring (:func:`transition`), Gauss–Legendre
quadrature of the forcing over panels (:func:`quadrature`), the step operators
and their propagation (:func:`step_operators`, :func:`propagate`), the rotations
of the spatial scaling (:func:`rotations_between`), quintic pieces of the
forcing (:func:`quintic_pieces`, :func:`evaluate_pieces`), the Gaussian basis
and its cache (:func:`basis`), the minimum-jerk law (:func:`minimum_jerk_law`),
the dense sampler of a timed path (:func:`dense_sampler`) and the reproduction
error (:func:`reproduction_departure`). See :mod:`lfdkit.imitate.dmp` for the
mathematics and the numbers that decided them.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np

from lfdkit.core.geometry import arc_length, path_length
from lfdkit.core.kernels import kernel

__all__ = [
    "END_NODES",
    "MAX_PANEL",
    "basis",
    "dense_sampler",
    "evaluate_pieces",
    "minimum_jerk_law",
    "propagate",
    "quadrature",
    "quintic_pieces",
    "remember",
    "reproduction_departure",
    "rotations_between",
    "step_operators",
    "transition",
]

#: Gauss–Legendre nodes per quadrature panel and the longest panel (normalised time).
_GAUSS_NODES = 4


MAX_PANEL = 0.01


#: Panels of the once-per-fit end-state integral: fine and of high order.
END_NODES = 6


_MAX_CACHED_GRIDS = 8


def transition(k: float, c: float, t: np.ndarray) -> np.ndarray:
    """``e^{A t}`` for ``A = [[0, 1], [−k, −c]]``, closed form, shape (2, 2, len(t)).

    Entry ``[i, j]`` is a contiguous array over ``t`` (the rollout reads whole rows).

    ``e^{At} = e^{μt} (C(t) I + S(t) (A − μI))`` with ``μ = −c/2``,
    ``δ² = μ² − k``, ``C = cosh δt``, ``S = sinh(δt)/δ`` (``cos``/``sin``
    when under-damped; ``C = 1``, ``S = t`` when critically damped, as the
    thesis's gains are).
    """
    t = np.asarray(t, dtype=np.float64)
    mu = -0.5 * c
    delta2 = mu * mu - k
    root = np.sqrt(abs(delta2))
    x = root * t
    if abs(delta2) <= 1e-12 * k or np.all(np.abs(x) < 1e-4):
        series = 1.0 + np.sign(delta2) * x * x / 6.0
        cosine, sine = 1.0 + np.sign(delta2) * x * x / 2.0, t * series
    elif delta2 > 0:
        cosine, sine = np.cosh(x), np.sinh(x) / root
    else:
        cosine, sine = np.cos(x), np.sin(x) / root
    decay = np.exp(mu * t)
    out = np.empty((2, 2, *t.shape))
    out[0, 0] = decay * (cosine - mu * sine)
    out[0, 1] = decay * sine
    out[1, 0] = -k * decay * sine
    out[1, 1] = decay * (cosine - (c + mu) * sine)
    return out


@lru_cache(maxsize=16)
def _legendre(n_nodes: int) -> tuple[np.ndarray, np.ndarray]:
    return np.polynomial.legendre.leggauss(n_nodes)


def quadrature(
    h: float, max_panel: float = MAX_PANEL, n_nodes: int = _GAUSS_NODES
) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes in ``[0, h]`` and their weights, panels ``<= max_panel``."""
    n_panels = max(1, int(np.ceil(h / max_panel - 1e-9)))
    x, w = _legendre(n_nodes)
    width = h / n_panels
    starts = width * np.arange(n_panels)[:, None]
    nodes = (starts + 0.5 * width * (x + 1.0)).ravel()
    weights = np.tile(0.5 * width * w, n_panels)
    return nodes, weights


def step_operators(
    k: float, c: float, h: float, max_panel: float = MAX_PANEL
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact one-step operators for the spring over a normalised step ``h``.

    Returns ``Φ = e^{Ah}`` (2, 2), the quadrature nodes ``σ`` (m,), and
    ``Γ`` (m, 2) with ``Γ_m = w_m e^{A(h − σ_m)} B``, so that
    ``x(s+h) = Φ x(s) + Σ_m Γ_m f(s + σ_m)``.
    """
    # Steps far shorter than a panel need one node fewer for the same accuracy.
    n_nodes = _GAUSS_NODES - 1 if h <= 0.2 * max_panel else _GAUSS_NODES
    nodes, weights = quadrature(h, max_panel, n_nodes)
    phi = transition(k, c, np.array([h]))[:, :, 0]
    gamma = transition(k, c, h - nodes)[:, 1, :].T * weights[:, None]
    return phi, nodes, gamma


def propagate(phi: np.ndarray, x0: np.ndarray, inputs: np.ndarray) -> np.ndarray:
    """Run ``x_{j+1} = Φ x_j + v_j`` as a second-order IIR filter.

    Parameters
    ----------
    phi : ndarray, shape (2, 2)
    x0 : ndarray, shape (2, m)
    inputs : ndarray, shape (n - 1, 2, m)

    Returns
    -------
    ndarray, shape (n, 2, m)

    Notes
    -----
    ``(I − Φ z⁻¹)⁻¹ = (I − adj(Φ) z⁻¹) / (1 − tr(Φ) z⁻¹ + det(Φ) z⁻²)`` for a
    2×2 ``Φ``, so each state is one call of :func:`scipy.signal.lfilter` on
    the sequence ``(x0, v_0, v_1, …)`` followed by one matrix product.
    """
    sequence = np.concatenate([x0[None], inputs], axis=0)
    denominator = [1.0, -np.trace(phi), np.linalg.det(phi)]
    from scipy.signal import lfilter  # here: lfdkit.imitate loads fast

    filtered = lfilter([1.0], denominator, sequence, axis=0)
    adjugate = np.array([[phi[1, 1], -phi[0, 1]], [-phi[1, 0], phi[0, 0]]])
    states = filtered.copy()
    states[1:] -= adjugate @ filtered[:-1]
    return states


def rotations_between(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Smallest rotations taking unit vector ``u`` (q,) onto each row of ``v`` (r, q).

    Each rotates in the plane spanned by ``u`` and ``v`` and leaves its
    orthogonal complement fixed (Rodrigues' formula in that plane). For
    ``v = −u`` the plane is not defined: the rotation by π is taken in the
    plane of ``u`` and the coordinate axis least aligned with it (in 2-D this
    is the unique rotation, ``−I``). In 1-D the "rotation" is the sign.
    """
    q = u.size
    if q == 1:
        return np.where(v * u[0] > 0, 1.0, -1.0)[:, :, None]
    cos = np.clip(v @ u, -1.0, 1.0)
    ortho = v - cos[:, None] * u
    sin = np.linalg.norm(ortho, axis=1)
    opposite = sin < 1e-12
    if np.any(opposite):
        axis = np.zeros(q)
        axis[int(np.argmin(np.abs(u)))] = 1.0
        axis -= (axis @ u) * u
        ortho[opposite] = axis / np.linalg.norm(axis)
        sin[opposite] = 0.0
        cos[opposite] = np.where(cos[opposite] > 0, 1.0, -1.0)
    ortho[~opposite] /= sin[~opposite, None]
    uu = np.outer(u, u)
    oo = ortho[:, :, None] * ortho[:, None, :]
    ou = ortho[:, :, None] * u[None, None, :]
    return (
        np.eye(q)
        + sin[:, None, None] * (ou - ou.transpose(0, 2, 1))
        + (cos - 1.0)[:, None, None] * (uu + oo)
    )


def quintic_pieces(
    values: np.ndarray, slopes: np.ndarray, curvatures: np.ndarray, spacing: float
) -> np.ndarray:
    """Coefficients of the C² piecewise quintic through knot values, slopes, curvatures.

    Knots at ``0, spacing, 2 spacing, …``; inputs (n_knots, q). Returns
    ``c`` (n_knots − 1, 6, q): on piece ``i`` the quintic is ``Σ_m c[i, m] t^m``
    with ``t = s / spacing − i`` in ``[0, 1]`` (quintic Hermite interpolation).
    """
    p0, p1 = values[:-1], values[1:]
    v0, v1 = slopes[:-1] * spacing, slopes[1:] * spacing
    a0, a1 = curvatures[:-1] * spacing**2, curvatures[1:] * spacing**2
    return np.stack(
        [
            p0,
            v0,
            0.5 * a0,
            10.0 * (p1 - p0) - 6.0 * v0 - 4.0 * v1 - 1.5 * a0 + 0.5 * a1,
            15.0 * (p0 - p1) + 8.0 * v0 + 7.0 * v1 + 1.5 * a0 - a1,
            6.0 * (p1 - p0) - 3.0 * (v0 + v1) - 0.5 * (a0 - a1),
        ],
        axis=1,
    )


def evaluate_pieces(s: np.ndarray, spacing: float, pieces: np.ndarray) -> np.ndarray:
    """Value and first two derivatives of :func:`_quintic_pieces` at ``s``, (q, 3, len(s)).

    numba's kernel or :func:`evaluate_quintic_pieces`, as :mod:`lfdkit.core.kernels` chooses.
    """
    evaluate = kernel(
        "evaluate_quintic_pieces", "lfdkit.imitate._dmp_kernels", "lfdkit.imitate._dmp_numerics"
    )
    out = np.empty((pieces.shape[2], 3, s.size))
    evaluate(np.ascontiguousarray(s, dtype=np.float64), spacing, pieces, out)
    return out


def evaluate_quintic_pieces(
    s: np.ndarray, spacing: float, pieces: np.ndarray, out: np.ndarray
) -> None:
    """NumPy form of ``_dmp_kernels.evaluate_quintic_pieces``, the same operations in order.

    ``pieces`` (n_pieces, 6, q) holds each piece's monomial coefficients in
    its local ``t = s / spacing − i``; fills ``out`` (q, 3, len(s)) with the
    value and first two derivatives in ``s``.
    """
    inv, inv2 = 1.0 / spacing, 1.0 / (spacing * spacing)
    scaled = s * inv
    piece = np.minimum(scaled.astype(np.int64), pieces.shape[0] - 1)
    t = scaled - piece
    c0, c1, c2, c3, c4, c5 = (pieces[piece, power].T for power in range(6))  # each (q, len(s))
    out[:, 0] = ((((c5 * t + c4) * t + c3) * t + c2) * t + c1) * t + c0
    out[:, 1] = ((((5.0 * c5 * t + 4.0 * c4) * t + 3.0 * c3) * t + 2.0 * c2) * t + c1) * inv
    out[:, 2] = (((20.0 * c5 * t + 12.0 * c4) * t + 6.0 * c3) * t + 2.0 * c2) * inv2


def remember(cache: dict, key: Any, value: Any) -> None:
    """Insert into a small first-in-first-out cache."""
    if len(cache) >= _MAX_CACHED_GRIDS:
        cache.pop(next(iter(cache)))
    cache[key] = value


@lru_cache(maxsize=32)
def _basis_cached(n_basis: int, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    centers = np.exp(-alpha * np.linspace(0.0, 1.0, n_basis))
    if n_basis == 1:
        return centers, np.array([1.0])
    gaps = np.abs(np.diff(centers))
    gaps = np.append(gaps, gaps[-1])
    # Neighbouring Gaussians cross at 1/√2 of their height, exp(−h (Δ/2)²) = 2^(−1/2):
    # wider than the usual half height, which reproduced paths measurably worse.
    widths = 2.0 * np.log(2.0) / gaps**2
    centers.setflags(write=False)
    widths.setflags(write=False)
    return centers, widths


def basis(n_basis: int, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    return _basis_cached(n_basis, float(alpha))


def minimum_jerk_law(u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fraction of the way ``10u³ − 15u⁴ + 6u⁵`` and its first two derivatives in ``u``."""
    return (
        u**3 * (10.0 - 15.0 * u + 6.0 * u**2),
        30.0 * u**2 * (1.0 - u) ** 2,
        60.0 * u * (1.0 - u) * (1.0 - 2.0 * u),
    )


def dense_sampler(s: np.ndarray | None, points: np.ndarray, law: Any = None) -> Any:
    """Positions and their first two derivatives on a dense, even grid of ``s ∈ [0, 1]``.

    Returns ``sample(n_basis) -> (grid, positions, velocities, accelerations)``,
    the grid as fine as ``n_basis`` basis functions need; the spline is built
    once, so ``n_basis="auto"`` samples every count of its ladder cheaply.

    With sample times ``s``, a cubic interpolating spline (not-a-knot ends)
    through every sample is differentiated analytically. With ``s=None`` the
    timing law is composed exactly: a cubic spline of the path in its
    arc-length fraction ``ℓ``, moved along by ``ℓ(s)`` of ``law`` (default
    :func:`_minimum_jerk_law`; or a :meth:`SpeedProfile.law`; it returns
    ``ℓ``, ``ℓ'`` and ``ℓ''``) by the chain rule, so the motion is at rest at
    both ends without the spline having to guess it from sparse end samples.

    The dense even grid matters when samples are uneven in time: a basis
    function with no sample under it would otherwise get an arbitrary weight.
    """
    n = points.shape[0]
    degree = min(3, n - 1)

    def grid_for(n_basis: int) -> np.ndarray:
        return np.linspace(0.0, 1.0, max(2 * n, 20 * n_basis, 1000))

    if s is not None:
        from scipy.interpolate import make_interp_spline  # here: lfdkit.imitate loads fast

        timed = make_interp_spline(s, points, k=degree, axis=0)

        def sample_timed(n_basis: int) -> tuple[np.ndarray, ...]:
            grid = grid_for(n_basis)
            return grid, timed(grid), timed(grid, 1), timed(grid, 2)

        return sample_timed
    fraction = arc_length(points) / path_length(points)
    from scipy.interpolate import make_interp_spline  # here: lfdkit.imitate loads fast

    spline = make_interp_spline(fraction, points, k=degree, axis=0)
    law = minimum_jerk_law if law is None else law

    def sample_composed(n_basis: int) -> tuple[np.ndarray, ...]:
        grid = grid_for(n_basis)
        where, speed, rate = law(grid)
        slope, bend = spline(where, 1), spline(where, 2)
        return (
            grid,
            spline(where),
            slope * speed[:, None],
            bend * speed[:, None] ** 2 + slope * rate[:, None],
        )

    return sample_composed


def reproduction_departure(
    k: float, c: float, s: np.ndarray, velocity0: np.ndarray, mismatch: np.ndarray
) -> np.ndarray:
    """Reproduction minus path on the even grid ``s``, shape (len(s), q).

    The path obeys the transformation system exactly with its target forcing
    ``F``, the reproduction with the fitted ``X w``; their difference ``e``
    obeys ``e'' = −k e − c e' + (X w − F)`` from ``e(0) = 0``,
    ``e'(0) = −y'(0)`` (the reproduction starts at rest). The mismatch
    ``X w − F`` (len(s), q) is held linear between grid points and the
    spring integrated exactly over each step, as :func:`_propagate` does but
    for the position only: one second-order IIR filter per dimension.
    """
    h = float(s[1] - s[0])
    x, w = _legendre(_GAUSS_NODES)
    nodes, weights = 0.5 * h * (x + 1.0), 0.5 * h * w
    kernel = transition(k, c, h - nodes)[:, 1, :]  # e^{A(h − σ)} B, (2, m)
    later = nodes / h
    now_weights, next_weights = kernel @ (weights * (1.0 - later)), kernel @ (weights * later)
    phi = transition(k, c, np.array([h]))[:, :, 0]
    # The state sequence (x0, v_0, v_1, …) of _propagate, both components, (n, q) each.
    u = np.ascontiguousarray(mismatch.T)  # (q, n): filter along contiguous rows
    drive = np.empty((2, *u.shape))
    drive[:, :, 0] = np.stack([np.zeros_like(velocity0), -velocity0])
    drive[:, :, 1:] = (
        now_weights[:, None, None] * u[None, :, :-1] + next_weights[:, None, None] * u[None, :, 1:]
    )
    # Position row of (I − Φ z⁻¹)⁻¹ = adj(I − Φ z⁻¹) / det(I − Φ z⁻¹).
    combined = drive[0].copy()
    combined[:, 1:] += -phi[1, 1] * drive[0, :, :-1] + phi[0, 1] * drive[1, :, :-1]
    denominator = [1.0, -np.trace(phi), np.linalg.det(phi)]
    from scipy.signal import lfilter  # here: lfdkit.imitate loads fast

    return lfilter([1.0], denominator, combined, axis=1).T
