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

After the reward, the skill chooses its behaviour model (route planner and
clearance floor) by cross-validated replanning error: each obstacle
demonstration left out of a refit and replanned in its own scene with every
candidate (:attr:`Skill.model_selection_`; the thesis's model unless
another is closer by more than 2 %). It then replans every training scene
with the model chosen and keeps the result per demonstration
(:attr:`Skill.training_fidelity_`: Pr over the nominal, passing sides,
clearance against the demonstrated one), with the clearance floor learned
per obstacle class (:attr:`Skill.clearances_`) where that model keeps one
(issue 26). A held-out median Pr below 50 % is warned about.

:meth:`Skill.plan` then does what the thesis's robot does in a new scene: the
DMP retargets the generalized path to the new start and goal (the *nominal*),
and the planner (receding-horizon MPC by default, or the full-horizon
optimum) moves along it around the scene's obstacles. The plan comes timed
(:class:`~lfdkit.model.timed_path.TimedPlan`: times, points, velocities): by
its own arc length with the duration and speed profile the skill learned from the demonstrations'
times (:attr:`Skill.timing_`, :mod:`lfdkit.imitate.timing`), or with the
``timing`` law over ``duration`` when they had none.

Demonstrations with the tool's orientation (``orientations=``, unit
quaternions) also give the mean orientation along the path and an
orientation DMP (:class:`lfdkit.imitate.QuaternionDMP`): plans then carry
the orientation from a start to a goal orientation, reached exactly
(:attr:`~lfdkit.model.timed_path.TimedPlan.orientations`).

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

