"""Periodic skills: a rhythm learned from several cycles, saved, loaded and planned (issue 33).

What: :class:`PeriodicSkill` learns a periodic movement of the tool (wiping,
polishing, repeated sweeps), positions and optionally orientations, from one
recording of several cycles (:class:`lfdkit.imitate.RhythmicDMP`, or
:class:`lfdkit.imitate.RhythmicPoseDMP` with orientations: both on one
phase), and plans a timed run of it with the amplitude, speed and centre
asked, starting and stopping at rest. It is the periodic counterpart of
:class:`lfdkit.skill.Skill` (which carries a movement from a start to a
goal): the same units, a file of its own next to the skill file, and a
plan that :func:`lfdkit.execute.pipeline.execute_plan` runs on an arm.

Why a class of its own, not a mode of :class:`~lfdkit.skill.Skill`: a
rhythm has no start, goal, obstacles or reward; what it has (period, cycle,
centre, amplitude) a discrete skill has not. Sharing the file machinery
(:mod:`lfdkit.io.skill_file`: strict JSON reader, atomic writer, never over a
file unless asked) and the plan's type (:class:`~lfdkit.model.timed_path.TimedPath`)
is what makes it first-class, not sharing the estimator.

File
----
One JSON object, ``{"format": "lfdkit-periodic-skill", "version": 1, ...}``:

``params``
    The constructor parameters (harmonics, gain, a given period, units,
    the plans' ramp).
``n_dims``, ``units``
    Dimension of the positions (2 or 3) and their unit.
``fit``
    ``{"cycles": C, "n_points": n}``: the demonstration's length in cycles
    and samples (said by ``lfdkit learn``; not used to plan).
``position``
    The position rhythm (:meth:`lfdkit.imitate.RhythmicDMP.to_state`):
    parameters, ``period`` (s), ``residual_rms`` (units), ``n_dims`` and the
    ``coefficients`` of the cycle's Fourier series, ``(2K + 1, n_dims)``
    nested lists (``a₀``, the centre, then the cosines, then the sines).
``orientation``
    Only with orientations: :meth:`lfdkit.imitate.QuaternionRhythmicDMP.to_state`
    (its ``centre`` quaternion ``[x, y, z, w]``, ``residual_rms`` in rad and
    the ``tangent`` rhythm of ``log(q ⊗ c̄)`` as ``position``).
``lfdkit``
    The version that wrote it.

Every number is written exactly (JSON decimals of Python's shortest
round-tripping form: a few hundred numbers, so readable lists rather than
base64), the file holds no date and no run time, and loading restores the
state without refitting: save → load → save gives the same bytes, and the
loaded skill's plans are the saved one's to the bit.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any, ClassVar

import numpy as np

from lfdkit import __version__
from lfdkit.core.constraints import Checked, Integer, Real
from lfdkit.core.estimator import Estimator, check_fitted
from lfdkit.core.units import check_units, conversion_factor
from lfdkit.core.validation import check_count, check_path, check_positive, check_times
from lfdkit.imitate.rhythmic import (
    MAX_HARMONICS,
    MIN_CYCLES,
    QuaternionRhythmicDMP,
    RhythmicDMP,
    RhythmicPoseDMP,
)
from lfdkit.io.skill_file import (
    PERIODIC_FORMAT,
    SavedToSkillFile,
    is_periodic_document,
    jsonable,
    made_from_document,
)
from lfdkit.model.timed_path import TimedPath

__all__ = [
    "PERIODIC_FORMAT",
    "PERIODIC_VERSION",
    "PeriodicSkill",
    "is_periodic_document",
]

PERIODIC_VERSION = 1
"""Newest periodic-skill-file version this module reads, and the one it writes."""

#: Ramp of a plan, in periods of the run, when none is given: half a cycle to rise, half to fall.
RAMP_PERIODS = 0.5
#: Most cycles one plan may run (10⁴ cycles of 400 steps: 4 million samples).
MAX_CYCLES = 10_000
#: A fit whose residual exceeds this fraction of the demonstration's RMS about its centre is poor.
POOR_FIT = 0.2
#: ... and above this fraction no cycle was found: refused (0.8 cycles of a circle leave 82 %).
NO_CYCLE = 0.5


class PeriodicSkill(SavedToSkillFile, Estimator):
    """A periodic movement of the tool, learned from several cycles, planned at any speed and size.

    Parameters
    ----------
    n_harmonics : int, default 8
        Harmonics of the cycle's Fourier series (:class:`lfdkit.imitate.RhythmicDMP`).
    alpha : float, default 25
        Gain of the transformation system.
    period : float, optional
        Seconds per cycle; default learned from the demonstration.
    units : {"m", "cm", "mm"}, default "m"
        Unit of the positions.
    ramp : float, optional
        Seconds of the smooth start and stop of a plan (the amplitude rises
        from 0 and falls back to it, the tool at rest at the centre at both
        ends); default half a cycle of the run; 0 starts on the cycle, moving.

    Attributes
    ----------
    position_ : RhythmicDMP
        The rhythm of the positions.
    orientation_ : QuaternionRhythmicDMP or None
        The rhythm of the orientations, on the same phase; None without.
    period_ : float
        Seconds per cycle.
    centre_ : ndarray, shape (n_dims,)
        The cycle's centre (its mean), in ``units``.
    cycles_ : float
        Cycles the demonstration covered.
    n_points_ : int
        Samples of the demonstration.
    n_dims_ : int

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0.0, 6.0, 601)
    >>> u = 2 * np.pi * t / 1.5
    >>> skill = PeriodicSkill().fit(np.c_[np.sin(u), 0.3 * np.sin(2 * u)], t)
    >>> plan = skill.plan(cycles=3, frequency=2.0)
    >>> round(skill.period_, 3), bool(np.allclose(plan.velocities[[0, -1]], 0.0))
    (1.5, True)
    """

    _parameter_constraints: ClassVar[dict[str, Any]] = {
        # The rhythm's own (:class:`RhythmicDMP`), then the skill's.
        "n_harmonics": Integer(minimum=1, maximum=MAX_HARMONICS),
        "alpha": Real(),
        "period": Real(meaning="seconds per cycle", optional=True),
        "units": Checked(check_units),
        "ramp": Real(allow_zero=True, optional=True),
    }

    def __init__(
        self,
        n_harmonics: int = 8,
        alpha: float = 25.0,
        period: float | None = None,
        units: str = "m",
        ramp: float | None = None,
    ):
        self.n_harmonics = n_harmonics
        self.alpha = alpha
        self.period = period
        self.units = units
        self.ramp = ramp

    # ------------------------------------------------------------------ learning
    def fit(self, positions: Any, times: Any, orientations: Any = None) -> PeriodicSkill:
        """Learn the rhythm from one recording of several cycles.

        Parameters
        ----------
        positions : array_like, shape (n_points, n_dims), n_dims 2 or 3
            Positions in ``units``, at least 1.5 cycles.
        times : array_like, shape (n_points,)
            Seconds, strictly increasing (any spacing).
        orientations : array_like, shape (n_points, 4), optional
            The tool's orientation, unit quaternions ``[x, y, z, w]``.

        Returns
        -------
        self

        Raises
        ------
        ValueError
            One line naming the argument: no rhythm found (too few cycles, a
            still demonstration), too few samples a cycle for the harmonics.
        """
        params = self._validate_params()
        y = check_path(positions, "positions", min_points=4, min_dims=2)
        if y.shape[1] > 3:
            raise ValueError(
                f"positions: {y.shape[1]} coordinates a sample; a tool moves in 2 or 3"
            )
        t = check_times(times, len(y), "times", of="positions")
        rhythm = {key: params[key] for key in ("n_harmonics", "alpha", "period")}
        if orientations is None:
            self.position_ = RhythmicDMP(**rhythm).fit(y, t)
            self.orientation_ = None
        else:
            pose = RhythmicPoseDMP(**rhythm).fit(y, orientations, t)
            self.position_, self.orientation_ = pose.position_, pose.orientation_
        self.cycles_ = float(t[-1] - t[0]) / self.position_.period_
        self.n_points_ = len(y)
        self._learned()
        unexplained = self._unexplained(y)
        if unexplained > NO_CYCLE:
            del self.position_  # not fitted: nothing half-learned is left to plan with
            raise ValueError(
                f"positions: no repeating cycle found (the best period, {self.period_:.4g} s, "
                f"leaves {100 * unexplained:.0f} % of the movement unexplained); record at "
                f"least {MIN_CYCLES} cycles of one repeated movement"
            )
        return self

    def _unexplained(self, demo: np.ndarray) -> float:
        """RMS residual of the fit over the demonstration's RMS distance from the centre."""
        stroke = float(np.sqrt(np.mean(np.sum((demo - self.centre_) ** 2, axis=1))))
        return self.position_.residual_rms_ / stroke if stroke > 0.0 else 0.0

    def _learned(self) -> None:
        """The attributes read off the rhythms (after a fit and after loading)."""
        self.period_ = self.position_.period_
        self.centre_ = self.position_.centre_
        self.n_dims_ = self.position_.n_dims_

    # ------------------------------------------------------------------ planning
    def plan(
        self,
        cycles: float | None = None,
        *,
        duration: float | None = None,
        amplitude: float | Callable[[float], Any] = 1.0,
        frequency: float | Callable[[float], Any] = 1.0,
        centre: Any = None,
        orientation_centre: Any = None,
        ramp: float | None = None,
        dt: float | None = None,
    ) -> TimedPath:
        """A timed run of the rhythm: rest at the centre, ``cycles`` cycles, rest at the centre.

        Parameters
        ----------
        cycles : float, optional
            Cycles at full amplitude between the rise and the fall (default 1
            when ``duration`` is not given). The run lasts ``cycles ·
            period_ / frequency + 2.5 ramp`` s: the rise, the cycles, the fall
            and a half ramp settling at the centre.
        duration : float, optional
            Seconds of the whole run instead (not with ``cycles``).
        amplitude : float or callable, default 1
            Size of the cycle about its centre (2: twice as wide), or a
            function of time (s).
        frequency : float or callable, default 1
            Speed factor (2: each cycle in half the period), or a function of
            time (then give ``duration``).
        centre : array_like, shape (n_dims,), or callable, optional
            Where the cycle is centred (default the learned ``centre_``), in
            ``units``, or a function of time returning it.
        orientation_centre : array_like, shape (4,), optional
            The orientation the rocking is about (default the learned one).
        ramp : float, optional
            Seconds of the smooth start and stop (default the ``ramp``
            parameter, else half a cycle of the run).
        dt : float, optional
            Step in seconds (default 1/400 of the learned period).

        Returns
        -------
        TimedPath
            ``times`` (n,) s from 0, ``positions`` and ``velocities`` (n,
            n_dims) in ``units`` and ``units``/s; ``orientations`` (n, 4) for
            a skill with orientations, else None.
        """
        check_fitted(self, "position_")
        if cycles is not None and duration is not None:
            raise ValueError("cycles: give cycles or duration, not both")
        if callable(frequency) and duration is None:
            raise ValueError("duration: a frequency that varies needs the run's duration")
        run_period = self.period_ / (1.0 if callable(frequency) else _speed(frequency))
        if ramp is None:
            ramp = self.ramp if self.ramp is not None else RAMP_PERIODS * run_period
        ramp = check_positive(ramp, "ramp", allow_zero=True)
        if duration is None:
            n = 1.0 if cycles is None else check_positive(cycles, "cycles")
            if n > MAX_CYCLES:
                raise ValueError(f"cycles: {n:g}, more than {MAX_CYCLES}; plan fewer at a time")
            duration = n * run_period + 2.5 * ramp
        else:
            duration = check_positive(duration, "duration")
            check_count(
                math.ceil(duration / run_period), "duration (cycles)", maximum=MAX_CYCLES + 3
            )
        settings = {"amplitude": amplitude, "frequency": frequency, "ramp": ramp}
        moving = self.position_.rollout(duration, dt, centre=centre, **settings)
        if self.orientation_ is None:
            if orientation_centre is not None:
                raise ValueError(
                    "orientation_centre: the skill learned no orientations; leave it out"
                )
            return moving
        turning = self.orientation_.rollout(duration, dt, centre=orientation_centre, **settings)
        return TimedPath(
            moving.times, moving.positions, moving.velocities, orientations=turning.orientations
        )

    # ------------------------------------------------------------------ reports
    @property
    def extent_(self) -> np.ndarray:
        """Peak-to-peak size of the learned cycle along each axis, shape (n_dims,), in ``units``."""
        check_fitted(self, "position_")
        cycle = self.position_.cycle(np.linspace(0.0, 2.0 * np.pi, 400, endpoint=False))
        return cycle.max(axis=0) - cycle.min(axis=0)

    def summary(self) -> str:
        """What was learned, on one line: period, cycles, size and fit error."""
        check_fitted(self, "position_")
        extent = self.extent_
        extent[extent < 1e-9 * extent.max()] = 0.0  # a flat axis, not rounding noise
        size = " x ".join(f"{v:.3g}" for v in extent)
        line = (
            f"period {self.period_:.4g} s from {self.cycles_:.3g} cycles, a {size} "
            f"{self.units} cycle ({self.n_harmonics} harmonics); fit RMS "
            f"{self.position_.residual_rms_:.3g} {self.units}"
        )
        if self.orientation_ is not None:
            line += f", orientation {1e3 * self.orientation_.residual_rms_:.3g} mrad"
        return line

    def fit_warning(self, demo: Any) -> str | None:
        """A poor fit said in words (residual above :data:`POOR_FIT` of the stroke), else None.

        ``demo`` is the positions the skill was fitted on.
        """
        check_fitted(self, "position_")
        unexplained = self._unexplained(np.asarray(demo, dtype=np.float64))
        if unexplained <= POOR_FIT:
            return None
        return (
            f"the learned cycle fits the demonstration poorly (RMS "
            f"{self.position_.residual_rms_:.3g} {self.units}, {100 * unexplained:.0f} % of "
            "the stroke): check that it repeats one movement, or give more harmonics"
        )

    def to_units(self, units: str) -> PeriodicSkill:
        """The same skill in another length unit (a new object; orientations are unchanged)."""
        check_fitted(self, "position_")
        units = check_units(units)
        factor = conversion_factor(self.units, units)
        state = self.position_.to_state()
        state["coefficients"] = state["coefficients"] * factor
        state["residual_rms"] *= factor
        made = type(self)(**{**self.get_params(), "units": units})
        made.position_ = RhythmicDMP.from_state(state, "position")
        made.orientation_ = self.orientation_
        made.cycles_, made.n_points_ = self.cycles_, self.n_points_
        made._learned()
        return made

    # ------------------------------------------------------------------ files
    def to_dict(self) -> dict[str, Any]:
        """The skill as a JSON-ready dict (the format of the module notes); the same each time."""
        check_fitted(self, "position_")
        document: dict[str, Any] = {
            "format": PERIODIC_FORMAT,
            "version": PERIODIC_VERSION,
            "lfdkit": __version__,
            "params": jsonable(self.get_params()),
            "n_dims": int(self.n_dims_),
            "units": self.units,
            "fit": {"cycles": float(self.cycles_), "n_points": int(self.n_points_)},
            "position": jsonable(self.position_.to_state()),
        }
        if self.orientation_ is not None:
            document["orientation"] = jsonable(self.orientation_.to_state())
        return document

    @classmethod
    def from_dict(cls, data: Any, *, source: str = "periodic skill") -> PeriodicSkill:
        """Rebuild a skill from :meth:`to_dict`'s output, without refitting.

        Raises
        ------
        ValueError
            For another format, a newer version, or a missing or broken field;
            one line starting with ``source`` and naming the field.
        """
        skill = made_from_document(
            cls, data, PERIODIC_FORMAT, PERIODIC_VERSION, ("n_dims", "units", "fit", "position"),
            source=source, kind="periodic skill",
        )  # fmt: skip
        n_dims = data["n_dims"]
        if isinstance(n_dims, bool) or n_dims not in (2, 3):
            raise ValueError(f"{source}: n_dims: expected 2 or 3, got {n_dims!r}")
        skill.cycles_, skill.n_points_ = _fit_record(data["fit"], f"{source}: fit")
        position = RhythmicDMP.from_state(data["position"], f"{source}: position")
        _check_rhythm_params(position, skill, f"{source}: position.params")
        if position.n_dims_ != n_dims:
            raise ValueError(
                f"{source}: position.n_dims: {position.n_dims_}, but n_dims is {n_dims}"
            )
        orientation = None
        if data.get("orientation") is not None:
            orientation = QuaternionRhythmicDMP.from_state(
                data["orientation"], f"{source}: orientation"
            )
            _check_rhythm_params(
                orientation, skill, f"{source}: orientation.params", ("n_harmonics", "alpha")
            )
            if orientation.period_ != position.period_:
                raise ValueError(
                    f"{source}: orientation.tangent.period: {orientation.period_!r}, not the "
                    f"position's {position.period_!r}: both run on one phase"
                )
        skill.position_, skill.orientation_ = position, orientation
        skill._learned()
        return skill


