"""Start-up: what a user waits for around the kernels (issue 30), before and after, side by side.

Run ``python benchmarks/startup.py`` (``--help`` for options; ``--quick``
skips ``lfdkit learn`` and the 1000-basis refit). Prints a table and writes
``startup.json`` to ``--output`` (``benchmarks/results/startup`` by default).

Every figure is a fresh Python process (what a user or a batch worker pays),
the median of ``--repeats`` runs (3), with numba's cache and Python's
bytecode cache warm (each command runs once untimed first;
``PYTHONDONTWRITEBYTECODE`` is unset for them, as a package installed by pip
has its bytecode compiled). "after" runs this checkout's ``src``; "before" runs
the ``src`` of ``--baseline-commit`` (default :data:`BASELINE_COMMIT`, the
commit before issue 30), extracted with ``git archive`` into the output
folder, or ``--baseline`` (any lfdkit source tree), in the same run,
alternating, so both see the same machine load. Measured:

``lfdkit --help``
    the entry point's imports and argparse (target ≤ 0.2 s).
``import lfdkit.app.cli``
    the command module alone.
``lfdkit plan``
    the README's example with one obstacle on the sweeping skill (target
    ≤ 0.6 s warm on a 2-core machine).
``lfdkit plan, LFDKIT_KERNELS=numba``
    the same with numba's kernels (what ``plan`` cost before it ran NumPy's).
``one plan, warm process``
    CPU seconds per plan after two, in one process, with the NumPy forms of
    the kernels and with numba's ("after" only).
``Skill.load``
    in a fresh process after ``import lfdkit.skill``, the sweeping skill and
    200- and 1000-basis skills (target ≤ 50 ms for any skill file). "before"
    reads the same file by refitting (the old reader ignores the stored
    DMP); it refuses ``n_basis`` above 200, so the 1000 row is "after" only.
``worker start-up``
    a ``ProcessExecutor`` of 2 workers, from creation to both workers' first
    ``plan`` task of ``lfdkit batch evaluate`` done (target ≤ 1.5 s). Since
    issue 30 the workers fork from a preloaded fork server on Linux; its CPU
    seconds and its workers' (no children the benchmark waits for) are
    counted with ``psutil`` over the process tree in the CPU column.
``lfdkit learn``
    the shipped sweeping demonstrations (once each; not with ``--quick``).
``batch N, --check C`` (with ``--batch N``; ``--batch-checks``, ``--batch-trees``)
    ``lfdkit batch evaluate SKILL --random N --check C`` serial and with
    ``--workers 2``, once each: the speed-up in wall time (target ≥ 1.85× for
    64 tasks on 2 cores) and, for a shared machine, "by CPU": the serial
    run's CPU seconds over the 2-worker run's critical path on 2 idle cores
    (polled with ``psutil``): the command's CPU up to its first task or, if
    later, the fork server's finish (it starts when the command starts it,
    beside the command), then the busier worker's CPU, then the command's
    rest. Both runs are whole commands: each pays Python's start, the
    imports, the skill and numba's start-up (the serial one in itself, the
    2-worker one in its fork server, once). And "tasks": the speed-up of the
    task phase, the seconds ``run_batch`` reports (from the first task sent
    to the last row written). Before it, each executor is equally warm
    (:func:`lfdkit.app.batch.make_executor`): the serial process has loaded
    numba and the workers' modules (:func:`lfdkit.app.batch.worker_modules`)
    and warmed the planner; the 2-worker run's fork server has loaded the
    same and one worker is forked. The whole command cannot reach 1.85× for
    short tasks: 64 ``plan`` tasks are about 1.4-2.0 s of CPU (21-31 ms
    each, their scenes' declined gaps add side blockers; 2-core machine at
    load 6) against about 1.2 s of start-up that no worker can share
    (Python, imports, the skill, numba), so the whole command's bound is
    about 1.4×; the task phase is what a longer batch scales by. A "before"
    tree older than that warm start counts its workers' start in its task
    phase. A "before" tree that cannot run a row (the default commit cannot
    read the skill files this checkout writes) is left out of that row.

The skill files are made once with this checkout (``skill.json``, the
sweeping skill; ``n_basis_1000.json``) and kept in the output folder.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

from _common import git_state, machine_info, package_versions

ROOT = Path(__file__).resolve().parent.parent
#: The commit before issue 30 (loading refitted the DMP).
BASELINE_COMMIT = "c7a1d8e"
#: CPU seconds of each child run (:func:`run`), in order.
CPU_SECONDS: list[float] = []
PLAN_ARGS = ["--goal", "0.36,0.5", "--obstacle", "cup:-0.05,0.47,r=0.03"]

# Run in a fresh process: prints the seconds Skill.load took (after the import).
LOAD_SCRIPT = """
import sys, time
from lfdkit.skill import Skill
start = time.perf_counter()
Skill.load(sys.argv[1])
print(time.perf_counter() - start)
"""

# Run in a fresh process: seconds from creating 2 workers to both first tasks done, and
# the CPU seconds of the fork server and its workers by then (psutil; they are no children
# the benchmark waits for, so the rusage of run() misses them).
WORKERS_SCRIPT = """
import sys, time
from pathlib import Path
import psutil
start = time.perf_counter()
from lfdkit.app.batch import ProcessExecutor
from lfdkit.tasks.sweeping.batch import evaluate_scenario
text = Path(sys.argv[1]).read_text()
with ProcessExecutor(2) as pool:
    futures = [
        pool.submit(evaluate_scenario, text, {"seed": 0, "index": i}, "plan") for i in range(2)
    ]
    rows = [f.result() for f in futures]
    wall = time.perf_counter() - start
    tree = 0.0
    for child in psutil.Process().children(recursive=True):
        try:
            times = child.cpu_times()
            tree += times.user + times.system
        except psutil.Error:
            pass
