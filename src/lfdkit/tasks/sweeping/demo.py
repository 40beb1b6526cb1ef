"""The sweeping workflows: what ``lfdkit demo`` runs, and the experiment in MuJoCo.

``lfdkit demo`` (:func:`run_demo`): from the shipped files
(:mod:`lfdkit.tasks.sweeping.examples`), learn a :class:`lfdkit.skill.Skill`
(Mean-Path of the clean sweeps, a DMP, the cup and marker reward by inverse
optimal control), score it on held-out sweeps, then plan a sweep to a new
dustpan position (:data:`~lfdkit.tasks.sweeping.scenarios.NEW_GOAL`) in three
unseen scenes holding a cup and a marker
(:func:`~lfdkit.tasks.sweeping.scenarios.unseen_scenes`), and compare with the
demonstrator's own plan (its true reward is known) and with the DMP alone;
sweep the first one with a simulated UR5. Writes figures, the skill, the
plans, a JSON record and one self-contained HTML report.

The experiment (thesis §6.4): each planner (:func:`default_planners`) turns
(start, goal, scene) of random unseen scenarios
(:func:`~lfdkit.tasks.sweeping.scenarios.random_scenarios`) into a table path;
:func:`run_experiment` executes every path with
:func:`lfdkit.tasks.sweeping.sim.execute_sweep` and :func:`summarize` counts
the outcomes per planner.
"""

from __future__ import annotations

import io
import json
import os
import secrets
import shutil
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from lfdkit import __version__
from lfdkit.app.behaviour import side_words, slow_return_words
from lfdkit.app.report import Report
from lfdkit.core.geometry import resample
from lfdkit.core.options import DEMONSTRATION_SPEED, POOR_FIDELITY
from lfdkit.core.progress import Progress, ProgressLike, Stage, as_progress
from lfdkit.emulate import Reward, metrics, plan_path
from lfdkit.io import atomic_write, load_demos, save_path
from lfdkit.io.scenes import load_scenes
from lfdkit.io.training import read_training_data
from lfdkit.model.scene import Scene
from lfdkit.skill import Skill, learn
from lfdkit.tasks.sweeping.examples import EXAMPLE_SEED, example_dataset, example_files
from lfdkit.tasks.sweeping.execution import GOAL_APPROACH, PLAN_SETTINGS, execute_skill
from lfdkit.tasks.sweeping.scenarios import (
    BRUSH,
    NEW_GOAL,
    UNSEEN_DESIGNS,
    Dustpan,
    SweepingTask,
    SweepScenario,
    unseen_scenes,
)
from lfdkit.tasks.sweeping.sim import SweepResult, execute_sweep

__all__ = [
    "GOAL_APPROACH",
    "INCOMPLETE_MARKER",
    "N_STEPS",
    "default_planners",
    "demo_outputs",
    "run_demo",
    "run_experiment",
    "summarize",
]

_FIGURES = (
    "mimic.png",
    "imitate.png",
    "emulate_test.png",
    "unseen_scenes.png",
    "simulation.png",
)
#: Written when MuJoCo can render off-screen (EGL, OSMesa or a display).
_RENDER = "simulation_render.png"
_RENDER_PATH = Path("figures") / _RENDER
#: Present in an output folder only while a run is moving its files into it.
INCOMPLETE_MARKER = "INCOMPLETE"
_URSCRIPT = "robot/unseen_1.script"
_PLANNERS = ("learned reward", "true reward", "DMP only")

#: A planner of the experiment: (start, goal, scene) to a table path (n, 2).
Planner = Callable[[np.ndarray, np.ndarray, Scene], np.ndarray]


def demo_outputs(output: str | os.PathLike[str]) -> list[Path]:
    """Every file :func:`run_demo` writes under ``output``."""
    out = Path(output)
    files = [out / "report.html", out / "results.json", out / "skill.json"]
    files += [out / "figures" / name for name in _FIGURES]
    files += [out / "plans" / f"unseen_{i + 1}.csv" for i in range(len(UNSEEN_DESIGNS))]
    files += [out / _URSCRIPT]
    files += [out / "data" / path.name for path in example_files().values()]
    return files


