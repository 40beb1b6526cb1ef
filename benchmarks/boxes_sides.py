"""A side preference among several boxes: leave one demonstration out, in millimetres.

Run ``python benchmarks/boxes_sides.py`` (``--quick``: two folds; ``--dims 2``
for discs in the plane). Prints a table and writes ``boxes_sides.json`` to
``--output`` (``benchmarks/results/boxes_sides``).

The data (issues 34 and 26): a person (:mod:`boxes3d`'s planning person: the
true reward along the straight line from its start to the goal, looking
ahead over the whole path, then 3 mm of smooth noise) reaches 1 m
(``--reach``) from spread starts to a goal past three boxes of three classes,
a carton, a tin and a tray (6 × 6 × 25 cm, turned up to 30° about z; in 2-D
discs of 2.5 cm), placed along its own straight line at 20, 50 and 80 % of
the reach in a shuffled order. The tin and the tray stand 2–5 cm to either
side of the line and are passed the shorter way. The *keeping* person keeps
every carton on its left (:func:`lfdkit.emulate.gaps.preferred_side_blockers`,
as :mod:`boxes3d`'s *over* person keeps boxes below it). The carton stands
4–7 cm to the right of the line in every other demonstration, so half its
passes are the long way round. The *control* person is the same without the
preference. The demonstrations are recorded in millimetres and the skill is
``Skill(units="mm")``, its path learned from one demonstration without
obstacles per start (the line with 2 mm of smooth noise).

Each fold fits a :class:`lfdkit.skill.Skill` on every demonstration but one
and plans the held-out one's scene from its start to its goal:

* *found*: folds whose skill found the carton's preference
  (``Skill.side_preferences_``);
* *sides*: boxes passed on the person's side (the lateral direction at the
  plan's nearest point, :func:`boxes3d.passing_side`; over and under count as
  sides too), of the boxes within 15 cm of the person or 5 cm of the line;
  *carton*: folds with every carton on the person's side;
* *plan / line mm*: mean distance to the held-out person
  (:func:`lfdkit.emulate.metrics.held_out_distances`), of the plan and of the
  straight line (what a DMP alone gives);
* *clear/p*: the plan's least clearance over the person's, least and median
  over the folds; *coll*: collisions;
* the control's line says in how many of its leave-one-out training sets a
  preference is found (there is none: 0 is right).

Measured (8 folds, seed 0; the same sets the helper measured before and
after :func:`lfdkit.emulate.fidelity._gone_around_alone`, 66569b2 against
122ba7f): 3-D, found 0 → 8 of 8, sides 17 → 22 of 24 (carton 2 → 8 of 8),
distance to the person mean 82 → 86 mm and median 88 → 38 mm against 108 for
the line (three folds plan 15–25 cm from the person once the carton's
blockers apply; one goes under all three boxes where the person went over
the tin), least clearance 0.61 → 0.74 of the person's (median 0.98 → 0.92),
no collision; 2-D, found
0 → 8, sides 19 → 24 of 24, distance 45 → 3 mm against 81 for the line,
least clearance 0.90 → 0.90, fit 2.4 s. The control finds none in any
training set, before or after. A 3-D fit's CPU per fold, median (quiet,
warm, side by side): 26.0 s at 0da3345, 22.5 s at d6dc5e2 (the states' costs
over each blocker's disc, box distances over the near segments, shared
window costs; every figure the same): the issue's 10 s is missed here,
where :mod:`boxes3d`'s own sets fit in 3-5 s.

Since (stop 48): the grid states' obstacle terms shared across a scene's plans
(``planner._STATE_COSTS``) and the side blockers found once per scene, every
figure the same, fit wall time median over the 8 folds 16.5 → 12.0 s (CPU
19.8 → 15.0 s; one fold, whose candidates include the thesis's receding
horizon in 3-D, 26-31 s); then a box's segment candidates in one array
operation each, corridors made once per nominal and the blockers' hole test
on the points left, again every figure the same: 10.7 s on a quiet machine
(9.5-12.9 s, that fold 22.9 s), and side by side with bac3aa3 at a busier
moment 16.8 → 13.5 s (CPU 20.6 → 16.5 s), the issue's 10 s still missed; the
noise read against each demonstration's own nominal
(``mimic_info_["noise_mse"]``: 4.6 mm² where the spread about the one path,
18,506 mm², was the starts' and made the gap allowance 5 cm), and the
allowance closing only gaps across the path: sides 22 → 24 of 24, distance to
the person mean 86 → 22 mm (median 38 → 21; line 108), least clearance 0.74 →
0.90 of the person's (median 0.92 → 0.94), no collision. 2-D unchanged.
Other seeds, before → after (``--seed``): 1, sides 23 → 23 of 24, distance
51 → 17 mm (line 110), least clearance 0.84 → 0.84; 2, sides 20 → 19 (one
fold passes the carton over it on its left where the person passed under it
on its left: 2 → 1 of 3), distance 60 → 56 mm (line 114), least clearance
0.68 → 0.68 (a fold that passes two of three boxes on the other side, before
and after).

Then (stop 49) the model choice's work runs side by side on the process's
threads (every compiled planner kernel releases the GIL): the folds' refits,
every fold's replans, and the fit's check for demonstrations the reward
replans on another side (``lfdkit.core.threads.side_by_side``); each fold's
skill, plans and scores are the same to the bit. The table now gives the
fit's wall time (the issue's target) with its CPU over every thread. Seed 0,
alternated with 2e07075 (this benchmark's timing copied there), two runs each
at a quiet moment of this 2-core machine: wall median 10.6 and 10.2 s before,
7.8 and 7.6 s after; slowest fold (6, whose candidates include the thesis's
receding horizon in 3-D) 23.1 and 22.9 → 15.4 and 14.0 s; CPU median 13.2
and 13.1 → 13.0 and 12.5 s; every other figure the same. Runs one after the
other at a busier moment: 13.6 s before, 12.3 s with the replans alone side
by side, 10.8 s with the refits and the check too. The issue's 10 s per
fold is met at the median and missed by the slowest fold. A median fold
spends about half its time in the reward fit on all (its search, runs and
after-fit checks; a refit where a demonstration is left out), whose Newton
solves, 1.7 ms each, are half the fit's CPU.

Then (stop 51) a 3-D receding horizon's window grids take their states' costs
from the whole path's grid where their levels are its levels, and the
per-plan window reaches cover 3-D (every plan the same): seed 0, side by side
with a8c5c20's code, fit wall median 8.5 → 8.1 s, slowest fold (6) 14.4 →
10.4 s (CPU 24.6 → 17.4 s). And the demonstrations going the long way round
the kept carton are left out of the reward fit
(``Skill.ioc_info_["preference_passes"]``): seed 0, sides 24 → 24 of 24,
distance to the person mean 22 → 17 mm (median 21 → 13), least clearance 0.90
→ 0.86 of the person's (median 0.94 → 0.96); seed 1, sides 23 → 24, 17 → 10
mm, least clearance 0.84 → 0.84; seed 2, sides 19 → 19 (fold 4, 1 → 3: its
reward's ``Q`` had been 3.3× the person's and the plan wove through the boxes;
fold 2, 3 → 1: it passes the tray and the tin over, where the person passed
under, both on their right), 56 → 37 mm (median 47 → 16), least clearance 0.68
→ 0.91; 2-D, sides 24 → 24, 3 → 2 mm, least clearance 0.90 → 0.97. Fit wall
median / slowest fold, one run each at a quiet moment (load 1.1-1.4): 6.0 /
9.4 s (seed 0), 6.7 / 7.0 s (seed 1), 6.5 / 9.6 s (seed 2), every fold within
the issue's 10 s; at a busier moment 7.2 / 10.1, 6.2 / 6.9 and 7.1 / 11.6 s.
Then 3-D Newton steps with the points' curvature blocks as they are where the
reduced system is definite (the reward fit's plans: median 20 → 5 Newton
iterations): 5.0 / 5.7 s (seed 0), 4.9 / 5.9 s (seed 1), 5.1 / 5.7 s (seed 2)
at a quiet moment, CPU median 9.6 → 8.1, 10.4 → 7.6 and 10.4 → 8.1 s; sides
the same, distance to the person 17 → 14, 10 → 10 and 37 → 39 mm, least
clearance the same.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import git_state, machine_info, write_json
from boxes3d import CLEARANCE, N_POINTS, _smooth_noise, passing_side, sided

from lfdkit.emulate import Box, Reward, Scene, metrics, plan_path
from lfdkit.emulate.fidelity import side_preferences
from lfdkit.model.scene import Obstacle
from lfdkit.skill import Skill

CLASSES = ("carton", "tin", "tray")
#: The person's reward (per metre): boxes3d's true reward, one response per class.
PRECISION = 150.0
NOMINAL_WEIGHT = 3.0
#: How far the keeping person holds a carton on its left (m, preferred_side_blockers).
KEPT_WITHIN = 0.15
#: A box counts for the sides within these of the person or of the straight line (mm).
NEAR_PERSON, NEAR_LINE = 150.0, 50.0
MM = 1000.0


def make_set(dims: int, n_demos: int, seed: int, keeps: bool, reach: float) -> dict:
    """Demonstrations round the boxes, their scenes and straight nominals, in mm.

    ``free``: one demonstration without obstacles per start (the line with 2 mm
    of smooth noise), what the skill's path and DMP are learned from.
    """
    rng = np.random.default_rng(seed)
    goal = np.array([reach, 0.0, 0.12])[:dims]
    reward = Reward(NOMINAL_WEIGHT, {c: np.full(dims, PRECISION) for c in CLASSES})
    demos, scenes, nominals, free = [], [], [], []
    for j in range(n_demos):
        angle = np.pi * (j + 0.5) / n_demos - 0.5 * np.pi + rng.uniform(-0.1, 0.1)
        start = np.array([0.0, 0.3 * np.sin(angle), 0.15 + 0.1 * rng.uniform(-1, 1)])[:dims]
        nominal = start + np.linspace(0.0, 1.0, N_POINTS)[:, None] * (goal - start)
        along = (goal - start) / np.linalg.norm(goal - start)
        left = np.array([-along[1], along[0], 0.0][:dims])
        left /= np.linalg.norm(left)
        obstacles = []
        for share, c in zip((0.2, 0.5, 0.8), rng.permutation(len(CLASSES)), strict=True):
            label = CLASSES[c]
            if label == "carton":  # on the line's right (the long way) in every other one
                sign, low, high = (-1.0 if j % 2 == 0 else 1.0), 0.04, 0.07
            else:
                sign, low, high = rng.choice([-1.0, 1.0]), 0.02, 0.05
            centre = start + share * (goal - start) + sign * rng.uniform(low, high) * left
            if dims == 3:
                turn = Rotation.from_euler("z", rng.uniform(-30.0, 30.0), True).as_quat()
                obstacles.append(Box(label, centre, 0.0, [0.06, 0.06, 0.25], turn))
            else:
                obstacles.append(Obstacle(label, centre, radius=0.025))
        scene = Scene(tuple(obstacles))
        own, where, clearance = reward, scene, CLEARANCE
        if keeps:
            own, where, clearance = sided(
                reward, scene, nominal, {"carton": ("left", KEPT_WITHIN)}, clearance
            )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            plan = plan_path(own, nominal, where, clearance=clearance)
        noise = _smooth_noise(rng, 0.003)[:, :dims]
        demos.append(MM * (plan.points + noise))
        scenes.append(scene.scaled(MM))
        nominals.append(MM * nominal)
        free.append(MM * (nominal + _smooth_noise(rng, 0.002)[:, :dims]))
    return {"demos": demos, "scenes": scenes, "nominals": nominals, "free": free}


def lateral_side(path: np.ndarray, nominal: np.ndarray, obstacle: Obstacle) -> np.ndarray:
    """Unit direction across the line from ``obstacle`` to where ``path`` passes it."""
    if isinstance(obstacle, Box):
        return passing_side(path, nominal, obstacle)
    k = int(np.argmin(np.linalg.norm(path - obstacle.position, axis=1)))
    along = nominal[-1] - nominal[0]
    along /= np.linalg.norm(along)
    lateral = path[k] - obstacle.position
    lateral -= (lateral @ along) * along
    return lateral / max(float(np.linalg.norm(lateral)), 1e-12)


def run_fold(data: dict, held: int) -> dict:
    """Fit on every demonstration but ``held``, plan its scene, compare with the person."""
    keep = [j for j in range(len(data["demos"])) if j != held]
    began, began_cpu = time.perf_counter(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        skill = Skill(units="mm").fit(
            [data["free"][j] for j in keep],
            [data["demos"][j] for j in keep],
            [data["scenes"][j] for j in keep],
        )
    row: dict = {
        "held": held,
        "fit_s": time.perf_counter() - began,  # wall: the target
        "fit_cpu_s": time.process_time() - began_cpu,  # every thread's
        "found": {c: p["side"] for c, p in skill.side_preferences_.items()},
    }
    person, scene, line = data["demos"][held], data["scenes"][held], data["nominals"][held]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            plan = skill.plan(person[0], person[-1], scene).points
    except ValueError as error:
        row["refused"] = str(error)
        return row
    near = [o for o in scene if o.distance(person) < NEAR_PERSON or o.distance(line) < NEAR_LINE]
    same = [bool(lateral_side(plan, line, o) @ lateral_side(person, line, o) > 0.0) for o in near]
    row["passes"], row["same"] = len(same), int(sum(same))
    row["carton_same"] = all(s for s, o in zip(same, near, strict=True) if o.label == "carton")
    row["plan_mm"] = metrics.held_out_distances(plan, person)["mean"]
    row["line_mm"] = metrics.held_out_distances(line, person)["mean"]
    row["clearance_ratio"] = float(
        metrics.clearance(plan, scene).min() / metrics.clearance(person, scene).min()
    )
    row["collisions"] = metrics.collisions(plan, scene)
    return row


def summarise(rows: list[dict]) -> dict:
    """The folds' figures (module docstring)."""
    done = [r for r in rows if "refused" not in r]
    ratios = [r["clearance_ratio"] for r in done] or [float("nan")]
    return {
        "folds": len(rows),
        "refused": len(rows) - len(done),
        "found": sum(bool(r["found"]) for r in rows),
        "sides": [sum(r["same"] for r in done), sum(r["passes"] for r in done)],
        "carton_sides": [sum(r["carton_same"] for r in done), len(done)],
        "plan_mm_mean": float(np.mean([r["plan_mm"] for r in done])) if done else None,
        "plan_mm_median": float(np.median([r["plan_mm"] for r in done])) if done else None,
        "line_mm_mean": float(np.mean([r["line_mm"] for r in done])) if done else None,
        "clearance_ratio_least": float(np.min(ratios)),
        "clearance_ratio_median": float(np.median(ratios)),
        "collisions": int(sum(r["collisions"] for r in done)),
        "fit_s_median": float(np.median([r["fit_s"] for r in rows])),
        "fit_s_max": float(np.max([r["fit_s"] for r in rows])),
        "fit_cpu_s_median": float(np.median([r["fit_cpu_s"] for r in rows])),
    }