print(f"cpu={tree}")
print(wall)
"""


# Run in a fresh process: CPU seconds per plan of the README's example, warm (after 2 plans),
# with the kernels LFDKIT_KERNELS names (the NumPy forms or numba's).
PER_PLAN_SCRIPT = """
import sys, time
import numpy as np
from lfdkit.skill import Skill
from lfdkit.model.scene import Obstacle, Scene
skill = Skill.load(sys.argv[1])
scene = Scene((Obstacle("cup", [-0.05, 0.47], radius=0.03),))
for _ in range(2):
    skill.plan(goal=[0.36, 0.5], scene=scene)
start = time.process_time()
for _ in range(5):
    skill.plan(goal=[0.36, 0.5], scene=scene)
print((time.process_time() - start) / 5)
"""


# Run in a fresh process: ``lfdkit ARGS``, printing on stderr this process's CPU seconds when it
# started the workers' fork server and when it first submitted a task (for the critical path),
# and the seconds of the batch's task phase (run_batch's: from its first task sent, the
# executor warm, to its last row written).
BATCH_SCRIPT = """
import sys, time
import lfdkit.app.batch
from multiprocessing import forkserver
from concurrent.futures import process
marks = {}
def mark(name, fn):
    def marked(*args, **kwargs):
        marks.setdefault(name, time.process_time())
        return fn(*args, **kwargs)
    return marked
forkserver.ensure_running = mark("fs_at", forkserver.ensure_running)
process.ProcessPoolExecutor.submit = mark("submit_at", process.ProcessPoolExecutor.submit)
run_batch = lfdkit.app.batch.run_batch
def timed_batch(*args, **kwargs):
    summary = run_batch(*args, **kwargs)
    marks["tasks_s"] = summary.seconds
    return summary
