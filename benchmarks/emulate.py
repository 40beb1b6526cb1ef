"""Emulation benchmark: inverse optimal control, MPC planning, baselines and speed.

Run ``python benchmarks/emulate.py`` (``--help`` for options; ``--quick`` for a
smoke run of about two minutes). Prints one table per section and a final
targets table (PASS/FAIL), writes ``emulate.json`` and the figures
``emulate_reward_<set>.png``, ``emulate_heldout.png``, ``emulate_transfer.png``
and ``emulate_baseline.png`` to ``--output`` (``benchmarks/results/emulate`` by
default). Exits 0 even when a target fails. All work runs under
``threadpoolctl.threadpool_limits(1)`` (one BLAS thread: the machine has two
cores and may be shared).

Data: ``load_emulation_dataset(name, seed)`` for ``artificial`` (thesis §5.5,
2-D), ``da_vinci_marker`` (§6.3, 3-D) and ``sweeping`` (§6.4, 2-D, classes cup
and marker); every set has a known true reward and a train/test split.

Nominal paths
-------------
The reward is relative to a nominal path. Each set is learned with each of:

* ``train``: ``MeanPath(center="biweight").fit(train_demos).path_``, the
  generalized path of the TRAINING demonstrations (the obstacle demonstrations
  themselves), as in the thesis's pipeline;
* ``free``: ``MeanPath().fit(free_demos).path_``, the generalized path of the
  set's obstacle-free demonstrations (``EmulationSet.free_demos``; skipped
  when the set has none);
* ``true``: the true nominal (a reference row: what a perfect mimicking layer
  would give).

Each table row says which. ``--figure-nominal`` (default ``free``, else
``train``) picks the nominal of sections 5 and of the figures.

1. Fit and recovery
-------------------
``IOC()`` (full horizon) and ``IOC(horizon=8)`` (staged: full horizon, then
MPC) on the training demonstrations in their scenes. Reported: fitted and
true ``Q`` and diagonal precisions, ``lfdkit.metrics.parameter_errors``
(target: every parameter within 10 % of the truth), seconds of the initial
grid (the fit's total time minus its stages), of each stage, L-BFGS
iterations, training loss (mean squared lateral distance, m²). For reference
(not with ``--quick``), ``IOC()`` along the true nominal on the noise-free
demonstrator's data (``noise=0``, same seed): the estimator without the
demonstration noise.

2. Evaluation
-------------
Test demonstrations (their scenes are not seen in training):

* MSE_R (``mse_paths``, m²) of the plans of the learned full-horizon reward
  (full horizon), of the staged reward (MPC H=8), of the true reward along the
  true nominal (full horizon: ``true_plan``; and MPC H=8), and MSE_Mp of
  replaying the nominal;
* Pr = ``improvement(MSE_Mp, MSE_R)`` (target ≥ 90 %) and the ratio
  MSE_R(learned)/MSE_R(true) with the same planner (target ≤ 1.5);
* for the thesis's figures: sweeping Pr per class (thesis 96.5 % cup, 92.7 %
  marker) and da Vinci train/test MSE_R (thesis 0.175/0.091 in its units).

Held-out scenes (``held_out_scenes``: cluttered, concave pocket, mixed cup and
marker, unseen marker positions) have no demonstrations: every plan is compared
with the true-parameter full-horizon plan (``true_plan``). Reported per
planner: collisions (``collisions``), minimum clearance (``clearance``, m) and
the MSE to ``true_plan``. Target: no collision in the cluttered and concave
scenes with the learned reward, judged for full horizon and MPC separately.

3. Baseline: DMP with obstacle-avoidance coupling
--------------------------------------------------
movement_primitives ``DMP(n_dims=2, execution_time=1, dt=0.01,
n_weights_per_dim=30)`` imitating the nominal (the minimum-jerk motion along
it sampled at 1000 uniform times, as the ``m_p dense`` row of
``benchmarks/imitate.py``: with 100 unevenly timed samples the peer's finite
differences make it overshoot), ``configure`` to the nominal's start and
goal, ``open_loop(coupling_term=...)`` with one
``CouplingTermObstacleAvoidance2D(obstacle, gamma, beta, fast=True)`` per
obstacle, summed by :class:`ObstacleCoupling`. γ and β tuned by grid search
(γ = 0 included: the plain DMP) on the TRAINING demonstrations (min MSE_R);
the best grid point is then scored on the test demonstrations. 2-D sets only:
the package's coupling term is 2-D (``CouplingTermObstacleAvoidance3D``
exists, but the brief scopes the baseline to the 2-D sets), so da Vinci is
skipped. Target: lfdkit's test MSE_R (full horizon) at least 3× lower.

4. Speed
--------
``load_emulation_dataset("sweeping", 0, n_cup=4, n_marker=4, n_points=100)``:
8 demonstrations × 100 points, two classes, all used for training, along the
true nominal. Times are medians of interleaved rounds (each method once per
round, so each sees the same machine load); a ratio is the median of the
per-round ratios.

(a) ``IOC().fit`` (target < 2 s) and ``IOC(horizon=8).fit`` (target < 15 s).
(b) The same with ``gradient="finite_difference"`` (the staged FD fit runs once,
    after the rounds: it takes minutes; skipped with ``--quick``).
(c) A straightforward SciPy implementation (:func:`scipy_ioc`): each inner plan
    by ``scipy.optimize.minimize(method="L-BFGS-B")`` over the actions with
    their bounds, cost and gradient from the planner's own
    ``Problem.from_scene(...).derivatives``, started from the demonstration (MPC: each
    window from the previous one shifted, the first from the demonstration);
    the outer loop ``minimize(L-BFGS-B)`` on the same scaled loss with
    SciPy's finite-difference gradient (step 1e-4 in log-parameters), a time
    limit per stage (``--scipy-limit``, 120 s), "did not finish" recorded with
    the best point evaluated. Both SciPy and lfdkit start from the same reward
    (lfdkit's former default: ``Q = 10 / extent²``, widths 5 % of the extent),
    lfdkit via ``IOC(init=...)``; the SciPy stage 2 starts from its stage 1.
(d) MPC H=12 in a sweeping scene (one cup) and the cluttered held-out scene:
    the whole ``plan_path(..., horizon=12)`` call divided by its 99 MPC steps
    (median over calls), and each window's ``planner.best_window`` timed
    directly (median, 90th percentile and max over all windows of several
    plans; the replayed loop is checked to reproduce the plan). Target
    < 1 ms median (the per-window median in the one-cup scene).
(e) A 100-point full-horizon ``plan_path`` (target < 100 ms median), same
    scenes; for information also a 3-D da Vinci held-out scene.

5. Composition and transfer (thesis §6.3.3, Figs 6.12-6.13)
-----------------------------------------------------------
Composition: on sweeping, ``IOC()`` on the cup-only training scenes and on the
marker-only ones, joined by ``Reward.combined`` (Q of the cup fit), planned in
the mixed and cluttered held-out scenes; compared with the jointly learned
reward and the true-parameter plan. Transfer: the reward learned on the
artificial task planned along other nominals (the straight 0.8 m sweeping
nominal and a quarter circle of radius 0.5 m) in a one-obstacle and a
four-obstacle cluttered scene; deviation (MSE) from the true-parameter plan
along the same nominal, collisions and clearance.
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
from scipy.interpolate import make_interp_spline
from scipy.optimize import minimize
from threadpoolctl import threadpool_limits

from lfdkit.datasets.emulation import load_emulation_dataset
from lfdkit.emulate import IOC, Corridor, Reward, Scene, plan_path
from lfdkit.emulate.planner import best_window
from lfdkit.emulate.problem import Problem
from lfdkit.geometry import arc_length, left_normals, project_onto_polyline
from lfdkit.metrics import clearance, collisions, improvement, mse_paths, parameter_errors
from lfdkit.mimic import MeanPath
from lfdkit.plot import emulation_grid

DATASETS = ("artificial", "da_vinci_marker", "sweeping")
VARIANTS = ("train", "free", "true")
LEARNED_VARIANTS = ("train", "free")
HORIZON = 8
SPEED_HORIZON = 12
RECOVERY_TARGET = 0.10
PR_TARGET = 90.0
RATIO_TARGET = 1.5
DMP_FACTOR_TARGET = 3.0
FIT_FULL_TARGET_S = 2.0
FIT_STAGED_TARGET_S = 15.0
MPC_STEP_TARGET_S = 1e-3
PLAN_TARGET_S = 0.1
DMP_GAMMAS = (0.0, 10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0)
DMP_BETAS = (0.5, 1.0, 2.0, 4.0, 20.0 / np.pi, 10.0, 20.0)
QUICK_GAMMAS = (0.0, 100.0, 1000.0)
QUICK_BETAS = (2.0, 20.0 / np.pi, 20.0)
DMP_WEIGHTS = 30
DMP_DT = 0.01
SCIPY_FD_STEP = 1e-4
#: Held-out scene names in the order of ``EmulationSet.held_out_scenes``.
HELD_OUT_NAMES = {
    "artificial": ("cluttered", "concave"),
    "da_vinci_marker": (
        "marker (0.035, 0.009)",
        "marker (0.05, -0.004)",
        "marker close",
        "2 markers",
    ),
    "sweeping": ("mixed cup+marker 1", "mixed marker+cup 2", "mixed cup+marker 3", "cluttered"),
}
#: Held-out scenes where the learned reward must not collide.
NO_COLLISION_SCENES = {"artificial": ("cluttered", "concave"), "sweeping": ("cluttered",)}
THESIS = {
    "artificial": "Q=10, R=[2500, 215], MSE_R 1.08e-3",
    "da_vinci_marker": "train/test MSE 0.175/0.091 (thesis units)",
    "sweeping": "Pr 96.5 % (cup), 92.7 % (marker)",
}
PLAN_NAMES = {
    "learned_full": "learned full horizon",
    "learned_mpc": f"learned MPC H={HORIZON}",
    "true_full": "true parameters (full)",
    "true_mpc": f"true parameters MPC H={HORIZON}",
}


# ----------------------------------------------------------------------------- helpers
_STARTED = time.perf_counter()


def progress(message: str) -> None:
    sys.stdout.flush()
    print(f"[{time.perf_counter() - _STARTED:6.1f} s] {message}", file=sys.stderr, flush=True)


def timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def pct(x: float | None) -> str:
    return "—" if x is None or not np.isfinite(x) else f"{100 * x:.1f}%"


def sci(x: float | None, digits: int = 2) -> str:
    return "—" if x is None or not np.isfinite(x) else f"{x:.{digits}e}"


def reward_record(reward: Reward) -> dict:
    return {
        "Q": float(reward.nominal_weight),
        "precisions": {c: np.diag(m).tolist() for c, m in reward.precisions.items()},
    }


def reward_text(reward: Reward) -> str:
    parts = [f"Q={reward.nominal_weight:.4g}"]
    for label, matrix in reward.precisions.items():
        parts.append(f"{label}=[{', '.join(f'{v:.4g}' for v in np.diag(matrix))}]")
    return " ".join(parts)


def mean_path(demos, **kwargs) -> tuple[np.ndarray, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        path = MeanPath(**kwargs).fit(demos).path_
    return path, [f"{w.category.__name__}: {w.message}" for w in caught]


def safe_plan(fn) -> tuple[np.ndarray | None, str | None]:
    """``fn()`` returns a Plan; errors (e.g. a start inside an obstacle) are recorded."""
    try:
        return fn().points, None
    except Exception as exc:  # recorded, never fatal
        return None, f"{type(exc).__name__}: {exc}"


def scene_metrics(path: np.ndarray | None, scene: Scene, reference: np.ndarray | None) -> dict:
    if path is None:
        return {"collisions": None, "min_clearance": None, "mse_to_true": None}
    gaps = clearance(path, scene)
    return {
        "collisions": collisions(path, scene),
        "min_clearance": float(gaps.min()) if gaps.size else None,
        "mse_to_true": None if reference is None else mse_paths(path, [reference]),
    }


def held_out_names(name: str, n: int) -> list[str]:
    names = list(HELD_OUT_NAMES.get(name, ()))
    return names if len(names) == n else [f"held-out {i}" for i in range(n)]


def nominal_variants(es, include) -> dict[str, dict]:
    """The nominal paths a set is learned with (module notes)."""
    out = {}
    if "train" in include:
        path, caught = mean_path(es.train_demos, center="biweight")
        out["train"] = {
            "path": path,
            "source": "MeanPath(center='biweight') of the training demonstrations",
            "warnings": caught,
        }
    free = getattr(es, "free_demos", None)
    if "free" in include and free:
        path, caught = mean_path(free)
        out["free"] = {
            "path": path,
            "source": f"MeanPath() of the {len(free)} obstacle-free demonstrations",
            "warnings": caught,
        }
    if "true" in include:
        out["true"] = {"path": es.nominal, "source": "true nominal (reference)", "warnings": []}
    for info in out.values():
        distance = project_onto_polyline(info["path"], es.nominal)[2]
        info["deviation_max"] = float(distance.max())
        info["deviation_mean"] = float(distance.mean())
    return out


# --------------------------------------------------------------------- 1. fit + recovery
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


# ----------------------------------------------------------------------- 2. evaluation
def true_plans(es, horizon: int | None, scenes) -> list[np.ndarray]:
    if horizon is None:
        return [es.true_plan(s) for s in scenes]
    return [plan_path(es.true_reward, es.nominal, s, horizon=horizon).points for s in scenes]


def evaluate(
    sets: dict, variants: dict, fits: list[dict], train_mse: bool = True
) -> tuple[list[dict], list[dict]]:
    """Test-demonstration rows and held-out-scene rows (section 2)."""
    test_rows, held_rows = [], []
    for name, es in sets.items():
        progress(f"   {name}: true-parameter plans")
        reference = {
            "test_full": true_plans(es, None, es.test_scenes),
            "test_mpc": true_plans(es, HORIZON, es.test_scenes),
            "held_full": true_plans(es, None, es.held_out_scenes),
            "held_mpc": true_plans(es, HORIZON, es.held_out_scenes),
        }
        mse_true = {
            "full": mse_paths(reference["test_full"], es.test_demos),
            "mpc": mse_paths(reference["test_mpc"], es.test_demos),
        }
        names = held_out_names(name, len(es.held_out_scenes))
        for variant, info in variants[name].items():
            progress(f"   {name} / {variant}: learned plans")
            nominal = info["path"]
            by = {r["mode"]: r for r in fits if r["dataset"] == name and r["nominal"] == variant}
            full, staged = by.get("full"), by.get(f"staged H={HORIZON}")
            learned = {}
            if full and not full["error"]:
                learned["full"] = (full["ioc"], None)
            if staged and not staged["error"]:
                learned["mpc"] = (staged["ioc"], HORIZON)
            mse_mp = mse_paths(nominal, es.test_demos)
            row = {
                "dataset": name,
                "nominal": variant,
                "mse_mp": mse_mp,
                "mse_true_full": mse_true["full"],
                "mse_true_mpc": mse_true["mpc"],
                "pr_true_full": improvement(mse_mp, mse_true["full"]),
                "pr_true_mpc": improvement(mse_mp, mse_true["mpc"]),
                "collisions_test": {},
                "_plans": {"true_full": reference["test_full"]},
            }
            for key, (ioc, horizon) in learned.items():
                plans, errors = plan_all(ioc, nominal, es.test_scenes, horizon)
                row["_plans"][f"learned_{key}"] = plans
                row["collisions_test"][key] = int(
                    sum(
                        collisions(p, s)
                        for p, s in zip(plans, es.test_scenes, strict=True)
                        if p is not None
                    )
                )
                if errors:
                    # A refused plan (e.g. a start within the learned response) leaves no MSE.
                    row[f"errors_{key}"] = errors
                    continue
                mse = mse_paths(plans, es.test_demos)
                row[f"mse_{key}"] = mse
                row[f"pr_{key}"] = improvement(mse_mp, mse)
                row[f"ratio_{key}"] = mse / mse_true[key]
                if key == "full" and name == "sweeping":
                    row["pr_by_class"] = pr_by_class(es, plans, nominal)
                if key == "full" and train_mse:
                    train_plans, train_errors = plan_all(ioc, nominal, es.train_scenes, None)
                    row["mse_mp_train"] = mse_paths(nominal, es.train_demos)
                    if not train_errors:
                        row["mse_train_full"] = mse_paths(train_plans, es.train_demos)
            test_rows.append(row)
            for i, scene in enumerate(es.held_out_scenes):
                ref = reference["held_full"][i]
                planners = {
                    "true_full": (ref, None),
                    "true_mpc": (reference["held_mpc"][i], None),
                }
                for key, (ioc, horizon) in learned.items():
                    planners[f"learned_{key}"] = safe_plan(
                        lambda ioc=ioc, horizon=horizon, scene=scene, nominal=nominal: ioc.plan(
                            nominal, scene, horizon=horizon
                        )
                    )
                held_rows.append(
                    {
                        "dataset": name,
                        "nominal": variant,
                        "scene": names[i],
                        "n_obstacles": len(scene),
                        "classes": list(scene.labels),
                        "planners": {
                            key: {**scene_metrics(path, scene, ref), "error": err, "_path": path}
                            for key, (path, err) in planners.items()
                        },
                    }
                )
    return test_rows, held_rows


def plan_all(ioc, nominal, scenes, horizon) -> tuple[list, list[str]]:
    """Plans of ``ioc`` in every scene (None where refused) and the error messages."""
    plans, errors = [], []
    for j, scene in enumerate(scenes):
        path, err = safe_plan(lambda scene=scene: ioc.plan(nominal, scene, horizon=horizon))
        plans.append(path)
        if err:
            errors.append(f"scene {j}: {err}")
    return plans, errors


def pr_by_class(es, plans, nominal) -> dict:
    out = {}
    for label in es.classes:
        idx = [j for j, s in enumerate(es.test_scenes) if label in s.classes]
        if not idx:
            continue
        demos = [es.test_demos[j] for j in idx]
        mse = mse_paths([plans[j] for j in idx], demos)
        out[label] = improvement(mse_paths(nominal, demos), mse)
    return out


def print_evaluation(test_rows: list[dict], held_rows: list[dict]) -> None:
    print(
        "\n2a. Test demonstrations: MSE_R [m²] of each planner, Pr = improvement over replaying"
        " the nominal (MSE_Mp), ratio = learned / true-parameter MSE_R (same planner)"
    )
    print(
        f"{'set':<16} {'nominal':<7} {'MSE_Mp':>9} {'learned':>9} {'Pr':>6} {'ratio':>6} "
        f"{'MPC H=8':>9} {'Pr':>6} {'ratio':>6} {'true':>9} {'true MPC':>9} {'coll':>5}  thesis"
    )
    for r in test_rows:
        coll = "/".join(str(v) for v in r["collisions_test"].values())
        print(
            f"{r['dataset']:<16} {r['nominal']:<7} {sci(r['mse_mp']):>9} "
            f"{sci(r.get('mse_full')):>9} {r.get('pr_full', np.nan):>5.1f}% "
            f"{r.get('ratio_full', np.nan):>6.2f} {sci(r.get('mse_mpc')):>9} "
            f"{r.get('pr_mpc', np.nan):>5.1f}% {r.get('ratio_mpc', np.nan):>6.2f} "
            f"{sci(r['mse_true_full']):>9} {sci(r['mse_true_mpc']):>9} {coll:>5}  "
            f"{THESIS.get(r['dataset'], '') if r['nominal'] == 'train' else ''}"
        )
    for r in test_rows:
        extra = []
        for key in ("full", "mpc"):
            if f"errors_{key}" in r:
                extra.append(
                    f"{key}: {len(r[f'errors_{key}'])} test plans refused: {r[f'errors_{key}'][0]}"
                )
        if "pr_by_class" in r:
            extra.append(
                "Pr by class "
                + ", ".join(f"{c} {v:.1f}%" for c, v in r["pr_by_class"].items())
                + " (thesis cup 96.5 %, marker 92.7 %)"
            )
        if r["dataset"] == "da_vinci_marker" and "mse_train_full" in r:
            extra.append(
                f"train/test MSE_R {r['mse_train_full'] * 1e6:.3f}/{r['mse_full'] * 1e6:.3f} mm²"
                f" (replay {r['mse_mp_train'] * 1e6:.2f}/{r['mse_mp'] * 1e6:.2f} mm²; "
                "thesis 0.175/0.091, units not stated)"
            )
        if extra:
            print(f"  {r['dataset']} / {r['nominal']}: " + "; ".join(extra))
    print("  coll = collisions of the learned full-horizon / MPC plans in the test scenes")

    print(
        "\n2b. Held-out scenes: collisions, minimum clearance [mm] and MSE to the "
        "true-parameter full-horizon plan [m²], per planner"
    )
    keys = ("learned_full", "learned_mpc", "true_full", "true_mpc")
    head = f"{'set':<16} {'nominal':<7} {'scene':<22} {'n':>2}"
    for key in keys:
        head += f" {PLAN_NAMES[key][:24]:>26}"
    print(head)
    for r in held_rows:
        line = f"{r['dataset']:<16} {r['nominal']:<7} {r['scene'][:22]:<22} {r['n_obstacles']:>2}"
        for key in keys:
            m = r["planners"].get(key)
            if m is None or m["collisions"] is None:
                cell = "error" if m and m.get("error") else "—"
            else:
                mse = "" if key == "true_full" else f" {sci(m['mse_to_true'], 1)}"
                cell = f"{m['collisions']}c {m['min_clearance'] * 1e3:5.1f}{mse}"
            line += f" {cell:>26}"
        print(line)


# ------------------------------------------------------------------------- 3. DMP
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


# ----------------------------------------------------------------------- 4. speed
class _OutOfTime(Exception):
    pass


def _targets_of(corridor: Corridor, demos) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """(start offset, lateral offsets, found) of each demonstration, as IOC prepares them."""
    out = []
    for demo in demos:
        offsets, found = corridor.offsets_of(demo)
        start = offsets[0] if found[0] else offsets[np.argmax(found)]
        out.append((start, offsets, found))
    return out


def scipy_plan(problem, d0: np.ndarray, init: np.ndarray, **options) -> np.ndarray:
    """Offsets minimising the planner's cost by L-BFGS-B over the bounded actions."""
    n, m = problem.n, problem.m
    bound = problem.max_step

    def fun(actions):
        d = d0 + np.cumsum(actions.reshape(n, m), axis=0)
        cost, gradient, _ = problem.derivatives(d)
        return cost, np.cumsum(gradient[::-1], axis=0)[::-1].ravel()

    a0 = np.clip(np.diff(np.vstack([d0[None], init]), axis=0), -bound, bound).ravel()
    result = minimize(
        fun,
        a0,
        jac=True,
        method="L-BFGS-B",
        bounds=[(-bound, bound)] * a0.size,
        options={"maxiter": 1000, "ftol": 1e-12, "gtol": 1e-9, **options},
    )
    return d0 + np.cumsum(result.x.reshape(n, m), axis=0)


