"""Discrete Dynamic Movement Primitive (thesis §3.3, Ijspeert et al.).

Formulation
-----------
One DMP moves all ``q`` dimensions with one shared phase. In the
*normalised time* ``s = t / (τ D)`` (``D`` the duration of the training
path, ``τ`` the temporal scaling; ``s`` runs from 0 to 1 over the movement)
each dimension obeys the thesis's critically damped transformation system
and canonical system (eq. 3.6, 3.8, 3.11)::

    y'' = k (g − y) − c y' + f(s),          Z' = −α Z,  Z(0) = 1,
    f(s) = M · Z Σᵢ wᵢ ψᵢ(Z) / Σᵢ ψᵢ(Z),     ψᵢ(Z) = exp(−hᵢ (Z − cᵢ)²),

where ``'`` is ``d/ds``. With ``τ D = 1`` this is the thesis's equation with
``τ = 1`` literally. Writing it in normalised time makes ``k``, ``c`` and
``α`` independent of how long the movement takes: the thesis's ``k = 156.25``,
``c = 25`` (critically damped, ``c² = 4k``) fit a 1 s and a 10 s path alike,
and ``τ`` rescales time only, never the path's shape (the thesis's eq. 3.6 uses
``τ`` as a mass, which would change the damping ratio with the duration).

``M`` maps the learned forcing to a new start ``y0`` and goal ``g``:

* ``scaling="per_dimension"`` (the thesis): ``M = diag((g − y0) / (g_d − y0_d))``,
  the thesis's factor ``(g − y0)`` over the training displacement. Exact for
  goals along the training displacement; but a dimension whose training
  displacement is (near) zero cannot be scaled, and one whose displacement
  changes sign mirrors the shape in that dimension only.
* ``scaling="spatial"``: ``M = σ R``, with ``R`` the smallest rotation taking
  the training start→goal direction onto the new one and ``σ`` the ratio of
  their lengths: the whole shape is rotated and scaled rigidly, so it never
  shears or mirrors. Use it when the task has no preferred axes (drawing,
  sweeping on a table, LASA shapes) or when a dimension of the training
  displacement is near zero; use ``per_dimension`` when the axes mean
  something (e.g. height must stay height) and goals move mainly along the
  training displacement. ``σ`` is the new displacement over the training
  one: for a nearly closed path (a short training displacement next to its
  extent) any new goal magnifies the shape and small goal changes turn it
  arbitrarily; it warns beyond ``σ = 10`` (as ``per_dimension`` does beyond a
  factor of 10) and refuses a closed path (start = goal) unless the new goal
  equals the new start.
* ``scaling="translate"``: ``M = I``, the shape is neither rotated nor
  scaled. The change of the start→goal vector,
  ``Δ = (g − y0) − (g_d − y0_d)``, drives a second, fixed forcing
  ``b(s) Δ`` with ``b = w'' + c w' + k (w − 1)``, ``w(s) = 10s³ − 15s⁴ + 6s⁵``
  (the minimum-jerk law; ``b = 0`` for ``s > 1``, continuously). Since
  ``χ = w − 1 + φ``, with ``φ(s) = e^{As}[0, 0]`` the spring's own decay from
  a unit start error, solves ``χ'' + c χ' + k χ = b`` from rest, the rollout
  from rest is exactly::

      y(s) = y_rep(s) + (1 − w(s)) (y0 − y0_d) + w(s) (g − g_d)

  the reproduction with the start offset faded out and the goal offset faded
  in along the movement. With minimum-jerk timing ``w`` is the fraction of the
  path's length travelled, so this is :func:`lfdkit.imitate.warp_path` of the
  reproduction. Every point moves by at most ``max(|y0 − y0_d|, |g − g_d|)``:
  the distortion is bounded by the offsets whatever the path, so closed paths
  (start = goal: loops, circles, figure-eights) and nearly closed ones, whose
  training start→goal vector is too short to define a rotation or a scale,
  are carried to any start and goal. It cannot turn a path towards a goal in
  another direction: a goal far off the training displacement shears the
  shape, which ``spatial`` rotates instead. Use it for closed and nearly
  closed paths and for starts and goals near the training ones: on held-out
  LASA demonstrations it lands as close as the warp of the Mean-Path (mean
  distance 1.070 mm against 1.068 mm, 182 folds; ``spatial`` 1.161 mm, and
  on the synthetic closed strokes 3 to 300 times the warp's; benchmark
  ``imitate.py`` section 5). Letting the spring alone absorb the offsets
  (``M = I`` without ``b``, the plain DMP) fades the start offset out as
  ``φ``, to 8 % by a third of the movement (21 % of the path's length with
  minimum-jerk timing): a kink near the start, and 40 % farther from
  held-out LASA demonstrations than the warp.

Learning (thesis eq. 3.13–3.14): the target forcing ``F = y_d'' − k (g_d − y_d)
+ c y_d'`` of the training path, with velocities and accelerations of an
interpolating cubic spline on a dense even grid (non-uniform times allowed;
with minimum-jerk timing, or a speed profile learned from timed
demonstrations (:mod:`lfdkit.imitate.timing`), the law is composed with a
spline in arc length exactly); weights by ridge-regularised linear least squares on the design
matrix ``X[t, i] = Z_t ψᵢ(Z_t) / Σⱼ ψⱼ(Z_t)``. The weights are stored in
absolute units (``weights_``); the thesis's ``wᵢ`` for its input ``u`` equal
``weights_ / (g_d − y0_d)``.

As the thesis states (§3.3), the forcing acts over the movement only:
``f = 0`` for ``s > 1`` (``t > τ D``), after which the spring alone pulls the
state to the goal.

With ``end="rest"`` (default) the least squares are solved subject to three
linear equality constraints per dimension: at ``s = 1`` the reproduction is at
the goal with zero velocity and zero forcing (so zero acceleration). Because
the rollout from rest is an affine map of the reproduction (see below), every
rollout then ends exactly at its goal, at rest, at ``t = τ D``, and stays
there. ``end="free"`` gives the thesis's plain least squares: its end point
misses the goal by the fit error at ``s = 1``, the acceleration jumps when the
forcing switches off, and the spring then converges to the goal. (Without the
switch-off, a path that ends at speed, like the thesis's equal time steps,
would drift by 8–10 % of its extent after the end.)

Choosing the number of basis functions
--------------------------------------
``n_basis="auto"`` fits the counts of :data:`BASIS_LADDER` (10, 15, 20, 30,
40, 60, 80, 100, 150, 200), smallest first, and keeps the first whose
reproduction error is at most ``basis_tol`` (default 1 %) of the path's
extent ``max_k ptp(path[:, k])``: the largest distance, at equal times over
the movement, between the reproduction and the training path
(``reproduction_error_``; the count kept is ``n_basis_``). At equal times
rather than closest points: it bounds the geometric distance, needs no
search, and does not depend on how coarsely the path is sampled. It costs
no rollout: the path obeys the transformation system exactly with its
target forcing ``F`` and the reproduction with ``X w``, so their difference
obeys ``e'' = −k e − c e' + (X w − F)`` from ``e(0) = 0``, ``e'(0) = −y_d'(0)``
(the reproduction starts at rest), which one IIR pass over the fitting grid
integrates exactly with the mismatch held linear between grid points (within
about 1 % of the error of an exact rollout). Each candidate is fitted exactly
as that integer ``n_basis`` is (same grid, design and constraints), so
``DMP(n_basis="auto")`` and ``DMP(n_basis=n_basis_)`` have the same weights.

The ladder grows by factors of 1.33 to 1.5: the count kept is at most about
1.5 times the smallest that would pass, in at most ten fits, and the error is
not monotone in the count (a path passing at 40 may fail at 60), which rules
out bisection. It starts at 10 (the default count; fewer rarely reproduce a
generalized path to 1 %) and stops at 200 (the Gram matrix costs
``20 n³`` operations, about 0.1 to 0.5 s at 200; an integer ``n_basis`` may be
up to :data:`~lfdkit.imitate.primitive.MAX_BASIS`, and a skill file stores the
fit, :meth:`DMP.to_state`): a path that needs more is noisy or has corners a
spring cannot follow. Then the count with the smallest error is kept and a
``RuntimeWarning`` says what to do. The error is time-aligned, so it counts lag too: with
``timing="uniform"`` the reproduction, which starts at rest, trails a path
that starts at full speed by 4 to 10 % of its extent whatever the count
(LASA), and ``"auto"`` warns. On the 182 leave-one-out Mean-Paths of the 26
single-motion LASA shapes (minimum-jerk timing) it keeps 15 to 200 (median
20; 20 misses 1 % on 84 of them), in a median 12.5 ms per fit against
8.5 ms for 20 basis functions on two cores (1.2 s for the one path that
needed 200). Smooth generalized paths of the thesis's tasks take 10 or 15.

Exact rollout
-------------
The transformation system is linear and its forcing a known function of ``s``.
Over a step ``h`` the state ``x = (y − g, y')`` moves exactly as::

    x(s + h) = e^{A h} x(s) + ∫₀ʰ e^{A (h − σ)} B f(s + σ) dσ,   A = [[0, 1], [−k, −c]]

The integral is evaluated by Gauss–Legendre quadrature (panels no longer than
half the basis spacing or 0.01, three or four nodes each: about 1e-13 of the
path's extent per unit time), so the discretisation is exact up to
quadrature error, with no Euler or Runge–Kutta truncation error at any step
size.

Two more facts make rollouts cheap. The response is linear in the initial
state and in the forcing, and the forcing is ``M`` times a fixed function of
``s``. So the learned forced response from rest is computed once per fit,
exactly as above, on knots a twelfth of a basis width apart (a linear
recursion run as a second-order IIR filter, :func:`scipy.signal.lfilter`),
and stored as a C² piecewise quintic through its positions, velocities and
accelerations (quintic Hermite interpolation; about 1e-11 of the path's
extent between knots). A rollout on any grid then evaluates that polynomial
and the closed-form ``e^{A s}``, and for any start, goal and initial velocity
is one matrix product; many goals at once are one larger product. In
particular, from rest ``y(s) = g + M (y_rep(s) − g_d)``: every new goal gets
an affine copy of the reproduction ``y_rep``. (With ``scaling="translate"``
the closed-form ``χ(s) Δ`` is one more column of that product, giving the
blend of the reproduction above.) :meth:`DMP.step` integrates each step
exactly with the quadrature, the forcing ``b`` included, and agrees with
:meth:`DMP.rollout` to about 1e-11 of the extent.
"""

