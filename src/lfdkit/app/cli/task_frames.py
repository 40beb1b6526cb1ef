"""Task-frame skills on the command line: ``learn --task-frames``, and ``plan`` of one.

A task-frame skill (:class:`lfdkit.skill.task_frames.TaskFrameSkill`, TP-GMM)
is learned from demonstrations recorded with their task frames' poses (the
``frame_<name>_...`` columns ``lfdkit import --task-frame`` writes) and
planned for new poses of those frames (``--frame NAME=POSE``). Its file says
which kind it is, so ``plan`` takes any skill file and hands this one here;
``plot`` draws the plan among its frames, ``execute`` runs it on an arm;
options of the other kinds are refused on one line (exit 2), not ignored.
"""

from __future__ import annotations

import argparse
import re
import sys

from lfdkit.app.cli.common import (
    CommandError,
    UsageError,
    bounded_int,
    refuse_existing,
    refuse_implausible_metres,
    tell,
    write_timed_run,
)
from lfdkit.app.cli.periodic import DISCRETE_OPTIONS, PERIODIC_OPTIONS
from lfdkit.core.numbers import parse_decimal

__all__ = [
    "add_learn_options",
    "add_run_options",
    "is_task_frame",
    "learn",
    "plan",
    "plot",
    "refuse_frame_options",
    "refuse_learn_options",
    "run",
]

#: Components of a task-frame skill's mixture when --components is not given.
DEFAULT_COMPONENTS = 10

# ``plan`` options of the other kinds of skill: (attribute, option, its default).
_OTHER_OPTIONS = (
    *DISCRETE_OPTIONS,
    *((attr, option, None) for attr, option in PERIODIC_OPTIONS),
)


def is_task_frame(skill: object) -> bool:
    """Whether a skill file read (:func:`~lfdkit.app.cli.common.load_skill_file`) is one."""
    # Not loaded yet: no skill read can be one (other plans never import it).
    module = sys.modules.get("lfdkit.skill.task_frames")
    return module is not None and isinstance(skill, module.TaskFrameSkill)


def _frame_pose(text: str) -> tuple[str, list[float]]:
    """``--frame NAME=POSE``: a frame's name and its pose's numbers (checked by the skill)."""
    name, sep, numbers = text.partition("=")
    if not sep or not name.strip():
        raise argparse.ArgumentTypeError(
            f"expected NAME=X,Y,ANGLE (2-D) or NAME=X,Y,Z,QX,QY,QZ,QW (3-D), got {text!r}"
        )
    try:
        pose = [parse_decimal(part) for part in numbers.split(",")]
    except ValueError as exc:
        raise argparse.ArgumentTypeError(f"{name.strip()}: {exc}") from None
    return name.strip(), pose


# ---------------------------------------------------------------- learn
def add_learn_options(parser: argparse.ArgumentParser) -> None:
    """``learn``'s task-frame options."""
    group = parser.add_argument_group(
        "task-frame skill (--task-frames): a movement learned in the frames of the objects it "
        "acts on (TP-GMM)"
    )
    group.add_argument(
        "--task-frames",
        action="store_true",
        help="learn a task-frame skill from demonstrations with frame_<name>_x, ... columns "
        "(lfdkit import --task-frame writes them); plan it with lfdkit plan SKILL --frame "
        "NAME=POSE for each frame",
    )
    group.add_argument(
        "--components",
        type=bounded_int(1, 1000),
        default=None,
        metavar="K",
        help=f"Gaussian components of its mixture (default {DEFAULT_COMPONENTS})",
    )


def refuse_learn_options(args: argparse.Namespace) -> None:
    """``learn`` without ``--task-frames``: its options are refused, not ignored."""
    if args.components is not None:
        raise UsageError("--components: only with --task-frames (a task-frame skill)")


def learn(args: argparse.Namespace) -> None:
    """``lfdkit learn --task-frames``: demonstrations with their frames to a skill file."""
    if args.periodic:
        raise UsageError("--task-frames: give --periodic or --task-frames, not both")
    if args.scenes is not None:
        raise UsageError("--scenes: a task-frame skill has no obstacles; leave --scenes out")
    refuse_existing(args.output, args.force)
    from lfdkit.io.demos import load_demo_files
    from lfdkit.skill.task_frames import TaskFrameSkill

    records = load_demo_files(args.demos)
    if not all(record.frames for record in records):
        raise CommandError(
            f"{args.demos[0]}: the demonstrations carry no task frames; a task-frame skill "
            "learns from frame_<name>_x, ... columns (lfdkit import --task-frame writes them)"
        )
    if args.units is None:  # implausible in metres and no unit given: refused, as learn does
        refuse_implausible_metres(
            args.demos[0], [r.points for r in records], [r.times for r in records]
        )
    components = DEFAULT_COMPONENTS if args.components is None else args.components
    skill = TaskFrameSkill(n_components=components, units=args.units or "m")
    try:
        skill.fit(records)
    except ValueError as exc:
        raise CommandError(f"{args.demos[0]}: {exc}") from None
    skill.save(args.output, overwrite=args.force)
    tell(args, f"learned a task-frame skill: {skill.summary()}; wrote {args.output}")


