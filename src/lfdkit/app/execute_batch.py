"""Any skill on any arm over many scenes or goals, in batch: ``lfdkit batch evaluate --task path``.

The sweeping task has its own batch (:mod:`lfdkit.tasks.sweeping.batch`:
brush, dustpan, cups); this is the same for the generic chain of
:func:`lfdkit.execute.pipeline.execute_plan`: one fitted skill (2-D or 3-D,
with or without orientation), one arm (a name of
:data:`lfdkit.execute.arm.ARMS` or a URDF, its XML sent to the workers), one
:class:`~lfdkit.execute.pipeline.TaskDescription` (frame, tool, plane
height, default orientation, start configuration), carried over

* the scenes of a scene file (each with the same start and goal), or
* ``N`` random goals: goal ``i`` of base seed ``S`` is drawn uniformly in a
  ball of radius ``spread`` around the goal, from
  ``SeedSequence(S, spawn_key=(i,))``, so task ``i`` is the same goal in any
  batch, on any worker.

:func:`evaluate_task` is the work unit, checked as far as asked
(:data:`TASK_CHECKS`): ``plan`` (the skill's timed plan, ~0.1 s for 100
points), ``robot`` (+ poses, inverse kinematics, the person's timing kept
within the limits, samples, program; ~0.5 s), ``mujoco`` (+ the MuJoCo
check: tracking error and obstacles touched; ~2 s for a 4 s motion).
What the arm cannot do (out of reach, a joint limit) or a plan that cannot
keep clear is an outcome (``ok`` false, ``failure``), not an error; a
simulated run is ``ok`` when nothing was touched and the tool tracked within
:data:`TRACKING_TOLERANCE` (2 mm, issue 29's bar).

:func:`outcome_table` reads a results file back into one table (counts,
duration ratios, slowdowns, tracking) as text and as JSON.
"""

from __future__ import annotations

import hashlib
import os
import warnings
from collections.abc import Iterator, Mapping, Sequence
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
    read_results,
    run_batch,
    skill_ends,
    skill_from_text,
    worker_cached,
)
from lfdkit.core.progress import ProgressLike

__all__ = [
    "TASK_CHECKS",
    "TRACKING_TOLERANCE",
    "arm_spec",
    "evaluate_task",
    "evaluate_task_batch",
    "outcome_table",
    "random_goal",
]

#: How far :func:`evaluate_task` carries a plan, cheapest first.
TASK_CHECKS = ("plan", "robot", "mujoco")
#: Largest simulated tool tracking error of a run counted ``ok`` (m).
TRACKING_TOLERANCE = 0.002


def arm_spec(arm: str | os.PathLike[str], tip_link: str | None = None) -> dict[str, Any]:
    """What a worker needs to build the arm: ``{"arm": NAME}`` or ``{"urdf": XML, "tip_link": T}``.

    Parameters
    ----------
    arm : str or path
        A key of :data:`lfdkit.execute.arm.ARMS` (``"ur5"``) or a URDF file.
    tip_link : str, optional
        With a URDF: the link the tool is on.

    Raises
    ------
    ValueError
        Neither an arm name nor a URDF file, or a URDF that does not read
        (checked here, once, not in every task).
    """
    from lfdkit.execute.arm import ARMS
    from lfdkit.execute.urdf import UrdfArm

    name = os.fspath(arm)
    if name in ARMS:
        if tip_link is not None:
            raise ValueError(f"tip_link: is for a URDF arm; the {name} has its own flange")
        return {"arm": name}
    path = Path(name)
    if not path.is_file():
        raise ValueError(f"arm: {name} is neither an arm name ({', '.join(ARMS)}) nor a URDF file")
    text = path.read_text(encoding="utf-8")
    try:
        UrdfArm(text, tip_link=tip_link)
    except ValueError as exc:
        raise ValueError(f"{name}: {str(exc).splitlines()[0]}") from None
    return {"urdf": text, "tip_link": tip_link}


def _arm(spec: Mapping[str, Any]) -> Any:
    from lfdkit.execute.arm import ARMS
    from lfdkit.execute.urdf import UrdfArm

    if "arm" in spec:
        return ARMS[spec["arm"]]
    text = str(spec["urdf"])
    tip = spec.get("tip_link")
    return worker_cached("arm", f"{tip}\n{text}", lambda: UrdfArm(text, tip_link=tip))


