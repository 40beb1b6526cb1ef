"""``lfdkit execute``: a skill on an arm (poses, joints, timing, URScript, a MuJoCo check).

Two chains: a 2-D skill on a UR arm by default runs the sweeping task
(:mod:`lfdkit.tasks.sweeping.execution`: brush, dustpan, MuJoCo); any other
skill or arm (``--task path``, a 3-D skill, ``--arm robot.urdf``) runs the
generic chain :func:`lfdkit.execute.pipeline.execute_plan`, which keeps the
skill's learned timing where the arm's limits allow it.
"""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

from lfdkit.app.cli import periodic, task_frames
from lfdkit.app.cli.common import (
    CommandError,
    add_orientation_options,
    add_skill_file_options,
    add_task_description_options,
    add_unknown_class_option,
    check_writable,
    elapsed,
    load_skill_file,
    option_named,
    orientation_options,
    parse_fraction,
    skill_and_scene,
    task_description,
    tell,
    unknown_class_options,
    working,
)
from lfdkit.app.cli.via import add_via_option, via_points

__all__ = ["add_options", "run_command"]


def run_command(args: argparse.Namespace) -> None:
    if _task_of(args) == "path":
        _run_path(args)
        return
    periodic.refuse_periodic_options(args)
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
        if args.rate is not None:
            raise CommandError("--rate: the sweeping task streams at 125 Hz; use --task path")
        via = via_points(args.via, skill.n_dims_, skill.timing_.duration)
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
                **unknown_class_options(args),
                via=via,
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
        f"planned a {plan['length_m']:.3f} m sweep around {len(run.scene)} "
        f"obstacle{'s' * (len(run.scene) != 1)}{clear}; "
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


def _task_of(args: argparse.Namespace) -> str:
    """``--task``, or the default: the sweep for a 2-D skill on a named UR arm, else the path."""
    if args.task is not None:
        return args.task
    from lfdkit.execute.arm import ARMS

    if args.arm not in ARMS:  # a URDF file (or a mistake, which _arm_from names)
        return "path"
    skill = load_skill_file(args.skill)
    # A rhythm, and a movement planned in its task frames, run as a path, whatever its dimension.
    if periodic.is_periodic(skill) or task_frames.is_task_frame(skill):
        return "path"
    return "sweep" if skill.n_dims_ == 2 else "path"


def _arm_from(args: argparse.Namespace):
    """``--arm``: a name of lfdkit.execute.arm.ARMS, or a URDF file (``--tip-link``)."""
    from lfdkit.execute.arm import ARMS
    from lfdkit.execute.urdf import UrdfArm

    if args.arm in ARMS:
        return ARMS[args.arm]
    path = Path(args.arm)
    if not path.is_file():
        raise CommandError(
            f"--arm {args.arm}: neither an arm name ({', '.join(ARMS)}) nor a URDF file"
        )
    try:
        return UrdfArm(path, tip_link=args.tip_link)
    except ValueError as exc:
        raise CommandError(f"--arm {args.arm}: {exc}") from None


