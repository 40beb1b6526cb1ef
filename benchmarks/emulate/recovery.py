"""Section 1 of the emulation benchmark: IOC fits on the training demonstrations and recovery."""

from __future__ import annotations

import numpy as np

from lfdkit.datasets.emulation import load_emulation_dataset
from lfdkit.emulate import IOC
from lfdkit.emulate.metrics import parameter_errors

from .common import progress, reward_record, reward_text, timed
from .spec import HORIZON, RECOVERY_TARGET


def fit_one(es, nominal: np.ndarray, horizon: int | None, max_iter: int) -> dict:
    record = {"mode": "full" if horizon is None else f"staged H={horizon}", "error": None}
    try:
        ioc, seconds = timed(
            lambda: IOC(horizon=horizon, max_iter=max_iter).fit(
                es.train_demos, es.train_scenes, nominal
            )
        )
    except Exception as exc:  # recorded, never fatal
        record["error"] = f"{type(exc).__name__}: {exc}"
        return record
    stages = [
        {k: (float(v) if isinstance(v, (float, np.floating)) else v) for k, v in s.items()}
        for s in ioc.stages_
    ]
    errors = parameter_errors(ioc.reward_, es.true_reward)
    record.update(
        {
            "ioc": ioc,
            "seconds": seconds,
            "init_seconds": seconds - sum(s["seconds"] for s in stages),
            "stages": stages,
            "reward": reward_record(ioc.reward_),
            "errors": errors,
            "max_error": max(errors.values()),
            "failing": [k for k, v in errors.items() if v > RECOVERY_TARGET],
            "loss": float(ioc.loss_),
            "converged": bool(getattr(ioc, "converged_", True)),
        }
    )
    return record


def fit_and_recover(sets: dict, variants: dict, max_iter: int) -> list[dict]:
    rows = []
    for name, es in sets.items():
        for variant, info in variants[name].items():
            for horizon in (None, HORIZON):
                progress(f"   {name} / {variant} / {'full' if horizon is None else 'staged'}")
                row = fit_one(es, info["path"], horizon, max_iter)
                row.update({"dataset": name, "nominal": variant})
                rows.append(row)
    return rows


def noise_free_fits(names, seed: int, max_iter: int) -> list[dict]:
    """Full-horizon fits along the true nominal on the noise-free demonstrator's data.

    Separates the estimator from the demonstration noise: with ``noise=0`` the
    demonstrations are exactly the true optimal plans.
    """
    rows = []
    for name in names:
        progress(f"   {name} / true / full, noise-free demonstrations")
        es = load_emulation_dataset(name, seed, noise=0.0)
        row = fit_one(es, es.nominal, None, max_iter)
        row.update({"dataset": name, "nominal": "true", "noise": 0.0})
        rows.append(row)
    return rows


def print_fits(rows: list[dict], sets: dict, noise_free: list[dict] = ()) -> None:
    print(
        "\n1. Fit and recovery (training demonstrations; errors = |fitted - true| / true; "
        f"* > {RECOVERY_TARGET:.0%})"
    )
    print(
        f"{'set':<16} {'nominal':<7} {'fit':<10} {'parameters (Q, precision diagonals 1/m²)':<58} "
        f"{'errors':<38} {'init':>6} {'stages s':>12} {'iters':>7} {'loss m²':>9}"
    )
    for name, es in sets.items():
        print(f"{name:<16} {'':<7} {'TRUE':<10} {reward_text(es.true_reward):<58}")
        for r in (r for r in rows if r["dataset"] == name):
            if r["error"]:
                print(f"{'':<16} {r['nominal']:<7} {r['mode']:<10} FAILED {r['error']}")
                continue
            errs = " ".join(
                f"{v * 100:.0f}{'*' if v > RECOVERY_TARGET else ''}" for v in r["errors"].values()
            )
            stages = "+".join(f"{s['seconds']:.2f}" for s in r["stages"])
            iters = "+".join(str(s["iterations"]) for s in r["stages"])
            print(
                f"{'':<16} {r['nominal']:<7} {r['mode']:<10} "
                f"{reward_text(r['ioc'].reward_):<58} {errs:<38} {r['init_seconds']:>6.2f} "
                f"{stages:>12} {iters:>7} {r['loss']:>9.2e}"
            )
    for r in noise_free:
        if r["error"]:
            print(f"{r['dataset']:<16} {'true':<7} noise 0    FAILED {r['error']}")
            continue
        errs = " ".join(
            f"{v * 100:.1f}{'*' if v > RECOVERY_TARGET else ''}" for v in r["errors"].values()
        )
        print(
            f"{r['dataset']:<16} {'true':<7} {'noise 0':<10} {reward_text(r['ioc'].reward_):<58} "
            f"{errs:<38} {r['init_seconds']:>6.2f} {r['stages'][0]['seconds']:>12.2f} "
            f"{r['stages'][0]['iterations']:>7} {r['loss']:>9.2e}"
        )
    if noise_free:
        print(
            "  noise 0: the same seed's demonstrations without their noise (the exact optimal "
            "plans), true nominal: the estimator alone"
        )
    keys = {
        name: list(parameter_errors(es.true_reward, es.true_reward)) for name, es in sets.items()
    }
    print("  error columns: " + "; ".join(f"{n}: {', '.join(k)}" for n, k in keys.items()))
    print(
        "  init = the fit's grid of starting stiffnesses/widths (not in stages_); "
        "stages = full horizon (+ MPC), seconds and L-BFGS iterations"
    )