def random_goal(goal: Any, spread: float, seed: int, index: int) -> np.ndarray:
    """Goal ``index`` of base seed ``seed``: uniform in the ball of radius ``spread`` at ``goal``.

    Parameters
    ----------
    goal : array_like, shape (q,)
        The centre (m).
    spread : float
        The ball's radius (m), >= 0.
    seed, index : int

    Returns
    -------
    ndarray, shape (q,)
    """
    centre = np.asarray(goal, dtype=np.float64)
    rng = np.random.default_rng(np.random.SeedSequence(seed, spawn_key=(index,)))
    direction = rng.standard_normal(centre.shape)
    direction /= max(float(np.linalg.norm(direction)), 1e-300)
    radius = spread * rng.random() ** (1.0 / centre.size)  # uniform in the ball's volume
    return centre + radius * direction


def evaluate_task(
    skill_text: str,
    where: Mapping[str, Any],
    arm: Mapping[str, Any],
    task: Mapping[str, Any],
    check: str = "robot",
    speed_fraction: float = 0.2,
    rate: float | None = None,
    unknown_class: float | None = None,
    via: Sequence[tuple[float, Any]] | None = None,
    unknown_response: str | None = None,
) -> dict[str, Any]:
    """Evaluate a skill on an arm for one scene or goal: the work unit of the path task's batch.

    Parameters
    ----------
    skill_text : str
        The skill file's JSON text, in metres (parsed once per worker).
    where : mapping
        ``{"scene": ID, "obstacles": Scene, "start": [..] or None, "goal":
        [..] or None}`` (None: the skill's path's ends), or ``{"seed": S,
        "index": I, "spread": R, "start": .., "goal": ..}`` for random goal
        ``I`` (:func:`random_goal` around ``goal``).
    arm : mapping
        :func:`arm_spec`'s.
    task : mapping
        :meth:`lfdkit.execute.pipeline.TaskDescription.to_dict`'s.
    check : {"plan", "robot", "mujoco"}
    speed_fraction : float
        Fraction of the arm's joint limits the timing may use.
    rate : float, optional
        Rate of the fixed-rate samples (Hz; default
        :data:`lfdkit.execute.pipeline.DEFAULT_RATE`).
    unknown_class : float, optional
        Plan around obstacles of classes the skill never learned with this
        margin (m; :meth:`lfdkit.skill.Skill.plan`); without it they are refused.
    via : sequence of (float, array_like (q,)), optional
        Via-points ``(phase, point)`` (m) every plan passes
        (:meth:`lfdkit.skill.Skill.plan`'s ``via``).
    unknown_response : str, optional
        With ``unknown_class``, the response such an obstacle gets besides
        (:meth:`lfdkit.skill.Skill.plan`'s ``unknown_response``).

    Returns
    -------
    dict
        ``scenario``, ``start``, ``goal`` (m), ``obstacles`` (their count),
        ``check``, ``ok``, ``failure`` (one line or None), and by stage:
        ``plan`` (``points``, ``length_m``, ``duration_s``,
        ``goal_error_m``, ``clearance_m``), ``robot`` (``poses``,
        ``motion_s``, ``duration_ratio``, ``timing``, ``slowed``,
        ``joint_speed_of_limit``, ``joint_acceleration_of_limit``,
        ``tool_speed_max_m_s``, ``samples``), ``simulation``
        (``tracking_error_m``, ``touched``). No wall times: the row depends
        on the inputs only.
    """
    from lfdkit.core.geometry import path_length
    from lfdkit.core.threads import one_blas_thread
    from lfdkit.emulate import UnsafePlanError
    from lfdkit.execute.pipeline import DEFAULT_RATE, ExecutionError, TaskDescription, execute_plan
    from lfdkit.model.scene import Scene

    if check not in TASK_CHECKS:
        raise ValueError(f"check: expected one of {', '.join(TASK_CHECKS)}, got {check!r}")
    # numba's kernels from the first task on, whatever the executor: their NumPy forms agree
    # with them to round-off only for 3-D plans and the timing law, and a row must not
    # depend on which kernels a process had turned to (issue 30).
    load_compiled()
    skill = skill_from_text(skill_text)
    robot_arm = _arm(arm)
    description = TaskDescription.from_dict(dict(task))
    start, goal = skill_ends(skill, where)
    if "index" in where:
        identity = {"seed": int(where["seed"]), "index": int(where["index"])}
        goal = random_goal(goal, float(where["spread"]), identity["seed"], identity["index"])
        scene = Scene(())
    else:
        identity = {"scene": where["scene"]}
        scene = where.get("obstacles") or Scene(())
    row = evaluate_row(identity, start, goal, len(scene), check)
    with one_blas_thread():
        try:
            with warnings.catch_warnings():  # the margin was asked for: no warning per task
                warnings.filterwarnings("ignore", r"plan: obstacle class.* never learned")
                plan = skill.plan(
                    start,
                    goal,
                    scene,
                    unknown_class=unknown_class,
                    unknown_response=unknown_response,
                    via=via,
                )
            details = plan.details
            row["plan"] = {
                "points": len(plan.times),
                "length_m": float(path_length(plan.points)),
                "duration_s": float(plan.times[-1] - plan.times[0]),
                "goal_error_m": float(details.goal_error),
                "clearance_m": float(np.min(details.clearance)) if len(details.clearance) else None,
            }
            if check != "plan":
                run = execute_plan(
                    plan,
                    robot_arm,
                    description,
                    speed_fraction=speed_fraction,
                    rate=DEFAULT_RATE if rate is None else rate,
                )
                robot = run.summary()["robot"]
                keys = (
                    "poses",
                    "motion_s",
                    "duration_ratio",
                    "timing",
                    "joint_speed_of_limit",
                    "joint_acceleration_of_limit",
                    "tool_speed_max_m_s",
                    "samples",
                )
                row["robot"] = {key: robot[key] for key in keys}
                row["robot"]["slowed"] = bool(run.trajectory.slowdowns)
        except (UnsafePlanError, ExecutionError) as exc:
            row["failure"] = error_line(exc)
            return row
        if check == "mujoco":
            from lfdkit.execute.simulation import simulate_execution

            found = simulate_execution(run, scene)
            row["simulation"] = {
                "tracking_error_m": found.tracking_error,
                "touched": [int(k) for k in found.touched],
            }
            failures = []
            if found.touched:
                failures.append(f"touched obstacle(s) {', '.join(map(str, found.touched))}")
            if found.tracking_error > TRACKING_TOLERANCE:
                failures.append(
                    f"tracking error {1e3 * found.tracking_error:.2f} mm > "
                    f"{1e3 * TRACKING_TOLERANCE:g} mm"
                )
            if failures:
                row["failure"] = "; ".join(failures)
                return row
    row["ok"] = True
    return row