def scipy_mpc(problem, d0: np.ndarray, guide: np.ndarray, horizon: int) -> np.ndarray:
    """Receding horizon: each window by :func:`scipy_plan`, warm-started from the last one."""
    n, m = problem.n, problem.m
    offsets = np.zeros((n, m))
    anchor = d0
    guess = guide[: min(horizon, n)].copy()
    for k in range(n):
        stop = min(k + horizon, n)
        guess = guess[: stop - k]
        if guess.shape[0] < stop - k:
            guess = np.vstack([guess, np.repeat(guess[-1:], stop - k - guess.shape[0], axis=0)])
        w = scipy_plan(problem.window(k, stop), anchor, guess)
        offsets[k] = w[0]
        anchor = w[0]
        guess = np.vstack([w[1:], w[-1:]]) if w.shape[0] > 1 else w
    return offsets


def scipy_ioc(demos, scenes, nominal, classes, theta0, horizon, limit_s: float) -> dict:
    """The straightforward SciPy IOC of section 4 (c); stops after ``limit_s`` seconds."""
    corridor = Corridor.from_path(nominal, 100)
    items = _targets_of(corridor, demos)
    q = corridor.n_dims
    count = sum(int(f[1:].sum()) for _, _, f in items)
    scale = float(np.mean([np.mean(off[f] ** 2) for _, off, f in items]))
    best = {"loss": np.inf, "theta": np.array(theta0, float)}
    evaluations, iterations = [0], [0]
    start = time.perf_counter()

    def loss(theta: np.ndarray) -> float:
        if time.perf_counter() - start > limit_s:
            raise _OutOfTime
        reward = Reward.from_theta(theta, classes, q)
        total = 0.0
        for (d0, offsets, found), scene in zip(items, scenes, strict=True):
            problem = Problem.from_scene(reward, corridor, scene)
            guide = np.where(found[1:, None], offsets[1:], 0.0)
            if horizon is None:
                d = scipy_plan(problem, d0, guide)
            else:
                d = scipy_mpc(problem, d0, guide, horizon)
            total += float(np.sum(np.where(found[1:, None], d - offsets[1:], 0.0) ** 2)) / count
        evaluations[0] += 1
        if total < best["loss"]:
            best.update(loss=total, theta=np.array(theta))
        return total / scale

    def callback(*_):
        iterations[0] += 1

    finished, message = True, ""
    try:
        result = minimize(
            loss,
            np.array(theta0, float),
            method="L-BFGS-B",
            bounds=[(-20.0, 25.0)] * len(theta0),
            callback=callback,
            options={"maxiter": 200, "ftol": 1e-10, "gtol": 1e-12, "eps": SCIPY_FD_STEP},
        )
        message = str(result.message)
        theta = result.x
    except _OutOfTime:
        finished, message = False, f"did not finish in {limit_s:.0f} s"
        theta = best["theta"]
    seconds = time.perf_counter() - start
    return {
        "planner": "full horizon" if horizon is None else f"MPC H={horizon}",
        "finished": finished,
        "seconds": seconds,
        "message": message,
        "outer_iterations": iterations[0],
        "loss_evaluations": evaluations[0],
        "loss": float(best["loss"]),
        "theta": np.asarray(theta).tolist(),
        "reward": reward_record(Reward.from_theta(theta, classes, q)),
    }


