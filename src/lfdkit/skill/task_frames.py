"""Task-frame skills: a movement learned in the frames of the objects it acts on (issue 33).

What: :class:`TaskFrameSkill` learns from demonstrations recorded with the
poses of their task frames (the brush's start, the dustpan; a file's
``frame_<name>_...`` columns, :attr:`lfdkit.model.demos.Demo.frames`) a
task-parameterised GMM (:class:`lfdkit.imitate.TPGMM`), and plans the
movement for new poses of those frames, timed as the demonstrations were.
It is the task-frame counterpart of :class:`lfdkit.skill.Skill` (which
carries a movement to a new start and goal *point*): near each frame the
plan keeps the shape the demonstrations had relative to it, so a sweep
arrives along a turned dustpan's axis (``benchmarks/tpgmm.py``: 4.5-8
degrees off it, where a DMP re-targeted to the dustpan's position arrives
34-60 degrees off).

Why a class of its own, as :class:`~lfdkit.skill.periodic.PeriodicSkill`:
what it is planned for (the frames' poses) is not a start, goal and scene.
It shares the data model (:class:`~lfdkit.model.demos.Demo` records and
their files), the skill-file machinery (:mod:`lfdkit.io.skill_file`: strict
JSON reader, atomic writer, never over a file unless asked) and the plan's
type (:class:`~lfdkit.model.timed_path.TimedPath`, which
:func:`lfdkit.execute.pipeline.execute_plan` runs on an arm).

With the tool's orientation (demonstrations with ``qx, qy, qz, qw``): in each
frame, the orientation about its mean there, as a half-angle rotation vector,
is a mixture over the phase; a plan fuses the frames' Gaussians by their
product on the rotations (a few Gauss-Newton steps in the tangent space of the
running estimate). On a brush held down and turned 0.3 rad in the pan's frame
on arriving (``tests/skill/test_task_frames.py``), plans for new poses leave
and arrive within 0.3 degrees of the known orientation, 3-5 degrees off
between, where the product is not the demonstrations' blend.

Units: EM works in metres whatever the skill's unit (``length_scale`` is one
metre in ``units``), so the same demonstrations in millimetres give the same
plans times 1000.

File
----
One JSON object, ``{"format": "lfdkit-task-frame-skill", "version": 1, ...}``:
``params`` (the constructor's), ``units``, ``n_dims``, ``frames`` (the frames'
names, in order), ``duration`` (the demonstrations' median, s; null without
times), ``n_demos``, ``frame_ranges`` (each frame's demonstrated poses: its
origins' box, mean rotation and rotation vectors' box, from which a plan for
poses beyond them is warned as an extrapolation; optional), ``tpgmm``
(:meth:`lfdkit.imitate.TPGMM.to_state`:
its parameters and mixture, every number exact) and ``orientation`` (null, or
each frame's reference quaternion and mixture). Loading never refits:
save → load → save gives the same bytes and the loaded skill's plans are the
saved one's to the bit.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping, Sequence
from typing import Any, ClassVar

import numpy as np
from sklearn.exceptions import ConvergenceWarning

from lfdkit import __version__
from lfdkit.core.constraints import Checked, Integer, OneOf
from lfdkit.core.estimator import Estimator, check_fitted
from lfdkit.core.rotations import (
    conjugate,
    continuous,
    exp,
    log,
    matrix_from_quaternion,
    mean_quaternion,
    multiply,
    quaternion_from_matrix,
)
from lfdkit.core.units import check_units, conversion_factor
from lfdkit.core.validation import check_count, check_positive
from lfdkit.imitate.dmp import MAX_RELATIVE_MAGNITUDE
from lfdkit.imitate.tpgmm import TPGMM, TaskFrame, frame_from_pose
from lfdkit.io.skill_file import (
    TASK_FRAME_FORMAT,
    SavedToSkillFile,
    jsonable,
    made_from_document,
)
from lfdkit.model.demos import Demo, demo_fields
from lfdkit.model.timed_path import TimedPath

__all__ = ["TASK_FRAME_FORMAT", "TASK_FRAME_VERSION", "TaskFrameSkill"]

TASK_FRAME_VERSION = 1
"""Newest task-frame-skill-file version this module reads, and the one it writes."""

#: Gauss-Newton steps of the product of the frames' orientation Gaussians, at most.
ORIENTATION_STEPS = 10
#: A frame stands still when its origins spread over at most this share of the
#: demonstrations' extent and it turns at most :data:`STILL_TURN` (rad): warned at the fit.
STILL_SHARE = 1e-3
STILL_TURN = float(np.radians(1.0))
#: A plan's frame turned more than this (rad) past the largest turn the demonstrations
#: showed, from their mean rotation, extrapolates: warned.
BEYOND_TURN = 0.25


class TaskFrameSkill(SavedToSkillFile, Estimator):
    """A movement learned in its task frames (TP-GMM), planned for new poses of them.

    Parameters
    ----------
    n_components : int, default 10
        Gaussian components of the mixture (:class:`lfdkit.imitate.TPGMM`).
    product : {"components", "paths"}, default "components"
        Where the frames are fused (:class:`lfdkit.imitate.TPGMM`).
    n_points : int, default 100
        Points of a plan when none are asked for.
    units : {"m", "cm", "mm"}, default "m"
        Unit of the positions and of the frames' origins.
    random_state : int or None, default 0
        Seed of EM's k-means start where a phase bin is short of samples (an
        int: the skill file stores it, and refits give the same skill).

    Attributes
    ----------
    tpgmm_ : TPGMM
        The fitted mixture.
    frame_names_ : list of str
        The task frames' names, in the order :meth:`plan` takes them.
    orientation_references_ : ndarray, shape (P, 4), or None
        With orientations: the tool's mean orientation in each frame.
    orientation_models_ : list of TPGMM, or None
        With orientations: each frame's mixture of the orientation about its
        reference (half-angle rotation vectors) over the phase.
    duration_ : float or None
        Seconds of a plan when none is asked for: the demonstrations' median
        duration (None when they had no times).
    n_demos_ : int
    n_dims_ : int

    Examples
    --------
    >>> import numpy as np
    >>> from lfdkit.model.demos import Demo
    >>> t = np.linspace(0.0, 1.0, 60)
    >>> hook = np.c_[-0.3 * (1 - t) ** 2, 0.05 * np.sin(np.pi * t)]  # in the pan's frame, m
    >>> rng = np.random.default_rng(0)
    >>> demos = []
    >>> for _ in range(6):
    ...     pan = np.r_[rng.uniform(0.3, 0.8, 2), rng.uniform(-1.0, 1.0)]  # x, y, angle
    ...     start = np.r_[rng.uniform(-0.1, 0.1, 2), 0.0]
    ...     c, s = np.cos(pan[2]), np.sin(pan[2])
    ...     path = hook @ np.array([[c, s], [-s, c]]) + pan[:2]
    ...     demos.append(Demo(path, 2.0 * t, frames={"start": start, "pan": pan}))
    >>> skill = TaskFrameSkill(n_components=6).fit(demos)
    >>> plan = skill.plan({"start": [0.0, 0.0, 0.0], "pan": [0.5, 0.3, 2.0]})
    >>> bool(np.linalg.norm(plan.positions[-1] - [0.5, 0.3]) < 0.01), plan.times[-1]
    (True, np.float64(2.0))
    """

    _parameter_constraints: ClassVar[dict[str, Any]] = {
        "n_components": Integer(maximum=1000),
        "product": OneOf(("components", "paths")),
        "n_points": Integer(minimum=2),
        "units": Checked(check_units),
    }

    def __init__(
        self,
        n_components: int = 10,
        product: str = "components",
        n_points: int = 100,
        units: str = "m",
        random_state: int | None = 0,
    ) -> None:
        self.n_components = n_components
        self.product = product
        self.n_points = n_points
        self.units = units
        self.random_state = random_state

    # ------------------------------------------------------------------ learning
    def fit(self, demos: Sequence[Any], frames: Sequence[Any] | None = None) -> TaskFrameSkill:
        """Learn the movement in its task frames.

        Parameters
        ----------
        demos : list of Demo, or list of array_like (n_i, d)
            Demonstrations in ``units``, d 2 or 3. :class:`~lfdkit.model.demos.Demo`
            records carry their times and task frames (``load_demos(path,
            as_records=True)`` of a file with ``frame_<name>_...`` columns).
        frames : list of mappings, optional
            With arrays: each demonstration's task frames by name, a pose
            each (``[x, y, angle]`` in 2-D, ``[x, y, z, qx, qy, qz, qw]`` in
            3-D), the same names in the same order for all.

        Returns
        -------
        self

        Raises
        ------
        ValueError
            One line naming the argument: no task frames, frames that differ
            between demonstrations, a bad pose, fewer samples than components.
        """
        params = self._validate_params()
        seed = self.random_state
        if not (seed is None or (isinstance(seed, int) and not isinstance(seed, bool))):
            raise ValueError(
                f"random_state: expected an int seed or None (the skill file stores it), "
                f"got {seed!r}"
            )
        records = demo_fields(demos, "demos", given={"frames": frames})
        if records is None:
            if frames is None:
                raise ValueError(
                    "frames: give each demonstration's task frames (a mapping of names to "
                    "poses), or Demo records that carry them"
                )
            if isinstance(frames, Mapping) or len(frames) != len(demos):
                raise ValueError(
                    f"frames: expected one mapping of named poses for each of the "
                    f"{len(demos)} demonstrations"
                )
            demos = [Demo(np.asarray(d), frames=f) for d, f in zip(demos, frames, strict=True)]
            records = demo_fields(demos, "demos")
        if any(not poses for poses in records.frames):
            j = next(j for j, poses in enumerate(records.frames) if not poses)
            raise ValueError(
                f"demos[{j}]: has no task frames; a task-frame skill learns from demonstrations "
                "recorded with the poses of their frames (frame_<name>_... columns)"
            )
        turned = [turns is not None for turns in records.orientations]
        if any(turned) and not all(turned):
            j = turned.index(False)
            raise ValueError(
                f"demos[{j}]: has no tool orientations, but demos[{turned.index(True)}] has; give "
                "every demonstration its orientations (qx, qy, qz, qw columns) or none"
            )
        n_dims = int(np.shape(records.points[0])[-1])
        if n_dims not in (2, 3):  # before EM: its time spent on a refusal
            raise ValueError(f"demos: {n_dims}-D; a tool moves in 2 or 3")
        scale = conversion_factor("m", params["units"])  # EM in metres, whatever the unit
        model = TPGMM(
            n_components=params["n_components"],
            product=params["product"],
            n_points=params["n_points"],
            random_state=seed,
            length_scale=scale,
        )
        with warnings.catch_warnings():  # scikit-learn's words for it; said below in ours
            warnings.simplefilter("ignore", ConvergenceWarning)
            self.tpgmm_ = model.fit(demos)
        if not self.tpgmm_.converged_:  # a poor fit is said
            warnings.warn(
                f"demos: the mixture's EM did not converge in {self.tpgmm_.n_iter_} iterations; "
                "plans may not follow the demonstrations: give fewer n_components or more "
                "demonstrations",
                UserWarning,
                stacklevel=2,
            )
        self.frame_names_ = list(self.tpgmm_.frame_names_ or [])
        self.orientation_references_, self.orientation_models_ = None, None
        if all(turned):
            self._fit_orientations(records, seed)
        durations = [float(t[-1] - t[0]) for t in records.times if t is not None]
        self.duration_ = float(np.median(durations)) if durations else None
        self.n_demos_ = len(records.points)
        self.frame_ranges_ = _frame_ranges(records.frames, self.frame_names_, self.tpgmm_.n_dims_)
        extent = float(np.ptp(np.vstack(records.points), axis=0).max())
        still = [
            name
            for name, shown in self.frame_ranges_.items()
            if float(np.max(np.subtract(shown["high"], shown["low"]))) <= STILL_SHARE * extent
            and float(np.max(np.abs(np.r_[shown["turn_low"], shown["turn_high"]]))) <= STILL_TURN
        ]
        if still and self.n_demos_ > 1:
            warnings.warn(
                f"demos: task frame(s) {', '.join(still)} stand still in every demonstration "
                "(within 0.1 % of their extent and 1 degree): plans for other poses of them "
                "extrapolate; show demonstrations with them moved and turned",
                UserWarning,
                stacklevel=2,
            )
        self.n_dims_ = int(self.tpgmm_.n_dims_)
        return self

    def _fit_orientations(self, records: Any, seed: int | None) -> None:
        """The tool's orientation in each frame: about a reference, a mixture over the phase.

        In frame ``j`` a sample's orientation is ``r_j ⊗ exp(v)`` with ``r_j`` the
        mean of the demonstrations' orientations in that frame and ``v`` (half-angle
        rotation vector, in ``r_j``'s own axes) fitted over the phase as one
        Gaussian mixture (a TP-GMM with one identity frame: GMR over the phase).
        """
        identity = [(np.eye(3), np.zeros(3))]
        references, models = [], []
        for name in self.frame_names_:
            local = [
                multiply(conjugate(_frame_rotation(poses[name])), continuous(turns))
                for poses, turns in zip(records.frames, records.orientations, strict=True)
            ]
            reference = mean_quaternion(np.vstack(local))
            tangents = [log(multiply(conjugate(reference), q)) for q in local]
            model = TPGMM(n_components=self.n_components, random_state=seed)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                model.fit(tangents, [identity] * len(tangents), times=records.times)
            references.append(reference)
            models.append(model)
        self.orientation_references_ = np.array(references)
        self.orientation_models_ = models

    def _orientations(self, phase: np.ndarray, frames: list[Any]) -> np.ndarray:
        """The tool's orientation at ``phase`` (n,) for the new frames' rotations, (n, 4).

        Each frame's Gaussian (mean and covariance in the tangent space of its
        mean orientation) is fused with the others' by their product on the
        rotations, computed in the tangent space of the running estimate and
        carried there by each frame's relative rotation (a few Gauss-Newton
        steps; a frame whose orientation varies little across the
        demonstrations at a phase rules there).
        """
        identity = [(np.eye(3), np.zeros(3))]
        means, covariances = [], []
        for rotation, reference, model in zip(
            frames, self.orientation_references_, self.orientation_models_, strict=True
        ):
            v, cov = model.predict(phase, identity, return_cov=True)
            means.append(multiply(rotation, multiply(reference, exp(v))))
            covariances.append(cov)
        estimate = means[
            int(np.argmin([np.trace(c, axis1=-2, axis2=-1).sum() for c in covariances]))
        ]
        for _ in range(ORIENTATION_STEPS):
            information = np.zeros((len(phase), 3, 3))
            pulled = np.zeros((len(phase), 3))
            for mean, cov in zip(means, covariances, strict=True):
                relative = multiply(conjugate(estimate), mean)
                turn = matrix_from_quaternion(relative)
                precision = np.linalg.inv(turn @ cov @ np.swapaxes(turn, -1, -2))
                information += precision
                pulled += np.einsum("nij,nj->ni", precision, log(relative))
            step = np.linalg.solve(information, pulled[..., None])[..., 0]
            estimate = multiply(estimate, exp(step))
            if float(np.abs(step).max()) < 1e-12:
                break
        return continuous(estimate / np.linalg.norm(estimate, axis=1, keepdims=True))

    # ------------------------------------------------------------------ planning
    def plan(
        self,
        frames: Mapping[str, Any],
        *,
        n_points: int | None = None,
        duration: float | None = None,
    ) -> TimedPath:
        """The movement for new poses of the task frames, timed as the demonstrations.

        Parameters
        ----------
        frames : mapping of str to array_like
            Each task frame's new pose by name (all of :attr:`frame_names_`):
            ``[x, y, angle]`` (angle in rad) in 2-D, ``[x, y, z, qx, qy, qz,
            qw]`` in 3-D, positions in ``units``; or a
            :class:`~lfdkit.imitate.TaskFrame`.
        n_points : int, optional
            Samples (default the ``n_points`` parameter).
        duration : float, optional
            Seconds (default :attr:`duration_`; needed when the
            demonstrations had no times).

        Returns
        -------
        TimedPath
            ``times`` (n,) s from 0, ``positions`` (n, d) in ``units``,
            ``velocities`` (n, d) in ``units``/s (central differences) and,
            for a skill learned with orientations, ``orientations`` (n, 4),
            unit quaternions ``[x, y, z, w]`` with continuous signs.

        Raises
        ------
        ValueError
            A frame missing or unknown (naming them), a bad pose, no duration.
        """
        check_fitted(self, "tpgmm_")
        if not isinstance(frames, Mapping):
            raise TypeError(
                f"frames: expected a mapping of the frames' names ({', '.join(self.frame_names_)}) "
                f"to their poses, got {type(frames).__name__}"
            )
        missing = [name for name in self.frame_names_ if name not in frames]
        unknown = [name for name in frames if name not in self.frame_names_]
        if missing or unknown:
            said = f"missing {', '.join(missing)}" if missing else f"unknown {', '.join(unknown)}"
            raise ValueError(
                f"frames: {said}; this skill was learned in the frames "
                f"{', '.join(self.frame_names_)}"
            )
        reach = MAX_RELATIVE_MAGNITUDE * self._extent()
        posed = [_frame(frames[name], name, self.n_dims_, reach) for name in self.frame_names_]
        turns = [_rotation_of(frame) for frame in posed]
        self._warn_beyond(posed, turns)
        n = check_count(self.n_points if n_points is None else n_points, "n_points", minimum=2)
        if duration is None:
            if self.duration_ is None:
                raise ValueError(
                    "duration: the demonstrations had no times; give the plan's duration (s)"
                )
            duration = self.duration_
        duration = check_positive(duration, "duration")
        positions = self.tpgmm_.path(posed, n)
        times = np.linspace(0.0, duration, n)
        velocities = np.gradient(positions, times, axis=0)
        orientations = None
        if self.orientation_models_ is not None:
            orientations = self._orientations(np.linspace(0.0, 1.0, n), turns)
        return TimedPath(times, positions, velocities, orientations=orientations)

    def _warn_beyond(self, posed: Sequence[TaskFrame], turns: Sequence[np.ndarray]) -> None:
        """Warn where a frame's new pose (its rotation ``turns``) lies beyond those shown.

        Beyond: an origin outside the demonstrated ones' box widened by a quarter
        of its size on each side (at least 1e-9 of the path's size), or a rotation
        vector from their mean rotation more than :data:`BEYOND_TURN` outside the
        box of theirs (in 2-D: the angle outside the demonstrated interval).
        """
        ranges = getattr(self, "frame_ranges_", None)
        if not ranges:
            return  # an older file: the demonstrated poses were not kept
        beyond = []
        for name, frame, rotation in zip(self.frame_names_, posed, turns, strict=True):
            shown = ranges[name]
            low, high = np.asarray(shown["low"]), np.asarray(shown["high"])
            margin = np.maximum(0.25 * (high - low), 1e-9 * self._extent())
            origin = np.asarray(frame.origin, dtype=np.float64)
            turn = _turn_vectors(rotation, np.asarray(shown["mean"]))[0]
            turn_low, turn_high = np.asarray(shown["turn_low"]), np.asarray(shown["turn_high"])
            if np.any(origin < low - margin) or np.any(origin > high + margin):
                span = ", ".join(
                    f"{'xyz'[i]} {low[i]:.3g} to {high[i]:.3g}" for i in range(len(low))
                )
                beyond.append(
                    f"{name} at ({', '.join(f'{v:.3g}' for v in origin)}) {self.units}, "
                    f"beyond the demonstrated {span}"
                )
            elif np.any(turn < turn_low - BEYOND_TURN) or np.any(turn > turn_high + BEYOND_TURN):
                axis = int(np.argmax(np.maximum(turn_low - turn, turn - turn_high)))
                beyond.append(
                    f"{name} turned {turn[axis]:+.2f} rad about {'xyz'[axis]} from the "
                    f"demonstrations' mean, beyond the {turn_low[axis]:+.2f} to "
                    f"{turn_high[axis]:+.2f} rad they showed"
                )
        if beyond:
            warnings.warn(
                f"plan: {'; '.join(beyond)}: the plan extrapolates the demonstrations "
                "(check it, or show demonstrations with such poses)",
                UserWarning,
                stacklevel=3,
            )

    def _extent(self) -> float:
        """The demonstrations' size (units): the mixture's largest local mean or position spread."""
        means = self.tpgmm_.means_[..., 1:]
        spread = np.sqrt(np.diagonal(self.tpgmm_.covariances_, axis1=-2, axis2=-1)[..., 1:])
        return float(max(np.abs(means).max(), spread.max(), 1e-12))

    # ------------------------------------------------------------------ reports
    def summary(self) -> str:
        """What was learned, on one line."""
        check_fitted(self, "tpgmm_")
        timed = f", {self.duration_:.3g} s" if self.duration_ is not None else ", no times"
        turning = " with the tool's orientation" if self.orientation_models_ is not None else ""
        return (
            f"{self.n_dims_}-D movement{turning} in the task frames {', '.join(self.frame_names_)} "
            f"from {self.n_demos_} demonstrations{timed} ({self.tpgmm_.n_components} components, "
            f"EM {'converged' if self.tpgmm_.converged_ else 'NOT converged'} in "
            f"{self.tpgmm_.n_iter_} iterations)"
        )

    def to_units(self, units: str) -> TaskFrameSkill:
        """The same skill in another length unit (a new object): its plans times the factor.

        The mixture's positions are scaled (means by the factor, covariances by
        its square, the phase's cross terms by it) and EM's length scale with
        them; frames' origins are then given in the new unit, angles and
        quaternions as before.
        """
        check_fitted(self, "tpgmm_")
        units = check_units(units)
        factor = conversion_factor(self.units, units)
        state = self.tpgmm_.to_state()
        scale = np.ones(self.n_dims_ + 1)
        scale[1:] = factor
        state["means"] = (np.asarray(state["means"]) * scale).tolist()
        state["covariances"] = (
            np.asarray(state["covariances"]) * np.multiply.outer(scale, scale)
        ).tolist()
        state["params"] = {**state["params"], "length_scale": conversion_factor("m", units)}
        state["log_likelihood"] -= self.tpgmm_.n_frames_ * self.n_dims_ * math.log(factor)
        made = type(self)(**{**self.get_params(), "units": units})
        made.tpgmm_ = TPGMM.from_state(state, "tpgmm")
        made.frame_names_ = list(self.frame_names_)
        made.duration_, made.n_demos_, made.n_dims_ = self.duration_, self.n_demos_, self.n_dims_
        made.frame_ranges_ = None if self.frame_ranges_ is None else {
            name: {**shown, "low": [factor * v for v in shown["low"]],
                   "high": [factor * v for v in shown["high"]]}
            for name, shown in self.frame_ranges_.items()
        }  # fmt: skip
        # Orientations do not depend on the unit.
        made.orientation_references_ = self.orientation_references_
        made.orientation_models_ = self.orientation_models_
        return made

    # ------------------------------------------------------------------ files
    def to_dict(self) -> dict[str, Any]:
        """The skill as a JSON-ready dict (the format of the module notes); the same each time."""
        check_fitted(self, "tpgmm_")
        return {
            "format": TASK_FRAME_FORMAT,
            "version": TASK_FRAME_VERSION,
            "lfdkit": __version__,
            "params": jsonable(self.get_params()),
            "units": self.units,
            "n_dims": int(self.n_dims_),
            "frames": list(self.frame_names_),
            "duration": self.duration_,
            "n_demos": int(self.n_demos_),
            "frame_ranges": jsonable(self.frame_ranges_),
            "tpgmm": jsonable(self.tpgmm_.to_state()),
            "orientation": None
            if self.orientation_models_ is None
            else {
                "references": self.orientation_references_.tolist(),
                "models": [jsonable(m.to_state()) for m in self.orientation_models_],
            },
        }

    @classmethod
    def from_dict(cls, data: Any, *, source: str = "task-frame skill") -> TaskFrameSkill:
        """Rebuild a skill from :meth:`to_dict`'s output, without refitting.

        Raises
        ------
        ValueError
            For another format, a newer version, or a missing or broken field;
            one line starting with ``source`` and naming the field.
        """
        keys = ("units", "n_dims", "frames", "duration", "n_demos", "tpgmm")
        skill = made_from_document(
            cls, data, TASK_FRAME_FORMAT, TASK_FRAME_VERSION, keys,
            source=source, kind="task-frame skill",
        )  # fmt: skip
        model = TPGMM.from_state(data["tpgmm"], f"{source}: tpgmm")
        wanted = {
            "n_components": skill.n_components,
            "product": skill.product,
            "length_scale": conversion_factor("m", skill.units),
        }
        for key, value in wanted.items():
            if getattr(model, key) != value:
                raise ValueError(
                    f"{source}: tpgmm.params.{key}: {getattr(model, key)!r}, but the skill's "
                    f"params say {value!r}; the file was edited: learn the skill again"
                )
        if data["n_dims"] != model.n_dims_ or model.n_dims_ not in (2, 3):
            raise ValueError(
                f"{source}: n_dims: {data['n_dims']!r}, but the mixture is {model.n_dims_}-D"
            )
        if data["frames"] != model.frame_names_:
            raise ValueError(
                f"{source}: frames: {data['frames']!r}, but the mixture's are "
                f"{model.frame_names_!r}"
            )
        duration = data["duration"]
        if duration is not None and (
            isinstance(duration, bool)
            or not isinstance(duration, (int, float))
            or not (math.isfinite(duration) and duration > 0.0)
        ):
            raise ValueError(f"{source}: duration: expected null or seconds > 0, got {duration!r}")
        n_demos = data["n_demos"]
        if isinstance(n_demos, bool) or not isinstance(n_demos, int) or n_demos < 1:
            raise ValueError(f"{source}: n_demos: expected a count, got {n_demos!r}")
        skill.orientation_references_, skill.orientation_models_ = _orientation_state(
            data.get("orientation"), len(model.frame_names_), f"{source}: orientation"
        )
        ranges = data.get("frame_ranges")  # absent: written before it was kept (no warnings)
        skill.frame_ranges_ = (
            None
            if ranges is None
            else _ranges_state(ranges, model.frame_names_, model.n_dims_, f"{source}: frame_ranges")
        )
        skill.tpgmm_ = model
        skill.frame_names_ = list(model.frame_names_)
        skill.duration_ = None if duration is None else float(duration)
        skill.n_demos_, skill.n_dims_ = n_demos, int(model.n_dims_)
        return skill


def _frame(pose: Any, name: str, n_dims: int, reach: float) -> TaskFrame:
    """A frame's new pose as a :class:`TaskFrame` of ``n_dims``; one-line errors naming it.

    ``reach``: the largest origin accepted (units),
    :data:`~lfdkit.imitate.dmp.MAX_RELATIVE_MAGNITUDE` times the demonstrations'
    extent, as a skill's goal (a typo or another unit, not a task).
    """
    where = f"frames[{name!r}]"
    if isinstance(pose, TaskFrame):
        frame = pose
        if not (np.all(np.isfinite(frame.origin)) and np.all(np.isfinite(frame.matrix))):
            raise ValueError(f"{where}: contains NaN or an infinite value")
    else:
        frame = frame_from_pose(pose, where)
    if np.asarray(frame.origin).shape != (n_dims,):
        want = "[x, y, angle]" if n_dims == 2 else "[x, y, z, qx, qy, qz, qw]"
        raise ValueError(f"{where}: this skill is {n_dims}-D; give {want}")
    origin = np.asarray(frame.origin, dtype=float)
    far = float(np.abs(origin).max())
    if far > reach:
        raise ValueError(
            f"frames[{name!r}]: the origin is {far:.3g} from 0, beyond "
            f"{MAX_RELATIVE_MAGNITUDE:g} times the demonstrations' extent ({reach:.3g}); "
            "check the pose and its unit"
        )
    return frame


def _frame_rotation(pose: Any) -> np.ndarray:
    """A pose's rotation as a unit quaternion: ``[x, y, angle]`` about z, or its ``[qx..qw]``."""
    pose = np.asarray(pose, dtype=np.float64)
    if pose.shape == (3,):
        return np.array([0.0, 0.0, np.sin(0.5 * pose[2]), np.cos(0.5 * pose[2])])
    return pose[3:] / np.linalg.norm(pose[3:])


def _rotation_of(frame: TaskFrame) -> np.ndarray:
    """A frame's rotation as a unit quaternion (a 2-D one's about z), as `_frame_rotation`."""
    matrix = np.asarray(frame.matrix, dtype=np.float64)
    if matrix.shape == (2, 2):
        return _frame_rotation(np.r_[frame.origin, np.arctan2(matrix[1, 0], matrix[0, 0])])
    return _frame_rotation(np.r_[frame.origin, quaternion_from_matrix(matrix)])


def _orientation_state(value: Any, n_frames: int, where: str) -> tuple[Any, Any]:
    """A file's ``orientation``: the references (P, 4) and the frames' mixtures, or Nones."""
    if value is None:
        return None, None
    if not isinstance(value, Mapping) or set(value) != {"references", "models"}:
        raise ValueError(f"{where}: expected null or an object with references and models")
    try:
        references = np.array(value["references"], dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{where}.references: expected [qx, qy, qz, qw] per frame") from None
    models = value["models"]
    if references.shape != (n_frames, 4) or not isinstance(models, list) or len(models) != n_frames:
        raise ValueError(
            f"{where}: expected a reference and a model for each of the {n_frames} frames"
        )
    if not np.all(np.abs(np.linalg.norm(references, axis=1) - 1.0) <= 1e-9):
        raise ValueError(f"{where}.references: not unit quaternions; the file was edited")
    made = [TPGMM.from_state(m, f"{where}.models[{j}]") for j, m in enumerate(models)]
    if any(m.n_dims_ != 3 or m.n_frames_ != 1 for m in made):
        raise ValueError(f"{where}.models: expected mixtures of 3-D rotation vectors, one frame")
    return references, made


def _frame_ranges(
    frames: Sequence[Mapping[str, Any]], names: Sequence[str], n_dims: int
) -> dict[str, dict[str, Any]]:
    """Each frame's demonstrated poses: the origins' box, the mean rotation, the largest turn."""
    out: dict[str, dict[str, Any]] = {}
    for name in names:
        poses = np.array([np.asarray(f[name], dtype=np.float64) for f in frames])
        origins = poses[:, :n_dims]
        turns = np.array([_frame_rotation(p) for p in poses])
        mean = mean_quaternion(turns)
        turned = _turn_vectors(turns, mean)
        out[name] = {
            "low": origins.min(axis=0).tolist(),
            "high": origins.max(axis=0).tolist(),
            "mean": mean.tolist(),
            "turn_low": turned.min(axis=0).tolist(),
            "turn_high": turned.max(axis=0).tolist(),
        }
    return out


def _turn_vectors(turns: np.ndarray, mean: np.ndarray) -> np.ndarray:
    """Rotation vectors (rad, in the mean's axes) of ``turns`` (m, 4) from ``mean``, (m, 3)."""
    return 2.0 * log(multiply(conjugate(mean), np.atleast_2d(turns)))


def _ranges_state(value: Any, names: Sequence[str], n_dims: int, where: str) -> dict:
    """A file's ``frame_ranges``: each frame's origins' box, mean rotation and turns' box."""
    if not isinstance(value, Mapping) or list(value) != list(names):
        raise ValueError(f"{where}: expected an object with the frames {', '.join(names)}")
    keys = ("low", "high", "mean", "turn_low", "turn_high")
    out = {}
    for name in names:
        shown = value[name]
        if not isinstance(shown, Mapping) or set(shown) != set(keys):
            raise ValueError(f"{where}.{name}: expected {', '.join(keys)}")
        try:
            low, high, mean, turn_low, turn_high = (
                np.array(shown[k], dtype=np.float64) for k in keys
            )
        except (TypeError, ValueError):
            raise ValueError(f"{where}.{name}: expected numbers") from None
        if (
            low.shape != (n_dims,)
            or high.shape != (n_dims,)
            or mean.shape != (4,)
            or turn_low.shape != (3,)
            or turn_high.shape != (3,)
            or not np.all(np.isfinite(np.r_[low, high, mean, turn_low, turn_high]))
            or np.any(low > high)
            or np.any(turn_low > turn_high)
            or abs(float(np.linalg.norm(mean)) - 1.0) > 1e-9
        ):
            raise ValueError(
                f"{where}.{name}: not a box, a rotation and turns; the file was edited"
            )
        arrays = (low, high, mean, turn_low, turn_high)
        out[name] = {k: v.tolist() for k, v in zip(keys, arrays, strict=True)}
    return out