# ---------------------------------------------------------------- internals
def _speed(frequency: Any) -> float:
    return check_positive(frequency, "frequency")


def _fit_record(fit: Any, where: str) -> tuple[float, int]:
    """``fit``'s cycles (> 0) and samples (an integer >= 4)."""
    if not isinstance(fit, Mapping):
        raise ValueError(f"{where}: expected an object, got {fit!r}")
    cycles, n_points = fit.get("cycles"), fit.get("n_points")
    if isinstance(cycles, bool) or not isinstance(cycles, (int, float)) or not cycles > 0.0:
        raise ValueError(f"{where}.cycles: expected a positive number, got {cycles!r}")
    if not math.isfinite(cycles):
        raise ValueError(f"{where}.cycles: expected a finite number, got {cycles!r}")
    if isinstance(n_points, bool) or not isinstance(n_points, int) or n_points < 4:
        raise ValueError(f"{where}.n_points: expected an integer of at least 4, got {n_points!r}")
    return float(cycles), n_points


def _check_rhythm_params(
    rhythm: Any,
    skill: PeriodicSkill,
    where: str,
    keys: tuple[str, ...] = ("n_harmonics", "alpha", "period"),
) -> None:
    """A stored rhythm was learned with the skill's harmonics, gain and given period."""
    for key in keys:
        if getattr(rhythm, key) != getattr(skill, key):
            raise ValueError(
                f"{where}.{key}: {getattr(rhythm, key)!r}, but the skill's params say "
                f"{getattr(skill, key)!r}; the file was edited: learn the skill again"
            )