:meth:`Skill.load` restores the DMPs as fitted (weights, training times,
timing and the forced response the rollouts evaluate, stored with a
checksum): loading is reading, never refitting, and a loaded skill plans to
the bit as the saved one (issue 30: 2.9 s to load the sweeping skill before,
most of it SciPy imports the refit needed). Files written before that are
refitted from the stored path and parameters (a deterministic closed-form
fit). A file from a newer format version, or one with a missing or broken
field, is refused with a message naming the file and the field.
"""

from __future__ import annotations

import os
import time
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any, ClassVar, Literal

import numpy as np

from lfdkit.core.constraints import Checked, Integer, OneOf, Real
from lfdkit.core.estimator import Estimator, check_fitted
from lfdkit.core.geometry import (
    arc_length,
    path_length,
    polyline_distances,
    project_onto_polyline,
    resample,
)
from lfdkit.core.options import (
    DEMONSTRATION_SPEED,
    MODELS,
    PLANNERS,
    POOR_FIDELITY,
    SCALINGS,
    SKILL_DEFAULTS,
    TIMINGS,
)
from lfdkit.core.progress import Progress, ProgressLike, as_progress
from lfdkit.core.rotations import check_quaternions, continuous, exp, multiply, slerp
from lfdkit.core.units import (
    UnitsWarning,
    check_units,
    conversion_factor,
    implausible_units,
    likely_units,
)
from lfdkit.core.validation import (
    check_class_names,
    check_demos,
    check_horizon,
    check_path,
    check_point,
    check_positive,
    check_times_list,
)
from lfdkit.emulate import IOC, Plan, Reward, UnsafePlanError, metrics, plan_path
from lfdkit.emulate.fidelity import demonstrated_clearances, replanning_fidelity
from lfdkit.emulate.problem import UNCERTAINTY_MARGIN
from lfdkit.emulate.reward import in_path_frame
from lfdkit.imitate import DMP, ProMP, QuaternionDMP, SpeedProfile, learn_timing
from lfdkit.imitate.orientation_dmp import orientation_error
from lfdkit.imitate.timing import DURATION_RANGE
from lfdkit.imitate.via_points import (
    DEFORMATION_BASIS,
    ViaPath,
    check_via,
    check_via_orientations,
    orientations_through_via,
    through_via_points,
)
from lfdkit.io import skill_file
from lfdkit.io.skill_file import (
    MAX_SKILL_FILE_BYTES,
    SKILL_FILE_LIMITS,
    SKILL_FORMAT,
    SKILL_VERSION,
)
from lfdkit.io.training import read_training_data
from lfdkit.mimic import MIMIC_METHODS, DemoOrientationWarning, MimicSettings, mean_orientations
from lfdkit.model.demos import demo_fields
from lfdkit.model.scene import Scene
from lfdkit.model.timed_path import TimedPlan

# The skill-file constants live with the format (lfdkit.io.skill_file); re-exported here.
__all__ = [
    "MAX_SKILL_FILE_BYTES",
    "SKILL_FILE_LIMITS",
    "SKILL_FORMAT",
    "SKILL_VERSION",
    "Skill",
    "learn",
]

PlannerKind = Literal["mpc", "full"]

# Samples of a DMP rollout handed to the planner, which resamples it at
# constant speed: dense enough that the resampled nominal follows the curve.
_NOMINAL_OVERSAMPLING = 4

#: Most training samples of an orientation DMP a skill file stores (3 doubles each, 0.6 MB).
_MAX_STORED_ORIENTATION_SAMPLES = 20_000

#: How closely (a rotation angle, degrees) the orientation DMP must reproduce the mean orientation.
_ORIENTATION_TOLERANCE_DEG = 0.5

#: How far a plan may pass from a via-point, as a share of the plan's extent, before a
#: warning says so: the nominal passes exactly, the planner's resampling at constant
#: speed cuts it by well under this (the issue-33 benchmark), an obstacle may by more.
VIA_TOLERANCE = 0.01

#: Re-plans of a moving-obstacle plan at its own (arc-length) times before it is refused.
RETIME_ROUNDS = 3

#: The clearance floors a behaviour model may keep (``{level: (quantile, factor)}`` of
#: :func:`lfdkit.emulate.fidelity.demonstrated_clearances`): none (the thesis's), the
#: demonstrations' low quantile with room for noise, and the closest any came (a person
#: who keeps a fixed margin).
CLEARANCE_FLOORS = {"none": None, "demonstrated": (0.1, 0.8), "closest": (0.0, 1.0)}
#: Fewest obstacle demonstrations for a cross-validated choice (fewer: training replanning).
MIN_CROSS_VALIDATION_DEMOS = 3
#: Most refits of the cross-validation: beyond this many demonstrations, each fold leaves
#: out every ``MAX_FOLDS``-th one (10 demonstrations: 5 folds of 2).
MAX_FOLDS = 5
#: L-BFGS iterations of each fold's refit, started from the reward fitted on all.
CROSS_VALIDATION_MAX_ITER = 6
#: Another model must replan the held-out demonstrations this much closer (MSE) to be chosen.
SELECTION_MARGIN = 0.02
#: The demonstrations keep a consistent clearance when planning each held-out one with the
#: closest any other came costs at most this times the error of planning it with no floor;
#: then the floor (``"demonstrated"``) is the default, not the thesis's model. Measured on
#: the fidelity benchmark's people (6 demonstrations, 5 folds; seed 0 / 1, 1x noise): the
#: thesis's person 2.08 / 1.25, the late swerver 1.02 / 1.00, the fixed-margin person
#: 1.28 / 1.21, the potential field 0.94 / 1.00. At 2x noise the thesis's person gives
#: 1.00 (seed 1): noise hides the difference, and its pairs are then closed.
CONSISTENT_CLEARANCE = 1.1


def _check_learned_classes(skill: Skill) -> None:
    """Refuse a skill whose ``params.classes`` contradicts the classes its reward learned.

    The reward fit (``ioc`` summary) learned its classes with ``params.classes``:
    each of them is one of those and is in the reward. Classes adopted from
    another skill are in the reward but not in the summary, so they pass.
    """
    learned = (skill.ioc_info_ or {}).get("classes")
    if skill.classes is None or not isinstance(learned, list):
        return
    reward = tuple(skill.reward_.classes) if getattr(skill, "reward_", None) is not None else ()
    stray = [c for c in learned if c not in skill.classes or c not in reward]
    if stray:
        raise ValueError(
            f"params.classes: {list(skill.classes)} contradicts the classes the reward learned "
            f"({learned}; reward: {list(reward)}): class {stray[0]!r}; the file was edited or "
            "damaged: learn the skill again"
        )


def _registered_mimic(value: Any, name: str) -> str:
    """A key of :data:`~lfdkit.mimic.MIMIC_METHODS` as registered now (users may add methods)."""
    return OneOf(tuple(MIMIC_METHODS))(value, name)


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
        The speed law along the path when the demonstrations carry no times
        (:class:`lfdkit.imitate.SpeedProfile`): the DMP is trained with it
        and plans are timed with it. Demonstrations with times replace it by
        their learned speed profile (:attr:`timing_`).
    duration : float or "auto"
        Duration of the movement in seconds when the demonstrations carry no
        times (timed demonstrations give their median duration instead).
        ``"auto"`` (default): the generalized path's length at a hand's
        typical demonstration speed, :data:`lfdkit.core.options.DEMONSTRATION_SPEED`
        (0.2 m/s on average, at least 1 s): an 80 cm sweep lasts about 4 s,
        not 1 s (issue 31).
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
    model : {"auto", "thesis", "path"}
        How the obstacle behaviour is modelled and planned (issue 26).
        ``"thesis"``: the thesis's model exactly, the reward fitted through
        its receding horizon (no goal term) and planned with the same MPC
        (each window's best optimum, ``lookahead=False``), no learned
        clearance; only where that MPC walks into a dead end (no plan) is
        the plan the lookahead MPC's. ``"auto"`` (default): the same fitted
        reward, planned with the behaviour model chosen from the
        demonstrations (:attr:`model_selection_`) by cross-validated
        replanning error (:data:`MAX_FOLDS` folds at most, each refitted
        from the reward fitted on all). The candidates: how far ahead the
        person reacts (the thesis's receding horizon, or the whole path's
        optimum) times a clearance floor kept from each class's obstacles
        (none; 0.8 times the 10 % quantile of what the demonstrations kept;
        the closest any came, :data:`CLEARANCE_FLOORS`). The thesis's model
        comes first and stays unless another replans the held-out
        demonstrations closer by more than :data:`SELECTION_MARGIN`:
        demonstrations that cannot tell the candidates apart (a floor
        below what every demonstration kept changes no plan of theirs)
        keep it. So a gap between two obstacles is closed only where the
        demonstrations show a floor; single-obstacle demonstrations cannot
        tell a person who threads gaps from one who goes around (the
        thesis's person threads gaps narrower than twice the clearance it
        keeps from one obstacle: fidelity benchmark, pairs, −964 % median Pr
        with the floor, 94-98 % without).

        ``"path"`` (2-D, static scenes): as ``"auto"``, with each obstacle's
        learned response turned from the direction it was learned along (the
        generalized path's start-to-goal direction when the reward was
        fitted, ``ioc_info_["frame_axis"]``) into the nominal's frame at the
        obstacle (:func:`lfdkit.emulate.reward.in_path_frame`): a person who
        reacts relative to the motion, not to the room. Not chosen
        automatically: demonstrations of one task cannot tell the two frames
        apart, and held out it helps some people and seeds and hurts others
        (fidelity benchmark, quick, median Pr on new tasks: seed 0 thesis-model
        person 95 → −118 %, late swerver −528 → 33 %; seed 1 fixed-margin
        person 63 → −269 %). Its candidates are ``"auto"``'s in the path frame.

        Either way the reward is fitted through exactly the route planner the
        skill plans with (the receding horizon ``H`` without goal term: the
        goal is joined to the route afterwards, leaving it alone,
        :mod:`lfdkit.emulate.planner`), and the training demonstrations are
        replanned with the model they were fitted with (:attr:`training_fidelity_`).
        The global-route candidate plans with the reward fitted through the
        receding horizon, and the folds' refits are full-horizon only (cheap):
        the cross-validated figures approximate those of full refits.
    max_slope : float
        Largest sideways step per step along the nominal (the action box).
    classes : sequence of str, optional
        Obstacle classes to learn (default: those in the training scenes).
    random_state : int, optional
        Seed of the mimic method's random initialisation (GMR, NLPCA; the
        other layers are deterministic).
    units : {"m", "cm", "mm"}
        Unit of every length the skill takes and gives: demonstrations,
        paths, starts and goals, obstacles, clearances (:mod:`lfdkit.core.units`).
        The reward's nominal weight and precisions are in 1/units². Learning
        is scale-invariant: the same demonstrations in millimetres (with
        ``units="mm"``) give the path in metres times 1000, the weight and
        precisions divided by 1e6, and the same plans times 1000 (to about
        1e-7 of the path's extent). Shown on figures and stored in the skill
        file; :meth:`to_units` converts a fitted skill.

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
        The DMP trained on ``path_``, timed by ``timing_``.
    timing_ : SpeedProfile
        Duration (s) and speed profile along the path, which the DMP and
        every plan follow: learned from the demonstrations' times
        (:func:`lfdkit.imitate.learn_timing`, ``source="demonstrations"``),
        or the ``timing`` law over ``duration``.
    reward_ : Reward or None
        The obstacle reward (None until :meth:`fit_reward` or :meth:`adopt`).
    ioc_ : IOC or None
        The fitted inverse optimal control (None after :meth:`adopt` or :meth:`load`).
    ioc_info_ : dict or None
        Summary of the reward fit: loss, stages, classes, demonstrations.
    n_dims_ : int
        Dimension ``q`` of the paths.
    orientations_ : ndarray, shape (n_points, 4), or None
        The demonstrations' mean tool orientation at each point of ``path_``
        (:func:`lfdkit.mimic.mean_orientations`, robust), unit quaternions
        ``[x, y, z, w]``; None when the demonstrations gave no orientations.
    orientation_dmp_ : QuaternionDMP or None
        The orientation DMP trained on ``orientations_`` at the path's times
        (those of ``dmp_``, i.e. the same timing ``timing_``): plans carry its
        rollout to a new start and goal orientation (:meth:`plan`).
    promp_ : ProMP or None
        The clean demonstrations' probabilistic movement primitive
        (:class:`lfdkit.imitate.ProMP`, 15 basis functions per dimension,
        each demonstration in the path's direction): how they varied, which
        shapes how plans bend through via-points (:meth:`plan`'s ``via``) and
        the band :meth:`via_path` gives. None for a path taken from elsewhere
        (:meth:`use_path`) or a file without it: via-points then bend the
        path smoothly, with no preferred direction.
    clearances_ : dict
        Per obstacle class, the clearance (units, from the obstacle's
        surface) plans keep at least: the demonstrations' own
        (:func:`lfdkit.emulate.fidelity.demonstrated_clearances`) where the
        behaviour model chosen keeps a floor; empty otherwise (and for
        ``model="thesis"`` or a reward only adopted).
    frame_ : {"world", "path"}
        The frame the learned responses are planned in (``"path"`` for
        ``model="path"``).
        (:func:`lfdkit.emulate.fidelity.demonstrated_clearances`), with
        ``model="auto"``; empty otherwise (and for a reward only adopted).
    class_radii_ : dict
        Per learned obstacle class, the median radius (units) of the obstacles
        it was learned from: which learned class is nearest in size to one
        never learned (``unknown_response="nearest"`` of :meth:`plan_details`).
        Empty before a reward is fitted, for a reward only adopted and in
        files from before it.
    route_ : {"lookahead", "window", "full"} or None
        The route planner plans use: the MPC with ``lookahead``, the thesis's
        MPC (``"window"``) or the full horizon; None before a reward is
        fitted (then ``"lookahead"`` for ``planner="mpc"``).
    training_fidelity_ : list of dict or None
        Per obstacle demonstration, how its own scene is replanned
        (:func:`lfdkit.emulate.fidelity.replanning_fidelity`: ``improvement``
        Pr %, ``sides_agree``, ``other_side``, ``clearance``,
        ``demonstrated_clearance``; ``demo`` its index, ``refused`` the
        planner's reason where it found no plan). Also in :attr:`ioc_info_`.
    model_selection_ : dict or None
        How the behaviour model was chosen: ``criterion`` (in words),
        ``cross_validated`` (False with fewer than
        :data:`MIN_CROSS_VALIDATION_DEMOS` obstacle demonstrations: then the
        training scenes are replanned), ``folds``, the ``chosen`` model's
        name and the ``runner_up``'s, and per candidate (``"window"``,
        ``"full+closest"``, ...) its ``route``, ``floor``, ``frame`` and
        held-out scores: ``mse`` (units²), ``improvement_pooled``,
        ``_median`` and ``_mean`` (Pr %), ``sides_agree`` (share),
        ``refused`` and ``clearance_relaxed`` (counts). Also in
        :attr:`ioc_info_` and the skill file.
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
        model: str = SKILL_DEFAULTS["model"],
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
        self.model = model
        self.max_slope = max_slope
        self.classes = classes
        self.random_state = random_state
        self.units = units

    # ------------------------------------------------------------ parameters
    #: What each parameter may be (:meth:`_validate_params`, when learning or
    #: loading starts). The counts and sizes are bounded by the ranges a skill
    #: file may hold (``SKILL_FILE_LIMITS``), so what is built in code can
    #: always be saved and loaded again.
    _parameter_constraints: ClassVar[dict[str, Any]] = {
        "mimic": Checked(_registered_mimic),
        "planner": OneOf(PLANNERS),
        "model": OneOf(MODELS),
        "timing": OneOf(TIMINGS),
        "scaling": OneOf(SCALINGS),
        **{
            name: Integer(
                minimum=int(SKILL_FILE_LIMITS[name][0]),
                maximum=int(SKILL_FILE_LIMITS[name][1]),
                options=("auto",) if name == "n_basis" else (),  # the DMP chooses the count
            )
            for name in ("n_points", "n_components", "n_basis")
        },
        # "auto": the path's length gives the duration.
        "duration": Real(maximum=SKILL_FILE_LIMITS["duration"][1], options=("auto",)),
        "max_slope": Real(maximum=SKILL_FILE_LIMITS["max_slope"][1]),
        "horizon": Checked(check_horizon),
        "classes": Checked(check_class_names, optional=True),
        "units": Checked(check_units),
    }

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
        times: Sequence[Any] | None = None,
        orientations: Sequence[Any] | None = None,
        progress: ProgressLike = None,
    ) -> Skill:
        """Learn every layer: path and DMP from ``demos``, the reward from the rest.

        Parameters
        ----------
        demos : sequence of array_like, each (n_j, q), or of Demo
            Clean demonstrations (no obstacle), at least 2, q 2 or 3; as
            :class:`~lfdkit.model.demos.Demo` records, with their times and
            orientations (then ``times`` and ``orientations`` are not given).
        obstacle_demos : sequence of array_like, each (n_j, q), or of Demo, optional
            Demonstrations recorded around obstacles; as records, each with its
            scene (then ``scenes`` is not given).
        scenes : sequence of Scene, optional
            One per obstacle demonstration given as arrays.
        goals : array_like, shape (q,) or (n_obstacle_demos, q), optional
            Passed to :meth:`fit_reward`.
        times : sequence of (array_like (n_j,) or None), optional
            Sample times of ``demos`` in seconds: the timing is learned from
            them (:meth:`fit_path`).
        orientations : sequence of array_like, each (n_j, 4), optional
            Tool orientations of ``demos`` (unit quaternions ``[x, y, z, w]``,
            one per sample): the skill learns their mean along the path and
            an orientation DMP (:meth:`fit_path`).
        progress : Progress, callable, bool or None
            Reports each stage (mimic, imitate, emulate) and the inverse
            optimal control's own stages and iterations: True for bars on a
            terminal, a callable for one line per stage as it starts
            (:func:`lfdkit.core.progress.as_progress`). Default: silent.

        Returns
        -------
        Skill
            ``self``.
        """
        demos, times, orientations = _clean_records(demos, times, orientations)
        obstacle_demos, scenes = _obstacle_records(obstacle_demos, scenes)
        if (obstacle_demos is None) != (scenes is None):
            raise ValueError("scenes: give obstacle_demos and scenes together, or neither")
        progress = as_progress(progress)
        self.fit_path(demos, times=times, orientations=orientations, progress=progress)
        self.reward_ = None
        self.ioc_ = None
        self.ioc_info_ = None
        self._reset_emulation()
        if obstacle_demos is not None and len(obstacle_demos):
            self.fit_reward(obstacle_demos, scenes, goals=goals, progress=progress)
        elif obstacle_demos is not None and scenes is not None and len(scenes):
            raise ValueError(f"scenes: {len(scenes)} scenes for 0 obstacle demonstrations")
        return self

    def fit_path(
        self,
        demos: Sequence[Any],
        *,
        times: Sequence[Any] | None = None,
        orientations: Sequence[Any] | None = None,
        progress: ProgressLike = None,
    ) -> Skill:
        """Learn the generalized path (mimic), its timing and the DMP on it (imitate).

        Parameters
        ----------
        demos : sequence of array_like, each (n_j, q), or of Demo
            Clean demonstrations, at least 2, all of the same dimension 2 or 3;
            as :class:`~lfdkit.model.demos.Demo` records, with their times and
            orientations (then ``times`` and ``orientations`` are not given).
        times : sequence of (array_like (n_j,) or None), optional
            Sample times of each demonstration in seconds (finite, strictly
            increasing; ``None`` for one without). The duration and speed
            profile along the path are learned from those given
            (:func:`lfdkit.imitate.learn_timing`: median over the
            demonstrations, smoothed, at rest at both ends); without any,
            the ``timing`` law over ``duration``.
        orientations : sequence of array_like, each (n_j, 4), optional
            The tool's orientation at each sample of each demonstration, unit
            quaternions ``[x, y, z, w]`` (signs may flip); all demonstrations
            or none (None entries for all is none). The skill learns
            :attr:`orientations_`, their robust mean at each path point
            (:func:`lfdkit.mimic.mean_orientations`, on the same
            correspondence as Mean-Path), and :attr:`orientation_dmp_`.
        progress : Progress, callable, bool or None
            As in :meth:`fit`.

        Returns
        -------
        Skill
            ``self``; an obstacle reward learned before is kept.

        Warns
        -----
        UnitsWarning
            When the demonstrations are implausible in :attr:`units` (they
            span over 20 m or under 1 mm, or timed ones move faster than 5
            m/s on average, in metres: :func:`lfdkit.core.units.implausible_units`);
            the message names the likely unit. ``lfdkit learn`` without
            ``--units`` refuses them.

        Raises
        ------
        ValueError
            For NaN, infinite or non-increasing times, or times that do not
            match their demonstration (the message names ``times[j]``);
            orientations that are not unit, do not match their demonstration,
            are given for some demonstrations only, or whose mean turns π or
            more away from its last (the message names ``orientations``).
        """
        self._validate_params()
        demos, times, orientations = _clean_records(demos, times, orientations)
        demos = check_demos(demos, "demos", min_demos=2, min_points=3)
        q = demos[0].shape[1]
        if q not in (2, 3):
            raise ValueError(f"demos: expected 2-D or 3-D points, got {q} dimensions")
        progress = as_progress(progress)
        stamps = check_times_list(times, demos, style="shape")
        quats = _check_orientations_list(orientations, demos)
        self._warn_units(demos, stamps)
        started = time.perf_counter()
        method = MIMIC_METHODS[self.mimic]
        settings = MimicSettings(
            n_points=int(self.n_points),
            random_state=self.random_state,
            n_components=int(self.n_components),
            # One metre in the skill's units: a method that is not scale-invariant
            # (GMR) fits in metres, so the path does not depend on the units.
            length_scale=conversion_factor("m", self.units),
        )
        # Recorded as well as passed on, so that the skill file and reports keep them.
        label = f"mimic: {self._mimic_name()} of {len(demos)} demonstrations"
        with warnings.catch_warnings(record=True) as caught, progress.stage(label):
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
        timing = None
        timed = [j for j, t in enumerate(stamps) if t is not None]
        if timed:
            progress.note(f"imitate: timing of {len(timed)} timed demonstrations")
            # Demonstrations the mimic method turned round run backwards in time too.
            turned = set(info["reversed"])
            runs = [demos[j][::-1] if j in turned else demos[j] for j in timed]
            clocks = [stamps[j][-1] - stamps[j][::-1] if j in turned else stamps[j] for j in timed]
            timing = learn_timing(runs, clocks, path)
        means = None
        if quats is not None:
            progress.note(f"mimic: mean orientation of {len(quats)} demonstrations")
            found = mean_orientations(path, demos, quats, robust=True)
            means = found.orientations
            info["orientation_spread_deg"] = float(np.degrees(np.median(found.spread)))
        self._set_path(path, info, progress, timing, means)
        self.promp_ = self._fit_promp(demos, info["reversed"])
        return self

    def use_path(
        self,
        path: Any,
        *,
        source: str = "given",
        timing: SpeedProfile | None = None,
        orientations: Any = None,
    ) -> Skill:
        """Take a generalized path from elsewhere and train the DMP on it.

        Parameters
        ----------
        path : array_like, shape (n, q)
            The path, q 2 or 3, at least 3 points.
        source : str
            Recorded in :attr:`mimic_info_` (e.g. where the path came from).
        timing : SpeedProfile, optional
            Its duration and speed profile (e.g. another skill's
            :attr:`timing_`, or :func:`lfdkit.imitate.learn_timing`);
            default the ``timing`` law over ``duration``.
        orientations : array_like, shape (n, 4), optional
            The tool's orientation at each point of the path (unit
            quaternions ``[x, y, z, w]``): the skill learns an orientation DMP
            on them (:attr:`orientation_dmp_`). Default: no orientation.
        """
        self._use_path(path, source, timing, orientations)
        return self

    def _use_path(
        self,
        path: Any,
        source: str,
        timing: SpeedProfile | None,
        orientations: Any,
        fitted: tuple[DMP, QuaternionDMP | None] | None = None,
    ) -> None:
        """:meth:`use_path`; with ``fitted``, those DMPs instead of fitting them (loading)."""
        self._validate_params()
        path = check_path(path, "path", min_points=3)
        if path.shape[1] not in (2, 3):
            raise ValueError(f"path: expected 2-D or 3-D points, got {path.shape[1]} dimensions")
        if timing is not None and not isinstance(timing, SpeedProfile):
            raise TypeError(f"timing: expected a SpeedProfile, got {type(timing).__name__}")
        if orientations is not None:
            unit = check_quaternions(orientations, "orientations", n=len(path))
            given = np.array(orientations, dtype=np.float64)
            # Kept as given when unit to rounding, so a skill file reads back bit for bit.
            close = np.abs(np.linalg.norm(given, axis=1) - 1.0).max() <= 1e-12
            orientations = given if close else unit
        self.mimic_ = None
        self.promp_ = None  # no demonstrations: via-points bend the path smoothly
        info = {"method": "given", "source": str(source)}
        self._set_path(path, info, None, timing, orientations, fitted)

    def _set_path(
        self,
        path: np.ndarray,
        info: dict[str, Any],
        progress: Progress | None,
        timing: SpeedProfile | None = None,
        orientations: np.ndarray | None = None,
        fitted: tuple[DMP, QuaternionDMP | None] | None = None,
    ) -> None:
        reward = getattr(self, "reward_", None)
        if reward is not None and reward.n_dims not in (None, path.shape[1]):
            raise ValueError(
                f"path: {path.shape[1]}-D, but the obstacle reward is {reward.n_dims}-D"
            )
        self.path_ = np.array(path, dtype=np.float64)
        self.mimic_info_ = info
        if timing is None:
            timing = SpeedProfile.from_law(self.timing, self._law_duration(self.path_))
        self.timing_ = timing
        # The stage says what it did once the DMP has chosen its basis count.
        with as_progress(progress).stage("imitate: DMP", announce=False) as stage:
            self.dmp_ = self._fit_dmp(self.path_) if fitted is None else fitted[0]
            chosen = " (n_basis='auto')" if isinstance(self.n_basis, str) else ""
            stage.describe(
                f"imitate: DMP with {self.dmp_.n_basis_} basis functions per dimension{chosen}, "
                f"reproducing the path within {self.dmp_.reproduction_error_:.2%} of its extent"
            )
        self.orientations_ = None
        self.orientation_dmp_ = None
        if orientations is not None:
            with as_progress(progress).stage("imitate: orientation DMP"):
                turned = continuous(orientations)
                # q and -q are one rotation: the sign that starts with w >= 0, for readers.
                self.orientations_ = -turned if turned[0, 3] < 0.0 else turned
                if fitted is None or fitted[1] is None:
                    self.orientation_dmp_ = self._fit_orientation_dmp(self.orientations_)
                else:
                    self.orientation_dmp_ = fitted[1]
        self.n_dims_ = int(self.path_.shape[1])
        if not hasattr(self, "reward_"):
            self.reward_ = None
            self.ioc_ = None
            self.ioc_info_ = None
            self._reset_emulation()

    def _law_duration(self, path: np.ndarray) -> float:
        """Seconds of the ``timing`` law: ``duration``, or for "auto" the path at a hand's pace."""
        if not (isinstance(self.duration, str) and self.duration == "auto"):
            return float(self.duration)
        metres = path_length(path) * conversion_factor(self.units, "m")
        return max(1.0, metres / DEMONSTRATION_SPEED)

    def _warn_units(self, demos: list[np.ndarray], stamps: list[np.ndarray | None]) -> None:
        """A :class:`UnitsWarning` when the demonstrations are implausible in :attr:`units`."""
        extent = max(float(np.ptp(demo, axis=0).max()) for demo in demos)
        speeds = [
            path_length(demo) / float(t[-1] - t[0])
            for demo, t in zip(demos, stamps, strict=True)
            if t is not None and t[-1] > t[0]
        ]
        reason = implausible_units(extent, self.units, max(speeds) if speeds else None)
        if reason is not None:
            likely = likely_units(extent, self.units)
            span = extent * conversion_factor(likely, "m")
            detail = f"{reason}; in {likely} they would span {span:.3g} m"
            warnings.warn(
                UnitsWarning(
                    f"demos: {detail}: if that is their unit, learn with units={likely!r}",
                    likely=likely,
                    detail=detail,
                ),
                stacklevel=3,
            )

    def _reset_emulation(self) -> None:
        """No learned clearance, route or fidelity (a skill without a fitted reward)."""
        self.clearances_: dict[str, float] = {}
        self.class_radii_: dict[str, float] = {}
        self.route_: str | None = None
        self.frame_ = "world"
        self.training_fidelity_: list[dict[str, Any]] | None = None
        self.model_selection_: dict[str, Any] | None = None

    def _fit_dmp(self, path: np.ndarray) -> DMP:
        n_basis = self.n_basis if isinstance(self.n_basis, str) else int(self.n_basis)
        dmp = DMP(n_basis=n_basis, scaling=self.scaling)
        if self.timing_.source in ("minimum_jerk", "uniform"):
            # The law by name: the fit skills made before timings were learned.
            return dmp.fit(path, duration=self.timing_.duration, timing=self.timing_.source)
        return dmp.fit(path, timing=self.timing_)

    def _fit_promp(self, demos: list[np.ndarray], reversed_: list[int]) -> ProMP | None:
        """The demonstrations' ProMP (:attr:`promp_`), each run in the path's direction.

        Its phase is the fraction of each demonstration's length (resampled
        at ``n_points`` points of equal spacing), as :meth:`via_path` bends
        the nominal by the fraction of its length: a correspondence in space,
        as Mean-Path's, whatever the demonstrations' speeds. None when fewer
        than 2 demonstrations have a length.
        """
        turned = set(reversed_)
        runs = [
            resample(demo[::-1] if j in turned else demo, int(self.n_points))
            for j, demo in enumerate(demos)
            if path_length(demo) > 0.0
        ]
        return ProMP(n_basis=DEFORMATION_BASIS).fit(runs) if len(runs) >= 2 else None

    def _fit_orientation_dmp(self, orientations: np.ndarray) -> QuaternionDMP:
        """The orientation DMP on the mean orientations, on the path DMP's clock.

        The mean orientation is a function of the path's arc-length fraction
        ``ℓ`` (one per path point); the DMP learns it composed with the
        skill's speed law, ``q(t) = Q(ℓ(t / T))`` (as the position DMP
        composes the path with it), sampled densely in time: the movement is
        at rest at both ends without the roughness of a few demonstrations'
        mean being magnified where the path starts and ends slowly. A plan's
        point reached at ``t`` then gets the mean orientation of the path
        point at the same fraction of the way. With ``n_basis="auto"`` the
        basis count is the fewest that reproduce it within 1 % of the turn,
        or :data:`_ORIENTATION_TOLERANCE_DEG` (a rotation angle) if looser.
        """
        from scipy.interpolate import make_interp_spline  # here: lfdkit.skill loads fast

        n_basis = self.n_basis if isinstance(self.n_basis, str) else int(self.n_basis)
        goal = orientations[-1]
        # The error the DMP learns: half the rotation angle to the goal (radians).
        half = orientation_error(orientations, goal)
        extent = float(np.max(np.ptp(half, axis=0)))
        tolerance = 0.5 * np.radians(_ORIENTATION_TOLERANCE_DEG)
        basis_tol = min(1.0, max(0.01, tolerance / extent)) if extent > 0.0 else 1.0
        fraction = arc_length(self.path_) / path_length(self.path_)
        phase = np.linspace(0.0, 1.0, max(1000, 10 * len(fraction)))
        spline = make_interp_spline(fraction, half, k=min(3, len(fraction) - 1), axis=0)
        dense = multiply(exp(spline(self.timing_.progress(phase))), goal)
        dense[-1] = goal  # the spline passes through it: exactly, not to rounding
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", RuntimeWarning)
            try:
                dmp = QuaternionDMP(n_basis=n_basis, basis_tol=basis_tol).fit(
                    dense, phase * self.timing_.duration
                )
            except ValueError as exc:
                message = str(exc).removeprefix("quaternions: ")
                raise ValueError(f"orientations: the mean along the path: {message}") from None
        if caught:  # said for the orientation, in degrees, not the DMP's words for a path
            departure = 2.0 * dmp.dmp_.reproduction_error_ * extent
            warnings.warn(
                f"orientation DMP: reproduces the demonstrations' mean orientation within "
                f"{np.degrees(departure):.2g} deg at best ({dmp.dmp_.n_basis_} basis functions); "
                "the mean is rough where the demonstrations disagree or are noisy",
                RuntimeWarning,
                stacklevel=4,
            )
        return dmp

    def fit_reward(
        self,
        demos: Sequence[Any],
        scenes: Sequence[Scene] | None = None,
        *,
        goals: Any = None,
        progress: ProgressLike = None,
    ) -> Skill:
        """Learn the obstacle reward by inverse optimal control (emulate).

        Each demonstration is compared with the plan along its own nominal:
        the DMP from the demonstration's first point to its goal. The goal is
        where the task ends (the dustpan), not where a demonstration that
        swerved around an obstacle happened to stop, so it defaults to the
        generalized path's goal.

        Parameters
        ----------
        demos : sequence of array_like, each (n_j, q), or of Demo
            Demonstrations recorded around obstacles; as
            :class:`~lfdkit.model.demos.Demo` records, each with its scene
            (then ``scenes`` is not given).
        scenes : sequence of Scene
            One per demonstration given as arrays.
        goals : array_like, shape (q,) or (n_demos, q), optional
            Goal of each demonstration's nominal (default: the generalized path's goal).
        progress : Progress, callable, bool or None
            As in :meth:`fit`; the inverse optimal control reports its
            starting search, each L-BFGS run's iterations and the MPC stage.

        Returns
        -------
        Skill
            ``self``.
        """
        self._check_fitted()
        demos, scenes = _obstacle_records(demos, scenes, required=True)
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
            # Refused, not learned at its t = 0 place: the demonstrator avoided where
            # it was at each moment, so a reward fitted to one place would be wrong.
            moving = next((i for i, o in enumerate(scene) if o.moving), None)
            if moving is not None:
                raise ValueError(
                    f"scenes[{j}]: obstacle {moving} ({scene.labels[moving]!r}) moves; the "
                    "reward is learned from standing obstacles only: give where it stood "
                    "during the demonstration, or learn without it (plans can avoid moving ones)"
                )
        goal = self._goals(goals, len(demos))
        progress = as_progress(progress)
        with progress.stage("emulate: nominal of each obstacle demonstration (DMP)"):
            starts = np.array([demo[0] for demo in demos])
            nominals = list(self._rollouts(starts, goal))
        stages = "full horizon, then MPC" if self.planner == "mpc" else "full horizon"
        started = time.perf_counter()
        label = f"emulate: inverse optimal control on {len(demos)} demos ({stages})"
        with progress.stage(label):
            ioc = IOC(
                self.classes,
                n_points=int(self.n_points),
                horizon=self._horizon,
                max_slope=float(self.max_slope),
                progress=progress,
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
        self._reset_emulation()
        # The direction the precisions are learned along (model="path" turns them from it).
        chord = self.path_[-1] - self.path_[0]
        self.ioc_info_["frame_axis"] = (chord / max(float(np.linalg.norm(chord)), 1e-300)).tolist()
        self.class_radii_ = _median_radii(scenes, ioc.classes_)
        with progress.stage("emulate: replanning the training scenes (fidelity, model choice)"):
            # Obstacles of a class not learned never shaped a demonstration (the IOC
            # warned): the training scenes are replanned without them.
            learned = [
                Scene(tuple(o for o in scene if o.label not in ioc.not_learned_))
                for scene in scenes
            ]
            self._select_model(demos, learned, goal, nominals)
        self.ioc_info_["training_fidelity"] = skill_file.jsonable(self.training_fidelity_)
        self.ioc_info_["model_selection"] = skill_file.jsonable(self.model_selection_)
        self._warn_fidelity()
        return self

    def _behaviour_candidates(self) -> list[dict[str, str]]:
        """The behaviour models :meth:`_select_model` chooses from (the first wins ties).

        Each is a route planner (how far ahead the person reacts: the
        thesis's receding horizon ``"window"``, which falls back on the MPC
        with lookahead only at a dead end, or the whole path, ``"full"``), a
        clearance floor (:data:`CLEARANCE_FLOORS`) and a frame of the learned
        responses (``"world"``, or ``"path"`` for ``model="path"``). The
        thesis's model (window, no floor, world) comes first: demonstrations
        that cannot tell the candidates apart keep it. The frame is not a
        candidate of ``"auto"``: demonstrations of one task cannot tell the
        two apart (the nominal hardly turns at their obstacles).
        """
        routes = ("full",) if self.planner == "full" else ("window", "full")
        if self.model == "thesis":
            return [{"route": routes[0], "floor": "none", "frame": "world"}]
        frame = "path" if self.model == "path" else "world"
        return [
            {"route": route, "floor": floor, "frame": frame}
            for floor in CLEARANCE_FLOORS
            for route in routes
        ]

    def _unfitted_route(self) -> str:
        """The route of a skill whose reward was not fitted here (as before routes were chosen)."""
        return "full" if self.planner == "full" else "lookahead"

    def _floors(
        self,
        demos: Sequence[np.ndarray],
        scenes: Sequence[Scene],
        nominals: Sequence[np.ndarray],
    ) -> dict[str, dict[str, float]]:
        """Each clearance floor learned from these demonstrations, ``{level: {class: units}}``."""
        classes = self.reward_.classes
        return {
            level: {}
            if spec is None
            else demonstrated_clearances(
                demos, scenes, nominals, classes, quantile=spec[0], factor=spec[1]
            )
            for level, spec in CLEARANCE_FLOORS.items()
        }

    def _replan_candidates(
        self,
        demo: np.ndarray,
        goal: np.ndarray,
        scene: Scene,
        nominal: np.ndarray,
        candidates: Sequence[Mapping[str, str]],
        reward: Reward,
        floors: Mapping[str, Mapping[str, float]],
    ) -> list[dict[str, Any]]:
        """One demonstration's scene replanned with each behaviour model: fidelity rows.

        A model whose clearance floor the same route's plan without a floor
        already keeps plans the same path: that plan is reused, not planned again.
        """
        replay = metrics.mse_paths([nominal], [demo], int(self.n_points))
        plans: dict[tuple[str, str], Any] = {}
        out = []
        for candidate in candidates:
            route, frame = candidate["route"], candidate["frame"]
            clearances = floors[candidate["floor"]]
            margins = self._margins(scene, demo[0], goal, 0.0, clearances)
            free = plans.get((route, frame))
            reuse = free is not None and not isinstance(free, str)
            if reuse and margins is not None:
                reuse = bool(np.all(scene.distances(free.points) >= margins))
            if reuse:
                plan, relaxed = free, False
            else:
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always", UserWarning)
                    try:
                        plan = self._plan(
                            demo[0],
                            goal,
                            scene,
                            "full" if route == "full" else None,
                            None,
                            "auto",
                            0.0,
                            route=route,
                            reward=reward,
                            clearances=clearances,
                            frame=frame,
                        )
                    except UnsafePlanError as exc:
                        plan = str(exc)
                relaxed = bool(caught)  # the floor could not all be kept (_plan warned)
                if margins is None:
                    plans[(route, frame)] = plan
            if isinstance(plan, str):
                out.append({"refused": plan})
                continue
            row = replanning_fidelity(plan.points, nominal, demo, scene)
            out.append({**row, "clearance_relaxed": relaxed, "replay_mse": replay})
        return out

    def _refit_on(
        self,
        keep: Sequence[int],
        demos: list[np.ndarray],
        scenes: list[Scene],
        nominals: list[np.ndarray],
    ) -> Reward:
        """The reward refitted on demonstrations ``keep``, warm-started from the one fitted on all.

        Full horizon only and without the after-fit checks (a fold's reward
        only plans; the MPC stage would triple the cost). Classes the kept
        demonstrations do not show keep the reward's own response.
        """
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                ioc = IOC(
                    self.reward_.classes,
                    n_points=int(self.n_points),
                    max_slope=float(self.max_slope),
                    init=self.reward_,
                    n_starts=1,
                    max_iter=CROSS_VALIDATION_MAX_ITER,
                    diagnose=False,
                ).fit(
                    [demos[i] for i in keep],
                    [scenes[i] for i in keep],
                    [nominals[i] for i in keep],
                )
        except ValueError:  # nothing to learn from them: the reward fitted on all
            return self.reward_
        learned = ioc.reward_
        return Reward(learned.nominal_weight, {**self.reward_.precisions, **learned.precisions})

    @staticmethod
    def _default_model(
        candidates: Sequence[Mapping[str, str]],
        names: Sequence[str],
        scores: Mapping[str, Mapping[str, Any]],
    ) -> tuple[str, float | None]:
        """The model that wins ties, and the clearance consistency that decided it.

        The thesis's model (the first candidate) unless the demonstrations
        keep a consistent clearance: planning them with the closest any other
        came (the ``"closest"`` floor, same route) costs at most
        :data:`CONSISTENT_CLEARANCE` times the error with no floor. A person
        whose closest approach is the same wherever the obstacle stands keeps
        a margin, and would not squeeze between two obstacles closer than
        that; one whose approach varies with the obstacle's place answers a
        smooth reward (the thesis's person) and may thread a gap. Then the
        ``"demonstrated"`` floor is the default.
        """
        base = candidates[0]
        same = {
            c["floor"]: name
            for c, name in zip(candidates, names, strict=True)
            if (c["route"], c["frame"]) == (base["route"], base["frame"])
        }
        if base["floor"] != "none" or not {"closest", "demonstrated"} <= same.keys():
            return names[0], None
        free, closest = scores[names[0]]["mse"], scores[same["closest"]]["mse"]
        if not (np.isfinite(free) and np.isfinite(closest)):
            return names[0], None
        ratio = closest / free if free > 0.0 else (1.0 if closest == 0.0 else np.inf)
        default = same["demonstrated"] if ratio <= CONSISTENT_CLEARANCE else names[0]
        return default, float(ratio)

    def _select_model(
        self,
        demos: list[np.ndarray],
        scenes: list[Scene],
        goal: np.ndarray,
        nominals: list[np.ndarray],
    ) -> None:
        """Choose the behaviour model by cross-validated replanning error (issue 26).

        The obstacle demonstrations are split into folds (one each, or every
        :data:`MAX_FOLDS`-th for more): for each fold the reward is refitted
        on the others (:meth:`_refit_on`), the clearance floors are learned
        from the others, and each held-out demonstration's scene is replanned
        with every candidate (:meth:`_behaviour_candidates`). A candidate's
        score is its mean squared distance to the held-out demonstrations
        (what Pr measures). Chosen: fewest refused, then fewest planned
        without all of the floor, then the smallest MSE; the default
        (:meth:`_default_model`: the thesis's model, or the demonstrated
        floor for demonstrations that keep a consistent clearance) unless
        another is closer by more than :data:`SELECTION_MARGIN`. With fewer than
        :data:`MIN_CROSS_VALIDATION_DEMOS` demonstrations the training scenes
        are replanned instead (not cross-validated, said in ``criterion``).
        Sets :attr:`route_`, :attr:`clearances_`, :attr:`frame_`,
        :attr:`training_fidelity_` (the chosen model with the reward fitted
        on all, in the training scenes) and :attr:`model_selection_`.
        """
        candidates = self._behaviour_candidates()
        names = [_behaviour_name(c) for c in candidates]
        n = len(demos)
        cross = n >= MIN_CROSS_VALIDATION_DEMOS
        full_floors = self._floors(demos, scenes, nominals)

        def replanned(indices: Sequence[int], models: Sequence[Mapping[str, str]], reward, floors):
            out: dict[str, list[dict[str, Any]]] = {_behaviour_name(c): [] for c in models}
            for j in indices:
                rows = self._replan_candidates(
                    demos[j], goal[j], scenes[j], nominals[j], models, reward, floors
                )
                for candidate, row in zip(models, rows, strict=True):
                    out[_behaviour_name(candidate)].append({"demo": j, **row})
            return out

        n_folds = min(n, MAX_FOLDS) if cross else 0
        held_out: dict[str, list[dict[str, Any]]] = {name: [] for name in names}
        for fold in range(n_folds):
            held = [j for j in range(n) if j % n_folds == fold]
            keep = [j for j in range(n) if j % n_folds != fold]
            reward = self._refit_on(keep, demos, scenes, nominals)
            floors = self._floors(
                [demos[i] for i in keep], [scenes[i] for i in keep], [nominals[i] for i in keep]
            )
            for name, rows in replanned(held, candidates, reward, floors).items():
                held_out[name] += rows
        training = {} if cross else replanned(range(n), candidates, self.reward_, full_floors)
        scores = {name: _fidelity_scores((held_out if cross else training)[name]) for name in names}
        default, consistency = self._default_model(candidates, names, scores)
        ranked = sorted(
            names,
            key=lambda r: (
                scores[r]["refused"],
                scores[r]["clearance_relaxed"],
                scores[r]["mse"] * ((1.0 - SELECTION_MARGIN) if r == default else 1.0),
            ),
        )
        chosen = candidates[names.index(ranked[0])]
        self.route_ = chosen["route"]
        self.frame_ = chosen["frame"]
        self.clearances_ = full_floors[chosen["floor"]]
        if ranked[0] not in training:
            training = replanned(range(n), [chosen], self.reward_, full_floors)
        self.training_fidelity_ = [
            {k: v for k, v in row.items() if k != "replay_mse"} for row in training[ranked[0]]
        ]
        self.model_selection_ = {
            "criterion": (
                f"{'leave-one-demonstration-out' if n_folds == n else f'{n_folds}-fold'} "
                "replanning MSE"
                if cross
                else f"training replanning MSE (not cross-validated: {n} demonstrations)"
            ),
            "cross_validated": cross,
            "folds": n_folds,
            "default": default,
            "clearance_consistency": consistency,
            "chosen": ranked[0],
            "runner_up": ranked[1] if len(ranked) > 1 else None,
            "candidates": {
                name: {**candidate, **scores[name]}
                for name, candidate in zip(names, candidates, strict=True)
            },
        }

    def _warn_fidelity(self) -> None:
        """Warn when the demonstrations are emulated poorly (held out or replanned): what to do."""
        rows = self.training_fidelity_ or []
        pr = [r["improvement"] for r in rows if "refused" not in r]
        refused = [r["demo"] for r in rows if "refused" in r]
        if refused:
            warnings.warn(
                f"the learned skill finds no plan in the scene of obstacle demonstration(s) "
                f"{', '.join(map(str, refused))}; check that they pass clear of the obstacles' "
                "radii, or lower --clearance",
                UserWarning,
                stacklevel=3,
            )
        selection = self.model_selection_ or {}
        chosen = selection.get("candidates", {}).get(selection.get("chosen"), {})
        held_out = chosen.get("improvement_median") if selection.get("cross_validated") else None
        if held_out is not None and held_out < POOR_FIDELITY:
            warnings.warn(
                f"the learned skill emulates its demonstrations poorly: a demonstration left out "
                f"of the fit is replanned at a median Pr of {held_out:.0f} % over the nominal "
                f"(cross-validated, below {POOR_FIDELITY:.0f} %); add demonstrations with the "
                "obstacles at several distances from the path and on both sides of it, or "
                "check that the clean demonstrations give the path the others deviate from",
                UserWarning,
                stacklevel=3,
            )
        elif pr and float(np.median(pr)) < 50.0:
            warnings.warn(
                f"the learned skill replans its own training demonstrations poorly (median Pr "
                f"{np.median(pr):.0f} % over the nominal); add demonstrations with the obstacles "
                "at several distances from the path, check that the clean demonstrations give "
                "the path the obstacle demonstrations deviate from, or try --planner full",
                UserWarning,
                stacklevel=3,
            )

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
        if not hasattr(self, "clearances_"):
            self._reset_emulation()
        # A class's learned clearance comes with it (none where the source has none).
        theirs = getattr(source, "clearances_", {}) if isinstance(source, Skill) else {}
        self.clearances_ = {c: m for c, m in self.clearances_.items() if c not in wanted}
        self.clearances_ |= {c: theirs[c] for c in wanted if c in theirs}
        sizes = getattr(source, "class_radii_", {}) if isinstance(source, Skill) else {}
        own = getattr(self, "class_radii_", {})
        self.class_radii_ = {c: r for c, r in own.items() if c not in wanted}
        self.class_radii_ |= {c: sizes[c] for c in wanted if c in sizes}
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
            DMP rollout positions at equal time steps (denser where the
            skill's speed profile is slow, e.g. at the ends).
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
        self,
        start: Any = None,
        goal: Any = None,
        scene: Scene | None = None,
        *,
        duration: float | None = None,
        speed: float | None = None,
        start_orientation: Any = None,
        goal_orientation: Any = None,
        **options: Any,
    ) -> TimedPlan:
        """The timed plan for a new start, goal and scene: positions, times and velocities.

        The path is :meth:`plan_details`' (its keyword ``options``:
        ``planner``, ``horizon``, ``goal_approach``, ``clearance``,
        ``unknown_class``; its errors
        and safety guarantees), timed by its own arc length with the skill's
        speed profile :attr:`timing_` (learned from the demonstrations' times,
        or the ``timing`` law): it starts and ends at rest (unless the timing
        is ``"uniform"``) and lasts the skill's duration, so a plan that
        swerves (and is longer) runs uniformly faster, never in a burst where
        it swerves. With moving obstacles the timed plan is checked again at
        its own times (the planner used the nominal's) and re-planned at them
        where it is not clear (:meth:`_checked_at_own_times`); its
        ``details.clearance`` is then the clearance at its own times.

        Parameters
        ----------
        start, goal : array_like, shape (q,), optional
            Default: the generalized path's own.
        scene : Scene, optional
            Obstacles (default none).
        duration : float, optional
            Seconds the plan lasts (default ``timing_.duration``).
        speed : float, optional
            Or a speed factor: the plan lasts ``timing_.duration / speed``
            (2 runs twice as fast). Not with ``duration``.
        start_orientation, goal_orientation : array_like, shape (4,), optional
            Only for a skill with orientation (:attr:`orientation_dmp_`): the
            tool's orientation at the start and at the goal, unit quaternions
            ``[x, y, z, w]``; default the first and last of
            :attr:`orientations_`.
        **options
            :meth:`plan_details`' keywords, ``via`` among them: ``[(phase,
            point), ...]``, points the plan passes at those fractions of its
            duration (:meth:`via_path`). The nominal passes each exactly; the
            plan, resampled at constant speed, within a small fraction of the
            path's extent, and around obstacles as the planner must (a
            :class:`UserWarning` says when a plan misses a via-point by more
            than :data:`VIA_TOLERANCE` of the path's extent). A skill with
            orientation takes ``(phase, point, [x, y, z, w])``: the
            orientations are turned to that one at the time the plan passes
            ``point`` (:meth:`orientations_at`), start and goal kept.

        Returns
        -------
        TimedPlan
            ``times`` (n_points,) s, ``points`` (n_points, q), ``velocities``
            (n_points, q) units/s, ``details`` (:meth:`plan_details`' Plan),
            and for a skill with orientation ``orientations`` (n_points, 4):
            the orientation DMP's movement from ``start_orientation`` to
            ``goal_orientation``, sampled at each point's normalised time
            ``t / duration`` (the phase the position DMP and the speed
            profile share), so it ends *exactly* at the goal orientation.
            It stands for its points in NumPy expressions (``np.asarray(plan)``
            is ``plan.points``), as the ndarray this method used to return.

        Raises
        ------
        ValueError
            For a ``duration`` or ``speed`` that is not a positive, finite
            number, both given, or a duration outside 1e-6 to 1e9 s; an
            orientation that is not a unit quaternion, or one given to a
            skill without orientation; and :meth:`plan_details`' errors.
        """
        total = self._plan_duration(duration, speed)
        if scene is not None and isinstance(scene, Scene) and scene.moving:
            options.setdefault("duration", total)  # where the tool is when: this plan's timing
        ends = self._orientation_ends(start_orientation, goal_orientation)
        turns = self._via_orientations(options.get("via"), ends is not None)
        details = self.plan_details(start, goal, scene, **options)
        times, velocities = self.timing_.time_path(details.points, total)
        if scene is not None and isinstance(scene, Scene) and scene.moving:
            details, times, velocities = self._checked_at_own_times(
                details, times, velocities, total, start, goal, scene, options
            )
        orientations = None
        if ends is not None:
            if turns is not None:
                turns = (_passing_phases(details.points, times, options["via"], turns[0]), turns[1])
            orientations = self._orientations_at(times / total, *ends, via=turns)
        if options.get("via") is not None:
            _warn_via_missed(details.points, options["via"], self.units)
        return TimedPlan(
            times, details.points, velocities, details=details, orientations=orientations
        )

    def _checked_at_own_times(
        self,
        details: Plan,
        times: np.ndarray,
        velocities: np.ndarray,
        total: float,
        start: Any,
        goal: Any,
        scene: Scene,
        options: dict[str, Any],
    ) -> tuple[Plan, np.ndarray, np.ndarray]:
        """A moving-obstacle plan checked at the times it is run; re-planned at them if needed.

        The planner avoids each obstacle where it is when the tool reaches a
        point on the *nominal's* timing (:meth:`point_times`); the plan is then
        timed by its own arc length, a little different where it swerves (the
        issue-27 battery: 1.58 mm inside a marker crossing at 4 m/s, 14 ms
        later than planned). So the timed plan is checked at its own times
        (:func:`lfdkit.emulate.planner.moving_clearance`); where it fails, it
        is re-planned with those times and re-timed, up to
        :data:`RETIME_ROUNDS` rounds, and refused if it still fails.
        """
        from lfdkit.emulate.planner import UnsafePlanError, moving_clearance

        clearance = float(options.get("clearance", 0.0))
        margin = options.get("unknown_class")
        reward = self.reward_ if self.reward_ is not None else Reward(1.0, {})
        unknown, margin = _unknown_margins(reward, scene, margin, clearance)
        clearance = clearance + np.where(unknown, margin, 0.0)  # each obstacle's
        hard = scene.has_extent | (clearance > 0.0)
        start_point, goal_point = self._ends(start, goal)
        for round_ in range(RETIME_ROUNDS + 1):
            gaps = moving_clearance(details.points, times, scene, clearance, UNCERTAINTY_MARGIN)
            tolerance = 1e-9 * max(_extent(details.points), 1e-300)
            if not np.any((gaps < -tolerance) & hard):
                details.clearance = gaps
                return details, times, velocities
            if round_ == RETIME_ROUNDS:
                break
            details = self._plan(
                start_point,
                goal_point,
                scene,
                options.get("planner"),
                options.get("horizon"),
                options.get("goal_approach", "auto"),
                clearance,
                options.get("progress"),
                times,
                unknown_class=options.get("unknown_class"),
                via=options.get("via"),
                unknown_response=options.get("unknown_response"),
            )
            times, velocities = self.timing_.time_path(details.points, total)
        o = int(np.argmin(np.where(hard, gaps, np.inf)))
        raise UnsafePlanError(
            f"no collision-free timed plan: timed by its own length, the plan passes "
            f"{-gaps[o]:.3g} inside obstacle {o} ({scene.obstacles[o].label!r}, radius plus "
            f"clearance {clearance[o]:g}) even after {RETIME_ROUNDS} re-plans at its own times; "
            "a longer duration or a larger clearance may help"
        )

    def _orientation_ends(self, start: Any, goal: Any) -> tuple[np.ndarray, np.ndarray] | None:
        """The start and goal orientations checked (default the learned ones); None without."""
        self._check_fitted()
        if getattr(self, "orientation_dmp_", None) is None:
            for value, name in ((start, "start_orientation"), (goal, "goal_orientation")):
                if value is not None:
                    raise ValueError(
                        f"{name}: this skill has no orientation; learn it from demonstrations "
                        "with orientations (qx, qy, qz, qw)"
                    )
            return None
        first = self.orientations_[0] if start is None else None
        last = self.orientations_[-1] if goal is None else None
        if first is None:
            first = check_quaternions(start, "start_orientation", n=1)[0]
        if last is None:
            last = check_quaternions(goal, "goal_orientation", n=1)[0]
        return first, last

    def orientations_at(
        self,
        phases: Any,
        start_orientation: Any = None,
        goal_orientation: Any = None,
        via: Sequence[tuple[float, Any, Any]] | None = None,
    ) -> np.ndarray:
        """The orientation DMP's movement at normalised times ``phases`` (0 start, 1 goal).

        Parameters
        ----------
        phases : array_like, shape (n,)
            Fractions of the movement's duration, in [0, 1] (clipped).
        start_orientation, goal_orientation : array_like, shape (4,), optional
            Unit quaternions ``[x, y, z, w]``; default the learned first and last.
        via : sequence of (float, array_like (q,), array_like (4,)), optional
            :meth:`plan`'s via-points; those with an orientation (third item)
            bend the movement through it at their phase
            (:func:`lfdkit.imitate.via_points.orientations_through_via`);
            their points are not used here.

        Returns
        -------
        ndarray, shape (n, 4)
            Unit quaternions, signs continuous from the start's. At phase 0
            the start orientation, at phase 1 exactly the goal orientation;
            between, the rollout (exact at its samples, 8 per plan point and
            at least 1001) interpolated by slerp, bent through each
            via-point's orientation (exact at its phase).

        Raises
        ------
        ValueError
            For a skill without orientation, or an orientation that is not a
            unit quaternion.
        """
        ends = self._orientation_ends(start_orientation, goal_orientation)
        if ends is None:
            raise ValueError("skill: has no orientation (orientation_dmp_ is None)")
        u = np.clip(np.asarray(phases, dtype=np.float64).ravel(), 0.0, 1.0)
        if not np.all(np.isfinite(u)):
            raise ValueError("phases: contains NaN")
        return self._orientations_at(u, *ends, via=self._via_orientations(via, True))

    def _via_orientations(
        self, via: Sequence[tuple[Any, ...]] | None, oriented: bool
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """The via-points' orientations (phases, quaternions), checked; None if none given."""
        if via is None:
            return None
        check_via(via, self.n_dims_)  # the entries' shape, before their orientations
        phases, turns = check_via_orientations(via)
        if len(phases) == 0:
            return None
        if not oriented:
            first = [len(entry) > 2 and entry[2] is not None for entry in via].index(True)
            raise ValueError(
                f"via[{first}]: orientation: this skill has no orientation; drop it, or learn "
                "from demonstrations with orientations (qx, qy, qz, qw)"
            )
        return phases, turns

    def _orientations_at(
        self,
        phases: np.ndarray,
        start: np.ndarray,
        goal: np.ndarray,
        via: tuple[np.ndarray, np.ndarray] | None = None,
    ) -> np.ndarray:
        """:meth:`orientations_at` from checked phases, start, goal and via-orientations."""
        n_steps = max(1001, 8 * int(self.n_points))
        run = self.orientation_dmp_.rollout(start=start, goal=goal, n_steps=n_steps)
        rollout = run.orientations

        def sampled(u: np.ndarray) -> np.ndarray:
            position = np.clip(u, 0.0, 1.0) * (n_steps - 1)
            k = np.minimum(np.floor(position).astype(int), n_steps - 2)
            return slerp(rollout[k], rollout[k + 1], position - k)

        out = sampled(phases)
        # The DMP's error ends at exactly 0: the last sample is the goal itself.
        end = phases >= 1.0
        out[end] = goal if goal @ rollout[-1] >= 0.0 else -goal
        if via is not None:
            at, turns = via
            out = orientations_through_via(phases, out, at, turns, sampled(at))
        out = continuous(out)
        return out if out[0] @ start >= 0.0 else -out

    def _plan_duration(self, duration: float | None, speed: float | None) -> float:
        """Seconds a plan lasts: ``duration``, or the skill's divided by ``speed``."""
        self._check_fitted()
        if duration is not None and speed is not None:
            raise ValueError("speed: give duration or speed, not both")
        if duration is not None:
            total = check_positive(duration, "duration")
        else:
            factor = 1.0 if speed is None else check_positive(speed, "speed")
            total = self.timing_.duration / factor
        low, high = DURATION_RANGE
        if not low <= total <= high:
            what = "duration" if duration is not None else "speed"
            raise ValueError(
                f"{what}: the plan would last {total:g} s; expected {low:g} to {high:g} s"
            )
        return total

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
        progress: ProgressLike = None,
        duration: float | None = None,
        unknown_class: float | None = None,
        via: Sequence[tuple[float, Any]] | None = None,
        unknown_response: str | None = None,
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
            keeps out of radius plus clearance (a hard constraint). With
            ``model="auto"`` the clearance the demonstrations kept from the
            obstacle's class (:attr:`clearances_`) comes on top (halved for
            an obstacle nearer the start or goal than that; where no plan
            keeps it, half of it and then none, with a warning), and the
            plan's ``clearance`` is measured beyond both.
        progress : Progress, callable, bool or None
            Reports the planner's global search and its MPC steps over the
            plan's points (:func:`lfdkit.core.progress.as_progress`); default silent.
        duration : float, optional
            Seconds the plan lasts (default ``timing_.duration``): with moving
            obstacles in ``scene``, the tool reaches plan point ``k`` at
            ``point_times()[k]`` and each obstacle is avoided where it
            is predicted then (:func:`lfdkit.emulate.plan_path`'s ``times``).
            Not used for a static scene.
        unknown_class : float, optional
            Opt-in for obstacles of a class this skill never learned: a margin
            (units, >= 0). Each such obstacle becomes a hard constraint, its
            radius plus this margin (plus ``clearance``), with *no* learned
            response (the plan keeps out but does not swerve as a demonstrator
            would); a ``UserWarning`` names the classes. Default None: such a
            scene is refused (the error names this option).
        via : sequence of (float, array_like (q,)), optional
            Via-points ``(phase, point)``: the nominal is bent through each
            ``point`` at ``phase``, the fraction of the movement's duration
            (strictly between 0 and 1), the way the demonstrations varied
            (:meth:`via_path`); the planner then follows it.
        unknown_response : str, optional
            With ``unknown_class``, the response such an obstacle gets besides
            its hard radius: None (default) none; ``"nearest"`` the response of
            the learned class nearest in size (:attr:`class_radii_` against
            the median radius of the class's obstacles in ``scene``); or the
            name of a learned class. The warning says which class was used.

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
            obstacles when no reward is learned) unless ``unknown_class`` is
            given, a negative ``unknown_class``, an ``unknown_response`` that
            is neither ``"nearest"`` nor a learned class (or ``"nearest"`` for
            a skill without :attr:`class_radii_`), a start or goal inside an
            obstacle, a horizon outside 4-12, or a via-point that is not a
            ``(phase, point)`` pair with a phase in (0, 1) and a point of the
            skill's dimension.
        """
        start, goal = self._ends(start, goal)
        times = None
        if isinstance(scene, Scene) and scene.moving:
            times = self.point_times(duration)
        return self._plan(
            start,
            goal,
            scene,
            planner,
            horizon,
            goal_approach,
            clearance,
            progress,
            times,
            unknown_class=unknown_class,
            via=via,
            unknown_response=unknown_response,
        )

    def via_path(
        self,
        via: Sequence[tuple[float, Any]] | None = None,
        start: Any = None,
        goal: Any = None,
    ) -> ViaPath:
        """The nominal bent through via-points, with the band the demonstrations leave around it.

        The DMP carries the path to ``start`` and ``goal`` (:meth:`nominal`);
        a deformation in the basis of :attr:`promp_`, with the demonstrations'
        weight covariance, is conditioned to be 0 at both ends and to reach
        each via-point (:func:`lfdkit.imitate.via_points.through_via_points`):
        where the demonstrations varied, the path moves as they did.

        Parameters
        ----------
        via : sequence of (float, array_like (q,)), optional
            ``(phase, point)`` pairs, phase strictly between 0 and 1 (the
            fraction of the movement's duration). None: no via-point (the
            nominal, with the band of the demonstrations' spread).
        start, goal : array_like, shape (q,), optional
            Default: the generalized path's own.

        Returns
        -------
        ViaPath
            ``points`` (the nominal's samples plus one per via-point, which is
            the via-point itself), their ``phases`` (fractions of the
            nominal's length, the ProMP's phase), the conditioned
            ``deformation``, the demonstrations' ``spread`` left around it
            (its ``covariance_at(phases)`` is the band, units²)
            and each via-point's ``miss`` (0 unless a warning said otherwise).
        """
        start, goal = self._ends(start, goal)
        nominal = self._nominal(start, goal)
        if via is None:
            phases, points = np.zeros(0), np.zeros((0, self.n_dims_))
        else:
            phases, points = check_via(via, self.n_dims_)
        # The rollout is at equal time steps: the via-points' phases are fractions of
        # time; the bending's (and the ProMP's) are fractions of the length travelled.
        travelled = arc_length(nominal)
        length = travelled / travelled[-1]
        at = np.interp(phases, np.linspace(0.0, 1.0, len(nominal)), length)
        return through_via_points(nominal, length, at, points, getattr(self, "promp_", None))

    def point_times(self, duration: float | None = None) -> np.ndarray:
        """When the tool reaches each of the plan's ``n_points`` points (s), on the nominal.

        The skill's speed profile (:attr:`timing_`) along a path sampled at
        constant arc length: point ``k`` is reached at
        ``duration · phase(k / (n_points − 1))``
        (:meth:`lfdkit.imitate.SpeedProfile.phase`). A plan that swerves is a
        little longer; timed by its own length it runs uniformly faster, so
        point ``k`` is reached at nearly the same time (the assumption with
        which moving obstacles are predicted).

        Parameters
        ----------
        duration : float, optional
            Seconds (default ``timing_.duration``).

        Returns
        -------
        ndarray, shape (n_points,)
        """
        total = self._plan_duration(duration, None)
        return total * self.timing_.phase(np.linspace(0.0, 1.0, int(self.n_points)))

    def _plan(
        self,
        start: np.ndarray,
        goal: np.ndarray,
        scene: Scene | None,
        planner: PlannerKind | None,
        horizon: int | None,
        goal_approach: float | str | None,
        clearance: float,
        progress: ProgressLike = None,
        times: np.ndarray | None = None,
        *,
        route: str | None = None,
        unknown_class: float | None = None,
        via: Sequence[tuple[float, Any]] | None = None,
        reward: Reward | None = None,
        clearances: Mapping[str, float] | None = None,
        frame: str | None = None,
        unknown_response: str | None = None,
    ) -> Plan:
        """:meth:`plan_details` from a checked start and goal.

        ``route``, ``reward``, ``clearances`` and ``frame`` default to the
        skill's (:attr:`route_`, :attr:`reward_`, :attr:`clearances_`,
        :attr:`frame_`); the model choice plans with others. ``via`` bends the
        nominal through via-points (:meth:`via_path`).
        """
        if via is None:
            nominal = self._nominal(start, goal)
        else:
            nominal = self.via_path(via, start, goal).points
        scene = Scene() if scene is None else scene
        if not isinstance(scene, Scene):
            raise TypeError(f"scene: expected a Scene, got {type(scene).__name__}")
        kind = self.planner if planner is None else planner
        OneOf(PLANNERS)(kind, "planner")
        # No route learned (a reward adopted, an older file): the MPC with lookahead, as before.
        route = route or getattr(self, "route_", None) or self._unfitted_route()
        if kind == "mpc" and (route != "full" or planner == "mpc"):
            h = int(self.horizon) if horizon is None else horizon
        else:
            h = None
        reward = self.reward_ if reward is None else reward
        if reward is None:
            if len(scene) and unknown_class is None:
                raise ValueError(
                    "scene: has obstacles, but this skill has no obstacle reward; learn one "
                    "with fit_reward() (demonstrations around obstacles) or adopt() it; "
                    f"{_UNKNOWN_HOW}"
                )
            reward = Reward(1.0, {})
        unknown, margin = _unknown_margins(reward, scene, unknown_class, clearance)
        responses = self._stand_in_classes(reward, scene, unknown, unknown_response)
        unknown_margin = np.where(unknown, margin, 0.0)
        if unknown.any():
            reach = scene.radii + clearance + unknown_margin
            reward = _with_stand_ins(reward, scene, unknown, reach, responses)
            _warn_unknown(
                scene, unknown, margin, self.units, responses, getattr(self, "class_radii_", {})
            )
        options = dict(
            horizon=h,
            n_points=int(self.n_points),
            max_slope=float(self.max_slope),
            goal_approach=goal_approach,
            progress=progress,
            times=times,
            lookahead=route != "window",
        )
        margins = self._margins(scene, start, goal, clearance, clearances)
        frame = frame or getattr(self, "frame_", "world")
        if (self.model == "path" or frame == "path") and len(scene) and not scene.moving:
            reward, scene = self._in_path_frame(reward, scene, nominal)
        # The thesis's MPC can walk into a dead end the lookahead sees: then that.
        routes = [route] + (["lookahead"] if route == "window" and h is not None else [])
        shares = (1.0, 0.5, 0.0) if margins is not None else (0.0,)
        # At least the clearance the demonstrations kept; where no plan keeps it
        # all (a narrow passage every way round), half of it, then none, said.
        for share in shares:
            plan = None
            for way in routes:
                options["lookahead"] = way != "window"
                extra = clearance + unknown_margin + (0.0 if margins is None else share * margins)
                try:
                    plan = plan_path(reward, nominal, scene, clearance=extra, **options)
                    break
                except UnsafePlanError:
                    if share == 0.0 and way == routes[-1]:
                        raise
            if plan is None:
                continue
            if margins is not None and share < 1.0:
                warnings.warn(
                    "plan: no plan keeps the clearance the demonstrations kept from the "
                    f"obstacles (up to {margins.max():.3g} {self.units}); planned with "
                    f"{share:.0%} of it",
                    UserWarning,
                    stacklevel=4,
                )
            return plan
        raise AssertionError("unreachable")  # pragma: no cover

    def _stand_in_classes(
        self, reward: Reward, scene: Scene, unknown: np.ndarray, response: str | None
    ) -> dict[str, str | None]:
        """For each unlearned class in ``scene``, the learned class whose response it takes.

        ``response`` is :meth:`plan_details`' ``unknown_response``: None (no
        response), ``"nearest"`` (the learned class whose obstacles'
        median radius :attr:`class_radii_` is nearest the class's own median
        radius in ``scene``; ties go to the first learned) or a learned class.
        """
        learned = tuple(reward.classes)
        if response is not None and (not isinstance(response, str) or response == ""):
            raise ValueError(
                f"unknown_response: expected 'nearest', a learned class or None, got {response!r}"
            )
        if response not in (None, "nearest") and response not in learned:
            known = ", ".join(repr(c) for c in learned) or "none"
            raise ValueError(
                f"unknown_response: {response!r} is not a learned class (learned: {known}); "
                "name one of them, 'nearest' or none"
            )
        labels = np.array(scene.labels, dtype=object)
        classes = list(dict.fromkeys(labels[unknown]))
        if response != "nearest":
            return {label: response for label in classes}
        sizes = getattr(self, "class_radii_", {})
        candidates = [c for c in learned if c in sizes]
        if classes and not candidates:
            raise ValueError(
                "unknown_response: 'nearest' needs the sizes of the learned classes' "
                "obstacles, which this skill lacks (a reward adopted, or a file from before "
                f"them); name the class whose response to use ({', '.join(learned) or 'none'})"
            )
        out = {}
        for label in classes:
            radius = float(np.median(scene.radii[labels == label]))
            out[label] = min(candidates, key=lambda c: abs(sizes[c] - radius))
        return out

    def _in_path_frame(
        self, reward: Reward, scene: Scene, nominal: np.ndarray
    ) -> tuple[Reward, Scene]:
        """``model="path"``: the reward turned into ``nominal``'s frame at each obstacle."""
        if self.n_dims_ != 2:
            raise ValueError(
                f"model: 'path' turns responses in the plane only, this skill is "
                f"{self.n_dims_}-D; use model='auto'"
            )
        axis = (self.ioc_info_ or {}).get("frame_axis")
        if axis is None:  # a reward adopted: learned along this path, as far as is known
            axis = self.path_[-1] - self.path_[0]
        return in_path_frame(reward, scene, nominal, np.asarray(axis, dtype=np.float64))

    def _margins(
        self,
        scene: Scene,
        start: np.ndarray,
        goal: np.ndarray,
        clearance: float,
        clearances: Mapping[str, float] | None = None,
    ) -> np.ndarray | None:
        """The learned clearance of each obstacle of ``scene`` (units), or None for none.

        Where the task's own start or goal is nearer an obstacle than its
        class's learned clearance, that obstacle keeps half the distance (the
        plan must start and end there).
        """
        learned = getattr(self, "clearances_", None) if clearances is None else clearances
        if not learned or not len(scene) or scene.moving:
            return None
        margins = np.array([learned.get(label, 0.0) for label in scene.labels])
        if not margins.any():
            return None
        ends = np.minimum(scene.distances(start[None]), scene.distances(goal[None]))
        room = 0.5 * np.maximum(ends - check_positive(clearance, "clearance", allow_zero=True), 0.0)
        return np.minimum(margins, room)

    def evaluate(
        self,
        demos: Sequence[Any],
        scenes: Sequence[Scene] | None = None,
        *,
        goals: Any = None,
        goal_approach: float | str | None = "auto",
        progress: ProgressLike = None,
    ) -> dict[str, float]:
        """Scores on held-out demonstrations in their scenes (thesis MSE_R and Pr).

        Each demonstration is compared with the plan from its first point to
        its goal (default the generalized path's goal) in its scene, and with
        the nominal replayed without the obstacle term. ``goal_approach`` is
        :meth:`plan`'s: by default the plan the robot would execute, which
        ends at the goal; None scores the thesis's model, which matches
        demonstrators that swerve late and end beside the goal. ``progress``
        counts the plans (:func:`lfdkit.core.progress.as_progress`).
        ``demos`` may be :class:`~lfdkit.model.demos.Demo` records, each with
        its scene (then ``scenes`` is not given).

        Returns
        -------
        dict
            ``mse`` (MSE_R of the plans, units²), ``mse_replay`` (MSE_Mp of the
            nominals) and ``improvement`` (Pr, percent), over 100 points per path.
        """
        self._check_fitted()
        demos, scenes = _obstacle_records(demos, scenes, "demos", required=True)
        demos = check_demos(demos, "demos", n_dims=self.n_dims_)
        scenes = list(scenes)
        if len(scenes) != len(demos):
            raise ValueError(f"scenes: {len(scenes)} scenes for {len(demos)} demonstrations")
        goal = self._goals(goals, len(demos))
        # The demonstrations' starts and the goals are checked: straight to the planner.
        plans = []
        label = f"evaluate: plan each of {len(demos)} held-out demonstrations"
        with as_progress(progress).stage(label, total=len(demos)) as stage:
            for demo, g, scene in zip(demos, goal, scenes, strict=True):
                plans.append(self._plan(demo[0], g, scene, None, None, goal_approach, 0.0).points)
                stage.advance()
        nominals = [self._nominal(demo[0], g) for demo, g in zip(demos, goal, strict=True)]
        mse = metrics.mse_paths(plans, demos)
        replay = metrics.mse_paths(nominals, demos)
        return {"mse": mse, "mse_replay": replay, "improvement": metrics.improvement(replay, mse)}

    def to_units(self, units: str) -> Skill:
        """The same skill with every length in ``units`` (``"m"``, ``"cm"`` or ``"mm"``).

        The generalized path is multiplied by the conversion factor ``f``
        (:func:`lfdkit.core.units.conversion_factor`, 1000 from metres to
        millimetres) and the DMP is fitted on it again (a linear fit: the same
        movement, scaled); the reward's nominal weight and precisions, in
        1/units², are divided by ``f²``. Plans of the converted skill are the
        original's times ``f``, to the planner's tolerance (about 1e-7 of the
        path's extent).

        Parameters
        ----------
        units : {"m", "cm", "mm"}
            The new unit.

        Returns
        -------
        Skill
            ``self`` when ``units`` is already the skill's; otherwise a new
            fitted skill with the same parameters but ``units``. The fit's
            diagnostics are not carried over: its ``mimic_info_`` says where
            the path came from, ``ioc_info_``, ``mimic_`` and ``ioc_`` are None.

        Raises
        ------
        ValueError
            If ``units`` is not a known unit (the message lists them).
        sklearn.exceptions.NotFittedError
            If the skill is not fitted.
        """
        self._check_fitted()
        check_units(units)
        if units == self.units:
            return self
        factor = conversion_factor(self.units, units)
        skill = type(self)(**{**self.get_params(), "units": units})
        method = self.mimic_info_.get("method", "given")
        skill.use_path(
            self.path_ * factor,
            source=f"{method} path in {self.units}",
            timing=self.timing_,  # seconds and a normalised speed law: no unit to convert
            orientations=self.orientations_,
        )
        if getattr(self, "promp_", None) is not None:
            skill.promp_ = self.promp_.scaled(factor)
        if self.reward_ is not None:
            area = factor**2
            precisions = {c: m / area for c, m in self.reward_.precisions.items()}
            skill.adopt(Reward(self.reward_.nominal_weight / area, precisions))
            skill.route_ = getattr(self, "route_", None)
            skill.frame_ = getattr(self, "frame_", "world")
            skill.clearances_ = {c: m * factor for c, m in self.clearances_.items()}
            skill.model_selection_ = getattr(self, "model_selection_", None)
            skill.class_radii_ = {
                c: r * factor for c, r in getattr(self, "class_radii_", {}).items()
            }
        return skill

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
        timing = self.timing_
        # Stored unless it is the law the parameters give (as in files before timings).
        learned = timing != SpeedProfile.from_law(self.timing, self._law_duration(self.path_))
        params = self.get_params()
        if params["model"] == SKILL_DEFAULTS["model"]:
            del params["model"]  # as in files before models: they read back the same
        emulation = None
        route = getattr(self, "route_", None)
        radii = dict(getattr(self, "class_radii_", {}))
        if self.reward_ is not None and (route is not None or self.clearances_ or radii):
            route = route or self._unfitted_route()
            emulation = {"route": route, "clearances": dict(self.clearances_)}
            if getattr(self, "frame_", "world") != "world":  # as in files before frames
                emulation["frame"] = self.frame_
            if radii:
                emulation["radii"] = radii
        return skill_file.to_document(
            params,
            n_dims=self.n_dims_,
            units=self.units,
            path=self.path_,
            mimic_info=self.mimic_info_,
            reward=reward,
            ioc_info=self.ioc_info_,
            timing=timing.to_dict() if learned else None,
            orientations=self.orientations_,
            emulation=emulation,
            # The fitted DMPs as they plan: loading restores them, never refits (issue 30).
            dmp={k: v for k, v in self.dmp_.to_state().items() if k != "path"},
            orientation_dmp=self._stored_orientation_dmp(),
            promp=None if getattr(self, "promp_", None) is None else self.promp_.to_state(),
        )

    def _stored_orientation_dmp(self) -> dict[str, Any] | None:
        """The orientation DMP's state for the file; None (refit on load) when too long.

        It holds its own training samples (``max(1000, 10 n)`` for a path of
        ``n`` points): beyond :data:`_MAX_STORED_ORIENTATION_SAMPLES` the file
        would outgrow :data:`MAX_SKILL_FILE_BYTES`, so that rare skill refits it.
        """
        dmp = self.orientation_dmp_
        if dmp is None or len(dmp.dmp_.path_) > _MAX_STORED_ORIENTATION_SAMPLES:
            return None
        return dmp.to_state()

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, source: str = "skill") -> Skill:
        """Rebuild a skill from :meth:`to_dict`'s output.

        The fields are read by :class:`lfdkit.io.skill_file.SkillDocument`;
        the skill checks its parameters, restores the DMP as fitted (refits
        it on the path for a file without ``dmp``) and rebuilds the reward
        from them, in that order.

        Raises
        ------
        ValueError
            For another format, a newer version, or a missing or broken field;
            the message starts with ``source`` and names the field.
        """
        document = skill_file.SkillDocument(data, source)
        params = document.params(cls().get_params())
        units = document.units()
        if units is not None:  # a file without it (or without params.units) is in metres
            stated = params.setdefault("units", units)
            if stated != units:
                raise ValueError(
                    f"{source}: units: {units!r} does not match params.units {stated!r}"
                )
        try:
            skill = cls(**params)
            skill._validate_params()
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{source}: params: {exc}") from None
        n_dims = document.n_dims()
        path = document.path(n_dims)
        raw_timing = document.timing()
        timing = None
        if raw_timing is not None:
            timing = SpeedProfile.from_dict(raw_timing, f"{source}: timing")
        orientations = document.orientations(len(path))
        try:
            fitted = _stored_dmps(skill, document, path, timing, orientations)
            skill._use_path(path, "given", timing, orientations, fitted)
            skill.mimic_info_ = document.mimic()
            skill.promp_ = _stored_promp(document, n_dims)
            reward = document.reward(n_dims)
            if reward is not None:
                weight, matrices = reward
                skill.adopt(Reward(weight, matrices))
            skill.ioc_info_ = document.ioc()
            emulation = document.emulation()
            if emulation is not None and skill.reward_ is not None:
                skill.route_, skill.clearances_, skill.frame_ = emulation
                skill.class_radii_ = document.class_radii()
                fit = skill.ioc_info_ or {}
                skill.training_fidelity_ = fit.get("training_fidelity")
                skill.model_selection_ = fit.get("model_selection")
            _check_learned_classes(skill)
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