def _run_path(args: argparse.Namespace) -> None:
    """Any skill on any arm, its learned timing kept (``execute_plan``)."""
    with working(args) as progress:
        with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn)"):
            from lfdkit.execute.pipeline import (
                DEFAULT_RATE,
                ExecutionError,
                execute_plan,
                robot_outputs,
                write_robot_execution,
            )
        arm = _arm_from(args)
        ur = getattr(arm, "ur_type", False)
        out = _output_folder_checked(args, robot_outputs(args.output, program=ur))
        args.units = "m"
        loaded = load_skill_file(args.skill)
        framed = task_frames.is_task_frame(loaded)
        if not framed:
            task_frames.refuse_frame_options(args)
        rhythm = periodic.is_periodic(loaded) or framed
        if rhythm:  # periodic or task frames: no start, goal or obstacles
            skill, scene, via = loaded.to_units("m"), periodic.no_scene(), None
        else:
            periodic.refuse_periodic_options(args)
            skill, scene, start, goal = skill_and_scene(args, loaded)
            # The plan lasts the skill's learned duration: a time in --via is within it.
            via = via_points(args.via, skill.n_dims_, skill.timing_.duration)
        task = task_description(args)
        try:
            if rhythm:
                plan = task_frames.run(args, skill) if framed else periodic.run(args, skill)
            with progress.stage(f"plan around {len(scene)} obstacle{'s' * (len(scene) != 1)}"):
                plan = (
                    plan
                    if rhythm
                    else skill.plan(
                        start,
                        goal,
                        scene,
                        **orientation_options(args),
                        **unknown_class_options(args),
                        via=via,
                    )
                )
            name = args.skill.name.encode("ascii", "replace").decode("ascii")
            rate = DEFAULT_RATE if args.rate is None else args.rate
            with progress.stage(f"robot: poses, inverse kinematics, timing ({arm.name})"):
                run = execute_plan(
                    plan,
                    arm,
                    task,
                    speed_fraction=args.speed_fraction,
                    rate=rate,
                    header=f"lfdkit execute {name}: {arm.name}, at most {args.speed_fraction:g} "
                    "of its joint limits",
                )
        except ExecutionError as exc:
            raise CommandError(f"{exc}; wrote nothing") from None
        except ValueError as exc:
            raise CommandError(option_named(str(exc))) from None
        extra = {"skill": str(args.skill)}
        check = None
        if not args.no_sim:
            with progress.stage(f"simulate in MuJoCo ({arm.name})"):
                from lfdkit.execute.simulation import simulate_execution

                try:
                    check = simulate_execution(run, scene)
                except ImportError as exc:
                    warnings.warn(f"skipped the simulation: {exc}", stacklevel=1)
            if check is not None:
                extra["simulation"] = {
                    "tracking_error_m": check.tracking_error,
                    "touched": list(check.touched),
                }
        with progress.stage(f"write the files in {out}"):
            out.mkdir(parents=True, exist_ok=True)
            written = write_robot_execution(out, run, overwrite=args.force, extra=extra)
    robot = run.summary()["robot"]
    tell(
        args,
        f"{arm.name}: {robot['poses']} poses, {robot['motion_s']:.2f} s "
        f"({robot['duration_ratio']:.3f} x the plan's {run.trajectory.planned_duration:.2f} s), "
        f"{robot['samples']} samples at {rate:g} Hz, tool at most "
        f"{robot['tool_speed_max_m_s']:.2f} m/s",
    )
    if check is not None:
        touched = ", ".join(str(i) for i in check.touched) or "none"
        tell(
            args,
            f"simulated in MuJoCo: tracking error {1e3 * check.tracking_error:.2f} mm, "
            f"obstacles touched: {touched}",
        )
        if check.touched:
            warnings.warn(f"the simulated arm touched obstacle(s) {touched}", stacklevel=1)
    if run.trajectory.slowdowns:
        warnings.warn(run.timing_note, stacklevel=1)
    else:
        tell(args, run.timing_note, level=2)
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
    add_unknown_class_option(parser, "m")
    add_via_option(parser)
    periodic.add_run_options(parser)
    task_frames.add_run_options(parser)
    parser.add_argument(
        "--yaw",
        choices=("demonstrated", "tangent"),
        default=None,
        help="the brush's heading: the demonstrated orientation (the default for a skill "
        "learned with orientations) or along the path's tangent (the default otherwise)",
    )
    parser.add_argument(
        "--arm",
        metavar="ARM|URDF",
        default="ur5",
        help="the robot arm: ur5 or ur10 (a key of lfdkit.execute.arm.ARMS), or a URDF file "
        "(default %(default)s)",
    )
    parser.add_argument(
        "--tip-link",
        metavar="LINK",
        default=None,
        help="with a URDF arm: the link the tool is on (default: the chain's one leaf)",
    )
    parser.add_argument(
        "--task",
        choices=("sweep", "path"),
        default=None,
        help="sweep: the sweeping task (2-D skill, UR arm, brush, dustpan, MuJoCo); path: any "
        "skill on any arm with its learned timing (default: sweep for a 2-D skill on ur5/ur10)",
    )
    parser.add_argument(
        "--rate",
        type=float,
        default=None,
        metavar="HZ",
        help="path task: rate of the fixed-rate trajectory and servoj stream (default 125; "
        "500 for an e-Series)",
    )
    add_task_description_options(parser)
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
