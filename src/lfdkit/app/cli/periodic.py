"""Periodic skills on the command line: ``learn --periodic``, and ``plan``/``plot`` of one.

A periodic skill (:class:`lfdkit.skill.periodic.PeriodicSkill`) is learned
from one recording of several cycles and planned as a run of cycles; its
file says which it is, so ``plan`` and ``plot`` take either kind of skill file
and this module handles the periodic one. Options of the other kind are
refused on one line (exit 2), not ignored.
"""

from __future__ import annotations

import argparse
import re
import sys
import warnings

from lfdkit.app.cli.common import (
    CommandError,
    UsageError,
    bounded_int,
    parse_numbers,
    parse_quaternion,
    point_arg,
    positive_or_none,
    refuse_existing,
    refuse_implausible_metres,
    tell,
    write_timed_run,
)
from lfdkit.core.numbers import parse_decimal

__all__ = [
    "DISCRETE_OPTIONS",
    "PERIODIC_OPTIONS",
    "add_learn_options",
    "add_run_options",
    "is_periodic",
    "learn",
    "no_scene",
    "plan",
    "plot",
    "refuse_periodic_options",
    "run",
]

#: Cycles a plot runs when --cycles and --duration are not given.
PLOT_CYCLES = 2.0

# ``plan``/``plot`` options of a skill from a start to a goal: (attribute, option, its default).
DISCRETE_OPTIONS = (
    ("start", "--start", None),
    ("goal", "--goal", None),
    ("obstacle", "--obstacle", None),
    ("scene", "--scene", None),
    ("via", "--via", None),
    ("start_orientation", "--start-orientation", None),
    ("goal_orientation", "--goal-orientation", None),
    ("planner", "--planner", None),
    ("horizon", "--horizon", None),
    ("clearance", "--clearance", 0.0),
    ("goal_approach", "--goal-approach", "auto"),
    ("unknown_class", "--unknown-class", None),
)
# Their periodic counterparts, refused for a skill from a start to a goal.
PERIODIC_OPTIONS = (
    ("cycles", "--cycles"),
    ("amplitude", "--amplitude"),
    ("frequency", "--frequency"),
    ("period", "--period"),
    ("centre", "--centre"),
    ("centre_orientation", "--centre-orientation"),
    ("ramp", "--ramp"),
)


def is_periodic(skill: object) -> bool:
    """Whether a skill file read (:func:`load_skill_file`) is a periodic skill."""
    # Not loaded yet: no skill read can be periodic (a discrete plan never imports it).
    periodic = sys.modules.get("lfdkit.skill.periodic")
    return periodic is not None and isinstance(skill, periodic.PeriodicSkill)


# ---------------------------------------------------------------- learn
def learn(args: argparse.Namespace) -> None:
    """``lfdkit learn --periodic``: one recording of several cycles to a periodic skill file."""
    if args.scenes is not None:
        raise UsageError("--scenes: a periodic skill has no obstacles; leave --scenes out")
    if len(args.demos) != 1:
        raise UsageError(
            f"DEMOS: {len(args.demos)} files; a periodic skill learns from one recording of "
            "several cycles: give one file"
        )
    period = positive_or_none(args.period, "--period", "seconds per cycle")
    speed = positive_or_none(args.pace, "--pace", "a mean speed in units per second")
    refuse_existing(args.output, args.force)
    import numpy as np

    from lfdkit.core.geometry import path_length
    from lfdkit.io import load_demos
    from lfdkit.skill.periodic import PeriodicSkill

    source = args.demos[0]
    records = load_demos(source, as_records=True)
    if len(records) != 1:
        ids = ", ".join(repr(r.id) for r in records[:3]) + (", ..." if len(records) > 3 else "")
        raise CommandError(
            f"{source}: {len(records)} demonstrations ({ids}); a periodic skill learns from one "
            "recording of several cycles: give a file with one"
        )
    demo = records[0]
    positions, times = demo.points, demo.times
    if times is None:
        if period is None and speed is None:
            raise CommandError(
                f"{source}: no t column; a periodic skill needs the samples' times: add a t "
                "column (seconds), or give --period S (seconds per cycle) or --pace V (mean "
                "speed, units/s)"
            )
        if speed is not None:  # evenly sampled at that mean speed
            times = np.linspace(0.0, path_length(positions) / speed, len(positions))
        else:  # the period found in samples, then made --period seconds
            samples = np.arange(len(positions), dtype=np.float64)
            in_samples = _fitted(PeriodicSkill(n_harmonics=args.harmonics), positions, samples)
            times = samples * (period / in_samples.period_)
    elif speed is not None:
        raise UsageError("--pace: the file has times (a t column); leave --pace out")
    if args.units is None:  # implausible in metres and no unit given: refused, as learn does
        refuse_implausible_metres(source, [positions], [times])
    skill = PeriodicSkill(n_harmonics=args.harmonics, period=period, units=args.units or "m")
    skill = _fitted(skill, positions, times, demo.orientations, source)
    poor = skill.fit_warning(positions)
    if poor is not None:
        warnings.warn(f"{source}: {poor} (--harmonics)", stacklevel=1)
    skill.save(args.output, overwrite=args.force)
    tell(args, f"learned a periodic skill: {skill.summary()}; wrote {args.output}")


