"""The learned reward (thesis eq. 5.4): stay near the nominal path, keep clear of obstacles.

For a state ``x`` (a point of the path, units of the demonstrations)::

    R(x) = −Q |x − x_N|² − Σ_o exp(−(x − O_o)ᵀ P_c(o) (x − O_o))

(a shape other than a round obstacle contributes its class's term at each of
its anchors, :meth:`lfdkit.model.scene.Obstacle.anchors`)

* ``x_N`` is the point of the nominal path whose normal passes through ``x``
  (thesis §5.3: the segment ``x_N x`` is perpendicular to the nominal). For a
  point in the plane this is the foot of the perpendicular onto the nominal
  polyline (:func:`lfdkit.core.geometry.project_onto_polyline`); the planner
  instead moves each planned point along its own nominal point's normal, so
  that the match holds by construction.
* ``Q > 0`` is the thesis's nominal weight (a scalar: only the distance
  across the path counts, and the path's direction changes along it).
* ``P_c = R_c⁻¹`` is the precision of obstacle class ``c``: positive
  definite, in world axes (as the thesis's ``R = diag(…)``). The obstacle term
  has unit height, so ``Q`` and ``P_c`` together set how far and how wide the
  path swerves.

Parameters for learning (:attr:`Reward.theta`) are logarithms: ``log Q`` and
the log-diagonal of every class's precision, so every ``θ`` gives a positive
definite reward.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from lfdkit.core.geometry import project_onto_polyline, segment_tangents
from lfdkit.core.validation import check_positive
from lfdkit.model.half_space import HalfSpace
from lfdkit.model.scene import Scene

__all__ = ["Reward", "in_path_frame", "passing_directions", "shown_directions", "unshown_widths"]


class Reward:
    """Nominal term plus one Gaussian obstacle term per class.

    Parameters
    ----------
    nominal_weight : float
        ``Q`` in 1/units² (thesis: 10 for the synthetic example, 200 for da
        Vinci, 20 for sweeping).
    precisions : mapping of class label to array_like, shape (q,) or (q, q)
        ``P_c = R_c⁻¹`` per obstacle class in 1/units²: a positive diagonal
        ``(q,)`` or a symmetric positive definite matrix ``(q, q)``.
    swerve : mapping of class label to array_like, shape (2,), optional
        The shape of a class's swerve along the path (issue 26): how much its
        response is stretched before and after the obstacle, ``(w_before,
        w_after)``, positive (1, 1: the thesis's symmetric Gaussian). A point
        at along-path distance ``τ`` from the obstacle (along the nominal's
        tangent; negative before it) sees the term as if it were at
        ``τ / w_before`` or ``τ / w_after``: ``w_before > 1`` starts the swerve
        earlier, ``w_after > 1`` returns more slowly
        (:func:`lfdkit.emulate.problem.swerve_shifts`). The planner applies
        it; a class without one (or None, the default) is symmetric.
        :meth:`value` and the other pointwise evaluations here ignore it (they
        have no path direction).
    along_path : bool, default False
        2-D: the precisions are in the path's axes (along, across), and the
        planner evaluates each obstacle's term in the nominal's arc-length
        coordinates, so its shape follows the path as it bends
        (:func:`lfdkit.emulate.problem.unrolled_terms`; :func:`in_path_frame`
        makes such a reward). The pointwise evaluations here take the
        precisions as world axes.

    Raises
    ------
    ValueError
        For a non-positive or non-finite weight, a precision that is not
        symmetric positive definite, classes of different dimensions, or a
        swerve that is not two positive numbers of a known class.
    """

    #: Precisions in the path's axes, planned along the bending path (see ``along_path``).
    along_path: bool = False

    def __init__(
        self,
        nominal_weight: float,
        precisions: Mapping[str, Any],
        swerve: Mapping[str, Any] | None = None,
        *,
        along_path: bool = False,
    ) -> None:
        self.nominal_weight = check_positive(nominal_weight, "nominal_weight")
        self.along_path = bool(along_path)
        matrices: dict[str, np.ndarray] = {}
        dims = set()
        for label, value in precisions.items():
            arr = np.asarray(value, dtype=np.float64)
            name = f"precisions[{label!r}]"
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"{name}: contains NaN or infinite values")
            diagonal = arr.ndim == 1
            if diagonal:
                if np.any(arr <= 0):
                    raise ValueError(f"{name}: diagonal entries must be positive, got {arr}")
                arr = np.diag(arr)
            if arr.ndim != 2 or arr.shape[0] != arr.shape[1] or arr.shape[0] not in (2, 3):
                raise ValueError(f"{name}: expected shape (q,) or (q, q) with q 2 or 3")
            if diagonal:  # positive and finite on the diagonal: symmetric positive definite
                dims.add(arr.shape[0])
                matrices[str(label)] = arr
                continue
            if not np.allclose(arr, arr.T, rtol=1e-10, atol=0.0):
                raise ValueError(f"{name}: must be symmetric")
            try:
                np.linalg.cholesky(arr)
            except np.linalg.LinAlgError:
                raise ValueError(f"{name}: must be positive definite") from None
            dims.add(arr.shape[0])
            matrices[str(label)] = arr
        if len(dims) > 1:
            raise ValueError("precisions: classes of different dimensions")
        self.precisions = matrices
        self.swerve: dict[str, np.ndarray] = {}
        for label, value in (swerve or {}).items():
            stretch = np.asarray(value, dtype=np.float64)
            if stretch.shape != (2,) or not np.all(np.isfinite(stretch) & (stretch > 0.0)):
                raise ValueError(
                    f"swerve[{label!r}]: expected two positive stretches (before, after), "
                    f"got {value!r}"
                )
            if str(label) not in matrices:
                raise ValueError(
                    f"swerve: class {label!r} has no precision; known classes: "
                    f"{', '.join(matrices) or 'none'}"
                )
            self.swerve[str(label)] = stretch

    # ------------------------------------------------------------ parameters
    @property
    def classes(self) -> tuple[str, ...]:
        """Learned obstacle classes, in order."""
        return tuple(self.precisions)

    @property
    def n_dims(self) -> int | None:
        """Spatial dimension of the precisions (None without classes)."""
        for matrix in self.precisions.values():
            return int(matrix.shape[0])
        return None

    @property
    def theta(self) -> np.ndarray:
        """``[log Q, log diag P_c for each class]``; defined for diagonal precisions only."""
        parts = [np.array([np.log(self.nominal_weight)])]
        for label, matrix in self.precisions.items():
            if np.any(matrix - np.diag(np.diag(matrix))):
                raise ValueError(f"theta: precision of {label!r} is not diagonal")
            parts.append(np.log(np.diag(matrix)))
        return np.concatenate(parts)

    @property
    def swerve_theta(self) -> np.ndarray:
        """``[log w_before, log w_after for each class]`` (zeros where a class has no swerve)."""
        return (
            np.log(
                np.concatenate([self.swerve.get(label, np.ones(2)) for label in self.precisions])
            )
            if self.precisions
            else np.zeros(0)
        )

    @classmethod
    def from_theta(cls, theta: Any, classes: Sequence[str], n_dims: int) -> Reward:
        """The reward with ``Q = exp θ₀`` and diagonal precisions ``exp θ`` per class.

        A θ with ``2 · len(classes)`` more values (the swerve model) ends with
        each class's ``log w_before, log w_after`` (:attr:`swerve_theta`).
        """
        theta = np.asarray(theta, dtype=np.float64)
        expected = 1 + len(classes) * n_dims
        if theta.shape not in ((expected,), (expected + 2 * len(classes),)):
            raise ValueError(f"theta: expected {expected} values, got shape {theta.shape}")
        if not np.all(np.isfinite(theta)):
            raise ValueError("theta: contains NaN or infinite values")
        precisions = {
            label: np.exp(theta[1 + i * n_dims : 1 + (i + 1) * n_dims])
            for i, label in enumerate(classes)
        }
        if theta.size == expected:
            return cls(float(np.exp(theta[0])), precisions)
        swerve = {
            label: np.exp(theta[expected + 2 * i : expected + 2 * i + 2])
            for i, label in enumerate(classes)
        }
        return cls(float(np.exp(theta[0])), precisions, swerve)

    def anchor_stretch(self, scene: Scene) -> np.ndarray | None:
        """Each reward anchor's swerve stretches (A, 2); None when no class swerves."""
        if not self.swerve or not len(scene):
            return None
        per_obstacle = np.array([self.swerve.get(label, np.ones(2)) for label in scene.labels])
        return per_obstacle[scene.anchors()[1]]

    def combined(self, other: Reward, nominal_weight: float | None = None) -> Reward:
        """One reward with the classes of both (e.g. learned from separate demonstration sets).

        ``nominal_weight`` defaults to this reward's; a class in both is taken from ``other``.
        """
        weight = self.nominal_weight if nominal_weight is None else nominal_weight
        precisions = {**self.precisions, **other.precisions}
        # a class taken from ``other`` takes its swerve (or none) with it
        swerve = {k: v for k, v in self.swerve.items() if k not in other.precisions}
        return Reward(weight, precisions, {**swerve, **other.swerve})

    def __repr__(self) -> str:
        parts = ", ".join(
            f"{k!r}: diag{np.round(np.diag(v), 4).tolist()}" for k, v in self.precisions.items()
        )
        extra = ""
        if self.swerve:
            extra = (
                ", swerve={"
                + ", ".join(f"{k!r}: {np.round(v, 3).tolist()}" for k, v in self.swerve.items())
                + "}"
            )
        return f"Reward(Q={self.nominal_weight:.6g}, precisions={{{parts}}}{extra})"

    # ------------------------------------------------------------ evaluation
    def precision_of(self, scene: Scene) -> np.ndarray:
        """Precision matrix of every obstacle of ``scene``, shape (n_obstacles, q, q).

        Raises
        ------
        ValueError
            If the scene has an obstacle of a class this reward has not learned,
            or its dimension differs.
        """
        unknown = [label for label in scene.classes if label not in self.precisions]
        if unknown:
            raise ValueError(
                f"scene: obstacle class {unknown[0]!r} was never learned (not in the "
                "training scenes, or no demonstration passed near one); known classes: "
                f"{', '.join(self.classes) or 'none'}; adopt a reward for it learned "
                "elsewhere (e.g. Skill.adopt) to plan with it"
            )
        if not len(scene):
            return np.zeros((0, self.n_dims or 2, self.n_dims or 2))
        if scene.positions.shape[1] != self.n_dims:
            raise ValueError(
                f"scene: {scene.positions.shape[1]}-D obstacles for a {self.n_dims}-D reward"
            )
        return np.array([self.precisions[label] for label in scene.labels])

    def anchor_precisions(self, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
        """The scene's reward anchors (A, q) and each one's precision (A, q, q).

        An obstacle's term is its class's Gaussian at each of its anchors
        (:meth:`lfdkit.model.scene.Obstacle.anchors`; a round obstacle's centre).

        Raises
        ------
        ValueError
            As :meth:`precision_of`.
        """
        precision = self.precision_of(scene)
        if not len(scene):
            return np.zeros((0, precision.shape[1])), precision
        anchors, owner = scene.anchors()
        return anchors, precision[owner]

    def obstacle_cost(self, points: Any, scene: Scene) -> np.ndarray:
        """``Σ_a exp(−(x − O_a)ᵀ P (x − O_a))`` over the anchors at each point, shape (n,)."""
        points = np.atleast_2d(np.asarray(points, dtype=np.float64))
        anchors, precision = self.anchor_precisions(scene)
        if not len(anchors):
            return np.zeros(points.shape[0])
        rel = points[:, None, :] - anchors[None]
        return np.exp(-np.einsum("nli,lij,nlj->nl", rel, precision, rel)).sum(axis=1)

    def value(self, points: Any, nominal: Any, scene: Scene) -> np.ndarray:
        """Reward at each point, shape (n,), the nominal point found by projection.

        Parameters
        ----------
        points : array_like, shape (n, q)
        nominal : array_like, shape (m, q)
            The nominal path (generalized or DMP-retargeted).
        scene : Scene

        Notes
        -----
        The distance to the nominal is that of
        :func:`~lfdkit.core.geometry.project_onto_polyline` (to rounding), found one
        segment at a time: a grid of many points (a figure's contours) costs
        memory in proportion to the points only.
        """
        points = np.atleast_2d(np.asarray(points, dtype=np.float64))
        distance = _distances_to_polyline(points, np.asarray(nominal, dtype=np.float64))
        return -self.nominal_weight * distance**2 - self.obstacle_cost(points, scene)

    def gradient(self, points: Any, nominal: Any, scene: Scene) -> np.ndarray:
        """Gradient of :meth:`value` with respect to each point, shape (n, q)."""
        return self._derivatives(points, nominal, scene)[0]

    def hessian(self, points: Any, nominal: Any, scene: Scene) -> np.ndarray:
        """Hessian of :meth:`value` at each point, shape (n, q, q).

        The nominal term's Hessian is ``−2Q (I − t tᵀ)`` where the foot of the
        perpendicular lies inside a segment of tangent ``t`` (the polyline's
        curvature sits in its vertices), ``−2Q I`` where it is a vertex.
        """
        return self._derivatives(points, nominal, scene)[1]

    def _derivatives(self, points: Any, nominal: Any, scene: Scene) -> tuple[np.ndarray, ...]:
        points = np.atleast_2d(np.asarray(points, dtype=np.float64))
        nominal = np.asarray(nominal, dtype=np.float64)
        q = points.shape[1]
        arc, foot, _ = project_onto_polyline(points, nominal)
        offset = points - foot
        gradient = -2.0 * self.nominal_weight * offset
        knots = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(nominal, axis=0), axis=1))])
        segment = np.clip(np.searchsorted(knots, arc, side="right") - 1, 0, len(nominal) - 2)
        at_vertex = np.isclose(arc, knots[segment]) | np.isclose(arc, knots[segment + 1])
        tangents = segment_tangents(nominal)[segment]
        across = np.eye(q) - np.where(at_vertex[:, None, None], 0.0, 1.0) * (
            tangents[:, :, None] * tangents[:, None, :]
        )
        hessian = -2.0 * self.nominal_weight * across
        anchors, precision = self.anchor_precisions(scene)
        if len(anchors):
            rel = points[:, None, :] - anchors[None]  # (n, A, q)
            pu = np.einsum("lij,nlj->nli", precision, rel)
            bump = np.exp(-np.einsum("nli,nli->nl", rel, pu))
            gradient += 2.0 * np.einsum("nl,nli->ni", bump, pu)
            hessian += np.einsum(
                "nl,nlij->nij",
                bump,
                2.0 * precision[None] - 4.0 * pu[:, :, :, None] * pu[:, :, None, :],
            )
        return gradient, hessian