def run_demo(
    output: str | os.PathLike[str],
    *,
    overwrite: bool = False,
    progress: ProgressLike = None,
    started: float | None = None,
) -> dict[str, Any]:
    """Run the sweeping workflow and write its outputs under ``output``.

    Parameters
    ----------
    output : path
        Output directory, created if needed.
    overwrite : bool
        Replace files of an earlier run; otherwise an existing output file
        raises ``FileExistsError`` before anything is written. Other files in
        ``output`` are left alone.
    progress : Progress, callable, bool or None
        Reports each of the :data:`N_STEPS` steps and the stages inside them
        (learning, planning, the simulation, the figures); a callable gets a
        short message as each starts (:func:`lfdkit.core.progress.as_progress`).
        Default: silent.
    started : float, optional
        ``time.perf_counter()`` when the run started for the caller (the
        ``lfdkit demo`` command passes its own start); default: now. The
        report's and ``results.json``'s whole-run time (``seconds.total``)
        is counted from it up to the moment the outputs are complete but for
        being written: everything slow (figures rendered to PNG) comes
        before, only writing the finished bytes and moving them into place
        after.

    Returns
    -------
    dict
        The results written to ``results.json``.

    Notes
    -----
    The outputs are written into a hidden sibling folder
    (``.NAME.partial-XXXX``, removed on any error or interrupt) and moved into
    ``output`` only when all are done, so a folder that looks complete is
    complete (see ``_move_into_place``; a process killed outright can leave
    the hidden ``.partial-`` folder behind, never a half-written ``output``).
    """
    out = Path(output)
    if out.exists() and not out.is_dir():
        raise NotADirectoryError(f"{out}: exists and is not a directory")
    clash = [p for p in [*demo_outputs(out), out / _RENDER_PATH] if p.exists()]
    if clash and not overwrite:
        raise FileExistsError(
            f"{clash[0]}: exists; pass overwrite=True to replace the demo's files"
        )
    # Everything is written into a hidden sibling folder first and moved into place at
    # the very end: an interrupted run never leaves a folder that looks complete.
    started = time.perf_counter() if started is None else float(started)
    out.parent.mkdir(parents=True, exist_ok=True)
    staging = _fresh_sibling(out)
    try:
        results = _run_into(staging, as_progress(progress), started)
        _move_into_place(staging, out, overwrite)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return results


def _run_into(out: Path, progress: Progress, started: float) -> dict[str, Any]:
    """The workflow of :func:`run_demo`, writing into the fresh folder ``out``."""
    overwrite = False
    for folder in {p.parent for p in demo_outputs(out)}:
        folder.mkdir(parents=True, exist_ok=True)
    steps = progress.stage("the sweeping demo: steps", total=N_STEPS, announce=False)
    with steps:
        files = example_files()
        with progress.stage("learn the skill from data/demos.csv and data/scenes.csv") as stage:
            truth = example_dataset()
            skill = learn(files["demos"], files["scenes"], progress=progress)
        learn_s = stage.seconds
        steps.advance()

        with progress.stage("score the held-out sweeps"):
            test_demos, test_ids = load_demos(files["test_demos"], return_ids=True)
            test_scene_map = load_scenes(files["test_scenes"])
            test_scenes = [test_scene_map[key] for key in test_ids]
            scores = skill.evaluate(test_demos, test_scenes, progress=progress)
            # The demonstrator's reward with the skill's own planner: differences are the reward's.
            horizon = skill.horizon if skill.planner == "mpc" else None
            true_plans = []
            label = "the demonstrator's plans of the held-out sweeps (true reward)"
            with progress.stage(label, total=len(test_demos)) as stage:
                for demo, scene in zip(test_demos, test_scenes, strict=True):
                    nominal = skill.nominal(demo[0])
                    plan = plan_path(
                        truth.true_reward,
                        nominal,
                        scene,
                        horizon=horizon,
                        n_points=int(skill.n_points),
                    )
                    true_plans.append(plan.points)
                    stage.advance()
            scores["mse_true_reward"] = metrics.mse_paths(true_plans, test_demos)
        steps.advance()

        start = skill.path_[0]
        scenes = unseen_scenes(start, NEW_GOAL)
        label = f"plan in {len(scenes)} unseen scenes with a new goal"
        with progress.stage(label, total=len(scenes)) as stage:
            nominal = skill.nominal(start, NEW_GOAL)
            unseen = [
                _unseen(skill, truth.true_reward, scene, i, start, nominal, horizon, stage)
                for i, scene in enumerate(scenes)
            ]
        steps.advance()

        with progress.stage("sweep in unseen scene 1 with a simulated UR5 (MuJoCo)"):
            execution = _execute(skill, start, scenes[0], progress)
        executed = execution.pop("plan_points")
        if not np.array_equal(executed, unseen[0]["paths"][_PLANNERS[0]]):
            raise RuntimeError("the demo's executed plan differs from the table's plan of scene 1")
        steps.advance()

        # Every figure is rendered to PNG once, for its file and the report, before the
        # whole run's time is taken: what remains is writing finished bytes.
        # Drawn (all but the simulation's, which came with the sweep), rendered, and the picture.
        total = 2 * len(_FIGURES)
        with progress.stage("draw the figures", total=total) as stage:
            figures = _figures(
                skill, truth, test_demos, test_scenes, true_plans, nominal, unseen, stage.advance
            )
            figures["simulation.png"] = execution.pop("figure")
            pngs = {}
            for name, figure in figures.items():
                pngs[name] = _png(figure)
                stage.advance()
            image = execution.pop("image")
            image_png = None if image is None else _png(image)
            stage.advance()
        steps.advance()

        program = execution.pop("program")
        results = _results(skill, truth, scores, unseen, learn_s, time.perf_counter() - started)
        results["execution"] = execution
        text = json.dumps(results, indent=1, allow_nan=False)
        with progress.stage("write the skill, the plans, the figures, the results and the report"):
            for i, item in enumerate(unseen):
                learned = item["paths"][_PLANNERS[0]]
                save_path(out / "plans" / f"unseen_{i + 1}.csv", learned, overwrite=overwrite)
            for name, png in pngs.items():
                _write_bytes(out / "figures" / name, png)
            if image_png is not None:
                _write_bytes(out / "figures" / _RENDER, image_png)
            atomic_write(out / _URSCRIPT, lambda f: f.write(program), overwrite=overwrite)
            skill.save(out / "skill.json", overwrite=overwrite)
            for path in files.values():
                _write_bytes(out / "data" / path.name, path.read_bytes())
            atomic_write(out / "results.json", lambda f: f.write(text + "\n"), overwrite=overwrite)
            _report(results, pngs, image_png).write(out / "report.html", overwrite=overwrite)
        steps.advance()
    return results