def _fitted(skill, positions, times, orientations=None, source=None):
    """``skill`` fitted; the library's errors in the command's words (the file, the options)."""
    try:
        return skill.fit(positions, times, orientations)
    except ValueError as exc:
        message = re.sub(r"^(demo|positions|orientations|times): ", "", str(exc))
        message = message.replace("n_harmonics:", "--harmonics:")
        raise CommandError(f"{source or 'DEMOS'}: {message}") from None


def add_learn_options(parser: argparse.ArgumentParser) -> None:
    """``learn``'s periodic options."""
    group = parser.add_argument_group(
        "periodic skill (--periodic): a rhythm learned from one recording of several cycles"
    )
    group.add_argument(
        "--periodic",
        action="store_true",
        help="learn a periodic skill (wiping, polishing): the period, the cycle as a Fourier "
        "series and, with qx,qy,qz,qw columns, the orientation's rhythm; plan it with lfdkit "
        "plan SKILL --cycles N",
    )
    group.add_argument(
        "--period",
        metavar="S",
        help="seconds per cycle (default: learned from the demonstration); for a file without "
        "times, the time scale",
    )
    group.add_argument(
        "--pace",
        metavar="V",
        help="a file without times: its mean speed, units/s (the period is then learned)",
    )
    group.add_argument(
        "--harmonics",
        type=bounded_int(1, 50),
        default=8,
        metavar="K",
        help="harmonics of the cycle's Fourier series, 1 to 50 (default %(default)s)",
    )


def refuse_learn_options(args: argparse.Namespace) -> None:
    """``learn`` without ``--periodic``: its periodic options are refused, not ignored."""
    for attr, option, default in (("period", "--period", None), ("pace", "--pace", None)):
        if getattr(args, attr) != default:
            raise UsageError(f"{option}: only with --periodic (a periodic skill)")
    if args.harmonics != 8:
        raise UsageError("--harmonics: only with --periodic (a periodic skill)")


# ---------------------------------------------------------------- plan and plot
def add_run_options(parser: argparse.ArgumentParser) -> None:
    """``plan``'s and ``plot``'s options of a periodic skill."""
    group = parser.add_argument_group(
        "periodic skill (lfdkit learn --periodic): the run; also --duration, --speed"
    )
    group.add_argument(
        "--cycles",
        metavar="N",
        help="cycles at full amplitude between the smooth start and stop (default 1; "
        "--duration S instead gives the whole run's seconds)",
    )
    group.add_argument(
        "--amplitude",
        metavar="A",
        help="size of the cycle about its centre, 1 as learned (default 1)",
    )
    group.add_argument(
        "--frequency",
        metavar="HZ",
        help="cycles per second (default the learned period's; or --period S, or --speed F "
        "for F times the learned speed)",
    )
    group.add_argument("--period", metavar="S", help="seconds per cycle (see --frequency)")
    group.add_argument(
        "--centre",
        type=parse_numbers,
        metavar="X,Y[,Z]",
        help="where the cycle is centred (default the learned centre)",
    )
    group.add_argument(
        "--centre-orientation",
        metavar="QX,QY,QZ,QW",
        help="orientation the tool rocks about (default the learned one)",
    )
    group.add_argument(
        "--ramp",
        metavar="S",
        help="seconds of the smooth start and stop, at rest at the centre at both ends "
        "(default half a cycle; 0 starts and ends on the cycle, moving)",
    )


def refuse_periodic_options(args: argparse.Namespace) -> None:
    """A skill from a start to a goal: the periodic options are refused (exit 2)."""
    for attr, option in PERIODIC_OPTIONS:
        if getattr(args, attr, None) is not None:
            raise UsageError(
                f"{option}: only for a periodic skill (lfdkit learn --periodic); "
                f"{args.skill} is a skill from a start to a goal"
            )


def _refuse_discrete_options(args: argparse.Namespace) -> None:
    for attr, option, default in DISCRETE_OPTIONS:
        if getattr(args, attr, default) != default:
            raise UsageError(
                f"{option}: {args.skill} is a periodic skill (no start, goal or obstacles); "
                "use --centre, --amplitude, --cycles"
            )


