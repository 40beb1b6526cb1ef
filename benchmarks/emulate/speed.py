"""Section 4 of the emulation benchmark: IOC fit and planning times."""

from __future__ import annotations

import time

import numpy as np

from lfdkit.datasets.emulation import load_emulation_dataset
from lfdkit.emulate import IOC, Corridor, Reward, plan_path
from lfdkit.emulate.metrics import parameter_errors
from lfdkit.emulate.planner import best_window
from lfdkit.emulate.problem import Problem
from lfdkit.model.scene import Scene

from .common import pct, progress, reward_record, reward_text, timed
from .reference import default_start, demo_targets, scipy_ioc, scipy_plan
from .spec import HORIZON, SPEED_HORIZON


def interleaved(tasks: dict, repeats: int) -> dict[str, list]:
    """Times of every task in rounds (one call of each per round); no warm-up round."""
    samples = {name: [] for name in tasks}
    results = {}
    for _ in range(repeats):
        for name, fn in tasks.items():
            results[name], seconds = timed(fn)
            samples[name].append(seconds)
    return {"times": {k: np.array(v) for k, v in samples.items()}, "results": results}


def fit_record(ioc: IOC, true: Reward) -> dict:
    return {
        "reward": reward_record(ioc.reward_),
        "loss": float(ioc.loss_),
        "stages": [{k: v for k, v in s.items()} for s in ioc.stages_],
        "max_error": max(parameter_errors(ioc.reward_, true).values()),
    }


def speed(fit_repeats: int, repeats: int, quick: bool, limit_s: float, vinci) -> dict:
    es = load_emulation_dataset("sweeping", 0, n_cup=4, n_marker=4, n_points=100)
    demos, scenes, nominal = es.demos, es.scenes, es.nominal
    classes, true = es.true_reward.classes, es.true_reward
    out = {
        "data": "sweeping seed 0, n_cup=4, n_marker=4, n_points=100; all 8 demos; true nominal",
        "n_demos": len(demos),
        "n_points": int(demos[0].shape[0]),
    }

    # (a), (b): implicit and finite-difference gradients, interleaved rounds.
    progress(f"   (a, b) IOC fits, {fit_repeats} interleaved rounds")
    runs = interleaved(
        {
            "implicit full": lambda: IOC().fit(demos, scenes, nominal),
            "implicit staged": lambda: IOC(horizon=HORIZON).fit(demos, scenes, nominal),
            "fd full": lambda: IOC(gradient="finite_difference").fit(demos, scenes, nominal),
        },
        fit_repeats,
    )
    times = runs["times"]
    out["fits"] = {
        name: {
            "median_s": float(np.median(t)),
            "samples_s": t.tolist(),
            **fit_record(runs["results"][name], true),
        }
        for name, t in times.items()
    }
    out["fd_ratio_full"] = float(np.median(times["fd full"] / times["implicit full"]))
    if quick:
        out["fits"]["fd staged"] = {"skipped": "--quick"}
    else:
        progress("   (b) finite-difference staged fit (once)")
        ioc, seconds = timed(
            lambda: IOC(horizon=HORIZON, gradient="finite_difference").fit(demos, scenes, nominal)
        )
        out["fits"]["fd staged"] = {"median_s": seconds, "samples_s": [seconds]}
        out["fits"]["fd staged"].update(fit_record(ioc, true))
        out["fd_ratio_staged"] = seconds / float(np.median(times["implicit staged"]))

    # (c) straightforward SciPy IOC, from the same start as lfdkit with init=...
    start_reward = default_start(nominal, classes, es.n_dims)
    progress(f"   (c) SciPy reference (limit {limit_s:.0f} s per stage)")
    corridor = Corridor.from_path(nominal, 100)
    agreement = []
    for (d0, offsets, found), scene in zip(demo_targets(corridor, demos), scenes, strict=True):
        problem = Problem.from_scene(true, corridor, scene)
        guide = np.where(found[1:, None], offsets[1:], 0.0)
        ours, cost, _, _ = problem.solve(d0, guide.copy())
        theirs = scipy_plan(problem, d0, guide)
        agreement.append(
            {
                "max_offset_difference_m": float(np.abs(theirs - ours).max()),
                "cost_scipy_minus_lfdkit": float(problem.cost(theirs) - cost),
            }
        )
    stage1 = scipy_ioc(demos, scenes, nominal, classes, start_reward.theta, None, limit_s)
    stage2 = scipy_ioc(demos, scenes, nominal, classes, stage1["theta"], HORIZON, limit_s)
    same = interleaved(
        {
            "lfdkit full (same start)": lambda: IOC(init=start_reward).fit(demos, scenes, nominal),
            "lfdkit staged (same start)": lambda: IOC(init=start_reward, horizon=HORIZON).fit(
                demos, scenes, nominal
            ),
        },
        fit_repeats,
    )
    out["scipy"] = {
        "start": reward_record(start_reward),
        "inner_plan_agreement": agreement,
        "full": stage1,
        "staged": stage2,
        "total_s": stage1["seconds"] + stage2["seconds"],
        "finished": stage1["finished"] and stage2["finished"],
    }
    for res in (stage1, stage2):
        res["max_error"] = max(
            parameter_errors(Reward.from_theta(res["theta"], classes, 2), true).values()
        )
    out["lfdkit_same_start"] = {
        name: {"median_s": float(np.median(t)), **fit_record(same["results"][name], true)}
        for name, t in same["times"].items()
    }

    # (d), (e) planning.
    progress(f"   (d, e) planning, {repeats} rounds")
    plans = {}
    scenes_d = {"one cup": scenes[0], "cluttered (4)": es.held_out_scenes[3]}
    for label, scene in scenes_d.items():
        plans[label] = time_planning(true, nominal, scene, repeats)
    if vinci is not None:
        scene = vinci.held_out_scenes[2]
        full = [timed(lambda: plan_path(vinci.true_reward, vinci.nominal, scene)) for _ in range(3)]
        mpc = [
            timed(lambda: plan_path(vinci.true_reward, vinci.nominal, scene, horizon=SPEED_HORIZON))
            for _ in range(3)
        ]
        plans["da Vinci 3-D (marker close)"] = {
            "full_median_s": float(np.median([t for _, t in full])),
            "full_newton_iterations": int(full[0][0].n_iter),
            "mpc_step_whole_call_s": float(np.median([t for _, t in mpc]))
            / (mpc[0][0].offsets.shape[0] - 1),
            "info_only": True,
        }
    out["planning"] = plans
    return out


