"""``lfdkit plot``: a skill's reward, demonstrations and plan."""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

from lfdkit.app.cli import periodic, task_frames
from lfdkit.app.cli.common import (
    add_skill_file_options,
    add_units_option,
    bounded_int,
    load_skill_file,
    refuse_existing,
    skill_and_scene,
    tell,
    working,
)
from lfdkit.app.cli.via import add_via_option, via_points
from lfdkit.core.progress import Progress

__all__ = ["add_options", "run_command"]


def run_command(args: argparse.Namespace) -> None:
    with working(args) as progress:
        _plot_with(args, progress)


def _warn_misplaced_demos(args: argparse.Namespace, skill, demos) -> None:
    """Warn when ``--demos`` lie far from the skill and another unit would bring them onto it."""
    if not demos or demos[0].shape[1] != skill.n_dims_:
        return
    import numpy as np

    from lfdkit.core.units import misplaced_units

    centre = np.mean([d.mean(axis=0) for d in demos], axis=0)
    low, high = skill.path_.min(axis=0).tolist(), skill.path_.max(axis=0).tolist()
    likely = misplaced_units(centre.tolist(), low, high, skill.units)
    if likely is not None:
        warnings.warn(
            f"--demos {args.demos}: they lie far from the skill's path (in {skill.units}); in "
            f"{likely} they would lie on it: if that is their unit, pass --units {likely}",
            UserWarning,
            stacklevel=2,
        )


def _plot_with(args: argparse.Namespace, progress: Progress) -> None:
    refuse_existing(args.output, args.force)
    loaded = load_skill_file(args.skill)
    if task_frames.is_task_frame(loaded):
        _save(args, task_frames.plot(args, loaded))
        return
    task_frames.refuse_frame_options(args)
    if periodic.is_periodic(loaded):
        _save(args, periodic.plot(args, loaded))
        return
    from lfdkit.app import plot
    from lfdkit.io import load_demos

    periodic.refuse_periodic_options(args)
    skill, scene, start, goal = skill_and_scene(args, loaded)
    demos = load_demos(args.demos) if args.demos is not None else []
    _warn_misplaced_demos(args, skill, demos)
    via = via_points(args.via, skill.n_dims_, skill.timing_.duration)
    nominal = skill.nominal(start, goal)
    plans, timed = {}, None
    if len(scene) or start is not None or goal is not None or via is not None:
        timed = skill.plan(start, goal, scene, via=via, progress=progress)
        plans["plan"] = timed.points
    if via is not None:
        from lfdkit.app.via_plot import via_figure

        fig = via_figure(
            skill.via_path(None, start, goal),
            skill.via_path(via, start, goal),
            via,
            plan=plans["plan"],
            plan_orientations=timed.orientations,
            demos=demos,
            scene=scene,
            units=skill.units,
            title=args.title or f"{args.skill.name}: via-points",
        )
    elif skill.reward_ is not None:
        fig = plot.emulation_figure(
            skill.reward_,
            nominal,
            scene,
            demos=demos,
            plans=plans,
            units=skill.units,
            title=args.title or f"{args.skill.name}: reward, nominal and plan",
        )
    else:
        rollout = skill.dmp_.rollout(start, goal, n_steps=200)
        fig = plot.retargeting_figure(
            demos,
            skill.path_,
            skill.dmp_.times_,
            [(rollout.times, rollout.positions)],
            units=skill.units,
            title=args.title or f"{args.skill.name}: path and DMP",
        )
    _save(args, fig)


def _save(args: argparse.Namespace, fig) -> None:
    from lfdkit.io import atomic_write

    atomic_write(
        args.output,
        lambda f: fig.savefig(f, format="png", dpi=args.dpi),
        binary=True,
        overwrite=args.force,
    )
    tell(args, f"wrote {args.output}")


def add_options(parser: argparse.ArgumentParser) -> None:
    add_skill_file_options(parser)
    parser.add_argument("--demos", type=Path, metavar="FILE", help="demonstrations to draw too")
    add_via_option(parser)
    periodic.add_run_options(parser)
    task_frames.add_run_options(parser)
    parser.add_argument("--title", default="", help="figure title")
    parser.add_argument(
        "--dpi",
        type=bounded_int(10, 1000),
        default=110,
        help="resolution, 10 to 1000 (default 110)",
    )
    parser.add_argument(
        "-o", "--output", type=Path, required=True, metavar="FIGURE.png", help="PNG file to write"
    )
    add_units_option(
        parser,
        None,
        "unit of the start, goal, obstacles, scene and demonstrations files and of the "
        "figure (default: the skill's; the skill is converted)",
    )