def _task_list(
    skill_text: str,
    arm: Mapping[str, Any],
    task: Mapping[str, Any],
    check: str,
    fraction: float,
    rate: float | None,
    unknown_class: float | None,
    via: list[Any] | None,
    unknown_response: str | None,
    wheres: Iterator[tuple[Any, dict[str, Any]]],
) -> Iterator[tuple[Any, tuple[Any, ...]]]:
    for key, where in wheres:
        yield (
            key,
            (
                skill_text,
                where,
                arm,
                task,
                check,
                fraction,
                rate,
                unknown_class,
                via,
                unknown_response,
            ),
        )


def _point(value: Any, name: str, dims: int) -> list[float] | None:
    if value is None:
        return None
    arr = np.asarray(value, dtype=np.float64)
    if arr.shape != (dims,) or not np.isfinite(arr).all():
        raise ValueError(f"{name}: expected {dims} finite coordinates (m), got {value!r}")
    return arr.tolist()


def evaluate_task_batch(
    skill: str | os.PathLike[str],
    results: str | os.PathLike[str],
    *,
    arm: str | os.PathLike[str] = "ur5",
    tip_link: str | None = None,
    task: Any = None,
    random: int | None = None,
    seed: int = 0,
    spread: float = 0.05,
    scenes: str | os.PathLike[str] | None = None,
    start: Any = None,
    goal: Any = None,
    check: str = "robot",
    speed_fraction: float = 0.2,
    rate: float | None = None,
    unknown_class: float | None = None,
    unknown_response: str | None = None,
    via: Sequence[tuple[float, Any]] | None = None,
    executor: Executor | None = None,
    overwrite: bool = False,
    window: int | None = None,
    progress: ProgressLike = None,
) -> BatchSummary:
    """Evaluate a skill file on an arm over many scenes or goals, one JSON line per task.

    Parameters
    ----------
    skill : path
        A skill in metres (``lfdkit learn``), 2-D or 3-D.
    results : path
        The JSON-lines results file (:func:`lfdkit.app.batch.run_batch`):
        resumed when it holds this batch, refused when it holds another.
    arm : str or path
        A name of :data:`lfdkit.execute.arm.ARMS` or a URDF file.
    tip_link : str, optional
        With a URDF: the link the tool is on.
    task : TaskDescription, mapping or path, optional
        The task description, or its JSON file
        (:meth:`lfdkit.execute.pipeline.TaskDescription.from_dict`).
    random : int, optional
        Evaluate random goals ``0 … random-1`` of ``seed`` within ``spread``
        (m) of ``goal`` (:func:`random_goal`). The count is left out of the
        spec: a larger count on a rerun adds goals.
    scenes : path, optional
        A scene file (``.csv`` or ``.json``) instead: each scene with
        ``start`` and ``goal``.
    start, goal : array_like, shape (q,), optional
        Default: the skill's path's ends.
    check : {"plan", "robot", "mujoco"}
    speed_fraction : float
        In ``(0, 1]``.
    rate : float, optional
        Rate of the fixed-rate samples (Hz).
    unknown_class : float, optional
        Margin (m) for obstacles of classes the skill never learned.
    unknown_response : str, optional
        With ``unknown_class``, the response such an obstacle gets besides:
        None (none), ``"nearest"`` or a learned class
        (:meth:`lfdkit.skill.Skill.plan`'s ``unknown_response``).
    via : sequence of (float, array_like (q,)), optional
        Via-points ``(phase, point)`` (m) every plan passes, the phase a
        fraction of the plan's duration (:meth:`lfdkit.skill.Skill.plan`).
    executor : Executor, optional
        Default :class:`lfdkit.app.batch.SerialExecutor`.
    overwrite, window, progress
        As in :func:`lfdkit.app.batch.run_batch`.

    Returns
    -------
    lfdkit.app.batch.BatchSummary
    """
    from lfdkit.execute.pipeline import TaskDescription
    from lfdkit.imitate.via_points import check_via
    from lfdkit.io.text import load_json
    from lfdkit.skill import Skill

    fraction = check_evaluate_arguments(random, scenes, check, TASK_CHECKS, speed_fraction)
    if rate is not None and not 1.0 <= float(rate) <= 1000.0:
        raise ValueError(f"rate: must be in [1, 1000] Hz, got {rate!r}")
    if task is None:
        description = TaskDescription()
    elif isinstance(task, TaskDescription):
        description = task
    elif isinstance(task, Mapping):
        description = TaskDescription.from_dict(dict(task))
    else:
        description = TaskDescription.from_dict(load_json(os.fspath(task)), os.fspath(task))
    machine = arm_spec(arm, tip_link)
    loaded = Skill.load(skill)  # the strict reader: a broken file is refused here, once
    if loaded.units != "m":
        raise ValueError(
            f"{os.fspath(skill)}: a skill in {loaded.units!r}; the robot works in metres: "
            "convert it with Skill.to_units('m') (lfdkit learn --units)"
        )
    dims = loaded.n_dims_
    ends = {"start": _point(start, "start", dims), "goal": _point(goal, "goal", dims)}
    if via is not None:  # checked once here, and as plain lists: the spec is JSON
        phases, points = check_via(via, dims)
        turns = [list(map(float, e[2])) if len(e) > 2 and e[2] is not None else None for e in via]
        via = [
            [float(s), [float(v) for v in p], *([q] if q is not None else [])]
            for s, p, q in zip(phases, points, turns, strict=True)
        ]
    text = Path(skill).read_text(encoding="utf-8")
    spec = evaluate_spec(
        "path",
        text,
        arm=machine.get("arm") or hashlib.sha256(machine["urdf"].encode()).hexdigest(),
        tip_link=tip_link,
        description=description.to_dict(),
        check=check,
        speed_fraction=fraction,
        rate=rate,
        unknown_class=unknown_class,
        **ends,
    )
    if via is not None:  # only when given: a results file from before resumes as it was
        spec["via"] = via
    if unknown_response is not None:  # likewise
        spec["unknown_response"] = unknown_response
    settings = (
        text,
        machine,
        description.to_dict(),
        check,
        fraction,
        rate,
        unknown_class,
        via,
        unknown_response,
    )
    arm_name = _arm(machine).name
    if random is not None:
        check_random_count(random, "goals")
        spread = float(spread)
        if not 0.0 <= spread < float("inf"):
            raise ValueError(f"spread: expected a radius >= 0 (m), got {spread!r}")
        spec["random"] = {"seed": int(seed), "spread": spread}
        wheres = (
            (i, {"seed": int(seed), "index": i, "spread": spread, **ends}) for i in range(random)
        )
        total = random
        label = f"evaluate {random:,} random goals on the {arm_name} ({check})"
    else:
        from lfdkit.io.scenes import load_scenes

        found = load_scenes(scenes)
        for key, scene in found.items():
            if len(scene) and scene.positions.shape[1] != dims:
                raise ValueError(
                    f"{os.fspath(scenes)}: scene {key!r} is {scene.positions.shape[1]}-D; the "
                    f"skill is {dims}-D"
                )
            if scene.moving:
                raise ValueError(
                    f"{os.fspath(scenes)}: scene {key!r} has a moving obstacle; batch evaluate "
                    "checks standing obstacles only; plan moving scenes one by one with lfdkit "
                    "plan, or drop the velocities"
                )
            shaped = [o.shape for o in scene if o.shape != "round"]
            if check == "mujoco" and shaped:
                raise ValueError(
                    f"{os.fspath(scenes)}: scene {key!r} has a {shaped[0]} obstacle; the MuJoCo "
                    "check models round obstacles only; use --check robot"
                )
        spec["scenes"] = hashlib.sha256(Path(scenes).read_bytes()).hexdigest()
        wheres = ((key, {"scene": key, "obstacles": sc, **ends}) for key, sc in found.items())
        total = len(found)
        label = f"evaluate {total:,} scenes of {Path(scenes).name} on the {arm_name} ({check})"
    return run_batch(
        executor or SerialExecutor(),
        evaluate_task,
        _task_list(*settings, wheres),
        results,
        spec=spec,
        total=total,
        overwrite=overwrite,
        window=window,
        progress=progress,
        label=label,
    )