def default_start(nominal: np.ndarray, classes, q: int) -> Reward:
    """lfdkit's former default start: ``Q = 10 / extent²``, every width 5 % of the extent."""
    points = Corridor.from_path(nominal, 100).points
    extent = float(np.ptp(points, axis=0).max())
    width = 0.05 * extent
    return Reward(10.0 / extent**2, {c: np.full(q, 1.0 / width**2) for c in classes})


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
    for (d0, offsets, found), scene in zip(_targets_of(corridor, demos), scenes, strict=True):
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


# ------------------------------------------------------------ 5. composition + transfer
def place(nominal: np.ndarray, u: float, lateral: float) -> np.ndarray:
    """Point at arc-length fraction ``u`` of ``nominal``, ``lateral`` m along its left normal."""
    s = arc_length(nominal)
    k = int(np.clip(np.searchsorted(s, u * s[-1]), 0, len(nominal) - 1))
    return nominal[k] + lateral * left_normals(nominal)[k]


def planner_metrics(reward, nominal, scene, reference, true_reward, true_nominal) -> dict:
    out = {}
    for key, r, nom, horizon in (
        ("learned_full", reward, nominal, None),
        ("learned_mpc", reward, nominal, HORIZON),
        ("true_full", true_reward, true_nominal, None),
        ("true_mpc", true_reward, true_nominal, HORIZON),
    ):
        path, err = safe_plan(
            lambda r=r, nom=nom, horizon=horizon: plan_path(r, nom, scene, horizon=horizon)
        )
        out[key] = {**scene_metrics(path, scene, reference), "error": err, "_path": path}
    return out