def learn(
    demos_path: str | os.PathLike[str] | Sequence[str | os.PathLike[str]],
    scenes_path: str | os.PathLike[str] | None = None,
    *,
    progress: ProgressLike = None,
    **params: Any,
) -> Skill:
    """Learn a skill from files: :func:`~lfdkit.io.training.read_training_data`, then ``fit``.

    ``demos_path`` may be several files, one set (a CSV without a ``demo``
    column is one demonstration, named by its file's stem).
    ``params`` are :class:`Skill`'s parameters. When the demonstrations file
    has times (a ``t`` column), the skill's timing is learned from those of
    the clean demonstrations; when it has orientations (``qx, qy, qz, qw``),
    the skill's orientation (:attr:`Skill.orientations_`, its DMP) from
    theirs. The ``lfdkit learn`` command calls exactly this.
    ``progress`` is :meth:`Skill.fit`'s (default silent).
    """
    progress = as_progress(progress)
    with progress.stage("read the demonstration and scene files"):
        data = read_training_data(demos_path, scenes_path)
    skill = Skill(**params)
    skill.fit(data.clean, data.around_obstacles or None, progress=progress)
    # Each replanned training scene by its demonstration's id in the file.
    stored = (skill.ioc_info_ or {}).get("training_fidelity") or []
    for rows in (skill.training_fidelity_ or [], stored):
        for row in rows:
            row["id"] = data.obstacle_ids[row["demo"]]
    return skill