# ---------------------------------------------------------------- plan
def add_run_options(parser: argparse.ArgumentParser) -> None:
    """``plan``'s options of a task-frame skill."""
    group = parser.add_argument_group(
        "task-frame skill (lfdkit learn --task-frames): the frames' new poses; also --duration, "
        "--speed"
    )
    group.add_argument(
        "--frame",
        type=_frame_pose,
        action="append",
        metavar="NAME=POSE",
        help="a task frame's new pose, X,Y,ANGLE in 2-D (rad) or X,Y,Z,QX,QY,QZ,QW in 3-D; "
        "one for each frame the skill learned",
    )
    group.add_argument(
        "--points",
        type=bounded_int(2, 100_000),
        default=None,
        metavar="N",
        help="points of the plan (default the skill's, 100)",
    )


def refuse_frame_options(args: argparse.Namespace) -> None:
    """A skill of another kind: the task-frame options are refused (exit 2)."""
    for attr, option in (("frame", "--frame"), ("points", "--points")):
        if getattr(args, attr, None) is not None:
            raise UsageError(
                f"{option}: only for a task-frame skill (lfdkit learn --task-frames); "
                f"{args.skill} is another kind of skill"
            )


def _planned(args: argparse.Namespace, skill, duration: float | None, speed: float | None):
    """The plan ``--frame`` asks for (a ``TimedPath``); usage errors name the options."""
    for attr, option, default in _OTHER_OPTIONS:
        if getattr(args, attr, default) != default:
            raise UsageError(
                f"{option}: {args.skill} is a task-frame skill (planned for its frames' "
                "poses: --frame NAME=POSE)"
            )
    given = dict(args.frame or [])
    if len(given) != len(args.frame or []):
        raise UsageError("--frame: a frame given twice; give each once")
    if not given:
        raise UsageError(
            f"--frame: give each frame's new pose: {', '.join(skill.frame_names_)} "
            "(NAME=X,Y,ANGLE or NAME=X,Y,Z,QX,QY,QZ,QW)"
        )
    if speed is not None:
        if skill.duration_ is None:
            raise UsageError("--speed: the demonstrations had no times; give --duration S instead")
        duration = skill.duration_ / speed
    try:
        return skill.plan(given, n_points=args.points, duration=duration)
    except (TypeError, ValueError) as exc:  # the library names the argument: here --frame
        message = re.sub(r"^frames\['([^']*)'\]", r"--frame \1", str(exc))
        message = message.replace("frames:", "--frame:")
        message = message.replace("duration:", "--duration:").replace("n_points:", "--points:")
        raise CommandError(message) from None


def _in_units(args: argparse.Namespace, skill):
    """The skill in ``--units``: its plan, and the poses' origins given, in that unit."""
    return skill if args.units is None else skill.to_units(args.units)


def plan(
    args: argparse.Namespace,
    skill,
    duration: float | None,
    speed: float | None,
    rate: float | None,
) -> None:
    """``lfdkit plan`` of a task-frame skill: the movement for the frames' new poses, as CSV."""
    import numpy as np

    skill = _in_units(args, skill)
    timed = _planned(args, skill, duration, speed)
    peak = float(np.linalg.norm(timed.velocities, axis=1).max())
    summary = (
        f"planned {len(timed.times)} points in the task frames "
        f"{', '.join(skill.frame_names_)}; lasts {timed.times[-1]:.4g} s, peak speed "
        f"{peak:.4g} {skill.units}/s"
    )
    write_timed_run(args, timed, summary, rate)


def run(args: argparse.Namespace, skill):
    """``lfdkit execute`` of a task-frame skill: the plan ``--frame`` asks for (a ``TimedPath``)."""
    return _planned(args, skill, None, None)


def plot(args: argparse.Namespace, skill):
    """``lfdkit plot`` of a task-frame skill: the plan among its frames (and ``--demos``)."""
    from lfdkit.app.task_frame_plot import task_frame_figure
    from lfdkit.imitate import TaskFrame

    skill = _in_units(args, skill)
    timed = _planned(args, skill, None, None)
    given = dict(args.frame)
    frames = {name: TaskFrame.from_vector(given[name]) for name in skill.frame_names_}
    demos = []
    if args.demos is not None:
        from lfdkit.io import load_demos

        if args.units is not None:
            raise UsageError("--demos: drawn in the skill's own unit; leave --units out")
        for record in load_demos(args.demos, as_records=True):
            if record.points.shape[1] != skill.n_dims_ or not record.frames:
                raise CommandError(
                    f"--demos {args.demos}: expected {skill.n_dims_}-D demonstrations with "
                    "their task frames (frame_<name>_... columns)"
                )
            own = {name: TaskFrame.from_vector(pose) for name, pose in record.frames.items()}
            demos.append((record.points, own))
    where = ", ".join(
        f"{name} at ({', '.join(f'{v:.3g}' for v in given[name][: skill.n_dims_])})"
        for name in skill.frame_names_
    )
    return task_frame_figure(
        timed.positions,
        frames,
        demos,
        orientations=timed.orientations,
        units=skill.units,
        title=args.title or f"{args.skill.name}: planned for {where}",
    )