def composition_transfer(sets: dict, variants: dict, fits: list[dict], figure_variant) -> dict:
    out = {"nominal": figure_variant, "composition": None, "transfer": None}
    sweep = sets.get("sweeping")
    if sweep is not None and figure_variant in variants["sweeping"]:
        nominal = variants["sweeping"][figure_variant]["path"]
        learned = {}
        for label in sweep.true_reward.classes:
            idx = [i for i in sweep.train if sweep.scenes[i].classes == (label,)]
            ioc = IOC().fit([sweep.demos[i] for i in idx], [sweep.scenes[i] for i in idx], nominal)
            learned[label] = ioc.reward_
        first, *rest = learned.values()
        combined = first
        for other in rest:
            combined = combined.combined(other)
        joint = next(
            r
            for r in fits
            if r["dataset"] == "sweeping" and r["nominal"] == figure_variant and r["mode"] == "full"
        )
        scenes = []
        names = held_out_names("sweeping", len(sweep.held_out_scenes))
        for name, scene in zip(names, sweep.held_out_scenes, strict=True):
            reference = sweep.true_plan(scene)
            metrics = planner_metrics(
                combined, nominal, scene, reference, sweep.true_reward, sweep.nominal
            )
            joint_path, err = safe_plan(lambda scene=scene: joint["ioc"].plan(nominal, scene))
            metrics["joint_full"] = {
                **scene_metrics(joint_path, scene, reference),
                "error": err,
                "_path": joint_path,
            }
            scenes.append({"scene": name, "scene_obj": scene, "planners": metrics})
        out["composition"] = {
            "separate": {c: reward_record(r) for c, r in learned.items()},
            "combined": reward_record(combined),
            "combined_errors": parameter_errors(combined, sweep.true_reward),
            "joint": reward_record(joint["ioc"].reward_),
            "scenes": scenes,
            "_nominal": nominal,
            "reward_obj": combined,
        }
    art = sets.get("artificial")
    if art is not None and figure_variant in variants["artificial"]:
        learned = next(
            r
            for r in fits
            if r["dataset"] == "artificial"
            and r["nominal"] == figure_variant
            and r["mode"] == "full"
        )["ioc"].reward_
        radius = float(art.scenes[0].radii[0])
        x = np.linspace(-0.4, 0.4, 400)
        angle = np.linspace(np.pi, np.pi / 2.0, 400)
        nominals = {
            "sweeping line": np.column_stack((x, np.full_like(x, 0.45))),
            "quarter circle": np.column_stack((0.5 + 0.5 * np.cos(angle), 0.5 * np.sin(angle))),
        }
        designs = {
            "one obstacle": ((0.5, 0.02),),
            "cluttered (4)": ((0.2, 0.03), (0.4, -0.025), (0.6, 0.035), (0.8, -0.02)),
        }
        cases = []
        for nom_name, nom in nominals.items():
            for scene_name, design in designs.items():
                scene = Scene.from_arrays(
                    ["obstacle"] * len(design),
                    [place(nom, u, lateral) for u, lateral in design],
                    [radius] * len(design),
                )
                reference = plan_path(art.true_reward, nom, scene).points
                metrics = planner_metrics(learned, nom, scene, reference, art.true_reward, nom)
                mpc_ref = metrics["true_mpc"]["_path"]
                if metrics["learned_mpc"]["_path"] is not None and mpc_ref is not None:
                    metrics["learned_mpc"]["mse_to_true_mpc"] = mse_paths(
                        metrics["learned_mpc"]["_path"], [mpc_ref]
                    )
                cases.append(
                    {
                        "nominal": nom_name,
                        "scene": scene_name,
                        "scene_obj": scene,
                        "_nominal": nom,
                        "planners": metrics,
                    }
                )
        out["transfer"] = {
            "reward": reward_record(learned),
            "reward_obj": learned,
            "cases": cases,
        }
    return out


