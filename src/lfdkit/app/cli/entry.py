"""The ``lfdkit`` entry point: the parser assembled from the command modules, ``main``,
and the plumbing every command runs in (signals, warnings as lines, exit codes)."""

from __future__ import annotations

import argparse
import contextlib
import os
import re
import signal
import sys
import time
import traceback
import warnings
from collections.abc import Iterator, Sequence
from contextlib import contextmanager

from lfdkit import __version__
from lfdkit.app.cli import (
    batch,
    bench,
    compare,
    datasets,
    demo,
    execute,
    import_,
    learn,
    plan,
    plot,
    teach,
)
from lfdkit.app.cli.common import (
    CommandError,
    UsageError,
    add_force_option,
    add_loudness_options,
    tell,
)

__all__ = ["main"]


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="lfdkit",
        description="Robot learning from demonstration: mimic, imitate, emulate, execute.",
        epilog="Run 'lfdkit COMMAND --help' for a command's options.",
    )
    parser.add_argument("--version", action="version", version=f"lfdkit {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    # Each command: its handler, its options, whether it writes files (-f/--force),
    # the line of `lfdkit --help` and the description of `lfdkit COMMAND --help`.
    commands = {
        "demo": (
            demo.run_command,
            demo.add_options,
            True,
            "the whole workflow on the built-in sweeping example, with a report",
            "Learn the sweeping skill from the shipped demonstrations (clean sweeps, sweeps "
            "around a cup and a marker), score it on held-out sweeps, plan to a moved dustpan "
            "in three unseen scenes, and write figures, the skill, the plans, JSON and an HTML "
            "report.",
        ),
        "import": (
            import_.run_command,
            import_.add_options,
            True,
            "demonstrations from robot recordings: ROS 1/2 bags and MCAP",
            "Read tool poses from recordings (ROS 1 .bag, ROS 2 bag folders with sqlite3 or MCAP "
            "storage, .mcap files) and write them as a demonstrations file lfdkit learn reads, "
            "with the orientation as qx, qy, qz, qw. Times are the header stamps (the receive "
            "time where a message has none), in seconds from the recording's first sample. "
            "One recording is one demonstration, or several with --split (at pauses: slower "
            "than --pause-speed for --pause-time); rest at both ends is trimmed unless "
            "--no-trim. -v prints per recording what was split and trimmed. Needs rosbags: "
            'pip install "lfdkit[ros]".',
        ),
        "learn": (
            learn.run_command,
            learn.add_options,
            True,
            "learn a skill from demonstration files",
            "Learn a skill: the generalized path and its DMP from the demonstrations without "
            "obstacles (with their mean tool orientation and an orientation DMP when the file "
            "has qx,qy,qz,qw columns), and the obstacle reward from those the scene file lists. "
            "If the obstacle reward fit does not converge, nothing is written and the exit "
            "status is 1. With --periodic: a periodic skill (wiping, polishing) from one "
            "recording of several cycles.",
        ),
        "plan": (
            plan.run_command,
            plan.add_options,
            True,
            "plan a path with a learned skill",
            "Plan with a learned skill: the DMP carries the path to the new start and goal, "
            "then the planner moves around the obstacles. Writes t,x,y[,z] rows as CSV "
            "(t in seconds: the plan timed along its length with the speed profile learned "
            "from the demonstrations' times, at rest at both ends; for a skill learned with "
            "orientations also qx,qy,qz,qw, the tool's orientation, ending exactly at "
            "--goal-orientation; with --velocities also vx,vy[,vz]). A periodic skill "
            "(lfdkit learn --periodic) is planned as --cycles N of its rhythm instead.",
        ),
        "plot": (
            plot.run_command,
            plot.add_options,
            True,
            "draw a skill: reward contours, demonstrations and a plan",
            "Draw a learned skill as a PNG: with an obstacle reward, its contours in the scene "
            "with the nominal, the demonstrations and the plan; otherwise the path and its DMP. "
            "A periodic skill: its recording, learned cycle and a run.",
        ),
        "execute": (
            execute.run_command,
            execute.add_options,
            True,
            "run a skill on a UR arm: poses, joints, URScript and a MuJoCo check",
            "Plan with a learned 2-D skill (metres) to the goal, turn the plan into the "
            "arm's tool poses and one continuous joint path within its limits, time it, write "
            "a URScript servoj program, and sweep it in MuJoCo (the sweeping task: the dustpan "
            "at the goal, the cube in front of the brush). What the arm cannot do (a pose out "
            "of reach, a joint limit, a speed) is refused on one line, exit status 1, and "
            "nothing is written. Writes plan.csv, poses.csv, joints.csv, program.script, "
            "summary.json and the pictures sweep.png and render.png in DIR.",
        ),
        "compare": (
            compare.run_command,
            compare.add_options,
            True,
            "compare the mimicking methods on the built-in data sets",
            "Compare Mean-Path, GMR, NLPCA and the arc-length average on the built-in data sets "
            "(known ground truth); write one figure per data set, a table and JSON.",
        ),
        "datasets": (
            datasets.run_command,
            datasets.add_options,
            True,
            "list the built-in data sets, or export one as a demonstrations file",
            "List the built-in data sets (name, kind, dimensions, demonstrations, units, what "
            "it is), or write one as files lfdkit learn reads: lfdkit datasets export NAME -o "
            "demos.csv [--scenes scenes.csv] [--seed N]. Files are written atomically and "
            "never over existing ones without --force.",
        ),
        "batch": (
            batch.run_command,
            batch.add_options,
            False,
            "many skills or many scenes: on local processes or a Dask cluster",
            "Run many independent tasks: learn one skill per folder (batch learn), or evaluate "
            "a skill over many scenes or goals (batch evaluate: the sweeping task, or any skill "
            "on any arm with --task path); in this process, on --workers N "
            "local processes or on a Dask cluster (--scheduler, --dask-local N). Results are "
            "written to a JSON-lines file as tasks finish; run the same command again to resume "
            "an interrupted batch. The results do not depend on where the tasks run.",
        ),
        "bench": (
            bench.run_command,
            bench.add_options,
            False,
            "run the benchmarks (source checkout)",
            "Run NAME.py (or the package NAME/) of the benchmarks folder (--benchmarks: "
            "./benchmarks, else the source checkout's); each prints a table and writes JSON "
            "and figures under results/NAME/ beside it.",
        ),
        "teach": (
            teach.run_command,
            teach.add_options,
            False,
            "a local web page: draw demonstrations, learn, try the skill live",
            "Serve a web page on this machine (http://127.0.0.1:8765/ by default; it works "
            "offline) where you draw demonstrations with a mouse, pen or finger, place "
            "obstacles and mark which demonstrations swerved around them, learn the skill "
            "(as lfdkit learn does), look at its layers and drag the start, goal and "
            "obstacles while the plan follows; it exports demos.csv, scenes.csv, the skill, "
            "the plan and the URScript program. Ctrl-C stops it. Needs the extra: "
            'pip install "lfdkit[teach]".',
        ),
    }
    for name, (handler, options, writes, summary, description) in commands.items():
        command = sub.add_parser(name, help=summary, description=description)
        options(command)
        if writes:
            add_force_option(command)
        add_loudness_options(command)
        command.set_defaults(handler=handler)
    return parser


_NUMBER_OPTIONS = (
    "--start",
    "--goal",
    "--duration",
    "--speed",
    # A periodic skill's (lfdkit.app.cli.periodic): a centre may be negative, and the
    # others' negative values are refused with a message of their own.
    "--centre",
    "--cycles",
    "--amplitude",
    "--frequency",
    "--period",
    "--ramp",
    "--pace",
)


_NEGATIVE = re.compile(r"^-[0-9.]")


def _join_negative_points(argv: Sequence[str]) -> list[str]:
    """``--start -0.4,0.45`` as ``--start=-0.4,0.45``: argparse reads ``-0.4,...`` as an option.

    The same for ``--duration`` and ``--speed``, whose negative values are refused
    with a message of their own (``-1e3`` too).
    """
    out: list[str] = []
    for token in argv:
        if out and out[-1] in _NUMBER_OPTIONS and _NEGATIVE.match(token):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``lfdkit`` console script; returns the exit code.

    Whatever goes wrong ends as one line on stderr, never a traceback: the
    expected failures as ``lfdkit CMD: error: <why>``, anything unexpected the
    same way plus "run with -v for details" (``-v`` prints the traceback too).
    Exit codes: 1 failure, 2 usage (argparse, which exits itself, or :class:`UsageError`),
    130 interrupted.
    """
    started = time.perf_counter()  # every time a command reports is counted from here
    if argv is None:  # the real command line: a plain kill cleans up like Ctrl-C
        argv = sys.argv[1:]
        with contextlib.suppress(ValueError, AttributeError):  # not the main thread / Windows
            signal.signal(signal.SIGTERM, _interrupt)
    args = _parser().parse_args(_join_negative_points(list(argv)))
    args.started = started
    args.progress = None
    prefix = f"lfdkit {args.command}"
    try:
        with _warnings_as_lines(args, prefix):
            args.handler(args)
    except KeyboardInterrupt:
        print(f"{prefix}: interrupted", file=sys.stderr)
        return 130
    except MemoryError:
        print(f"{prefix}: error: out of memory: {_too_large(args)}", file=sys.stderr)
        return 1
    except BrokenPipeError:
        # The reader went away (``lfdkit plan ... | head``): no more output, and none at exit.
        with contextlib.suppress(OSError, ValueError, AttributeError):
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        print(f"{prefix}: error: standard output closed early (broken pipe)", file=sys.stderr)
        return 1
    except FileExistsError as exc:
        # The library's wording is for Python callers; here the switch is --force.
        where = exc.filename or getattr(args, "output", None) or "the output"
        print(f"{prefix}: error: {where}: exists; pass --force to overwrite it", file=sys.stderr)
        return 1
    except (CommandError, OSError, ValueError, TypeError) as exc:
        message = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        if isinstance(exc, FileNotFoundError) and exc.filename:
            message = f"{exc.filename}: no such file"
        print(f"{prefix}: error: {message}", file=sys.stderr)
        return 2 if isinstance(exc, UsageError) else 1
    except Exception as exc:  # the last resort: a bug or a case nobody foresaw
        if args.verbosity >= 2:
            traceback.print_exc(file=sys.stderr)
        text = str(exc).splitlines()[0] if str(exc) else ""
        what = f"{type(exc).__name__}: {text}" if text else type(exc).__name__
        print(
            f"{prefix}: error: unexpected {what} (run with -v for details)",
            file=sys.stderr,
        )
        return 1
    return 0


def _interrupt(signum: int, frame: object) -> None:
    """SIGTERM as KeyboardInterrupt, so that partial outputs are removed on the way out."""
    raise KeyboardInterrupt


#: Command options whose size drives memory use, for the out-of-memory message.
_SIZE_OPTIONS = (
    ("n_points", "--n-points"),
    ("dpi", "--dpi"),
    ("demos", "the demonstrations file"),
    ("skill", "the skill file"),
    ("scene", "the scene file"),
)


def _too_large(args: argparse.Namespace) -> str:
    """Which inputs of this command could have asked for too much memory."""
    named = [
        f"{label} {getattr(args, attr)}"
        if label.startswith("--")
        else f"{label} ({getattr(args, attr)})"
        for attr, label in _SIZE_OPTIONS
        if getattr(args, attr, None) is not None
    ]
    if not named:
        return "an input is too large for this machine"
    return "an input is too large for this machine: check " + ", ".join(named)


@contextmanager
def _warnings_as_lines(args: argparse.Namespace, prefix: str) -> Iterator[None]:
    """Show each warning once as ``lfdkit CMD: warning: <message>``, not Python's two lines.

    Notes (:class:`lfdkit.mimic.DemoOrientationWarning`, e.g. a demonstration
    flipped to the common direction) only with ``-v``; other warnings always,
    ``-q`` included (it silences progress and summaries, not poor results).
    """

    def show(message, category, filename, lineno, file=None, line=None) -> None:
        # Imported here, when a warning comes: lfdkit.mimic pulls in scikit-learn.
        from lfdkit.mimic import DemoOrientationWarning

        # A warning says a result may be poor: -q silences progress, never that.
        level = 2 if issubclass(category, DemoOrientationWarning) else 0
        text = str(message).splitlines()[0] if str(message) else category.__name__
        tell(args, f"{prefix}: warning: {text}", level=level)

    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = show
        yield
