"""Figures of the emulation benchmark (``emulate_*.png`` in the output folder)."""

from __future__ import annotations

from pathlib import Path

from lfdkit.app.plot import emulation_grid

from .common import held_out_names, reward_text, safe_plan, sci
from .spec import HORIZON, PLAN_NAMES


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
