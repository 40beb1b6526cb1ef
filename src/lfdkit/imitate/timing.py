"""Timing along a path: the duration of a movement and its speed profile.

A movement that follows a path of length ``L`` (units) in ``T`` seconds is
described, whatever the path, by its *progress law* ``σ(u)``: the fraction of
the path's length travelled at the normalised time (phase) ``u = t / T``,
rising from ``σ(0) = 0`` to ``σ(1) = 1``. Its derivative ``ν(u) = dσ/du`` is
the *normalised speed*: the speed along the path is ``L ν(t/T) / T`` (units
per second), and ``ν`` averages 1 over the movement. A
:class:`SpeedProfile` is such a law with a duration:

* :meth:`SpeedProfile.minimum_jerk` is ``σ = 10u³ − 15u⁴ + 6u⁵``,
  ``ν = 30 u² (1 − u)²``: rest to rest, peak 1.875 at mid-movement (what
  lfdkit assumed before timings were learned, and still the default when
  demonstrations carry no times);
* :meth:`SpeedProfile.uniform` is ``ν = 1``, the thesis's equal time steps
  (constant speed, which a DMP starting at rest cannot follow at the ends);
* :func:`learn_timing` learns ``T`` and ``ν`` from demonstrations with times.

Representation
--------------
``ν`` is a quartic B-spline on ``[0, 1]`` with clamped, evenly spaced knots
and non-negative coefficients (so ``ν ≥ 0`` and ``σ`` never runs backwards);
five coefficients are one polynomial piece, in which the minimum-jerk law is
exact (Bernstein coefficients ``(0, 0, 5, 0, 0)``). The coefficients are
stored as given (a skill file holds them exactly); every evaluation divides
by ``σ(1)``, so the law integrates to 1 to round-off whatever their scale.

Learning (:func:`learn_timing`)
-------------------------------
For each demonstration ``j`` with times ``t_j`` (seconds):

1. **progress**: where each sample lies along the path the demonstrations
   follow (the generalized path; the skill passes its own), as a fraction of
   its length (:func:`path_progress`). Each sample is matched to a segment by
   a monotone assignment that minimises the summed squared distances (a
   dynamic programme over samples × segments), so a loop or a closed shape is
   passed in order, and sensor noise across the path adds no length (a noisy
   demonstration's own arc length would: 2 mm of noise on 8 mm steps puts
   20 % errors into the speed). The running maximum keeps it non-decreasing,
   and it is rescaled to run from 0 to 1 between the demonstration's first
   and last sample;
2. **phase**: ``u = (t − t₀) / T_j``, with ``T_j`` its duration.

The duration is the median ``T_j``; the progress law is the pointwise median
of the demonstrations' ``σ_j(u)`` on 201 phases (a median of non-decreasing
curves is non-decreasing, and a few outlying demonstrations or jittery time
stamps do not move it), and ``ν`` is fitted to it by non-negative least
squares on the integrated B-spline basis (16 coefficients by default: the
smoothing), the two first and two last held at zero so that the movement
starts and ends at rest with zero acceleration along the path, as a robot
must. Demonstrations should be trimmed of idle samples before and after the
movement: a recorded pause becomes part of the learned timing.

Timing a path (:meth:`SpeedProfile.time_path`)
-----------------------------------------------
Any path, such as a plan that swerves around an obstacle and is longer than
the nominal, is timed by *its own* arc length: the point at fraction ``σ`` of
its length ``L`` is reached at ``t = T σ⁻¹(σ)`` and passed at the speed
``L ν(u) / T`` along the tangent (of a cubic spline through the points in
``σ``). The speed profile is then the learned one, scaled by the path's
length: a 10 % longer path in the same duration is 10 % faster everywhere,
never locally faster where it swerves. (Keeping the nominal's time for each
plan point instead, the swerve's longer steps take the nominal's short time
steps: 30 % above the demonstrations' peak speed around a large cup on the
sweeping example, against the 7 % by which that plan is longer.)
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lfdkit.core.geometry import arc_length, segment_lengths
from lfdkit.core.kernels import kernel
from lfdkit.core.validation import (
    check_count,
    check_demos,
    check_path,
    check_positive,
    check_times_list,
)
from lfdkit.imitate._dmp_numerics import minimum_jerk_law

__all__ = [
    "DEGREE",
    "DURATION_RANGE",
    "MAX_COEFFICIENTS",
    "SpeedProfile",
    "learn_timing",
    "minimum_jerk_law",
    "path_progress",
]

#: Degree of the B-spline of the normalised speed ``ν`` (quartic: minimum jerk is exact).
DEGREE = 4
#: Bisection steps of :meth:`SpeedProfile.phase`: 2⁻⁵⁵ in the phase, below a double's resolution.
BISECTION_STEPS = 55
#: Most coefficients a speed profile may have (a skill file holds at most this many).
MAX_COEFFICIENTS = 200
#: Durations (seconds) a speed profile and a :class:`lfdkit.imitate.DMP` accept.
DURATION_RANGE = (1e-6, 1e9)
#: Phases on which the demonstrations' progress is compared and fitted.
_N_PHASES = 201
#: Demonstration samples beyond this are thinned (evenly) before matching them to the path.
_MAX_MATCHED_SAMPLES = 4000
#: A demonstration must cover at least this fraction of the path to give a timing.
_MIN_COVERAGE = 0.5
#: Weight of the row ``σ(1) = 1`` in the least-squares fit.
_END_WEIGHT = 1e3
_SOURCES = ("minimum_jerk", "uniform", "demonstrations", "given")


class _Spline:
    """A B-spline on ``[t[degree], t[-degree-1]]``, evaluated by de Boor's algorithm.

    What the speed law needs of :class:`scipy.interpolate.BSpline` (value,
    derivative, antiderivative) in NumPy alone: importing
    ``scipy.interpolate`` costs a fresh ``lfdkit plan`` 0.5 to 1.4 s (it pulls
    in ``scipy.optimize``, ``sparse``, ``spatial`` and ``special``), against a
    plan of 30 ms. Agrees with SciPy's to rounding (tests).
    """

    def __init__(self, knots: np.ndarray, coefficients: np.ndarray, degree: int) -> None:
        self.t, self.c, self.k = knots, coefficients, degree

    def __call__(self, x: np.ndarray) -> np.ndarray:
        t, c, k = self.t, self.c, self.k
        x = np.asarray(x, dtype=np.float64)
        span = np.searchsorted(t, x, side="right") - 1
        span = np.clip(span, k, len(t) - k - 2)  # the right end is in the last piece
        d = [c[span - k + j] for j in range(k + 1)]
        for r in range(1, k + 1):
            for j in range(k, r - 1, -1):
                left, right = t[span - k + j], t[span + 1 + j - r]
                alpha = (x - left) / (right - left)
                d[j] = (1.0 - alpha) * d[j - 1] + alpha * d[j]
        return d[k]

    def derivative(self) -> _Spline:
        t, c, k = self.t, self.c, self.k
        m = c.size
        slopes = k * np.diff(c) / (t[k + 1 : k + m] - t[1:m])
        return _Spline(t[1:-1], slopes, k - 1)

    def antiderivative(self) -> _Spline:
        t, c, k = self.t, self.c, self.k
        m = c.size
        running = np.cumsum(c * (t[k + 1 : k + 1 + m] - t[:m])) / (k + 1)
        return _Spline(np.r_[t[0], t, t[-1]], np.r_[0.0, running], k + 1)


def _interpolant_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``dy/dx`` at the nodes of the not-a-knot cubic spline through ``(x, y)``, (n, q).

    The interpolant of :func:`scipy.interpolate.make_interp_spline` with
    ``k=min(3, n - 1)`` (a line through 2 points, the parabola through 3),
    solved for its node slopes as a tridiagonal system by elimination in
    NumPy (:func:`_solve_tridiagonal`; no SciPy, so a one-shot ``lfdkit plan``
    that runs NumPy kernels loads none: 0.3 s of CPU saved). It agrees with
    ``scipy.linalg.solve_banded`` to round-off (about 1e-15 relative).
    """
    dx = np.diff(x)[:, None]
    slope = np.diff(y, axis=0) / dx
    n = len(x)
    if n == 2:
        return np.repeat(slope, 2, axis=0)
    if n == 3:  # the parabola: its slope at each node
        h0, h1 = dx[0], dx[1]
        bend = (slope[1] - slope[0]) / (h0 + h1)
        return np.stack([slope[0] - bend * h0, slope[0] + bend * h0, slope[1] + bend * h1])
    bands = np.zeros((3, n))
    rhs = np.empty_like(y)
    bands[1, 1:-1] = 2.0 * (dx[:-1, 0] + dx[1:, 0])
    bands[0, 2:] = dx[:-1, 0]
    bands[2, :-2] = dx[1:, 0]
    rhs[1:-1] = 3.0 * (dx[1:] * slope[:-1] + dx[:-1] * slope[1:])
    # Not-a-knot: the third derivative is continuous at the second and last-but-one nodes.
    first, last = x[2] - x[0], x[-1] - x[-3]
    bands[1, 0], bands[0, 1] = dx[1, 0], first
    rhs[0] = ((dx[0] + 2.0 * first) * dx[1] * slope[0] + dx[0] ** 2 * slope[1]) / first
    bands[1, -1], bands[2, -2] = dx[-2, 0], last
    rhs[-1] = (dx[-1] ** 2 * slope[-2] + (2.0 * last + dx[-1]) * dx[-2] * slope[-1]) / last
    return _solve_tridiagonal(bands[2, :-1], bands[1], bands[0, 1:], rhs)


