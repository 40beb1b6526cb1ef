"""``lfdkit batch``: many skills or many scenes, on local processes or Dask."""

from __future__ import annotations

import argparse
import contextlib
from pathlib import Path

from lfdkit import __version__
from lfdkit.app.cli.common import (
    CommandError,
    UsageError,
    add_force_option,
    add_loudness_options,
    add_seed_option,
    add_skill_param_options,
    add_task_description_options,
    add_unknown_class_option,
    bounded_int,
    check_writable,
    parse_fraction,
    parse_numbers,
    point_arg,
    positive_or_none,
    refuse_existing,
    skill_params,
    task_description,
    tell,
    unknown_class_options,
    working,
)
from lfdkit.app.cli.via import add_via_option, via_points
from lfdkit.core.progress import Progress

__all__ = ["add_options", "run_command"]


def run_command(args: argparse.Namespace) -> None:
    from lfdkit.app.batch import describe_executor, make_executor

    out: Path = args.output
    if out.is_dir():
        raise CommandError(f"--output {out}: is a directory; give a results file (.jsonl)")
    if not out.parent.exists():
        raise CommandError(f"--output {out}: folder {out.parent} does not exist")
    check_writable(out.parent, "--output", out)
    where = describe_executor(args.workers, args.scheduler, args.dask_local)
    resuming = out.exists() and not args.force
    with working(args) as progress:
        if args.mode == "learn":
            run, noun = _batch_learn_setup(args, resuming), "skills"
        elif _evaluate_task_of(args) == "path":
            run, noun = _batch_path_setup(args, progress), "tasks"
        else:
            run, noun = _batch_evaluate_setup(args, progress), "scenes"
        _check_results_file(out)
        verb = "resuming" if resuming else "starting"
        tell(args, f"lfdkit {__version__}: {verb} the batch in {out} on {where}", level=2)
        try:
            with contextlib.ExitStack() as stack:
                with progress.stage(f"start {where}"):
                    pool = stack.enter_context(
                        make_executor(
                            args.workers,
                            args.scheduler,
                            args.dask_local,
                            tasks=getattr(args, "random", None),
                            executes=_executes(args),
                        )
                    )
                summary = run(pool, progress)
        except ImportError as exc:
            raise CommandError(str(exc)) from None
    ran = summary.done + summary.failed
    rate = f" ({summary.throughput:.3g} tasks/s)" if ran else ""
    skipped = f"; {summary.skipped} done before, skipped" if summary.skipped else ""
    path_task = args.mode == "evaluate" and args.task == "path"
    detail = _batch_outcomes(args, out) if args.mode == "evaluate" and not path_task else ""
    tell(
        args,
        f"ran {ran} of {summary.total} {noun} in {summary.seconds:.1f} s{rate} on {where}"
        f"{skipped}{detail}; results in {out}",
    )
    if path_task:
        _path_outcomes(args, out)
    failed = summary.failed + summary.failed_before
    if failed:
        first = f" (first: {summary.errors[0]})" if summary.errors else ""
        raise CommandError(
            f"{failed} of {summary.total} tasks failed{first}; each error is in {out}; "
            "the others' results are there too"
        )


def _check_results_file(out: Path) -> None:
    """Refuse a results file that is no regular file, with or without ``--force``.

    A FIFO would hang the batch, a link be written through. Checked after the
    options (:mod:`lfdkit.io` loads NumPy: the workers' fork server starts
    first, :func:`_start_workers`).
    """
    from lfdkit.io.atomic import check_output_path

    try:
        check_output_path(out, overwrite=True)
    except OSError as exc:
        raise UsageError(f"--output {exc}") from None


def _start_workers(args: argparse.Namespace) -> None:
    """Start local workers' fork server, once the command line has been checked (issue 30).

    It loads (NumPy, the skill, numba for a long batch: up to about 1.7 s of
    CPU) on its own core while this process loads its own; started before the
    checks, a usage error would leave it loading in the background for
    nothing. Each setup calls this after its last check of the options
    (again, harmless, where :func:`_evaluate_task_of` started it: a process
    has one fork server).
    """
    local = args.workers if args.workers is not None else args.dask_local
    if local is not None:
        from lfdkit.app.batch import start_worker_server

        start_worker_server(getattr(args, "random", None), local, _executes(args))


def _executes(args: argparse.Namespace) -> bool:
    """Whether the batch's tasks carry plans onto a robot (the fork server loads the pipeline).

    The path task's always import it; the sweep's from ``--check robot`` on.
    """
    if args.mode != "evaluate":
        return False
    return args.task == "path" or args.simulate or args.check in ("robot", "mujoco")


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
    params = skill_params(args)
    _start_workers(args)

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


