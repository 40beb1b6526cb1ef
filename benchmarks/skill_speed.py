"""A learned skill's planning speed: ``python benchmarks/skill_speed.py`` (``--quick``).

What a user waits for (issue 26's "planning speed kept": a 100-point 2-D plan
≤ 20 ms, an MPC step ≤ 1 ms at H = 12 with 4 obstacles), measured on the
skill rather than on :func:`lfdkit.emulate.plan_path` alone: the thesis
person's data of the fidelity benchmark (seed 0, 10 demonstrations, 1×
noise, ``benchmarks/emulate/people.py``), fitted once with the default
behaviour model (``model="auto"``: with its safety floor, which also plans
each scene without the floor to check the route) and once with
``model="thesis"``; then every held-out scene of the training task is
planned by each, in alternating rounds, with numba's kernels.

Reported per skill: median CPU ms per ``Skill.plan`` (100 points, 2-D,
timed and with every check), of which ``time_path`` (the speed law's
timing), and the MPC step: CPU time of ``plan_details`` divided by its
points. A hash of all plans lets two checkouts be compared for bit-identical
plans. ``--baseline DIR`` (another checkout, e.g. a detached worktree of an
earlier commit) times the same fitted skills with ``DIR/src`` in a child
process, round for round alternating with this checkout's, and reports the
ratios (a loaded machine slows both alike) and whether the plans' hashes
agree. Writes ``skill_speed.json`` to ``--output``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import pickle
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

os.environ.setdefault("LFDKIT_KERNELS", "numba")  # the compiled kernels, as a batch runs them

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import git_state, machine_info, write_json

from lfdkit.skill import Skill


def fitted(model: str, data: dict) -> Skill:
    from emulate import fidelity as F  # here: a --child of another checkout never loads it

    free = [F.noisy(c, key, 1.0, 1.0) for c, key in data["free"]["train"]]
    train = data["train"][:10]
    demos = [F.noisy(clean, key, 1.0, 1.0) for _, clean, key in train]
    scenes = [case.scene for case, _, _ in train]
    return Skill(model=model).fit(free, demos, scenes)


def cpu(fn, *args):
    """``fn(*args)`` and the CPU seconds it took."""
    began = time.process_time()
    out = fn(*args)
    return out, time.process_time() - began


def timed_round(skills: dict, cases: list, digest: dict | None = None) -> dict:
    """One round over every scene: CPU seconds per plan, per MPC step and of ``time_path``."""
    samples = {name: {"plan": [], "details": [], "time_path": []} for name in skills}
    with threadpool_limits(limits=1), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the floor's and gaps' warnings: results, not noise
        for goal, scene, start in cases:
            for name, skill in skills.items():
                plan, seconds = cpu(skill.plan, start, goal, scene)
                details, detail_s = cpu(skill.plan_details, start, goal, scene)
                _, timing_s = cpu(skill.timing_.time_path, plan.points, 1.0)
                samples[name]["plan"].append(seconds)
                samples[name]["details"].append(detail_s / (details.points.shape[0] - 1))
                samples[name]["time_path"].append(timing_s)
                if digest is not None:
                    digest[name].update(np.ascontiguousarray(plan.points).tobytes())
    return samples


def child(path: Path, rounds: int) -> int:
    """``--child``: time the pickled skills (this process's lfdkit); JSON on stdout."""
    with open(path, "rb") as file:
        skills, cases = pickle.load(file)
    timed_round(skills, cases[:1])  # warm-up: numba's compiled kernels loaded
    digest = {name: hashlib.sha256() for name in skills}
    rounds_out = [timed_round(skills, cases, digest if r == 0 else None) for r in range(rounds)]
    hashes = {name: d.hexdigest()[:16] for name, d in digest.items()}
    print(json.dumps({"rounds": rounds_out, "hash": hashes}))
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 scenes per family, 2 rounds")
    parser.add_argument("--rounds", type=int, default=None, help="rounds (default 3; quick 2)")
    parser.add_argument(
        "--baseline", type=Path, default=None, help="another checkout to time side by side"
    )
    parser.add_argument("--child", type=Path, default=None, help=argparse.SUPPRESS)
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).resolve().parent / "results" / "skill"
    )
    args = parser.parse_args(argv)
    rounds = args.rounds or (2 if args.quick else 3)
    if args.child is not None:
        return child(args.child, 1)
    from emulate import fidelity as F

    with threadpool_limits(limits=1), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the floor's and gaps' warnings: results, not noise
        data = F.person_data("thesis", 0, 1.0, 2 if args.quick else 4)
        held = [(c, person) for c, person, _ in data["held"] if c.task == "train"]
        skills = {"default (auto)": fitted("auto", data), "thesis": fitted("thesis", data)}
    cases = [(c.goal, c.scene, person[0]) for c, person in held]
    timed_round(skills, cases[:1])  # warm-up: numba's compiled kernels loaded
    checkouts = {"this": []} | ({} if args.baseline is None else {"baseline": []})
    digest = {name: hashlib.sha256() for name in skills}
    hashes = {}
    with tempfile.TemporaryDirectory() as tmp:
        pickled = Path(tmp) / "skills.pkl"
        with open(pickled, "wb") as file:
            pickle.dump((skills, cases), file)
        for round_ in range(rounds):
            checkouts["this"].append(timed_round(skills, cases, digest if round_ == 0 else None))
            if args.baseline is not None:
                out = subprocess.run(
                    [sys.executable, __file__, "--child", str(pickled)],
                    env={**os.environ, "PYTHONPATH": str(args.baseline.resolve() / "src")},
                    capture_output=True,
                    text=True,
                    check=True,
                )
                answer = json.loads(out.stdout.strip().splitlines()[-1])
                checkouts["baseline"] += answer["rounds"]
                hashes = answer["hash"]
    result = {"scenes": len(cases), "rounds": rounds, "skills": {}}
    print(f"{len(cases)} scenes x {rounds} rounds, median CPU (ms)")
    print(
        f"{'skill':<16} {'checkout':<9} {'plan':>8} {'time_path':>10} {'MPC step':>9}  plans' hash"
    )
    for name in skills:
        result["skills"][name] = {}
        for checkout, runs in checkouts.items():
            row = {
                key: float(np.median([x for run in runs for x in run[name][key]])) * 1e3
                for key in ("plan", "details", "time_path")
            }
            row["hash"] = digest[name].hexdigest()[:16] if checkout == "this" else hashes[name]
            result["skills"][name][checkout] = row
            print(
                f"{name:<16} {checkout:<9} {row['plan']:8.1f} {row['time_path']:10.2f} "
                f"{row['details']:9.3f}  {row['hash']}"
            )
        if args.baseline is not None:
            this, base = result["skills"][name]["this"], result["skills"][name]["baseline"]
            ratio = {key: base[key] / this[key] for key in ("plan", "details")}
            result["skills"][name]["speed_up"] = ratio
            same = "identical" if this["hash"] == base["hash"] else "DIFFERENT"
            print(
                f"{name:<16} {'speed-up':<9} {ratio['plan']:7.2f}x {'':>10} "
                f"{ratio['details']:8.2f}x  plans {same}"
            )
    result["machine"], result["git"] = machine_info(), git_state()
    if args.baseline is not None:
        result["baseline"] = str(args.baseline)
    args.output.mkdir(parents=True, exist_ok=True)
    print("wrote", write_json(args.output / "skill_speed.json", result))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
