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
plans (run it with ``PYTHONPATH`` at each). Writes ``skill_speed.json`` to
``--output``.
"""

from __future__ import annotations

import argparse
import hashlib
import os
import sys
import time
import warnings
from pathlib import Path

os.environ.setdefault("LFDKIT_KERNELS", "numba")  # the compiled kernels, as a batch runs them

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import git_state, machine_info, write_json
from emulate import fidelity as F

from lfdkit.skill import Skill


def fitted(model: str, data: dict) -> Skill:
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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 scenes per family, 2 rounds")
    parser.add_argument("--rounds", type=int, default=None, help="rounds (default 3; quick 2)")
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).resolve().parent / "results" / "skill"
    )
    args = parser.parse_args(argv)
    rounds = args.rounds or (2 if args.quick else 3)
    with threadpool_limits(limits=1), warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the floor's and gaps' warnings: results, not noise
        data = F.person_data("thesis", 0, 1.0, 2 if args.quick else 4)
        cases = [(c, person) for c, person, _ in data["held"] if c.task == "train"]
        skills = {"default (auto)": fitted("auto", data), "thesis": fitted("thesis", data)}
        for skill in skills.values():  # warm-up: numba's compiled kernels loaded
            skill.plan(cases[0][1][0], cases[0][0].goal, cases[0][0].scene)
        samples = {name: {"plan": [], "details": [], "time_path": []} for name in skills}
        digest = {name: hashlib.sha256() for name in skills}
        for round_ in range(rounds):
            for case, person in cases:
                for name, skill in skills.items():
                    start, goal, scene = person[0], case.goal, case.scene
                    plan, seconds = cpu(skill.plan, start, goal, scene)
                    details, detail_s = cpu(skill.plan_details, start, goal, scene)
                    _, timing_s = cpu(skill.timing_.time_path, plan.points, 1.0)
                    samples[name]["plan"].append(seconds)
                    samples[name]["details"].append(detail_s / (details.points.shape[0] - 1))
                    samples[name]["time_path"].append(timing_s)
                    if round_ == 0:
                        digest[name].update(np.ascontiguousarray(plan.points).tobytes())
    result = {"scenes": len(cases), "rounds": rounds, "skills": {}}
    print(f"{len(cases)} scenes x {rounds} rounds, median CPU (ms)")
    print(f"{'skill':<16} {'plan':>8} {'time_path':>10} {'MPC step':>9}  plans' hash")
    for name, s in samples.items():
        row = {k: float(np.median(v)) * 1e3 for k, v in s.items()}
        row["hash"] = digest[name].hexdigest()[:16]
        result["skills"][name] = row
        print(
            f"{name:<16} {row['plan']:8.1f} {row['time_path']:10.2f} {row['details']:9.3f}"
            f"  {row['hash']}"
        )
    result["machine"], result["git"] = machine_info(), git_state()
    args.output.mkdir(parents=True, exist_ok=True)
    print("wrote", write_json(args.output / "skill_speed.json", result))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
