"""The sweeping task of thesis §6.4: a UR arm sweeps a cube into a dustpan past cups and markers.

Modules, each depending only on those before it:

* :mod:`.scenarios`: the one description of the scene (table, cube, brush,
  dustpan, the cup and marker classes: every dimension, mass and colour) and
  the scenario generators (random unseen scenes, the demo's unseen scenes);
* :mod:`.examples`: the shipped example files (``data/``) and the data set
  they come from;
* :mod:`.sim`: the scene in MuJoCo with any :class:`lfdkit.execute.arm.Arm`
  (poses, inverse kinematics, timing, simulation, outcome);
* :mod:`.figures`: top views of simulated sweeps;
* :mod:`.execution`: a learned skill on the robot, ``lfdkit execute``: plan,
  tool poses, inverse kinematics, timing, URScript and the MuJoCo check;
* :mod:`.demo`: the workflow of ``lfdkit demo`` and the planner experiment;
* :mod:`.moving`: a cup or marker sliding across the sweep, the predictive
  MPC against re-planning around where it is now and the DMPs
  (``benchmarks/moving.py``); :mod:`.manoeuvres`: obstacles that
  accelerate, stop and go, turn, come in pairs, head-on or fast.

* :mod:`.batch`: a skill evaluated over many scenes in batch, ``lfdkit batch
  evaluate`` (on any executor of :func:`lfdkit.app.batch.make_executor`).

Everything public is importable from here. The names of :mod:`.figures`,
:mod:`.execution`, :mod:`.demo`, :mod:`.moving` and :mod:`.batch` (which import
matplotlib's figures and the whole skill pipeline) are loaded on first use.
"""

from __future__ import annotations

from lfdkit.core.lazy import lazy_names
from lfdkit.tasks.sweeping.examples import (
    EXAMPLE_SEED,
    example_dataset,
    example_files,
    write_example_files,
)
from lfdkit.tasks.sweeping.scenarios import (
    BRUSH,
    CUBE,
    CUBE_SIZE,
    DEFAULT_OBSTACLE_CLASS,
    GOAL_DEPTH,
    NEW_GOAL,
    NOMINAL_DUSTPAN,
    OBSTACLE_CLASSES,
    TABLE,
    UNSEEN_DESIGNS,
    Brush,
    Cube,
    Dustpan,
    ObstacleClass,
    SweepingTask,
    SweepScenario,
    Table,
    obstacle,
    obstacle_class,
    random_scenarios,
    unseen_scenes,
)
from lfdkit.tasks.sweeping.sim import (
    HOME,
    SETTLE_TIME,
    TIMESTEP,
    TRACKING_TOLERANCE,
    SweepResult,
    build_model,
    execute_sweep,
    simulate_sweep,
    simulate_timed_path,
    sweep_motion,
    sweeping_mjcf,
)

#: Names loaded on first use, by the submodule that defines them.
_LAZY = {
    "draw_dustpan": "figures",
    "dustpan_outline": "figures",
    "sweep_figure": "figures",
    "GOAL_APPROACH": "execution",
    "SERVO_RATE": "execution",
    "ExecutionError": "execution",
    "SweepExecution": "execution",
    "execute_skill": "execution",
    "execution_outputs": "execution",
    "write_execution": "execution",
    "INCOMPLETE_MARKER": "demo",
    "N_STEPS": "demo",
    "default_planners": "demo",
    "demo_outputs": "demo",
    "run_demo": "demo",
    "run_experiment": "demo",
    "summarize": "demo",
    "evaluate_batch": "batch",
    "evaluate_scenario": "batch",
    "MovingRun": "moving",
    "MovingScenario": "moving",
    "moving_figure": "moving",
    "moving_scenarios": "moving",
    "run_moving": "moving",
    "simulate_run": "moving",
    "manoeuvre_scenarios": "manoeuvres",
}

__all__ = [
    "BRUSH",
    "CUBE",
    "CUBE_SIZE",
    "DEFAULT_OBSTACLE_CLASS",
    "EXAMPLE_SEED",
    "GOAL_APPROACH",
    "GOAL_DEPTH",
    "HOME",
    "INCOMPLETE_MARKER",
    "NEW_GOAL",
    "NOMINAL_DUSTPAN",
    "N_STEPS",
    "OBSTACLE_CLASSES",
    "SERVO_RATE",
    "SETTLE_TIME",
    "TABLE",
    "TIMESTEP",
    "TRACKING_TOLERANCE",
    "UNSEEN_DESIGNS",
    "Brush",
    "Cube",
    "Dustpan",
    "ExecutionError",
    "MovingRun",
    "MovingScenario",
    "ObstacleClass",
    "SweepExecution",
    "SweepResult",
    "SweepScenario",
    "SweepingTask",
    "Table",
    "build_model",
    "default_planners",
    "demo_outputs",
    "draw_dustpan",
    "dustpan_outline",
    "evaluate_batch",
    "evaluate_scenario",
    "example_dataset",
    "example_files",
    "execute_skill",
    "execute_sweep",
    "execution_outputs",
    "manoeuvre_scenarios",
    "moving_figure",
    "moving_scenarios",
    "obstacle",
    "obstacle_class",
    "random_scenarios",
    "run_demo",
    "run_experiment",
    "run_moving",
    "simulate_run",
    "simulate_sweep",
    "simulate_timed_path",
    "summarize",
    "sweep_figure",
    "sweep_motion",
    "sweeping_mjcf",
    "unseen_scenes",
    "write_example_files",
    "write_execution",
]


__getattr__, __dir__ = lazy_names(__name__, _LAZY, globals())