def _evaluate_task_of(args: argparse.Namespace) -> str:
    """``--task``, or the default: the sweep for a 2-D skill on ur5 with no path-task option."""
    if args.task is None:
        if not args.skill.is_file():
            raise CommandError(f"{args.skill}: no such file")
        path_only = [args.arm, args.tip_link, args.task_file, args.offset, args.height]
        path_only += [args.q_start, args.tool_length, args.rate, args.spread, args.summary]
        path_only += [args.unknown_class, args.approach, args.retreat, args.via]
        if all(v is None for v in path_only) and _valid_for_either_task(args):
            _start_workers(args)  # valid whatever the skill: before loading it (0.3 s)
        from lfdkit.skill import Skill

        sweep = Skill.load(args.skill).n_dims_ == 2 and all(v is None for v in path_only)
        args.task = "sweep" if sweep else "path"
    return args.task


def _valid_for_either_task(args: argparse.Namespace) -> bool:
    """Whether options with no path-task option pass both tasks' checks, whatever the skill.

    The sweep and the path task refuse different options: with none of the
    path task's own, only these differ, and start and goal are checked
    against the skill's dimensions.
    """
    one_source = (args.random is None) != (args.scenes is None)
    seeded_file = args.scenes is not None and args.seed is not None
    points = args.start is not None or args.goal is not None
    return one_source and not seeded_file and not points and args.check != "kinematics"


def _batch_path_setup(args: argparse.Namespace, progress: Progress):
    """Any skill on any arm with a task description (:mod:`lfdkit.app.execute_batch`)."""
    if (args.random is None) == (args.scenes is None):
        raise UsageError("give the scenes or goals: --scenes FILE or --random N")
    if args.scenes is not None and args.seed is not None:
        raise UsageError("--seed is for --random: the scenes of a file are given")
    if args.scenes is not None and args.spread is not None:
        raise UsageError("--spread is for --random: it draws goals around --goal")
    if args.check == "kinematics":
        raise UsageError(
            "--check kinematics: is the sweeping task's; the path task checks plan, robot or mujoco"
        )
    if args.summary is not None:
        refuse_existing(args.summary, args.force, "--summary")
    check = "mujoco" if args.simulate else args.check
    rate = positive_or_none(args.rate, "--rate", "a rate in Hz (e.g. 125)")
    spread = positive_or_none(args.spread, "--spread", "a radius in metres (e.g. 0.05)")
    task = task_description(args)
    if args.start is None and args.goal is None and args.via is None:
        _start_workers(args)  # nothing left to check against the skill: beside its loading
    with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn, numba)"):
        from lfdkit.app.execute_batch import evaluate_task_batch
        from lfdkit.skill import Skill

    loaded = Skill.load(args.skill)
    dims = loaded.n_dims_
    via = via_points(args.via, dims, loaded.timing_.duration)  # every plan lasts the skill's
    start, goal = point_arg(args.start, "--start", dims), point_arg(args.goal, "--goal", dims)
    _start_workers(args)  # (again: harmless)

    def run(executor, progress):
        try:
            return evaluate_task_batch(
                args.skill,
                args.output,
                arm=args.arm or "ur5",
                tip_link=args.tip_link,
                task=task,
                random=args.random,
                seed=args.seed or 0,
                spread=0.05 if spread is None else spread,
                scenes=args.scenes,
                start=start,
                goal=goal,
                check=check,
                speed_fraction=args.speed_fraction,
                rate=rate,
                **unknown_class_options(args),
                via=via,
                executor=executor,
                overwrite=args.force,
                progress=progress,
            )
        except ValueError as exc:
            message = str(exc).splitlines()[0]
            for name in ("arm", "tip_link", "rate", "spread", "start", "goal"):
                if message.startswith(f"{name}:"):
                    message = "--" + name.replace("_", "-") + message[len(name) :]
            raise CommandError(message) from None

    return run


def _path_outcomes(args: argparse.Namespace, out: Path) -> None:
    """The path task's table on stdout (and ``--summary`` as JSON)."""
    import json

    from lfdkit.app.execute_batch import outcome_table
    from lfdkit.io import write_text

    summary, table = outcome_table(out)
    if args.verbosity >= 1:
        print(table)
    if args.summary is not None:
        text = json.dumps({"results": str(out), **summary}, indent=1) + "\n"
        write_text(args.summary, text, overwrite=args.force)