def _unseen(
    skill: Skill,
    true_reward: Reward,
    scene: Scene,
    i: int,
    start: np.ndarray,
    nominal: np.ndarray,
    horizon: int | None,
    stage: Stage,
) -> dict[str, Any]:
    """The plans of unseen scene ``i``: the learned skill's, the demonstrator's, the DMP's."""
    t0 = time.perf_counter()
    # Every plan of the unseen scenes is planned as the robot's (PLAN_SETTINGS): the learned
    # plan of scene 1 in the table is the one the simulated UR5 executes.
    learned = skill.plan(start, NEW_GOAL, scene, **PLAN_SETTINGS).points
    plan_ms = 1e3 * (time.perf_counter() - t0)
    # The demonstrator's nominal to the new goal is the straight sweep.
    true_nominal = resample(np.vstack([start, NEW_GOAL]), 500)
    reference = plan_path(
        true_reward,
        true_nominal,
        scene,
        horizon=horizon,
        n_points=int(skill.n_points),  # as the learned plan's
        **PLAN_SETTINGS,
    ).points
    # Drawn in this order: the learned plan on top of the demonstrator's.
    paths = {
        _PLANNERS[2]: resample(nominal, len(learned)),
        _PLANNERS[1]: reference,
        _PLANNERS[0]: learned,
    }
    # Every row is held to the same margin, the brush's half-width that the plans keep
    # (issue 31: the DMP passing 0.1 mm from a cup counted as no collision).
    margin = PLAN_SETTINGS["clearance"]
    rows = []
    for name in _PLANNERS:
        path = paths[name]
        gaps = metrics.clearance(path, scene)
        rows.append(
            {
                "scene": i + 1,
                "planner": name,
                "collisions": _brush_collisions(gaps, margin),
                "min_clearance_mm": 1e3 * float(gaps.min()),
                "margin_mm": 1e3 * margin,
                "rms_to_true_mm": 1e3 * float(np.sqrt(metrics.mse_paths(path, [reference]))),
                "end_to_goal_mm": 1e3 * float(np.linalg.norm(path[-1] - NEW_GOAL)),
            }
        )
    rows[0]["plan_ms"] = plan_ms
    stage.advance()
    return {"scene": scene, "paths": paths, "rows": rows}


#: Slack of :func:`_brush_collisions` (m): the planner keeps its clearance to 1e-9 of the
#: path's extent; a micrometre is far below anything a brush feels.
_CLEARANCE_SLACK = 1e-6


def _brush_collisions(gaps: np.ndarray, margin: float) -> int:
    """Obstacles a tool of half-width ``margin`` (m) touches, from the path's ``gaps`` (m).

    ``gaps`` are the path's distances to the obstacles' surfaces
    (:func:`lfdkit.emulate.metrics.clearance`); an obstacle counts when the
    path comes nearer than ``margin`` (less a micrometre's slack, so that a
    plan kept at exactly the margin is not counted).
    """
    return int(np.count_nonzero(np.asarray(gaps) < margin - _CLEARANCE_SLACK))