def _distances_to_polyline(points: np.ndarray, polyline: np.ndarray) -> np.ndarray:
    """Distance of each point (m, q) to a polyline (n, q), a segment at a time, shape (m,).

    Loops over the segments with one array of the points' size per coordinate:
    for many points (a grid) several times faster than the (points × segments)
    arrays of :func:`~lfdkit.core.geometry.project_onto_polyline`, which it matches
    to rounding.
    """
    if len(polyline) == 1:
        return np.linalg.norm(points - polyline[0], axis=1)
    coords = [np.ascontiguousarray(points[:, k]) for k in range(points.shape[1])]
    best = np.full(len(points), np.inf)
    rel = [np.empty_like(best) for _ in coords]
    u, d2 = np.empty_like(best), np.empty_like(best)
    for a, b in itertools.pairwise(polyline):
        d = b - a
        length2 = float(d @ d)
        u.fill(0.0)
        for c, r, ak, dk in zip(coords, rel, a, d, strict=True):
            np.subtract(c, ak, out=r)
            u += r * dk
        if length2 > 0:
            u /= length2
            np.clip(u, 0.0, 1.0, out=u)
        else:
            u.fill(0.0)
        d2.fill(0.0)
        for r, dk in zip(rel, d, strict=True):
            r -= u * dk
            d2 += r * r
        np.minimum(best, d2, out=best)
    return np.sqrt(best)


