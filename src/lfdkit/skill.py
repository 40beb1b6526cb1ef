"""The layered skill: mimic → imitate → emulate, in one object (thesis Fig 1.4 and 5.2).

A :class:`Skill` learns, in order,

1. **mimic**: the generalized path of clean demonstrations (no obstacle),
   :class:`lfdkit.mimic.MeanPath` (default) or any method of
   :data:`lfdkit.mimic.MIMIC_METHODS`;
2. **imitate**: a :class:`lfdkit.imitate.DMP` trained on that path, which
   carries it to a new start and goal;
3. **emulate**: from demonstrations recorded around obstacles, one
   :class:`lfdkit.emulate.Reward` term per obstacle class, by inverse optimal
   control (:class:`lfdkit.emulate.IOC`).

:meth:`Skill.plan` then does what the thesis's robot does in a new scene: the
DMP retargets the generalized path to the new start and goal (the *nominal*),
and the planner (receding-horizon MPC by default, or the full-horizon
optimum) moves along it around the scene's obstacles.

Each layer can be learned on its own (:meth:`Skill.fit_path`,
:meth:`Skill.fit_reward`) or taken from elsewhere (:meth:`Skill.use_path`,
:meth:`Skill.adopt`, e.g. an obstacle class learned in another skill).

Files
-----
:meth:`Skill.save` writes one JSON document, ``{"format": "lfdkit-skill",
"version": 1, ...}``, with every number written exactly (floats round-trip
bit for bit) and no pickle; the format, its limits and its strict reader are
:mod:`lfdkit.io.skill_file`.

The same fitted skill always writes the same bytes: the file holds no date
and no run times (those stay on the object, in :attr:`Skill.mimic_info_` and
:attr:`Skill.ioc_info_`, for reports), so skill files can be compared and
cached.

:meth:`Skill.load` refits the DMP from the stored path and parameters (a
deterministic closed-form fit), so a loaded skill plans exactly as the saved
one. A file from a newer format version, or one with a missing or broken
field, is refused with a message naming the file and the field.
"""

from __future__ import annotations

import os
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import Any, Literal, NamedTuple

import numpy as np

from lfdkit import metrics
from lfdkit._estimator import Estimator, check_fitted
from lfdkit._options import MAX_HORIZON, MIN_HORIZON, PLANNERS, SCALINGS, SKILL_DEFAULTS, TIMINGS
from lfdkit._validation import check_demos, check_path, check_point, check_positive
from lfdkit.demos import DemoId
from lfdkit.emulate import IOC, Plan, Reward, plan_path
from lfdkit.imitate import DMP
from lfdkit.io import load_demos, skill_file
from lfdkit.io.scenes import load_scenes
from lfdkit.io.skill_file import (
    MAX_SKILL_FILE_BYTES,
    SKILL_FILE_LIMITS,
    SKILL_FORMAT,
    SKILL_VERSION,
)
from lfdkit.mimic import MIMIC_METHODS, DemoOrientationWarning, MimicSettings
from lfdkit.scene import Scene

# The skill-file constants live with the format (lfdkit.io.skill_file); re-exported here.
__all__ = [
    "MAX_SKILL_FILE_BYTES",
    "SKILL_FILE_LIMITS",
    "SKILL_FORMAT",
    "SKILL_VERSION",
    "Skill",
    "TrainingData",
    "learn",
    "read_training_data",
]

PlannerKind = Literal["mpc", "full"]
Progress = Callable[[str], None]

# Samples of a DMP rollout handed to the planner, which resamples it at
# constant speed: dense enough that the resampled nominal follows the curve.
_NOMINAL_OVERSAMPLING = 4


