"""``lfdkit import``: demonstrations from ROS 1/2 bags and MCAP recordings."""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # annotations only: the CLI's start-up imports no NumPy
    import numpy as np

from lfdkit.app.cli.common import (
    CommandError,
    LazyChoices,
    UsageError,
    arm_keys,
    positive_or_none,
    refuse_existing,
    tell,
)

__all__ = ["add_options", "run_command"]


def _frame_pair(text: str) -> tuple[str, str]:
    parent, sep, child = text.partition(":")
    if not sep or not parent.strip() or not child.strip():
        raise argparse.ArgumentTypeError(f"expected PARENT:CHILD frames, got {text!r}")
    return parent.strip(), child.strip()


def _task_frame(text: str) -> tuple[str, str, str]:
    """``PARENT:CHILD[=NAME]``: a task frame's tf pair and its name in the file (CHILD)."""
    pair, _, name = text.partition("=")
    parent, child = _frame_pair(pair)
    name = name.strip() or child.lstrip("/")
    from lfdkit.io.demos import is_frame_name  # the files' rule (NumPy: only with --task-frame)

    if not is_frame_name(name):
        raise argparse.ArgumentTypeError(
            f"task frame name {name!r}: letters, digits, '_' and '-' only (it names the "
            f"columns frame_<name>_x, ...); rename it with {pair}=NAME"
        )
    return parent, child, name


def _frame_poses(
    path: Path, args: argparse.Namespace, rec: Any, segments: list[tuple[int, int]]
) -> list[dict[str, np.ndarray]]:
    """Each segment's task frames (``--task-frame``), posed where the segment starts."""
    import numpy as np

    from lfdkit.core.rotations import heading
    from lfdkit.io.recordings import read_frame_poses

    starts = [rec.start_ns + round(float(rec.times[a]) * 1e9) for a, _ in segments]
    out: list[dict[str, np.ndarray]] = [{} for _ in segments]
    for parent, child, name in args.task_frame:
        if args.frame is not None and parent.lstrip("/") != args.frame[0].lstrip("/"):
            raise UsageError(
                f"--task-frame {parent}:{child}: the tool's poses are in {args.frame[0]!r} "
                f"(--frame); give the task frame in it too ({args.frame[0]}:{child})"
            )
        positions, turns = read_frame_poses(path, (parent, child), starts)
        yaws = heading(turns) if args.planar else None  # the object's turn about z
        for k, (poses, p, q) in enumerate(zip(out, positions, turns, strict=True)):
            if yaws is None:
                poses[name] = np.concatenate([p, q])
            elif np.isnan(yaws[k]):
                raise UsageError(
                    f"--task-frame {parent}:{child}: where demonstration {k + 1} of "
                    f"{path.name} starts, its x axis points straight up or down, so it has no "
                    "turn about z for --planar; import without --planar (3-D poses)"
                )
            else:
                poses[name] = np.array([p[0], p[1], yaws[k]])
    return out


