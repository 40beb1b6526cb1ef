"""The estimator :class:`Skill`: its parameters, learning (mimic, imitate, emulate), :func:`learn`.

The class is put together from the mixins of the package's other modules
(planning, the behaviour-model choice, orientation, via-points, unknown
classes, files), so each part of the skill reads on its own; this module
keeps what learns: :meth:`Skill.fit`, :meth:`Skill.fit_path`,
:meth:`Skill.fit_reward`, :meth:`Skill.adopt`, :meth:`Skill.evaluate` and
:meth:`Skill.to_units`. The package docstring (:mod:`lfdkit.skill`) tells the
whole story.
"""

from __future__ import annotations

import os
import re
import time
import warnings
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar, Literal

import numpy as np

from lfdkit.core.constraints import Checked, Integer, OneOf, Real
from lfdkit.core.estimator import Estimator, check_fitted
from lfdkit.core.geometry import (
    path_length,
    resample,
)
from lfdkit.core.options import (
    DEMONSTRATION_SPEED,
    LONGEST_DEMONSTRATION,
    MODELS,
    PLANNERS,
    SCALINGS,
    SKILL_DEFAULTS,
    TIMINGS,
)
from lfdkit.core.progress import Progress, ProgressLike, as_progress
from lfdkit.core.rotations import check_quaternions, continuous
from lfdkit.core.threads import side_by_side
from lfdkit.core.units import (
    UnitsWarning,
    check_units,
    conversion_factor,
    implausible_units,
    likely_units,
    misplaced_units,
)
from lfdkit.core.validation import (
    check_class_names,
    check_demos,
    check_horizon,
    check_path,
    check_point,
    check_times_list,
)
from lfdkit.emulate import Reward, UnsafePlanError, metrics
from lfdkit.emulate.fidelity import kept_sides, replanning_fidelity, side_preferences
from lfdkit.emulate.gaps import declined_gap_width, swerve_reach
from lfdkit.emulate.reward import shown_directions
from lfdkit.imitate import DMP, ProMP, QuaternionDMP, SpeedProfile, learn_timing
from lfdkit.imitate.via_points import (
    DEFORMATION_BASIS,
)
from lfdkit.io import skill_file
from lfdkit.io.skill_file import (
    SKILL_FILE_LIMITS,
)
from lfdkit.io.training import read_training_data
from lfdkit.mimic import MIMIC_METHODS, DemoOrientationWarning, MimicSettings, mean_orientations
from lfdkit.model.demos import demo_fields
from lfdkit.model.half_space import HalfSpace
from lfdkit.model.scene import Scene
from lfdkit.skill.files import SkillFiles
from lfdkit.skill.orientation import SkillOrientation, check_orientations_list
from lfdkit.skill.planning import PlannerKind, Planning, obstacle_extent
from lfdkit.skill.selection import MIN_CROSS_VALIDATION_DEMOS, BehaviourSelection
from lfdkit.skill.unknown import UnknownClasses, median_radii
from lfdkit.skill.via import ViaPoints


def _registered_mimic(value: Any, name: str) -> str:
    """A key of :data:`~lfdkit.mimic.MIMIC_METHODS` as registered now (users may add methods)."""
    return OneOf(tuple(MIMIC_METHODS))(value, name)


#: ``model_selection_`` entries in the data's units and in units², each converted by
#: :meth:`Skill.to_units` (the rest are ratios, shares, counts and names).
_SELECTION_LENGTHS = ("gap_clearances", "gap_allowance", "swerve_reach")
_SELECTION_AREAS = ("noise_mse", "no_floor_mse")


def _scaled(value: Any, factor: float) -> Any:
    """``value`` (a number, a list or a dict of them; None stays None) times ``factor``."""
    if value is None:
        return None
    if isinstance(value, dict):
        return {k: _scaled(v, factor) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_scaled(v, factor) for v in value]
    return value * factor


def _selection_in_units(selection: dict | None, factor: float) -> dict | None:
    """``Skill.model_selection_`` with its lengths times ``factor`` and areas times its square."""
    if not selection:
        return selection
    out = dict(selection)
    for key in _SELECTION_LENGTHS:
        if key in out:
            out[key] = _scaled(out[key], factor)
    for key in _SELECTION_AREAS:
        if key in out:
            out[key] = _scaled(out[key], factor**2)
    if isinstance(out.get("candidates"), dict):
        out["candidates"] = {
            name: {
                k: (_scaled(v, factor**2) if k in ("mse", "error") else v) for k, v in row.items()
            }
            if isinstance(row, dict)
            else row
            for name, row in out["candidates"].items()
        }
    return out