def print_composition(c: dict) -> None:
    print(
        f"\n5. Composition and transfer (nominal: {c['nominal']}); collisions, minimum clearance"
        " [mm], MSE to the true-parameter full-horizon plan along the same nominal [m²]"
    )
    keys = ("learned_full", "learned_mpc", "joint_full", "true_mpc")
    if c["composition"]:
        comp = c["composition"]
        sep = "; ".join(
            f"{label}: {reward_text(Reward(r['Q'], r['precisions']))}"
            for label, r in comp["separate"].items()
        )
        print(f"  separate fits: {sep}")
        print(
            "  combined: "
            + reward_text(Reward(comp["combined"]["Q"], comp["combined"]["precisions"]))
            + "  errors "
            + ", ".join(f"{k} {v * 100:.0f}%" for k, v in comp["combined_errors"].items())
        )
        head = f"  {'sweeping scene':<22}"
        for _key, title in zip(
            keys,
            ("combined full", f"combined MPC H={HORIZON}", "joint full", "true MPC"),
            strict=True,
        ):
            head += f" {title:>24}"
        print(head + f" {'true full':>12}")
        for s in comp["scenes"]:
            print(f"  {s['scene'][:22]:<22}" + cells(s["planners"], keys))
    if c["transfer"]:
        t = c["transfer"]
        print(
            "  transfer of the artificial reward "
            + reward_text(Reward(t["reward"]["Q"], t["reward"]["precisions"]))
        )
        head = f"  {'nominal / scene':<30}"
        for title in ("learned full", f"learned MPC H={HORIZON}", "true MPC"):
            head += f" {title:>24}"
        print(head + f" {'true full':>12}")
        for case in t["cases"]:
            label = f"{case['nominal']} / {case['scene']}"
            print(
                f"  {label[:30]:<30}"
                + cells(case["planners"], ("learned_full", "learned_mpc", "true_mpc"))
            )