def _solve_tridiagonal(
    below: np.ndarray, diagonal: np.ndarray, above: np.ndarray, rhs: np.ndarray
) -> np.ndarray:
    """``x`` (n, q) with ``below[i-1] x[i-1] + diagonal[i] x[i] + above[i] x[i+1] = rhs[i]``.

    Elimination without pivoting (the Thomas algorithm): the spline's rows
    are diagonally dominant but the two not-a-knot rows, whose elimination
    leaves a positive pivot (``x[2] − x[0]`` after the first), so it is stable.
    On Python floats, a column at a time: the same operations as on NumPy's
    rows (each rounded once), bit for bit, without a NumPy call per row (a
    100-point plan's timing spent a third of its time in this loop).
    """
    n = diagonal.size
    low, diag, up = below.tolist(), diagonal.tolist(), above.tolist()
    pivot, factor = [diag[0]] * n, [0.0] * n
    for i in range(1, n):
        factor[i] = low[i - 1] / pivot[i - 1]
        pivot[i] = diag[i] - factor[i] * up[i - 1]
    columns = []
    for y in np.asarray(rhs, dtype=np.float64).reshape(n, -1).T.tolist():
        for i in range(1, n):
            y[i] = y[i] - factor[i] * y[i - 1]
        x = [0.0] * n
        x[-1] = y[-1] / pivot[-1]
        for i in range(n - 2, -1, -1):
            x[i] = (y[i] - up[i] * x[i + 1]) / pivot[i]
        columns.append(x)
    return np.array(columns, dtype=np.float64).T.copy().reshape(np.shape(rhs))


