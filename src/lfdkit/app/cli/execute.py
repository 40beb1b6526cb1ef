"""``lfdkit execute``: a skill on a UR arm (poses, joints, URScript, a MuJoCo check)."""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

from lfdkit.app.cli.common import (
    CommandError,
    LazyChoices,
    add_orientation_options,
    add_skill_file_options,
    arm_keys,
    check_writable,
    elapsed,
    option_named,
    orientation_options,
    parse_fraction,
    skill_and_scene,
    tell,
    working,
)

__all__ = ["add_options", "run_command"]


def run_command(args: argparse.Namespace) -> None:
    simulate = not args.no_sim
    orientations = orientation_options(args)
    with working(args) as progress:
        with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn, numba, MuJoCo)"):
            from lfdkit.execute.arm import ARMS
            from lfdkit.tasks.sweeping.execution import (
                ExecutionError,
                execute_skill,
                execution_outputs,
                write_execution,
            )
        out = _output_folder_checked(
            args, execution_outputs(args.output, simulate=simulate, render=args.render)
        )
        # The robot works in metres: the command line's lengths are metres, the skill converted.
        args.units = "m"
        skill, scene, start, goal = skill_and_scene(args)
        arm = ARMS[args.arm]
        # The program's header comment is ASCII, whatever the skill file is called.
        name = args.skill.name.encode("ascii", "replace").decode("ascii")
        try:
            run = execute_skill(
                skill,
                start,
                goal,
                scene,
                arm=arm,
                speed_fraction=args.speed_fraction,
                simulate=simulate,
                render=args.render,
                yaw=args.yaw,
                **orientations,
                header=f"lfdkit execute {name}: {arm.name} at {args.speed_fraction:g} of its "
                "joint limits",
                progress=progress,
            )
        except ExecutionError as exc:
            raise CommandError(f"{exc}; wrote nothing") from None
        except ValueError as exc:  # the library names the argument, the command its option
            message = option_named(str(exc))
            if message.startswith("yaw:"):
                message = "--" + message
            raise CommandError(message) from None
        with progress.stage(f"write the files in {out}"):
            out.mkdir(parents=True, exist_ok=True)
            written = write_execution(
                out, run, overwrite=args.force, extra={"skill": str(args.skill)}
            )
    summary = run.summary()
    plan, robot = summary["plan"], summary["robot"]
    clear = (
        f", closest obstacle {1e3 * plan['clearance_m']:.1f} mm beyond the brush"
        if plan["clearance_m"] is not None
        else ""
    )
    tell(
        args,
        f"planned a {plan['length_m']:.3f} m sweep around {len(run.scene)} obstacles{clear}; "
        f"{arm.name}: {robot['poses']} poses, {robot['motion_s']:.1f} s at "
        f"{args.speed_fraction:.0%} of its joint limits, tool at most "
        f"{robot['tool_speed_max_m_s']:.2f} m/s",
    )
    if run.result is not None:
        tell(args, f"simulated in MuJoCo: {run.result.summary()}")
        if not run.result.success:
            warnings.warn(f"the simulated sweep failed: {run.result.summary()}", stacklevel=1)
    elif simulate:
        warnings.warn(f"skipped the simulation: {run.skipped}", stacklevel=1)
    tell(args, " ".join(f"{name} {t:.2f} s;" for name, t in run.seconds.items()), level=2)
    tell(args, f"wrote {len(written)} files in {out}/ in {elapsed(args):.1f} s")


def _output_folder_checked(args: argparse.Namespace, planned: list[Path]) -> Path:
    """``--output`` (a folder), checked before the work.

    Not a file, none of the ``planned`` files there without ``--force``, and
    writable where it is (or will be) made.
    """
    out: Path = args.output
    if out.exists() and not out.is_dir():
        raise CommandError(f"--output {out}: exists and is not a directory")
    clash = [p for p in planned if p.exists()]
    if clash and not args.force:
        raise CommandError(f"--output {out}: {clash[0]} exists; pass --force to overwrite it")
    parent = out if out.is_dir() else next(p for p in out.parents if p.is_dir())
    check_writable(parent, "--output", out)
    return out


def add_options(parser: argparse.ArgumentParser) -> None:
    add_skill_file_options(parser)
    add_orientation_options(parser)
    parser.add_argument(
        "--yaw",
        choices=("demonstrated", "tangent"),
        default=None,
        help="the brush's heading: the demonstrated orientation (the default for a skill "
        "learned with orientations) or along the path's tangent (the default otherwise)",
    )
    parser.add_argument(
        "--arm",
        choices=LazyChoices(arm_keys),
        metavar="ARM",
        default="ur5",
        help="the robot arm: ur5 or ur10, a key of lfdkit.execute.arm.ARMS (default %(default)s)",
    )
    parser.add_argument(
        "--speed-fraction",
        type=parse_fraction,
        default=0.2,
        metavar="F",
        help="fraction of the arm's joint speed limits, in (0, 1] (default %(default)s, the "
        "thesis's playback speed)",
    )
    parser.add_argument(
        "--no-sim", action="store_true", help="skip the MuJoCo simulation of the sweep"
    )
    parser.add_argument(
        "--render",
        action="store_true",
        help="also render the end of the simulated sweep as render.png (needs OpenGL: EGL, "
        "OSMesa or a display)",
    )
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        required=True,
        metavar="DIR",
        help="folder for the plan, poses, joints, URScript, summary and pictures "
        "(created if missing)",
    )
