"""Seeded emulation data sets: demonstrations around obstacles from a known true reward.

The thesis's obstacle data sets (§5.5, §6.3, §6.4) are not public, so each one
is regenerated here by a synthetic *demonstrator* whose reward is known
exactly. Every generator returns an :class:`EmulationSet`; the learned reward
of an inverse-optimal-control fit (:class:`lfdkit.emulate.IOC`) can be
compared with :attr:`EmulationSet.true_reward`.

The demonstrator
----------------
A demonstration in a scene is made in three steps.

1. **Plan.** The full-horizon optimal path of the true reward (thesis eq. 5.4)
   ``R(x) = −Q |x − x_N|² − Σ_o exp(−(x − O_o)ᵀ P_c (x − O_o))`` along the
   true nominal, ``plan_path(true_reward, nominal, scene,
   n_points=plan_points)`` (:func:`lfdkit.emulate.plan_path`; ``plan_points =
   100`` by default, the thesis's "one hundred time steps"). It starts exactly
   at the nominal's start.
2. **Noise.** Each plan point is moved along the plan's own normals
   (:func:`lfdkit.core.geometry.left_normals` in 2-D; in 3-D the two rows of the
   parallel-transported :func:`lfdkit.core.geometry.normal_frames`) by smooth random
   functions of the plan's normalised arc length ``u``: sums of three
   sinusoids with frequencies uniform in 0.5-3 cycles per path, random phases
   and amplitudes, scaled so that their standard deviation over ``u`` is
   ``noise`` (the same construction as :mod:`lfdkit.datasets.synthetic`; the
   magnitude never exceeds ``sqrt(6) * noise``). The defaults are about
   1.5 mm per metre of nominal path (0.15 % of its length), which is 2-3 % of
   the obstacle's lateral response width ``1 / sqrt(nᵀ P n)`` in every
   setting (table below). ``noise=0`` gives the noise-free demonstrator;
   the random draws are consumed all the same, so the scenes of a seed do
   not depend on ``noise``.
3. **Sampling.** The noisy polyline is resampled to ``n_points`` points
   equally spaced in arc length.

===============  =========  ==============  ============  ==================
setting          length     noise (default) lateral width noise / width
===============  =========  ==============  ============  ==================
artificial       1.02 m     1.5 mm          49-68 mm      2.2-3.1 %
da_vinci_marker  0.152 m    0.25 mm         10.8 mm       2.3 %
sweeping         0.80 m     1.0 mm          32 / 34 mm    3.2 % / 3.0 %
===============  =========  ==============  ============  ==================

Conventions
-----------
* Every random draw comes from one ``numpy.random.Generator`` built by
  :func:`lfdkit.core.validation.check_random_state` from ``seed``; the same integer
  seed gives bit-identical arrays. Draws are made demonstration by
  demonstration (its obstacle, then its noise), so the first ``k``
  demonstrations of a seed do not depend on how many follow (within a class
  for :func:`sweeping`).
* Held-out scenes are fixed designs (no random draws): the same for every seed.
* Positions are in metres; precisions in 1/m², in world axes (as the thesis's
  ``R = diag(…)``).
* Obstacles near the nominal are placed by their arc-length fraction ``u``
  along the nominal and a signed lateral offset along the nominal's normal
  there, measured in units of the obstacle's lateral response width
  ``w = 1 / sqrt(nᵀ P n)``. Lateral offsets are at least ``0.2 w`` so the
  side the demonstrator passes on is never a coin toss.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lfdkit.core.geometry import arc_length, left_normals, normal_frames, point_tangents, resample
from lfdkit.core.units import check_units
from lfdkit.core.validation import check_demos, check_path, check_positive, check_random_state
from lfdkit.datasets._shared import SizedDemoSet, check_count_at_least, generate, smooth_offset
from lfdkit.datasets.synthetic import DA_VINCI_TOP, da_vinci_polyline, da_vinci_wall_outlines
from lfdkit.emulate.planner import plan_path
from lfdkit.emulate.reward import Reward
from lfdkit.model.scene import Scene

__all__ = [
    "CUP_RADIUS",
    "EMULATION_DATASETS",
    "MARKER_RADIUS",
    "SWEEP_GOAL",
    "SWEEP_START",
    "EmulationSet",
    "artificial_obstacles",
    "da_vinci_marker",
    "load_emulation_dataset",
    "sweeping",
]

#: Points of the ground-truth ``nominal`` returned in every :class:`EmulationSet`.
_N_NOMINAL = 500
#: Points of the fine construction polyline of each nominal.
_N_FINE = 4001
#: Frequencies (cycles per path) of the smooth demonstration noise.
_NOISE_FREQ = (0.5, 3.0)
#: Smallest and largest lateral offset of a random obstacle, in response widths.
_LATERAL = (0.2, 1.0)


# --------------------------------------------------------------------- data model
@dataclass(frozen=True, eq=False)
class EmulationSet(SizedDemoSet):
    """Demonstrations in scenes with obstacles, by a demonstrator whose reward is known.

    Attributes
    ----------
    name : str
        The generator's key in :data:`EMULATION_DATASETS`.
    nominal : ndarray, shape (M, q)
        The true nominal path (``M = 500`` for every generator here, q 2 or 3):
        what the demonstrator follows when there is no obstacle.
    demos : list of ndarray, each shape (n_j, q)
        The demonstrations, float64, in the direction of ``nominal``.
    scenes : list of Scene
        ``scenes[j]`` holds the obstacles of demonstration ``j`` (q-D positions).
    true_reward : Reward
        The reward the demonstrator maximises (its ``nominal_weight`` and one
        precision per obstacle class).
    units : str
        Unit of every coordinate, one of :data:`lfdkit.core.units.UNITS` (the
        generators here use ``"m"`` or ``"mm"``).
    train, test : ndarray of int, shape (n_train,), (n_test,)
        Indices into ``demos``: disjoint, together every demonstration once;
        ``train`` non-empty.
    walls : tuple of ndarray, each shape (n_w, q)
        Polylines of environment constraints, for drawing and checks; may be empty.
    description : str
        How the set was made and what its ground truth is.
    held_out_scenes : list of Scene
        Unseen scenes for evaluating planning (cluttered, concave or mixed-class
        arrangements); only classes that occur in the training scenes.
    free_demos : list of ndarray, each (n_points, q)
        Demonstrations of the task with no obstacle (the nominal plus the same
        noise): what the mimicking layer learns the nominal path from.

    Raises
    ------
    ValueError
        If a field is inconsistent (the message names it): lengths or
        dimensions that do not match, classes the reward does not know, held-out
        classes absent from the training scenes, or index sets that overlap,
        repeat, fall out of range or miss a demonstration.
    TypeError
        If a field is of the wrong kind (e.g. a scene that is not a :class:`Scene`).

    Notes
    -----
    Equality is identity (``eq=False``). The arrays are not write-protected.
    """

    name: str
    nominal: np.ndarray
    demos: list[np.ndarray]
    scenes: list[Scene]
    true_reward: Reward
    units: str
    train: np.ndarray
    test: np.ndarray
    walls: tuple[np.ndarray, ...] = ()
    description: str = ""
    held_out_scenes: list[Scene] = field(default_factory=list)
    free_demos: list[np.ndarray] = field(default_factory=list)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"name: expected a non-empty string, got {self.name!r}")
        nominal = check_path(self.nominal, "nominal")
        q = nominal.shape[1]
        if q not in (2, 3):
            raise ValueError(f"nominal: expected 2-D or 3-D points, got {q} dimensions")
        demos = check_demos(self.demos, "demos", n_dims=q)
        if not isinstance(self.true_reward, Reward):
            raise TypeError(
                f"true_reward: expected a Reward, got {type(self.true_reward).__name__}"
            )
        if self.true_reward.n_dims not in (None, q):
            raise ValueError(
                f"true_reward: {self.true_reward.n_dims}-D precisions for {q}-D demonstrations"
            )
        scenes = self._check_scenes(self.scenes, "scenes", q)
        if len(scenes) != len(demos):
            raise ValueError(
                f"scenes: expected one scene per demonstration ({len(demos)}), got {len(scenes)}"
            )
        held_out = self._check_scenes(self.held_out_scenes, "held_out_scenes", q)
        check_units(self.units)
        train = _check_indices(self.train, "train", len(demos))
        test = _check_indices(self.test, "test", len(demos))
        if not train.size:
            raise ValueError("train: needs at least one demonstration")
        common = np.intersect1d(train, test)
        if common.size:
            raise ValueError(f"test: indices {common.tolist()} are also in train")
        missing = np.setdiff1d(np.arange(len(demos)), np.concatenate((train, test)))
        if missing.size:
            raise ValueError(f"train, test: demonstrations {missing.tolist()} are in neither set")
        seen = {c for i in train for c in scenes[i].classes}
        for i, scene in enumerate(held_out):
            unseen = [c for c in scene.classes if c not in seen]
            if unseen:
                raise ValueError(
                    f"held_out_scenes[{i}]: obstacle class {unseen[0]!r} does not occur in "
                    "the training scenes"
                )
        walls = tuple(check_path(w, f"walls[{i}]", n_dims=q) for i, w in enumerate(self.walls))
        object.__setattr__(self, "nominal", nominal)
        object.__setattr__(self, "demos", demos)
        object.__setattr__(self, "scenes", scenes)
        object.__setattr__(self, "held_out_scenes", held_out)
        object.__setattr__(self, "train", train)
        object.__setattr__(self, "test", test)
        object.__setattr__(self, "walls", walls)

    def _check_scenes(self, scenes: Any, name: str, q: int) -> list[Scene]:
        if isinstance(scenes, (Scene, str, bytes)) or not isinstance(scenes, Sequence):
            raise TypeError(f"{name}: expected a list of Scene objects")
        out = list(scenes)
        known = self.true_reward.classes
        for i, scene in enumerate(out):
            if not isinstance(scene, Scene):
                raise TypeError(f"{name}[{i}]: expected a Scene, got {type(scene).__name__}")
            if len(scene) and scene.positions.shape[1] != q:
                raise ValueError(
                    f"{name}[{i}]: {scene.positions.shape[1]}-D obstacles for {q}-D demonstrations"
                )
            unknown = [c for c in scene.classes if c not in known]
            if unknown:
                raise ValueError(
                    f"{name}[{i}]: obstacle class {unknown[0]!r} is not in true_reward "
                    f"(classes: {', '.join(known) or 'none'})"
                )
        return out

    @property
    def classes(self) -> tuple[str, ...]:
        """Obstacle classes of the demonstration scenes, in order of first appearance."""
        return tuple(dict.fromkeys(c for scene in self.scenes for c in scene.classes))

    @property
    def train_demos(self) -> list[np.ndarray]:
        """The training demonstrations, in the order of :attr:`train`."""
        return [self.demos[i] for i in self.train]

    @property
    def train_scenes(self) -> list[Scene]:
        """The scenes of the training demonstrations."""
        return [self.scenes[i] for i in self.train]

    @property
    def test_demos(self) -> list[np.ndarray]:
        """The test demonstrations, in the order of :attr:`test`."""
        return [self.demos[i] for i in self.test]

    @property
    def test_scenes(self) -> list[Scene]:
        """The scenes of the test demonstrations."""
        return [self.scenes[i] for i in self.test]

    def true_plan(self, scene: Scene, *, n_points: int = 100) -> np.ndarray:
        """The noise-free demonstrator's path in ``scene``, shape (n_points, q).

        The full-horizon optimum of :attr:`true_reward` along :attr:`nominal`
        with ``n_points`` plan points, found as the demonstrations' plans are
        (see the module notes): with the generator's ``plan_points`` and
        ``noise=0`` it is the demonstration before resampling.

        Raises
        ------
        ValueError
            As :func:`lfdkit.emulate.plan_path`: an unknown class, or the
            start within one response width of an obstacle.
        """
        return _optimal_plan(self.true_reward, self.nominal, scene, n_points)


def _check_indices(value: Any, name: str, n: int) -> np.ndarray:
    arr = np.asarray(value)
    if arr.size == 0:
        return np.zeros(0, dtype=np.intp)
    if arr.ndim != 1 or not np.issubdtype(arr.dtype, np.integer):
        raise ValueError(f"{name}: expected a 1-D array of integer indices, got {arr!r}")
    if arr.min() < 0 or arr.max() >= n:
        raise ValueError(f"{name}: indices must lie in [0, {n - 1}], got {arr.tolist()}")
    if np.unique(arr).size != arr.size:
        raise ValueError(f"{name}: repeated indices in {arr.tolist()}")
    return arr.astype(np.intp)


# --------------------------------------------------------------------- helpers
class _Track:
    """A fine nominal with arc length and normals, to place obstacles beside it."""

    def __init__(self, fine: np.ndarray) -> None:
        self.fine = fine
        self.s = arc_length(fine)
        self.length = float(self.s[-1])
        self.tangents = point_tangents(fine)

    def at(self, u: float) -> tuple[np.ndarray, np.ndarray]:
        """Point and unit tangent at arc-length fraction ``u`` (linear interpolation)."""
        s = u * self.length
        point = np.array([np.interp(s, self.s, self.fine[:, k]) for k in range(2)])
        tangent = np.array([np.interp(s, self.s, self.tangents[:, k]) for k in range(2)])
        return point, tangent / np.linalg.norm(tangent)

    def place(self, u: float, lateral: float, precision: np.ndarray) -> np.ndarray:
        """Position at fraction ``u`` and ``lateral`` response widths left of the nominal."""
        point, tangent = self.at(u)
        normal = np.array([-tangent[1], tangent[0]])
        return point + lateral * _width(precision, normal) * normal

    def local(self, u: float, along: float, across: float) -> np.ndarray:
        """Position ``along`` metres ahead and ``across`` metres left of the point at ``u``."""
        point, tangent = self.at(u)
        return point + along * tangent + across * np.array([-tangent[1], tangent[0]])


def _width(precision: np.ndarray, direction: np.ndarray) -> float:
    """Response width ``1 / sqrt(nᵀ P n)`` of a precision along a unit direction."""
    return float(1.0 / np.sqrt(direction @ precision @ direction))


def _lateral(rng: np.random.Generator) -> float:
    """Signed lateral offset in response widths: magnitude in ``_LATERAL``, random side."""
    magnitude = rng.uniform(*_LATERAL)
    return magnitude if rng.random() < 0.5 else -magnitude


def _optimal_plan(reward: Reward, nominal: np.ndarray, scene: Scene, n_points: int) -> np.ndarray:
    """The demonstrator's path: the full-horizon optimum of the true reward.

    The thesis's model, without a goal term: a demonstrator who swerved late
    may end beside the goal, as the thesis's demonstrations do.
    """
    return plan_path(reward, nominal, scene, n_points=n_points, goal_approach=None).points


class _Demonstrator:
    """The synthetic demonstrator of one data set (see the module notes).

    Holds the true reward and nominal, the random generator and the noise and
    sampling settings, checked once; makes the demonstrations and, last, the
    :class:`EmulationSet`.
    """

    def __init__(
        self,
        reward: Reward,
        nominal: np.ndarray,
        seed: Any,
        noise: Any,
        n_points: Any,
        plan_points: Any,
    ) -> None:
        self.noise = check_positive(noise, "noise", allow_zero=True)
        self.n_points = check_count_at_least(n_points, "n_points", 2)
        self.plan_points = check_count_at_least(plan_points, "plan_points", 3)
        self.rng = check_random_state(seed)
        self.reward = reward
        self.nominal = nominal

    def demonstrate(self, scene: Scene) -> np.ndarray:
        """One demonstration: the true optimal plan, smooth normal noise, resampled."""
        plan = _optimal_plan(self.reward, self.nominal, scene, self.plan_points)
        q = plan.shape[1]
        s = arc_length(plan)
        u = s / s[-1]
        if q == 2:
            normals = left_normals(plan)[:, None, :]
        else:
            normals = normal_frames(point_tangents(plan))[:, 1:, :]
        path = plan.copy()
        for i in range(q - 1):
            offset = smooth_offset(self.rng, u, self.noise, freq=_NOISE_FREQ)
            path += offset[:, None] * normals[:, i, :]
        return resample(path, self.n_points)

    def emulation_set(
        self,
        name: str,
        demos: list[np.ndarray],
        scenes: list[Scene],
        split: tuple[np.ndarray, np.ndarray],
        n_free: Any,
        **fields: Any,
    ) -> EmulationSet:
        """The data set, with ``n_free`` demonstrations with no obstacle drawn last.

        The free demonstrations (the nominal plus noise, for learning the
        nominal) come after every other draw, so the other demonstrations do
        not depend on ``n_free``. ``split`` is ``(train, test)``; ``fields``
        are the remaining :class:`EmulationSet` fields.
        """
        n_free = check_count_at_least(n_free, "n_free", 0)
        free_demos = [self.demonstrate(Scene()) for _ in range(n_free)]
        train, test = split
        return EmulationSet(
            name=name,
            nominal=self.nominal,
            demos=demos,
            scenes=scenes,
            true_reward=self.reward,
            units="m",
            train=train,
            test=test,
            free_demos=free_demos,
            **fields,
        )


def _split(n: int, n_test: int, offset: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """First ``n − n_test`` indices for training, the last ``n_test`` for testing."""
    idx = np.arange(offset, offset + n)
    return idx[: n - n_test], idx[n - n_test :]


# --------------------------------------------------------------------- §5.5 artificial
# Thesis parameters (precisions P = R⁻¹ in 1/m², world axes, here and below).
_ARTIFICIAL_Q = 10.0
_ARTIFICIAL_P = (2500.0, 215.0)
#: Physical radius of the artificial obstacles, metres.
_OBSTACLE_RADIUS = 0.02


def _artificial_nominal() -> np.ndarray:
    """Fine gentle S from (0, 0) to (1, 0) m: ``y = 0.05 sin(2π x)``, shape (_N_FINE, 2)."""
    x = np.linspace(0.0, 1.0, 20001)
    return resample(np.column_stack((x, 0.05 * np.sin(2.0 * np.pi * x))), _N_FINE)


def artificial_obstacles(
    seed: Any = None,
    n_demos: int = 8,
    noise: float = 0.0015,
    n_points: int = 100,
    *,
    plan_points: int = 100,
    n_free: int = 5,
) -> EmulationSet:
    """Artificial demonstrations, one obstacle per scene (thesis §5.5, Figs 5.8-5.11).

    Nominal (metres): the gentle S ``y = 0.05 sin(2π x)``, ``x`` from 0 to 1
    (length about 1.02 m, at most 17° from the ``x`` axis). True reward:
    ``Q = 10`` and class ``"obstacle"`` with precision ``P = diag(2500, 215)``
    1/m² (the thesis's "Q = 10 and R = [2500, 215]", read as the precision):
    a response 2 cm wide along the path (``x``) and 6.8 cm across it (``y``).

    Scene ``j`` has one obstacle (radius 0.02 m) at arc-length fraction
    ``u ~ U[0.2, 0.8]`` of the nominal, offset along the nominal's left normal
    by ``±U[0.2, 1.0]`` response widths (random side; the width
    ``1 / sqrt(nᵀ P n)`` is 4.9-6.8 cm, least where the S is steepest). The
    demonstrator passes it on the far side, 6-9.5 cm off the nominal at the
    peak (more for an obstacle nearer the path), at least 6.4 cm from its
    centre. The response is so
    short along the path that the swerve is a tent: out and back at the
    planner's largest slope (45°), peaking beside the obstacle.

    Parameters
    ----------
    seed : None, int or numpy.random.Generator
    n_demos : int
        Number of demonstrations (thesis: 8).
    noise : float
        Standard deviation of the smooth normal noise, metres (default
        1.5 mm, 2.2-3.1 % of the lateral response width); 0 for the noise-free
        demonstrator.
    n_points : int
        Points per demonstration, equally spaced in arc length.
    plan_points : int
        Points ``K`` of the demonstrator's plan (:func:`lfdkit.emulate.plan_path`).

    Returns
    -------
    EmulationSet
        ``n_demos`` arrays of shape ``(n_points, 2)`` in metres; ``nominal`` of
        shape ``(500, 2)``; ``train`` the first ``n_demos - n_demos // 4``
        demonstrations (6 of 8), ``test`` the last ``n_demos // 4`` (2).
        ``held_out_scenes``: [0] a cluttered scene, four obstacles spread along
        the path on alternating sides (thesis Fig 6.12); [1] the concave
        arrangement of Fig 5.8, five obstacles on a half circle of radius
        0.08 m centred on the nominal at ``u = 0.45``, its opening towards the
        oncoming path, so that a path going straight on would be caught in the
        pocket. Under the true reward the full-horizon plan goes round the
        pocket (3.4 cm clear of every obstacle), while the receding-horizon
        plan with ``H = 8`` or ``12`` cuts through an obstacle's radius.
    """
    n_demos = check_count_at_least(n_demos, "n_demos")
    fine = _artificial_nominal()
    track = _Track(fine)
    reward = Reward(_ARTIFICIAL_Q, {"obstacle": _ARTIFICIAL_P})
    demonstrator = _Demonstrator(
        reward, resample(fine, _N_NOMINAL), seed, noise, n_points, plan_points
    )
    rng, noise = demonstrator.rng, demonstrator.noise
    precision = reward.precisions["obstacle"]

    def scene_of(positions: list[np.ndarray]) -> Scene:
        return Scene.from_arrays(
            ["obstacle"] * len(positions), positions, [_OBSTACLE_RADIUS] * len(positions)
        )

    demos, scenes = [], []
    for _ in range(n_demos):
        u = rng.uniform(0.2, 0.8)
        scene = scene_of([track.place(u, _lateral(rng), precision)])
        demos.append(demonstrator.demonstrate(scene))
        scenes.append(scene)
    cluttered = scene_of(
        [
            track.place(u, lat, precision)
            for u, lat in ((0.22, 0.5), (0.42, -0.4), (0.6, 0.6), (0.8, -0.3))
        ]
    )
    angles = np.deg2rad([90.0, 45.0, 0.0, -45.0, -90.0])
    concave = scene_of([track.local(0.45, 0.08 * np.cos(a), 0.08 * np.sin(a)) for a in angles])
    return demonstrator.emulation_set(
        "artificial",
        demos,
        scenes,
        _split(n_demos, n_demos // 4),
        n_free,
        description=(
            f"Thesis §5.5: {n_demos} demos along the S y = 0.05 sin(2πx) m, x in [0, 1], one "
            "obstacle per scene at u ~ U[0.2, 0.8] and ±U[0.2, 1] response widths off the "
            f"path; demonstrator = optimal plan ({demonstrator.plan_points} points) of Q = 10, "
            f"P = diag(2500, 215) 1/m², plus smooth normal noise sd {noise:g} m, resampled "
            f"to {demonstrator.n_points} points. Held out: 4-obstacle clutter, 5-obstacle "
            "concave pocket."
        ),
        held_out_scenes=[cluttered, concave],
    )


# --------------------------------------------------------------------- §6.3 da Vinci
_DA_VINCI_Q = 200.0
_DA_VINCI_P = (475.8, 8576.3, 8576.3)
#: Physical radius of a marker (da Vinci and sweeping), metres.
MARKER_RADIUS = 0.01


def da_vinci_marker(
    seed: Any = None,
    n_demos: int = 12,
    noise: float = 0.00025,
    n_points: int = 100,
    *,
    plan_points: int = 100,
    n_free: int = 5,
) -> EmulationSet:
    """3-D pick-and-place between two walls around a marker (thesis §6.3, Figs 6.6-6.8).

    Nominal and walls are those of :func:`lfdkit.datasets.synthetic.da_vinci_walls`
    (metres): from (0, 0, 0) up to the transport height z = 0.035, along ``x``
    and down to (0.1, 0, 0.005), length about 0.152 m, between the walls
    ``y = ±0.025``. True reward: ``Q = 200`` and class ``"marker"`` with
    precision ``P = diag(475.8, 8576.3, 8576.3)`` 1/m². The thesis gives
    ``R⁻¹ = diag(475.8, 8576.3)`` for its planar (top, ``x``-``y``) view; the
    third (``z``) value repeats the second, so the marker is as narrow
    vertically as sideways. Its response is 4.6 cm wide along ``x`` and
    1.08 cm in ``y`` and ``z``: it reaches over most of the 7 cm straight
    transport segment, so the demonstrator shifts sideways over the whole
    transport rather than making a local dodge.

    Scene ``j`` has one marker (radius 0.01 m) at ``x ~ U[0.03, 0.07]`` (the
    middle of the transport segment), at the transport height ``z = 0.035``
    (so swerves are horizontal, as in the thesis's planar view) and
    ``y = ±U[0.2, 1.0] × 1.08 cm`` (random side). So the marker never reaches
    into a wall (``|y| + 0.01 <= 0.0208 < 0.025``) and the start is more than
    three response widths from it (``(x − O)ᵀ P (x − O) > 10``; the planner
    refuses a start below 1). The demonstrator passes on the far side,
    1.2-1.9 cm off the nominal, more than 2 cm from the marker's centre and
    more than 5 mm from the walls.

    Parameters
    ----------
    seed : None, int or numpy.random.Generator
    n_demos : int
        Number of demonstrations (the thesis recorded 8).
    noise : float
        Standard deviation of each smooth normal noise component, metres
        (default 0.25 mm, 2.3 % of the lateral response width).
    n_points : int
        Points per demonstration, equally spaced in arc length.
    plan_points : int
        Points ``K`` of the demonstrator's plan.

    Returns
    -------
    EmulationSet
        Arrays of shape ``(n_points, 3)`` in metres; ``nominal`` of shape
        ``(500, 3)``; ``walls`` two closed rectangles of shape ``(5, 3)``;
        ``train`` the first ``n_demos - n_demos // 3`` (8 of 12), ``test`` the
        last ``n_demos // 3`` (4). ``held_out_scenes``: three single-marker
        scenes at fixed positions (x, y) = (0.035, 0.009), (0.05, −0.004),
        (0.068, 0.0015) m (the last closer to the path than any training
        marker), and one with two markers on the same side, (0.035, 0.006)
        and (0.065, 0.004) m, all at z = 0.035.

    Notes
    -----
    Because the ``z`` precision equals the ``y`` one, a marker is a point that
    can also be passed over or under. With one marker beside the path the
    optimum is a sideways dodge (the training scenes); with two markers on
    opposite sides of the path the optimum dodges *vertically* by about 2 cm,
    which a standing marker would not allow, so no held-out scene has that
    arrangement.
    """
    n_demos = check_count_at_least(n_demos, "n_demos")
    reward = Reward(_DA_VINCI_Q, {"marker": _DA_VINCI_P})
    demonstrator = _Demonstrator(
        reward,
        resample(resample(da_vinci_polyline(), _N_FINE), _N_NOMINAL),
        seed,
        noise,
        n_points,
        plan_points,
    )
    rng, noise = demonstrator.rng, demonstrator.noise
    width = _width(reward.precisions["marker"], np.array([0.0, 1.0, 0.0]))

    def scene_of(xy: Sequence[tuple[float, float]]) -> Scene:
        positions = [[x, y, DA_VINCI_TOP] for x, y in xy]
        return Scene.from_arrays(["marker"] * len(xy), positions, [MARKER_RADIUS] * len(xy))

    demos, scenes = [], []
    for _ in range(n_demos):
        x = rng.uniform(0.03, 0.07)
        scene = scene_of([(x, _lateral(rng) * width)])
        demos.append(demonstrator.demonstrate(scene))
        scenes.append(scene)
    held_out = [
        scene_of([(0.035, 0.009)]),
        scene_of([(0.05, -0.004)]),
        scene_of([(0.068, 0.0015)]),
        scene_of([(0.035, 0.006), (0.065, 0.004)]),
    ]
    return demonstrator.emulation_set(
        "da_vinci_marker",
        demos,
        scenes,
        _split(n_demos, n_demos // 3),
        n_free,
        walls=da_vinci_wall_outlines(),
        description=(
            f"Thesis §6.3: {n_demos} 3-D pick-and-place demos between walls y = ±0.025 m, one "
            "marker per scene at x ~ U[0.03, 0.07], |y| ~ U[0.2, 1] * 1.08 cm, z = 0.035 m; "
            f"demonstrator = optimal plan ({demonstrator.plan_points} points) of Q = 200, "
            "P = diag(475.8, 8576.3, 8576.3) 1/m² (thesis planar R⁻¹, z repeats y), plus "
            f"smooth normal noise sd {noise:g} m per normal direction, resampled to "
            f"{demonstrator.n_points} points. Held out: 3 unseen marker positions and 2 markers "
            "on one side."
        ),
        held_out_scenes=held_out,
    )


# --------------------------------------------------------------------- §6.4 sweeping
_SWEEPING_Q = 20.0
_CUP_P = (15.4, 1000.0)
_MARKER_P = (20.08, 880.0)
#: Physical radius of a cup, metres. A 6 cm cup: the thesis's cup response is 3.2 cm wide
#: across the path, so the optimum of its reward can graze a wider cup in a cluttered scene.
CUP_RADIUS = 0.03
#: Start (the cube) of the sweeping nominal, UR5 base frame, metres.
SWEEP_START = (-0.40, 0.45)
#: Goal (in the dustpan) of the sweeping nominal, UR5 base frame, metres.
SWEEP_GOAL = (0.40, 0.45)


def sweeping(
    seed: Any = None,
    n_cup: int = 6,
    n_marker: int = 6,
    noise: float = 0.001,
    n_points: int = 90,
    *,
    plan_points: int = 100,
    n_free: int = 5,
) -> EmulationSet:
    """Table-top sweeping of a cube into a dustpan around a cup or a marker (thesis §6.4).

    Nominal (metres, the table plane in the UR5 base frame of thesis Fig 6.14,
    ``x`` along the table's width): the straight sweep from the cube at
    (−0.4, 0.45) to the dustpan at (0.4, 0.45), 0.8 m. True reward: ``Q = 20``;
    class ``"cup"`` with ``P = diag(15.4, 1000)`` and class ``"marker"`` with
    ``P = diag(20.08, 880)`` 1/m² (the thesis's ``R_c = diag(1/15.4, 1/1000)``,
    ``R_m = diag(1/20.08, 1/880)``).

    These responses are 3.2 cm (cup) and 3.4 cm (marker) wide across the
    path but 25 cm and 22 cm wide *along* it (``x``): an obstacle in the middle
    of the path still weighs ``exp(−15.4 × 0.4²) ≈ 0.085`` at the cube and at
    the dustpan, so the response spans the whole sweep. The demonstrator leaves
    the cube at the largest allowed slope (45°), passes the obstacle 3.6-6 cm
    off the nominal (6.3-7.1 cm from its centre) and does not fully come back:
    it ends 0.3-3.1 cm beside the dustpan, on the side it passed on. The path
    runs along ``x`` because along ``y`` the thesis numbers would swerve by
    less than the cup's radius (the demonstrator would hit the cup); and it is
    straight because on a curved nominal the long world-aligned response makes
    S-shaped swerves. The thesis numbers are kept unchanged. For about one
    scene in eight ``plan_path`` alone returns the pass on the obstacle's own
    side, at up to three times the optimal cost; ``plan_path`` now also restarts
    from the mirror image of its best plan and finds the cheaper far side.

    Scene ``j`` has one obstacle, a cup (radius 0.03 m) for the first ``n_cup``
    demonstrations, then a marker (radius 0.01 m) for the next ``n_marker``, at
    arc-length fraction ``u ~ U[0.35, 0.5]`` (0.28-0.40 m from the cube, so the
    cube is more than one response width away as the planner requires) and
    ``±U[0.2, 1.0]`` lateral response widths off the path (random side).

    Parameters
    ----------
    seed : None, int or numpy.random.Generator
    n_cup, n_marker : int
        Number of demonstrations with a cup and with a marker (each >= 1).
    noise : float
        Standard deviation of the smooth normal noise, metres (default 1 mm,
        3 % of the lateral response width).
    n_points : int
        Points per demonstration (thesis: 90 data points played back).
    plan_points : int
        Points ``K`` of the demonstrator's plan.

    Returns
    -------
    EmulationSet
        Arrays of shape ``(n_points, 2)`` in metres; ``nominal`` of shape
        ``(500, 2)``. Split per class: of each class, the first
        ``n - n // 3`` demonstrations train and the last ``n // 3`` test
        (4 + 2 of each with the defaults). ``held_out_scenes`` (positions as
        (u, lateral offset in metres)): [0]-[2] a cup and a marker together
        (mixed classes, thesis Fig 6.15): cup (0.38, +0.02) with marker
        (0.62, −0.015); marker (0.4, −0.01) with cup (0.6, +0.025); cup
        (0.45, −0.03) with marker (0.55, +0.02); [3] a cluttered scene, two
        cups and two markers alternating along the path: cup (0.36, 0.04),
        marker (0.46, −0.03), cup (0.56, 0.05), marker (0.66, −0.04).
    """
    n_cup = check_count_at_least(n_cup, "n_cup")
    n_marker = check_count_at_least(n_marker, "n_marker")
    x = np.linspace(SWEEP_START[0], SWEEP_GOAL[0], 2001)
    fine = resample(np.column_stack((x, np.linspace(SWEEP_START[1], SWEEP_GOAL[1], 2001))), 2001)
    track = _Track(fine)
    reward = Reward(_SWEEPING_Q, {"cup": _CUP_P, "marker": _MARKER_P})
    demonstrator = _Demonstrator(
        reward, resample(fine, _N_NOMINAL), seed, noise, n_points, plan_points
    )
    rng, noise = demonstrator.rng, demonstrator.noise
    radius = {"cup": CUP_RADIUS, "marker": MARKER_RADIUS}

    def scene_of(items: Sequence[tuple[str, np.ndarray]]) -> Scene:
        return Scene.from_arrays(
            [c for c, _ in items], [p for _, p in items], [radius[c] for c, _ in items]
        )

    demos, scenes = [], []
    for label, count in (("cup", n_cup), ("marker", n_marker)):
        for _ in range(count):
            u = rng.uniform(0.35, 0.5)
            position = track.place(u, _lateral(rng), reward.precisions[label])
            scene = scene_of([(label, position)])
            demos.append(demonstrator.demonstrate(scene))
            scenes.append(scene)
    held_out = [
        scene_of([(label, track.local(u, 0.0, across)) for label, u, across in design])
        for design in (
            (("cup", 0.38, 0.02), ("marker", 0.62, -0.015)),
            (("marker", 0.4, -0.01), ("cup", 0.6, 0.025)),
            (("cup", 0.45, -0.03), ("marker", 0.55, 0.02)),
            (
                ("cup", 0.36, 0.04),
                ("marker", 0.46, -0.03),
                ("cup", 0.56, 0.05),
                ("marker", 0.66, -0.04),
            ),
        )
    ]
    cup_train, cup_test = _split(n_cup, n_cup // 3)
    marker_train, marker_test = _split(n_marker, n_marker // 3, offset=n_cup)
    return demonstrator.emulation_set(
        "sweeping",
        demos,
        scenes,
        (np.concatenate((cup_train, marker_train)), np.concatenate((cup_test, marker_test))),
        n_free,
        description=(
            f"Thesis §6.4: {n_cup} cup + {n_marker} marker sweeping demos along the straight "
            "0.8 m nominal (-0.4, 0.45) -> (0.4, 0.45) m, one obstacle per scene at "
            "u ~ U[0.35, 0.5], ±U[0.2, 1] lateral response widths; demonstrator = optimal "
            f"plan ({demonstrator.plan_points} points) of Q = 20, cup P = diag(15.4, 1000), "
            f"marker P = diag(20.08, 880) 1/m², plus smooth normal noise sd {noise:g} m, "
            f"resampled to {demonstrator.n_points} points. The along-path response (25 cm) "
            "spans the whole sweep. Held out: 3 cup + marker scenes and a 4-obstacle clutter."
        ),
        held_out_scenes=held_out,
    )


# --------------------------------------------------------------------- registry
#: Short name -> generator, for every synthetic emulation data set.
EMULATION_DATASETS: dict[str, Callable[..., EmulationSet]] = {
    "artificial": artificial_obstacles,
    "da_vinci_marker": da_vinci_marker,
    "sweeping": sweeping,
}


def load_emulation_dataset(name: str, seed: Any = None, **kwargs: Any) -> EmulationSet:
    """The emulation data set ``name``, a key of :data:`EMULATION_DATASETS`.

    As :func:`lfdkit.datasets.load_dataset` for the mimicking sets: ``seed`` and
    ``kwargs`` go to the generator, and an unknown ``name`` raises
    ``ValueError`` listing the valid names.
    """
    return generate(EMULATION_DATASETS, "emulation data set", name, seed, kwargs)
