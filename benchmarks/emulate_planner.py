"""Plans a robot can trust: global optimality, clearance, the goal, pockets and speed.

Run ``python benchmarks/emulate_planner.py`` (``--quick`` for a smoke run).
Prints one table per section and writes ``planner.json`` to ``--output``
(``benchmarks/results/emulate`` by default).

1. Global optimality. Random scenes (``tests/emulate/test_planner_safety.py``'s
   ``random_case``: random stiffness and widths, 1–8 obstacles scattered,
   overlapping or in a concave pocket, on a straight, S-shaped or curved
   nominal of 50 points): the plan's cost against the exhaustive reference of
   the same test module (a dynamic programme over every path on a grid twice
   as fine as the planner's, polished by SciPy's L-BFGS-B). Target: every plan
   within 1e-6 (relative) of the reference; for goal-reaching plans the route
   (the plan without goal term) is checked so, and the goal-reaching plan
   must pass every obstacle on the route's side (issue 26).
2. Clearance and goal. The same scenes with random radii (0–1.5 response
   widths) and tool clearances, full horizon and MPC H=8; and the held-out
   scenes of the synthetic data sets (cluttered, concave) with their true
   rewards. Target: 0 plans inside radius plus clearance (refusals counted
   apart), every goal-reaching plan within 1e-3 of the extent from its goal.
3. Concave pocket (thesis Fig 5.8, ``artificial_obstacles`` held-out scene 1,
   true reward): the MPC at H = 6…12 against the full-horizon plan, with and
   without ``lookahead``.
4. Speed (median of ``--repeats`` after a warm-up): a 100-point 2-D plan with
   4 obstacles (full horizon; target ≤ 20 ms), the MPC per step at H = 12 with
   4 obstacles (target ≤ 1 ms), and a 100-point 3-D plan (target ≤ 100 ms).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the tests' reference solver

from _common import git_state, machine_info, package_versions

from lfdkit.datasets.emulation import artificial_obstacles, da_vinci_marker
from lfdkit.datasets.planning import (
    N_POINTS,
    random_case,
    random_case_with_radii,
    reference_cost,
)
from lfdkit.emulate import Corridor, Reward, UnsafePlanError, plan_path
from lfdkit.emulate.fidelity import passing_sides
from lfdkit.emulate.metrics import clearance as path_clearance
from lfdkit.io import atomic_write
from lfdkit.model.scene import Obstacle, Scene


def progress(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def global_optimality(n_scenes: int, goal_scenes: int) -> dict:
    rows = {}
    for name, count, approach, offset in (
        ("thesis model", n_scenes, None, 0),
        ("goal-reaching", goal_scenes, "auto", 10_000),
    ):
        excess, kept = [], 0
        for seed in range(offset, offset + count):
            reward, path, scene = random_case(seed)
            # The route is the plan without the goal term (issue 26): the
            # goal-reaching plan is it joined to the goal, on the same sides.
            route = plan_path(reward, path, scene, n_points=N_POINTS, goal_approach=None)
            best = reference_cost(reward, path, scene, None)
            excess.append((route.cost - best) / max(best, 1e-300))
            if approach is not None:
                plan = plan_path(reward, path, scene, n_points=N_POINTS, goal_approach=approach)
                corridor = Corridor.from_path(path, N_POINTS)
                a = passing_sides(plan.points, corridor, scene)
                b = passing_sides(route.points, corridor, scene)
                kept += bool(np.all(np.einsum("om,om->o", a, b) >= 0.0))
        excess = np.array(excess)
        rows[name] = {
            "scenes": count,
            "within_1e-6": int(np.sum(excess <= 1e-6)),
            "worst_relative_excess": float(excess.max()),
            "better_than_reference": int(np.sum(excess < -1e-9)),
        }
        if approach is not None:
            rows[name]["sides_of_the_route_kept"] = kept
    return rows


def clearance_and_goal(n_scenes: int) -> dict:
    violations = refused = planned = 0
    worst_goal = 0.0
    smallest = np.inf
    for seed in range(n_scenes):
        reward, path, scene, clearance = random_case_with_radii(seed)
        extent = Corridor.from_path(path, N_POINTS).extent
        for horizon in (None, 8):
            try:
                plan = plan_path(
                    reward, path, scene, n_points=N_POINTS, horizon=horizon, clearance=clearance
                )
            except (UnsafePlanError, ValueError):
                refused += 1
                continue
            planned += 1
            margin = path_clearance(plan.points, scene, clearance)
            smallest = min(smallest, float(margin.min()))
            violations += int(np.sum(margin < -1e-12))
            worst_goal = max(worst_goal, plan.goal_error / extent)
    held = []
    for name, es in (
        ("artificial", artificial_obstacles(seed=0)),
        ("da_vinci", da_vinci_marker(seed=0)),
    ):
        for i, scene in enumerate(es.held_out_scenes):
            for horizon in (None, 8, 12):
                plan = plan_path(es.true_reward, es.nominal, scene, horizon=horizon)
                held.append(
                    {
                        "set": name,
                        "scene": i,
                        "horizon": horizon,
                        "min_clearance": float(plan.clearance.min()),
                        "goal_error_relative": plan.goal_error
                        / Corridor.from_path(es.nominal).extent,
                    }
                )
    held_violations = sum(row["min_clearance"] < -1e-12 for row in held)
    return {
        "random": {
            "plans": planned,
            "refused": refused,
            "violations": violations,
            "smallest_margin": smallest,
            "worst_goal_error_relative": worst_goal,
        },
        "held_out": held,
        "held_out_violations": int(held_violations),
        "pass": violations == 0 and held_violations == 0 and worst_goal <= 1e-3,
    }


def pocket() -> list[dict]:
    es = artificial_obstacles(seed=0)
    scene = es.held_out_scenes[1]
    corridor = Corridor.from_path(es.nominal)
    full = plan_path(es.true_reward, es.nominal, scene)
    centre = np.mean(scene.positions, axis=0)
    reach = np.max(np.linalg.norm(scene.positions - centre, axis=1))
    rows = [{"planner": "full horizon", "cost": full.cost, "enters": False}]
    for lookahead in (True, False):
        for horizon in (6, 8, 10, 12):
            plan = plan_path(
                es.true_reward, es.nominal, scene, horizon=horizon, lookahead=lookahead
            )
            inside = np.linalg.norm(plan.points - centre, axis=1) < reach
            rows.append(
                {
                    "planner": f"MPC H={horizon}" + ("" if lookahead else " (thesis)"),
                    "cost": plan.cost,
                    "enters": bool(inside.any()),
                    "min_clearance": float(plan.clearance.min()),
                }
            )
    del corridor
    return rows


def median_ms(fn, repeats: int) -> float:
    fn()  # numba compiles on first use
    times = []
    for _ in range(repeats):
        started = time.perf_counter()
        fn()
        times.append(time.perf_counter() - started)
    return 1e3 * float(np.median(times))


def speed(repeats: int) -> dict:
    x = np.linspace(0.0, 1.0, 200)
    nominal = np.column_stack([x, 0.05 * np.sin(2 * np.pi * x)])
    reward = Reward(10.0, {"cup": [2500.0, 215.0]})
    scene = Scene(
        tuple(
            Obstacle("cup", [u, 0.05 * np.sin(2 * np.pi * u) + dy], radius=0.01)
            for u, dy in ((0.3, 0.01), (0.45, -0.02), (0.6, 0.015), (0.75, -0.01))
        )
    )
    full = median_ms(lambda: plan_path(reward, nominal, scene), repeats)
    mpc = median_ms(lambda: plan_path(reward, nominal, scene, horizon=12), repeats) / 99
    x3 = np.column_stack([x, 0.1 * np.sin(np.pi * x), 0.05 * x])
    reward3 = Reward(10.0, {"cup": [2500.0, 215.0, 215.0]})
    scene3 = Scene(
        tuple(
            Obstacle("cup", p, radius=0.01)
            for p in ([0.3, 0.081, 0.025], [0.6, 0.095, 0.02], [0.75, 0.07, 0.04])
        )
    )
    full3 = median_ms(lambda: plan_path(reward3, x3, scene3), repeats)
    mpc3 = median_ms(lambda: plan_path(reward3, x3, scene3, horizon=12), repeats)
    return {
        "plan_2d_100_points_ms": full,
        "mpc_step_h12_4_obstacles_ms": mpc,
        "plan_3d_100_points_ms": full3,
        "mpc_3d_100_points_ms": mpc3,
        "pass": full <= 20.0 and mpc <= 1.0 and full3 <= 100.0,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).parent / "results" / "emulate"
    )
    parser.add_argument("--quick", action="store_true", help="50 scenes per check, 3 repeats")
    parser.add_argument("--repeats", type=int, default=None)
    args = parser.parse_args(argv)
    n_scenes, goal_scenes = (50, 20) if args.quick else (500, 100)
    repeats = args.repeats or (3 if args.quick else 9)
    args.output.mkdir(parents=True, exist_ok=True)
    with threadpool_limits(limits=1):
        progress("1. global optimality ...")
        optimality = global_optimality(n_scenes, goal_scenes)
        print("\n1. Global optimality (plan cost vs exhaustive reference)")
        print(f"{'model':<16}{'scenes':>8}{'within 1e-6':>13}{'worst excess':>14}{'better':>8}")
        for name, row in optimality.items():
            kept = row.get("sides_of_the_route_kept")
            print(
                f"{name:<16}{row['scenes']:>8}{row['within_1e-6']:>13}"
                f"{row['worst_relative_excess']:>14.1e}{row['better_than_reference']:>8}"
                + ("" if kept is None else f"  (goal plan on the route's sides: {kept})")
            )
        progress("2. clearance and goal ...")
        safety = clearance_and_goal(n_scenes // 2)
        r = safety["random"]
        print(
            f"\n2. Clearance: {r['plans']} random plans, {r['refused']} refused, "
            f"{r['violations']} violations (smallest margin {r['smallest_margin']:.2e}); "
            f"held-out scenes: {safety['held_out_violations']} violations; worst goal error "
            f"{r['worst_goal_error_relative']:.1e} of the extent "
            f"({'PASS' if safety['pass'] else 'FAIL'})"
        )
        progress("3. concave pocket ...")
        pockets = pocket()
        print("\n3. Concave pocket (artificial held-out scene 1, true reward)")
        for row in pockets:
            print(f"  {row['planner']:<22} cost {row['cost']:.4f}  enters: {row['enters']}")
        progress("4. speed ...")
        timing = speed(repeats)
        print(
            f"\n4. Speed: 2-D 100-point plan {timing['plan_2d_100_points_ms']:.1f} ms (<= 20), "
            f"MPC step H=12 {timing['mpc_step_h12_4_obstacles_ms']:.2f} ms (<= 1), "
            f"3-D plan {timing['plan_3d_100_points_ms']:.1f} ms (<= 100), 3-D MPC "
            f"{timing['mpc_3d_100_points_ms']:.1f} ms ({'PASS' if timing['pass'] else 'FAIL'})"
        )
    record = {
        "optimality": optimality,
        "safety": safety,
        "pocket": pockets,
        "speed": timing,
        "machine": machine_info(),
        "packages": package_versions(["numpy", "scipy", "numba"]),
        "git": git_state(),
    }
    target = args.output / "planner.json"
    atomic_write(target, lambda f: json.dump(record, f, indent=2), overwrite=True)
    print(f"\nwrote {target}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