lfdkit.app.batch.run_batch = timed_batch  # before the task modules import it
from lfdkit.app.cli import main
code = main(sys.argv[1:])
print("MARKS " + " ".join(f"{k}={v}" for k, v in marks.items()), file=sys.stderr)
sys.exit(code)
"""


def run(src: Path, args: list[str], cwd: Path, env: dict | None = None) -> float:
    """Wall seconds of ``python ARGS`` with ``src`` first on the path; raises if it fails.

    A script that times itself prints its seconds last; those are returned.
    The child's CPU seconds (user + system, its own children included) are
    added to :data:`CPU_SECONDS`: on a shared machine they vary less than wall time.
    """
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    env = {**os.environ, "PYTHONPATH": str(src), "OMP_NUM_THREADS": "1", **(env or {})}
    # As installed: Python's bytecode cached (else every process compiles lfdkit's source).
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    start = time.perf_counter()
    done = subprocess.run(
        [sys.executable, *args], cwd=cwd, env=env, capture_output=True, text=True, check=False
    )
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    CPU_SECONDS.append(after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} ({src}) failed: {done.stderr.strip()[-400:]}")
    out = done.stdout.strip().splitlines()
    for line in out:  # CPU seconds of processes that are not waited-for children
        if line.startswith("cpu="):
            CPU_SECONDS[-1] += float(line[4:])
    try:
        return float(out[-1])  # a script that times itself
    except (IndexError, ValueError):
        return wall


def run_tree(src: Path, args: list[str], cwd: Path) -> tuple[float, float, dict[str, float]]:
    """Wall and CPU seconds of ``python ARGS``, and its descendants' CPU seconds by role.

    The descendants (a batch's fork server, its workers, multiprocessing's
    resource tracker) are polled with ``psutil`` every 0.1 s while the command
    runs (their last reading kept: a worker's final 0.1 s may be missed); the
    fork server is no child the command waits for, so rusage misses them.
    Returns ``(wall, cpu of the command itself, {"forkserver": s, "workers":
    [s, ...]})``, with :data:`BATCH_SCRIPT`'s marks (``fs_at``, ``submit_at``)
    where it ran the command.
    """
    import psutil

    env = {**os.environ, "PYTHONPATH": str(src), "OMP_NUM_THREADS": "1"}
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    child = subprocess.Popen(
        [sys.executable, *args], cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    seen: dict[int, tuple[str, float]] = {}
    while child.poll() is None:
        try:
            for process in psutil.Process(child.pid).children(recursive=True):
                with contextlib.suppress(psutil.Error):
                    times = process.cpu_times()
                    # Workers forked from the fork server keep its command line: the
                    # server is the one the command started itself.
                    server = process.ppid() == child.pid
                    role = (
                        "forkserver"
                        if server and "forkserver" in " ".join(process.cmdline())
                        else "worker"
                    )
                    if "resource_tracker" in " ".join(process.cmdline()):
                        role = "tracker"
                    # A role once known stays (an exiting process's command line reads empty).
                    known = seen.get(process.pid, ("worker", 0.0))[0]
                    role = role if known == "worker" else known
                    seen[process.pid] = (role, times.user + times.system)
        except psutil.Error:
            pass
        time.sleep(0.1)
    wall = time.perf_counter() - start
    stderr = child.stderr.read().decode() if child.stderr else ""
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if child.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} ({src}) failed: {stderr.strip()[-400:]}")
    own = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
    roles: dict = {"forkserver": 0.0, "workers": []}
    for line in stderr.splitlines():  # BATCH_SCRIPT's marks
        if line.startswith("MARKS "):
            roles |= {k: float(v) for k, v in (m.split("=") for m in line.split()[1:])}
    for role, cpu in seen.values():
        if role == "forkserver":
            roles["forkserver"] += cpu
        elif role == "worker":
            roles["workers"].append(cpu)
    return wall, own, roles


def measure(
    name: str,
    args: list[str],
    trees: dict[str, Path],
    cwd: Path,
    repeats: int,
    env: dict | None = None,
    warm: bool = True,
) -> dict:
    """Median seconds of ``args`` per tree, the trees alternating; a warm-up run each first.

    ``env``: extra environment variables for every run (e.g. ``LFDKIT_KERNELS``);
    ``warm``: False for runs long enough to need no warm-up (a batch). A tree
    other than "after" whose warm-up run fails (an older lfdkit that cannot
    read this checkout's skill file) is left out of the row, with a note.
    """
    trees = dict(trees)
    for label, src in list(trees.items()) if warm else ():
        try:
            run(src, args, cwd, env)  # warm: numba's cache, the OS's file cache
        except RuntimeError as error:  # an older tree may not read this checkout's files
            if label == "after":
                raise
            reason = str(error).strip().splitlines()[-1][-160:]
            print(f"  {name}: {label} left out, it failed: {reason}", flush=True)
            del trees[label]
    times: dict[str, list[float]] = {label: [] for label in trees}
    cpu: dict[str, list[float]] = {label: [] for label in trees}
    for _ in range(repeats):
        for label, src in trees.items():
            times[label].append(run(src, args, cwd, env))
            cpu[label].append(CPU_SECONDS[-1])
    row = {"what": name, **{label: statistics.median(t) for label, t in times.items()}}
    row |= {f"{label}_cpu": statistics.median(t) for label, t in cpu.items()}
    row["runs"] = times
    if "before" in row and "after" in row:
        row["ratio"] = row["before"] / row["after"]
        row["cpu_ratio"] = row["before_cpu"] / row["after_cpu"]
    print(
        f"  {name}: "
        + ", ".join(f"{k} {row[k]:.3f} s ({row[k + '_cpu']:.3f} s CPU)" for k in trees),
        flush=True,
    )
    return row


def extract(commit: str, folder: Path) -> Path:
    """``src`` of ``commit`` under ``folder`` (once), by ``git archive``."""
    if not (folder / "src").exists():
        folder.mkdir(parents=True, exist_ok=True)
        archive = subprocess.run(
            ["git", "archive", commit, "src"], cwd=ROOT, capture_output=True, check=True
        ).stdout
        subprocess.run(["tar", "-x", "-C", str(folder)], input=archive, check=True)
    return folder / "src"


def make_skills(out: Path, quick: bool) -> dict:
    """The sweeping skill (learned once, untimed) and 200- and 1000-basis skills.

    Returns ``{"learn": args}``, the ``lfdkit learn`` command to time (not
    with ``quick``).
    """
    made = {}
    skill = out / "skill.json"
    cli = ["-m", "lfdkit.app.cli"]
    data = out / "data"
    learn = [*cli, "learn", str(data / "demos.csv"), "--scenes", str(data / "scenes.csv")]
    learn += ["-o", str(skill), "-f", "-q"]
    if not quick:
        made["learn"] = learn
    if not (data / "scenes.csv").exists():
        data.mkdir(exist_ok=True)
        export = ["datasets", "export", "sweeping", "-o", str(data / "demos.csv")]
        export += ["--scenes", str(data / "scenes.csv"), "-f", "-q"]
        run(ROOT / "src", [*cli, *export], out)
    if not skill.exists():
        run(ROOT / "src", learn, out)
    for n_basis in (200, 1000):
        big = out / f"n_basis_{n_basis}.json"
        if not big.exists():
            code = (
                "import numpy as np, sys\nfrom lfdkit.skill import Skill\n"
                "u = np.linspace(0, 1, 100)\n"
                "path = np.column_stack([0.6 * u, 0.1 * np.sin(2 * np.pi * u)])\n"
                f"Skill(n_basis={n_basis}).use_path(path).save(sys.argv[1], overwrite=True)\n"
            )
            run(ROOT / "src", ["-c", code, str(big)], out)
    return made


def batch_rows(trees: dict[str, Path], out: Path, skill: str, args: argparse.Namespace) -> list:
    """``lfdkit batch evaluate --random N``, serial and on 2 workers, per check; speed-ups.

    Once each (a batch is long). The workers' CPU seconds are not in the CPU
    column (the fork server is no child the benchmark waits for).
    """
    used = trees if args.batch_trees == "both" else {"after": trees["after"]}
    rows = []
    for check in args.batch_checks.split(","):
        base = ["-c", BATCH_SCRIPT, "batch", "evaluate", skill, "--random", str(args.batch)]
        name = f"batch {args.batch}, --check {check}"
        for label, src in used.items():
            results = ["--check", check, "-o", f"batch-{label}-{check}.jsonl", "-f", "-q"]
            serial_wall, serial_cpu, serial_roles = run_tree(src, [*base, *results], out)
            wall, own, roles = run_tree(src, [*base, *results, "--workers", "2"], out)
            workers = sorted(roles["workers"], reverse=True)
            # On 2 idle cores: the command up to its first task and, beside it from when the
            # command started it, the fork server; then the busier worker; then the command's
            # rest (collecting, the summary).
            before = roles.get("submit_at", own)
            fork_server_at = roles.get("fs_at", before)
            critical = max(before, fork_server_at + roles["forkserver"])
            critical += (workers[0] if workers else 0.0) + max(0.0, own - before)
            row = {
                "what": f"{name} ({label})",
                "serial_wall": serial_wall,
                "serial_cpu": serial_cpu,
                "workers_wall": wall,
                "command_cpu": own,
                "forkserver_cpu": roles["forkserver"],
                "forkserver_started_at_cpu": fork_server_at,
                "first_submit_at_cpu": before,
                "worker_cpu": workers,
                "speedup_wall": serial_wall / wall,
                "speedup_cpu": serial_cpu / critical,
                # The task phase: run_batch's seconds, each executor warm before it.
                "serial_tasks_s": serial_roles.get("tasks_s", float("nan")),
                "workers_tasks_s": roles.get("tasks_s", float("nan")),
            }
            row["speedup_tasks"] = row["serial_tasks_s"] / row["workers_tasks_s"]
            print(
                f"  {row['what']}: serial {serial_wall:.1f} s ({serial_cpu:.1f} s CPU); 2 workers"
                f" {wall:.1f} s (command {own:.1f} + fork server {roles['forkserver']:.1f} +"
                f" workers {', '.join(f'{w:.1f}' for w in workers)} s CPU); speed-up"
                f" {row['speedup_wall']:.2f}x wall, {row['speedup_cpu']:.2f}x by CPU"
                " (serial CPU / the 2-worker critical path); task phase serial"
                f" {row['serial_tasks_s']:.2f} s, 2 workers {row['workers_tasks_s']:.2f} s:"
                f" {row['speedup_tasks']:.2f}x (target >= 1.85x)",
                flush=True,
            )
            rows.append(row)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument(
        "--baseline",
        type=Path,
        default=None,
        help="source tree of the code before (default: --baseline-commit's)",
    )
    parser.add_argument(
        "--baseline-commit",
        default=BASELINE_COMMIT,
        help=f"commit whose src is 'before' (default {BASELINE_COMMIT})",
    )
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true", help="no learn, no 1000-basis refit")
    parser.add_argument("--output", type=Path, default=ROOT / "benchmarks/results/startup")
    parser.add_argument(
        "--batch",
        type=int,
        default=0,
        metavar="N",
        help="also time `lfdkit batch evaluate --random N`, serial and 2 workers (0: not)",
    )
    parser.add_argument(
        "--batch-checks",
        default="plan,robot",
        help="the batches' --check values, comma-separated (e.g. plan,robot,mujoco)",
    )
    parser.add_argument(
        "--batch-trees",
        choices=("after", "both"),
        default="after",
        help="the trees whose batches are timed (default after: they take minutes)",
    )
    args = parser.parse_args()
    out = args.output.resolve()
    out.mkdir(parents=True, exist_ok=True)
    baseline = args.baseline or extract(args.baseline_commit, out / "baseline")
    trees = {"before": baseline.resolve(), "after": (ROOT / "src").resolve()}
    print(f"machine: {machine_info()}", flush=True)
    made = make_skills(out, args.quick)
    cli = ["-m", "lfdkit.app.cli"]
    skill = str(out / "skill.json")
    rows = [
        measure("python -c pass (the floor)", ["-c", "pass"], trees, out, args.repeats),
        measure("lfdkit --help", [*cli, "--help"], trees, out, args.repeats),
        measure("import lfdkit.app.cli", ["-c", "import lfdkit.app.cli"], trees, out, args.repeats),
        measure(
            "lfdkit plan (README, 1 obstacle)",
            [*cli, "plan", skill, *PLAN_ARGS, "-o", "path.csv", "-f", "-q"],
            trees,
            out,
            args.repeats,
        ),
        measure(
            "lfdkit plan, LFDKIT_KERNELS=numba",
            [*cli, "plan", skill, *PLAN_ARGS, "-o", "path.csv", "-f", "-q"],
            trees,
            out,
            args.repeats,
            {"LFDKIT_KERNELS": "numba"},
        ),
        measure("Skill.load, sweeping skill", ["-c", LOAD_SCRIPT, skill], trees, out, args.repeats),
    ]
    # The kernels' per-plan cost, warm, in CPU seconds (the "after" tree: "before" has numba only).
    for form in ("numpy", "numba"):
        rows.append(
            measure(
                f"one plan, warm process, {form} kernels (CPU)",
                ["-c", PER_PLAN_SCRIPT, skill],
                {"after": trees["after"]},
                out,
                args.repeats,
                {"LFDKIT_KERNELS": form},
            )
        )
    for n_basis in (200, 1000):
        big = ["-c", LOAD_SCRIPT, str(out / f"n_basis_{n_basis}.json")]
        # Before, files held at most 200 (a 1000 file is refused) and the refit takes seconds.
        only_after = n_basis > 200 or args.quick
        used = {"after": trees["after"]} if only_after else trees
        rows.append(measure(f"Skill.load, n_basis {n_basis}", big, used, out, 1))
    rows.append(
        measure(
            "2 workers started, first tasks done",
            ["-c", WORKERS_SCRIPT, skill],
            trees,
            out,
            args.repeats,
        )
    )
    if args.batch:
        rows += batch_rows(trees, out, skill, args)
    if "learn" in made:
        rows.append(measure("lfdkit learn (sweeping demo)", made["learn"], trees, out, 1))
    print()
    print(f"wall seconds (CPU seconds of the process and its children), load {os.getloadavg()}")
    print(f"{'what':38s} {'before':>17s} {'after':>17s} {'ratio wall':>10s} {'CPU':>6s}")
    for row in rows:
        if "speedup_cpu" in row:  # a batch: serial against 2 workers
            print(
                f"{row['what']:38s} serial {row['serial_wall']:.1f} s, 2 workers"
                f" {row['workers_wall']:.1f} s: {row['speedup_wall']:.2f}x wall,"
                f" {row['speedup_cpu']:.2f}x by CPU; tasks {row['speedup_tasks']:.2f}x"
                " (target >= 1.85x)"
            )
            continue
        cells = []
        for label in ("before", "after"):
            if label in row:
                cells.append(f"{row[label]:7.3f} ({row[label + '_cpu']:6.3f})")
            else:
                cells.append(f"{'-':>17s}")
        ratio = f"{row['ratio']:9.1f}x {row['cpu_ratio']:5.1f}x" if "ratio" in row else ""
        print(f"{row['what']:38s} {cells[0]:>17s} {cells[1]:>17s} {ratio}")
    record = {
        "benchmark": "startup",
        "trees": {k: str(v) for k, v in trees.items()},
        "baseline_commit": None if args.baseline else args.baseline_commit,
        "repeats": args.repeats,
        "quick": args.quick,
        "rows": rows,
        "machine": machine_info(),
        "git": git_state(),
        "packages": package_versions(["numpy", "scipy", "numba"]),
    }
    (out / "startup.json").write_text(json.dumps(record, indent=1) + "\n")
    print(f"\nwrote {out / 'startup.json'}")


if __name__ == "__main__":
    main()