from __future__ import annotations

import hashlib
import json
import warnings
from collections.abc import Mapping
from typing import Any, ClassVar, Literal, NamedTuple

import numpy as np

from lfdkit.core.constraints import OneOf
from lfdkit.core.estimator import not_fitted
from lfdkit.core.geometry import arc_length, path_length, segment_lengths
from lfdkit.core.options import SCALINGS, SKILL_DEFAULTS, TIMINGS
from lfdkit.core.validation import (
    MAX_POINTS,
    check_count,
    check_path,
    check_point,
    check_positive,
    check_times,
)
from lfdkit.imitate._dmp_numerics import (
    END_NODES,
    MAX_PANEL,
    basis,
    dense_sampler,
    evaluate_pieces,
    minimum_jerk_law,
    propagate,
    quadrature,
    quintic_pieces,
    remember,
    reproduction_departure,
    rotations_between,
    step_operators,
    transition,
)
from lfdkit.imitate.primitive import PRIMITIVE_DEFAULTS, Primitive, check_tau
from lfdkit.imitate.timing import DURATION_RANGE, SpeedProfile
from lfdkit.model.timed_path import TimedPath

__all__ = [
    "BASIS_LADDER",
    "DMP",
    "MAX_RELATIVE_MAGNITUDE",
    "MAX_ROLLOUT_SAMPLES",
    "STATE_VERSION",
    "minimum_jerk_times",
]

Scaling = Literal["translate", "spatial", "per_dimension"]
EndCondition = Literal["rest", "free"]
Timing = Literal["minimum_jerk", "uniform"]

_END_CONDITIONS = ("rest", "free")
#: A training displacement below this fraction of the path's extent counts as zero.
_ZERO_DISPLACEMENT = 1e-9
#: Per-dimension scale factors beyond this magnitude trigger a warning.
_LARGE_SCALE = 10.0
#: Basis counts ``n_basis="auto"`` tries, smallest first (module notes).
BASIS_LADDER = (10, 15, 20, 30, 40, 60, 80, 100, 150, 200)
#: Caps on what a caller may ask for (and :data:`~lfdkit.imitate.primitive.MAX_BASIS`),
#: so that a typo is an error naming the argument, not a MemoryError or an overflow.
#: Most samples of one rollout call (steps times rollouts).
MAX_ROLLOUT_SAMPLES = 10_000_000
#: Starts, goals and states farther than this many training scales from the
#: training path (and initial velocities that would carry that far in one
#: movement) are refused: the result would overflow or mean nothing.
MAX_RELATIVE_MAGNITUDE = 1e6
#: A step of :meth:`DMP.step` may span at most this many movement durations.
MAX_STEP_DURATIONS = 1e3
#: Version of :meth:`DMP.to_state`'s layout; :meth:`DMP.from_state` reads up to it.
STATE_VERSION = 1
#: The fields of a state, the checksum last; those that are arrays.
_STATE_FIELDS = (
    "version",
    "params",
    "n_basis",
    "alpha",
    "reproduction_error",
    "duration",
    "scale",
    "weights",
    "path",
    "times",
    "timing",
    "knots",
    "checksum",
)
_STATE_ARRAYS = ("path", "weights", "times", "knots")


def minimum_jerk_times(path: Any, duration: float = 1.0) -> np.ndarray:
    """Times at which a rest-to-rest minimum-jerk motion passes the path's points.

    The arc length ``ℓ(t)`` follows ``L (10 u³ − 15 u⁴ + 6 u⁵)``, ``u = t / T``:
    the motion starts and stops at rest, unlike the thesis's equal time steps
    (constant speed), which a DMP starting at rest cannot follow at the ends.

    Parameters
    ----------
    path : array_like, shape (n_points, q)
        Path with distinct consecutive points.
    duration : float
        Total time ``T`` in seconds.

    Returns
    -------
    ndarray, shape (n_points,)
        Strictly increasing times from 0 to ``duration``.
    """
    points = check_path(path, "path", min_points=2, min_dims=1)
    duration = check_positive(duration, "duration")
    _check_distinct(points)
    fraction = arc_length(points) / path_length(points)
    # Invert the monotone quintic 10u³ − 15u⁴ + 6u⁵ by bisection, vectorised.
    low, high = np.zeros_like(fraction), np.ones_like(fraction)
    for _ in range(60):
        mid = 0.5 * (low + high)
        below = minimum_jerk_law(mid)[0] < fraction
        low = np.where(below, mid, low)
        high = np.where(below, high, mid)
    times = 0.5 * (low + high) * duration
    times[0], times[-1] = 0.0, duration
    return times