def cells(planners: dict, keys) -> str:
    line = ""
    for key in keys:
        m = planners.get(key)
        if m is None or m["collisions"] is None:
            line += f" {'error' if m and m.get('error') else '—':>24}"
        else:
            line += (
                f" {str(m['collisions']) + 'c':>3} {m['min_clearance'] * 1e3:6.1f} "
                f"{sci(m['mse_to_true'], 1):>13}"
            )
    ref = planners["true_full"]
    line += f" {str(ref['collisions']) + 'c':>3} {ref['min_clearance'] * 1e3:6.1f}"
    return line


# ---------------------------------------------------------------------------- figures
def reward_figures(sets, variants, fits, test_rows, out_dir: Path) -> list[str]:
    written = []
    for name, es in sets.items():
        panels = []
        for variant, info in variants[name].items():
            full = next(
                (
                    r
                    for r in fits
                    if r["dataset"] == name and r["nominal"] == variant and r["mode"] == "full"
                ),
                None,
            )
            row = next(
                (r for r in test_rows if r["dataset"] == name and r["nominal"] == variant), None
            )
            if not full or full["error"] or row is None:
                continue
            plans = {}
            for key in ("learned_full", "learned_mpc", "true_full"):
                path = row["_plans"].get(key, [None])[0]
                if path is not None:
                    plans[PLAN_NAMES[key]] = path
            panels.append(
                {
                    "reward": full["ioc"].reward_,
                    "nominal": info["path"],
                    "scene": es.test_scenes[0],
                    "demos": [es.test_demos[0]],
                    "plans": plans,
                    "title": f"nominal: {variant}\n{reward_text(full['ioc'].reward_)}",
                }
            )
        if not panels:
            continue
        fig = emulation_grid(
            panels,
            ncols=len(panels),
            title=f"{name}: learned reward (full-horizon fit), test scene 0 and its "
            f"demonstration\ntrue {reward_text(es.true_reward)}",
        )
        path = out_dir / f"emulate_reward_{name}.png"
        fig.savefig(path, dpi=100)
        written.append(path.name)
    return written


def heldout_figure(sets, variants, fits, held_rows, variant, out_dir: Path) -> str | None:
    panels = []
    short = {
        "learned_full": "L-full",
        "learned_mpc": "L-MPC",
        "true_full": "T-full",
        "true_mpc": "T-MPC",
    }
    for name in ("artificial", "sweeping"):
        es = sets.get(name)
        if es is None or variant not in variants[name]:
            continue
        full = next(
            (
                r
                for r in fits
                if r["dataset"] == name and r["nominal"] == variant and r["mode"] == "full"
            ),
            None,
        )
        if not full or full["error"]:
            continue
        names = held_out_names(name, len(es.held_out_scenes))
        for scene_name, scene in zip(names, es.held_out_scenes, strict=True):
            row = next(
                r
                for r in held_rows
                if r["dataset"] == name and r["nominal"] == variant and r["scene"] == scene_name
            )
            plans = {
                PLAN_NAMES[key]: row["planners"][key]["_path"]
                for key in ("learned_full", "learned_mpc", "true_full", "true_mpc")
                if key in row["planners"] and row["planners"][key]["_path"] is not None
            }
            coll = ", ".join(
                f"{short[k]} {v['collisions']}"
                for k, v in row["planners"].items()
                if v["collisions"] is not None
            )
            panels.append(
                {
                    "reward": full["ioc"].reward_,
                    "nominal": variants[name][variant]["path"],
                    "scene": scene,
                    "plans": plans,
                    "title": f"{name}: {scene_name}\ncollisions: {coll}",
                }
            )
    if not panels:
        return None
    fig = emulation_grid(
        panels,
        ncols=3,
        title=f"Held-out scenes: learned reward (nominal '{variant}', contours of the full-horizon"
        " fit) vs true parameters (L = learned, T = true)",
    )
    path = out_dir / "emulate_heldout.png"
    fig.savefig(path, dpi=90)
    return path.name


def transfer_figure(c: dict, out_dir: Path) -> str | None:
    panels = []

    def plans_of(planners, learned_label):
        out = {}
        for key, label in (
            ("learned_full", f"{learned_label} full horizon"),
            ("learned_mpc", f"{learned_label} MPC H={HORIZON}"),
            ("true_full", PLAN_NAMES["true_full"]),
        ):
            if planners[key]["_path"] is not None:
                out[label] = planners[key]["_path"]
        return out

    if c["composition"]:
        comp = c["composition"]
        for s in comp["scenes"]:
            panels.append(
                {
                    "reward": comp["reward_obj"],
                    "nominal": comp["_nominal"],
                    "scene": s["scene_obj"],
                    "plans": plans_of(s["planners"], "learned"),
                    "title": f"composition (cup + marker fits): {s['scene']}",
                }
            )
    if c["transfer"]:
        t = c["transfer"]
        for case in t["cases"]:
            panels.append(
                {
                    "reward": t["reward_obj"],
                    "nominal": case["_nominal"],
                    "scene": case["scene_obj"],
                    "plans": plans_of(case["planners"], "learned"),
                    "title": f"transfer (artificial reward): {case['nominal']}, {case['scene']}",
                }
            )
    if not panels:
        return None
    fig = emulation_grid(
        panels, ncols=4, title="Composition (sweeping, thesis Fig 6.12) and transfer (Fig 6.13)"
    )
    path = out_dir / "emulate_transfer.png"
    fig.savefig(path, dpi=85)
    return path.name


