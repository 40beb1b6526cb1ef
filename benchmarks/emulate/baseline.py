"""Section 3 of the emulation benchmark: movement_primitives' DMP with obstacle coupling.

Also used by ``benchmarks/robot.py`` (the same baseline in the sweeping experiment).
"""

from __future__ import annotations

import time

import numpy as np
from scipy.interpolate import make_interp_spline

from lfdkit.core.geometry import arc_length
from lfdkit.emulate.metrics import collisions, mse_paths
from lfdkit.model.scene import Scene

from .common import progress, sci
from .spec import (
    DMP_BETAS,
    DMP_DT,
    DMP_GAMMAS,
    DMP_WEIGHTS,
    LEARNED_VARIANTS,
    QUICK_BETAS,
    QUICK_GAMMAS,
)


def timed_motion(path: np.ndarray, duration: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The minimum-jerk motion along ``path`` sampled at ``n`` uniform times (as imitate.py)."""
    fraction = arc_length(path) / arc_length(path)[-1]
    spline = make_interp_spline(fraction, path, k=3, axis=0)
    times = np.linspace(0.0, duration, n)
    u = times / duration
    return times, spline(u**3 * (10.0 - 15.0 * u + 6.0 * u**2))


class ObstacleCoupling:
    """Sum of movement_primitives' 2-D obstacle-avoidance coupling terms, one per obstacle.

    movement_primitives offers one term per point obstacle; ``open_loop`` takes a
    single object with ``coupling(y, yd) -> (cd, cdd)``, so this adds them up.
    """

    def __init__(self, scene: Scene, gamma: float, beta: float) -> None:
        from movement_primitives.dmp import CouplingTermObstacleAvoidance2D

        self.terms = [
            CouplingTermObstacleAvoidance2D(o.position.copy(), gamma=gamma, beta=beta, fast=True)
            for o in scene
        ]

    def coupling(self, y, yd):
        cd, cdd = np.zeros_like(y), np.zeros_like(y)
        for term in self.terms:
            a, b = term.coupling(y, yd)
            cd += a
            cdd += b
        return cd, cdd


def peer_dmp(nominal: np.ndarray):
    from movement_primitives.dmp import DMP

    times, motion = timed_motion(nominal, 1.0, 1000)
    dmp = DMP(n_dims=2, execution_time=1.0, dt=DMP_DT, n_weights_per_dim=DMP_WEIGHTS)
    dmp.imitate(times, motion)
    dmp.configure(start_y=nominal[0], goal_y=nominal[-1])
    return dmp


def dmp_rollout(dmp, scene: Scene, gamma: float, beta: float) -> np.ndarray:
    with np.errstate(all="ignore"):
        if gamma == 0.0:
            return dmp.open_loop()[1]
        return dmp.open_loop(coupling_term=ObstacleCoupling(scene, gamma, beta))[1]


def dmp_score(dmp, demos, scenes, gamma: float, beta: float) -> float:
    paths = [dmp_rollout(dmp, s, gamma, beta) for s in scenes]
    if not all(np.all(np.isfinite(p)) for p in paths):
        return float("inf")
    try:
        return mse_paths(paths, demos)
    except ValueError:
        return float("inf")


def dmp_baseline(sets: dict, variants: dict, test_rows: list[dict], quick: bool) -> list[dict]:
    gammas, betas = (QUICK_GAMMAS, QUICK_BETAS) if quick else (DMP_GAMMAS, DMP_BETAS)
    rows = []
    for name, es in sets.items():
        if es.n_dims != 2:
            rows.append({"dataset": name, "skipped": "3-D: the coupling term benchmarked is 2-D"})
            continue
        for variant in LEARNED_VARIANTS:
            if variant not in variants[name]:
                continue
            progress(f"   {name} / {variant}: grid {len(gammas)}x{len(betas)}")
            nominal = variants[name][variant]["path"]
            dmp = peer_dmp(nominal)
            start = time.perf_counter()
            grid = []
            for gamma in gammas:
                for beta in betas if gamma else betas[:1]:
                    score = dmp_score(dmp, es.train_demos, es.train_scenes, gamma, beta)
                    grid.append({"gamma": gamma, "beta": beta, "train_mse": score})
            grid_s = time.perf_counter() - start
            best = min(grid, key=lambda g: g["train_mse"])
            plain = grid[0]
            test = dmp_score(dmp, es.test_demos, es.test_scenes, best["gamma"], best["beta"])
            test_plain = dmp_score(dmp, es.test_demos, es.test_scenes, 0.0, 0.0)
            ours = next(r for r in test_rows if r["dataset"] == name and r["nominal"] == variant)
            rollouts = [dmp_rollout(dmp, s, best["gamma"], best["beta"]) for s in es.test_scenes]
            rows.append(
                {
                    "dataset": name,
                    "nominal": variant,
                    "grid": grid,
                    "grid_seconds": grid_s,
                    "best_gamma": best["gamma"],
                    "best_beta": best["beta"],
                    "train_mse_best": best["train_mse"],
                    "train_mse_plain": plain["train_mse"],
                    "test_mse": test,
                    "test_mse_plain": test_plain,
                    "test_collisions": int(
                        sum(collisions(p, s) for p, s in zip(rollouts, es.test_scenes, strict=True))
                    ),
                    "lfdkit_test_mse_full": ours.get("mse_full"),
                    "lfdkit_test_mse_mpc": ours.get("mse_mpc"),
                    "factor_full": test / ours["mse_full"] if ours.get("mse_full") else None,
                    "factor_mpc": test / ours["mse_mpc"] if ours.get("mse_mpc") else None,
                    "_rollouts": rollouts,
                }
            )
    return rows


def print_dmp(rows: list[dict]) -> None:
    print(
        "\n3. Baseline: movement_primitives DMP + CouplingTermObstacleAvoidance2D per obstacle, "
        "gamma, beta by grid search on the training demonstrations (MSE_R m²)"
    )
    print(
        f"{'set':<16} {'nominal':<7} {'best gamma':>7} {'beta':>6} {'train':>9} {'train g=0':>10} "
        f"{'test':>9} {'test g=0':>9} {'coll':>4} {'lfdkit full':>11} {'MPC':>9} "
        f"{'DMP/lfdkit':>10} {'grid s':>7}"
    )
    for r in rows:
        if "skipped" in r:
            print(f"{r['dataset']:<16} skipped: {r['skipped']}")
            continue
        print(
            f"{r['dataset']:<16} {r['nominal']:<7} {r['best_gamma']:>7.0f} {r['best_beta']:>6.2f} "
            f"{sci(r['train_mse_best']):>9} {sci(r['train_mse_plain']):>10} "
            f"{sci(r['test_mse']):>9} {sci(r['test_mse_plain']):>9} {r['test_collisions']:>4} "
            f"{sci(r['lfdkit_test_mse_full']):>11} {sci(r['lfdkit_test_mse_mpc']):>9} "
            f"{(r['factor_full'] or np.nan):>9.1f}x {r['grid_seconds']:>7.1f}"
        )
    print("  g=0: the DMP without coupling; coll = collisions of the tuned DMP in the test scenes")
