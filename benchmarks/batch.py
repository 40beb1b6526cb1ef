"""Batch runs: throughput by executor and worker count, and the client's memory.

Run ``python benchmarks/batch.py`` (``--help`` for options; ``--quick`` for a
smoke run). Prints two tables and writes ``batch.json`` to ``--output``
(``benchmarks/results/batch`` by default).

The skill is learned once from the shipped sweeping example (seed 0) and kept
as ``skill.json`` in the output folder.

Throughput
----------
``--scenes`` random sweeping scenes (default 8, checked with ``--check``,
default ``mujoco``: plan, poses, IK, timing, URScript and the MuJoCo sweep at
0.2 of the UR5's joint limits) evaluated by
:func:`lfdkit.tasks.sweeping.batch.evaluate_batch` on each executor of
:func:`lfdkit.app.batch.make_executor`: serial (this process), local processes
with 1 and 2 workers, a Dask LocalCluster with 1 and 2 worker processes.
Each executor is started as ``lfdkit batch evaluate --random N --check C``
starts it (``make_executor(tasks=N, executes=...)``: with at least 8 tasks a
worker, the workers' fork server loads numba once) and warmed up (one ``plan``
task per worker slot, twice over: the imports, numba's cached kernels and
MuJoCo load once per process); the table gives the start-up time apart and the
throughput of the batch itself (tasks/s), with its ratio to serial. The
executors run in turn, ``--rounds`` times (3); the table gives medians over
the rounds (the ratio: the median of the per-round ratios, each against that
round's serial run), as the machine may be shared. Every run's rows are compared with the
first serial run's (they must be equal), and its file too (rows in the
tasks' order: byte for byte the same). On a 2-core machine
two workers can at best double the throughput; the machine may be shared.

Per-task overhead
-----------------
``--overhead-tasks`` (2,000) tasks that do nothing (``dict`` of a small
mapping) through :func:`lfdkit.app.batch.run_batch` on each executor: what one
task costs the machinery (submit, pickle, schedule, return, write one line),
in milliseconds per task of the batch's wall time: in chunks (the default)
and one task a unit (``chunk_seconds=0``: what each unit costs).

Scheduling overhead
-------------------
``--scheduling-scenes`` (64) random scenes checked ``plan`` (tasks of about
30–70 ms, the shortest there are) through :func:`lfdkit.app.batch.run_batch`
on serial, 2 local processes and a 2-worker Dask LocalCluster, each started
(as the command starts it for 64 tasks: numba loaded once, before the
tasks) and warmed first, once in chunks of short tasks (the default,
:data:`lfdkit.app.batch.CHUNK_SECONDS` of work a unit) and once one task a
unit (``chunk_seconds=0``), in the same minutes. The table gives the batch's
seconds, its ratio to the warm serial run (throughput), and the overhead
fraction: ``1 - (seconds inside the tasks) / (wall seconds x workers)``
(:attr:`lfdkit.app.batch.BatchSummary.overhead_fraction`: scheduling,
sending, collecting and the workers idle at the end; target under 5 %).
Every run's rows must equal the serial run's.

Memory
------
``lfdkit batch evaluate SKILL --random N --check plan --workers 2`` run as a
child process for N = ``--memory-scenes`` (10,000) and N / 10, each child
reporting its own peak RSS (Linux's ``VmHWM``: the client only, not its
workers). Target: under 2 GB at 10,000 scenes, and
no growth with N (results are streamed to the file, a bounded window of
tasks in flight).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

from _common import git_state, machine_info, package_versions

EXECUTORS = (
    ("serial", {}),
    ("processes, 1 worker", {"workers": 1}),
    ("processes, 2 workers", {"workers": 2}),
    ("Dask LocalCluster, 1 worker", {"dask_local": 1}),
    ("Dask LocalCluster, 2 workers", {"dask_local": 2}),
)
MEMORY_TARGET_MB = 2048.0


def learned_skill(folder: Path) -> Path:
    path = folder / "skill.json"
    if not path.exists():
        from lfdkit.skill import learn
        from lfdkit.tasks.sweeping.examples import example_files

        files = example_files()
        learn(files["demos"], files["scenes"], random_state=0).save(path)
    return path


def rows(path: Path) -> list[dict]:
    from lfdkit.app.batch import read_results

    return sorted(read_results(path), key=lambda r: r["task"])


def warm_up(executor, skill_text: str) -> None:
    from lfdkit.tasks.sweeping.batch import evaluate_scenario

    slots = 2 * int(getattr(executor, "workers", 1))
    where = [{"seed": 999, "index": i} for i in range(slots)]
    futures = [executor.submit(evaluate_scenario, skill_text, w, "plan") for w in where]
    for future in futures:
        future.result()


def throughput(skill: Path, out: Path, n: int, check: str, rounds: int) -> list[dict]:
    """Each executor in turn, ``rounds`` times; throughput and ratio to serial per round.

    The machine is shared: a round times every executor within a few minutes of
    each other, and the table gives medians of the rounds (ratios: medians of
    the per-round ratios).
    """
    from lfdkit.app.batch import make_executor
    from lfdkit.tasks.sweeping.batch import evaluate_batch

    text = skill.read_text()
    runs: dict[str, list[dict]] = {name: [] for name, _ in EXECUTORS}
    reference = None
    for k in range(rounds):
        serial_rate = None
        for name, kwargs in EXECUTORS:
            tag = "_".join(f"{key}{v}" for key, v in kwargs.items()) or "serial"
            results = out / f"throughput_{tag}.jsonl"
            begin = time.perf_counter()
            # Started as `lfdkit batch evaluate --random n --check check` starts it.
            executes = check in ("robot", "mujoco")
            with make_executor(**kwargs, tasks=n, executes=executes) as executor:
                warm_up(executor, text)
                startup = time.perf_counter() - begin
                summary = evaluate_batch(
                    skill, results, random=n, seed=0, check=check, executor=executor, overwrite=True
                )
            got = rows(results)
            if reference is None:
                reference, reference_file = got, results.read_bytes()
            rate = summary.throughput
            serial_rate = serial_rate or rate
            runs[name].append(
                {
                    "round": k,
                    "workers": int(getattr(executor, "workers", 1)),
                    "startup_s": startup,
                    "batch_s": summary.seconds,
                    "tasks_per_s": rate,
                    "ratio_vs_serial": rate / serial_rate,
                    "errors": summary.failed,
                    "equal_to_serial": got == reference,
                    # rows written in the tasks' order: the serial run's file, byte for byte
                    "same_file_as_serial": results.read_bytes() == reference_file,
                }
            )
            print(f"  round {k + 1}/{rounds}: {name:<30} {rate:7.3f} tasks/s", flush=True)
    table = []
    for name, done in runs.items():
        row = {
            "executor": name,
            "workers": done[0]["workers"],
            "tasks": n,
            "check": check,
            "rounds": rounds,
            "startup_s": statistics.median(r["startup_s"] for r in done),
            "batch_s": statistics.median(r["batch_s"] for r in done),
            "tasks_per_s": statistics.median(r["tasks_per_s"] for r in done),
            "ratio_vs_serial": statistics.median(r["ratio_vs_serial"] for r in done),
            "equal_to_serial": all(r["equal_to_serial"] for r in done),
            "same_file_as_serial": all(r["same_file_as_serial"] for r in done),
            "errors": sum(r["errors"] for r in done),
            "runs": done,
        }
        table.append(row)
    print(
        f"{'executor':<30} {'start s':>8} {'batch s':>8} {'tasks/s':>8} {'ratio':>7} "
        "equal same-file"
    )
    for row in table:
        print(
            f"{row['executor']:<30} {row['startup_s']:8.1f} {row['batch_s']:8.1f} "
            f"{row['tasks_per_s']:8.3f} {row['ratio_vs_serial']:6.2f}x "
            f"{'yes' if row['equal_to_serial'] else 'NO':>5} "
            f"{'yes' if row['same_file_as_serial'] else 'NO':>9}",
            flush=True,
        )
    return table


def overhead(out: Path, n: int) -> list[dict]:
    """Milliseconds per do-nothing task, in chunks (the default) and one task a unit."""
    from lfdkit.app.batch import make_executor, run_batch

    table = []
    for name, kwargs in EXECUTORS:
        with make_executor(**kwargs) as executor:
            work = [(i, ({"i": i},)) for i in range(2 * executor.workers)]
            run_batch(executor, dict, work, out / "warm.jsonl", spec={}, overwrite=True)
            row = {"executor": name, "tasks": n}
            for key, chunk in (("ms_per_task", None), ("ms_per_unit", 0.0)):
                if chunk == 0.0 and not kwargs:
                    row[key] = row["ms_per_task"]  # the serial executor has no units
                    continue
                work = ((i, ({"i": i},)) for i in range(n))
                summary = run_batch(
                    executor,
                    dict,
                    work,
                    out / "overhead.jsonl",
                    spec={},
                    total=n,
                    overwrite=True,
                    chunk_seconds=chunk,
                )
                row[key] = 1e3 * summary.seconds / n
        table.append(row)
        print(f"{name:<30} {row['ms_per_task']:8.3f} {row['ms_per_unit']:13.3f}", flush=True)
    return table


def scheduling(skill: Path, out: Path, n: int, rounds: int) -> list[dict]:
    """Warm executors, ``n`` plan tasks, chunked and one task a unit; overhead fractions."""
    from lfdkit.app.batch import make_executor, run_batch
    from lfdkit.tasks.sweeping.batch import evaluate_scenario, random_tasks

    text = skill.read_text()
    executors = [EXECUTORS[0], EXECUTORS[2], EXECUTORS[4]]
    found: dict[tuple[str, str], list[dict]] = {}
    reference = None
    for k in range(rounds):
        serial_s = None
        for name, kwargs in executors:
            with make_executor(**kwargs, tasks=n) as executor:  # as the command starts it
                warm_up(executor, text)
                modes = [("one task a unit", 0.0), ("chunks", None)]
                for mode, chunk in modes[1:] if not kwargs else modes:
                    results = out / "scheduling.jsonl"
                    summary = run_batch(
                        executor,
                        evaluate_scenario,
                        random_tasks(text, n, 0, "plan", 0.2),
                        results,
                        spec={"scheduling": n},
                        total=n,
                        overwrite=True,
                        chunk_seconds=chunk,
                    )
                    got = rows(results)
                    reference = reference or got
                    serial_s = serial_s or summary.seconds
                    run = {
                        "round": k,
                        "batch_s": summary.seconds,
                        "ratio_vs_serial": serial_s / summary.seconds,
                        "overhead_fraction": summary.overhead_fraction,
                        "busy_s": summary.busy_seconds,
                        "equal_to_serial": got == reference,
                    }
                    found.setdefault((name, mode if kwargs else "-"), []).append(run)
                    print(
                        f"  round {k + 1}/{rounds}: {name:<30} {mode if kwargs else '-':<16}"
                        f" {summary.seconds:6.2f} s, overhead {summary.overhead_fraction:6.1%}",
                        flush=True,
                    )
    table = []
    print(f"{'executor':<30} {'units':<16} {'batch s':>8} {'ratio':>7} {'overhead':>9} equal")
    for (name, mode), done in found.items():
        row = {
            "executor": name,
            "units": mode,
            "tasks": n,
            "batch_s": statistics.median(r["batch_s"] for r in done),
            "ratio_vs_serial": statistics.median(r["ratio_vs_serial"] for r in done),
            "overhead_fraction": statistics.median(r["overhead_fraction"] for r in done),
            "equal_to_serial": all(r["equal_to_serial"] for r in done),
            "runs": done,
        }
        table.append(row)
        print(
            f"{name:<30} {mode:<16} {row['batch_s']:8.2f} {row['ratio_vs_serial']:6.2f}x"
            f" {row['overhead_fraction']:9.1%} {'yes' if row['equal_to_serial'] else 'NO'}",
            flush=True,
        )
    return table


# The child's peak RSS: Linux's VmHWM (ru_maxrss would carry over the RSS of the
# benchmark process it was forked from, hundreds of MB, across the exec).
_CHILD = """
import json, resource, sys, time
from lfdkit.app.cli import main
begin = time.perf_counter()
rc = main(sys.argv[1:])
try:
    with open("/proc/self/status") as f:
        peak = next(int(l.split()[1]) for l in f if l.startswith("VmHWM:")) / 1024