def baseline_figure(sets, variants, fits, dmp_rows, variant, out_dir: Path) -> str | None:
    panels = []
    for r in dmp_rows:
        if "skipped" in r or r["nominal"] != variant:
            continue
        es = sets[r["dataset"]]
        nominal = variants[r["dataset"]][variant]["path"]
        by = {
            f["mode"]: f for f in fits if f["dataset"] == r["dataset"] and f["nominal"] == variant
        }
        full = by.get("full")
        if not full or full["error"]:
            continue
        scene = es.test_scenes[0]
        ours, _ = safe_plan(
            lambda full=full, nominal=nominal, scene=scene: full["ioc"].plan(nominal, scene)
        )
        plans = {} if ours is None else {"lfdkit full horizon": ours}
        plans["DMP + coupling (tuned)"] = r["_rollouts"][0]
        panels.append(
            {
                "reward": full["ioc"].reward_,
                "nominal": nominal,
                "scene": scene,
                "demos": [es.test_demos[0]],
                "plans": plans,
                "title": f"{r['dataset']}, test scene 0; DMP \u03b3={r['best_gamma']:.0f}, "
                f"\u03b2={r['best_beta']:.2f}\ntest MSE_R: DMP {sci(r['test_mse'])}, lfdkit "
                f"{sci(r['lfdkit_test_mse_full'])} m²",
            }
        )
    if not panels:
        return None
    fig = emulation_grid(
        panels,
        ncols=len(panels),
        title="DMP with obstacle-avoidance coupling (Hoffmann et al., movement_primitives)\n"
        f"vs lfdkit (nominal '{variant}'); \u03b3, \u03b2 tuned on the training demonstrations",
    )
    path = out_dir / "emulate_baseline.png"
    fig.savefig(path, dpi=100)
    return path.name


# ---------------------------------------------------------------------------- targets
def check_targets(fits, test_rows, held_rows, dmp_rows, speed_result) -> list[dict]:
    checks = []
    for variant in LEARNED_VARIANTS:
        for name in dict.fromkeys(r["dataset"] for r in fits):
            rows = [r for r in fits if r["dataset"] == name and r["nominal"] == variant]
            if not rows:
                continue
            parts, ok = [], True
            for r in rows:
                if r["error"]:
                    parts.append(f"{r['mode']}: error")
                    ok = False
                    continue
                ok &= not r["failing"]
                fails = ", ".join(f"{k} {r['errors'][k] * 100:.0f}%" for k in r["failing"])
                parts.append(f"{r['mode']}: " + (f"fails {fails}" if fails else "all within"))
            checks.append(
                {
                    "target": f"recovery within 10% ({name}, nominal {variant})",
                    "pass": bool(ok),
                    "detail": "; ".join(parts),
                }
            )
        for r in (r for r in test_rows if r["nominal"] == variant):
            prs = [r.get("pr_full"), r.get("pr_mpc")]
            ratios = [r.get("ratio_full"), r.get("ratio_mpc")]

            def show(value, unit, key, r=r):
                if value is not None:
                    return f"{value:.1f}%" if unit == "%" else f"{value:.2f}x"
                return "plans refused" if f"errors_{key}" in r else "no fit"

            checks.append(
                {
                    "target": f"test Pr >= 90% ({r['dataset']}, nominal {variant})",
                    "pass": all(p is not None and p >= PR_TARGET for p in prs),
                    "detail": f"full {show(prs[0], '%', 'full')}, MPC {show(prs[1], '%', 'mpc')}",
                }
            )
            checks.append(
                {
                    "target": f"test MSE_R <= 1.5x true ({r['dataset']}, nominal {variant})",
                    "pass": all(x is not None and x <= RATIO_TARGET for x in ratios),
                    "detail": f"full {show(ratios[0], 'x', 'full')}, "
                    f"MPC {show(ratios[1], 'x', 'mpc')}",
                }
            )
        for key in ("learned_full", "learned_mpc"):
            hits, seen = [], False
            for r in held_rows:
                if r["nominal"] != variant or r["scene"] not in NO_COLLISION_SCENES.get(
                    r["dataset"], ()
                ):
                    continue
                m = r["planners"].get(key)
                if m is None:
                    continue
                seen = True
                if m["collisions"] is None or m["collisions"] > 0:
                    hits.append(f"{r['dataset']} {r['scene']}: {m['collisions']}")
            if seen:
                checks.append(
                    {
                        "target": f"no collision, cluttered + concave ({PLAN_NAMES[key]}, "
                        f"nominal {variant})",
                        "pass": not hits,
                        "detail": "; ".join(hits) or "none",
                    }
                )
        for r in dmp_rows:
            if "skipped" in r or r["nominal"] != variant:
                continue
            factor = r["factor_full"]
            checks.append(
                {
                    "target": f"MSE_R >= 3x lower than DMP+coupling ({r['dataset']}, {variant})",
                    "pass": bool(factor is not None and factor >= DMP_FACTOR_TARGET),
                    "detail": (f"{factor:.1f}x" if factor is not None else "lfdkit plans refused")
                    + f" (DMP {sci(r['test_mse'])}, lfdkit {sci(r['lfdkit_test_mse_full'])})",
                }
            )
    s = speed_result
    fits_s = s["fits"]
    checks.append(
        {
            "target": "IOC fit 8 demos x 100, 2 classes, full horizon < 2 s",
            "pass": fits_s["implicit full"]["median_s"] < FIT_FULL_TARGET_S,
            "detail": f"median {fits_s['implicit full']['median_s']:.2f} s",
        }
    )
    checks.append(
        {
            "target": "IOC fit staged with MPC H=8 < 15 s",
            "pass": fits_s["implicit staged"]["median_s"] < FIT_STAGED_TARGET_S,
            "detail": f"median {fits_s['implicit staged']['median_s']:.2f} s",
        }
    )
    sc = s["scipy"]
    for key in ("full", "staged"):
        ours = s["lfdkit_same_start"][f"lfdkit {key} (same start)"]["median_s"]
        theirs = sc[key]["seconds"] + (sc["full"]["seconds"] if key == "staged" else 0.0)
        checks.append(
            {
                "target": f"faster than the SciPy reference ({key}, same start)",
                "pass": bool(ours < theirs),
                "detail": f"lfdkit {ours:.2f} s vs SciPy {theirs:.1f} s"
                + ("" if sc[key]["finished"] else " (SciPy did not finish)"),
            }
        )
    one = s["planning"]["one cup"]
    checks.append(
        {
            "target": "MPC step H=12 < 1 ms median (sweeping, one cup)",
            "pass": bool(one["window_median_s"] < MPC_STEP_TARGET_S),
            "detail": f"window median {one['window_median_s'] * 1e3:.3f} ms, whole call "
            f"{one['mpc_step_whole_call_s'] * 1e3:.3f} ms/step, max {one['window_max_s'] * 1e3:.2f}"
            " ms",
        }
    )
    clutter = s["planning"]["cluttered (4)"]
    checks.append(
        {
            "target": "MPC step H=12 < 1 ms median (sweeping, cluttered 4)",
            "pass": bool(clutter["window_median_s"] < MPC_STEP_TARGET_S),
            "detail": f"window median {clutter['window_median_s'] * 1e3:.3f} ms, whole call "
            f"{clutter['mpc_step_whole_call_s'] * 1e3:.3f} ms/step",
        }
    )
    for label in ("one cup", "cluttered (4)"):
        p = s["planning"][label]
        checks.append(
            {
                "target": f"100-point full-horizon plan < 100 ms (sweeping, {label})",
                "pass": bool(p["full_median_s"] < PLAN_TARGET_S),
                "detail": f"median {p['full_median_s'] * 1e3:.1f} ms",
            }
        )
    return checks