# ------------------------------------------------------------------ helpers
def _stored_dmps(
    skill: Skill,
    document: skill_file.SkillDocument,
    path: np.ndarray,
    timing: SpeedProfile | None,
    orientations: np.ndarray | None,
) -> tuple[DMP, QuaternionDMP | None] | None:
    """The DMPs a skill file stores, restored and checked against the skill; None to refit.

    None for a file without them (before issue 30). A state that does not
    belong to this skill (another path, timing, basis count or scaling) is
    refused: planning with it would not be what the file says.
    """
    state = document.dmp()
    if state is None:
        if not isinstance(skill.n_basis, str) and skill.n_basis > skill_file.MAX_REFIT_BASIS:
            raise ValueError(
                f"params.n_basis: {skill.n_basis} basis functions, but no fitted DMP (dmp) to "
                f"restore; a file without it holds at most {skill_file.MAX_REFIT_BASIS} "
                "(refitting more takes tens of seconds): save the skill again with this lfdkit"
            )
        return None
    dmp = DMP.from_state({**state, "path": path}, "dmp")
    law = timing or SpeedProfile.from_law(skill.timing, skill._law_duration(path))
    wanted = {
        "duration": (dmp.duration_, law.duration),
        "params.scaling": (dmp.scaling, skill.scaling),
        "params.n_basis": (dmp.n_basis, skill.n_basis),
        "timing": (
            dmp.timing_ is not None and tuple(dmp.timing_.coefficients),
            tuple(law.coefficients),
        ),
    }
    for name, (stored, expected) in wanted.items():
        if stored != expected:
            said = "another speed profile" if name == "timing" else f"{stored!r}"
            raise ValueError(
                f"dmp.{name}: the stored DMP was fitted with {said}, not the skill's; "
                "remove the dmp field to refit"
            )
    orientation_state = document.orientation_dmp()
    if orientations is None or orientation_state is None:
        return dmp, None  # a skill with orientations but none stored: fitted again
    return dmp, QuaternionDMP.from_state(orientation_state, "orientation.dmp")