def _knots(n_coefficients: int) -> np.ndarray:
    """Clamped, evenly spaced knots on [0, 1] for ``n_coefficients`` quartic B-splines."""
    inner = np.linspace(0.0, 1.0, n_coefficients - DEGREE + 1)
    return np.concatenate([np.zeros(DEGREE), inner, np.ones(DEGREE)])


@dataclass(frozen=True, eq=False)
class SpeedProfile:
    """How fast a movement runs along its path: a duration and a normalised speed law.

    Parameters
    ----------
    duration : float
        Duration ``T`` of the movement, seconds (1e-6 to 1e9).
    coefficients : array_like, shape (m,)
        B-spline coefficients of the normalised speed ``ν(u)`` (module notes),
        ``m`` from 5 to :data:`MAX_COEFFICIENTS`, finite, non-negative, not all
        zero. Their scale does not matter (``σ(1)`` is normalised to 1).
    source : {"minimum_jerk", "uniform", "demonstrations", "given"}
        Where the law came from (for files and reports).
    demo_durations : tuple of float
        Durations of the demonstrations it was learned from, seconds (empty
        for a law that was not learned).

    Notes
    -----
    Instances are immutable; :meth:`with_duration` gives a copy lasting
    another time. Use :meth:`minimum_jerk`, :meth:`uniform` or
    :func:`learn_timing` to make one.
    """

    duration: float
    coefficients: np.ndarray
    source: str = "given"
    demo_durations: tuple[float, ...] = field(default=())

    def __post_init__(self) -> None:
        duration = _check_duration(self.duration)
        try:
            coefficients = np.array(self.coefficients, dtype=np.float64)
        except (TypeError, ValueError) as exc:
            raise TypeError("coefficients: expected a 1-D array of numbers") from exc
        if coefficients.ndim != 1 or not DEGREE + 1 <= coefficients.size <= MAX_COEFFICIENTS:
            raise ValueError(
                f"coefficients: expected a 1-D array of {DEGREE + 1} to {MAX_COEFFICIENTS} "
                f"values, got shape {coefficients.shape}"
            )
        if not np.all(np.isfinite(coefficients)):
            raise ValueError("coefficients: contains NaN or infinite values")
        if np.any(coefficients < 0.0) or not np.any(coefficients > 0.0):
            raise ValueError(
                "coefficients: expected non-negative values, not all zero (the speed along "
                "the path never runs backwards)"
            )
        if self.source not in _SOURCES:
            raise ValueError(f"source: expected one of {_SOURCES}, got {self.source!r}")
        demo_durations = tuple(float(d) for d in self.demo_durations)
        if not all(np.isfinite(d) and d > 0 for d in demo_durations):
            raise ValueError("demo_durations: expected positive, finite durations in seconds")
        coefficients.setflags(write=False)
        object.__setattr__(self, "duration", float(duration))
        object.__setattr__(self, "coefficients", coefficients)
        object.__setattr__(self, "demo_durations", demo_durations)
        object.__setattr__(self, "_splines", None)

    def _law_splines(self) -> tuple[Any, Any, Any, float]:
        """``(ν, σ, ν', σ(1))`` as B-splines, built on first use.

        Built lazily: making a profile (loading a skill) then costs no
        ``scipy.interpolate`` import (about 1.4 s cold), only evaluating one does.
        """
        if self._splines is None:
            speed = _Spline(_knots(self.coefficients.size), self.coefficients, DEGREE)
            progress = speed.antiderivative()
            splines = (speed, progress, speed.derivative(), float(progress(np.array(1.0))))
            object.__setattr__(self, "_splines", splines)
        return self._splines

    # ------------------------------------------------------------ constructors
    @classmethod
    def minimum_jerk(cls, duration: float = 1.0) -> SpeedProfile:
        """The minimum-jerk law ``ν = 30 u² (1 − u)²`` over ``duration`` seconds (exact)."""
        return cls(duration, np.array([0.0, 0.0, 5.0, 0.0, 0.0]), "minimum_jerk")

    @classmethod
    def uniform(cls, duration: float = 1.0) -> SpeedProfile:
        """Constant speed ``ν = 1`` over ``duration`` seconds (the thesis's equal time steps)."""
        return cls(duration, np.ones(DEGREE + 1), "uniform")

    @classmethod
    def from_law(cls, timing: str, duration: float = 1.0) -> SpeedProfile:
        """:meth:`minimum_jerk` or :meth:`uniform` by name (a DMP's ``timing`` choices)."""
        if timing == "minimum_jerk":
            return cls.minimum_jerk(duration)
        if timing == "uniform":
            return cls.uniform(duration)
        raise ValueError(f"timing: expected 'minimum_jerk' or 'uniform', got {timing!r}")

    def with_duration(self, duration: float) -> SpeedProfile:
        """The same law lasting ``duration`` seconds."""
        return SpeedProfile(duration, self.coefficients, self.source, self.demo_durations)

    # ------------------------------------------------------------ evaluation
    def progress(self, u: Any) -> np.ndarray:
        """Fraction ``σ(u)`` of the path travelled at phase ``u = t / T`` (clipped to [0, 1])."""
        _, progress, _, total = self._law_splines()
        return progress(_phase(u)) / total

    def speed(self, u: Any) -> np.ndarray:
        """Normalised speed ``ν(u) = dσ/du``; the speed along the path is ``L ν / T``."""
        speed, _, _, total = self._law_splines()
        return speed(_phase(u)) / total

    def law(self, u: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``σ(u)``, ``σ'(u)`` and ``σ''(u)`` (derivatives in ``u``), ``u`` clipped to [0, 1]."""
        u = _phase(u)
        speed, progress, rate, total = self._law_splines()
        return progress(u) / total, speed(u) / total, rate(u) / total

    @property
    def peak_speed(self) -> float:
        """Largest normalised speed ``max ν`` (1.875 for minimum jerk, 1 for uniform)."""
        return float(np.max(self.speed(np.linspace(0.0, 1.0, 2001))))

    def phase(self, fraction: Any) -> np.ndarray:
        """The phase ``u`` at which the fraction ``σ`` of the path is reached (``σ⁻¹``).

        Where ``ν`` is zero over an interval (a pause) the first phase is
        returned. ``fraction`` is clipped to [0, 1].
        """
        target = np.clip(np.asarray(fraction, dtype=np.float64), 0.0, 1.0)
        _, progress, _, total = self._law_splines()
        # numba's kernel (about 100x faster) or phase_bisection below, bit for bit the same.
        bisection = kernel("phase_bisection", "lfdkit.imitate._timing_kernels", __name__)
        flat = np.ascontiguousarray(target.reshape(-1))
        out = np.empty_like(flat)
        bisection(progress.t, progress.c, progress.k, total, BISECTION_STEPS, flat, out)
        return out.reshape(target.shape)

    def times(self, path: Any, duration: float | None = None) -> np.ndarray:
        """Time at which each point of ``path`` is reached, seconds, by its arc length.

        Parameters
        ----------
        path : array_like, shape (n, q)
            Consecutive points distinct.
        duration : float, optional
            Seconds (default :attr:`duration`).

        Returns
        -------
        ndarray, shape (n,)
            From 0 to the duration, non-decreasing (strictly where ``ν > 0``).
        """
        points = check_path(path, "path", min_points=2, min_dims=1)
        total = self.duration if duration is None else _check_duration(duration)
        return total * self.phase(_fractions(points))

    def time_path(self, path: Any, duration: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """Times and velocities of a path run with this speed law (module notes).

        Parameters
        ----------
        path : array_like, shape (n, q)
            Points, at least 2, consecutive points distinct (units).
        duration : float, optional
            Seconds (default :attr:`duration`).

        Returns
        -------
        times : ndarray, shape (n,)
            Seconds from 0 to the duration.
        velocities : ndarray, shape (n, q)
            Units per second: the speed along the path ``L ν(u) / T`` (so
            zero at the ends for a rest-to-rest law) in the direction of the
            path's tangent (a cubic spline through the points).
        """
        points = check_path(path, "path", min_points=2, min_dims=1)
        total = self.duration if duration is None else _check_duration(duration)
        lengths = segment_lengths(points)
        fractions = _fractions(points)
        u = self.phase(fractions)
        tangent = _interpolant_slopes(fractions, points)
        norms = np.linalg.norm(tangent, axis=1)
        flat = norms <= 1e-12 * float(lengths.sum())
        if np.any(flat):  # a spline cusp: the neighbours' chord instead
            tangent[flat] = np.gradient(points, fractions, axis=0)[flat]
            norms[flat] = np.linalg.norm(tangent[flat], axis=1)
        direction = tangent / np.where(norms > 0.0, norms, 1.0)[:, None]
        speed = float(lengths.sum()) * self.speed(u) / total
        return total * u, direction * speed[:, None]

    # ------------------------------------------------------------ files
    def to_dict(self) -> dict[str, Any]:
        """The profile as JSON-ready data (floats exact): source, duration, coefficients."""
        out: dict[str, Any] = {
            "source": self.source,
            "duration": self.duration,
            "speed": self.coefficients.tolist(),
        }
        if self.demo_durations:
            out["demo_durations"] = list(self.demo_durations)
        return out

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], where: str = "timing") -> SpeedProfile:
        """Read :meth:`to_dict`'s output; errors start with ``where`` and name the field."""
        if not isinstance(data, Mapping):
            raise ValueError(f"{where}: expected an object")
        for key in ("source", "duration", "speed"):
            if key not in data:
                raise ValueError(f"{where}.{key}: missing field")
        speed = data["speed"]
        if not isinstance(speed, list) or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in speed
        ):
            raise ValueError(f"{where}.speed: expected a list of numbers")
        duration = data["duration"]
        if isinstance(duration, bool) or not isinstance(duration, (int, float)):
            raise ValueError(f"{where}.duration: expected a number, got {duration!r}")
        durations = data.get("demo_durations", [])
        if not isinstance(durations, list) or not all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in durations
        ):
            raise ValueError(f"{where}.demo_durations: expected a list of numbers")
        try:
            return cls(
                float(duration), np.array(speed, dtype=np.float64), data["source"], tuple(durations)
            )
        except (TypeError, ValueError) as exc:
            message = str(exc)
            if message.startswith("coefficients:"):  # the field's name in the file
                message = "speed:" + message[len("coefficients:") :]
            raise ValueError(f"{where}.{message}") from None

    def __repr__(self) -> str:
        return (
            f"SpeedProfile(duration={self.duration:g}, source={self.source!r}, "
            f"{self.coefficients.size} coefficients, peak speed {self.peak_speed:.3g})"
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, SpeedProfile):
            return NotImplemented
        return (
            self.duration == other.duration
            and self.source == other.source
            and self.demo_durations == other.demo_durations
            and np.array_equal(self.coefficients, other.coefficients)
        )

    __hash__ = None  # type: ignore[assignment]