def print_targets(checks: list[dict]) -> None:
    print("\nTargets")
    for c in checks:
        verdict = "PASS" if c["pass"] else "FAIL"
        print(f"  {verdict}  {c['target']:<72} {c['detail']}")


# ------------------------------------------------------------------------------ output


def _clean(value):
    """JSON-ready copy: private keys (``_...``), live objects and arrays handled."""
    if isinstance(value, dict):
        return {
            str(k): _clean(v)
            for k, v in value.items()
            if not str(k).startswith("_") and k not in ("ioc", "scene_obj", "reward_obj")
        }
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).parent / "results" / "emulate"
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="smoke run: nominal 'free' (else 'train') only, max_iter 2, no train MSE_R, "
        "small DMP grid, 1 fit round, SciPy limit 5 s, no finite-difference staged fit",
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--datasets", nargs="*", default=list(DATASETS), metavar="NAME")
    parser.add_argument("--fit-repeats", type=int, default=None, help="fit rounds (default 3)")
    parser.add_argument("--repeats", type=int, default=None, help="planning rounds (default 15)")
    parser.add_argument("--scipy-limit", type=float, default=None, help="s per stage (120)")
    parser.add_argument("--figure-nominal", choices=VARIANTS, default="free")
    args = parser.parse_args(argv)
    quick = args.quick
    fit_repeats = args.fit_repeats or (1 if quick else 3)
    repeats = args.repeats or (3 if quick else 15)
    limit_s = args.scipy_limit or (5.0 if quick else 120.0)
    max_iter = 2 if quick else 200
    args.output.mkdir(parents=True, exist_ok=True)
    wall = time.perf_counter()

    with threadpool_limits(limits=1):
        progress("data sets and nominal paths ...")
        sets = {name: load_emulation_dataset(name, args.seed) for name in args.datasets}
        figure_variant = args.figure_nominal
        if figure_variant == "free" and not all(
            getattr(es, "free_demos", None) for es in sets.values()
        ):
            figure_variant = "train"
        include = (figure_variant,) if quick else VARIANTS
        variants = {name: nominal_variants(es, include) for name, es in sets.items()}
        for name, vs in variants.items():
            for variant, info in vs.items():
                progress(
                    f"   {name} / {variant}: {info['source']}, max deviation from the true "
                    f"nominal {info['deviation_max'] * 1e3:.1f} mm"
                )

        progress("1. fits ...")
        fits = fit_and_recover(sets, variants, max_iter)
        noise_free = [] if quick else noise_free_fits(list(sets), args.seed, max_iter)
        print_fits(fits, sets, noise_free)
        print("  nominal paths (deviation from the true nominal, max/mean mm):")
        for name, vs in variants.items():
            print(
                f"    {name:<16} "
                + "; ".join(
                    f"{v}: {i['deviation_max'] * 1e3:.1f}/{i['deviation_mean'] * 1e3:.1f}"
                    for v, i in vs.items()
                )
            )

        progress("2. evaluation ...")
        test_rows, held_rows = evaluate(sets, variants, fits, train_mse=not quick)
        print_evaluation(test_rows, held_rows)

        progress("3. DMP baseline ...")
        dmp_rows = dmp_baseline(sets, variants, test_rows, quick)
        print_dmp(dmp_rows)

        progress("4. speed ...")
        speed_result = speed(fit_repeats, repeats, quick, limit_s, sets.get("da_vinci_marker"))
        print_speed(speed_result)

        progress("5. composition and transfer ...")
        comp = composition_transfer(sets, variants, fits, figure_variant)
        print_composition(comp)

        progress("figures ...")
        figures = reward_figures(sets, variants, fits, test_rows, args.output)
        for name in (
            heldout_figure(sets, variants, fits, held_rows, figure_variant, args.output),
            transfer_figure(comp, args.output),
            baseline_figure(sets, variants, fits, dmp_rows, figure_variant, args.output),
        ):
            if name:
                figures.append(name)

    checks = check_targets(fits, test_rows, held_rows, dmp_rows, speed_result)
    print_targets(checks)
    wall = time.perf_counter() - wall
    print(f"\nwall time {wall:.1f} s")

    result = {
        "benchmark": "emulate",
        "created": time.strftime("%Y-%m-%dT%H:%M:%S"),
        "command": [sys.executable, *sys.argv] if argv is None else ["emulate.py", *argv],
        "quick": quick,
        "seed": args.seed,
        "machine": machine_info(),
        "versions": package_versions(
            ("lfdkit", "numpy", "scipy", "numba", "matplotlib", "movement_primitives")
        ),
        "git": git_state(),
        "wall_time_s": wall,
        "settings": {
            "horizon": HORIZON,
            "speed_horizon": SPEED_HORIZON,
            "max_iter": max_iter,
            "fit_repeats": fit_repeats,
            "repeats": repeats,
            "scipy_limit_s": limit_s,
            "figure_nominal": figure_variant,
            "dmp": {"n_weights_per_dim": DMP_WEIGHTS, "dt": DMP_DT, "execution_time": 1.0},
        },
        "thesis": THESIS,
        "datasets": {
            name: {
                "n_demos": es.n_demos,
                "n_dims": es.n_dims,
                "train": es.train,
                "test": es.test,
                "true_reward": reward_record(es.true_reward),
                "held_out": held_out_names(name, len(es.held_out_scenes)),
                "nominals": {
                    v: {k: i[k] for k in ("source", "warnings", "deviation_max", "deviation_mean")}
                    for v, i in variants[name].items()
                },
            }
            for name, es in sets.items()
        },
        "fits": fits,
        "noise_free_fits": noise_free,
        "test": test_rows,
        "held_out": held_rows,
        "dmp_baseline": dmp_rows,
        "speed": speed_result,
        "composition_transfer": comp,
        "figures": figures,
        "targets": checks,
    }
    out = args.output / "emulate.json"
    out.write_text(json.dumps(_clean(result), indent=1))
    progress(f"\nwrote {out} and figures in {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