def time_planning(reward: Reward, nominal: np.ndarray, scene: Scene, repeats: int) -> dict:
    plan_path(reward, nominal, scene, horizon=SPEED_HORIZON)  # warm-up (numba)
    mpc_times, full_times = [], []
    for _ in range(repeats):
        mpc, t = timed(lambda: plan_path(reward, nominal, scene, horizon=SPEED_HORIZON))
        mpc_times.append(t)
        full, t = timed(lambda: plan_path(reward, nominal, scene))
        full_times.append(t)
    steps = mpc.offsets.shape[0] - 1
    # Each window of the same MPC loop, timed on its own.
    corridor = Corridor.from_path(nominal, mpc.offsets.shape[0])
    problem = Problem.from_scene(reward, corridor, scene)
    n, m = problem.n, problem.m
    windows, replay_error = [], 0.0
    for _ in range(max(1, min(repeats, 5))):
        offsets = np.zeros((n + 1, m))
        offsets[0] = mpc.offsets[0]
        guess = np.zeros((min(SPEED_HORIZON, n), m))
        for k in range(n):
            stop = min(k + SPEED_HORIZON, n)
            window = problem.window(k, stop)
            guess = guess[: stop - k]
            if guess.shape[0] < stop - k:
                guess = np.vstack([guess, np.repeat(guess[-1:], stop - k - guess.shape[0], 0)])
            start = time.perf_counter()
            d = best_window(window, offsets[k], guess)[0]
            windows.append(time.perf_counter() - start)
            offsets[k + 1] = d[0]
            guess = np.vstack([d[1:], d[-1:]]) if d.shape[0] > 1 else d
        replay_error = max(replay_error, float(np.abs(offsets - mpc.offsets).max()))
    windows = np.array(windows)
    return {
        "n_obstacles": len(scene),
        "mpc_steps": steps,
        "mpc_call_median_s": float(np.median(mpc_times)),
        "mpc_step_whole_call_s": float(np.median(mpc_times)) / steps,
        "window_median_s": float(np.median(windows)),
        "window_p90_s": float(np.percentile(windows, 90)),
        "window_max_s": float(windows.max()),
        "window_fraction_over_1ms": float(np.mean(windows > 1e-3)),
        "window_fraction_over_2ms": float(np.mean(windows > 2e-3)),
        "window_samples": int(windows.size),
        "window_replay_max_difference": replay_error,
        "full_median_s": float(np.median(full_times)),
        "full_samples_s": full_times,
        "mpc_newton_iterations": int(mpc.n_iter),
        "full_newton_iterations": int(full.n_iter),
    }