#: How a plan around an obstacle class never learned is asked for (in refusals).
_UNKNOWN_HOW = (
    "to plan around it as a hard radius plus a margin with no learned response, pass "
    "unknown_class=MARGIN (lfdkit plan/execute: --unknown-class margin=M)"
)

#: Width of the stand-in response of an unlearned class, as a fraction of its hard
#: radius: ``exp(-(1/0.01)^2)`` = 0 at the constraint's edge, so it shapes nothing.
_UNKNOWN_RESPONSE_WIDTH = 0.01


def _stored_promp(document: skill_file.SkillDocument, n_dims: int) -> ProMP | None:
    """The file's ProMP (:attr:`Skill.promp_`), of the skill's dimension; None without."""
    state = document.promp()
    if state is None:
        return None
    promp = ProMP.from_state(state, f"{document.source}: promp")
    if promp.n_dims_ != n_dims:
        raise ValueError(
            f"{document.source}: promp.n_dims: {promp.n_dims_}, but the path is {n_dims}-D"
        )
    return promp


def _unknown_margins(
    reward: Reward, scene: Scene, margin: float | None, clearance: float
) -> tuple[np.ndarray, float]:
    """Which obstacles are of a class ``reward`` never learned (mask), and their margin.

    Without ``margin`` a scene with such a class is refused, the error naming
    the opt-in; with it, each such obstacle must have something to keep out
    of (radius plus clearance plus margin above 0).
    """
    unknown = np.array([label not in reward.precisions for label in scene.labels], dtype=bool)
    if margin is not None:
        margin = check_positive(margin, "unknown_class", allow_zero=True)
    if not unknown.any():
        return unknown, 0.0
    if margin is None:
        label = scene.labels[int(np.argmax(unknown))]
        known = ", ".join(repr(c) for c in reward.classes) or "none"
        raise ValueError(
            f"scene: obstacle class {label!r} was never learned (learned classes: {known}); "
            f"{_UNKNOWN_HOW}, or demonstrate around it"
        )
    reach = scene.radii + check_positive(clearance, "clearance", allow_zero=True) + margin
    point = np.flatnonzero(unknown & (reach <= 0.0))
    if point.size:
        o = int(point[0])
        raise ValueError(
            f"unknown_class: obstacle {o} ({scene.labels[o]!r}) has radius 0 and no "
            f"clearance, so margin {margin:g} leaves nothing to keep out of; give a "
            "positive margin"
        )
    return unknown, margin


