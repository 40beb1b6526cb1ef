"""Section 5 of the emulation benchmark: composition of rewards and transfer to other nominals."""

from __future__ import annotations

import numpy as np

from lfdkit.core.geometry import arc_length, left_normals
from lfdkit.emulate import IOC, Reward, plan_path
from lfdkit.emulate.metrics import mse_paths, parameter_errors
from lfdkit.model.scene import Scene

from .common import held_out_names, reward_record, reward_text, safe_plan, scene_metrics, sci
from .spec import HORIZON


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