# ------------------------------------------------------------------ learning
def path_progress(demo: Any, path: Any) -> np.ndarray:
    """Fraction of a path's length at which each sample of a demonstration passes.

    Parameters
    ----------
    demo : array_like, shape (n, q)
        The demonstration, in the units of ``path``.
    path : array_like, shape (m, q)
        The path to measure along: the generalized path, or a smoothed
        demonstration (a noisy demonstration's own arc length is lengthened by
        its noise, and its timing with it).

    Returns
    -------
    ndarray, shape (n,)
        Non-decreasing fractions in [0, 1]: each sample is matched to a
        segment of ``path`` so that the matched segments never go back and
        the summed squared distances are least (module notes), and placed at
        its closest point on that segment; the running maximum removes what
        noise would still move backwards.
    """
    points = check_path(demo, "demo", min_points=2, min_dims=1)
    line = check_path(path, "path", min_points=2, n_dims=points.shape[1])
    lengths = segment_lengths(line)
    total = float(lengths.sum())
    if total <= 0.0:
        raise ValueError("path: has zero length")
    start = line[:-1]
    direction = np.diff(line, axis=0)
    len2 = lengths**2
    along = (points @ direction.T) - np.einsum("ij,ij->i", start, direction)
    u = np.clip(np.divide(along, len2, out=np.zeros_like(along), where=len2 > 0), 0.0, 1.0)
    closest = start[None] + u[:, :, None] * direction[None]
    dist2 = np.sum((points[:, None, :] - closest) ** 2, axis=2)  # (n, segments)
    matched = _monotone_assignment(dist2)
    rows = np.arange(len(points))
    s = (arc_length(line)[matched] + u[rows, matched] * lengths[matched]) / total
    return np.maximum.accumulate(np.clip(s, 0.0, 1.0))