def _median_radii(scenes: Sequence[Scene], classes: Sequence[str]) -> dict[str, float]:
    """Per class, the median radius (units) of its obstacles over ``scenes``."""
    radii: dict[str, list[float]] = {c: [] for c in classes}
    for scene in scenes:
        for label, radius in zip(scene.labels, scene.radii, strict=True):
            if label in radii:
                radii[label].append(float(radius))
    return {c: float(np.median(values)) for c, values in radii.items() if values}


def _with_stand_ins(
    reward: Reward,
    scene: Scene,
    unknown: np.ndarray,
    reach: np.ndarray,
    responses: dict[str, str | None],
) -> Reward:
    """``reward`` with a stand-in for every unlearned class.

    The planner needs a precision for every class. Where ``responses`` names
    a learned class, the unlearned one takes its precision; where it names
    none, the stand-in is so narrow (:data:`_UNKNOWN_RESPONSE_WIDTH` of the
    class's smallest hard radius ``reach``, units) that it is nil wherever
    the plan may go.
    """
    labels = np.array(scene.labels, dtype=object)
    stand_ins = {}
    for label in dict.fromkeys(labels[unknown]):
        like = responses.get(label)
        if like is not None:
            stand_ins[label] = reward.precisions[like]
            continue
        width = _UNKNOWN_RESPONSE_WIDTH * float(reach[labels == label].min())
        stand_ins[label] = np.full(scene.positions.shape[1], 1.0 / width**2)
    return Reward(reward.nominal_weight, {**reward.precisions, **stand_ins})