class Skill(Estimator):
    """A task learned from demonstrations: generalized path, DMP and obstacle reward.

    Parameters
    ----------
    mimic : str
        How the generalized path is computed from the clean demonstrations: a
        key of :data:`lfdkit.mimic.MIMIC_METHODS` ("mean_path", the default,
        Mean-Path with its default adaptive centre; "mean_path_mean",
        "mean_path_median", "mean_path_biweight", "gmr", "nlpca", "average").
    n_points : int
        Points of the generalized path and of every plan (thesis: 100).
    n_components : int
        Gaussian components when ``mimic="gmr"``.
    n_basis : int or "auto"
        DMP basis functions per dimension, or ``"auto"`` (default): the
        fewest that reproduce the path within 1 % of its extent
        (:class:`lfdkit.imitate.DMP`; the count used is ``dmp_.n_basis_``).
    timing : {"minimum_jerk", "uniform"}
        Times assigned to the generalized path for the DMP fit
        (:meth:`lfdkit.imitate.DMP.fit`).
    duration : float
        Duration of the movement, seconds.
    scaling : {"translate", "spatial", "per_dimension"}
        How the DMP carries the path to a new start and goal
        (:class:`lfdkit.imitate.DMP`). ``"translate"`` keeps the shape and
        blends the start and goal offsets in along the movement: defined for
        closed shapes, and the closest to held-out demonstrations (1.00 times
        the affine warp on LASA against 1.09 for ``"spatial"``).
        ``"spatial"`` rotates and scales the whole shape with the start→goal
        vector, for goals in another direction; ``"per_dimension"`` is the
        thesis's.
    planner : {"mpc", "full"}
        Receding-horizon MPC (as on the robot) or the full-horizon optimum; the
        reward fit is staged (full horizon, then MPC) for ``"mpc"``.
    horizon : int
        MPC horizon ``H``, 4 to 12.
    max_slope : float
        Largest sideways step per step along the nominal (the action box).
    classes : sequence of str, optional
        Obstacle classes to learn (default: those in the training scenes).
    random_state : int, optional
        Seed of the mimic method's random initialisation (GMR, NLPCA; the
        other layers are deterministic).
    units : str
        Unit of every coordinate (for files and figures).

    Attributes
    ----------
    path_ : ndarray, shape (n_points, q)
        The generalized path.
    mimic_ : estimator or None
        The fitted mimicking estimator (None after :meth:`use_path` or :meth:`load`).
    mimic_info_ : dict
        How the path was made (method, number of demonstrations, the indices
        of those reversed to the majority's direction under ``"reversed"``,
        the path's length over the median demonstration's under
        ``"length_ratio"``, the mimic method's warnings as text under
        ``"warnings"``, diagnostics).
    dmp_ : DMP
        The DMP trained on ``path_``.
    reward_ : Reward or None
        The obstacle reward (None until :meth:`fit_reward` or :meth:`adopt`).
    ioc_ : IOC or None
        The fitted inverse optimal control (None after :meth:`adopt` or :meth:`load`).
    ioc_info_ : dict or None
        Summary of the reward fit: loss, stages, classes, demonstrations.
    n_dims_ : int
        Dimension ``q`` of the paths.
    """

    def __init__(
        self,
        *,
        mimic: str = SKILL_DEFAULTS["mimic"],
        n_points: int = SKILL_DEFAULTS["n_points"],
        n_components: int = SKILL_DEFAULTS["n_components"],
        n_basis: int | Literal["auto"] = SKILL_DEFAULTS["n_basis"],
        timing: str = SKILL_DEFAULTS["timing"],
        duration: float = SKILL_DEFAULTS["duration"],
        scaling: str = SKILL_DEFAULTS["scaling"],
        planner: PlannerKind = SKILL_DEFAULTS["planner"],
        horizon: int = SKILL_DEFAULTS["horizon"],
        max_slope: float = SKILL_DEFAULTS["max_slope"],
        classes: Sequence[str] | None = SKILL_DEFAULTS["classes"],
        random_state: int | None = SKILL_DEFAULTS["random_state"],
        units: str = SKILL_DEFAULTS["units"],
    ) -> None:
        self.mimic = mimic
        self.n_points = n_points
        self.n_components = n_components
        self.n_basis = n_basis
        self.timing = timing
        self.duration = duration
        self.scaling = scaling
        self.planner = planner
        self.horizon = horizon
        self.max_slope = max_slope
        self.classes = classes
        self.random_state = random_state
        self.units = units

    # ------------------------------------------------------------ parameters
    def _check_params(self) -> None:
        _check_choice(self.mimic, "mimic", tuple(MIMIC_METHODS))
        _check_choice(self.planner, "planner", PLANNERS)
        _check_choice(self.timing, "timing", TIMINGS)
        _check_choice(self.scaling, "scaling", SCALINGS)
        # The ranges a skill file may hold (SKILL_FILE_LIMITS), so what is built in
        # code can always be saved and loaded again.
        for name in ("n_points", "n_components", "n_basis"):
            if name == "n_basis" and isinstance(self.n_basis, str) and self.n_basis == "auto":
                continue  # the DMP chooses the count
            value = check_positive(getattr(self, name), name, integer=True)
            low, high = SKILL_FILE_LIMITS[name]
            if not low <= value <= high:
                raise ValueError(f"{name}: expected {low} to {high:g}, got {value}")
        for name in ("duration", "max_slope"):
            value = check_positive(getattr(self, name), name)
            if value > SKILL_FILE_LIMITS[name][1]:
                raise ValueError(
                    f"{name}: expected at most {SKILL_FILE_LIMITS[name][1]:g}, got {value:g}"
                )
        if not isinstance(self.horizon, (int, np.integer)) or not (
            MIN_HORIZON <= int(self.horizon) <= MAX_HORIZON
        ):
            raise ValueError(
                f"horizon: expected an integer {MIN_HORIZON} <= H <= {MAX_HORIZON}, "
                f"got {self.horizon!r}"
            )
        if self.classes is not None and (
            isinstance(self.classes, str) or not all(isinstance(c, str) and c for c in self.classes)
        ):
            raise ValueError(f"classes: expected a list of class names, got {self.classes!r}")
        if not isinstance(self.units, str) or not self.units:
            raise ValueError(f"units: expected a non-empty string, got {self.units!r}")

    @property
    def _horizon(self) -> int | None:
        return int(self.horizon) if self.planner == "mpc" else None

    # ------------------------------------------------------------------ fit
    def fit(
        self,
        demos: Sequence[Any],
        obstacle_demos: Sequence[Any] | None = None,
        scenes: Sequence[Scene] | None = None,
        *,
        goals: Any = None,
        progress: Progress | None = None,
    ) -> Skill:
        """Learn every layer: path and DMP from ``demos``, the reward from the rest.

        Parameters
        ----------
        demos : sequence of array_like, each (n_j, q)
            Clean demonstrations (no obstacle), at least 2, q 2 or 3.
        obstacle_demos : sequence of array_like, each (n_j, q), optional
            Demonstrations recorded around obstacles.
        scenes : sequence of Scene, optional
            One per obstacle demonstration.
        goals : array_like, shape (q,) or (n_obstacle_demos, q), optional
            Passed to :meth:`fit_reward`.
        progress : callable, optional
            Called with a short message as each stage starts.

        Returns
        -------
        Skill
            ``self``.
        """
        if (obstacle_demos is None) != (scenes is None):
            raise ValueError("scenes: give obstacle_demos and scenes together, or neither")
        self.fit_path(demos, progress=progress)
        self.reward_ = None
        self.ioc_ = None
        self.ioc_info_ = None
        if obstacle_demos is not None and len(obstacle_demos):
            self.fit_reward(obstacle_demos, scenes, goals=goals, progress=progress)
        elif obstacle_demos is not None and scenes is not None and len(scenes):
            raise ValueError(f"scenes: {len(scenes)} scenes for 0 obstacle demonstrations")
        return self

    def fit_path(self, demos: Sequence[Any], *, progress: Progress | None = None) -> Skill:
        """Learn the generalized path (mimic) and the DMP on it (imitate).

        Parameters
        ----------
        demos : sequence of array_like, each (n_j, q)
            Clean demonstrations, at least 2, all of the same dimension 2 or 3.
        progress : callable, optional

        Returns
        -------
        Skill
            ``self``; an obstacle reward learned before is kept.
        """
        self._check_params()
        demos = check_demos(demos, "demos", min_demos=2, min_points=3)
        q = demos[0].shape[1]
        if q not in (2, 3):
            raise ValueError(f"demos: expected 2-D or 3-D points, got {q} dimensions")
        _tell(progress, f"mimic: {self._mimic_name()} of {len(demos)} demonstrations")
        started = time.perf_counter()
        method = MIMIC_METHODS[self.mimic]
        settings = MimicSettings(
            n_points=int(self.n_points),
            random_state=self.random_state,
            n_components=int(self.n_components),
        )
        # Recorded as well as passed on, so that the skill file and reports keep them.
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            estimator = method.fit(method.build(settings), demos)  # checked above
        path = estimator.path_
        info: dict[str, Any] = method.diagnostics(estimator)
        for warning in caught:
            warnings.warn(warning.message, stacklevel=2)
        # Demonstrations the mimic method turned round to the majority's direction.
        info["reversed"] = [int(j) for j in np.flatnonzero(estimator.reversed_)]
        info["length_ratio"] = float(estimator.length_ratio_)
        info["warnings"] = [
            str(w.message) for w in caught if not issubclass(w.category, DemoOrientationWarning)
        ]
        info = {"method": self.mimic, "n_demos": len(demos), **info}
        info["seconds"] = time.perf_counter() - started
        self.mimic_ = estimator
        self._set_path(path, info, progress)
        return self

    def use_path(self, path: Any, *, source: str = "given") -> Skill:
        """Take a generalized path from elsewhere and train the DMP on it.

        Parameters
        ----------
        path : array_like, shape (n, q)
            The path, q 2 or 3, at least 3 points.
        source : str
            Recorded in :attr:`mimic_info_` (e.g. where the path came from).
        """
        self._check_params()
        path = check_path(path, "path", min_points=3)
        if path.shape[1] not in (2, 3):
            raise ValueError(f"path: expected 2-D or 3-D points, got {path.shape[1]} dimensions")
        self.mimic_ = None
        self._set_path(path, {"method": "given", "source": str(source)}, None)
        return self

    def _set_path(self, path: np.ndarray, info: dict[str, Any], progress: Progress | None) -> None:
        reward = getattr(self, "reward_", None)
        if reward is not None and reward.n_dims not in (None, path.shape[1]):
            raise ValueError(
                f"path: {path.shape[1]}-D, but the obstacle reward is {reward.n_dims}-D"
            )
        self.path_ = np.array(path, dtype=np.float64)
        self.mimic_info_ = info
        self.dmp_ = self._fit_dmp(self.path_)
        chosen = " (n_basis='auto')" if isinstance(self.n_basis, str) else ""
        _tell(
            progress,
            f"imitate: DMP with {self.dmp_.n_basis_} basis functions per dimension{chosen}, "
            f"reproducing the path within {self.dmp_.reproduction_error_:.2%} of its extent",
        )
        self.n_dims_ = int(self.path_.shape[1])
        if not hasattr(self, "reward_"):
            self.reward_ = None
            self.ioc_ = None
            self.ioc_info_ = None

    def _fit_dmp(self, path: np.ndarray) -> DMP:
        n_basis = self.n_basis if isinstance(self.n_basis, str) else int(self.n_basis)
        dmp = DMP(n_basis=n_basis, scaling=self.scaling)
        return dmp.fit(path, duration=float(self.duration), timing=self.timing)

    def fit_reward(
        self,
        demos: Sequence[Any],
        scenes: Sequence[Scene],
        *,
        goals: Any = None,
        progress: Progress | None = None,
    ) -> Skill:
        """Learn the obstacle reward by inverse optimal control (emulate).

        Each demonstration is compared with the plan along its own nominal:
        the DMP from the demonstration's first point to its goal. The goal is
        where the task ends (the dustpan), not where a demonstration that
        swerved around an obstacle happened to stop, so it defaults to the
        generalized path's goal.

        Parameters
        ----------
        demos : sequence of array_like, each (n_j, q)
            Demonstrations recorded around obstacles.
        scenes : sequence of Scene
            One per demonstration.
        goals : array_like, shape (q,) or (n_demos, q), optional
            Goal of each demonstration's nominal (default: the generalized path's goal).
        progress : callable, optional

        Returns
        -------
        Skill
            ``self``.
        """
        self._check_fitted()
        demos = check_demos(demos, "obstacle_demos", n_dims=self.n_dims_)
        scenes = list(scenes)
        if len(scenes) != len(demos):
            raise ValueError(
                f"scenes: {len(scenes)} scenes for {len(demos)} obstacle demonstrations; "
                "give one scene per demonstration"
            )
        for j, scene in enumerate(scenes):
            if not isinstance(scene, Scene):
                raise TypeError(f"scenes[{j}]: expected a Scene, got {type(scene).__name__}")
            if len(scene) and scene.positions.shape[1] != self.n_dims_:
                raise ValueError(
                    f"scenes[{j}]: {scene.positions.shape[1]}-D obstacles for "
                    f"{self.n_dims_}-D demonstrations"
                )
        goal = self._goals(goals, len(demos))
        _tell(progress, "emulate: nominal of each obstacle demonstration (DMP)")
        starts = np.array([demo[0] for demo in demos])
        nominals = list(self._rollouts(starts, goal))
        stages = "full horizon, then MPC" if self.planner == "mpc" else "full horizon"
        _tell(progress, f"emulate: inverse optimal control on {len(demos)} demos ({stages})")
        started = time.perf_counter()
        ioc = IOC(
            self.classes,
            n_points=int(self.n_points),
            horizon=self._horizon,
            max_slope=float(self.max_slope),
        ).fit(demos, scenes, nominals)
        self.ioc_ = ioc
        self.reward_ = ioc.reward_
        self.ioc_info_ = {
            "n_demos": len(demos),
            "classes": list(ioc.classes_),
            "loss": float(ioc.loss_),
            "converged": bool(ioc.converged_),
            "convergence_message": ioc.convergence_message_,
            "not_learned": list(ioc.not_learned_),
            "identifiability": skill_file.jsonable(ioc.identifiability_),
            "seconds": time.perf_counter() - started,
            "stages": skill_file.jsonable(
                [
                    {k: v for k, v in stage.items() if isinstance(v, (int, float, str, bool))}
                    for stage in ioc.stages_
                ]
            ),
        }
        return self

    def _goals(self, goals: Any, n_demos: int) -> np.ndarray:
        """One goal per demonstration, shape (n_demos, q); default the generalized path's."""
        goal = self.path_[-1] if goals is None else goals
        point = check_point(goal, "goals", self.n_dims_, batch="n_demos", style="point")
        if point.ndim == 2 and point.shape[0] not in (1, n_demos):
            raise ValueError(f"goals: {point.shape[0]} goals for {n_demos} demonstrations")
        return np.broadcast_to(point, (n_demos, self.n_dims_))

    def adopt(self, source: Skill | Reward, classes: Sequence[str] | None = None) -> Skill:
        """Reuse obstacle classes learned elsewhere (thesis §6.3.3, composition and transfer).

        Parameters
        ----------
        source : Skill or Reward
            Where the classes were learned.
        classes : sequence of str, optional
            Which classes to take (default all of ``source``'s). A class this
            skill already has is replaced.

        Returns
        -------
        Skill
            ``self``; its nominal weight ``Q`` is kept if it has a reward,
            otherwise taken from ``source``.
        """
        reward = getattr(source, "reward_", None) if isinstance(source, Skill) else source
        if not isinstance(reward, Reward):
            raise ValueError("source: has no learned obstacle reward to adopt")
        wanted = reward.classes if classes is None else tuple(classes)
        missing = [c for c in wanted if c not in reward.precisions]
        if missing:
            raise ValueError(
                f"classes: {missing[0]!r} is not learned in source "
                f"(it has {', '.join(reward.classes) or 'none'})"
            )
        n_dims = getattr(self, "n_dims_", None)
        if n_dims is not None and reward.n_dims not in (None, n_dims):
            raise ValueError(f"source: {reward.n_dims}-D reward for a {n_dims}-D skill")
        taken = Reward(reward.nominal_weight, {c: reward.precisions[c] for c in wanted})
        own = getattr(self, "reward_", None)
        self.reward_ = taken if own is None else own.combined(taken)
        if not hasattr(self, "ioc_"):
            self.ioc_ = None
            self.ioc_info_ = None
        return self

    # ------------------------------------------------------------------ use
    def _check_fitted(self) -> None:
        check_fitted(self, "path_", "skill: not fitted; call fit() or fit_path() first")

    def _rollouts(self, starts: np.ndarray, goals: np.ndarray) -> np.ndarray:
        n_steps = _NOMINAL_OVERSAMPLING * int(self.n_points)
        # Starts and goals come checked (_ends, _goals, check_demos): not again in the DMP.
        return self.dmp_.rollout(starts, goals, n_steps=n_steps, check_input=False).positions

    def nominal(self, start: Any = None, goal: Any = None) -> np.ndarray:
        """The generalized path carried to a new start and goal by the DMP.

        Parameters
        ----------
        start, goal : array_like, shape (q,), optional
            Default: the generalized path's own.

        Returns
        -------
        ndarray, shape (4 n_points, q)
            DMP rollout positions (minimum-jerk timing: denser at the ends).
        """
        return self._nominal(*self._ends(start, goal))

    def _ends(self, start: Any, goal: Any) -> tuple[np.ndarray, np.ndarray]:
        """The start and goal a caller gave, checked (default: the generalized path's)."""
        self._check_fitted()
        q = self.n_dims_
        start = self.path_[0] if start is None else check_point(start, "start", q, style="point")
        goal = self.path_[-1] if goal is None else check_point(goal, "goal", q, style="point")
        return start, goal

    def _nominal(self, start: np.ndarray, goal: np.ndarray) -> np.ndarray:
        """:meth:`nominal` from a checked start and goal."""
        tol = 1e-12 * _extent(self.path_)
        # A closed skill (an "o") goes from a point back to it; an open one cannot.
        closed = np.allclose(self.path_[0], self.path_[-1], rtol=0.0, atol=tol)
        if not closed and np.allclose(start, goal, rtol=0.0, atol=tol):
            raise ValueError("goal: coincides with start; a path needs distinct ends")
        return self._rollouts(start[None], goal[None])[0]

    def plan(
        self, start: Any = None, goal: Any = None, scene: Scene | None = None, **options: Any
    ) -> np.ndarray:
        """The planned path for a new start, goal and scene: ``plan_details(...).points``.

        ndarray, shape (n_points, q), from ``start``; the keyword ``options``
        (``planner``, ``horizon``, ``goal_approach``, ``clearance``), the errors
        and the safety guarantees are :meth:`plan_details`'.
        """
        return self.plan_details(start, goal, scene, **options).points

    def plan_details(
        self,
        start: Any = None,
        goal: Any = None,
        scene: Scene | None = None,
        *,
        planner: PlannerKind | None = None,
        horizon: int | None = None,
        goal_approach: float | str | None = "auto",
        clearance: float = 0.0,
    ) -> Plan:
        """The path for a new start, goal and scene: DMP-retargeted nominal, then MPC.

        Parameters
        ----------
        start, goal : array_like, shape (q,), optional
            Default: the generalized path's own.
        scene : Scene, optional
            Obstacles (default none); each class must have been learned.
        planner : {"mpc", "full"}, optional
            Override the skill's planner.
        horizon : int, optional
            Override the MPC horizon (4 to 12).
        goal_approach : float, "auto" or None
            Length (units of the path) before the goal over which the plan is
            drawn back onto the nominal so that it ends at the goal; "auto"
            (the default) is a tenth of the path. None: the thesis's reward,
            which has no goal term; a swerve can leave the plan's end beside
            the goal. See :func:`lfdkit.emulate.planner.goal_weights`.
        clearance : float
            Tool clearance (units) added to every obstacle's radius; the plan
            keeps out of radius plus clearance (a hard constraint).

        Returns
        -------
        Plan
            ``points`` (n_points, q), the planned path from ``start`` (with no
            obstacle, the nominal resampled at constant speed), with its
            ``clearance``, ``goal_error`` and ``cost``.

        Raises
        ------
        lfdkit.emulate.UnsafePlanError
            When no plan within the action bounds keeps out of the obstacles
            and reaches the goal.
        ValueError
            For a start or goal of the wrong dimension or not finite, a scene
            with an obstacle class this skill has not learned (or with
            obstacles when no reward is learned), a start or goal inside an
            obstacle, or a horizon outside 4-12.
        """
        start, goal = self._ends(start, goal)
        return self._plan(start, goal, scene, planner, horizon, goal_approach, clearance)

    def _plan(
        self,
        start: np.ndarray,
        goal: np.ndarray,
        scene: Scene | None,
        planner: PlannerKind | None,
        horizon: int | None,
        goal_approach: float | str | None,
        clearance: float,
    ) -> Plan:
        """:meth:`plan_details` from a checked start and goal."""
        nominal = self._nominal(start, goal)
        scene = Scene() if scene is None else scene
        if not isinstance(scene, Scene):
            raise TypeError(f"scene: expected a Scene, got {type(scene).__name__}")
        kind = self.planner if planner is None else planner
        _check_choice(kind, "planner", PLANNERS)
        if kind == "mpc":
            h = int(self.horizon) if horizon is None else horizon
        else:
            h = None
        reward = self.reward_
        if reward is None:
            if len(scene):
                raise ValueError(
                    "scene: has obstacles, but this skill has no obstacle reward; learn one "
                    "with fit_reward() (demonstrations around obstacles) or adopt() it"
                )
            reward = Reward(1.0, {})
        return plan_path(
            reward,
            nominal,
            scene,
            horizon=h,
            n_points=int(self.n_points),
            max_slope=float(self.max_slope),
            goal_approach=goal_approach,
            clearance=clearance,
        )

    def evaluate(
        self,
        demos: Sequence[Any],
        scenes: Sequence[Scene],
        *,
        goals: Any = None,
        goal_approach: float | str | None = "auto",
    ) -> dict[str, float]:
        """Scores on held-out demonstrations in their scenes (thesis MSE_R and Pr).

        Each demonstration is compared with the plan from its first point to
        its goal (default the generalized path's goal) in its scene, and with
        the nominal replayed without the obstacle term. ``goal_approach`` is
        :meth:`plan`'s: by default the plan the robot would execute, which
        ends at the goal; None scores the thesis's model, which matches
        demonstrators that swerve late and end beside the goal.

        Returns
        -------
        dict
            ``mse`` (MSE_R of the plans, units²), ``mse_replay`` (MSE_Mp of the
            nominals) and ``improvement`` (Pr, percent), over 100 points per path.
        """
        self._check_fitted()
        demos = check_demos(demos, "demos", n_dims=self.n_dims_)
        scenes = list(scenes)
        if len(scenes) != len(demos):
            raise ValueError(f"scenes: {len(scenes)} scenes for {len(demos)} demonstrations")
        goal = self._goals(goals, len(demos))
        # The demonstrations' starts and the goals are checked: straight to the planner.
        plans = [
            self._plan(demo[0], g, scene, None, None, goal_approach, 0.0).points
            for demo, g, scene in zip(demos, goal, scenes, strict=True)
        ]
        nominals = [self._nominal(demo[0], g) for demo, g in zip(demos, goal, strict=True)]
        mse = metrics.mse_paths(plans, demos)
        replay = metrics.mse_paths(nominals, demos)
        return {"mse": mse, "mse_replay": replay, "improvement": metrics.improvement(replay, mse)}

    # ------------------------------------------------------------------ files
    def to_dict(self) -> dict[str, Any]:
        """The skill as a JSON-ready dict (:func:`lfdkit.io.skill_file.to_document`).

        The same fitted skill always gives the same dict: no date, and the
        run times (``"seconds"``) of :attr:`mimic_info_` and :attr:`ioc_info_`
        are left out (they stay on the object for reports).
        """
        self._check_fitted()
        reward = None
        if self.reward_ is not None:
            reward = (self.reward_.nominal_weight, self.reward_.precisions)
        return skill_file.to_document(
            self.get_params(),
            n_dims=self.n_dims_,
            units=self.units,
            path=self.path_,
            mimic_info=self.mimic_info_,
            reward=reward,
            ioc_info=self.ioc_info_,
        )

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, source: str = "skill") -> Skill:
        """Rebuild a skill from :meth:`to_dict`'s output.

        The fields are read by :class:`lfdkit.io.skill_file.SkillDocument`;
        the skill checks its parameters, refits the DMP on the path and
        rebuilds the reward from them, in that order.

        Raises
        ------
        ValueError
            For another format, a newer version, or a missing or broken field;
            the message starts with ``source`` and names the field.
        """
        document = skill_file.SkillDocument(data, source)
        params = document.params(cls().get_params())
        try:
            skill = cls(**params)
            skill._check_params()
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{source}: params: {exc}") from None
        n_dims = document.n_dims()
        path = document.path(n_dims)
        try:
            skill.use_path(path)
            skill.mimic_info_ = document.mimic()
            reward = document.reward(n_dims)
            if reward is not None:
                weight, matrices = reward
                skill.adopt(Reward(weight, matrices))
            skill.ioc_info_ = document.ioc()
        except ValueError as exc:
            if str(exc).startswith(source):
                raise
            raise ValueError(f"{source}: {exc}") from None
        return skill

    def save(self, path: str | os.PathLike[str], *, overwrite: bool = False) -> Path:
        """Write the skill to a JSON file, atomically (:mod:`lfdkit.io.skill_file`).

        Returns the file written. Raises ``FileExistsError`` if ``path``
        exists and ``overwrite`` is false, ``IsADirectoryError`` if it is a
        directory (:func:`lfdkit.io.skill_file.write_skill_file`).
        """
        target = skill_file.check_skill_path(path)
        return skill_file.write_skill_file(target, self.to_dict(), overwrite=overwrite)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> Skill:
        """Read a skill written by :meth:`save`.

        Parsing is strict (:func:`lfdkit.io.load_json`: no repeated keys,
        no NaN, bounded size and depth) and the parameters must lie in
        :data:`SKILL_FILE_LIMITS`.

        Raises
        ------
        FileNotFoundError
            If the file does not exist.
        ValueError
            For a file that is binary (e.g. a pickle), larger than
            :data:`MAX_SKILL_FILE_BYTES`, not valid JSON, not a skill, from a
            newer version, or with a broken or out-of-range field (the message
            names the file and field).
        """
        name = os.fspath(path)
        return cls.from_dict(skill_file.read_skill_file(name), source=name)

    def _mimic_name(self) -> str:
        return MIMIC_METHODS[self.mimic].label

    def __repr__(self) -> str:
        changed = {k: v for k, v in self.get_params().items() if v != SKILL_DEFAULTS.get(k)}
        args = ", ".join(f"{k}={v!r}" for k, v in changed.items())
        return f"Skill({args})"