def _stats(values: list[float], scale: float = 1.0) -> dict[str, float | None]:
    if not values:
        return {"median": None, "max": None}
    arr = np.asarray(values, dtype=np.float64) * scale
    return {"median": float(np.median(arr)), "max": float(arr.max())}


def outcome_table(results: str | os.PathLike[str]) -> tuple[dict[str, Any], str]:
    """A results file of :func:`evaluate_task_batch` as one summary: JSON-ready and as text.

    Returns
    -------
    summary : dict
        ``tasks``, ``ok``, ``not_ok``, ``errors``, ``failures`` (the first
        few, one line each), and ``median``/``max`` of ``plan_s``,
        ``duration_ratio``, ``joint_speed_of_limit``, ``tracking_error_mm``,
        with ``slowed`` (tasks whose timing was stretched) and ``touched``.
    text : str
        The same as a table, one row per quantity.
    """
    rows = [r for r in read_results(results)]
    done = [r for r in rows if "error" not in r]
    robot = [r["robot"] for r in done if "robot" in r]
    simulated = [r["simulation"] for r in done if "simulation" in r]
    summary: dict[str, Any] = {
        "tasks": len(rows),
        "ok": sum(bool(r["ok"]) for r in done),
        "not_ok": sum(not r["ok"] for r in done),
        "errors": len(rows) - len(done),
        "failures": [f"{r['task']}: {r['failure']}" for r in done if r.get("failure")][:5]
        + [f"{r['task']}: {r['error']}" for r in rows if "error" in r][:5],
        "plan_s": _stats([r["plan"]["duration_s"] for r in done if "plan" in r]),
        "duration_ratio": _stats([r["duration_ratio"] for r in robot]),
        "slowed": sum(bool(r["slowed"]) for r in robot),
        "joint_speed_of_limit": _stats([r["joint_speed_of_limit"] for r in robot]),
        "tracking_error_mm": _stats([s["tracking_error_m"] for s in simulated], 1e3),
        "touched": sum(bool(s["touched"]) for s in simulated),
    }
    lines = [
        f"{summary['tasks']} tasks: {summary['ok']} ok, {summary['not_ok']} not ok, "
        f"{summary['errors']} errors",
        f"{'':<24}{'median':>10}{'max':>10}  of",
    ]
    measured = (
        ("plan duration (s)", "plan_s", len(done), ""),
        ("robot / plan duration", "duration_ratio", len(robot), f"; {summary['slowed']} slowed"),
        ("joint speed / limit", "joint_speed_of_limit", len(robot), ""),
        (
            "tracking error (mm)",
            "tracking_error_mm",
            len(simulated),
            f"; {summary['touched']} touched",
        ),
    )
    for title, key, count, note in measured:
        if count:
            stat = summary[key]
            lines.append(f"{title:<24}{stat['median']:>10.4g}{stat['max']:>10.4g}  {count}{note}")
    lines += [f"  {line}" for line in summary["failures"]]
    return summary, "\n".join(lines)
