"""The planning problem shared by the planner and the inverse optimal control (thesis §5.4).

Coordinates
-----------
A plan moves along a nominal path at constant speed: the ``k``-th planned
point lies on the normal of the ``k``-th nominal point,

    x_k = x_k^N + N_kᵀ d_k,

with ``N_k`` (m, q), ``m = q − 1``, the orthonormal normals of the nominal
(:class:`Corridor`; the left normal in 2-D) and ``d_k`` the lateral offset.
The start offset ``d_0`` is fixed; the unknowns are ``d_1 … d_{K−1}``, linked
by the actions ``a_k = d_k − d_{k−1}`` in the box ``|a_k| ≤ max_step`` per
component.

Cost
----
The cost of offsets ``d`` (n, m), ``n = K − 1``, is the negative reward
(:class:`lfdkit.emulate.Reward`) summed over the points,

    Σ_k Q_k |d_k|² + Σ_{k,o} exp(−(x_k − O_o)ᵀ P_o (x_k − O_o)),

with ``Q_k`` the nominal weight (``Q``, ramped up towards the goal when a plan
must reach it: :func:`goal_weights`) and, for obstacles with a hard radius,
the clearance barrier of :mod:`lfdkit.emulate.planner`. A reward with a
swerve (issue 26) moves each point's ``O_o`` along the path
(:func:`swerve_shifts`), a constant per point and obstacle: the terms keep
their form, only their precomputed coefficients change, and without a swerve
nothing is computed for it. :class:`Problem`
precomputes the obstacle terms once per scene, so every evaluation is a few
element-wise operations; :meth:`Problem.solve` is the compiled projected
Newton solver (:mod:`._problem_kernels`) that the planner polishes its starts
with and the IOC differentiates. :meth:`Problem.cost` and
:meth:`Problem.derivatives` are the same cost in NumPy (without the barrier):
the readable reference that tests and the SciPy benchmark use, held to the
compiled kernel by ``tests/emulate/test_problem.py``.

Validation
----------
Nothing here validates what :func:`lfdkit.emulate.plan_path` and
:meth:`lfdkit.emulate.IOC.fit` have validated where the data entered; a
:class:`Corridor` validates its nominal path, :meth:`Problem.from_scene`
checks the scene against the reward (its classes) and the corridor (its
dimension), and :func:`goal_weights` its goal approach.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from lfdkit.core.geometry import (
    PolylineSet,
    normal_frames,
    path_length,
    point_tangents,
    project_onto_polyline,
    resample,
)
from lfdkit.core.kernels import kernel
from lfdkit.core.memo import DigestMemo, array_digest
from lfdkit.core.validation import check_path, check_positive
from lfdkit.emulate.reward import Reward
from lfdkit.model.scene import Scene

__all__ = [
    "BARRIER_WEIGHT",
    "GOAL_APPROACH_FRACTION",
    "GOAL_GAIN",
    "MAX_POINTS",
    "PLAN_POINTS",
    "UNCERTAINTY_MARGIN",
    "Corridor",
    "Problem",
    "check_times",
    "goal_weights",
    "horizon_points",
    "longest_segment",
    "predicted_sigma",
    "swerve_shifts",
    "unrolled_terms",
]

#: Most points a plan may have (memory and time grow linearly).
MAX_POINTS = 100_000
#: Points of a plan unless told (``plan_path``'s ``n_points``); a receding horizon's
#: steps are steps of a path of this many points (:func:`horizon_points`).
PLAN_POINTS = 100
#: Factor on the nominal weight at the goal when a plan must reach it (``goal_approach``).
GOAL_GAIN = 1e4
#: Default goal approach, as a fraction of the nominal path's length.
GOAL_APPROACH_FRACTION = 0.1


def horizon_points(horizon: int, n_points: int) -> int:
    """Points a receding horizon of ``horizon`` steps spans on a plan of ``n_points``.

    The horizon counts steps of a path of :data:`PLAN_POINTS` points (the
    thesis's recordings and figures): how far ahead the person reacts, as a
    share of the path. So at ``K`` points it spans ``⌈H K / 100⌉`` points, and
    at 100 points or fewer exactly ``H`` (those plans and fits are unchanged).
    Counted in points, an 8-step horizon covered 1.6 % of a 500-point path:
    the thesis's MPC saw a box too late to swerve round it and was refused
    where the 100-point plan passes.
    """
    return max(int(horizon), -(-int(horizon) * int(n_points) // PLAN_POINTS))


def longest_segment(step: Any, max_step: Any, m: int) -> Any:
    """The longest segment between neighbouring plan points (units).

    The nominal ``step`` along and the largest sideways step ``max_step`` in
    each of the ``m`` lateral directions, with 10 % slack for the normals
    turning on a curved nominal. A segment whose ends keep
    ``√(r² + L²/4)`` from a centre keeps ``r`` from it: the hard radii are
    widened by half of it (:class:`Problem`; the coarse route and the taut
    plan likewise).
    """
    return 1.1 * np.sqrt(step**2 + m * max_step**2)


def goal_weights(
    corridor: Corridor, weight: float, goal_approach: float | str | None
) -> np.ndarray:
    """Nominal weight of offsets 1 … K−1: ``Q``, ramped up over the last ``goal_approach``.

    Over the final stretch of length ``goal_approach`` (``"auto"``:
    :data:`GOAL_APPROACH_FRACTION` of the nominal's length) the weight rises as
    ``Q (1 + GOAL_GAIN · r²(3 − 2r))`` with ``r`` from 0 to 1 (a smooth step),
    which draws the plan back onto the nominal so it ends at the goal. None
    keeps ``Q`` everywhere (the thesis's model).

    Parameters
    ----------
    corridor : Corridor
    weight : float
        The reward's nominal weight ``Q`` (1/units²).
    goal_approach : float, "auto" or None
        Length of the approach (units, positive), "auto" or None.

    Returns
    -------
    ndarray, shape (K − 1,)

    Raises
    ------
    ValueError
        For a goal approach that is not positive, "auto" or None.
    """
    n = corridor.n_points - 1
    if goal_approach is None:
        return np.full(n, float(weight))
    if isinstance(goal_approach, str):
        if goal_approach != "auto":
            raise ValueError(
                f"goal_approach: expected a length, 'auto' or None, got {goal_approach!r}"
            )
        approach = GOAL_APPROACH_FRACTION * corridor.length
    else:
        approach = check_positive(goal_approach, "goal_approach")
    position = np.arange(1, n + 1) * corridor.step
    r = np.clip((position - (n * corridor.step - approach)) / approach, 0.0, 1.0)
    return weight * (1.0 + GOAL_GAIN * r * r * (3.0 - 2.0 * r))


@dataclass(frozen=True, eq=False)
class Corridor:
    """A nominal path sampled at constant speed, with the normals a plan moves along.

    Attributes
    ----------
    points : ndarray, shape (K, q)
        Nominal points ``x_k^N``, equally spaced in arc length.
    normals : ndarray, shape (K, q − 1, q)
        Orthonormal normals ``N_k`` of each point (rows).
    tangents : ndarray, shape (K, q)
    step : float
        Arc length between consecutive points.
    """

    points: np.ndarray
    normals: np.ndarray
    tangents: np.ndarray
    step: float

    @classmethod
    def from_path(cls, nominal: Any, n_points: int = PLAN_POINTS) -> Corridor:
        """Resample ``nominal`` (n, q), q 2 or 3, to ``n_points`` equally spaced points."""
        path = check_path(nominal, "nominal", min_points=2)
        if path.shape[1] not in (2, 3):
            raise ValueError(f"nominal: expected 2-D or 3-D points, got {path.shape[1]}")
        n_points = check_positive(n_points, "n_points", integer=True)
        if not 3 <= n_points <= MAX_POINTS:
            raise ValueError(f"n_points: expected 3 to {MAX_POINTS} points, got {n_points}")
        # A skill plans one nominal many times over (its model choice: every candidate in
        # every training scene); in 3-D its frames' transport is a loop over the points.
        key = array_digest(path, label=str(n_points))
        found = _CORRIDORS.get(key)
        if found is not None:
            return found
        points = resample(path, n_points)
        tangents = point_tangents(points)
        frames = normal_frames(tangents)
        step = float(np.linalg.norm(points[1] - points[0]))
        normals = frames[:, 1:, :]  # a view, as it always was (einsum's paths follow strides)
        for array in (points, normals, tangents):  # shared by every caller: never written to
            array.setflags(write=False)
        return _CORRIDORS.put(key, cls(points, normals, tangents, step))

    @property
    def n_points(self) -> int:
        return int(self.points.shape[0])

    @property
    def n_dims(self) -> int:
        return int(self.points.shape[1])

    @property
    def length(self) -> float:
        """Arc length from the first to the last point."""
        return self.step * (self.n_points - 1)

    @property
    def extent(self) -> float:
        """Largest side of the points' bounding box (the scale of goal tolerances)."""
        return float(np.ptp(self.points, axis=0).max())

    def to_points(self, offsets: np.ndarray) -> np.ndarray:
        """World points ``x_k^N + N_kᵀ d_k`` for offsets (K, q − 1)."""
        return self.points + np.einsum("km,kmq->kq", offsets, self.normals)

    def offsets_of(self, demo: Any) -> tuple[np.ndarray, np.ndarray]:
        """Lateral offsets where a demonstration crosses each normal.

        Returns
        -------
        offsets : ndarray, shape (K, q − 1)
            ``N_k (p_k − x_k^N)`` with ``p_k`` the nearest crossing of the
            demonstration (travelled in the nominal's direction) with the
            normal hyperplane of point ``k``; 0 where there is none.
        found : ndarray of bool, shape (K,)
        """
        demo = check_path(demo, "demo", n_dims=self.n_dims)
        hits = PolylineSet([demo]).intersect(self.points, self.tangents, same_direction=True)
        found = hits.found[:, 0]
        rel = np.where(found[:, None], hits.points[:, 0] - self.points, 0.0)
        return np.einsum("kmq,kq->km", self.normals, rel), found


#: Corridors made by :meth:`Corridor.from_path`, by a digest of the path and the point
#: count, the 256 most recently used: the same numbers, made once (a 3-D fit's model
#: choice made 269, most of them of the same few nominals: 0.6 s).
_CORRIDORS: DigestMemo[Corridor] = DigestMemo(max_items=256)

#: Moving obstacles: standard deviations of the prediction added to the hard radius.
UNCERTAINTY_MARGIN = 2.0

#: Scale of the clearance barrier (an obstacle's reward term is at most 1).
BARRIER_WEIGHT = 1.0


class Problem:
    """Offsets ``d_1 … d_n`` after a fixed ``d_0``: the cost's ingredients.

    The exponent of obstacle ``l`` at point ``k`` is a quadratic in the offset,
    ``s = c + 2 bᵀd + dᵀA d`` with ``c = rᵀPr``, ``b = N P r``, ``A = N P Nᵀ``
    and ``r = x_k^N − O_l``: precomputed once, so each evaluation is a few
    element-wise operations. Obstacles with a hard radius (``hard_radius > 0``)
    add the clearance barrier, on the squared distance ``|r|² + 2 (N r)ᵀd + |d|²``
    (the normals are orthonormal). Build one with :meth:`from_scene`.

    Parameters
    ----------
    base : ndarray, shape (n, q)
        Nominal points of the offsets (points 1 … K−1 of the corridor), in units.
    normals : ndarray, shape (n, m, q)
        Their orthonormal normals.
    obstacles : ndarray, shape (L, q) or (n, L, q)
        Centres of the reward's obstacle terms (a round obstacle's centre; a
        shape's anchors, :meth:`lfdkit.model.scene.Obstacle.anchors`), in units;
        with moving obstacles a centre per point (where each is predicted
        when the tool reaches that point).
    precision : ndarray, shape (L, q, q)
        Each term's precision ``P`` (1/units²).
    weight : float or ndarray, shape (n,)
        Nominal weight ``Q`` per offset (1/units²).
    max_step : float
        Action bound: largest change of an offset component per point (units).
    hard_radius : ndarray, shape (L,) or (B,), or (n, B), optional
        Radius plus clearance (units) of each ball the plan must keep out of,
        or of each ball at each point (moving obstacles: the margin grows with
        the prediction's uncertainty); 0 or None: no barrier.
    hard_centres : ndarray, shape (B, q) or (n, B, q), optional
        Centres of those balls (the obstacles' covering balls,
        :meth:`lfdkit.model.scene.Obstacle.balls`); None: the term centres
        ``obstacles``, with ``hard_radius`` of shape (L,).
    tangents : ndarray, shape (n, q), optional
        Unit tangents of the nominal at ``base``: needed with ``stretch``.
    stretch : ndarray, shape (L, 2), optional
        Each term's swerve stretches before and after its anchor along the path
        (:func:`swerve_shifts`); None (the default): symmetric terms (the
        thesis's model, computed exactly as without the argument).

    Attributes
    ----------
    base, normals, obstacles, precision, max_step
        As given.
    weight : ndarray, shape (n,)
    c : ndarray, shape (n, L)
        ``rᵀPr`` (dimensionless).
    b : ndarray, shape (n, L, m)
        ``N P r`` (1/units).
    a : ndarray, shape (n, L, m, m)
        ``N P Nᵀ`` (1/units²).
    hard : ndarray of int, shape (H,)
        The balls with a barrier (indices into ``hard_centres``).
    hard_centres : ndarray, shape (B, q)
        As given (``obstacles`` when not given).
    inner2, outer2 : ndarray, shape (H,)
        Squared radii (units²) where the barrier is infinite and where it
        starts: the hard radius widened by half a segment's length, and a
        thin zone outside it (the smallest over the points when it varies).
    rr : ndarray, shape (n, H)
        ``|r|²`` of the obstacles with a barrier (units²), less
        ``r_k² − inner2`` where the radius ``r_k`` varies from point to point
        (so the barrier meets each point's own radius).
    moving : bool
        Whether the obstacle centres are given per point.
    nr : ndarray, shape (n, H, m)
        ``N r`` of the obstacles with a barrier (units).
    shift, shift_rate : ndarray, shape (n, L, q), or None
        With ``stretch``: what the swerve adds to ``r`` and its derivative in
        the log-stretch of the side the point is on (units); None without.
    shift_side : ndarray of int, shape (n, L), or None
        0 where the point is before the anchor along the path, 1 after.
    """

    def __init__(
        self,
        base: np.ndarray,
        normals: np.ndarray,
        obstacles: np.ndarray,
        precision: np.ndarray,
        weight: float | np.ndarray,
        max_step: float,
        hard_radius: np.ndarray | None = None,
        hard_centres: np.ndarray | None = None,
        tangents: np.ndarray | None = None,
        stretch: np.ndarray | None = None,
        unrolled: tuple[np.ndarray, ...] | None = None,
    ) -> None:
        self.base, self.normals = base, normals  # (n, q), (n, m, q)
        self.obstacles = obstacles  # (L, q)
        self.max_step = float(max_step)
        # Moving obstacles: a centre per point, (n, L, q); static ones: (L, q).
        self.moving = obstacles.ndim == 3
        # A reward along the path: its terms in the nominal's arc-length coordinates.
        self.unrolled = unrolled
        self._set_terms(precision, weight, tangents, stretch)
        self.hard_centres = obstacles if hard_centres is None else hard_centres
        radius = np.zeros(self.hard_centres.shape[-2]) if hard_radius is None else hard_radius
        # balls with a barrier (a radius per point for moving obstacles: (n, B))
        self.hard = np.flatnonzero((radius if radius.ndim == 1 else radius.max(axis=0)) > 0.0)
        # A segment of length L whose ends keep √(r² + L²/4) from a centre keeps r from
        # it; L is at most the nominal step and the largest sideways step (10 % slack
        # for the normals turning on a curved nominal).
        step = _step_of(base)
        segment = longest_segment(step, max_step, normals.shape[1])
        inner = np.sqrt(radius[..., self.hard] ** 2 + 0.25 * segment**2)  # (H,) or (n, H)
        smallest = inner if inner.ndim == 1 else inner.min(axis=0, initial=np.inf)
        self.inner2 = smallest**2
        self.outer2 = (smallest + 0.25 * np.maximum(smallest, step)) ** 2
        centres = self.hard_centres[..., self.hard, :]
        hard_rel = base[:, None, :] - (centres if centres.ndim == 3 else centres[None])  # (n, H, q)
        self.rr = np.einsum("khq,khq->kh", hard_rel, hard_rel)
        if inner.ndim == 2:
            # A radius growing from point to point with the same kernels: the barrier
            # acts on u = |x − O|² against the smallest radius², so u − (r_k² − r²)
            # meets it exactly at r_k (the zone beyond keeps its width in u).
            self.rr = self.rr - (inner**2 - self.inner2[None])
        self.nr = np.einsum("kmq,khq->khm", normals, hard_rel)
        self.rr, self.nr = np.ascontiguousarray(self.rr), np.ascontiguousarray(self.nr)

    def _set_terms(
        self,
        precision: np.ndarray,
        weight: float | np.ndarray,
        tangents: np.ndarray | None,
        stretch: np.ndarray | None,
    ) -> None:
        """The reward's part: precisions, nominal weight, swerve and the obstacle terms.

        With :attr:`unrolled` (a reward along the path, :func:`unrolled_terms`)
        the terms are those of the nominal straightened out: points at
        ``(s_k, d_k)``, each anchor at its arc length and lateral offset, its
        precision in the path's axes (along, across), as the reward gives it;
        :attr:`precision` is the world-axis one where it is passed.
        """
        base, obstacles, normals = self.base, self.obstacles, self.normals
        self.precision = precision  # (L, q, q): world axes, for the planner's geometry
        if self.unrolled is not None:
            base, normals, obstacles, precision, tangents = self.unrolled
        # Nominal weight per offset: Q, or Q ramped up towards the goal.
        self.weight = np.broadcast_to(np.asarray(weight, dtype=np.float64), (base.shape[0],)).copy()
        rel = base[:, None, :] - (obstacles if self.moving else obstacles[None])  # (n, L, q)
        self.shift = self.shift_rate = self.shift_side = None
        if stretch is not None:
            # The swerve moves each term along the path per point: only c and b change.
            self.shift, self.shift_rate, self.shift_side = swerve_shifts(rel, tangents, stretch)
            rel = rel + self.shift
        c, b, a = _obstacle_terms(rel, normals, precision)
        # C order (moving obstacles' centres make Fortran-ordered terms): numba then
        # compiles one version of each kernel, not one per layout (a copy only then).
        self.c, self.b, self.a = (np.ascontiguousarray(x) for x in (c, b, a))

    @classmethod
    def from_scene(
        cls,
        reward: Reward,
        corridor: Corridor,
        scene: Scene,
        max_slope: float = 1.0,
        goal_approach: float | str | None = None,
        clearance: float | np.ndarray | None = None,
        times: Any = None,
        margin: float = UNCERTAINTY_MARGIN,
        like: Problem | None = None,
    ) -> Problem:
        """The problem of offsets 1 … K−1 after the fixed start, steps up to ``max_slope`` · step.

        Parameters
        ----------
        reward : Reward
            Must know every class of ``scene``.
        corridor : Corridor
        scene : Scene
            Obstacles of the corridor's dimension.
        max_slope : float
            Largest sideways step per nominal step (positive; not checked here).
        goal_approach : float, "auto" or None
            See :func:`goal_weights`; None (the default) is the thesis's model.
        clearance : float or ndarray (n_obstacles,), optional
            None: no hard radii (the thesis's model, as the IOC fits it); a
            number (units), or one per obstacle: each obstacle's radius plus
            it is a hard constraint.
        times : array_like, shape (K,), optional
            When the tool reaches each corridor point (s from the plan's start);
            needed for a scene with moving obstacles: point ``k``'s obstacle
            terms and hard radii are at the obstacles' predicted positions at
            ``times[k]`` (:meth:`lfdkit.model.scene.Obstacle.predict`). Ignored for
            a static scene (whose problem is the same as without it).
        margin : float
            Moving obstacles: the hard radius at point ``k`` grows by
            ``margin · σ_k`` (σ the prediction's largest standard deviation)
            plus half the obstacle's predicted move between neighbouring points.
        like : Problem, optional
            A problem of the same corridor, static scene, ``max_slope`` and
            ``clearance`` under another reward (not checked): its geometry
            (anchors, hard radii) is shared and only the reward's terms are
            computed, the same numbers as a problem built afresh. The inverse
            optimal control builds one per demonstration at every θ it tries,
            and the geometry was most of a build's time. Ignored for a scene
            with moving obstacles.

        Raises
        ------
        ValueError
            For an obstacle class ``reward`` does not know, obstacles of
            another dimension than the corridor, or a bad ``goal_approach``.
        """
        q = corridor.n_dims
        anchors, precision = reward.anchor_precisions(scene)
        if len(scene) and anchors.shape[1] != q:
            raise ValueError(f"scene: {anchors.shape[1]}-D obstacles for a {q}-D nominal path")
        if like is not None and not scene.moving:
            stretch = reward.anchor_stretch(scene)
            problem = object.__new__(cls)
            problem.__dict__.update(like.__dict__)  # the geometry, shared (never written to)
            problem._set_terms(
                precision.reshape(-1, q, q),
                goal_weights(corridor, reward.nominal_weight, goal_approach),
                None if stretch is None else corridor.tangents[1:],
                stretch,
            )
            return problem
        hard_radius = hard_centres = None
        if clearance is not None and len(scene):
            # Offsets move at most max_slope·step per point, so no plan leaves the
            # corridor's box grown by this reach: a long shape is covered only there
            # (a 1 km rod's balls would otherwise be metres wide; the final check is exact).
            reach = max_slope * corridor.step * corridor.n_points + float(np.max(clearance))
            box = (corridor.points.min(axis=0) - reach, corridor.points.max(axis=0) + reach)
            hard_centres, radii, owner = scene.balls(within=box)
            # An obstacle without volume (a point: radius 0) has a barrier only with a clearance.
            extra = np.broadcast_to(np.asarray(clearance, dtype=np.float64), (len(scene),))[owner]
            hard = scene.has_extent[owner] | (extra > 0.0)
            hard_radius = np.where(hard, radii + extra, 0.0)
        if scene.moving:
            shifts, grow = _predicted_shifts(scene, corridor, times, margin)  # (n, O, q), (n, O)
            anchors = anchors[None] + shifts[:, scene.anchors()[1]]
            if hard_centres is not None:
                hard_centres = hard_centres[None] + shifts[:, owner]
                hard_radius = np.where(hard_radius > 0.0, hard_radius[None] + grow[:, owner], 0.0)
        stretch = reward.anchor_stretch(scene)
        unrolled = None
        if getattr(reward, "along_path", False) and q == 2 and not scene.moving and len(anchors):
            unrolled, precision = unrolled_terms(corridor, anchors, precision.reshape(-1, q, q))
        return cls(
            corridor.points[1:],
            corridor.normals[1:],
            anchors if anchors.ndim == 3 else anchors.reshape(-1, q),
            precision.reshape(-1, q, q),
            goal_weights(corridor, reward.nominal_weight, goal_approach),
            max_slope * corridor.step,
            hard_radius,
            hard_centres,
            None if stretch is None else corridor.tangents[1:],
            stretch,
            unrolled,
        )

    @property
    def n(self) -> int:
        """Number of offsets."""
        return int(self.base.shape[0])

    @property
    def m(self) -> int:
        """Components of an offset, ``q − 1``."""
        return int(self.normals.shape[1])

    @property
    def has_obstacles(self) -> bool:
        """Whether the scene has obstacles (each has at least one term)."""
        return bool(self.obstacles.shape[-2])

    @property
    def step(self) -> float:
        """Arc length between consecutive nominal points (0 with a single point)."""
        return _step_of(self.base)

    def window(self, start: int, stop: int, stride: int = 1) -> Problem:
        """The sub-problem of offsets ``start, start + stride, …`` below ``stop`` (terms sliced).

        ``stride`` > 1 (a coarse route's problem) copies the strided rows into
        C-ordered arrays, as the compiled kernels take them; a contiguous
        window shares its rows.
        """
        rows = slice(start, stop, stride)

        def sliced(values: np.ndarray) -> np.ndarray:
            return np.ascontiguousarray(values[rows])

        sub = object.__new__(Problem)
        sub.base, sub.normals = sliced(self.base), sliced(self.normals)
        sub.moving, sub.unrolled = self.moving, None  # its terms are sliced, not recomputed
        sub.obstacles, sub.precision = self.obstacles, self.precision
        if self.moving:  # a centre per point
            sub.obstacles = sliced(self.obstacles)
        sub.weight, sub.max_step = sliced(self.weight), self.max_step
        sub.c, sub.b, sub.a = sliced(self.c), sliced(self.b), sliced(self.a)
        sub.hard, sub.inner2, sub.outer2 = self.hard, self.inner2, self.outer2
        sub.hard_centres = self.hard_centres
        if self.hard_centres.ndim == 3:
            sub.hard_centres = sliced(self.hard_centres)
        sub.rr, sub.nr = sliced(self.rr), sliced(self.nr)
        sub.shift = sub.shift_rate = sub.shift_side = None
        if self.shift is not None:
            sub.shift, sub.shift_rate = sliced(self.shift), sliced(self.shift_rate)
            sub.shift_side = sliced(self.shift_side)
        return sub

    def kernel_arguments(self) -> tuple:
        """The cost's arrays as the compiled kernels take them.

        ``(c, b, a, weight, rr, nr, inner2, outer2, mu)`` with ``mu`` the
        barrier's scale :data:`BARRIER_WEIGHT`: the first arguments of
        :mod:`._problem_kernels`' and :mod:`._planner_kernels`' functions.
        """
        return (
            self.c,
            self.b,
            self.a,
            self.weight,
            self.rr,
            self.nr,
            self.inner2,
            self.outer2,
            BARRIER_WEIGHT,
        )

    def bumps(self, d: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Obstacle terms ``e`` (n, L) and ``N P u = b + A d`` (n, L, m) at offsets ``d`` (n, m)."""
        npu = self.b + np.einsum("klmn,kn->klm", self.a, d)
        exponent = self.c + np.einsum("klm,km->kl", self.b + npu, d)
        return np.exp(-exponent), npu

    def cost(self, d: np.ndarray) -> float:
        """The reward's cost ``−Σ R`` (without the clearance barrier)."""
        value = float(np.sum(self.weight[:, None] * d * d))
        if self.has_obstacles:
            value += float(self.bumps(d)[0].sum())
        return value

    def total_cost(self, d: np.ndarray) -> float:
        """The cost with the clearance barrier (``+inf`` inside a hard radius)."""
        planner_cost = _kernel("planner_cost")
        return float(planner_cost(*self.kernel_arguments(), np.ascontiguousarray(d, float)))

    def derivatives(self, d: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
        """Cost, gradient (n, m) and Hessian blocks (n, m, m) in the offsets (no barrier).

        The NumPy form of the compiled derivatives the solver uses (without
        the clearance barrier): for reference solvers and checks.
        """
        m = d.shape[1]
        cost = float(np.sum(self.weight[:, None] * d * d))
        gradient = 2.0 * self.weight[:, None] * d
        hessian = 2.0 * self.weight[:, None, None] * np.eye(m)[None]
        if self.has_obstacles:
            bump, npu = self.bumps(d)
            cost += float(bump.sum())
            gradient -= 2.0 * np.einsum("kl,klm->km", bump, npu)
            hessian += np.einsum(
                "kl,klmn->kmn", bump, 4.0 * npu[..., :, None] * npu[..., None, :] - 2.0 * self.a
            )
        return cost, gradient, hessian

    def solve(
        self, d0: np.ndarray, init: np.ndarray, *, tol: float = 1e-10, max_iter: int = 100
    ) -> tuple[np.ndarray, float, int, bool]:
        """The local optimum from ``init`` by projected Newton on the actions (compiled).

        Parameters
        ----------
        d0 : ndarray, shape (m,)
            The fixed start offset (units).
        init : array_like, shape (n, m)
            Starting offsets; actions outside the box are clipped first.
        tol : float
            Convergence: largest free action gradient at most
            ``tol (1 + 2 Q_min max_step)``.
        max_iter : int

        Returns
        -------
        d : ndarray, shape (n, m)
            The optimum (a new array).
        cost : float
            Its cost with the clearance barrier; ``+inf`` for a start inside a
            hard radius, which is returned unchanged.
        n_iter : int
            Newton iterations.
        converged : bool
        """
        planner_newton = _kernel("planner_newton")  # numba's compile on their first use
        d = np.array(init, dtype=np.float64, order="C").reshape(self.n, self.m)
        cost, n_iter, ok = planner_newton(
            *self.kernel_arguments(),
            self.max_step,
            np.ascontiguousarray(d0, dtype=np.float64),
            d,
            tol,
            max_iter,
        )
        return d, float(cost), int(n_iter), bool(ok)


def _kernel(name: str) -> Any:
    """The solver's kernel ``name``: numba's or its NumPy form (:mod:`lfdkit.core.kernels`)."""
    return kernel(name, "lfdkit.emulate._problem_kernels", "lfdkit.emulate._planner_numpy")


def check_times(times: Any, n_points: int) -> np.ndarray:
    """The times (K,) of a plan's points: finite, non-decreasing, one per point.

    Always a new array (the caller's is never written to, nor aliased: a
    closed loop shifts its own copy when it holds the tool).
    """
    if times is None:
        raise ValueError(
            "times: a scene with moving obstacles needs the time (s) at which the tool "
            "reaches each point of the plan"
        )
    out = np.array(times, dtype=np.float64).reshape(-1)  # a copy, writable
    if out.size != n_points:
        raise ValueError(f"times: expected {n_points} times (one per plan point), got {out.size}")
    if not np.all(np.isfinite(out)) or np.any(np.diff(out) < 0.0):
        raise ValueError("times: must be finite and non-decreasing")
    return out


def predicted_sigma(covs: np.ndarray) -> np.ndarray:
    """The largest standard deviation of each covariance (n, q, q): shape (n,), units."""
    if not covs.size:
        return np.zeros(covs.shape[0])
    if covs.shape[1] == 2:  # closed form: (a + d)/2 + √(((a − d)/2)² + b²)
        a, b, d = covs[:, 0, 0], covs[:, 0, 1], covs[:, 1, 1]
        largest = 0.5 * (a + d) + np.sqrt(0.25 * (a - d) ** 2 + b * b)
    else:
        largest = np.linalg.eigvalsh(covs)[:, -1]
    return np.sqrt(np.maximum(largest, 0.0))


def swerve_shifts(
    rel: np.ndarray, tangents: np.ndarray, stretch: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """What a swerve adds to each point's offset from each anchor (issue 26).

    The thesis's term is symmetric along the path: a person who starts early,
    swerves steeply and returns slowly (a DMP's second-order lag; a late
    reactive person the other way round) cannot be expressed by it. Each
    point ``k`` at along-path distance ``τ = t_kᵀ r`` from an anchor (``r =
    x_k^N − O``, ``t_k`` the nominal's tangent; negative before it) sees the
    term as if it were at ``τ' = τ / w`` (``w = w_before`` for ``τ < 0``,
    ``w_after`` otherwise): ``r`` gains ``(τ' − τ) t_k``. The move is along
    the path and the planned offsets are across it, so the shift is a
    constant per point: the cost keeps the thesis's form ``c + 2bᵀd + dᵀAd``
    with other ``c`` and ``b`` (``A`` unchanged) and the planner's kernels
    are the same. Continuous at ``τ = 0``; ``w = 1`` on both sides adds zero.

    Parameters
    ----------
    rel : ndarray, shape (n, L, q)
        ``x_k^N − O_l`` (units).
    tangents : ndarray, shape (n, q)
        Unit tangents of the nominal at the points.
    stretch : ndarray, shape (L, 2)
        ``(w_before, w_after)`` of each anchor, positive.

    Returns
    -------
    shift : ndarray, shape (n, L, q)
        Added to ``rel`` (units).
    rate : ndarray, shape (n, L, q)
        Derivative of the shift in the log-stretch of the point's side
        (``−τ' t_k``), for the inverse optimal control.
    side : ndarray of int, shape (n, L)
        0 before the anchor, 1 after.
    """
    tau = np.einsum("klq,kq->kl", rel, tangents)
    side = (tau >= 0.0).astype(np.int64)
    warped = tau / stretch[np.arange(stretch.shape[0])[None], side]  # τ' (n, L)
    shift = (warped - tau)[..., None] * tangents[:, None, :]
    rate = -warped[..., None] * tangents[:, None, :]
    return shift, rate, side


def _predicted_shifts(
    scene: Scene, corridor: Corridor, times: Any, margin: float
) -> tuple[np.ndarray, np.ndarray]:
    """Each obstacle's predicted move from its position (n, O, q) and radius growth (n, O).

    At corridor points 1 … K−1 (at ``times[1:]``): the growth is ``margin · σ``
    plus half the larger of the mean's moves to the neighbouring points (the
    obstacle moves while the tool runs a segment).
    """
    times = check_times(times, corridor.n_points)
    margin = check_positive(margin, "margin", allow_zero=True)
    n, q = times.size - 1, corridor.n_dims
    shifts, grow = np.zeros((n, len(scene), q)), np.zeros((n, len(scene)))
    moving = [o for o, obstacle in enumerate(scene.obstacles) if obstacle.motion is not None]
    if not moving:
        return shifts, grow
    # The moving obstacles' predictions stacked, (M, K, q) and (M, K, q, q), and worked
    # on at once: a closed loop builds this every step (one obstacle at a time was a
    # fifth of the moving MPC's step); element by element the same arithmetic.
    predictions = [scene.obstacles[o].predict(times) for o in moving]
    means = np.stack([mean for mean, _ in predictions])
    covs = np.stack([cov for _, cov in predictions])
    step = means[:, 1:] - means[:, :-1]
    move = np.sqrt(np.einsum("okq,okq->ok", step, step))  # (M, K − 1)
    ahead = np.concatenate([move[:, 1:], move[:, -1:]], axis=1)
    positions = np.array([scene.obstacles[o].position for o in moving])  # (M, q)
    shifts[:, moving] = np.swapaxes(means[:, 1:] - positions[:, None], 0, 1)
    sigma = predicted_sigma(covs[:, 1:].reshape(-1, q, q)).reshape(len(moving), n)
    grow[:, moving] = (margin * sigma + 0.5 * np.maximum(move, ahead)).T
    return shifts, grow


def unrolled_terms(
    corridor: Corridor, anchors: np.ndarray, precision: np.ndarray
) -> tuple[tuple[np.ndarray, ...], np.ndarray]:
    """A reward along the path: its terms' geometry with the nominal straightened out (2-D).

    A person who reacts relative to the motion keeps the shape of a response
    along the path as the path bends. A response ten times as long as it is
    wide, kept straight along the direction where its obstacle is passed,
    lies across the region outside a bend on both sides of it: at the trough
    of an S-curve plans passed a box 1-3 cm inside the bend on the far side,
    the long way round (the fidelity benchmark's late swerver, seed 14, new
    tasks: Pr −255 %; straightened, 95 %). Here each point is ``(s_k, d_k)``
    (arc length, lateral offset), each anchor its arc length and lateral
    offset from the nominal (beyond an end, the arc length runs on along the
    end's tangent), each precision as given (in the path's axes, along and
    across).

    Parameters
    ----------
    corridor : Corridor
        2-D.
    anchors : ndarray, shape (A, 2)
    precision : ndarray, shape (A, 2, 2)
        In the path's axes (along, across).

    Returns
    -------
    terms : tuple
        ``(base (n, 2), normals (n, 1, 2), anchors (A, 2), precision (A, 2, 2),
        tangents (n, 2))`` of points ``1 … K−1`` in the straightened frame.
    world : ndarray, shape (A, 2, 2)
        Each precision turned into world axes where its anchor is passed (the
        nominal's direction at its nearest point): for the planner's geometry
        (the responses' widths and reach), not for the terms.
    """
    points, tangents = corridor.points, corridor.tangents
    arc, foot, _ = project_onto_polyline(anchors, points)
    # The direction at the foot: the points' tangents interpolated (smooth over vertices).
    where = np.clip(arc / corridor.step, 0.0, len(points) - 1.0)
    below = np.minimum(where.astype(np.int64), len(points) - 2)
    share = (where - below)[:, None]
    tangent = (1.0 - share) * tangents[below] + share * tangents[below + 1]
    tangent = tangent / np.linalg.norm(tangent, axis=1, keepdims=True)
    left = np.column_stack([-tangent[:, 1], tangent[:, 0]])
    offset = anchors - foot
    total = path_length(points)  # as ``arc`` measures it (the corridor's length to rounding)
    ends = (arc <= 1e-12 * total) | (arc >= (1.0 - 1e-12) * total)
    along = arc + np.where(ends, np.einsum("aq,aq->a", offset, tangent), 0.0)
    lateral = np.einsum("aq,aq->a", offset, left)
    axes = np.stack([tangent, left], axis=2)  # columns: the path's axes in the room
    world = np.einsum("aiq,aqr,ajr->aij", axes, precision, axes)
    n = len(points) - 1
    base = np.column_stack([corridor.step * np.arange(1, n + 1), np.zeros(n)])
    normals = np.broadcast_to(np.array([[[0.0, 1.0]]]), (n, 1, 2))
    along_x = np.broadcast_to(np.array([[1.0, 0.0]]), (n, 2))
    return (base, normals, np.column_stack([along, lateral]), precision, along_x), world


def _obstacle_terms(
    rel: np.ndarray, normals: np.ndarray, precision: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``c = rᵀPr`` (n, L), ``b = N P r`` (n, L, m) and ``A = N P Nᵀ`` (n, L, m, m).

    From ``r`` (n, L, q), the normals (n, m, q) and the precisions (L, q, q).
    The IOC builds a problem per demonstration at every θ it tries, so this is
    its hot spot (a third of a 3-D fit's set-up time with einsum; issue 34):
    diagonal precisions (every learned reward's) scale ``r`` instead of a
    matrix product, ``b`` in 3-D is summed axis by axis, and ``A``, which does not
    depend on the point's offset from the anchor, is computed once per run of
    anchors sharing a precision (an obstacle's anchors, or a whole class) and
    repeated: 1.13 → 0.37 ms for 99 points and 14 anchors in 3-D. The same
    numbers as the einsum forms, to the bit with NumPy 2 on x86
    (``tests/emulate/test_problem.py`` holds them to rounding).
    """
    n_anchors, q = precision.shape[0], precision.shape[-1]
    diagonal = np.einsum("lii->li", precision)
    if np.array_equal(precision, diagonal[:, :, None] * np.eye(q)):
        pr = rel * diagonal[None]  # exact: the einsum's other terms are zeros
    else:
        pr = np.einsum("lij,klj->kli", precision, rel)
    c = np.einsum("kli,kli->kl", rel, pr)
    if q == 3:  # the einsum's slow case (ten times 2-D's time)
        # Summed over the axes in the einsum's order (a two-lane inner loop: (0 + 2) + 1),
        # so that fits are the same to the bit as with it.
        terms = [normals[:, None, :, j] * pr[:, :, None, j] for j in range(q)]
        b = (terms[0] + terms[2]) + terms[1]
    else:
        b = np.einsum("kmq,klq->klm", normals, pr)
    # Runs of consecutive anchors with one precision: A once per run.
    if n_anchors == 1:  # one run (a training scene's obstacle): its runs cost more than A
        a = np.einsum("kmq,lqr,knr->klmn", normals, precision, normals)
    elif n_anchors:
        changes = np.any(precision[1:] != precision[:-1], axis=(1, 2))
        starts = np.concatenate(([0], np.flatnonzero(changes) + 1))
        lengths = np.diff(np.append(starts, n_anchors))
        per_run = np.einsum("kmq,lqr,knr->klmn", normals, precision[starts], normals)
        a = np.repeat(per_run, lengths, axis=1)
    else:
        a = np.zeros((rel.shape[0], 0, normals.shape[1], normals.shape[1]))
    return c, b, a


def _step_of(base: np.ndarray) -> float:
    return float(np.linalg.norm(base[1] - base[0])) if base.shape[0] > 1 else 0.0
