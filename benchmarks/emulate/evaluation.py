"""Section 2 of the emulation benchmark: test demonstrations and held-out scenes."""

from __future__ import annotations

import numpy as np

from lfdkit.emulate import plan_path
from lfdkit.emulate.metrics import collisions, improvement, mse_paths

from .common import held_out_names, progress, safe_plan, scene_metrics, sci
from .spec import HORIZON, PLAN_NAMES, THESIS


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