def passing_directions(nominal: np.ndarray, points: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """The direction a path runs where it passes each point: unit tangents, shape (n_points, q).

    The tangent at the path's point nearest each of ``points`` (n_points, q),
    from the segments on both sides of it (a zero-length one adds nothing);
    ``fallback`` (unit, (q,)) where the path stands still or folds back there.
    """
    tangents = segment_tangents(nominal)
    out = np.empty((len(points), nominal.shape[1]))
    for i, point in enumerate(points):
        k = int(np.argmin(np.linalg.norm(nominal - point, axis=1)))
        t = tangents[max(k - 1, 0)] + tangents[min(k, len(tangents) - 1)]
        norm = float(np.linalg.norm(t))
        out[i] = t / norm if norm > 1e-9 else fallback
    return out


def shown_directions(
    scenes: Sequence[Scene], nominals: Sequence[np.ndarray], fallback: np.ndarray
) -> dict[str, list[float]]:
    """The directions each class's response was shown in: ``{class: angles}`` (2-D).

    Each angle (rad, in [0, π): a direction and its reverse alike, as a
    Gaussian response is the same turned by π) is the direction its
    demonstration's nominal ran where it passed an obstacle of the class
    (:func:`passing_directions`), rounded to 1e-4 rad, sorted, without repeats.
    """
    shown: dict[str, set[float]] = {}
    for scene, nominal in zip(scenes, nominals, strict=True):
        if not len(scene):
            continue
        t = passing_directions(np.asarray(nominal, dtype=np.float64), scene.positions, fallback)
        for label, angle in zip(scene.labels, np.arctan2(t[:, 1], t[:, 0]) % np.pi, strict=True):
            shown.setdefault(label, set()).add(round(float(angle), 4) % round(math.pi, 4))
    return {label: sorted(angles) for label, angles in sorted(shown.items())}


def unshown_widths(
    reward: Reward, scene: Scene, nominal: Any, shown: Mapping[str, Sequence[float]]
) -> list[tuple[int, float, float, float]]:
    """Obstacles passed in a direction their class's response was never shown in, where it
    matters: ``(index, degrees, across, along)`` for each (2-D, world-axis responses).

    A response learned in world axes from demonstrations that passed the class's
    obstacles running one way keeps its shape in the room when a task passes one
    running another way; a person who reacts relative to the motion keeps it
    relative to the path (:func:`in_path_frame`). Demonstrations in one
    direction cannot tell the two apart. ``across`` and ``along`` are the
    room-axis response's widths across and along the path at the obstacle over
    the widths its class showed across and along the nearest direction it was
    shown in (``degrees`` from it); the width along a unit direction ``u`` is
    ``(uᵀ P u)^(-1/2)``. Listed where the width across the path (how far the
    plan swerves, which gaps it takes) differs by more than a quarter (a
    factor outside [0.8, 1.25]) and the nominal passes within the obstacle's
    reach plus three of its widest widths (it reacts to it). Across is what
    is judged: a response ten times as long as it is wide changes that by a
    quarter at a turn of about 40° (its width along the path, mixed with the
    far larger precision across, by a third at 10°).
    """
    nominal = np.asarray(nominal, dtype=np.float64)
    out: list[tuple[int, float, float, float]] = []
    if nominal.ndim != 2 or nominal.shape[1] != 2 or not len(scene):
        return out
    learned = [
        i
        for i, o in enumerate(scene.obstacles)
        # A half-space (a table, a wall) has no centre to be passed in a direction.
        if shown.get(o.label) and o.label in reward.precisions and not isinstance(o, HalfSpace)
    ]
    if not learned:
        return out
    directions = passing_directions(nominal, scene.positions, np.array([1.0, 0.0]))
    for i in learned:
        obstacle = scene.obstacles[i]
        precision = reward.precision_of(Scene((obstacle,)))[0]
        widest = 1.0 / math.sqrt(float(np.linalg.eigvalsh(precision)[0]))
        near = float(np.min(np.linalg.norm(nominal - obstacle.position, axis=1)))
        centres, radii = obstacle.balls()
        offsets = np.atleast_2d(np.asarray(centres, dtype=np.float64)) - obstacle.position
        reach = float(np.max(np.linalg.norm(offsets, axis=1) + np.asarray(radii, dtype=float)))
        if near > reach + 3.0 * widest:
            continue
        beta = math.atan2(directions[i, 1], directions[i, 0])
        turns = [(beta - a + math.pi / 2) % math.pi - math.pi / 2 for a in shown[obstacle.label]]
        turn = min(turns, key=abs)
        alpha = beta - turn
        widths = []
        for angle in (alpha, beta):
            along = np.array([math.cos(angle), math.sin(angle)])
            across = np.array([-along[1], along[0]])
            widths.append((across @ precision @ across, along @ precision @ along))
        across = math.sqrt(widths[0][0] / widths[1][0])
        along = math.sqrt(widths[0][1] / widths[1][1])
        if abs(math.log(across)) > math.log(1.25):
            out.append((i, math.degrees(abs(turn)), across, along))
    return out


def in_path_frame(
    reward: Reward,
    scene: Scene,
    nominal: Any,
    axis: Any,
    shown: Mapping[str, Sequence[float]] | None = None,
) -> tuple[Reward, Scene]:
    """The reward with each obstacle's response kept in the path's axes (2-D).

    The thesis's precisions are in world axes: a response learned long along
    the training task's direction stays long along that world direction on a
    task that runs another way. In the path frame each obstacle's response
    keeps the shape it was shown with relative to the motion: its precision
    is expressed in the axes (along, across) of the direction its class was
    shown in (``Rᵀ P R``; the nearest of ``shown``'s directions, mod π, to the
    direction the nominal runs past the obstacle, :func:`passing_directions`;
    else ``axis``, the direction the reward was learned along), and the
    planner evaluates it in the nominal's arc-length coordinates
    (``along_path``, :func:`lfdkit.emulate.problem.unrolled_terms`), so it
    follows the path as the path bends. An obstacle passed in a direction it
    was shown in, on a straight stretch, is planned exactly as in world axes:
    the fit saw the response so, and demonstrations of one task cannot tell
    the frames apart (turned from ``axis`` alone, the few degrees the training
    nominals run off it turned responses 10 times as long as they are wide,
    and the potential-field person's held-out swerve error rose 206 → 235 mm²,
    fidelity benchmark seed 1, mm, 4 demonstrations, 2× noise).

    Parameters
    ----------
    reward : Reward
        2-D reward.
    scene : Scene
        Static obstacles.
    nominal : array_like, shape (n, 2)
        The nominal path planned along.
    axis : array_like, shape (2,)
        The direction (unit or not) the precisions' first axis was learned
        along (the training task's direction): for classes ``shown`` lacks.
    shown : mapping of str to sequence of float, optional
        Per class, the angles (rad, mod π) its response was shown in
        (:func:`shown_directions`, ``ioc_info_["shown_directions"]``).

    Returns
    -------
    reward : Reward
        One class per obstacle, ``"<label>#<index>"``, its precision in the
        path's axes (along, across), ``along_path`` set.
    scene : Scene
        The obstacles relabelled so.
    """
    nominal = np.asarray(nominal, dtype=np.float64)
    axis = np.asarray(axis, dtype=np.float64)
    if nominal.ndim != 2 or nominal.shape[1] != 2 or axis.shape != (2,):
        raise ValueError("in_path_frame: defined for 2-D paths only; use world axes in 3-D")
    axis = axis / np.linalg.norm(axis)
    learned_along = [math.atan2(axis[1], axis[0])]
    directions = passing_directions(nominal, scene.positions, axis)
    precisions, obstacles, swerve = {}, [], {}
    for i, obstacle in enumerate(scene.obstacles):
        beta = math.atan2(directions[i, 1], directions[i, 0])
        # A Gaussian response is the same turned by π: the shown direction nearest mod π.
        alpha = min(
            (shown or {}).get(obstacle.label) or learned_along,
            key=lambda a: abs((beta - a + math.pi / 2) % math.pi - math.pi / 2),
        )
        cos, sin = math.cos(alpha), math.sin(alpha)
        axes = np.array([[cos, -sin], [sin, cos]])  # columns: along and across, in the room
        label = f"{obstacle.label}#{i}"
        matrix = axes.T @ reward.precision_of(Scene((obstacle,)))[0] @ axes
        precisions[label] = 0.5 * (matrix + matrix.T)
        if obstacle.label in reward.swerve:  # along the path already: it turns with it
            swerve[label] = reward.swerve[obstacle.label]
        obstacles.append(dataclasses.replace(obstacle, label=label))
    return (
        Reward(reward.nominal_weight, precisions, swerve, along_path=True),
        Scene(tuple(obstacles)),
    )