class Skill(
    SkillFiles,
    Planning,
    BehaviourSelection,
    SkillOrientation,
    ViaPoints,
    UnknownClasses,
    Estimator,
):
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
        the closest any came, :data:`CLEARANCE_FLOORS`), and the first route
        with a swerve (each class's response stretched before and after its
        obstacle along the path, fitted after the thesis's reward and
        warm-started from it: a person who starts early and returns slowly,
        or swerves late; ``Reward.swerve``). The thesis's model
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

        ``"path"`` (2-D, static scenes): as ``"auto"``, with every model's
        learned responses in the path frame: each obstacle's response in the
        axes of the nearest direction its class was shown in
        (``ioc_info_["shown_directions"]``; else the direction it was learned
        along, ``ioc_info_["frame_axis"]``), evaluated in the nominal's
        arc-length coordinates so that it bends with the path
        (:func:`lfdkit.emulate.reward.in_path_frame`,
        :func:`lfdkit.emulate.problem.unrolled_terms`): a person who reacts
        relative to the motion, not to the room. ``"auto"`` plans the
        swerve and the slow return so (their shape is along the motion) and
        the symmetric models in world axes (the thesis's model): the
        demonstrations of one task cannot tell the frames apart. Measured
        (fidelity benchmark, ``--sizes 4 10``, seeds 0, 1, 11 and 14, against
        world axes, the responses turned where passed): the potential-field
        person's pooled Pr 54 → 68 %, new tasks 63 → 83 %; the late swerver's
        pooled 40 → 56 %, new tasks −251 → 17 % (median over the rows); bent
        with the path too (and seed 17), new tasks 90 % and 91 %; the
        thesis-model person's new tasks need world axes (seed 0: 95 %, −118 %
        in the path frame).

        Either way the reward is fitted through exactly the route planner the
        skill plans with (the receding horizon ``H`` without goal term: the
        goal is joined to the route afterwards, leaving it alone,
        :mod:`lfdkit.emulate.planner`), and the training demonstrations are
        replanned with the model they were fitted with (:attr:`training_fidelity_`).
        The global-route candidate plans with the reward fitted through the
        receding horizon, and the folds' refits are full-horizon only (cheap):
        the cross-validated figures approximate those of full refits. Where
        the full-horizon stage of the fit replans the demonstrations closer
        than the receding horizon's (``ioc_info_["horizon"]`` None: a person
        who planned the whole path, e.g. around boxes in 3-D, issue 34), that
        reward is kept and the whole path is the only route (not for ``"thesis"``).
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
        ``"warnings"``, the demonstrations' mean squared distance from the
        path under ``"spread_mse"`` and from the path carried to each one's
        own start and goal under ``"noise_mse"``, their noise (units²,
        :func:`lfdkit.emulate.metrics.demonstration_spread`), diagnostics).
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
        Summary of the reward fit: loss, stages, classes, demonstrations;
        ``left_out``: the obstacle demonstrations the reward fitted on all
        replanned on another side of an obstacle, left out of the fit and of
        the model choice (said in a warning; :meth:`fit_reward`; their rows
        in :attr:`training_fidelity_` have ``left_out`` True);
        ``preference_passes``: those going the long way round a class kept
        on one side (:attr:`side_preferences_`), left out of the reward fit
        and the model choice's refits but replanned and scored (the blockers
        explain their side, not the reward: :meth:`_long_way_passes`);
        ``demonstrated_slope``: how steeply the demonstrations swerved
        (:func:`lfdkit.emulate.ioc.demonstrated_slope`), the steepest way
        back to the goal a plan takes where ``max_slope`` cannot keep its
        route's passing sides (:func:`lfdkit.emulate.plan_path`'s
        ``return_slope``; absent in older files: none steeper);
        ``side_preferences``: the classes the demonstrations keep on one side
        even the long way round (:func:`lfdkit.emulate.fidelity.side_preferences`;
        said in a warning; plans keep them so, :attr:`side_preferences_`).
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
        (:func:`lfdkit.emulate.fidelity.demonstrated_clearances`), the
        behaviour model's floor or, for a model without one,
        :data:`SAFETY_FLOOR` (then :attr:`gaps_` is ``"open"``); empty for
        ``model="thesis"`` or a reward only adopted.
    gaps_ : {"closed", "open"}
        ``"open"``: between two obstacles whose clearances would close the
        gap between them, the clearances give way so the plan may pass
        (:func:`lfdkit.emulate.gaps.open_gap_margins`, the thesis's person)
        where the plan without them passes and the gap is at least
        :data:`~lfdkit.emulate.gaps.PASSABLE` times the larger of the two;
        ``"closed"``: they are kept whole and the plan goes around both (a
        person who keeps a margin), as it does round two obstacles whose gap
        is narrower than the clearances the demonstrations typically kept
        from their classes (``model_selection_["gap_clearances"]``, the
        median; :func:`lfdkit.emulate.gaps.close_narrow_gaps`), or, across
        the path, within :data:`~lfdkit.emulate.gaps.GAP_STANDARD_ERRORS`
        standard errors of them (``model_selection_["gap_allowance"]``, from
        the demonstrations' noise and how many showed each class; said). A floor that
        would move the route from the plan without it (open: to another side of an obstacle, other
        than round a gap it keeps closed; closed: between two obstacles that
        plan went round) is kept at half, then none (with a warning). Either
        way, a gap across the path no wider than the widest a training scene
        showed the person going round stays closed
        (``model_selection_["declined_gap"]``, in the clearances typically
        kept; :func:`lfdkit.emulate.gaps.declined_gap_width`).
    frame_ : {"world", "path"}
        The frame the learned responses are planned in (``"path"`` for
        ``model="path"``, and in 2-D for a chosen swerve or slow return).
    return_fraction_ : float
        The receding horizon's largest step back toward the nominal, as a
        fraction of the action bound (``plan_path``'s ``return_fraction``):
        the demonstrations' return slope where the slow-return model was
        chosen (``model_selection_["return_fraction"]``), else 1 (symmetric).
        (:func:`lfdkit.emulate.fidelity.demonstrated_clearances`), with
        ``model="auto"``; empty otherwise (and for a reward only adopted).
    class_radii_ : dict
        Per learned obstacle class, the median radius (units) of the obstacles
        it was learned from: which learned class is nearest in size to one
        never learned (``unknown_response="nearest"`` of :meth:`plan_details`).
        Empty before a reward is fitted, for a reward only adopted and in
        files from before it.
    side_preferences_ : dict
        Per obstacle class the demonstrations keep on one side of the path
        whatever the shorter way round
        (:func:`lfdkit.emulate.fidelity.side_preferences`),
        ``{"side": "left" or "right" (3-D also "above" or "below", the last
        axis up), "within": units, "clearance": units}``: every plan passes
        each obstacle of the class whose surface its nominal passes nearer
        than ``within`` (:data:`~lfdkit.emulate.fidelity.SIDE_REACH` times the
        clearance the demonstrations typically kept from the class, the
        median) on that side, the long way round where it must
        (:func:`lfdkit.emulate.gaps.preferred_side_blockers`; where no plan
        can, the learned response's way, warned), at least ``clearance`` from
        it (the class's learned floor,
        :func:`lfdkit.emulate.gaps.preferred_side_margins`; none in older
        files). A symmetric reward cannot express it: it passes an obstacle
        the shorter way (what that changes on the fidelity probe's person
        who keeps cups on its left: :mod:`lfdkit.emulate.gaps`). Empty
        without one, for a reward only adopted (unless from a skill with one) and in older files.
    route_ : {"lookahead", "window", "full", "taut"} or None
        The route planner plans use: the MPC with ``lookahead``, the thesis's
        MPC (``"window"``), the full horizon, or the shortest path round the
        obstacles that keeps :attr:`clearances_` (``"taut"``, 2-D:
        :func:`lfdkit.emulate.taut.taut_plan`; the full horizon where it
        finds none); None before a reward is fitted (then ``"lookahead"`` for
        ``planner="mpc"``).
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
        ``"full+closest"``, ``"window/swerve"``, ...) its ``route``, ``floor``,
        ``frame`` (and ``swerve``: ``"learned"``) and held-out scores:
        ``mse`` (units²), ``error`` (units², what the choice ranks by: the
        folds' trimmed mean MSE), ``improvement_pooled``, ``_median`` and ``_mean``
        (Pr %), ``sides_agree`` (share), ``refused`` and
        ``clearance_relaxed`` (counts); ``swerve``: the swerve candidates'
        stretches ``[before, after]`` per class; ``swerve_route`` (a swerve
        chosen): the stretches-only reward that routes among several
        obstacles, as each class's width ratios and stretches;
        ``declined_gap``: the widest gap across the path the demonstrations
        went round, in the clearances they typically kept (None: none shown);
        ``swerve_reach``: how far before and after a lone obstacle the
        demonstrations stayed swerved (units, 2-D;
        :func:`lfdkit.emulate.gaps.swerve_reach`), for the pairs one behind
        the other that plans go round both of (:func:`lfdkit.emulate.gaps.held_pairs`).
        ``clearance_consistency``, measured above ``noise_mse`` (units², the
        noise of the demonstrations without obstacles, ``mimic_info_["noise_mse"]``),
        and ``threads_gaps``; ``gap_clearances`` and ``gap_allowance`` (units).
        Also in :attr:`ioc_info_` and the skill file.
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
        quats = check_orientations_list(orientations, demos)
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
        # How far the person strays from their own path with no obstacle: the noise floor
        # of every replanning error (the behaviour model choice, issue 26).
        turned = set(info["reversed"])
        runs = [demo[::-1] if j in turned else demo for j, demo in enumerate(demos)]
        info["spread_mse"] = metrics.demonstration_spread(path, runs, int(self.n_points))
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
        # The noise proper: each run against the path carried to its own start and goal
        # (runs from spread starts stray from the one path by the starts' spread).
        nominals = self._rollouts(np.stack([r[0] for r in runs]), np.stack([r[-1] for r in runs]))
        info["noise_mse"] = metrics.demonstration_spread(list(nominals), runs, int(self.n_points))
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
        """A :class:`UnitsWarning` when the demonstrations are implausible in :attr:`units`.

        Also a warning when their times are (the median lasting over
        :data:`~lfdkit.core.options.LONGEST_DEMONSTRATION`: milliseconds read as seconds).
        """
        lasting = [float(t[-1] - t[0]) for t in stamps if t is not None]
        if lasting and float(np.median(lasting)) > LONGEST_DEMONSTRATION:
            warnings.warn(
                f"times: the demonstrations last {float(np.median(lasting)):.4g} s (median), "
                f"longer than a demonstration does (over {LONGEST_DEMONSTRATION:g} s); times "
                "are in seconds: if they are in milliseconds, divide them by 1000",
                UserWarning,
                stacklevel=3,
            )
        extent = max(float(np.ptp(demo, axis=0).max()) for demo in demos)
        if not extent > 0.0:  # every point the same: the mimic step refuses it, saying so
            return
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
        self.gaps_ = "closed"
        self.class_radii_: dict[str, float] = {}
        self.route_: str | None = None
        self.frame_ = "world"
        self.return_fraction_ = 1.0
        self.side_preferences_: dict[str, dict[str, Any]] = {}
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

        A demonstration the reward fitted on all of them replans on another
        side of an obstacle is left out, and the reward fitted again on the
        rest (:meth:`_unexplained`; a ``UserWarning`` names it,
        ``ioc_info_["left_out"]``): a side no plan of that reward takes cannot
        be explained by its shape, and the fit bent the whole reward trying.
        Not where the refit would leave a class unlearned that the fit on all
        learned: those demonstrations are how the person passes that class (a
        side preference: ``ioc_info_["side_preferences"]``, warned), not coin
        flips, and without the class every scene with it would be refused.
        A demonstration that goes the long way round a class the plans keep on
        one side is left out of the fit from the start (the side blockers
        explain its side; ``ioc_info_["preference_passes"]``), unless only
        such passes show a class.

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
        self._check_obstacle_scenes(demos, scenes)
        goal = self._goals(goals, len(demos))
        progress = as_progress(progress)
        with progress.stage("emulate: nominal of each obstacle demonstration (DMP)"):
            starts = np.array([demo[0] for demo in demos])
            nominals = list(self._rollouts(starts, goal))
        # Classes kept on one side whatever the shorter way: every plan below keeps them so
        # (the check of left-out demonstrations, the model choice, the training fidelity).
        found = side_preferences(demos, scenes, nominals, int(self.n_points))
        preferred = self._preferred_sides(found, demos, scenes, nominals)
        self.side_preferences_ = preferred
        stages = "full horizon, then MPC" if self.planner == "mpc" else "full horizon"
        started = time.perf_counter()
        label = f"emulate: inverse optimal control on {len(demos)} demos ({stages})"
        # Imported where it fits: loading and planning never need the IOC (issue 30).
        from lfdkit.emulate.ioc import IOC

        def fitted(keep: Sequence[int]) -> IOC:
            return IOC(
                self.classes,
                n_points=int(self.n_points),
                horizon=self._horizon,
                # The thesis's model is its staged fit exactly; the others keep the
                # full-horizon fit where it replans the demonstrations closer.
                keep_full_horizon=self.model != "thesis",
                max_slope=float(self.max_slope),
                progress=progress,
            ).fit([demos[j] for j in keep], [scenes[j] for j in keep], [nominals[j] for j in keep])

        # Its warnings are given once it stands (a refit without some demonstrations has its own).
        # The long way round a kept class is the side blockers' doing, not the reward's.
        by_preference = self._long_way_passes(found, scenes)
        with progress.stage(label), warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            ioc = fitted([j for j in range(len(demos)) if j not in by_preference])
            shown = {c for j in by_preference for c in scenes[j].labels}
            if shown & set(ioc.not_learned_):
                by_preference = []  # a class only they come near: learned from them after all
                said.clear()  # the first fit's warnings are not this one's
                ioc = fitted(range(len(demos)))
        unexplained = self._unexplained(ioc, demos, scenes, goal, nominals)
        left_out = [j for j in unexplained if j not in by_preference]
        keep = [j for j in range(len(demos)) if j not in left_out]
        if left_out:
            named = ", ".join(map(str, left_out))
            stage = f"emulate: inverse optimal control without demo(s) {named}"
            with progress.stage(stage), warnings.catch_warnings(record=True) as said_again:
                warnings.simplefilter("always")
                refit = fitted([j for j in keep if j not in by_preference])
            # Without them a class the fit on all learned would be unlearned (every scene
            # with it refused): they are how the person passes it (a side preference, the
            # fidelity probe's person who keeps cups on its left), not coin flips.
            lost = [c for c in refit.not_learned_ if c not in ioc.not_learned_]
            if lost:
                left_out, keep = [], list(range(len(demos)))
            else:
                ioc, said = refit, said_again
        for w in said:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        if left_out:
            warnings.warn(
                f"obstacle demonstration(s) {named} pass an obstacle on a side the reward "
                "learned from all of them never takes (it replans them on the other side): "
                "left out of the reward fit, which they would bend to explain their swerve; "
                "show the obstacle further aside of the path, or check the scene",
                UserWarning,
                stacklevel=2,
            )
        self.ioc_ = ioc
        self.reward_ = ioc.reward_
        self.ioc_info_ = {
            "n_demos": len(demos),
            # Obstacle demonstrations left out of the fit (:meth:`_unexplained`).
            "left_out": left_out,
            # Those going the long way round a kept class: out of the reward fit alone.
            "preference_passes": list(by_preference),
            "classes": list(ioc.classes_),
            "horizon": ioc.horizon_,
            "loss": float(ioc.loss_),
            "converged": bool(ioc.converged_),
            "convergence_message": ioc.convergence_message_,
            "not_learned": list(ioc.not_learned_),
            # How steeply the demonstrations swerved: the plans' way back to the goal
            # may be as steep where the route's sides need it (plan_path's return_slope).
            "demonstrated_slope": float(getattr(ioc, "demonstrated_slope_", 0.0)),
            # How steeply they swerved out and came back (the slow-return model's bound).
            "demonstrated_return": skill_file.jsonable(getattr(ioc, "demonstrated_return_", None)),
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
        self.side_preferences_ = preferred
        # The direction the precisions are learned along (model="path" turns them from it).
        chord = self.path_[-1] - self.path_[0]
        self.ioc_info_["frame_axis"] = (chord / max(float(np.linalg.norm(chord)), 1e-300)).tolist()
        if self.n_dims_ == 2:  # the directions each class's response was shown in (planning warns)
            self.ioc_info_["shown_directions"] = shown_directions(
                scenes, nominals, np.asarray(self.ioc_info_["frame_axis"])
            )
        self.class_radii_ = median_radii(scenes, ioc.classes_)
        with progress.stage("emulate: replanning the training scenes (fidelity, model choice)"):
            # Obstacles of a class not learned never shaped a demonstration (the IOC
            # warned): the training scenes are replanned without them.
            learned = [
                Scene(tuple(o for o in scene if o.label not in ioc.not_learned_))
                for scene in scenes
            ]
            self._select_model(
                [demos[j] for j in keep],
                [learned[j] for j in keep],
                goal[keep],
                [nominals[j] for j in keep],
                # The model choice's refits leave them out too (numbered as its demonstrations).
                [i for i, j in enumerate(keep) if j in by_preference],
            )
        if self.model_selection_ is not None:
            # Read off every demonstration, those left out of the fit too: one that went
            # round a gap the reward threads is replanned on another side, and left out.
            self.model_selection_["declined_gap"] = declined_gap_width(
                demos, learned, nominals, self.model_selection_.get("gap_clearances") or {}
            )
            # How long a swerve round a lone obstacle lasts along the path (before, after).
            self.model_selection_["swerve_reach"] = swerve_reach(demos, learned, nominals)
        for row in self.training_fidelity_ or []:  # numbered as the caller's demonstrations
            row["demo"] = keep[row["demo"]]
        if left_out and self.training_fidelity_ is not None:  # each said with its own plan
            rows = [
                self._left_out_row(j, demos[j], goal[j], learned[j], nominals[j]) for j in left_out
            ]
            self.training_fidelity_ = sorted(
                self.training_fidelity_ + rows, key=lambda row: row["demo"]
            )
        self.ioc_info_["training_fidelity"] = skill_file.jsonable(self.training_fidelity_)
        self.ioc_info_["model_selection"] = skill_file.jsonable(self.model_selection_)
        self._warn_side_preferences(found)
        self._warn_fidelity()
        return self

    def _preferred_sides(
        self,
        found: dict[str, dict[str, Any]],
        demos: Sequence[np.ndarray],
        scenes: Sequence[Scene],
        nominals: Sequence[np.ndarray],
    ) -> dict[str, dict[str, Any]]:
        """:attr:`side_preferences_` from the preferences found (left, right; 3-D: above, below).

        :func:`lfdkit.emulate.fidelity.kept_sides`: where (``within``) and how
        far (``clearance``) plans keep each such class on its side. None for
        ``model="thesis"`` (the thesis's plans exactly; the preference is only
        said).
        """
        if self.model == "thesis":  # the thesis's planner exactly: said, not kept
            return {}
        return kept_sides(found, demos, scenes, nominals)

    def _warn_side_preferences(self, found: dict[str, dict[str, Any]]) -> None:
        """Say which classes the demonstrations pass on one side by preference.

        The learned reward is symmetric about each obstacle, so its plans
        would pass an obstacle the shorter way round; a person who keeps a
        class on one side (:func:`lfdkit.emulate.fidelity.side_preferences`)
        is reproduced by the side blockers of :attr:`side_preferences_` (2-D
        and 3-D). Said, as the model choice is, since it decides routes the
        reward does not (the fidelity probe's person who keeps cups on its
        left: without this, the only word was a demonstration left out "as a
        coin flip"); where no side is kept (``model="thesis"``), said as a limit.
        Recorded in ``ioc_info_["side_preferences"]``.
        """
        self.ioc_info_["side_preferences"] = skill_file.jsonable(found)
        for label, info in found.items():
            where = {"above": "above them", "below": "below them"}.get(
                info["side"], f"on their {info['side']}"
            )
            named = ", ".join(map(str, info["long_way"]))
            shown = (
                f"the demonstrations keep every {label!r} {where} ({info['passes']} passes), "
                f"going the long way round it in demonstration(s) {named}"
            )
            if label in self.side_preferences_:
                within = self.side_preferences_[label]["within"]
                message = (
                    f"{shown}: a side preference, kept: plans pass every {label!r} their nominal "
                    f"comes within {within:.3g} {self.units} of {where}, the long way round "
                    "where needed (the learned reward alone would take the shorter way)"
                )
            else:
                message = (
                    f"{shown}: a side preference the learned reward (symmetric about each "
                    f"obstacle) cannot express, so plans pass a {label!r} the shorter way round "
                    "where the person would not; where the side matters, give the plan a via "
                    "point on the person's side"
                )
            warnings.warn(message, UserWarning, stacklevel=3)

    def _long_way_passes(
        self, found: Mapping[str, Mapping[str, Any]], scenes: Sequence[Scene]
    ) -> list[int]:
        """Obstacle demonstrations that go the long way round a class kept on one side.

        Plans keep such a class on its side by blockers
        (:attr:`side_preferences_`), so these passes are the preference's, and
        a reward symmetric about each obstacle fitted to them bends to explain
        the long way round: ``benchmarks/boxes_sides.py`` (3-D, seed 2, fold 4:
        two of seven demonstrations) learned a ``Q`` 3.3× the person's, with
        a training loss half the person's own reward's, and its plan wove
        through the three boxes (one of three sides, 122 mm from the person)
        where the person's reward, planned the same way, kept all three
        (6 mm); fitted without those two, 1 of 3 → 3 of 3 sides, 5.6 mm. The
        reward is fitted on the others where at least
        :data:`~lfdkit.skill.selection.MIN_CROSS_VALIDATION_DEMOS` remain
        and their ``scenes`` show every class these passes' do (a class only
        they show is learned from them); none where no side is kept
        (``model="thesis"``).
        """
        kept = [info for label, info in found.items() if label in self.side_preferences_]
        passes = sorted({int(j) for info in kept for j in info.get("long_way", ())})
        others = [scene for j, scene in enumerate(scenes) if j not in passes]
        shown = {c for j in passes for c in scenes[j].labels}
        if len(others) < MIN_CROSS_VALIDATION_DEMOS or not shown <= {
            c for scene in others for c in scene.labels
        }:
            return []
        return passes

    def _unexplained(
        self,
        ioc: Any,
        demos: Sequence[np.ndarray],
        scenes: Sequence[Scene],
        goal: np.ndarray,
        nominals: Sequence[np.ndarray],
    ) -> list[int]:
        """Obstacle demonstrations the reward fitted on all replans on another side of an obstacle.

        The fit compares each demonstration with the plan warm-started on it,
        on its own side; a demonstration that passed an obstacle on the side
        of its centre (a near-centred obstacle, a person's coin flip) is on a
        side the fitted reward never plans, and the fit bends the whole
        reward to explain how far it swerved there. The potential-field
        person of the fidelity benchmark, seed 3: one box 5 mm beside the
        path passed 15 cm on its own side, and ``Q`` fell to its plausibility
        wall (nothing held plans on their nominals; held-out sides 71 %,
        pooled Pr −41 %; without that demonstration 96 % and 79 %). Each is
        replanned with no clearance floor by the route the reward was fitted
        for; those on another side are returned where they are a minority
        and the rest still allow a cross-validated model choice, else none
        (``model="thesis"``: none, its fit is the thesis's exactly).
        """
        n = len(demos)
        if self.model == "thesis" or n < 2 * MIN_CROSS_VALIDATION_DEMOS:
            return []
        route = self._fitted_routes(ioc.horizon_)[0]
        frame = "path" if self.model == "path" else "world"
        n_points = int(self.n_points)

        def other_side(j: int) -> bool:
            scene = Scene(tuple(o for o in scenes[j] if o.label not in ioc.not_learned_))
            if not len(scene):
                return False
            try:
                plan = self._plan(
                    demos[j][0],
                    goal[j],
                    scene,
                    "full" if route == "full" else None,
                    None,
                    "auto",
                    0.0,
                    route=route,
                    reward=ioc.reward_,
                    clearances={},
                    gaps="closed",
                    frame=frame,
                )
            except UnsafePlanError:  # no plan at all: the model choice reports it
                return False
            fidelity = replanning_fidelity(plan.points, nominals[j], demos[j], scene, n_points)
            return not fidelity["sides_agree"]

        # Each demonstration's plan is its own: side by side on the process's threads.
        out = [j for j, other in enumerate(side_by_side(other_side, range(n))) if other]
        few = 2 * len(out) < n and n - len(out) >= MIN_CROSS_VALIDATION_DEMOS
        return out if few else []

    def _left_out_row(
        self, j: int, demo: np.ndarray, goal: np.ndarray, scene: Scene, nominal: np.ndarray
    ) -> dict[str, Any]:
        """A left-out demonstration's fidelity row: its scene planned as the skill plans."""
        try:
            plan = self._plan(demo[0], goal, scene, None, None, "auto", 0.0)
        except UnsafePlanError as exc:
            return {"demo": j, "refused": str(exc), "left_out": True}
        row = replanning_fidelity(plan.points, nominal, demo, scene, int(self.n_points))
        return {"demo": j, **row, "clearance_relaxed": False, "left_out": True}

    def _check_obstacle_scenes(self, demos: list[np.ndarray], scenes: list[Scene]) -> None:
        """Refuse a demonstration that starts or ends inside its obstacle; warn for doubtful scenes.

        A person's demonstration cannot start, end or pass inside a solid
        obstacle, so one that does names a wrong position, radius or unit in
        the scene (the fit would fail on it, or learn from it, without saying
        which). Warned: a demonstration passing deeper than a quarter of the
        obstacle's size inside it, an obstacle far from every demonstration or
        too small for the unit (a box in metres near a millimetre reach's
        origin) that another unit would bring among them
        (:func:`lfdkit.core.units.misplaced_units`), and a class in one scene only.
        """
        points = np.concatenate([self.path_, *demos])
        low, high = points.min(axis=0).tolist(), points.max(axis=0).tolist()
        units = self.units
        misplaced: list[tuple[str, str]] = []
        for j, (demo, scene) in enumerate(zip(demos, scenes, strict=True)):
            for i, obstacle in enumerate(scene):
                name = f"scenes[{j}]: obstacle {i} ({obstacle.label!r})"
                if obstacle.has_extent:
                    for end, point in (("starts", demo[:1]), ("ends", demo[-1:])):
                        depth = -obstacle.distance(point)
                        if depth > 0.0:
                            raise ValueError(
                                f"{name}: its demonstration {end} {depth:.3g} {units} inside "
                                "it, which no demonstration can; check the obstacle's position "
                                "and size, and that the scenes are in the demonstrations' unit"
                            )
                    # An unbounded shape (a table's half-space) by its part among the points.
                    balls = obstacle.clipped(np.array(low), np.array(high)).balls()[1]
                    size = max(obstacle.radius, float(np.max(balls)))
                    depth = -obstacle.distance(demo)
                    if depth > 0.25 * size:
                        warnings.warn(
                            f"{name}: its demonstration passes {depth:.3g} {units} inside it "
                            f"(its size {size:.3g} {units}); check the obstacle's position and "
                            "size, and that the demonstration was recorded around it",
                            UserWarning,
                            stacklevel=4,
                        )
                if isinstance(obstacle, HalfSpace) or np.size(obstacle.position) != len(low):
                    continue
                at = obstacle.position.tolist()
                size = obstacle_extent(obstacle)
                likely = misplaced_units(at, low, high, units, size=size)
                if likely is None:
                    continue
                if misplaced_units(at, low, high, units) is None:  # by its size
                    said = f"{name}: {size:.3g} {units} across is smaller than any obstacle"
                else:
                    shown = ", ".join(f"{v:.4g}" for v in at)
                    said = f"{name}: at ({shown}) {units} lies far from every demonstration"
                misplaced.append((said, likely))
        seen: dict[str, list[int]] = {}
        for j, scene in enumerate(scenes):
            for label in dict.fromkeys(scene.labels):
                seen.setdefault(label, []).append(j)
        for label, where in seen.items():
            if len(where) == 1 and len(demos) > 1:
                warnings.warn(
                    f"scenes[{where[0]}]: obstacle class {label!r} is in this scene only: its "
                    "learned response rests on one demonstration and cannot be cross-validated; "
                    f"show another demonstration around a {label}",
                    UserWarning,
                    stacklevel=4,
                )
        if misplaced:  # one line for them all: a scene file in another unit
            (first, likely), more = misplaced[0], len(misplaced) - 1
            others = f" (and {more} other obstacle{'s' * (more != 1)})" if more else ""
            warnings.warn(
                f"{first}{others}; in {likely} it would lie among them: give the scenes in "
                f"the demonstrations' unit ({units})",
                UserWarning,
                stacklevel=4,
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
        taken = Reward(
            reward.nominal_weight,
            {c: reward.precisions[c] for c in wanted},
            {c: reward.swerve[c] for c in wanted if c in reward.swerve},  # a swerve comes with it
        )
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
        if any(c in theirs for c in wanted):  # their clearances keep gaps as theirs did
            self.gaps_ = getattr(source, "gaps_", "closed")
        # So does the side a class is kept on (none where the source keeps none).
        sides = getattr(source, "side_preferences_", {}) if isinstance(source, Skill) else {}
        own = getattr(self, "side_preferences_", {})
        self.side_preferences_ = {c: p for c, p in own.items() if c not in wanted}
        self.side_preferences_ |= {c: dict(sides[c]) for c in wanted if c in sides}
        sizes = getattr(source, "class_radii_", {}) if isinstance(source, Skill) else {}
        own = getattr(self, "class_radii_", {})
        self.class_radii_ = {c: r for c, r in own.items() if c not in wanted}
        self.class_radii_ |= {c: sizes[c] for c in wanted if c in sizes}
        return self

    # ------------------------------------------------------------------ use
    def _check_fitted(self) -> None:
        check_fitted(self, "path_", "skill: not fitted; call fit() or fit_path() first")

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
            # the swerve's stretches are ratios: no unit
            skill.adopt(Reward(self.reward_.nominal_weight / area, precisions, self.reward_.swerve))
            skill.route_ = getattr(self, "route_", None)
            skill.frame_ = getattr(self, "frame_", "world")
            skill.return_fraction_ = getattr(self, "return_fraction_", 1.0)  # a ratio: no unit
            skill.clearances_ = {c: m * factor for c, m in self.clearances_.items()}
            skill.gaps_ = getattr(self, "gaps_", "closed")
            skill.model_selection_ = _selection_in_units(
                getattr(self, "model_selection_", None), factor
            )
            skill.class_radii_ = {
                c: r * factor for c, r in getattr(self, "class_radii_", {}).items()
            }
            skill.side_preferences_ = {
                c: {**p, **{k: p[k] * factor for k in ("within", "clearance") if k in p}}
                for c, p in getattr(self, "side_preferences_", {}).items()
            }
        return skill

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
    ids = data.obstacle_ids

    def named(text: str) -> str:  # scenes[j] by the file's demo ids
        return re.sub(
            r"^scenes\[(\d+)\]", lambda m: f"{scenes_path}: demo {ids[int(m[1])]!r}", text
        )

    caught: list[warnings.WarningMessage] = []
    try:
        with warnings.catch_warnings(record=True) as caught:  # the caller's filters kept
            skill.fit(data.clean, data.around_obstacles or None, progress=progress)
    except ValueError as exc:
        if str(exc).startswith("scenes["):
            raise ValueError(named(str(exc))) from None
        raise
    finally:
        for warning in caught:  # re-issued to the caller, named by the file's ids
            message = warning.message
            if type(message) is UserWarning and str(message).startswith("scenes["):
                message = UserWarning(named(str(message)))
            warnings.warn_explicit(message, warning.category, warning.filename, warning.lineno)
    # Each replanned training scene by its demonstration's id in the file.
    stored = (skill.ioc_info_ or {}).get("training_fidelity") or []
    for rows in (skill.training_fidelity_ or [], stored):
        for row in rows:
            row["id"] = data.obstacle_ids[row["demo"]]
    return skill


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
    framed = next((poses for poses in fields.frames if poses), None)
    if framed is not None:  # recorded for TP-GMM: said, not silently dropped
        warnings.warn(
            f"demos: the demonstrations carry task frames ({', '.join(framed)}), which a Skill "
            "does not use: it carries the path to a new start and goal only; to reproduce in "
            "new frame poses fit lfdkit.imitate.TPGMM on them",
            UserWarning,
            stacklevel=3,
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