def run_command(args: argparse.Namespace) -> None:
    speed = positive_or_none(args.pause_speed, "--pause-speed", "a positive speed (units/s)")
    pause = positive_or_none(args.pause_time, "--pause-time", "a positive number of seconds")
    if args.topic is None or args.list_topics:
        _list_topics(args)
        return
    if args.output is None:
        raise UsageError("-o/--output: name the demonstrations file to write (DEMOS.csv)")
    refuse_existing(args.output, args.force)
    from lfdkit.io import save_demos
    from lfdkit.io.recordings import JOINT_STATE, list_topics, read_poses
    from lfdkit.io.segmentation import segment_recording
    from lfdkit.model.demos import Demo

    demos: list[Demo] = []
    total_pauses = total_returns = 0
    for path in args.recordings:
        topics = list_topics(path)
        msgtype = next((t.msgtype for t in topics if t.name == args.topic), None)
        if msgtype == JOINT_STATE:
            if args.frame is not None:
                raise UsageError(f"--frame applies to tf topics; {args.topic} holds {msgtype}")
            from lfdkit.execute.arm import ARMS
            from lfdkit.execute.recordings import tool_poses_from_joint_states

            rec = tool_poses_from_joint_states(path, args.topic, arm=ARMS[args.arm])
        else:
            rec = read_poses(path, args.topic, frame=args.frame)
        for note in rec.notes:
            tell(args, f"{path}: {note}")
        positions = rec.positions[:, :2] if args.planar else rec.positions
        try:
            seg = segment_recording(
                rec.times,
                positions,
                speed=speed,
                pause=pause,
                split=args.split,
                trim=not args.no_trim,
                returns="drop" if args.drop_returns else "keep",
            )
        except ValueError as exc:
            if "never move" not in str(exc):
                raise
            top = str(exc).split("top speed ", 1)[1].split(")")[0]
            raise CommandError(
                f"{path}: the tool never moves faster than --pause-speed {speed:g} units/s "
                f"(top speed {top}): nothing to import; lower --pause-speed"
            ) from None
        start = time.strftime("%Y-%m-%d %H:%M:%S", time.gmtime(rec.start_ns // 10**9))
        tell(
            args,
            f"{seg.table(str(path))}\n  {rec.msgtype} on {rec.topic}"
            + (f" ({rec.frame[0]} -> {rec.frame[1]})" if rec.frame else "")
            + f", times from the {rec.stamps} stamps, t = 0 at {start} UTC "
            f"+ {rec.start_ns % 10**9} ns",
            level=2,
        )
        total_pauses += len(seg.pauses)
        total_returns += len(seg.returns)
        frames = _frame_poses(path, args, rec, seg.segments) if args.task_frame else None
        for k, (a, b) in enumerate(seg.segments):
            demos.append(
                Demo(
                    positions[a:b],
                    rec.times[a:b],
                    rec.orientations[a:b],
                    frames=None if frames is None else frames[k],
                )
            )
    save_demos(args.output, demos, overwrite=args.force)
    n = sum(len(demo.points) for demo in demos)
    duration = sum(float(demo.times[-1] - demo.times[0]) for demo in demos)
    tell(
        args,
        f"imported {_count(len(demos), 'demonstration')} ({n} samples, {duration:.2f} s"
        + (f", split at {_count(total_pauses, 'pause')}" if args.split else "")
        + (f", {_count(total_returns, 'move')} back to the start left out" if total_returns else "")
        + f") from {len(args.recordings)} recording{'s' * (len(args.recordings) > 1)}; "
        f"wrote {args.output}",
    )


def _count(n: int, noun: str) -> str:
    """``1 pause``, ``2 pauses``."""
    return f"{n} {noun}{'s' * (n != 1)}"


def _list_topics(args: argparse.Namespace) -> None:
    """Without --topic (or with --list-topics): each recording's topics on standard output."""
    from lfdkit.io.recordings import list_topics

    for path in args.recordings:
        topics = list_topics(path)
        print(f"{path}:")
        for topic in topics:
            print(f"  {topic}")
        if not topics:
            print("  no topics (the recording is empty)")
    tell(args, "import one with --topic T -o DEMOS.csv")


def add_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "recordings",
        type=Path,
        nargs="+",
        metavar="RECORDING",
        help="a ROS 1 .bag, a ROS 2 bag folder, or an .mcap/.db3 file (one demonstration "
        "each, or several with --split)",
    )
    parser.add_argument(
        "--topic",
        metavar="T",
        help="the topic: PoseStamped, PoseWithCovarianceStamped, TransformStamped, Odometry, "
        "JointState (tool poses by the arm's kinematics) or /tf with --frame; without it the "
        "topics present are listed (exit 0, nothing written)",
    )
    parser.add_argument(
        "--list-topics",
        action="store_true",
        help="list each recording's topics (name, type, messages) and write nothing",
    )
    parser.add_argument(
        "--frame",
        type=_frame_pair,
        metavar="PARENT:CHILD",
        help="for /tf: the child's pose in the parent, chained with /tf_static",
    )
    parser.add_argument(
        "--arm",
        choices=LazyChoices(arm_keys),
        metavar="ARM",
        default="ur5",
        help="for JointState: the arm (ur5 or ur10, default %(default)s)",
    )
    parser.add_argument(
        "--split",
        action="store_true",
        help="split each recording into demonstrations at pauses (see --pause-speed, --pause-time)",
    )
    parser.add_argument(
        "--pause-speed",
        default="0.01",
        metavar="V",
        help="at rest below this speed, recording units/s (default %(default)s: 1 cm/s)",
    )
    parser.add_argument(
        "--pause-time",
        default="0.5",
        metavar="S",
        help="shortest pause that splits, seconds (default %(default)s)",
    )
    parser.add_argument(
        "--drop-returns",
        action="store_true",
        help="with --split: leave out the pieces heading against the first one (moving back "
        "to the start between demonstrations); -v lists them",
    )
    parser.add_argument(
        "--no-trim", action="store_true", help="keep the rest at both ends of each recording"
    )
    parser.add_argument(
        "--planar",
        action="store_true",
        help="write x, y only (a task on a table), not z; task frames as x, y and their turn "
        "about z",
    )
    parser.add_argument(
        "--task-frame",
        type=_task_frame,
        action="append",
        metavar="PARENT:CHILD[=NAME]",
        help="an object's pose from /tf and /tf_static, where each demonstration starts, as "
        "columns frame_NAME_x, ... (NAME: CHILD by default; PARENT: the frame the tool's "
        "poses are in); repeat for several; for TP-GMM (lfdkit.imitate.TPGMM)",
    )
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        metavar="DEMOS.csv",
        help="demonstrations file to write: demo, t, x, y[, z], qx, qy, qz, qw (needed with "
        "--topic)",
    )