def _monotone_assignment(cost: np.ndarray) -> np.ndarray:
    """Non-decreasing column per row minimising the summed ``cost[i, m_i]`` (dynamic programme)."""
    n, m = cost.shape
    columns = np.arange(m)
    back = np.empty((n, m), dtype=np.int32)
    total = cost[0].copy()
    for i in range(1, n):
        best = np.minimum.accumulate(total)
        # The last column attaining each running minimum: where a new minimum is set.
        back[i] = np.maximum.accumulate(np.where(total <= best, columns, 0))
        total = cost[i] + best
    out = np.empty(n, dtype=np.intp)
    out[-1] = int(np.argmin(total))
    for i in range(n - 1, 0, -1):
        out[i - 1] = back[i, out[i]]
    return out


def learn_timing(
    demos: Sequence[Any],
    times: Sequence[Any],
    path: Any,
    *,
    n_coefficients: int = 16,
) -> SpeedProfile:
    """The duration and speed profile of timed demonstrations (module notes).

    Parameters
    ----------
    demos : sequence of array_like, each (n_j, q)
        The demonstrations (at least one), units of ``path``.
    times : sequence of array_like, each (n_j,)
        Their sample times in seconds, finite and strictly increasing.
    path : array_like, shape (m, q)
        The path the demonstrations follow (the generalized path), along which
        their progress is measured (:func:`path_progress`).
    n_coefficients : int
        B-spline coefficients of the speed (6 to :data:`MAX_COEFFICIENTS`):
        fewer smooth more.

    Returns
    -------
    SpeedProfile
        ``source="demonstrations"``; ``duration`` the median demonstration's,
        ``demo_durations`` each one's.

    Warns
    -----
    UserWarning
        When a demonstration covers less than half of ``path`` (it is left out).

    Raises
    ------
    ValueError
        For NaN, infinite or non-increasing times (naming ``times[j]``), times
        that do not match their demonstration, durations outside 1e-6 to
        1e9 s, or when no demonstration covers half of ``path``.
    """
    demos = check_demos(demos, "demos", min_demos=1, min_points=3)
    stamps = check_times_list(times, demos, missing=False, style="shape")
    n_coefficients = check_count(
        n_coefficients, "n_coefficients", minimum=DEGREE + 2, maximum=MAX_COEFFICIENTS
    )
    phases = np.linspace(0.0, 1.0, _N_PHASES)
    curves, durations, partial = [], [], []
    for j, (demo, t) in enumerate(zip(demos, stamps, strict=True)):
        t = np.asarray(t, dtype=np.float64)
        duration = float(t[-1] - t[0])
        low, high = DURATION_RANGE
        if not low <= duration <= high:
            raise ValueError(
                f"times[{j}]: the demonstration lasts {duration:g} s; expected "
                f"{low:g} to {high:g} s"
            )
        keep = _thinned(len(demo))
        progress = path_progress(demo[keep], path)
        covered = progress[-1] - progress[0]
        if covered < _MIN_COVERAGE:
            partial.append(f"demos[{j}] covers {covered:.0%}")
            continue
        fraction = (progress - progress[0]) / covered
        curves.append(np.interp(phases, (t[keep] - t[0]) / duration, fraction))
        durations.append(duration)
    if partial:
        message = (
            f"{', '.join(partial)} of the path; a demonstration must cover at least "
            f"{_MIN_COVERAGE:.0%} of it to give its timing"
        )
        if not curves:
            raise ValueError(f"demos: {message}")
        warnings.warn(f"timing: left out {message}", UserWarning, stacklevel=2)
    median = np.median(np.array(curves), axis=0)
    coefficients = _fit_speed(phases, median, n_coefficients)
    return SpeedProfile(
        float(np.median(durations)), coefficients, "demonstrations", tuple(durations)
    )