class _Solution(NamedTuple):
    """Weights for one basis count, with the grid, target forcing and reproduction error."""

    n_basis: int
    weights: np.ndarray
    s: np.ndarray
    target: np.ndarray
    error: float


class DMP(Primitive):
    """Discrete Dynamic Movement Primitive with one phase shared by all dimensions.

    Parameters
    ----------
    n_basis : int or "auto", default "auto"
        Number of Gaussian basis functions (weights per dimension), 1 to
        :data:`~lfdkit.imitate.primitive.MAX_BASIS` (1000), or ``"auto"``: the smallest count of
        :data:`BASIS_LADDER` whose reproduction is within ``basis_tol`` of the
        path (module notes; the count chosen is ``n_basis_``). The thesis's 10
        is ``DMP(**THESIS_DMP)`` (:data:`lfdkit.core.options.THESIS_DMP`).
    k : float
        Spring constant, in units of the normalised time (see the module notes).
    c : float
        Damping; ``c = 2 sqrt(k)`` is critically damped (thesis: 156.25 and 25).
    alpha : float, optional
        Decay rate of the canonical system. Default ``ln 100`` (so ``Z`` falls
        to 0.01 at the end of the movement).
    tau : float
        Default temporal scaling of rollouts: 1 reproduces the training path's
        duration, 2 takes twice as long along the same path (1e-6 to 1e6).
    scaling : {"translate", "spatial", "per_dimension"}, default "translate"
        How the learned forcing is carried to a new start and goal (module
        notes). ``"translate"`` keeps the shape and works for closed and nearly
        closed paths, which the other two cannot stretch; the thesis's
        ``"per_dimension"`` is :data:`~lfdkit.core.options.THESIS_DMP`'s. The
        defaults are those :class:`lfdkit.skill.Skill` builds
        (:data:`~lfdkit.core.options.SKILL_DEFAULTS`), so a DMP used on its own
        behaves as inside a skill.
    end : {"rest", "free"}
        ``"rest"``: constrain the fit so every rollout ends at its goal at rest,
        with zero acceleration, at ``t = τ D``; ``"free"``: the thesis's
        unconstrained least squares.
    regularization : float
        Ridge term relative to the mean diagonal of ``XᵀX``; keeps the weights
        defined when basis functions outnumber or fall between samples.
    basis_tol : float
        With ``n_basis="auto"``: the largest reproduction error accepted, as a
        fraction of the path's extent (``0 < basis_tol <= 1``; default 1 %).
        Ignored for an integer ``n_basis``.

    Attributes
    ----------
    n_basis_ : int
        The number of basis functions used: ``n_basis``, or the count chosen
        when ``n_basis="auto"``.
    reproduction_error_ : float
        Largest distance, at equal times over the movement, between the
        reproduction (the rollout from the training start to the training
        goal) and the training path, as a fraction of the path's extent
        ``max_k ptp(path[:, k])``: what ``basis_tol`` bounds.
    weights_ : ndarray, shape (n_basis_, q)
        Forcing weights in absolute units (path units per normalised time²).
    centers_, widths_ : ndarray, shape (n_basis_,)
        Basis centres ``cᵢ`` in the phase ``Z`` (equally spaced in time) and
        widths ``hᵢ`` (neighbours cross at ``1/√2`` of their height).
    alpha_ : float
        The canonical decay rate used.
    start_, goal_ : ndarray, shape (q,)
        First and last point of the training path.
    duration_ : float
        Duration ``D`` of the training path in seconds.
    times_ : ndarray, shape (n_points,)
        Training times in seconds, starting at 0.
    timing_ : SpeedProfile or None
        The speed law the training times follow along the path's arc length
        (``timing`` over ``duration_``); None when ``times`` were given.
    path_ : ndarray, shape (n_points, q)
        The training path.
    forcing_times_ : ndarray, shape (n_fit,)
        Dense, even times (seconds) at which the target forcing was fitted.
    forcing_target_ : ndarray, shape (n_fit, q)
        The target forcing ``F`` of the training path at ``forcing_times_``.
    n_dims_ : int
        Dimension ``q``.
    """

    # The shared parameters are checked by Primitive's table first.
    _parameter_constraints: ClassVar[dict[str, Any]] = {
        "scaling": OneOf(SCALINGS),
        "end": OneOf(_END_CONDITIONS),
    }

    def __init__(
        self,
        n_basis: int | Literal["auto"] = PRIMITIVE_DEFAULTS["n_basis"],
        k: float = PRIMITIVE_DEFAULTS["k"],
        c: float = PRIMITIVE_DEFAULTS["c"],
        alpha: float | None = PRIMITIVE_DEFAULTS["alpha"],
        tau: float = PRIMITIVE_DEFAULTS["tau"],
        scaling: Scaling = SKILL_DEFAULTS["scaling"],
        end: EndCondition = "rest",
        regularization: float = PRIMITIVE_DEFAULTS["regularization"],
        basis_tol: float = PRIMITIVE_DEFAULTS["basis_tol"],
    ) -> None:
        super().__init__(
            n_basis=n_basis,
            k=k,
            c=c,
            alpha=alpha,
            tau=tau,
            regularization=regularization,
            basis_tol=basis_tol,
        )
        self.scaling = scaling
        self.end = end

    # ------------------------------------------------------------------ learning
    def _check_params(self) -> None:
        self._validate_params()
        self._check_rest_basis(self.end)

    def fit(
        self,
        path: Any,
        times: Any = None,
        *,
        duration: float | None = None,
        dt: float | None = None,
        timing: Timing | SpeedProfile = SKILL_DEFAULTS["timing"],
    ) -> DMP:
        """Learn the forcing weights from one path.

        Parameters
        ----------
        path : array_like, shape (n_points, q)
            The path to imitate, e.g. a generalized path from
            :class:`lfdkit.mimic.MeanPath` or :class:`lfdkit.mimic.GMR`.
            At least 3 points.
        times : array_like, shape (n_points,), optional
            Strictly increasing sample times in seconds (shifted to start at 0).
            Default: equal time steps over ``duration`` (the thesis's choice).
        duration : float, optional
            Total duration in seconds when ``times`` is not given (default 1).
        dt : float, optional
            Or the time step in seconds: the duration is ``dt * (n_points − 1)``.
        timing : {"minimum_jerk", "uniform"} or SpeedProfile, default "minimum_jerk"
            How times are assigned when ``times`` is not given (the default is
            the Skill's, :data:`~lfdkit.core.options.SKILL_DEFAULTS`). ``"uniform"``:
            equal steps (the thesis; with points equally spaced along the path
            this is constant speed, which a DMP starting at rest cannot follow
            at the ends). ``"minimum_jerk"``: :func:`minimum_jerk_times`, a
            rest-to-rest motion along the path, reproduced far more closely.
            A :class:`lfdkit.imitate.SpeedProfile` (e.g. learned from timed
            demonstrations by :func:`lfdkit.imitate.learn_timing`): the path is
            run along its arc length with that speed law, composed exactly as
            minimum jerk is, over ``duration`` (default the profile's own).

        Returns
        -------
        DMP
            ``self``.

        Warns
        -----
        RuntimeWarning
            With ``n_basis="auto"``, when no count of :data:`BASIS_LADDER`
            reproduces the path within ``basis_tol`` (the closest is kept).
        """
        self._check_params()
        points = check_path(path, "path", min_points=3, min_dims=1)
        n = points.shape[0]
        profile = timing if isinstance(timing, SpeedProfile) else None
        if profile is None and timing not in TIMINGS:
            raise ValueError(f"timing: expected one of {TIMINGS} or a SpeedProfile, got {timing!r}")
        if duration is not None and dt is not None:
            raise ValueError("dt: give either duration or dt, not both")
        if times is None:
            total = 1.0 if profile is None else profile.duration
            if duration is not None:
                total = check_positive(duration, "duration")
            if dt is not None:
                total = check_positive(dt, "dt") * (n - 1)
            if profile is not None:
                _check_distinct(points)
                t = profile.times(points, total)
            elif timing == "uniform":
                t = np.linspace(0.0, total, n)
            else:
                t = minimum_jerk_times(points, total)
        else:
            if duration is not None or dt is not None:
                raise ValueError("times: give either times or a duration/dt, not both")
            t = check_times(times, n, of="path", style="shape")
            t = t - t[0]
        span = float(t[-1])
        low, high = DURATION_RANGE
        if not low <= span <= high:
            raise ValueError(
                f"{'times' if times is not None else 'duration'}: the path must last "
                f"{low:g} to {high:g} s, got {span:g} s"
            )
        composed = times is None and timing != "uniform"
        law = minimum_jerk_law if profile is None else profile.law
        sample = dense_sampler(None if composed else t / span, points, law)
        start, goal = points[0].copy(), points[-1].copy()
        extent = float(np.max(np.ptp(points, axis=0)))
        self.alpha_ = self._phase_rate()
        if isinstance(self.n_basis, str):
            solution = self._choose_basis(sample, start, goal, extent)
        else:
            solution = self._solve(int(self.n_basis), sample, start, goal, extent)
        self.n_basis_ = solution.n_basis
        self.reproduction_error_ = solution.error
        self.weights_ = solution.weights
        self.start_, self.goal_ = start, goal
        self.duration_ = span
        self.times_ = t
        if times is not None:
            self.timing_ = None
        elif profile is not None:
            self.timing_ = profile.with_duration(span)
        else:
            self.timing_ = SpeedProfile.from_law(timing, span)
        self.path_ = points.copy()
        self.forcing_times_ = solution.s * span
        self.forcing_target_ = solution.target
        self.n_dims_ = points.shape[1]
        self._extent = extent
        # The scale against which absurd starts, goals and states are judged.
        self.scale_ = max(extent, float(np.max(np.abs(points))), 1e-300)
        self._knot_states = self._response_states()
        self._set_knots()
        return self

    def _set_knots(self) -> None:
        """The rollout's quintic pieces from :attr:`_knot_states`; empty caches."""
        states = self._knot_states
        spacing = 1.0 / (states.shape[0] - 1)
        self._knots = (
            spacing,
            quintic_pieces(states[:, 0], states[:, 1], states[:, 2], spacing),
        )
        self._grid_cache: dict[int, tuple[np.ndarray, ...]] = {}
        self._left_cache: dict[tuple[int, float, bool], np.ndarray] = {}
        self._step_cache: dict[float, tuple[np.ndarray, ...]] = {}

    # ------------------------------------------------------------------ state
    def to_state(self) -> dict[str, Any]:
        """What rollouts and steps need, as plain data: restored exactly by :meth:`from_state`.

        Returns
        -------
        dict
            ``version`` (:data:`STATE_VERSION`), ``params`` (:meth:`get_params`),
            ``n_basis``, ``alpha``, ``reproduction_error``, ``duration``,
            ``scale``, ``weights`` (n_basis_, q), ``path`` (n_points, q),
            ``times`` (n_points,), ``timing`` (:meth:`SpeedProfile.to_dict`
            or None), ``knots`` (n_knots, 3, q): the learned forced response
            from rest with its first two derivatives at the knots, and
            ``checksum``, a SHA-256 of all of them, so that a state edited or
            paired with another path is refused rather than planned with.
        """
        self._check_fitted()
        state = {
            "version": STATE_VERSION,
            "params": self.get_params(),
            "n_basis": int(self.n_basis_),
            "alpha": float(self.alpha_),
            "reproduction_error": float(self.reproduction_error_),
            "duration": float(self.duration_),
            "scale": float(self.scale_),
            "weights": self.weights_,
            "path": self.path_,
            "times": self.times_,
            "timing": None if self.timing_ is None else self.timing_.to_dict(),
            "knots": self._knot_states,
        }
        state["checksum"] = _state_checksum(state)
        return state

    @classmethod
    def from_state(cls, state: Mapping[str, Any], where: str = "dmp") -> DMP:
        """The fitted DMP of :meth:`to_state`, without refitting (rollouts equal to the bit).

        ``forcing_times_`` and ``forcing_target_`` (fit diagnostics) are None
        on a restored DMP; refit it for them.

        Raises
        ------
        ValueError
            One line starting with ``where``, for a state of a newer version,
            with a missing or malformed field, or whose checksum does not
            match its contents (edited, corrupted, or given another path).
        """
        version = state.get("version")
        if not isinstance(version, int) or isinstance(version, bool) or version < 1:
            raise ValueError(f"{where}.version: expected an integer >= 1, got {version!r}")
        if version > STATE_VERSION:
            raise ValueError(
                f"{where}.version: state version {version} is newer than this lfdkit reads "
                f"({STATE_VERSION}); upgrade lfdkit"
            )
        missing = [key for key in _STATE_FIELDS if key not in state]
        if missing:
            raise ValueError(f"{where}.{missing[0]}: missing field")
        state = dict(state)
        for key in _STATE_ARRAYS:
            try:
                state[key] = np.array(state[key], dtype=np.float64)
            except (TypeError, ValueError):
                raise ValueError(f"{where}.{key}: expected an array of numbers") from None
            if not np.all(np.isfinite(state[key])):
                raise ValueError(f"{where}.{key}: contains NaN or infinite values")
        for key in ("n_basis", "alpha", "reproduction_error", "duration", "scale"):
            value = state[key]
            kinds, low = ((int,), 1) if key == "n_basis" else ((int, float), 0)
            if isinstance(value, bool) or not isinstance(value, kinds) or not value >= low:
                raise ValueError(f"{where}.{key}: expected a number >= {low}, got {value!r}")
        if state["checksum"] != _state_checksum(state):
            raise ValueError(
                f"{where}: the stored DMP does not match its checksum (the file was edited or "
                "corrupted, or the path changed); remove the field to refit the DMP"
            )
        try:
            dmp = cls(**dict(state["params"]))
            dmp._check_params()
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{where}.params: {exc}") from None
        path, weights, times, knots = (state[key] for key in _STATE_ARRAYS)
        n_basis, alpha = state["n_basis"], float(state["alpha"])
        if path.ndim != 2 or path.shape[0] < 3 or times.shape != path.shape[:1]:
            raise ValueError(f"{where}.times: expected one time per path point")
        if weights.shape != (n_basis, path.shape[1]):
            raise ValueError(
                f"{where}.weights: expected shape ({n_basis}, {path.shape[1]}), got {weights.shape}"
            )
        dmp.alpha_ = alpha
        dmp._use_basis(int(n_basis))
        n_knots = int(np.ceil(4.0 / dmp._panel)) + 1
        if knots.shape != (n_knots, 3, path.shape[1]):
            raise ValueError(
                f"{where}.knots: expected shape ({n_knots}, 3, {path.shape[1]}), got {knots.shape}"
            )
        dmp.n_basis_ = int(n_basis)
        dmp.reproduction_error_ = float(state["reproduction_error"])
        dmp.weights_ = weights
        dmp.start_, dmp.goal_ = path[0].copy(), path[-1].copy()
        dmp.duration_ = float(state["duration"])
        dmp.times_ = times
        timing = state["timing"]
        dmp.timing_ = None if timing is None else SpeedProfile.from_dict(timing, f"{where}.timing")
        dmp.path_ = path
        dmp.forcing_times_ = None
        dmp.forcing_target_ = None
        dmp.n_dims_ = path.shape[1]
        dmp._extent = float(np.max(np.ptp(path, axis=0)))
        dmp.scale_ = float(state["scale"])
        dmp._knot_states = knots
        dmp._set_knots()
        return dmp

    def _use_basis(self, n_basis: int) -> None:
        """Set the basis functions and the quadrature panel for ``n_basis`` of them."""
        self.centers_, self.widths_ = basis(n_basis, self.alpha_)
        # Quadrature panels resolve the narrowest basis function (spacing 1/(n−1) in s).
        self._panel = min(MAX_PANEL, 0.5 / max(n_basis - 1, 1))

    def _solve(
        self,
        n_basis: int,
        sample: Any,
        start: np.ndarray,
        goal: np.ndarray,
        extent: float,
    ) -> _Solution:
        """Weights for ``n_basis`` basis functions and the reproduction error they give.

        ``sample(n_basis)`` returns the dense grid, positions and derivatives
        (:func:`_dense_sampler`). Leaves the basis of ``n_basis`` in place.
        """
        s, positions, velocity, acceleration = sample(n_basis)
        target = acceleration - self.k * (goal - positions) + self.c * velocity
        self._use_basis(n_basis)
        design = self._design(s)
        gram = design.T @ design
        ridge = float(self.regularization) * max(float(np.mean(np.diag(gram))), 1e-300)
        gram[np.diag_indices_from(gram)] += ridge
        rhs = design.T @ target
        from scipy import linalg  # here: lfdkit.imitate loads fast

        if self.end == "rest":
            # At s = 1: y = g and y' = 0 (the state), and f = 0 so y'' = 0 too.
            constraint = np.vstack([self._end_response(), self._design(np.array([1.0]))])
            homogeneous = transition(self.k, self.c, np.array([1.0]))[:, 0, 0]
            wanted = np.vstack([-np.outer(homogeneous, start - goal), np.zeros((1, start.size))])
            m, n_constraints = gram.shape[0], constraint.shape[0]
            kkt = np.zeros((m + n_constraints, m + n_constraints))
            kkt[:m, :m], kkt[:m, m:], kkt[m:, :m] = gram, constraint.T, constraint
            solution = linalg.solve(kkt, np.vstack([rhs, wanted]), assume_a="sym")
            weights = solution[:m]
        else:
            weights = linalg.solve(gram, rhs, assume_a="pos")
        if not np.all(np.isfinite(weights)):
            raise ValueError(
                "path: the least-squares problem for the weights is singular; "
                "raise regularization or lower n_basis"
            )
        # The reproduction departs from the path as the spring filters the forcing
        # residual (module notes): one IIR pass on the grid, no rollout needed.
        departure = reproduction_departure(
            self.k, self.c, s, velocity[0], design @ weights - target
        )
        error = float(np.max(np.linalg.norm(departure, axis=1))) / max(extent, 1e-300)
        return _Solution(n_basis, weights, s, target, error)

    def _choose_basis(
        self, sample: Any, start: np.ndarray, goal: np.ndarray, extent: float
    ) -> _Solution:
        """``n_basis="auto"``: the first count of :data:`BASIS_LADDER` within ``basis_tol``."""
        tol = float(self.basis_tol)
        best = None
        for n_basis in BASIS_LADDER:
            solution = self._solve(n_basis, sample, start, goal, extent)
            if solution.error <= tol:
                return solution
            if best is None or solution.error < best.error:
                best = solution
        warnings.warn(
            f"n_basis='auto': no count up to {BASIS_LADDER[-1]} reproduces the path within "
            f"basis_tol={tol:g} of its extent; kept the closest, {best.n_basis} basis "
            f"functions ({best.error:.2%} of the extent). Raise basis_tol, fit with "
            "timing='minimum_jerk' (a path timed at constant speed cannot be followed from "
            "rest), or smooth the path (lfdkit.core.geometry.smooth_path) if it is noisy or has "
            "sharp corners",
            RuntimeWarning,
            stacklevel=3,
        )
        self._use_basis(best.n_basis)
        return best

    def _response_states(self) -> np.ndarray:
        """The forced response, exact, on knots a quarter quadrature panel apart.

        Position, velocity and acceleration (from the ODE) at each knot, shape
        (n_knots, 3, q), define a quintic Hermite interpolant whose error,
        about ``(Δ/σ)⁶ / 46080`` for a basis of width ``σ`` at knot spacing
        ``Δ = σ/12``, is near 1e-11 of the response: a rollout on any grid
        then costs a polynomial evaluation, not a new integration.
        """
        n_knots = int(np.ceil(4.0 / self._panel)) + 1
        states = self._forced_response(n_knots)
        knots = np.linspace(0.0, 1.0, n_knots)
        forcing = self._design(knots) @ self.weights_
        curvature = -self.k * states[:, 0] - self.c * states[:, 1] + forcing
        return np.concatenate([states, curvature[:, None, :]], axis=1)

    def _check_fitted(self) -> None:
        # sklearn's check_is_fitted scans every attribute: too slow for a 100 µs rollout.
        if not hasattr(self, "weights_"):
            raise not_fitted("This DMP instance is not fitted yet; call fit(path) first")

    def _design(self, s: np.ndarray) -> np.ndarray:
        """Design matrix ``X[t, i] = Z ψᵢ(Z) / Σ ψ(Z)``, shape (len(s), n_basis)."""
        phase = np.exp(-self.alpha_ * s)
        psi = np.exp(-self.widths_ * (phase[:, None] - self.centers_) ** 2)
        total = psi.sum(axis=1, keepdims=True)
        # Far outside every basis the Gaussians underflow; the nearest one takes over.
        empty = total[:, 0] < 1e-300
        if np.any(empty):
            nearest = np.argmin(np.abs(phase[empty, None] - self.centers_), axis=1)
            psi[empty] = 0.0
            psi[np.flatnonzero(empty), nearest] = 1.0
            total[empty] = 1.0
        design = psi * (phase / total[:, 0])[:, None]
        # Thesis §3.3: the input is active over the movement only, u(t) = 0 for t > T.
        design[s > 1.0 + 1e-12] = 0.0
        return design

    def _end_response(self) -> np.ndarray:
        """State at ``s = 1`` driven by each basis forcing from rest, shape (2, n_basis)."""
        nodes, weights = quadrature(1.0, 0.5 * self._panel, END_NODES)
        kernels = transition(self.k, self.c, 1.0 - nodes)[:, 1, :].T
        return (kernels * weights[:, None]).T @ self._design(nodes)

    def forcing(self, times: Any) -> np.ndarray:
        """Learned forcing in the training frame at the given training-path times.

        Parameters
        ----------
        times : array_like, shape (n,)
            Times in seconds along the training path (``0 … duration_``; later
            times give the decaying tail).

        Returns
        -------
        ndarray, shape (n, q)
            ``Z Σ wᵢ ψᵢ / Σ ψᵢ`` in path units per normalised time².
        """
        self._check_fitted()
        t = np.atleast_1d(np.asarray(times, dtype=np.float64))
        if t.ndim != 1 or not np.all(np.isfinite(t)):
            raise ValueError("times: expected a 1-D array of finite values")
        return self._design(t / self.duration_) @ self.weights_

    # --------------------------------------------------------------- retargeting
    def scale_matrix(self, start: Any = None, goal: Any = None) -> np.ndarray:
        """Linear map ``M`` carrying the learned forcing to a new start and goal.

        With ``scaling="translate"`` this is the identity; the start and goal
        offsets then enter through the blend of the module notes, not ``M``.

        Parameters
        ----------
        start, goal : array_like, shape (q,) or (n_rollouts, q), optional
            Default: the training path's start and goal.

        Returns
        -------
        ndarray, shape (q, q) or (n_rollouts, q, q)
        """
        self._check_fitted()
        starts, goals, batch = self._starts_goals(start, goal)
        matrices = self._scale_matrices(starts, goals)
        return matrices if batch else matrices[0]

    def _starts_goals(
        self, start: Any, goal: Any, check_input: bool = True
    ) -> tuple[np.ndarray, np.ndarray, bool]:
        arrays = []
        for value, name, default in ((start, "start", self.start_), (goal, "goal", self.goal_)):
            if value is None:
                arrays.append(default)
            elif check_input:
                arrays.append(self._check_position(value, name))
            else:
                arrays.append(self._within_reach(np.asarray(value), name))
        batch = arrays[0].ndim == 2 or arrays[1].ndim == 2
        starts, goals = (np.atleast_2d(a) for a in arrays)
        if starts.shape[0] != goals.shape[0] and 1 not in (starts.shape[0], goals.shape[0]):
            raise ValueError(
                f"start, goal: {starts.shape[0]} starts and {goals.shape[0]} goals do not match"
            )
        starts, goals = np.broadcast_arrays(starts, goals)
        return starts, goals, batch

    def _check_position(self, value: Any, name: str) -> np.ndarray:
        """A finite state of shape (q,) or (n, q) within reach of the training scale."""
        return self._within_reach(check_point(value, name, self.n_dims_, batch="n_rollouts"), name)

    def _within_reach(self, arr: np.ndarray, name: str) -> np.ndarray:
        """``arr`` (finite positions) if within reach of the training scale; else refused."""
        limit = MAX_RELATIVE_MAGNITUDE * getattr(self, "scale_", _training_scale(self.path_))
        if np.max(np.abs(arr), initial=0.0) > limit:
            raise ValueError(
                f"{name}: {np.max(np.abs(arr)):.3g} is beyond {MAX_RELATIVE_MAGNITUDE:g} times "
                f"the training path's scale ({limit:.3g}); the result would overflow"
            )
        return arr

    def _check_velocity(self, value: Any, name: str, time_scale: float) -> np.ndarray:
        """A finite velocity that does not carry past the position bound in one movement."""
        arr = check_point(value, name, self.n_dims_, batch="n_rollouts")
        limit = MAX_RELATIVE_MAGNITUDE * getattr(self, "scale_", _training_scale(self.path_))
        if np.max(np.abs(arr), initial=0.0) * time_scale > limit:
            raise ValueError(
                f"{name}: {np.max(np.abs(arr)):.3g} units/s would carry beyond "
                f"{MAX_RELATIVE_MAGNITUDE:g} times the training path's scale within the "
                f"movement ({time_scale:.3g} s); the result would overflow"
            )
        return arr

    def _scale_matrices(self, starts: np.ndarray, goals: np.ndarray) -> np.ndarray:
        trained = self.goal_ - self.start_
        wanted = goals - starts
        tiny = _ZERO_DISPLACEMENT * max(self._extent, 1e-300)
        n_rollouts, q = wanted.shape
        if self.scaling == "translate":
            return np.broadcast_to(np.eye(q), (n_rollouts, q, q)).copy()
        if self.scaling == "per_dimension":
            flat = np.abs(trained) <= tiny
            ratio = np.ones_like(wanted)
            np.divide(wanted, trained, out=ratio, where=~flat[None, :])
            moved = flat[None, :] & (np.abs(wanted) > tiny)
            if np.any(moved):
                dim = int(np.argwhere(moved)[0, 1])
                raise ValueError(
                    f"goal: per-dimension scaling cannot move dimension {dim}: the training "
                    "path starts and ends at the same value there (displacement 0); "
                    "use scaling='spatial' (or 'translate' to keep the shape)"
                )
            largest = np.unravel_index(np.argmax(np.abs(ratio)), ratio.shape)
            if abs(ratio[largest]) > _LARGE_SCALE:
                count = int(np.count_nonzero(np.any(np.abs(ratio) > _LARGE_SCALE, axis=1)))
                warnings.warn(
                    f"per-dimension scaling multiplies the shape of dimension {largest[1]} by "
                    f"{ratio[largest]:.3g} ({count} of {n_rollouts} rollouts beyond "
                    f"±{_LARGE_SCALE:g}): its training displacement is small; "
                    "scaling='spatial' keeps the shape",
                    RuntimeWarning,
                    stacklevel=3,
                )
            return ratio[:, :, None] * np.eye(q)[None]
        length = float(np.linalg.norm(trained))
        if length <= tiny:
            if np.any(np.linalg.norm(wanted, axis=1) > tiny):
                raise ValueError(
                    "goal: the training path starts and ends at the same point, so its "
                    "shape has no start→goal direction to rotate and scale; a closed "
                    "movement can only be moved (give goal equal to start), or use "
                    "scaling='translate', which keeps the shape for any start and goal"
                )
            # A closed movement to a closed goal: translate it.
            return np.broadcast_to(np.eye(q), (n_rollouts, q, q)).copy()
        norms = np.linalg.norm(wanted, axis=1)
        still = norms <= tiny
        directions = wanted / np.where(still, 1.0, norms)[:, None]
        directions[still] = trained / length  # any rotation: the scale is 0
        matrices = rotations_between(trained / length, directions)
        sigma = np.where(still, 0.0, norms / length)
        matrices *= sigma[:, None, None]
        if np.max(sigma) > _LARGE_SCALE:
            count = int(np.count_nonzero(sigma > _LARGE_SCALE))
            warnings.warn(
                f"spatial scaling magnifies the shape {np.max(sigma):.3g} times ({count} of "
                f"{n_rollouts} rollouts beyond {_LARGE_SCALE:g}): the training start→goal "
                f"displacement ({length:.3g}) is short next to the path's extent "
                f"({self._extent:.3g}); scaling='translate' keeps the shape",
                RuntimeWarning,
                stacklevel=3,
            )
        return matrices

    def _offsets(self, starts: np.ndarray, goals: np.ndarray) -> np.ndarray | None:
        """``scaling="translate"``: the change of the start→goal vector, (n_rollouts, q).

        ``None`` for the other scalings, whose ``M`` already maps the training
        start→goal vector onto the new one.
        """
        if self.scaling != "translate":
            return None
        return (goals - starts) - (self.goal_ - self.start_)

    # ------------------------------------------------------------------- rollout
    def _grid(self, n_steps: int) -> tuple[np.ndarray, ...]:
        """Cached pieces of the exact solution on ``n_steps`` equal steps over ``s ∈ [0, 1]``.

        Returns ``s`` (n,), transition powers ``e^{A s_j}`` (2, 2, n) and the
        learned forced response from rest with its first two derivatives (q, 3, n).
        """
        cached = self._grid_cache.get(n_steps)
        if cached is not None:
            return cached
        s = np.linspace(0.0, 1.0, n_steps)
        forced = evaluate_pieces(s, *self._knots)
        powers = transition(self.k, self.c, s)
        pieces = (s, powers, forced)
        remember(self._grid_cache, n_steps, pieces)
        return pieces

    def _forced_response(self, n_steps: int) -> np.ndarray:
        """Learned forced response from rest on ``n_steps`` equal steps of ``s ∈ [0, 1]``.

        Exact propagation (module notes), shape (n_steps, 2, q): position and
        its derivative in normalised time.
        """
        s = np.linspace(0.0, 1.0, n_steps)
        phi, nodes, gamma = step_operators(self.k, self.c, s[1], self._panel)
        node_times = (s[:-1, None] + nodes[None, :]).ravel()
        node_forcing = (self._design(node_times) @ self.weights_).reshape(
            n_steps - 1, nodes.size, self.n_dims_
        )
        inputs = np.einsum("mk,jmq->jkq", gamma, node_forcing)
        return propagate(phi, np.zeros((2, self.n_dims_)), inputs)

    def rollout(
        self,
        start: Any = None,
        goal: Any = None,
        tau: float | None = None,
        n_steps: int | None = None,
        *,
        start_velocity: Any = None,
        check_input: bool = True,
    ) -> TimedPath:
        """Run the DMP from ``start`` to ``goal``, exactly (module notes), for one or many goals.

        Parameters
        ----------
        start, goal : array_like, shape (q,) or (n_rollouts, q), optional
            Start and goal; default the training path's. Either may hold many
            rows, the other is broadcast: one call then returns a batch.
        tau : float, optional
            Temporal scaling (default ``self.tau``): the movement lasts
            ``tau * duration_`` seconds.
        n_steps : int, optional
            Samples over the movement, ends included (default: as many as the
            training path; at least 2).
        start_velocity : array_like, shape (q,) or (n_rollouts, q), optional
            Initial velocity in units per second (default at rest).
        check_input : bool
            False skips checking the form of ``start`` and ``goal``: for a caller
            that has validated them already (float arrays of shape (q,) or
            (n_rollouts, q), finite), such as :class:`lfdkit.skill.Skill`. Their
            bounds below still apply. Do not use it for anything else.

        Raises
        ------
        ValueError
            For NaN/inf, a start or goal beyond :data:`MAX_RELATIVE_MAGNITUDE`
            times the training path's scale (its extent or largest coordinate)
            or a velocity that would carry that far in one movement, ``n_steps``
            above 1,000,000, more than :data:`MAX_ROLLOUT_SAMPLES` samples in
            all, or ``tau`` outside 1e-6 to 1e6: the result would overflow or
            not fit in memory.

        Returns
        -------
        TimedPath
            ``times`` (n_steps,) in seconds; positions, velocities and
            accelerations of shape (n_steps, q), or (n_rollouts, n_steps, q)
            when ``start`` or ``goal`` is 2-D.
        """
        self._check_fitted()
        tau = check_tau(self.tau if tau is None else tau)
        n_steps = self.path_.shape[0] if n_steps is None else n_steps
        n_steps = check_positive(n_steps, "n_steps", integer=True)
        if n_steps < 2:
            raise ValueError(f"n_steps: needs at least 2 samples, got {n_steps}")
        check_count(n_steps, "n_steps", minimum=2, maximum=MAX_POINTS)
        starts, goals, batch = self._starts_goals(start, goal, check_input)
        time_scale = tau * self.duration_
        velocity = np.zeros(self.n_dims_)
        if start_velocity is not None:
            velocity = self._check_velocity(start_velocity, "start_velocity", time_scale)
            batch = batch or velocity.ndim == 2
        velocity = np.atleast_2d(velocity)
        if velocity.shape[0] not in (1, starts.shape[0]) and starts.shape[0] != 1:
            raise ValueError(
                f"start_velocity: {velocity.shape[0]} rows do not match "
                f"{starts.shape[0]} starts/goals"
            )
        starts, goals, velocity = np.broadcast_arrays(starts, goals, velocity)
        if n_steps * starts.shape[0] > MAX_ROLLOUT_SAMPLES:
            raise ValueError(
                f"n_steps: {n_steps:,} steps for {starts.shape[0]:,} rollouts exceed "
                f"{MAX_ROLLOUT_SAMPLES:,} samples in one call; split the batch"
            )
        x0 = np.stack([starts - goals, velocity * time_scale], axis=1)  # (r, 2, q)
        matrices = self._scale_matrices(starts, goals)
        offsets = self._offsets(starts, goals)
        s = np.linspace(0.0, 1.0, n_steps)
        n_rollouts, q = starts.shape
        # Everything is linear in (x0, M, g): one matrix product gives positions,
        # velocities and accelerations for every rollout at once. Columns are
        # (rollout, dimension) pairs; memory traffic, not arithmetic, is the cost.
        blocks = [
            x0.transpose(1, 0, 2).reshape(2, n_rollouts * q),
            matrices.transpose(2, 0, 1).reshape(q, n_rollouts * q),
            goals.reshape(1, n_rollouts * q),
        ]
        if offsets is not None:
            blocks.append(offsets.reshape(1, n_rollouts * q))
        right = np.concatenate(blocks)
        left = self._rollout_coefficients(n_steps, time_scale, offsets is not None)
        columns = (left @ right).reshape(3, n_steps, n_rollouts, q)
        # (rollout, step, dimension) views of the (step, rollout, dimension) blocks.
        positions, velocities, accelerations = columns.transpose(0, 2, 1, 3)
        times = s * time_scale
        if not batch:
            return TimedPath(times, positions[0], velocities[0], accelerations=accelerations[0])
        return TimedPath(times, positions, velocities, accelerations=accelerations)

    def _rollout_coefficients(self, n_steps: int, time_scale: float, blend: bool) -> np.ndarray:
        """Left factor of the rollout product, shape (3 n_steps, 3 + q) or (…, 4 + q).

        Rows: position, velocity and acceleration blocks; columns multiply the
        initial state (2), the forcing map ``M`` (q), the goal (1) and, with
        ``blend`` (``scaling="translate"``), the change of the start→goal
        vector (1): its response ``χ = w − 1 + φ`` (module notes).
        """
        key = (n_steps, time_scale, blend)
        cached = self._left_cache.get(key)
        if cached is not None:
            return cached
        s, powers, forced = self._grid(n_steps)
        q, n = self.n_dims_, n_steps
        # Built transposed, one contiguous row per column of the product.
        columns = np.empty((3 + q + blend, 3, n))
        columns[:2, 0] = powers[0]  # e^{As} applied to (y0 − g, y0')
        columns[:2, 1] = powers[1]
        # d/ds e^{As} = A e^{As}: the homogeneous acceleration is its second row.
        columns[:2, 2] = -self.k * powers[0] - self.c * powers[1]
        columns[2 : 2 + q] = forced
        columns[2 + q] = 0.0
        columns[2 + q, 0] = 1.0  # position = goal + error
        if blend:
            # φ = e^{As}[0, 0], the response to a unit start error: χ = w − 1 + φ.
            columns[-1] = minimum_jerk_law(s)
            columns[-1, 0] -= 1.0
            columns[-1] += columns[0]  # (φ, φ', φ'')
        columns[:, 1] /= time_scale
        columns[:, 2] /= time_scale**2
        left = columns.reshape(3 + q + blend, 3 * n).T
        remember(self._left_cache, key, left)
        return left

    def step(
        self,
        t: float,
        position: Any,
        velocity: Any,
        dt: float,
        *,
        start: Any = None,
        goal: Any = None,
        tau: float | None = None,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Advance a (possibly perturbed) state by one exact step, for online use.

        The phase is the elapsed time ``t``; the state is whatever the robot is
        at, so a push is absorbed and the motion pulled back to the path and on
        to the goal. Steps of ``duration·tau / (n_steps − 1)`` from the start at
        rest reproduce :meth:`rollout` to round-off.

        Parameters
        ----------
        t : float
            Time since the movement started, in seconds (``>= 0``).
        position, velocity : array_like, shape (q,) or (n_rollouts, q)
            Current state, units and units per second.
        dt : float
            Step in seconds (``> 0``).
        start, goal : array_like, shape (q,) or (n_rollouts, q), optional
            Start the movement began from (it sets the forcing's scale) and goal.
        tau : float, optional
            Temporal scaling (default ``self.tau``).

        Returns
        -------
        position, velocity, acceleration : ndarray, shape like ``position``
            The state at ``t + dt`` and its acceleration.

        Raises
        ------
        ValueError
            For the absurd arguments :meth:`rollout` refuses, and a ``dt`` of
            more than :data:`MAX_STEP_DURATIONS` movement durations.
        """
        self._check_fitted()
        tau = check_tau(self.tau if tau is None else tau)
        time_scale = tau * self.duration_
        dt = check_positive(dt, "dt")
        if dt > MAX_STEP_DURATIONS * time_scale:
            raise ValueError(
                f"dt: {dt:g} s is more than {MAX_STEP_DURATIONS:g} movement durations "
                f"({time_scale:g} s each)"
            )
        t = check_positive(t, "t", allow_zero=True)
        starts, goals, _ = self._starts_goals(start, goal)
        pos = self._check_position(position, "position")
        vel = self._check_velocity(velocity, "velocity", time_scale)
        single = pos.ndim == 1 and vel.ndim == 1 and starts.shape[0] == 1
        pos, vel = np.atleast_2d(pos), np.atleast_2d(vel)
        matrices = self._scale_matrices(starts, goals)
        offsets = self._offsets(starts, goals)
        x = np.stack([pos - goals, vel * time_scale], axis=1)  # (r, 2, q)
        s_now, s_next = t / time_scale, (t + dt) / time_scale
        # The forcing switches off at s = 1: never integrate across the switch.
        for s_from, s_to in (
            ((s_now, 1.0), (1.0, s_next)) if s_now < 1.0 < s_next else ((s_now, s_next),)
        ):
            x = self._advance(x, s_from, s_to - s_from, matrices, offsets)
        forcing_end = self._design(np.array([s_next])) @ self.weights_
        acceleration = (
            -self.k * x[:, 0] - self.c * x[:, 1] + np.einsum("p,rqp->rq", forcing_end[0], matrices)
        )
        if offsets is not None:
            acceleration += self._blend_forcing(np.array([s_next]))[0] * offsets
        new_pos = x[:, 0] + goals
        new_vel = x[:, 1] / time_scale
        new_acc = acceleration / time_scale**2
        if single:
            return new_pos[0], new_vel[0], new_acc[0]
        return new_pos, new_vel, new_acc

    def _blend_forcing(self, s: np.ndarray) -> np.ndarray:
        """``b(s) = w'' + c w' + k (w − 1)``, zero after the movement (module notes), (len(s),).

        The forcing per unit change of the start→goal vector under
        ``scaling="translate"``: it makes the response ``χ = w − 1 + φ``.
        """
        w, slope, bend = minimum_jerk_law(np.minimum(s, 1.0))
        return np.where(s > 1.0 + 1e-12, 0.0, bend + self.c * slope + self.k * (w - 1.0))

    def _advance(
        self,
        x: np.ndarray,
        s: float,
        h: float,
        matrices: np.ndarray,
        offsets: np.ndarray | None = None,
    ) -> np.ndarray:
        """Exact step of the state ``x`` (r, 2, q) from normalised time ``s`` by ``h``.

        ``offsets`` (r, q): the change of the start→goal vector under
        ``scaling="translate"``, driving :meth:`_blend_forcing`.
        """
        if s >= 1.0:
            # No forcing after the movement: the spring alone, no quadrature (whose
            # panels would grow with a long step).
            phi = transition(self.k, self.c, np.array([h]))[:, :, 0]
            return np.einsum("ab,rbq->raq", phi, x)
        operators = self._step_cache.get(h)
        if operators is None:
            operators = step_operators(self.k, self.c, h, self._panel)
            remember(self._step_cache, h, operators)
        phi, nodes, gamma = operators
        forcing_nodes = self._design(s + nodes) @ self.weights_  # (m, q)
        drive = np.einsum("mk,mp,rqp->rkq", gamma, forcing_nodes, matrices)
        if offsets is not None:
            drive += np.einsum("mk,m,rq->rkq", gamma, self._blend_forcing(s + nodes), offsets)
        return np.einsum("ab,rbq->raq", phi, x) + drive


def _state_checksum(state: Mapping[str, Any]) -> str:
    """SHA-256 over a state's fields (arrays as little-endian float64 bytes), hex."""
    digest = hashlib.sha256()
    try:
        for key in _STATE_FIELDS[:-1]:
            value = state[key]
            if key in _STATE_ARRAYS:
                array = np.ascontiguousarray(value, dtype="<f8")
                digest.update(repr(array.shape).encode() + array.tobytes())
            else:
                plain = json.dumps(value, sort_keys=True, default=_plain_number)
                digest.update(plain.encode())
            digest.update(b"|")
    except (TypeError, ValueError):
        return ""  # not numbers where numbers belong: matches no checksum
    return digest.hexdigest()


def _plain_number(value: Any) -> Any:
    """A NumPy scalar as the Python number JSON writes (for :func:`_state_checksum`)."""
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"{type(value).__name__} is not JSON data")


def _check_distinct(points: np.ndarray) -> None:
    steps = segment_lengths(points)
    if np.any(steps == 0.0):
        row = int(np.argmax(steps == 0.0))
        raise ValueError(
            f"path: points {row} and {row + 1} coincide; remove repeated points "
            "(lfdkit.core.geometry.remove_repeated_points) or give times"
        )


def _training_scale(path: np.ndarray) -> float:
    return max(float(np.max(np.ptp(path, axis=0))), float(np.max(np.abs(path))), 1e-300)