# ------------------------------------------------------------- training files
class TrainingData(NamedTuple):
    """Demonstrations from files, split by whether they were recorded around obstacles.

    Attributes
    ----------
    free_demos : list of ndarray, each (n_j, q)
        Demonstrations without a scene, or with an empty one: the clean
        demonstrations the generalized path is learned from.
    free_ids : list of int or str
    obstacle_demos : list of ndarray, each (n_j, q)
        Demonstrations whose scene has obstacles.
    obstacle_ids : list of int or str
    scenes : list of Scene
        One per obstacle demonstration.
    """

    free_demos: list[np.ndarray]
    free_ids: list[DemoId]
    obstacle_demos: list[np.ndarray]
    obstacle_ids: list[DemoId]
    scenes: list[Scene]


def read_training_data(
    demos_path: str | os.PathLike[str], scenes_path: str | os.PathLike[str] | None = None
) -> TrainingData:
    """Read a demonstrations file and, optionally, the scene file of the obstacle demonstrations.

    Parameters
    ----------
    demos_path : path
        Demonstrations, ``.csv``, ``.npz`` or ``.json`` (:func:`lfdkit.io.load_demos`).
    scenes_path : path, optional
        Scenes by demonstration id, ``.csv`` or ``.json``
        (:func:`lfdkit.io.load_scenes`). A demonstration it does not
        list, or lists with no obstacle, is a clean demonstration.

    Raises
    ------
    ValueError
        If a file is malformed (the message names the file, line and field),
        demonstrations mix dimensions, or the scene file names a
        demonstration id that the demonstrations file does not have.
    """
    demos, ids = load_demos(demos_path, return_ids=True)
    dims = {demo.shape[1] for demo in demos}
    if len(dims) > 1:
        first = demos[0].shape[1]
        j = next(j for j, demo in enumerate(demos) if demo.shape[1] != first)
        raise ValueError(
            f"{os.fspath(demos_path)}: demonstration {ids[j]!r} is {demos[j].shape[1]}-D, "
            f"but {ids[0]!r} is {first}-D; all demonstrations must share their dimension"
        )
    scenes = {} if scenes_path is None else load_scenes(scenes_path)
    known = set(ids)
    stray = [key for key in scenes if key not in known]
    if stray:
        raise ValueError(
            f"{os.fspath(scenes_path)}: demo {stray[0]!r} is not in {os.fspath(demos_path)} "
            f"(its ids: {', '.join(map(str, ids[:5]))}{', ...' if len(ids) > 5 else ''})"
        )
    short = [(key, len(demo)) for demo, key in zip(demos, ids, strict=True) if len(demo) < 3]
    if short:
        raise ValueError(
            f"{os.fspath(demos_path)}: demonstration {short[0][0]!r} has {short[0][1]} "
            "points; a path needs at least 3"
        )
    data = TrainingData([], [], [], [], [])
    for demo, key in zip(demos, ids, strict=True):
        scene = scenes.get(key)
        if scene is None or not len(scene):
            data.free_demos.append(demo)
            data.free_ids.append(key)
        else:
            if scene.positions.shape[1] != demo.shape[1]:
                raise ValueError(
                    f"{os.fspath(scenes_path)}: demo {key!r}: {scene.positions.shape[1]}-D "
                    f"obstacles for a {demo.shape[1]}-D demonstration"
                )
            data.obstacle_demos.append(demo)
            data.obstacle_ids.append(key)
            data.scenes.append(scene)
    if len(data.free_demos) < 2:
        raise ValueError(
            f"{os.fspath(demos_path)}: needs at least 2 demonstrations without obstacles to "
            f"learn the path from, found {len(data.free_demos)}"
        )
    return data


def learn(
    demos_path: str | os.PathLike[str],
    scenes_path: str | os.PathLike[str] | None = None,
    *,
    progress: Progress | None = None,
    **params: Any,
) -> Skill:
    """Learn a skill from files: :func:`read_training_data`, then :meth:`Skill.fit`.

    ``params`` are :class:`Skill`'s parameters. The ``lfdkit learn`` command
    calls exactly this.
    """
    data = read_training_data(demos_path, scenes_path)
    skill = Skill(**params)
    obstacle = data.obstacle_demos or None
    return skill.fit(
        data.free_demos, obstacle, data.scenes if obstacle else None, progress=progress
    )


# ------------------------------------------------------------------ helpers
def _tell(progress: Progress | None, message: str) -> None:
    if progress is not None:
        progress(message)


def _check_choice(value: Any, name: str, choices: Sequence[str]) -> None:
    if value not in choices:
        raise ValueError(f"{name}: expected one of {', '.join(map(repr, choices))}, got {value!r}")


def _extent(path: np.ndarray) -> float:
    return float(np.max(np.ptp(path, axis=0))) or 1.0