def print_speed(s: dict) -> None:
    print(f"\n4. Speed ({s['data']}; {s['n_demos']} demos x {s['n_points']} points)")
    print(
        f"{'(a, b) IOC fit':<34} {'median':>9} {'stages s':>14} {'iters':>7} {'loss m²':>10} "
        f"{'max err':>8}"
    )
    for name, f in s["fits"].items():
        if "skipped" in f:
            print(f"{name:<34} skipped ({f['skipped']})")
            continue
        stages = "+".join(f"{st['seconds']:.2f}" for st in f["stages"])
        iters = "+".join(str(st["iterations"]) for st in f["stages"])
        print(
            f"{name:<34} {f['median_s']:>7.2f} s {stages:>14} {iters:>7} {f['loss']:>10.3e} "
            f"{pct(f['max_error']):>8}"
        )
    line = f"  finite differences / implicit: full {s['fd_ratio_full']:.1f}x"
    if "fd_ratio_staged" in s:
        line += f", staged {s['fd_ratio_staged']:.1f}x (one FD run / median implicit)"
    print(line)
    sc = s["scipy"]
    start = reward_text(Reward(sc["start"]["Q"], sc["start"]["precisions"]))
    print(f"(c) SciPy reference and lfdkit from the same start {start}")
    for key in ("full", "staged"):
        r = sc[key]
        ours = s["lfdkit_same_start"][f"lfdkit {key} (same start)"]
        status = "finished" if r["finished"] else "DID NOT FINISH"
        print(
            f"  SciPy {r['planner']:<15} {r['seconds']:>8.1f} s  {status:<15} outer it "
            f"{r['outer_iterations']:>3}, {r['loss_evaluations']:>4} losses, loss "
            f"{r['loss']:.3e}, max err {pct(r['max_error'])}; lfdkit {ours['median_s']:.2f} s,"
            f" loss {ours['loss']:.3e}, max err {pct(ours['max_error'])}"
        )
    agree = sc["inner_plan_agreement"]
    close = [a for a in agree if a["max_offset_difference_m"] < 1e-4]
    worse = [a["cost_scipy_minus_lfdkit"] for a in agree if a["max_offset_difference_m"] >= 1e-4]
    line = (
        f"  SciPy total {sc['total_s']:.1f} s (issue: about 13 s and 95 s). Inner plans at the "
        f"true reward, same start: {len(close)}/{len(agree)} agree within "
        f"{max([a['max_offset_difference_m'] for a in close], default=0):.1e} m"
    )
    if worse:
        line += (
            f"; elsewhere SciPy stops at a higher cost (+{min(worse):.2g} to +{max(worse):.2g},"
            f" offsets up to {max(a['max_offset_difference_m'] for a in agree) * 1e3:.1f} mm)"
        )
    print(line)
    print(
        f"{'(d, e) planning':<30} {'MPC H=12 step':>14} {'window med':>11} {'p90':>7} {'max':>7} "
        f"{'>2ms':>6} {'full plan':>10} {'Newton it':>10}"
    )
    for label, p in s["planning"].items():
        if p.get("info_only"):
            print(
                f"{label:<30} {p['mpc_step_whole_call_s'] * 1e3:>11.3f} ms {'':>11} {'':>7} "
                f"{'':>7} {'':>6} {p['full_median_s'] * 1e3:>7.1f} ms "
                f"{p['full_newton_iterations']:>10}  (information)"
            )
            continue
        print(
            f"{label:<30} {p['mpc_step_whole_call_s'] * 1e3:>11.3f} ms "
            f"{p['window_median_s'] * 1e3:>8.3f} ms {p['window_p90_s'] * 1e3:>7.3f} "
            f"{p['window_max_s'] * 1e3:>7.3f} {p['window_fraction_over_2ms'] * 100:>5.1f}% "
            f"{p['full_median_s'] * 1e3:>7.1f} ms {p['full_newton_iterations']:>10}"
        )
    print(
        "  MPC step = whole plan_path(horizon=12) call / its 99 steps (median over calls); window ="
        " planner.best_window alone, over every window (replay reproduces the plan to "
        f"{max(p.get('window_replay_max_difference', 0) for p in s['planning'].values()):.0e})"
    )