def control_found(data: dict) -> int:
    """In how many leave-one-out training sets a side preference is found."""
    n = len(data["demos"])
    count = 0
    for held in range(n):
        keep = [j for j in range(n) if j != held]
        parts = [[data[key][j] for j in keep] for key in ("demos", "scenes", "nominals")]
        count += bool(side_preferences(*parts))
    return count


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="two folds")
    parser.add_argument("--dims", type=int, choices=(2, 3), default=3)
    parser.add_argument("--demos", type=int, default=8, help="demonstrations (8)")
    parser.add_argument("--reach", type=float, default=1.0, help="start to goal, m (1.0)")
    parser.add_argument("--seed", type=int, default=0, help="the people's seed (0)")
    parser.add_argument("--output", type=Path, default=Path("benchmarks/results/boxes_sides"))
    args = parser.parse_args()
    kept = make_set(args.dims, args.demos, args.seed, True, args.reach)
    rows = [run_fold(kept, held) for held in range(2 if args.quick else args.demos)]
    summary = summarise(rows)
    control = make_set(args.dims, args.demos, args.seed, False, args.reach)
    control_sets = control_found(control)
    print(
        f"{'person':<8} {'folds':>5} {'found':>5} {'sides':>6} {'carton':>6} "
        f"{'plan/line mm':>13} {'median':>6} {'clear/p least/med':>17} {'coll':>4} "
        f"{'refused':>7} {'fit s med/max':>13} {'cpu s':>5}"
    )
    plan_mm = summary["plan_mm_mean"] or float("nan")
    line_mm = summary["line_mm_mean"] or float("nan")
    median_mm = summary["plan_mm_median"] or float("nan")
    print(
        f"{'keeping':<8} {summary['folds']:>5} {summary['found']:>5} "
        f"{'{}/{}'.format(*summary['sides']):>6} {'{}/{}'.format(*summary['carton_sides']):>6} "
        f"{plan_mm:>6.0f}/{line_mm:<6.0f} {median_mm:>6.0f} "
        f"{summary['clearance_ratio_least']:>8.2f}/{summary['clearance_ratio_median']:<8.2f} "
        f"{summary['collisions']:>4} {summary['refused']:>7} "
        f"{summary['fit_s_median']:>6.1f}/{summary['fit_s_max']:<6.1f} "
        f"{summary['fit_cpu_s_median']:>5.1f}"
    )
    print(f"control: a preference found in {control_sets} of {args.demos} training sets (0)")
    args.output.mkdir(parents=True, exist_ok=True)
    path = write_json(
        args.output / "boxes_sides.json",
        {
            "benchmark": "boxes_sides",
            "args": {k: str(v) if isinstance(v, Path) else v for k, v in vars(args).items()},
            "keeping": {"summary": summary, "folds": rows},
            "control_sets_with_preference": control_sets,
            "git": git_state(),
            "machine": machine_info(),
        },
    )
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
