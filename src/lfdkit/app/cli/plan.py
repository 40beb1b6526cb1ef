"""``lfdkit plan``: a path for a new start, goal and scene."""

from __future__ import annotations

import argparse
import math
import time
import warnings
from pathlib import Path

from lfdkit.app.cli import periodic, task_frames
from lfdkit.app.cli.common import (
    CommandError,
    UsageError,
    add_orientation_options,
    add_planner_options,
    add_skill_file_options,
    add_units_option,
    add_unknown_class_option,
    load_skill_file,
    option_named,
    orientation_options,
    positive_or_none,
    refuse_existing,
    skill_and_scene,
    unknown_class_options,
    working,
    write_timed_run,
)
from lfdkit.app.cli.via import add_via_option, via_points
from lfdkit.core.numbers import parse_decimal
from lfdkit.core.progress import Progress
from lfdkit.core.units import UnitsWarning

__all__ = ["add_options", "run_command"]


def _decimal(text: str) -> float:
    """An argparse type: a decimal number, strictly (no ``1_0``, nan or inf)."""
    try:
        return parse_decimal(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _goal_approach(text: str) -> float | str | None:
    """``--goal-approach``: a positive length, ``auto`` or ``none``."""
    word = text.strip().lower()
    if word in ("auto", "none"):
        return None if word == "none" else "auto"
    try:
        value = parse_decimal(text, finite=False)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected a length, 'auto' or 'none', got {text!r}"
        ) from None
    if not math.isfinite(value) or value <= 0.0:
        raise argparse.ArgumentTypeError(f"expected a positive length, got {text!r}")
    return value


def run_command(args: argparse.Namespace) -> None:
    with working(args) as progress:
        _plan_with(args, progress)


def _plan_with(args: argparse.Namespace, progress: Progress) -> None:
    # Checked here, not by argparse, so that a bad value is one line (exit 2).
    duration = positive_or_none(args.duration, "--duration", "a positive number of seconds")
    speed = positive_or_none(args.speed, "--speed", "a positive speed factor")
    if duration is not None and speed is not None:
        raise UsageError("--speed: give --duration or --speed, not both")
    rate = positive_or_none(args.rate, "--rate", "a positive rate in Hz (e.g. 125)")
    orientations = orientation_options(args)
    if args.output is not None:
        refuse_existing(args.output, args.force)
    loaded = load_skill_file(args.skill)
    if task_frames.is_task_frame(loaded):
        task_frames.plan(args, loaded, duration, speed, rate)
        return
    task_frames.refuse_frame_options(args)
    if periodic.is_periodic(loaded):
        periodic.plan(args, loaded, duration, speed, rate)
        return
    periodic.refuse_periodic_options(args)
    skill, scene, start, goal = skill_and_scene(args, loaded)
    lasts = duration if duration is not None else skill.timing_.duration / (speed or 1.0)
    via = via_points(args.via, skill.n_dims_, lasts)
    started = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", UserWarning)
        try:
            timed = skill.plan(
                start,
                goal,
                scene,
                duration=duration,
                speed=speed,
                **orientations,
                planner=args.planner,
                horizon=args.horizon,
                goal_approach=args.goal_approach,
                clearance=args.clearance,
                **unknown_class_options(args),
                progress=progress,
                via=via,
            )
        except ValueError as exc:  # the library names the argument, the command its option
            raise CommandError(option_named(str(exc))) from None
    for warning in caught:  # a point in another unit: said with the option that converts it
        message = warning.message
        if isinstance(message, UnitsWarning):
            message = UnitsWarning(
                f"{message.detail}; in {message.likely} it would lie within it: "
                f"if that is its unit, pass --units {message.likely}"
            )
        warnings.showwarning(message, warning.category, warning.filename, warning.lineno)
    plan = timed.details
    units = skill.units
    clear = (
        f"; closest obstacle {plan.clearance.min():.4g} {units} beyond radius + clearance"
        + (" (+ margin, unlearned classes)" if args.unknown_class is not None else "")
        if len(scene)
        else ""
    )
    summary = (
        f"planned {len(timed)} points around {len(scene)} obstacle{'s' * (len(scene) != 1)} in "
        f"{1e3 * (time.perf_counter() - started):.0f} ms; ends {plan.goal_error:.3g} {units} "
        f"from the goal{clear}; lasts {timed.duration:.4g} s, peak speed "
        f"{timed.speeds.max():.4g} {units}/s{_assumed(skill, duration, speed)}"
        f"{_via_summary(timed.points, via, units)}"
    )
    write_timed_run(args, timed, summary, rate)


def _via_summary(points, via, units: str) -> str:
    """How closely the plan passes its via-points (nothing without)."""
    if via is None:
        return ""
    import numpy as np

    from lfdkit.core.geometry import polyline_distances

    miss = polyline_distances(np.array([entry[1] for entry in via], dtype=float), points)
    return f"; passes {len(via)} via-point{'s' * (len(via) != 1)} within {miss.max():.3g} {units}"


def _assumed(skill, duration: float | None, speed: float | None) -> str:
    """Says so when the plan's duration is a guess: untimed demonstrations, nothing given."""
    if duration is not None or skill.timing_.source not in ("minimum_jerk", "uniform"):
        return ""
    if skill.duration != "auto":
        return ""
    return (
        " (the demonstrations had no times: their duration is assumed from a hand's pace; "
        "--duration S or --speed F sets it)"
    )


def add_options(parser: argparse.ArgumentParser) -> None:
    add_skill_file_options(parser)
    add_orientation_options(parser)
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        metavar="PATH.csv",
        help="CSV file to write (default: standard output)",
    )
    add_planner_options(parser, defaults=False)
    parser.add_argument(
        "--goal-approach",
        type=_goal_approach,
        default="auto",
        metavar="LENGTH|auto|none",
        help="return onto the nominal over this last stretch so the plan ends at the goal "
        "(path units; default auto: the last tenth of the path; none: the thesis's reward, "
        "no goal term, the plan may end beside the goal)",
    )
    parser.add_argument(
        "--clearance",
        type=_decimal,
        default=0.0,
        metavar="LENGTH",
        help="tool clearance added to every obstacle's radius; the plan keeps out of radius "
        "plus clearance or the command fails (path units; default 0)",
    )
    add_unknown_class_option(parser, "path units")
    add_via_option(parser)
    periodic.add_run_options(parser)
    task_frames.add_run_options(parser)
    parser.add_argument(
        "--duration",
        metavar="S",
        help="seconds the plan lasts (default: the skill's, learned from the demonstrations' "
        "times, else its duration parameter)",
    )
    parser.add_argument(
        "--speed",
        metavar="FACTOR",
        help="run the skill's timing FACTOR times as fast (0.5: twice as long; not with "
        "--duration)",
    )
    parser.add_argument(
        "--rate",
        metavar="HZ",
        help="write the plan sampled at this fixed rate (rows k/HZ seconds apart, e.g. 125 "
        "for a UR controller; positions and velocities from the cubic Hermite curve through "
        "the plan; default: the planned points at their own times)",
    )
    parser.add_argument(
        "--velocities",
        action="store_true",
        help="add the velocity columns vx,vy[,vz] (path units per second)",
    )
    add_units_option(
        parser,
        None,
        "unit of the start, goal, obstacles, scene file, lengths and the plan written "
        "(default: the skill's; the skill is converted)",
    )
