"""A skill evaluated over many sweeping scenes, in batch: ``lfdkit batch evaluate``.

:func:`evaluate_scenario` is the work unit: one skill (its JSON text) on one
scene, checked as far as asked (:data:`CHECKS`):

``plan``
    the plan to the dustpan around the obstacles, with the brush's half
    width as clearance (:meth:`lfdkit.skill.Skill.plan_details`, as
    :func:`~lfdkit.tasks.sweeping.execution.execute_skill` plans), ~30 ms;
``kinematics``
    and the flange poses and one continuous inverse-kinematics branch
    (:func:`~lfdkit.tasks.sweeping.sim.sweep_motion`), ~0.1 s;
``robot``
    :func:`~lfdkit.tasks.sweeping.execution.execute_skill` without the
    simulation: also the timing, the URScript stream and its limit checks,
    ~0.2 s;
``mujoco``
    the whole chain and the sweep simulated in MuJoCo, ~1.5–3 s at the
    thesis's 0.2 of the joint limits.

A scene is either random (:func:`scenario` of a base seed and the task's
index: the dustpan moved, a cup and a marker near the sweep, as
:func:`~lfdkit.tasks.sweeping.scenarios.random_scenarios` makes them, from a
generator seeded by ``SeedSequence(seed, spawn_key=(index,))``, so task ``i``
is the same scene in any batch, on any worker) or one scene of a scene file.
The unit returns a JSON-ready row; what the robot cannot do, or a plan that
cannot keep clear, is an outcome (``ok`` false, ``failure``), not an error.

:func:`evaluate_batch` runs the units with :func:`lfdkit.app.batch.run_batch` on
any executor of :func:`lfdkit.app.batch.make_executor`.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Iterator, Mapping
from concurrent.futures import Executor
from pathlib import Path
from typing import Any

import numpy as np

from lfdkit.app.batch import (
    BatchSummary,
    SerialExecutor,
    check_evaluate_arguments,
    check_random_count,
    error_line,
    evaluate_row,
    evaluate_spec,
    load_compiled,
    run_batch,
    skill_ends,
    skill_from_text,
)
from lfdkit.core.progress import ProgressLike
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.tasks.sweeping.scenarios import (
    BRUSH,
    GOAL_APPROACH,
    SweepScenario,
    obstacle_class,
    random_scenarios,
)

__all__ = [
    "CHECKS",
    "evaluate_batch",
    "evaluate_scenario",
    "random_tasks",
    "scenario",
    "scene_tasks",
]

#: How far :func:`evaluate_scenario` carries a plan, cheapest first.
CHECKS = ("plan", "kinematics", "robot", "mujoco")


def scenario(seed: int, index: int) -> SweepScenario:
    """Random scene ``index`` of the batch seeded ``seed``: the same whatever else is drawn."""
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index,)))
    return random_scenarios(1, rng)[0]


def _standing(obstacles: Any) -> Scene:
    """Obstacles ``[label, x, y, radius]`` as a scene, each with the radius it stands with."""
    scene = []
    for label, x, y, radius in obstacles:
        found = Obstacle(str(label), (float(x), float(y)), float(radius))
        scene.append(
            Obstacle(found.label, found.position, obstacle_class(label).cylinder_radius(found))
        )
    return Scene(tuple(scene))


def _listed(scene: Scene) -> list[list[Any]]:
    return [[o.label, *map(float, o.position), float(o.radius)] for o in scene]


def evaluate_scenario(
    skill_text: str,
    where: Mapping[str, Any],
    check: str = "robot",
    speed_fraction: float = 0.2,
) -> dict[str, Any]:
    """Evaluate a skill on one sweeping scene: the work unit of ``lfdkit batch evaluate``.

    Parameters
    ----------
    skill_text : str
        The skill file's JSON text (parsed once per worker and kept).
    where : mapping
        ``{"seed": S, "index": I}`` for random scene ``I`` (:func:`scenario`),
        or ``{"scene": ID, "obstacles": [[label, x, y, radius], ...], "start":
        [x, y] or None, "goal": [x, y] or None}`` (None: the skill's path's
        ends; a radius 0 is the class's).
    check : {"plan", "kinematics", "robot", "mujoco"}
        How far to carry the plan (:data:`CHECKS`).
    speed_fraction : float
        Fraction of the UR5's joint limits the motion is timed at (robot, mujoco).

    Returns
    -------
    dict
        ``scenario`` (``where`` without the obstacles), ``start``, ``goal``
        (m), ``obstacles`` (``[label, x, y, radius]``, as they stand),
        ``check``, ``ok`` (the checks passed: plan clear, robot able, sweep
        successful), ``failure`` (one line, or None), and by stage reached:
        ``plan`` (``length_m``, ``goal_error_m``, ``clearance_m`` beyond
        radius plus half the brush), ``robot`` (``poses``; from ``robot``
        on also ``motion_s``, ``tool_speed_max_m_s``,
        ``joint_speed_of_limit``), ``simulation`` (``success``,
        ``cube_in_dustpan``, ``touched``, ``tracking_error_m``,
        ``path_error_m``, ``failures``). No wall times: the row depends on
        the inputs only.
    """
    from lfdkit.core.geometry import path_length
    from lfdkit.core.threads import one_blas_thread
    from lfdkit.emulate import UnsafePlanError

    if check not in CHECKS:
        raise ValueError(f"check: expected one of {', '.join(CHECKS)}, got {check!r}")
    if check == "plan":
        # Planning alone needs neither the robot nor SciPy (the execution pipeline imports
        # it): a worker that only plans starts about a second sooner (issue 30).
        failures: tuple[type[Exception], ...] = (UnsafePlanError,)
    else:
        from lfdkit.execute import ur5
        from lfdkit.tasks.sweeping.execution import ExecutionError, execute_skill
        from lfdkit.tasks.sweeping.sim import sweep_motion

        failures = (UnsafePlanError, ExecutionError)
        # numba's kernels from the first task on, whatever the executor: the timing law's
        # NumPy form agrees with them to round-off only (a 2-D plan, bit for bit), and a row
        # must not depend on which kernels a process had turned to (issue 30).
        load_compiled()
    skill = skill_from_text(skill_text)
    if "index" in where:
        drawn = scenario(int(where["seed"]), int(where["index"]))
        start, goal, scene = drawn.start, drawn.goal, _standing(_listed(drawn.scene))
        identity = {"seed": int(where["seed"]), "index": int(where["index"])}
    else:
        start, goal = skill_ends(skill, where)
        scene = _standing(where.get("obstacles", ()))
        identity = {"scene": where["scene"]}
    row = evaluate_row(identity, start, goal, _listed(scene), check)
    with one_blas_thread():
        try:
            if check in ("plan", "kinematics"):
                plan = skill.plan_details(
                    start, goal, scene, goal_approach=GOAL_APPROACH, clearance=0.5 * BRUSH.width
                )
                row["plan"] = _plan_row(plan, path_length)
                if check == "kinematics":
                    try:
                        poses, _ = sweep_motion(plan.points)
                    except ur5.KinematicsError as exc:
                        raise ExecutionError(f"the UR5 cannot follow the plan: {exc}") from None
                    row["robot"] = {"poses": len(poses)}
            else:
                run = execute_skill(
                    skill,
                    start,
                    goal,
                    scene,
                    speed_fraction=speed_fraction,
                    simulate=check == "mujoco",
                )
                row.update(_execution_row(run, path_length))
        except failures as exc:
            row["failure"] = error_line(exc)
            return row
    simulated = row.get("simulation")
    row["ok"] = True if simulated is None else bool(simulated["success"])
    if simulated is not None and not simulated["success"]:
        row["failure"] = "; ".join(simulated["failures"])
    return row


def _plan_row(plan: Any, path_length: Any) -> dict[str, Any]:
    return {
        "points": len(plan.points),
        "length_m": float(path_length(plan.points)),
        "goal_error_m": float(plan.goal_error),
        "clearance_m": float(np.min(plan.clearance)) if len(plan.clearance) else None,
    }


def _execution_row(run: Any, path_length: Any) -> dict[str, Any]:
    summary = run.summary()
    robot = summary["robot"]
    out: dict[str, Any] = {
        "plan": _plan_row(run.plan.details, path_length),
        "robot": {
            "poses": robot["poses"],
            "motion_s": robot["motion_s"],
            "tool_speed_max_m_s": robot["tool_speed_max_m_s"],
            "joint_speed_of_limit": robot["joint_speed_of_limit"],
        },
    }
    if run.result is not None:
        simulation = summary["simulation"]
        out["simulation"] = {
            key: simulation[key]
            for key in (
                "success",
                "cube_in_dustpan",
                "touched",
                "tracking_error_m",
                "path_error_m",
                "clearance_m",
                "failures",
            )
        }
    elif run.skipped and summary.get("simulation", {}).get("skipped") != "not asked for":
        raise RuntimeError(f"the simulation did not run: {run.skipped}")
    return out


# ------------------------------------------------------------------ tasks and batches
def random_tasks(
    skill_text: str, n: int, seed: int, check: str = "robot", speed_fraction: float = 0.2
) -> Iterator[tuple[int, tuple[Any, ...]]]:
    """``(index, args of evaluate_scenario)`` for random scenes ``0 … n-1``, lazily."""
    for index in range(n):
        yield index, (skill_text, {"seed": seed, "index": index}, check, speed_fraction)


def scene_tasks(
    skill_text: str,
    scenes: Mapping[Any, Scene],
    start: Any = None,
    goal: Any = None,
    check: str = "robot",
    speed_fraction: float = 0.2,
) -> Iterator[tuple[Any, tuple[Any, ...]]]:
    """``(scene id, args of evaluate_scenario)`` for each scene of a scene file, lazily."""
    ends = {
        "start": None if start is None else [float(v) for v in start],
        "goal": None if goal is None else [float(v) for v in goal],
    }
    for key, scene in scenes.items():
        where = {"scene": key, "obstacles": _listed(scene), **ends}
        yield key, (skill_text, where, check, speed_fraction)


def evaluate_batch(
    skill: str | os.PathLike[str],
    results: str | os.PathLike[str],
    *,
    random: int | None = None,
    seed: int = 0,
    scenes: str | os.PathLike[str] | None = None,
    start: Any = None,
    goal: Any = None,
    check: str = "robot",
    speed_fraction: float = 0.2,
    executor: Executor | None = None,
    overwrite: bool = False,
    window: int | None = None,
    progress: ProgressLike = None,
) -> BatchSummary:
    """Evaluate a skill file over many scenes, streaming one row per scene to ``results``.

    Parameters
    ----------
    skill : path
        A 2-D skill in metres (``lfdkit learn``).
    results : path
        The JSON-lines results file (:func:`lfdkit.app.batch.run_batch`): resumed
        when it holds this batch, refused when it holds another.
    random : int, optional
        Evaluate random scenes ``0 … random-1`` of ``seed`` (:func:`scenario`).
        The spec leaves the count out: a larger count on a rerun adds scenes.
    seed : int
        Base seed of the random scenes.
    scenes : path, optional
        A scene file (``.csv`` or ``.json``, many scenes by id) instead.
    start, goal : array_like, shape (2,), optional
        For the scenes of a file (default the skill's path's ends).
    check : {"plan", "kinematics", "robot", "mujoco"}
    speed_fraction : float
    executor : Executor, optional
        Default :class:`lfdkit.app.batch.SerialExecutor`.
    overwrite, window, progress
        As in :func:`lfdkit.app.batch.run_batch`.

    Returns
    -------
    lfdkit.app.batch.BatchSummary
    """
    from lfdkit.skill import Skill

    fraction = check_evaluate_arguments(random, scenes, check, CHECKS, speed_fraction)
    loaded = Skill.load(skill)  # the strict reader: a broken file is refused here, once
    if loaded.n_dims_ != 2 or loaded.units != "m":
        raise ValueError(
            f"{os.fspath(skill)}: a {loaded.n_dims_}-D skill in {loaded.units!r}; the sweeping "
            "task needs a 2-D skill in metres"
        )
    text = Path(skill).read_text(encoding="utf-8")
    spec = evaluate_spec("sweeping", text, check=check, speed_fraction=fraction)
    if random is not None:
        check_random_count(random, "scenes")
        spec["random"] = {"seed": int(seed)}
        tasks = random_tasks(text, random, int(seed), check, fraction)
        total = random
        label = f"evaluate {random:,} random scenes ({check})"
    else:
        from lfdkit.io.scenes import load_scenes

        found = load_scenes(scenes)
        flat = [key for key, scene in found.items() if len(scene) and scene.positions.shape[1] != 2]
        shaped = [
            (key, o.shape) for key, scene in found.items() for o in scene if o.shape != "round"
        ]
        if shaped:
            raise ValueError(
                f"{os.fspath(scenes)}: scene {shaped[0][0]!r} has a {shaped[0][1]} obstacle; the "
                "sweeping scene stands every obstacle as an upright cylinder (round ones only)"
            )
        if flat:
            raise ValueError(
                f"{os.fspath(scenes)}: scene {flat[0]!r} is not 2-D (x, y on the table)"
            )
        moving = [key for key, scene in found.items() if scene.moving]
        if moving:
            # The batch stands each obstacle still at its place (an upright cylinder in the
            # simulation); evaluating a moving one there would report a run that never happened.
            raise ValueError(
                f"{os.fspath(scenes)}: scene {moving[0]!r} has a moving obstacle; batch "
                "evaluate checks standing obstacles only; evaluate moving scenes one by one "
                "with lfdkit plan (it plans against the motion), or drop the velocities"
            )
        spec["scenes"] = hashlib.sha256(Path(scenes).read_bytes()).hexdigest()
        spec["start"] = None if start is None else [float(v) for v in start]
        spec["goal"] = None if goal is None else [float(v) for v in goal]
        tasks = scene_tasks(text, found, start, goal, check, fraction)
        total = len(found)
        label = f"evaluate {total:,} scenes of {Path(scenes).name} ({check})"
    return run_batch(
        executor or SerialExecutor(),
        evaluate_scenario,
        tasks,
        results,
        spec=spec,
        total=total,
        overwrite=overwrite,
        window=window,
        progress=progress,
        label=label,
    )