def _fit_speed(phases: np.ndarray, progress: np.ndarray, n_coefficients: int) -> np.ndarray:
    """Non-negative B-spline coefficients of ``ν`` whose integral fits ``progress`` (at rest at
    both ends: the two first and two last coefficients zero), scaled so that ``σ(1) = 1``."""
    from scipy.interpolate import BSpline
    from scipy.optimize import nnls

    knots = _knots(n_coefficients)
    free = np.arange(2, n_coefficients - 2)
    basis = BSpline(knots, np.eye(n_coefficients)[:, free], DEGREE).antiderivative()
    design = basis(phases)  # (phases, free): σ(u) per unit coefficient
    ends = _END_WEIGHT * basis(np.array([1.0]))
    solution, _ = nnls(np.vstack([design, ends]), np.concatenate([progress, [_END_WEIGHT]]))
    coefficients = np.zeros(n_coefficients)
    coefficients[free] = solution
    reached = float(basis(1.0) @ solution)
    if not reached > 0.0:  # cannot happen for a progress curve rising from 0 to 1
        raise ValueError("times: the demonstrations' progress does not rise along the path")
    return coefficients / reached


# ------------------------------------------------------------------ helpers
def _phase(u: Any) -> np.ndarray:
    return np.clip(np.asarray(u, dtype=np.float64), 0.0, 1.0)