def _warn_unknown(
    scene: Scene,
    unknown: np.ndarray,
    margin: float,
    units: str,
    responses: dict[str, str | None],
    sizes: dict[str, float],
) -> None:
    """Says which obstacles are planned around as hard radii, with which response (one line)."""
    labels = np.array(scene.labels, dtype=object)
    classes = list(dict.fromkeys(labels[unknown]))
    count = int(np.count_nonzero(unknown))
    borrowed = []
    for label in classes:
        like = responses.get(label)
        if like is None:
            continue
        said = f"{label!r} takes the learned response of {like!r}"
        if like in sizes:
            radius = float(np.median(scene.radii[labels == label]))
            said += f" (radius {radius:.3g} {units} against {sizes[like]:.3g} {units})"
        borrowed.append(said)
    if not borrowed:
        how = (
            " with no learned response: the plan keeps out but does not swerve as a "
            "demonstrator would; demonstrate around the class to learn its response"
        )
    else:
        bare = [repr(c) for c in classes if responses.get(c) is None]
        how = "; " + "; ".join(borrowed) + (f"; {', '.join(bare)} no response" if bare else "")
        how += "; demonstrate around the class to learn its own response"
    warnings.warn(
        f"plan: obstacle class{'es' * (len(classes) != 1)} "
        f"{', '.join(repr(c) for c in classes)} never learned: planned around "
        f"{'it' if count == 1 else 'them'} ({count} obstacle{'s' * (count != 1)}) as a hard "
        f"radius plus margin {margin:g} {units} (plus the clearance){how}",
        UserWarning,
        stacklevel=5,
    )


