"""The thesis's sweeping experiment in MuJoCo (§6.4): random unseen scenes, several planners.

A scenario moves the dustpan and places one cup and one marker near the
straight sweep from the cube to the dustpan (:func:`random_scenarios`). Each
planner turns (start, goal, scene) into a table path; :func:`run_experiment`
executes every path with :func:`lfdkit.robot.sim.execute_sweep` and
:func:`summarize` counts the outcomes per planner.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from lfdkit._validation import check_positive, check_random_state
from lfdkit.emulate import Reward, plan_path
from lfdkit.robot.sim import Dustpan, SweepingTask, SweepResult, execute_sweep
from lfdkit.scene import Obstacle, Scene
from lfdkit.skill import Skill

__all__ = [
    "GOAL_APPROACH",
    "SweepScenario",
    "default_planners",
    "random_scenarios",
    "run_experiment",
    "summarize",
]

#: Stretch before the dustpan over which plans return to the nominal (m): the dustpan's depth.
GOAL_APPROACH = 0.1
#: Where the thesis's dustpan stands (middle of its opening), m.
NOMINAL_DUSTPAN = np.array([0.38, 0.45])
_RADIUS = {"cup": 0.03, "marker": 0.01}

Planner = Callable[[np.ndarray, np.ndarray, Scene], np.ndarray]
Progress = Callable[[str], None]


@dataclass(frozen=True)
class SweepScenario:
    """An unseen scene: the dustpan and the obstacles (the cube starts at ``start``).

    Attributes
    ----------
    start : ndarray, shape (2,)
        Start of the sweep (the brush behind the cube), m.
    dustpan : Dustpan
    scene : Scene
    """

    start: np.ndarray
    dustpan: Dustpan
    scene: Scene

    @property
    def goal(self) -> np.ndarray:
        """Where the brush stops: just inside the dustpan, on its centre line (2,)."""
        return self.dustpan.goal()


def random_scenarios(
    n: int,
    seed: Any = None,
    *,
    start: Any = (-0.4, 0.45),
    dustpan_shift: tuple[float, float] = (0.12, 0.08),
    lateral: float = 0.03,
) -> list[SweepScenario]:
    """Random unseen sweeping scenes.

    The dustpan's opening moves from :data:`NOMINAL_DUSTPAN` by up to
    ``dustpan_shift[0]`` towards the cube and ``±dustpan_shift[1]``
    sideways (uniform), facing the cube. A cup and a marker stand near the
    straight line from the start to the dustpan: one at a fraction
    ``U[0.3, 0.45]`` of the way, the other (random order) at ``U[0.55, 0.7]``,
    each ``U[−lateral, lateral]`` off the line. With the 5 cm brush every
    obstacle within 5.5 cm (cup) or 3.5 cm (marker) of the line is hit by a
    straight sweep.

    Parameters
    ----------
    n : int
        Number of scenarios.
    seed : None, int or numpy.random.Generator
    start : array_like, shape (2,)
        Start of the sweep, m.
    dustpan_shift : (float, float)
        Largest move of the dustpan along and across the sweep, m.
    lateral : float
        Largest offset of an obstacle from the line, m.

    Returns
    -------
    list of SweepScenario
    """
    n = check_positive(n, "n", integer=True)
    rng = check_random_state(seed)
    start = np.asarray(start, dtype=np.float64)
    scenarios = []
    for _ in range(n):
        shift = np.array(
            [-rng.uniform(0.0, dustpan_shift[0]), rng.uniform(-dustpan_shift[1], dustpan_shift[1])]
        )
        opening = NOMINAL_DUSTPAN + shift
        direction = opening - start
        yaw = math.atan2(direction[1], direction[0])
        dustpan = Dustpan(opening, yaw)
        line = dustpan.goal() - start
        normal = np.array([-line[1], line[0]]) / np.linalg.norm(line)
        fractions = [rng.uniform(0.3, 0.45), rng.uniform(0.55, 0.7)]
        labels = ["cup", "marker"] if rng.random() < 0.5 else ["marker", "cup"]
        obstacles = tuple(
            Obstacle(
                label, start + u * line + rng.uniform(-lateral, lateral) * normal, _RADIUS[label]
            )
            for label, u in zip(labels, fractions, strict=True)
        )
        scenarios.append(SweepScenario(start.copy(), dustpan, Scene(obstacles)))
    return scenarios


def default_planners(skill: Skill, true_reward: Reward | None = None) -> dict[str, Planner]:
    """The planners compared in the experiment.

    * ``learned skill``: :meth:`Skill.plan` with the goal approach
      (:data:`GOAL_APPROACH`), MPC as on the robot;
    * ``learned, thesis end``: the same without the goal term (the thesis's model);
    * ``replay generalized path``: the generalized path as demonstrated;
    * ``DMP alone``: the DMP carried to the new goal, obstacles ignored;
    * ``true reward`` (when given): the demonstrator's own reward, same planner.
    """

    def learned(start: np.ndarray, goal: np.ndarray, scene: Scene) -> np.ndarray:
        return skill.plan(start, goal, scene, goal_approach=GOAL_APPROACH)

    planners: dict[str, Planner] = {
        "learned skill": learned,
        "learned, thesis end": lambda start, goal, scene: skill.plan(
            start, goal, scene, goal_approach=None
        ),
        "replay generalized path": lambda start, goal, scene: skill.path_,
        "DMP alone": lambda start, goal, scene: skill.nominal(start, goal),
    }
    if true_reward is not None:

        def true_plan(start: np.ndarray, goal: np.ndarray, scene: Scene) -> np.ndarray:
            return plan_path(
                true_reward,
                skill.nominal(start, goal),
                scene,
                horizon=int(skill.horizon),
                n_points=int(skill.n_points),
                goal_approach=GOAL_APPROACH,
            ).points

        planners["true reward"] = true_plan
    return planners


def run_experiment(
    scenarios: Sequence[SweepScenario],
    planners: dict[str, Planner],
    *,
    speed_fraction: float = 0.2,
    progress: Progress | None = None,
) -> list[dict]:
    """Plan and simulate every scenario with every planner.

    Returns
    -------
    list of dict
        One per (scenario, planner): ``scenario``, ``planner``, ``success``,
        ``cube_in_dustpan``, ``touched`` (number of obstacles touched),
        ``tracking_error`` and ``path_error`` (m), ``duration`` (s of robot
        motion), ``plan_s`` (planning time), ``failures`` (list of str) and
        ``result`` (the :class:`SweepResult`).
    """
    rows = []
    for index, scenario in enumerate(scenarios):
        for name, planner in planners.items():
            begin = time.perf_counter()
            try:
                path = np.asarray(planner(scenario.start, scenario.goal, scenario.scene), float)
                plan_s = time.perf_counter() - begin
                # A path that is not a path (NaN, wrong shape) fails here, not in the simulator.
                task = SweepingTask.for_path(path, scenario.dustpan, scenario.scene)
            except ValueError as exc:
                rows.append(_row(index, name, None, float("nan"), f"planning failed: {exc}"))
                continue
            result = execute_sweep(path, task, speed_fraction=speed_fraction)
            rows.append(_row(index, name, result, plan_s))
        if progress is not None:
            progress(f"scenario {index + 1}/{len(scenarios)}")
    return rows


def _row(
    index: int, name: str, result: SweepResult | None, plan_s: float, failure: str = ""
) -> dict:
    if result is None:
        return {
            "scenario": index,
            "planner": name,
            "success": False,
            "cube_in_dustpan": False,
            "touched": 0,
            "tracking_error": float("nan"),
            "path_error": float("nan"),
            "duration": float("nan"),
            "plan_s": plan_s,
            "failures": [failure],
            "result": None,
        }
    return {
        "scenario": index,
        "planner": name,
        "success": result.success,
        "cube_in_dustpan": result.cube_in_dustpan,
        "touched": len(result.touched),
        "tracking_error": result.tracking_error,
        "path_error": result.path_error,
        "duration": result.duration,
        "plan_s": plan_s,
        "failures": list(result.failures),
        "result": result,
    }


def summarize(rows: Sequence[dict]) -> dict[str, dict]:
    """Per planner: runs, success / cube-in-dustpan / no-touch rates and tracking errors."""
    out: dict[str, dict] = {}
    for name in dict.fromkeys(row["planner"] for row in rows):
        mine = [row for row in rows if row["planner"] == name]
        tracking = np.array([row["tracking_error"] for row in mine], dtype=float)
        finite = tracking[np.isfinite(tracking)]
        out[name] = {
            "runs": len(mine),
            "success_rate": float(np.mean([row["success"] for row in mine])),
            "cube_in_dustpan_rate": float(np.mean([row["cube_in_dustpan"] for row in mine])),
            "no_touch_rate": float(np.mean([row["touched"] == 0 for row in mine])),
            "tracking_max_m": float(finite.max()) if finite.size else float("nan"),
            "tracking_median_m": float(np.median(finite)) if finite.size else float("nan"),
            "not_run": int(np.sum(~np.isfinite(tracking))),
            "duration_median_s": float(
                np.nanmedian([row["duration"] for row in mine]) if finite.size else float("nan")
            ),
        }
    return out