def phase_bisection(
    knots: np.ndarray,
    coefficients: np.ndarray,
    degree: int,
    total: float,
    steps: int,
    target: np.ndarray,
    out: np.ndarray,
) -> None:
    """NumPy form of ``_timing_kernels.phase_bisection``: ``σ⁻¹`` by bisection, into ``out``.

    ``σ`` is the progress B-spline (``knots``, ``coefficients``, ``degree``)
    over ``total``, its value at 1; ``target`` (n,) is clipped to [0, 1].
    Where ``ν`` is zero over an interval (a pause) the first phase is found.
    """
    progress = _Spline(knots, coefficients, degree)
    low, high = np.zeros_like(target), np.ones_like(target)
    for _ in range(steps):  # bisection of the non-decreasing σ: 2⁻⁵⁵ in u
        mid = 0.5 * (low + high)
        below = progress(_phase(mid)) / total < target
        low = np.where(below, mid, low)
        high = np.where(below, high, mid)
    out[:] = 0.5 * (low + high)
    out[target <= 0.0] = 0.0
    out[target >= 1.0] = 1.0


def _check_duration(duration: Any) -> float:
    """The one check of a given duration (seconds, within :data:`DURATION_RANGE`)."""
    value = check_positive(duration, "duration")
    low, high = DURATION_RANGE
    if not low <= value <= high:
        raise ValueError(f"duration: expected {low:g} to {high:g} s, got {value:g}")
    return value


def _fractions(points: np.ndarray) -> np.ndarray:
    """Arc-length fraction of each point, from 0 to 1."""
    lengths = segment_lengths(points)
    if np.any(lengths == 0.0):
        row = int(np.argmax(lengths == 0.0))
        raise ValueError(
            f"path: points {row} and {row + 1} coincide; a timed path needs distinct "
            "consecutive points (lfdkit.core.geometry.remove_repeated_points)"
        )
    along = np.concatenate([[0.0], np.cumsum(lengths)])
    if not along[-1] > 0.0:
        raise ValueError("path: has zero length")
    return along / along[-1]  # ends at 1.0 exactly: σ⁻¹ is steep at a rest-to-rest end


def _thinned(n: int) -> np.ndarray:
    """Indices of at most :data:`_MAX_MATCHED_SAMPLES` evenly spread samples, ends kept."""
    if n <= _MAX_MATCHED_SAMPLES:
        return np.arange(n)
    return np.unique(np.round(np.linspace(0, n - 1, _MAX_MATCHED_SAMPLES)).astype(np.intp))