except (OSError, StopIteration):
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
print(json.dumps({"rc": rc, "seconds": time.perf_counter() - begin, "maxrss_mb": peak}))
"""


def memory(skill: Path, out: Path, n: int) -> list[dict]:
    table = []
    for count in (max(1, n // 10), n):
        results = out / f"memory_{count}.jsonl"
        command = [
            sys.executable,
            "-c",
            _CHILD,
            "batch",
            "evaluate",
            str(skill),
            "--random",
            str(count),
            "--check",
            "plan",
            "--workers",
            "2",
            "-o",
            str(results),
            "--force",
            "-q",
        ]
        done = subprocess.run(command, capture_output=True, text=True, check=False)
        report = json.loads(done.stdout.strip().splitlines()[-1])
        lines = sum(1 for _ in results.open()) - 1
        row = {
            "scenes": count,
            "rows_written": lines,
            "exit_code": report["rc"],
            "seconds": report["seconds"],
            "client_peak_rss_mb": report["maxrss_mb"],
            "results_file_mb": results.stat().st_size / 2**20,
        }
        table.append(row)
        print(
            f"{count:>8,} {lines:>8,} {row['seconds']:8.1f} {row['client_peak_rss_mb']:10.1f} "
            f"{row['results_file_mb']:8.2f}",
            flush=True,
        )
    return table


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=None, help="throughput scenes (8)")
    parser.add_argument("--rounds", type=int, default=None, help="throughput rounds (3)")
    parser.add_argument(
        "--check", default="mujoco", choices=("plan", "kinematics", "robot", "mujoco")
    )
    parser.add_argument("--memory-scenes", type=int, default=None, help="(10,000)")
    parser.add_argument("--overhead-tasks", type=int, default=2000)
    parser.add_argument("--scheduling-scenes", type=int, default=64)
    parser.add_argument("--skip-scheduling", action="store_true")
    parser.add_argument("--skip-memory", action="store_true")
    parser.add_argument("--skip-overhead", action="store_true")
    parser.add_argument("--skip-throughput", action="store_true")
    parser.add_argument("--quick", action="store_true", help="6 scenes, 1,000 for memory")
    parser.add_argument("--output", type=Path, default=Path("benchmarks/results/batch"))
    args = parser.parse_args()
    scenes = args.scenes or (4 if args.quick else 8)
    rounds = args.rounds or (1 if args.quick else 3)
    memory_scenes = args.memory_scenes or (1000 if args.quick else 10_000)
    args.output.mkdir(parents=True, exist_ok=True)
    skill = learned_skill(args.output)
    record: dict = {
        "machine": machine_info(),
        "git": git_state(),
        "versions": package_versions(["lfdkit", "numpy", "mujoco", "dask", "distributed"]),
    }
    if not args.skip_throughput:
        print(f"\nThroughput: {scenes} random scenes, check {args.check}, {rounds} rounds")
        record["throughput"] = throughput(skill, args.output, scenes, args.check, rounds)
    if not args.skip_scheduling:
        print(f"\nScheduling overhead: {args.scheduling_scenes} plan tasks, warm executors")
        record["scheduling"] = scheduling(skill, args.output, args.scheduling_scenes, rounds)
    if not args.skip_overhead:
        print(f"\nPer-task overhead: {args.overhead_tasks:,} tasks that do nothing")
        print(f"{'executor':<30} {'ms/task':>8} {'one a unit':>13}")
        record["overhead"] = overhead(args.output, args.overhead_tasks)
    if not args.skip_memory:
        print("\nMemory: lfdkit batch evaluate --random N --check plan --workers 2 (client RSS)")
        print(f"{'scenes':>8} {'rows':>8} {'s':>8} {'peak MB':>10} {'file MB':>8}")
        record["memory"] = memory(skill, args.output, memory_scenes)
        peak = record["memory"][-1]["client_peak_rss_mb"]
        verdict = "PASS" if peak < MEMORY_TARGET_MB else "FAIL"
        print(
            f"target: client peak RSS < {MEMORY_TARGET_MB:.0f} MB at {memory_scenes:,}: {verdict}"
        )
        record["memory_target"] = {"limit_mb": MEMORY_TARGET_MB, "pass": peak < MEMORY_TARGET_MB}
    path = args.output / "batch.json"
    path.write_text(json.dumps(record, indent=1) + "\n")
    print(f"\nwrote {path}")


if __name__ == "__main__":
    main()