def _run_settings(args: argparse.Namespace, skill, duration: float | None, speed: float | None):
    """The keywords of :meth:`PeriodicSkill.plan` from the options, checked (usage errors)."""
    _refuse_discrete_options(args)
    cycles = positive_or_none(args.cycles, "--cycles", "a positive number of cycles")
    if cycles is not None and duration is not None:
        raise UsageError("--cycles: give --cycles or --duration, not both")
    frequency = positive_or_none(args.frequency, "--frequency", "cycles per second (> 0)")
    period = positive_or_none(args.period, "--period", "seconds per cycle (> 0)")
    given = [name for name, v in (("--frequency", frequency), ("--period", period)) if v]
    if speed is not None:
        given.append("--speed")
    if len(given) > 1:
        raise UsageError(f"{given[1]}: give one of --frequency, --period and --speed")
    factor = speed or 1.0
    if frequency is not None:
        factor = frequency * skill.period_
    elif period is not None:
        factor = skill.period_ / period
    amplitude = positive_or_none(args.amplitude, "--amplitude", "a positive size factor")
    ramp = None
    if args.ramp is not None:
        try:
            ramp = parse_decimal(args.ramp)
        except ValueError:
            ramp = -1.0
        if ramp < 0.0:
            raise UsageError(f"--ramp: expected seconds >= 0, got {args.ramp!r}")
    orientation = parse_quaternion(args.centre_orientation, "--centre-orientation")
    if orientation is not None and skill.orientation_ is None:
        raise UsageError("--centre-orientation: the skill learned no orientations")
    return {
        "cycles": cycles,
        "duration": duration,
        "amplitude": 1.0 if amplitude is None else amplitude,
        "frequency": factor,
        "centre": point_arg(args.centre, "--centre", skill.n_dims_),
        "orientation_centre": orientation,
        "ramp": ramp,
    }


def _planned(skill, settings: dict):
    try:
        return skill.plan(**settings)
    except ValueError as exc:  # the library names the argument, the command its option
        message = re.sub(
            r"^(cycles|duration|ramp|amplitude|frequency|centre|orientation_centre)",
            lambda m: "--" + m[1].replace("orientation_centre", "centre-orientation"),
            str(exc),
        )
        raise CommandError(message) from None


def plan(args: argparse.Namespace, skill, duration: float | None, speed: float | None, rate):
    """``lfdkit plan`` of a periodic skill: a timed run of cycles, as CSV."""
    if args.units is not None:
        skill = skill.to_units(args.units)
    settings = _run_settings(args, skill, duration, speed)
    run = _planned(skill, settings)
    summary = _run_summary(skill, settings, run)
    write_timed_run(args, run, summary, rate)


def run(args: argparse.Namespace, skill):
    """``lfdkit execute`` of a periodic skill: the plan its options ask for (a TimedPath)."""
    return _planned(skill, _run_settings(args, skill, None, None))


def no_scene():
    """The empty scene a periodic skill runs in (``execute`` simulates it)."""
    from lfdkit.model.scene import Scene

    return Scene(())


def _run_summary(skill, settings: dict, run) -> str:
    """The plan in one line: cycles, period, amplitude, centre, length and peak speed."""
    import numpy as np

    period = skill.period_ / settings["frequency"]
    centre = skill.centre_ if settings["centre"] is None else settings["centre"]
    cycles = settings["cycles"]
    what = _cycles(cycles) if cycles is not None else f"{run.times[-1]:.4g} s"
    peak = float(np.linalg.norm(run.velocities, axis=1).max())
    rest = ", at rest at both ends" if settings["ramp"] != 0.0 else ""
    return (
        f"planned {what} of {period:.4g} s at amplitude {settings['amplitude']:g} about "
        f"{','.join(f'{v:.4g}' for v in centre)} {skill.units}: {len(run.times)} points, "
        f"lasts {run.times[-1]:.4g} s{rest}, peak speed {peak:.4g} {skill.units}/s"
    )


def _cycles(n: float) -> str:
    return f"{n:g} cycle{'s' * (n != 1)}"


def plot(args: argparse.Namespace, skill):
    """``lfdkit plot`` of a periodic skill: the demonstration, the learned cycle and a run."""
    from lfdkit.app.rhythmic_plot import rhythmic_figure
    from lfdkit.core.rotations import conjugate, log, multiply
    from lfdkit.io import load_demos
    from lfdkit.model.timed_path import TimedPath

    if args.units is not None:
        skill = skill.to_units(args.units)
    settings = _run_settings(args, skill, None, None)
    if settings["cycles"] is None:
        settings["cycles"] = PLOT_CYCLES
    run = _planned(skill, settings)
    demo = times = demo_orientations = None
    if args.demos is not None:
        records = load_demos(args.demos, as_records=True)
        if len(records) != 1:
            raise CommandError(
                f"--demos {args.demos}: {len(records)} demonstrations; give the recording the "
                "periodic skill learned from"
            )
        demo, times, demo_orientations = (
            records[0].points,
            records[0].times,
            records[0].orientations,
        )
        if demo.shape[1] != skill.n_dims_:
            raise CommandError(
                f"--demos {args.demos}: {demo.shape[1]}-D, the skill is {skill.n_dims_}-D"
            )
    turn = None
    if skill.orientation_ is not None:
        about = conjugate(skill.orientation_.centre_)
        turn = TimedPath(run.times, 2.0 * log(multiply(run.orientations, about)))
    period = skill.period_ / settings["frequency"]
    return rhythmic_figure(
        skill.position_,
        demo,
        times,
        run,
        orientation=skill.orientation_,
        demo_orientations=demo_orientations,
        orientation_run=turn,
        units=skill.units,
        title=args.title
        or f"{args.skill.name}: {_cycles(settings['cycles'])} of {period:.3g} s at amplitude "
        f"{settings['amplitude']:g}"
        + (" (demonstration grey)" if demo is not None else ""),
    )
