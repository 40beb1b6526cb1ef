"""Robustness, units and speed of the inverse optimal control (lfdkit.emulate.IOC).

Run ``python benchmarks/emulate_robustness.py`` (``--quick`` for a smoke run of
a minute or two). Prints one table per section and writes
``robustness.json`` to ``--output`` (``benchmarks/results/emulate`` by
default). All work runs under ``threadpool_limits(1)`` (one BLAS thread).

1. Robustness
-------------
The thesis's artificial demonstrator (``artificial_obstacles``, true reward
``Q = 10``, ``P = diag(2500, 215)``) at ``--seed``: training sets of 3, 6, 12
and 24 demonstrations at 1×, 2×, 3× and 4× its default noise (1.5 mm), each
learned with ``IOC()`` (full horizon) along the Mean-Path of the set's five
obstacle-free demonstrations. Scored on eight test demonstrations drawn with
another seed (their scenes unseen) at the same noise, along the same
nominal: Pr = ``improvement(MSE_Mp, MSE_R)`` of the full-horizon plans, and
collisions of the plans in the test scenes and in the held-out cluttered and
concave scenes; for the learned reward and for the true reward (the same
planner and nominal). Also the largest relative parameter error, the
training loss at the learned and at the true parameters (planned the same
way, :meth:`IOC.training_loss`), whether the fit converged, the parameters
reported as not identified, and the fit's seconds.

2. Units
--------
The same demonstrations, nominal and scenes in metres and in millimetres
(×1000): relative difference of the learned ``Q`` and precisions (after
×10⁶) and of the plans in the held-out scenes (after ÷1000), relative to the
path's extent. Target: the plans ≤ 1e-6 (the parameters are reported).

3. Speed
--------
``sweeping`` seed 0, ``n_cup=4, n_marker=4, n_points=100`` (8 demonstrations ×
100 points, two classes, true nominal): ``IOC()`` and the staged
``IOC(horizon=8)``, medians of ``--repeats`` calls after one warm-up call
(numba compiles on first use; target: staged ≤ 2 s). The straightforward SciPy
IOC of ``benchmarks/emulate/`` (:func:`emulate.scipy_ioc`, full horizon then
MPC H=8, SciPy's own inner plans and finite-difference outer gradients) from
lfdkit's former default start, with a time limit per stage, against
``IOC(init=<same start>, horizon=8)`` in the same run (target: ≥ 10×; when
SciPy hits its limit the ratio is a lower bound). 3-D: ``da_vinci_marker``
seed 0 with 8 demonstrations and one class, ``IOC()`` and ``IOC(horizon=8)``
(target ≤ 10 s).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from _common import git_state, machine_info, package_versions
from threadpoolctl import threadpool_limits

from lfdkit.datasets.emulation import artificial_obstacles, load_emulation_dataset
from lfdkit.emulate import IOC, Reward, plan_path
from lfdkit.emulate.metrics import collisions, improvement, mse_paths, parameter_errors
from lfdkit.mimic import MeanPath
from lfdkit.model.scene import Scene

BASE_NOISE = 0.0015  # artificial_obstacles' default, metres
N_TEST = 8
HORIZON = 8


def progress(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def timed(fn):
    started = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - started


def plans(reward: Reward, nominal: np.ndarray, scenes) -> list[np.ndarray]:
    return [plan_path(reward, nominal, scene).points for scene in scenes]


def score(reward: Reward, nominal, test_demos, test_scenes, held_scenes) -> dict:
    test_plans = plans(reward, nominal, test_scenes)
    held_plans = plans(reward, nominal, held_scenes)
    mse_mp = mse_paths(nominal, test_demos)
    test_hits = [collisions(p, s) for p, s in zip(test_plans, test_scenes, strict=True)]
    held_hits = [collisions(p, s) for p, s in zip(held_plans, held_scenes, strict=True)]
    return {
        "pr": improvement(mse_mp, mse_paths(test_plans, test_demos)),
        "collisions_test": sum(test_hits),
        "collisions_held_out": sum(held_hits),
    }


# ------------------------------------------------------------------ 1. robustness
def robustness(seed: int, sizes, factors) -> list[dict]:
    rows = []
    for n_demos in sizes:
        for factor in factors:
            noise = BASE_NOISE * factor
            progress(f"   {n_demos} demos, noise {factor:g}x")
            train = artificial_obstacles(seed, n_demos=n_demos, noise=noise)
            test = artificial_obstacles(seed + 1000, n_demos=N_TEST, noise=noise, n_free=0)
            nominal = MeanPath().fit(train.free_demos).path_
            true = train.true_reward
            row = {"n_demos": n_demos, "noise_factor": factor, "noise_m": noise}
            try:
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    ioc, seconds = timed(
                        lambda train=train, nominal=nominal: IOC().fit(
                            train.demos, train.scenes, nominal
                        )
                    )
            except ValueError as exc:  # recorded, never fatal
                row["error"] = str(exc)
                rows.append(row)
                continue
            row.update(
                seconds=seconds,
                converged=bool(ioc.converged_),
                convergence_message=ioc.convergence_message_,
                warnings=[str(w.message) for w in caught],
                reward={"Q": ioc.reward_.nominal_weight}
                | {c: np.diag(p).tolist() for c, p in ioc.reward_.precisions.items()},
                max_parameter_error=max(parameter_errors(ioc.reward_, true).values())
                if "obstacle" in ioc.reward_.precisions
                else None,
                not_identified=[k for k, v in ioc.identifiability_.items() if not v["identified"]],
                loss_learned=ioc.loss_,
                loss_true=ioc.training_loss(true),
            )
            held = train.held_out_scenes
            try:
                row["learned"] = score(ioc.reward_, nominal, test.demos, test.scenes, held)
            except ValueError as exc:
                row["learned"] = {"error": str(exc)}
            row["true"] = score(true, nominal, test.demos, test.scenes, held)
            rows.append(row)
    return rows


def print_robustness(rows: list[dict]) -> None:
    print("\n1. Robustness (artificial demonstrator, full horizon, Mean-Path of free demos)")
    print(
        f"  {'demos':>5} {'noise':>5} | {'Pr learned':>10} {'Pr true':>8} | "
        f"{'coll. L/T':>9} | {'max par err':>11} | {'loss L/T':>8} | {'conv':>4} "
        f"{'not identified':<28} {'s':>5}"
    )
    for r in rows:
        if "error" in r:
            print(f"  {r['n_demos']:>5} {r['noise_factor']:>4g}x | error: {r['error']}")
            continue
        learned, true = r["learned"], r["true"]
        pr = f"{learned['pr']:>9.1f}%" if "pr" in learned else f"{'error':>10}"
        coll = (
            f"{learned.get('collisions_test', 0) + learned.get('collisions_held_out', 0)}"
            f"/{true['collisions_test'] + true['collisions_held_out']}"
        )
        err = r["max_parameter_error"]
        print(
            f"  {r['n_demos']:>5} {r['noise_factor']:>4g}x | {pr} {true['pr']:>7.1f}% | "
            f"{coll:>9} | {'-' if err is None else f'{err:.2f}':>11} | "
            f"{r['loss_learned'] / r['loss_true']:>8.3f} | {'yes' if r['converged'] else 'NO':>4} "
            f"{', '.join(r['not_identified']) or '-':<28} {r['seconds']:>5.1f}"
        )


# ------------------------------------------------------------------------ 2. units
def units_check(seed: int) -> dict:
    es = load_emulation_dataset("artificial", seed, n_demos=6, noise=2 * BASE_NOISE)
    nominal = MeanPath().fit(es.free_demos).path_

    def scaled(scene: Scene, factor: float) -> Scene:
        return Scene.from_arrays(scene.labels, factor * scene.positions, factor * scene.radii)

    metres = IOC().fit(es.demos, es.scenes, nominal)
    mm = IOC().fit(
        [1000.0 * d for d in es.demos], [scaled(s, 1000.0) for s in es.scenes], 1000.0 * nominal
    )
    reward_diff = max(
        abs(mm.reward_.nominal_weight * 1e6 / metres.reward_.nominal_weight - 1.0),
        *(
            float(np.max(np.abs(np.diag(mm.reward_.precisions[c]) * 1e6 / np.diag(p) - 1.0)))
            for c, p in metres.reward_.precisions.items()
        ),
    )
    extent = float(np.ptp(nominal, axis=0).max())
    plan_diff = 0.0
    for scene in es.held_out_scenes:
        a = metres.plan(nominal, scene).points
        b = mm.plan(1000.0 * nominal, scaled(scene, 1000.0)).points / 1000.0
        plan_diff = max(plan_diff, float(np.max(np.abs(a - b))) / extent)
    return {
        "reward_relative_difference": reward_diff,
        "plan_relative_difference": plan_diff,
        # The target is the plan (relative 1e-6); the parameters are reported: the
        # two fits see the same numbers to round-off, which L-BFGS's path amplifies.
        "pass": plan_diff <= 1e-6,
    }


# ------------------------------------------------------------------------ 3. speed
def median_time(fn, repeats: int) -> tuple[float, object]:
    fn()  # warm-up: numba compiles (or loads its cache)
    times, out = [], None
    for _ in range(repeats):
        out, seconds = timed(fn)
        times.append(seconds)
    return float(np.median(times)), out


def speed(repeats: int, scipy_limit: float) -> dict:
    es = load_emulation_dataset("sweeping", 0, n_cup=4, n_marker=4, n_points=100)
    demos, scenes, nominal = es.demos, es.scenes, es.nominal
    out = {"data": "sweeping seed 0, n_cup=4, n_marker=4, n_points=100, true nominal"}
    progress("   sweeping: full and staged fits")
    out["full_s"], _ = median_time(lambda: IOC().fit(demos, scenes, nominal), repeats)
    out["staged_s"], staged = median_time(
        lambda: IOC(horizon=HORIZON).fit(demos, scenes, nominal), repeats
    )
    out["staged_stages"] = [
        {k: v for k, v in s.items() if k in ("planner", "seconds", "iterations")}
        for s in staged.stages_
    ]
    out["staged_target_pass"] = out["staged_s"] <= 2.0

    import emulate  # benchmarks/emulate/: the straightforward SciPy IOC

    start = emulate.default_start(nominal, es.true_reward.classes, 2)
    progress(f"   SciPy IOC, full horizon then MPC H={HORIZON} (limit {scipy_limit:g} s a stage)")
    classes = es.true_reward.classes
    stage1 = emulate.scipy_ioc(demos, scenes, nominal, classes, start.theta, None, scipy_limit)
    stage2 = emulate.scipy_ioc(
        demos, scenes, nominal, classes, stage1["theta"], HORIZON, scipy_limit
    )
    same_s, same = median_time(
        lambda: IOC(init=start, horizon=HORIZON).fit(demos, scenes, nominal), repeats
    )
    scipy_s = stage1["seconds"] + stage2["seconds"]
    out["scipy"] = {
        "seconds": scipy_s,
        "finished": stage1["finished"] and stage2["finished"],
        "loss": stage2["loss"],
    }
    out["lfdkit_same_start"] = {"seconds": same_s, "loss": same.loss_}
    out["ratio"] = scipy_s / same_s
    out["ratio_is_lower_bound"] = not out["scipy"]["finished"]
    out["ratio_target_pass"] = out["ratio"] >= 10.0

    progress("   3-D: da Vinci, 8 demonstrations")
    vinci = load_emulation_dataset("da_vinci_marker", 0, n_demos=8)
    out["3d_full_s"], _ = median_time(
        lambda: IOC().fit(vinci.demos, vinci.scenes, vinci.nominal), max(1, repeats // 2)
    )
    out["3d_staged_s"], _ = median_time(
        lambda: IOC(horizon=HORIZON).fit(vinci.demos, vinci.scenes, vinci.nominal),
        max(1, repeats // 2),
    )
    out["3d_target_pass"] = max(out["3d_full_s"], out["3d_staged_s"]) <= 10.0
    return out


def print_speed(s: dict) -> None:
    print(f"\n3. Speed ({s['data']})")
    print(f"  IOC() {s['full_s']:.2f} s; IOC(horizon={HORIZON}) {s['staged_s']:.2f} s", end="")
    print(f" (target <= 2 s: {'PASS' if s['staged_target_pass'] else 'FAIL'})")
    bound = ">= " if s["ratio_is_lower_bound"] else ""
    print(
        f"  SciPy IOC {s['scipy']['seconds']:.1f} s (loss {s['scipy']['loss']:.3g}) vs lfdkit "
        f"from the same start {s['lfdkit_same_start']['seconds']:.2f} s "
        f"(loss {s['lfdkit_same_start']['loss']:.3g}): {bound}{s['ratio']:.0f}x "
        f"(target >= 10x: {'PASS' if s['ratio_target_pass'] else 'FAIL'})"
    )
    print(
        f"  3-D (da Vinci, 8 demos): IOC() {s['3d_full_s']:.1f} s, "
        f"IOC(horizon={HORIZON}) {s['3d_staged_s']:.1f} s "
        f"(target <= 10 s: {'PASS' if s['3d_target_pass'] else 'FAIL'})"
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).parent / "results" / "emulate"
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="smoke run: 3 and 12 demos at 1x and 4x noise, 1 timing repeat, SciPy limit 10 s",
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeats", type=int, default=None, help="timing repeats (default 3)")
    parser.add_argument("--scipy-limit", type=float, default=None, help="s per stage (120)")
    args = parser.parse_args(argv)
    sizes, factors = ((3, 12), (1.0, 4.0)) if args.quick else ((3, 6, 12, 24), (1.0, 2.0, 3.0, 4.0))
    repeats = args.repeats or (1 if args.quick else 3)
    scipy_limit = args.scipy_limit or (10.0 if args.quick else 120.0)
    args.output.mkdir(parents=True, exist_ok=True)
    wall = time.perf_counter()
    with threadpool_limits(limits=1):
        progress("1. robustness ...")
        rows = robustness(args.seed, sizes, factors)
        print_robustness(rows)
        progress("2. units ...")
        units = units_check(args.seed)
        print(
            "\n2. Units (metres vs millimetres): reward "
            f"{units['reward_relative_difference']:.1e}, "
            f"plans {units['plan_relative_difference']:.1e} relative "
            f"(target: plans <= 1e-6: {'PASS' if units['pass'] else 'FAIL'})"
        )
        progress("3. speed ...")
        speed_result = speed(repeats, scipy_limit)
        print_speed(speed_result)
    result = {
        "quick": args.quick,
        "seed": args.seed,
        "robustness": rows,
        "units": units,
        "speed": speed_result,
        "wall_s": time.perf_counter() - wall,
        "machine": machine_info(),
        "git": git_state(),
        "packages": package_versions(["lfdkit", "numpy", "scipy", "numba"]),
    }
    path = args.output / "robustness.json"
    path.write_text(json.dumps(result, indent=1, default=float))
    progress(f"wrote {path} in {result['wall_s']:.0f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