def _png(figure: Any) -> bytes:
    """A matplotlib figure as PNG bytes (110 dpi)."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=110)
    return buffer.getvalue()


def _write_bytes(path: Path, content: bytes) -> None:
    """Write ``content`` to a new file ``path``, atomically."""
    atomic_write(path, lambda f: f.write(content), binary=True)


def _fresh_sibling(out: Path) -> Path:
    """A new hidden folder next to ``out``, with the permissions a plain mkdir gives."""
    while True:
        staging = out.parent / f".{out.name}.partial-{secrets.token_hex(4)}"
        try:
            staging.mkdir()  # not tempfile.mkdtemp: its 0o700 would become the output's
            return staging
        except FileExistsError:  # pragma: no cover - 32 random bits collided
            continue


def _move_into_place(staging: Path, out: Path, overwrite: bool) -> None:
    """Move the finished outputs from ``staging`` to ``out``.

    A new ``out`` is the staging folder renamed: atomic. Into an existing
    folder (which may hold the user's other files, so it is never replaced
    as a whole) the files are moved one by one, each atomically, under an
    ``INCOMPLETE`` marker, with ``report.html`` last: a move cut short leaves
    the marker and no report.
    """
    if not out.exists():
        try:
            os.rename(staging, out)
            return
        except OSError:
            if not out.is_dir():  # not a folder that appeared meanwhile: a real failure
                raise
    files = sorted(p for p in staging.rglob("*") if p.is_file())
    report = staging / "report.html"
    files = [p for p in files if p != report] + [report]
    if not overwrite:
        clash = [out / p.relative_to(staging) for p in files]
        clash = [p for p in clash if p.exists()]
        if clash:
            raise FileExistsError(
                f"{clash[0]}: exists; pass overwrite=True to replace the demo's files"
            )
    marker = out / INCOMPLETE_MARKER
    marker.write_text("lfdkit demo was interrupted while writing this folder; run it again.\n")
    (out / "report.html").unlink(missing_ok=True)
    for source in files:
        target = out / source.relative_to(staging)
        target.parent.mkdir(parents=True, exist_ok=True)
        os.replace(source, target)
    marker.unlink()


N_STEPS = 6
"""Number of steps of :func:`run_demo` (its stages at the top; each has stages inside)."""


#: How the demonstrator's plans are drawn: a wide pale band under the learned plan, so that
#: both stay visible where they coincide.
_PLAN_STYLES = {_PLANNERS[1]: {"linewidth": 6.0, "alpha": 0.45, "solid_capstyle": "round"}}


def _figures(
    skill, truth, test_demos, test_scenes, true_plans, nominal, unseen, made: Callable[[], None]
) -> dict:
    """The demo's figures but the simulation's; ``made()`` is called as each is done."""
    from lfdkit.app import plot
    from lfdkit.mimic import GMR
    from lfdkit.tasks.sweeping.figures import dustpan_outline

    files = example_files()
    # The clean sweeps: the demonstrations the Mean-Path is computed from.
    data = read_training_data(files["demos"], files["scenes"]).free_demos
    # GMR's 2-sd tube shows how far the clean sweeps spread around the path.
    gmr = GMR(n_components=6, random_state=0).fit(data)
    figures = {
        "mimic.png": plot.mean_path_figure(
            data,
            skill.mimic_,
            nominal=truth.nominal,
            gmr=gmr,
            title=f"The {len(data)} clean sweeps, their Mean-Path and GMR's 2-sd tube",
            layout="stacked",
        )
    }
    made()
    rollout = skill.dmp_.rollout(goal=NEW_GOAL, n_steps=200)
    figures["imitate.png"] = plot.retargeting_figure(
        data,
        skill.path_,
        skill.dmp_.times_,
        [(rollout.times, rollout.positions)],
        title="DMP: the sweep carried to the moved dustpan",
        goal_names=["new dustpan"],
    )
    made()
    panels = []
    for j, (demo, scene, reference) in enumerate(
        zip(test_demos, test_scenes, true_plans, strict=True)
    ):
        panels.append(
            {
                "reward": skill.reward_,
                "nominal": skill.nominal(demo[0]),
                "scene": scene,
                "demos": [demo],
                "plans": {
                    _PLANNERS[1]: reference,
                    _PLANNERS[0]: skill.plan(demo[0], None, scene).points,
                },
                "title": f"held-out sweep {j + 1} ({scene.labels[0]})",
            }
        )
    figures["emulate_test.png"] = plot.emulation_grid(
        panels,
        ncols=2,
        title="Learned reward on held-out sweeps",
        plan_styles=_PLAN_STYLES,
        panel_width=4.8,
    )
    made()
    walls = dustpan_outline(Dustpan.for_sweep(skill.path_[0], NEW_GOAL))
    panels = [
        {
            "reward": skill.reward_,
            "nominal": nominal,
            "scene": item["scene"],
            # The DMP alone is the nominal, drawn as such.
            "plans": {name: path for name, path in item["paths"].items() if name != _PLANNERS[2]},
            "title": f"unseen scene {i + 1}",
            "goal": NEW_GOAL,
            "outlines": {"dustpan": walls},
        }
        for i, item in enumerate(unseen)
    ]
    figures["unseen_scenes.png"] = plot.emulation_grid(
        panels,
        ncols=1,
        title="Unseen scenes, dustpan moved: learned skill vs the demonstrator",
        plan_styles=_PLAN_STYLES,
        panel_width=9.6,
    )
    made()
    return figures


def _execute(skill: Skill, start: np.ndarray, scene: Scene, progress: Progress) -> dict:
    """Plan with the goal approach and sweep in MuJoCo; the dustpan stands at the new goal.

    The chain of ``lfdkit execute`` (:func:`execute_skill`), with a picture.
    """
    run = execute_skill(
        skill,
        start,
        NEW_GOAL,
        scene,
        render=True,
        header="lfdkit demo: the learned sweep of unseen scene 1 (servoj at 125 Hz)",
        progress=progress,
    )
    result, dustpan, program = run.result, run.dustpan, run.program
    if result is None:  # MuJoCo missing: the demo's report needs the simulated sweep
        raise RuntimeError(f"the demo needs MuJoCo to simulate its sweep: {run.skipped}")
    figure = run.top_view("Simulated UR5 sweep, unseen scene 1")
    return {
        "success": result.success,
        "summary": result.summary(),
        "failures": result.failures,
        "cube_in_dustpan": result.cube_in_dustpan,
        "touched": result.touched,
        "tracking_error_mm": 1e3 * result.tracking_error,
        "path_error_mm": 1e3 * result.path_error,
        "motion_s": result.duration,
        "cube_in_dustpan_frame_m": dustpan.local(result.cube_final).tolist(),
        "goal_approach_m": GOAL_APPROACH,
        "clearance_m": PLAN_SETTINGS["clearance"],
        "plan_points": run.plan.points,
        "plan": "plans/unseen_1.csv",
        "rendered": result.image is not None,
        "figure": figure,
        "image": None
        if result.image is None
        else run.render_view("Simulated UR5 sweep, unseen scene 1 (MuJoCo render)"),
        "program": program,
    }


def _results(skill: Skill, truth, scores, unseen, learn_s: float, total_s: float) -> dict:
    errors = metrics.parameter_errors(skill.reward_, truth.true_reward)
    parameters = [
        {
            "parameter": "Q",
            "learned": skill.reward_.nominal_weight,
            "true": truth.true_reward.nominal_weight,
            "relative_error": errors["Q"],
        }
    ]
    for label, matrix in truth.true_reward.precisions.items():
        for i, axis in enumerate("xy"):
            parameters.append(
                {
                    "parameter": f"{label} P_{axis}{axis}",
                    "learned": float(skill.reward_.precisions[label][i, i]),
                    "true": float(matrix[i, i]),
                    "relative_error": errors[f"{label}[{i}]"],
                }
            )
    # e2 sums the distances at 100 points along the true path: their mean, in mm.
    mimic_error = metrics.e2(skill.path_, truth.nominal, n_points=100) / 100
    return {
        "lfdkit": __version__,
        "example": f"sweeping (synthetic demonstrator, seed {EXAMPLE_SEED})",
        "seconds": {"learn": learn_s, "total": total_s},
        "mimic": {
            **skill.mimic_info_,
            "mean_distance_to_true_path_mm": 1e3 * float(mimic_error),
        },
        "imitate": {
            "n_basis": skill.dmp_.n_basis_,
            "reproduction_rms_mm": 1e3
            * float(np.sqrt(metrics.mse_paths(skill.nominal(), [skill.path_]))),
            "new_goal": NEW_GOAL.tolist(),
            # The time base of the DMP figure and of every plan (issue 31: it was 1 s).
            "duration_s": float(skill.timing_.duration),
            "timing": skill.timing_.source,
        },
        "emulate": {
            "ioc": skill.ioc_info_,
            "parameters": parameters,
            "test": scores,
            # What plans keep besides the reward (issue 26): the slow return's bound (1: none)
            # on the step bound's slope, and the classes kept on one side (metres).
            "behaviour": {
                "return_fraction": float(skill.return_fraction_),
                "max_slope": float(skill.max_slope),
                "sides": {c: dict(p) for c, p in skill.side_preferences_.items()},
            },
        },
        "unseen": [row for item in unseen for row in item["rows"]],
    }


def _behaviour_sentences(emulate: dict) -> list[str]:
    """The slow return and the sides plans keep, in words (lengths in mm); none: nothing.

    ``emulate`` is the results' ``"emulate"`` (its ``"behaviour"``: absent in
    results from before it).
    """
    behaviour = emulate.get("behaviour") or {}
    out = []
    slow = slow_return_words(
        behaviour.get("return_fraction", 1.0),
        (emulate.get("ioc") or {}).get("demonstrated_return"),
        behaviour.get("max_slope", 1.0),
        "m",
    )
    if slow is not None:
        out.append(f"{slow[0].upper()}{slow[1:]}.")
    sides = behaviour.get("sides") or {}
    if sides:
        in_mm = {
            c: {k: 1e3 * v if k in ("within", "clearance") else v for k, v in p.items()}
            for c, p in sides.items()
        }
        out.append(
            "Plans keep the sides the sweeps kept, the long way round where needed: "
            f"{side_words(in_mm, 'mm')}."
        )
    return out


def _timing_sentence(imitate: dict) -> str:
    """Where the skill's duration came from, and how it relates to the robot's run below."""
    duration = imitate["duration_s"]
    if imitate["timing"] in ("minimum_jerk", "uniform"):
        source = (
            "the demonstrations carry no times, so it is their path's length at a hand's "
            f"typical demonstration pace, {DEMONSTRATION_SPEED:g} m/s on average "
            "(Skill(duration='auto'))"
        )
    else:
        source = "learned from the demonstrations' times"
    return (
        f"The skill's movement, and every plan, lasts {duration:.1f} s: {source}. The robot "
        "below runs its plan as fast as its speed setting allows, so its time differs."
    )


#: What the report's abbreviations and terms mean, in its glossary.
GLOSSARY = {
    "nominal": "The path the robot follows when nothing is in the way: the generalized path "
    "carried to the scene's start and goal by the DMP (for the demonstrator, the straight "
    "sweep). The reward measures every plan against it.",
    "Mean-Path": "The generalized path of the clean sweeps (thesis ch. 4): a curve whose every "
    "point is the mean of the demonstrations where they cross its normal there. It is found "
    "iteratively from their average.",
    "Distance-Space": "Each demonstration drawn as its signed distance from the Mean-Path, "
    "measured along the path's normals, against the position along the path: zero is the "
    "Mean-Path itself, so the spread of the demonstrations is seen at full scale.",
    "e1, e3": "The Mean-Path's iteration measures: e1 is the sum of the squared normal "
    "distances from the path to the demonstrations (m²), e3 the summed length of the update "
    "the iteration computes at the path's points (m). The iteration stops when e1 changes "
    "by less than tol (1e-4) of its value; e3 goes to zero at convergence.",
    "GMR": "Gaussian mixture regression: a second way to mimic, drawn as its mean and a tube "
    "of ±2 standard deviations across it.",
    "DMP": "Dynamic movement primitive: the learned path as a dynamical system that can be "
    "started and ended anywhere (imitate).",
    "reward": "What the demonstrator is taken to maximize along a path (thesis ch. 5): "
    "-Q·d² - Σ exp(-(x - o)ᵀ P (x - o)), with d the distance to the nominal and o each "
    "obstacle; higher (brighter in the figures) is better.",
    "Q": "Weight of staying on the nominal (1/m²): the reward's cost of a squared distance "
    "from it.",
    "P": "Precision matrix of an obstacle class (1/m², here diagonal P_xx, P_yy): how fast "
    "the class's penalty falls off with distance along x and y; larger is narrower.",
    "IOC": "Inverse optimal control: learning Q and P from the obstacle sweeps, so that the "
    "planner's paths under the learned reward reproduce them.",
    "MPC": "Model predictive control: the planner optimizes the reward over a window of "
    "the next few steps, executes one and moves on.",
    "MSE_R": "Mean squared distance between the plans of a reward and the held-out "
    "demonstrations (mm²), point by point over 100 points spaced equally along each path.",
    "MSE_Mp": "The same for replaying the nominal without the obstacle term (mm²): what "
    "mimicking alone would score.",
    "Pr": "Improvement over replaying the nominal: (MSE_Mp - MSE_R) / MSE_Mp, in percent; "
    "100 % is a perfect reproduction, 0 % no better than replaying.",
    "goal approach": "The last stretch before the goal (here the dustpan's depth) over "
    "which a plan is drawn back onto the nominal so that it ends at the goal.",
    "clearance": "Distance from a path to an obstacle's surface; plans keep at least the "
    "brush's half-width.",
}


def _report(results: dict, figures: dict, image: bytes | None = None) -> Report:
    """The HTML report; ``figures`` and ``image`` (MuJoCo's picture) as PNG bytes."""
    report = Report(
        "lfdkit demo: sweeping a cube into a dustpan",
        subtitle="Learn from demonstrations, then sweep around a cup and a marker in new scenes",
    )
    report.definition_list(
        {
            "data": results["example"],
            "learned in": f"{results['seconds']['learn']:.2f} s",
            "whole run": f"{results['seconds']['total']:.1f} s",
            "inputs": "data/demos.csv, data/scenes.csv (clean and obstacle sweeps)",
        }
    )
    mimic = results["mimic"]
    report.heading("Mimic: the generalized path")
    report.paragraph(
        f"Mean-Path of the {mimic['n_demos']} clean sweeps (the demonstrations without an "
        f"obstacle; the {results['emulate']['ioc']['n_demos']} obstacle sweeps teach the "
        f"reward, below): {mimic['n_iter']} iteration{'s' if mimic['n_iter'] != 1 else ''}; "
        f"mean distance to the demonstrator's true path "
        f"{mimic['mean_distance_to_true_path_mm']:.2f} mm; its length is "
        f"{mimic['length_ratio']:.2f} times the median demonstration's."
    )
    for text in mimic.get("warnings", []):
        report.paragraph(f"Warning: {text}")
    report.figure(
        figures["mimic.png"],
        "Top: the clean sweeps (grey), their Mean-Path (red), GMR's mean and ±2 sd tube (blue) "
        "and the demonstrator's true path (dashed); the y axis is stretched to show the "
        "millimetre spread. Bottom left: the sweeps in the Distance-Space of the Mean-Path. "
        "Bottom right: the iteration, on log scales: the relative change of the residual e1 "
        "per iteration (red) against the stopping tolerance, and the mean update per path "
        "point e3/n (black).",
    )
    imitate = results["imitate"]
    report.heading("Imitate: a DMP to new goals")
    report.paragraph(
        f"DMP with {imitate['n_basis']} basis functions per dimension reproduces the path to "
        f"{imitate['reproduction_rms_mm']:.3f} mm RMS and is carried to the moved dustpan at "
        f"{tuple(round(v, 3) for v in imitate['new_goal'])} m. " + _timing_sentence(imitate)
    )
    report.figure(
        figures["imitate.png"],
        "The clean sweeps, the generalized path (blue) and the DMP to the new goal (red dashed); "
        f"right: x and y over the skill's time, {imitate['duration_s']:.1f} s.",
    )
    emulate = results["emulate"]
    report.heading("Emulate: the obstacle reward")
    report.table(
        [
            {
                "parameter": row["parameter"],
                "learned": row["learned"],
                "true": row["true"],
                "relative error": row["relative_error"],
            }
            for row in emulate["parameters"]
        ],
        "Learned reward (1/m²) against the demonstrator's true one.",
        formats={"learned": ".4g", "true": ".4g", "relative error": ".1%"},
    )
    fidelity = (emulate["ioc"] or {}).get("training_fidelity") or []
    if fidelity:
        selection = emulate["ioc"].get("model_selection") or {}
        bad = [
            r for r in fidelity if "refused" in r or r["improvement"] < 0 or not r["sides_agree"]
        ]
        report.table(
            [
                {
                    "demonstration": r.get("id", r["demo"]),
                    "Pr (%)": r.get("improvement"),
                    "sides kept": r.get("sides_agree"),
                    "clearance (mm)": None if r.get("clearance") is None else 1e3 * r["clearance"],
                    "demonstrated (mm)": (
                        None
                        if r.get("demonstrated_clearance") is None
                        else 1e3 * r["demonstrated_clearance"]
                    ),
                }
                for r in fidelity
            ],
            f"Each training sweep replanned in its own scene (planner: "
            f"{selection.get('chosen', '?')}, runner-up {selection.get('runner_up') or 'none'}): "
            + (
                f"{len(bad)} replanned worse than its nominal or on another side."
                if bad
                else "every one closer than its nominal and on its sides."
            ),
            formats={"Pr (%)": ".1f", "clearance (mm)": ".1f", "demonstrated (mm)": ".1f"},
        )
        median = float(np.median([r["improvement"] for r in fidelity if "refused" not in r]))
        if median < 50.0:
            report.paragraph(
                f"Warning: the training sweeps are replanned poorly (median Pr {median:.0f} %): "
                "the learned reward does not explain the demonstrations."
            )
        chosen = (selection.get("candidates") or {}).get(selection.get("chosen")) or {}
        held_out = chosen.get("improvement_median")
        if selection.get("cross_validated") and held_out is not None:
            runner = (selection.get("candidates") or {}).get(selection.get("runner_up")) or {}
            report.paragraph(
                f"Behaviour model {selection['chosen']} chosen by {selection['criterion']}: "
                f"held-out sweeps replanned at a median Pr of {held_out:.0f} %"
                + (
                    f" (runner-up {selection['runner_up']}: "
                    f"{runner.get('improvement_median', float('nan')):.0f} %)."
                    if runner
                    else "."
                )
                + (
                    f" Warning: below {POOR_FIDELITY:.0f} %, the skill emulates the sweeper "
                    "poorly; add sweeps with the obstacles at several distances from the path."
                    if held_out < POOR_FIDELITY
                    else ""
                )
            )
    for sentence in _behaviour_sentences(emulate):
        report.paragraph(sentence)
    test = emulate["test"]
    report.table(
        [
            {"planner": "learned skill", "MSE_R (mm²)": 1e6 * test["mse"]},
            {"planner": "true reward", "MSE_R (mm²)": 1e6 * test["mse_true_reward"]},
            {"planner": "replay the nominal (MSE_Mp)", "MSE_R (mm²)": 1e6 * test["mse_replay"]},
        ],
        f"Held-out sweeps: improvement over replaying the nominal Pr = "
        f"{test['improvement']:.1f} %.",
    )
    report.figure(
        figures["emulate_test.png"],
        "Reward of the learned skill on the held-out sweeps (brighter is higher), with the "
        "demonstration (black dotted), the plan of the learned reward (red) and that of the "
        "true reward (pale blue band, under the red where they agree).",
    )
    run = results["execution"]
    report.heading("Unseen scenes with a new goal")
    report.paragraph(
        f"Every plan here uses the settings of the execution below: it returns to the nominal "
        f"over the last {run['goal_approach_m']:.2f} m (the goal approach), so it ends at the "
        f"goal, and keeps {1e3 * run['clearance_m']:.0f} mm (the brush's half-width) from every "
        "obstacle. The learned plan of scene 1 is the one the simulated UR5 executes."
    )
    margin_mm = 1e3 * run["clearance_m"]
    labels = {
        "scene": "scene",
        "planner": "planner",
        "collisions": f"collisions (< {margin_mm:.0f} mm)",
        "min_clearance_mm": "min clearance (mm)",
        "rms_to_true_mm": "RMS to demonstrator (mm)",
        "end_to_goal_mm": "end to goal (mm)",
        "plan_ms": "plan (ms)",
    }
    report.table(
        [{labels[k]: v for k, v in row.items() if k in labels} for row in results["unseen"]],
        f"Each planner in each unseen scene, every row against the same margin, the brush's "
        f"half-width {margin_mm:.0f} mm: collisions are the obstacles the path comes nearer "
        "than that (the brush touches them); min clearance is the path's smallest distance "
        "to an obstacle's surface; then the RMS distance to the demonstrator's plan and the "
        "distance of the end to the goal. The DMP alone ignores the obstacles.",
        columns=list(labels.values()),
        formats={
            labels["min_clearance_mm"]: ".1f",
            labels["rms_to_true_mm"]: ".2f",
            labels["end_to_goal_mm"]: ".2f",
            labels["plan_ms"]: ".0f",
        },
    )
    report.figure(
        figures["unseen_scenes.png"],
        "Plans in the unseen scenes over the learned reward (brighter is higher): the "
        "demonstrator's plan with the true reward (pale band) and the learned skill's (line "
        "on it), from the cube on the left to the goal (star) in the moved dustpan. The "
        "nominal (dashed) is the DMP alone, which ignores the obstacles.",
    )
    report.heading("Execution: a simulated UR5 sweeps the cube")
    report.paragraph(
        f"The learned plan of unseen scene 1 ({run['plan']}, the table's first row), turned "
        f"into brush poses at {BRUSH.sweep_height:g} m, joint angles (analytic IK on one "
        "branch) and a trajectory at 20 % of the UR5's joint limits, then run in MuJoCo with "
        f"joint position control. Outcome: {run['summary']}; path deviation "
        f"{run['path_error_mm']:.2f} mm; {run['motion_s']:.1f} s of motion. The URScript "
        "(servoj) is robot/unseen_1.script."
    )
    report.figure(
        figures["simulation.png"],
        "Top view: the brush (flange) trace, the cube's trace (dotted) and where it came to rest.",
    )
    if image is not None:
        report.figure(
            image,
            "MuJoCo at the end of the sweep: planned path (red), the cube's trace (green).",
        )
    report.heading("Glossary")
    report.definition_list(GLOSSARY)
    report.heading("Files")
    report.file_list(
        {
            "skill.json": "the learned skill: lfdkit plan skill.json ...",
            **{
                f"plans/unseen_{i + 1}.csv": f"the plan of unseen scene {i + 1} (t, x, y)"
                for i in range(len(UNSEEN_DESIGNS))
            },
            _URSCRIPT: "URScript for a UR5 (servoj)",
            **{f"figures/{name}": "a figure above" for name in _FIGURES},
            **({f"figures/{_RENDER}": "the MuJoCo render above"} if image is not None else {}),
            "results.json": "every number of this report",
            "data/": "the inputs: try lfdkit learn data/demos.csv --scenes data/scenes.csv "
            "-o my_skill.json",
        },
        "Next to this report (links relative to its folder):",
    )
    return report


# ------------------------------------------------------------------ the experiment
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
        return skill.plan(start, goal, scene, goal_approach=GOAL_APPROACH).points

    planners: dict[str, Planner] = {
        "learned skill": learned,
        "learned, thesis end": lambda start, goal, scene: (
            skill.plan(start, goal, scene, goal_approach=None).points
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
    progress: Callable[[str], None] | None = None,
) -> list[dict]:
    """Plan and simulate every scenario with every planner.

    ``progress`` is called with ``"scenario i/n"`` after each scenario.

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
    """One row of :func:`run_experiment`; a run that did not happen (``result`` None) failed."""
    run = result or SweepResult(
        success=False, cube_in_dustpan=False, touched=[], failures=[failure]
    )
    return {
        "scenario": index,
        "planner": name,
        "success": run.success,
        "cube_in_dustpan": run.cube_in_dustpan,
        "touched": len(run.touched),
        "tracking_error": run.tracking_error,
        "path_error": run.path_error,
        "duration": run.duration,
        "plan_s": plan_s,
        "failures": list(run.failures),
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