def _clean_records(demos: Any, times: Any, orientations: Any) -> tuple[Any, Any, Any]:
    """Clean demonstrations, their times and orientations, from records or as given."""
    fields = demo_fields(demos, "demos", given={"times": times, "orientations": orientations})
    if fields is None:
        return demos, times, orientations
    for j, scene in enumerate(fields.scenes):
        if scene is not None and len(scene):
            raise ValueError(
                f"demos[{j}]: recorded around obstacles ({len(scene)} in its scene, demo "
                f"{fields.ids[j]!r}); give it in obstacle_demos, the clean demonstrations in demos"
            )
    return fields.points, fields.times, fields.orientations


def _obstacle_records(
    demos: Any, scenes: Any, name: str = "obstacle_demos", *, required: bool = False
) -> tuple[Any, Any]:
    """Demonstrations in scenes (argument ``name``) and their scenes, from records or as given.

    With ``required``, demonstrations given as arrays need ``scenes``.
    """
    fields = demo_fields(demos, name, given={"scenes": scenes})
    if fields is None:
        if required and scenes is None:
            raise ValueError("scenes: give one scene per demonstration (or Demo records)")
        return demos, scenes
    missing = next((j for j, scene in enumerate(fields.scenes) if scene is None), None)
    if missing is not None:
        raise ValueError(
            f"{name}[{missing}]: the record (demo {fields.ids[missing]!r}) has no "
            "scene; give each record the scene it was recorded in"
        )
    return fields.points, fields.scenes


def _passing_phases(
    points: np.ndarray, times: np.ndarray, via: Sequence[tuple[Any, ...]], phases: np.ndarray
) -> np.ndarray:
    """When the timed plan passes each oriented via-point, as fractions of its duration.

    The plan is timed by its own length (:meth:`SpeedProfile.time_path`), so it
    passes a via-point a little off the phase asked (measured: 0.317 for 0.3,
    where the orientation would then be 1.8° off); the orientation is turned to
    be exact where the tool *is* at the point. A via-point the plan misses by
    more than :data:`VIA_TOLERANCE` of its extent (warned) keeps the phase asked.
    """
    oriented = [entry for entry in via if len(entry) > 2 and entry[2] is not None]
    _, targets = check_via([(entry[0], entry[1]) for entry in oriented], points.shape[1])
    along, _, miss = project_onto_polyline(targets, points)
    passing = np.interp(along, arc_length(points), times) / times[-1]
    near = (miss <= VIA_TOLERANCE * _extent(points)) & (passing > 0.0) & (passing < 1.0)
    return np.where(near, passing, phases)


def _warn_via_missed(points: np.ndarray, via: Sequence[tuple[float, Any]], units: str) -> None:
    """A warning naming the via-points a plan passes farther than :data:`VIA_TOLERANCE` from."""
    _, targets = check_via(via, points.shape[1])
    miss = polyline_distances(targets, points)
    limit = VIA_TOLERANCE * _extent(points)
    far = np.flatnonzero(miss > limit)
    if far.size:
        i = int(far[0])
        warnings.warn(
            f"via[{i}]: the plan passes {miss[i]:.3g} {units} from it ({far.size} of "
            f"{len(targets)} via-points farther than {limit:.3g} {units}): an obstacle (its "
            "learned response) or the planner's action bound pulls the plan away; move the "
            "via-point or the obstacle, or raise max_slope",
            UserWarning,
            stacklevel=3,
        )


def _behaviour_name(candidate: Mapping[str, str]) -> str:
    """A behaviour model's short name: ``"window"``, ``"lookahead+closest"``, ``"path:window"``."""
    name = candidate["route"]
    if candidate["floor"] != "none":
        name += f"+{candidate['floor']}"
    return f"path:{name}" if candidate["frame"] == "path" else name


def _fidelity_scores(rows: Sequence[Mapping[str, Any]]) -> dict[str, Any]:
    """A behaviour model's replanning scores over fidelity rows (:meth:`Skill._replan`'s)."""
    planned = [r for r in rows if "refused" not in r]
    pr = [r["improvement"] for r in planned]
    replay = sum(r["replay_mse"] for r in planned)
    mse = float(np.mean([r["mse"] for r in planned])) if planned else np.inf
    return {
        "refused": len(rows) - len(planned),
        "clearance_relaxed": sum(r["clearance_relaxed"] for r in planned),
        "mse": mse,
        "improvement_pooled": (
            float(100.0 * (1.0 - mse * len(planned) / replay)) if planned and replay > 0 else None
        ),
        "improvement_median": float(np.median(pr)) if pr else None,
        "improvement_mean": float(np.mean(pr)) if pr else None,
        "sides_agree": float(np.mean([r["sides_agree"] for r in planned])) if planned else None,
    }


def _check_orientations_list(
    orientations: Sequence[Any] | None, demos: list[np.ndarray]
) -> list[np.ndarray] | None:
    """One (n_j, 4) unit-quaternion array per demonstration, or None for none at all."""
    if orientations is None:
        return None
    if isinstance(orientations, np.ndarray) and orientations.ndim == 2:
        raise TypeError(
            "orientations: expected a sequence of (n_j, 4) arrays, one per demonstration"
        )
    orientations = list(orientations)
    if len(orientations) != len(demos):
        raise ValueError(
            f"orientations: {len(orientations)} arrays for {len(demos)} demonstrations; "
            "give one (n_j, 4) array per demonstration"
        )
    given = [o is not None for o in orientations]
    if not any(given):
        return None
    if not all(given):
        raise ValueError(
            f"orientations: orientations[{given.index(False)}] is None; give orientations for "
            "every demonstration or none"
        )
    return [
        check_quaternions(o, f"orientations[{j}]", n=len(demo))
        for j, (o, demo) in enumerate(zip(orientations, demos, strict=True))
    ]


def _extent(path: np.ndarray) -> float:
    return float(np.max(np.ptp(path, axis=0))) or 1.0