def _batch_evaluate_setup(args: argparse.Namespace, progress: Progress):
    described = ("arm", "tip_link", "task_file", "offset", "height", "q_start", "tool_length")
    for option in (*described, "approach", "retreat"):
        if getattr(args, option) is not None:
            raise UsageError(
                f"--{option.replace('_', '-')}: is for --task path; the sweeping task runs on "
                "the UR5 with its brush"
            )
    for option in ("rate", "spread", "summary", "unknown_class", "via"):
        if getattr(args, option) is not None:
            raise UsageError(f"--{option.replace('_', '-')}: is for --task path")
    if (args.random is None) == (args.scenes is None):
        raise UsageError("give the scenes: --scenes FILE or --random N")
    if args.random is not None and (args.start is not None or args.goal is not None):
        raise UsageError("--start/--goal are for --scenes; random scenes have their own")
    if args.scenes is None and args.seed is None:
        args.seed = 0
    elif args.scenes is not None and args.seed is not None:
        raise UsageError("--seed is for --random: the scenes of a file are given")
    check = "mujoco" if args.simulate else args.check
    start, goal = point_arg(args.start, "--start", 2), point_arg(args.goal, "--goal", 2)
    _start_workers(args)  # loads beside this process's own loading
    with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn, numba, MuJoCo)"):
        from lfdkit.tasks.sweeping.batch import evaluate_batch

    def run(executor, progress):
        return evaluate_batch(
            args.skill,
            args.output,
            random=args.random,
            seed=args.seed or 0,
            scenes=args.scenes,
            start=start,
            goal=goal,
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


def _executor_options(parser: argparse.ArgumentParser) -> None:
    """Where a batch runs: this process (default), local processes or a Dask cluster."""
    group = parser.add_argument_group("where the tasks run (default: in this process)")
    where = group.add_mutually_exclusive_group()
    where.add_argument(
        "--workers",
        type=bounded_int(1, 1024),
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
        type=bounded_int(1, 1024),
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


def add_options(parser: argparse.ArgumentParser) -> None:
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
    add_skill_param_options(learn)
    _executor_options(learn)
    evaluate = modes.add_parser(
        "evaluate",
        help="evaluate a skill over many scenes or goals (the sweeping task, or any arm)",
        description="Evaluate a 2-D sweeping skill (metres) over many scenes: those of a scene "
        "file, or N random ones (a moved dustpan, a cup and a marker near the sweep; scene i "
        "of --seed S is the same in any batch). Each scene is checked as far as --check says "
        "(plan; kinematics: + poses and inverse kinematics; robot: + timing and URScript; "
        "mujoco: + the simulated sweep) and written as one JSON line. Exit status 1 if a "
        "task raised an error (recorded in the file); a scene the robot cannot sweep is an "
        "outcome (ok false), not an error. With --task path (the default for a 3-D skill, "
        "a URDF arm or any task-description option) any skill runs on any arm (--arm) with a "
        "task description, as lfdkit execute does, over the scenes of a file or N random goals "
        "within --spread of the goal; a table of the outcomes is printed at the end.",
    )
    evaluate.add_argument(
        "skill", type=Path, metavar="SKILL.json", help="a skill from lfdkit learn"
    )
    scenes = evaluate.add_mutually_exclusive_group()
    scenes.add_argument(
        "--scenes", type=Path, metavar="FILE", help="a scene file with many scenes (.csv or .json)"
    )
    scenes.add_argument("--random", type=bounded_int(1, 10**9), metavar="N", help="N random scenes")
    add_seed_option(evaluate, None, "base seed of the random scenes (default 0)")
    for end in ("start", "goal"):
        evaluate.add_argument(
            f"--{end}",
            type=parse_numbers,
            metavar="X,Y[,Z]",
            help=f"the plan's {end} (default: the skill's); sweep: --scenes only; path: with "
            f"--random the {'centre of the random goals' if end == 'goal' else 'start'}",
        )
    evaluate.add_argument(
        "--check",
        choices=("plan", "kinematics", "robot", "mujoco"),
        default="robot",
        help="how far to carry each plan (default %(default)s; kinematics: sweep only)",
    )
    evaluate.add_argument(
        "--simulate", action="store_true", help="sweep in MuJoCo: the same as --check mujoco"
    )
    evaluate.add_argument(
        "--speed-fraction",
        type=parse_fraction,
        default=0.2,
        metavar="F",
        help="fraction of the arm's joint speed limits, in (0, 1] (default %(default)s)",
    )
    path = evaluate.add_argument_group("the path task: any skill on any arm")
    path.add_argument(
        "--task",
        choices=("sweep", "path"),
        default=None,
        help="sweep: the sweeping task (2-D skill, UR5, brush, dustpan); path: any skill on any "
        "arm (default: sweep for a 2-D skill without the options below)",
    )
    path.add_argument(
        "--arm",
        metavar="ARM|URDF",
        default=None,
        help="the robot arm: ur5, ur10 or a URDF file (default ur5)",
    )
    path.add_argument(
        "--tip-link", metavar="LINK", default=None, help="with a URDF arm: the link of the tool"
    )
    path.add_argument(
        "--rate",
        default=None,
        metavar="HZ",
        help="rate of the fixed-rate samples (default 125)",
    )
    path.add_argument(
        "--spread",
        default=None,
        metavar="R",
        help="--random: goals drawn uniformly within R m of the goal (default 0.05)",
    )
    path.add_argument(
        "--summary",
        type=Path,
        default=None,
        metavar="FILE.json",
        help="also write the outcome table as JSON",
    )
    add_unknown_class_option(path, "m")
    add_via_option(path)
    add_task_description_options(evaluate)
    _results_option(evaluate)
    _executor_options(evaluate)
    for mode in (learn, evaluate):
        add_force_option(mode)
        add_loudness_options(mode)
