"""Moving obstacles in the sweeping task: a cup or marker slides across the table mid-sweep.

The thesis plans around static obstacles and leaves moving ones, predicted
over the MPC horizon, to future work. This module is the experiment that
proves the prediction in :mod:`lfdkit.emulate.moving` works where it matters:

* :func:`moving_scenarios` — random scenes: while the brush sweeps the cube
  towards the dustpan, a cup or a marker starts sliding (at a random time,
  2–10 cm/s, from the left or the right, up to 30° off square) and crosses the
  sweep near the moment the brush gets there, so that it is not in the way
  when the sweep starts, but will be;
* :func:`run_moving` — one closed loop with one of :data:`METHODS`: the
  obstacle is observed with noise (:data:`OBSERVATION_NOISE`) at every control
  step (a plan point, and at least every :data:`MAX_PERIOD` s; also during
  :data:`PRE_ROLL` s before the sweep), a constant-velocity Kalman filter
  whose allowance covers accelerations up to :data:`TRACKER_MAX_ACCELERATION`
  tracks it (one filter per obstacle), and

  - ``"predictive MPC"``: :class:`lfdkit.emulate.RecedingPlanner` with the
    tracker's predictions over the horizon, the margin growing with their
    uncertainty;
  - ``"static MPC"``: the same planner re-planned every step with the
    obstacle where the tracker says it is now, as if it stood still;
  - ``"DMP"``: the skill's nominal (the DMP to the goal), blind;
  - ``"DMP + coupling"``: a DMP of ``movement_primitives`` imitating the
    nominal, with its obstacle-avoidance coupling term
    (``CouplingTermObstacleAvoidance2D``, Hoffmann et al. 2009) at the
    obstacle's current estimate, at every DMP step;

  the brush runs the plan with the skill's timing (point ``k`` at
  ``times[k]``, :meth:`lfdkit.skill.Skill.point_times`). When every move in
  the window is blocked, an MPC holds the brush for :data:`WAIT` s —
  staying, stepping aside or retreating, whichever keeps the largest
  predicted clearance (:meth:`lfdkit.emulate.RecedingPlanner.hold`) — and
  tries again (its remaining times move later); the obstacle keeps moving. A
  run stops with a verdict when no hold keeps clear of a predicted contact,
  and gives up after :data:`MAX_WAIT` s of holds. Steps longer than
  :data:`MAX_PERIOD` (the first and last, 0.64 s on the rest-to-rest
  profile) are observed and re-checked every :data:`MAX_PERIOD` s, the tool
  stopping and holding where the rest of a step is no longer clear.
* :func:`simulate_run` — the executed, timed sweep replayed on the UR5 in
  MuJoCo (:func:`lfdkit.tasks.sweeping.sim.simulate_timed_path`), the
  obstacle a mocap body on its true track: cube in the dustpan, obstacles
  touched.

The closed loop is kinematic (the brush is where the plan puts it at each
time; the MuJoCo replay then checks that the arm tracks it, within 0.3 mm),
so the controller sees exactly what a loop on the robot would, as long as the
brush does not touch the obstacle; a touch is a failure either way.

A collision is the brush, a disc of half its width, coming closer to the
obstacle's true centre than its radius at any time (:func:`true_clearance`:
the executed path and every true track interpolated at 200 Hz, independent
of the planner's own checks). :mod:`lfdkit.tasks.sweeping.manoeuvres` draws
obstacles that accelerate, stop and go, turn, come in pairs, head-on or
fast.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lfdkit.core.validation import check_positive, check_random_state
from lfdkit.emulate import Corridor, RecedingPlanner, UnsafePlanError
from lfdkit.emulate.planner import timed_gaps
from lfdkit.model.motion import ConstantVelocityKalman, Tracked, Trajectory
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill
from lfdkit.tasks.sweeping.scenarios import (
    BRUSH,
    Dustpan,
    SweepingTask,
    obstacle,
)
from lfdkit.tasks.sweeping.sim import SweepResult, simulate_timed_path

__all__ = [
    "BASE_CLEARANCE",
    "MAX_PERIOD",
    "METHODS",
    "OBSERVATION_NOISE",
    "PRE_ROLL",
    "SLIDE_PAST",
    "SLIDE_SPEEDS",
    "SWEEP_DURATION",
    "TRACKER_MAX_ACCELERATION",
    "WAIT",
    "MovingRun",
    "MovingScenario",
    "moving_figure",
    "moving_scenarios",
    "run_moving",
    "simulate_run",
    "true_clearance",
]

#: The closed-loop methods compared.
METHODS = ("predictive MPC", "static MPC", "DMP", "DMP + coupling")
#: Speeds of the sliding obstacle (m/s).
SLIDE_SPEEDS = (0.02, 0.10)
#: How far past the sweep the obstacle slides before it stops (m).
SLIDE_PAST = 0.15
#: Least distance of the obstacle's track ends from the robot's base, the origin (m).
BASE_CLEARANCE = 0.2
#: Standard deviation of each coordinate of an observation of the obstacle (m).
OBSERVATION_NOISE = 0.003
#: Seconds the sweep lasts (the skill's speed profile stretched to it).
SWEEP_DURATION = 6.0
#: Seconds the obstacle is observed before the sweep starts.
PRE_ROLL = 1.0
#: Seconds an MPC holds the brush when every move in its window is blocked.
WAIT = 0.1
#: Most seconds of waiting before a run gives up.
MAX_WAIT = 10.0
#: Longest time between observations while the tool moves (s): longer steps are cut.
MAX_PERIOD = 0.1
#: The trackers' acceleration bound (m/s²): the allowance covers obstacles that
#: speed up, brake or turn (v²/R) at most this hard (lfdkit.model.motion.ConstantVelocityKalman).
TRACKER_MAX_ACCELERATION = 0.3
#: How far ahead (s) the trackers' acceleration bound is carried (then held).
TRACKER_BOUND_HORIZON = 0.3
#: Rate at which collisions are checked (Hz).
CHECK_RATE = 200.0
#: The MPCs' largest sideways step per nominal step: turns gentle enough that the cube
#: stays in front of the brush (at 1, a 45° swerve and its return lose it).
MAX_SLOPE = 0.5
#: The MPCs' return to the nominal before the goal (m): room to come back from a swerve
#: at :data:`MAX_SLOPE`.
GOAL_APPROACH = 0.25
#: The tracker's process noise (m/s^1.5) and velocity prior (m/s). With the acceleration
#: bound, 0.05 gives the narrowest allowance 0.06–0.3 s ahead (0.02: a longer memory,
#: a larger lag bound; 0.1 and more: a noisier estimate).
TRACKER_ACCELERATION, TRACKER_VELOCITY = 0.05, 0.2


@dataclass(frozen=True)
class MovingScenario:
    """A sweep with an obstacle that slides across it.

    Attributes
    ----------
    start, goal : ndarray, shape (2,)
        The sweep's ends (m); the dustpan is at the goal.
    dustpan : Dustpan
    obstacle : Obstacle
        The sliding cup or marker; its motion (a :class:`lfdkit.model.motion.Trajectory`)
        is the truth: at rest until :attr:`start_time`, then sliding.
    speed : float
        m/s.
    start_time : float
        When it starts sliding (s after the sweep starts).
    crossing_time : float
        When its centre crosses the nominal sweep (s).
    seed : int
        Of the observation noise.
    others : tuple of Obstacle
        Further moving obstacles (:mod:`lfdkit.tasks.sweeping.manoeuvres`).
    kind : str
        The scenario family ("crossing" here; :data:`~lfdkit.tasks.sweeping.manoeuvres.KINDS`).
    """

    start: np.ndarray
    goal: np.ndarray
    dustpan: Dustpan
    obstacle: Obstacle
    speed: float
    start_time: float
    crossing_time: float
    seed: int
    others: tuple[Obstacle, ...] = ()
    kind: str = "crossing"

    @property
    def obstacles(self) -> tuple[Obstacle, ...]:
        """Every moving obstacle: :attr:`obstacle` first, then :attr:`others`."""
        return (self.obstacle, *self.others)

    def truth(self, times: Any) -> np.ndarray:
        """Where the obstacle's centre is at ``times`` (n,), shape (n, 2)."""
        return self.obstacle.predict(times)[0]


def moving_scenarios(
    n: int,
    seed: Any,
    nominal: Any,
    times: Any,
    *,
    speeds: tuple[float, float] = SLIDE_SPEEDS,
    slack: float = 0.75,
) -> list[MovingScenario]:
    """Random sweeps with a cup or marker sliding across the nominal path.

    The crossing point is at ``U[0.3, 0.7]`` of the nominal (by points),
    the heading the path's normal (left or right at random) turned by up to
    30°, the speed ``U[speeds]``, the crossing ``U[−slack, slack]`` s from the
    moment the brush is there; the obstacle starts sliding at ``U[0, 0.5]`` of
    the sweep's duration, from where it must start to cross then (at least
    8 cm from the path plus its radius, redrawn otherwise), and stops
    :data:`SLIDE_PAST` beyond the path; a track that starts or stops within
    :data:`BASE_CLEARANCE` of the robot's base (the origin, 45 cm from the
    sweep) is redrawn.

    Parameters
    ----------
    n : int
    seed : int or numpy.random.Generator
    nominal : array_like, shape (K, 2)
        The brush's nominal path, a point per control step (m).
    times : array_like, shape (K,)
        When the brush is at each nominal point (s).
    speeds : (float, float)
        Least and largest sliding speed (m/s).
    slack : float
        Largest gap between the crossing and the brush's passage (s).
    """
    n = check_positive(n, "n", integer=True)
    rng = check_random_state(seed)
    nominal = np.asarray(nominal, dtype=np.float64)
    times = np.asarray(times, dtype=np.float64)
    start, goal = nominal[0], nominal[-1]
    dustpan = Dustpan.for_sweep(start, goal)
    out = []
    while len(out) < n:
        k = round(rng.uniform(0.3, 0.7) * (len(nominal) - 1))
        tangent = nominal[min(k + 1, len(nominal) - 1)] - nominal[max(k - 1, 0)]
        tangent /= np.linalg.norm(tangent)
        side = 1.0 if rng.random() < 0.5 else -1.0
        turn = np.radians(rng.uniform(-30.0, 30.0))
        normal = side * np.array([-tangent[1], tangent[0]])
        c, s = math.cos(turn), math.sin(turn)
        heading = -np.array([c * normal[0] - s * normal[1], s * normal[0] + c * normal[1]])
        speed = rng.uniform(*speeds)
        crossing = times[k] + rng.uniform(-slack, slack)
        start_time = rng.uniform(0.0, 0.5 * times[-1])
        label = "cup" if rng.random() < 0.5 else "marker"
        noise_seed = int(rng.integers(2**31))
        distance = speed * (crossing - start_time)
        base = obstacle(label, nominal[k])
        if distance < 0.08 + base.radius:
            continue
        origin = nominal[k] - distance * heading
        finish = start_time + (distance + SLIDE_PAST) / speed
        end = origin + (distance + SLIDE_PAST) * heading
        if min(np.linalg.norm(origin), np.linalg.norm(end)) < BASE_CLEARANCE:
            continue  # it would stand on the robot's base
        motion = Trajectory([start_time, finish], [origin, end])
        sliding = Obstacle(label, origin, base.radius, motion=motion)
        out.append(
            MovingScenario(
                start.copy(),
                goal.copy(),
                dustpan,
                sliding,
                float(speed),
                float(start_time),
                float(crossing),
                noise_seed,
            )
        )
    return out


@dataclass
class MovingRun:
    """One closed-loop sweep.

    Attributes
    ----------
    method : str
    times : ndarray, shape (m,)
        When the brush is at each executed point (s); waits repeat a point.
    points : ndarray, shape (m, 2)
        The brush's executed path (m).
    clearance : float
        Least distance between the brush (a disc of half its width) and the
        obstacle's surface, at the same time (m); negative: a collision.
    collided : bool
    reached_goal : bool
        The brush ended within 1 cm of the goal.
    waited : float
        Seconds the brush was held (an MPC with every move blocked).
    step_ms : ndarray
        Planner time of each control step (ms; empty for the DMPs).
    observations : ndarray, shape (j, 3)
        ``t, x, y`` of every observation.
    windows : list of (float, ndarray, ndarray, ndarray)
        For the MPCs: at each step its time, the planned window (h + 1, 2)
        and the predicted obstacle means (h, 2) and standard deviations (h,).
    failure : str
        Why a run stopped early ("" when it did not): gave up after
        :data:`MAX_WAIT` s of holds, or stopped with a verdict before a
        predicted contact (:meth:`lfdkit.emulate.RecedingPlanner.hold`).
    holds : int
        Control steps the tool was held (each :data:`WAIT` s).
    prediction_errors : ndarray, shape (j, 3)
        Predictive MPC: for every obstacle at every planned window point, the
        distance of the window point to the predicted obstacle, the true
        position's distance from the prediction and the allowance
        (``margin`` σ) (m): the allowance's coverage.
    headings : ndarray, shape (m,) or None
        MPCs that held the brush: its heading at each executed point (rad,
        unwrapped): the nominal's direction at the plan point it belongs to,
        so that a hold's sideways or backward step does not turn the brush
        round (following the path's tangent through them, the arm could not:
        5 of 50 replays); None: along the path. (Following the path with the
        holds' moves left out instead: 5 of 7 such replays failed.)
    """

    method: str
    times: np.ndarray
    points: np.ndarray
    clearance: float
    collided: bool
    reached_goal: bool
    waited: float = 0.0
    step_ms: np.ndarray = field(default_factory=lambda: np.zeros(0))
    observations: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    windows: list = field(default_factory=list, repr=False)
    failure: str = ""
    holds: int = 0
    prediction_errors: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)), repr=False)
    headings: np.ndarray | None = field(default=None, repr=False)


class _Sensor:
    """The noisy observations of each obstacle and a Kalman filter per obstacle.

    (Which observation belongs to which obstacle is known: data association
    is not this experiment's subject.)
    """

    def __init__(self, scenario: MovingScenario, noise: float, max_acceleration: float) -> None:
        self.scenario, self.noise = scenario, noise
        self.rng = np.random.default_rng(scenario.seed)
        self.filters = [
            ConstantVelocityKalman(
                noise,
                acceleration=TRACKER_ACCELERATION,
                velocity_std=TRACKER_VELOCITY,
                max_acceleration=max_acceleration,
                bound_horizon=TRACKER_BOUND_HORIZON,
            )
            for _ in scenario.obstacles
        ]
        self.filter = self.filters[0]
        self.log: list[tuple[float, float, float]] = []

    def observe(self, t: float) -> list[np.ndarray]:
        """Observe every obstacle at ``t``; the filtered positions now, one (2,) each."""
        out = []
        for o, (item, kf) in enumerate(zip(self.scenario.obstacles, self.filters, strict=True)):
            z = item.predict([t])[0][0] + self.noise * self.rng.standard_normal(2)
            kf.update(t, z)
            if o == 0:
                self.log.append((t, *z))
            out.append(kf.predict([t])[0][0])
        return out

    def scene(self, estimates: list[np.ndarray], predictive: bool) -> Scene:
        """The obstacles where estimated, with the trackers' predictions when ``predictive``."""
        return Scene(
            tuple(
                Obstacle(o.label, e, o.radius, motion=Tracked(kf) if predictive else None)
                for o, e, kf in zip(self.scenario.obstacles, estimates, self.filters, strict=True)
            )
        )


def true_clearance(
    scenario: MovingScenario, times: Any, points: Any, rate: float = CHECK_RATE
) -> tuple[float, float]:
    """Least brush–obstacle surface distance against the TRUE tracks, and when (m, s).

    Independent of the planner's checks: the executed path ``points`` (m, 2)
    at ``times`` (m,) and every obstacle's true track are interpolated on a
    grid of ``rate`` Hz (and the executed times themselves); the brush is a
    disc of half its width.
    """
    times = np.asarray(times, dtype=np.float64)
    points = np.asarray(points, dtype=np.float64)
    grid = np.union1d(np.arange(times[0], times[-1], 1.0 / rate), times)
    brush = np.column_stack([np.interp(grid, times, points[:, i]) for i in range(2)])
    best, when = np.inf, float(grid[0])
    for o in scenario.obstacles:
        gap = np.linalg.norm(brush - o.predict(grid)[0], axis=1) - o.radius - 0.5 * BRUSH.width
        i = int(np.argmin(gap))
        if gap[i] < best:
            best, when = float(gap[i]), float(grid[i])
    return best, when


def _clearance(scenario: MovingScenario, times: np.ndarray, points: np.ndarray) -> float:
    """Least brush–obstacle surface distance over the sweep, on a fine time grid (m)."""
    return true_clearance(scenario, times, points)[0]


def run_moving(
    skill: Skill,
    scenario: MovingScenario,
    method: str,
    *,
    duration: float = SWEEP_DURATION,
    horizon: int = 12,
    noise: float = OBSERVATION_NOISE,
    margin: float = 2.0,
    coupling_gain: float = 1000.0,
    max_slope: float = MAX_SLOPE,
    goal_approach: float = GOAL_APPROACH,
    max_acceleration: float = TRACKER_MAX_ACCELERATION,
) -> MovingRun:
    """One closed-loop sweep of ``scenario`` with ``method`` (one of :data:`METHODS`).

    Parameters
    ----------
    skill : Skill
        The sweeping skill (2-D, metres, with a reward for cups and markers).
    scenario : MovingScenario
    method : str
    duration : float
        Seconds the sweep lasts (without waits).
    horizon : int
        MPC horizon.
    noise : float
        Observation noise (m).
    margin : float
        Predictive MPC: standard deviations of the prediction added to the radius.
    coupling_gain : float
        ``gamma`` of the DMP's coupling term.
    max_slope : float
        The MPCs' largest sideways step per nominal step (:data:`MAX_SLOPE`).
    goal_approach : float
        The MPCs' return to the nominal before the goal (m, :data:`GOAL_APPROACH`).
    max_acceleration : float
        The trackers' acceleration bound (m/s², :data:`TRACKER_MAX_ACCELERATION`;
        0: the plain constant-velocity filter).
    """
    if method not in METHODS:
        raise ValueError(f"method: expected one of {', '.join(METHODS)}, got {method!r}")
    times = skill.point_times(duration)
    nominal = skill.nominal(scenario.start, scenario.goal)
    sensor = _Sensor(scenario, noise, max_acceleration)
    period = float(np.median(np.diff(times)))
    for t in np.arange(-PRE_ROLL, 0.0, period):
        sensor.observe(float(t))
    holds, errors, headings = 0, np.zeros((0, 3)), None
    if method == "DMP":
        points = Corridor.from_path(nominal, int(skill.n_points)).points
        out_times, waited, step_ms, windows, failure = times, 0.0, np.zeros(0), [], ""
        for t in times:
            sensor.observe(float(t))
    elif method == "DMP + coupling":
        out_times, points = _coupled_dmp(nominal, times, sensor, coupling_gain)
        waited, step_ms, windows, failure = 0.0, np.zeros(0), [], ""
    else:
        loop = _Loop(
            skill,
            scenario,
            nominal,
            times,
            sensor,
            method == "predictive MPC",
            horizon,
            margin,
            max_slope,
            goal_approach,
        )
        loop.run()
        out_times, points = np.array(loop.times), np.array(loop.points)
        waited, step_ms, windows, failure = (
            loop.waited,
            np.array(loop.step_ms),
            loop.windows,
            loop.failure,
        )
        holds, errors = loop.holds, np.array(loop.errors).reshape(-1, 3)
        if loop.holds:  # (a run without holds: along its own path, as any sweep)
            tangents = loop.planner.corridor.tangents[loop.index]
            headings = np.unwrap(np.arctan2(tangents[:, 1], tangents[:, 0]))
    clearance = _clearance(scenario, out_times, points)
    return MovingRun(
        method=method,
        times=out_times,
        points=points,
        clearance=clearance,
        collided=clearance < 0.0,
        reached_goal=bool(np.linalg.norm(points[-1] - scenario.goal) < 0.01),
        waited=waited,
        step_ms=step_ms,
        observations=np.array(sensor.log),
        windows=windows,
        failure=failure,
        holds=holds,
        prediction_errors=errors,
        headings=headings,
    )


class _Loop:
    """The MPCs' closed loop: observe, plan a window, move; hold safely when blocked.

    A step longer than :data:`MAX_PERIOD` (the rest-to-rest profile's first
    and last, 0.64 s at 6 s) is cut into sub-steps: at each the obstacles
    are observed and the rest of the step is checked against the new
    predictions; where it would enter an allowance the tool stops there and
    holds (:meth:`lfdkit.emulate.RecedingPlanner.hold`).
    """

    def __init__(
        self,
        skill: Skill,
        scenario: MovingScenario,
        nominal: np.ndarray,
        times: np.ndarray,
        sensor: _Sensor,
        predictive: bool,
        horizon: int,
        margin: float,
        max_slope: float,
        goal_approach: float,
    ) -> None:
        self.planner = RecedingPlanner(
            skill.reward_,
            nominal,
            times,
            horizon=horizon,
            max_slope=max_slope,
            n_points=int(skill.n_points),
            goal_approach=goal_approach,
            clearance=0.5 * BRUSH.width,
            margin=margin,
        )
        self.scenario, self.sensor, self.predictive = scenario, sensor, predictive
        self.times, self.points = [0.0], [self.planner.point]
        self.index = [0]  # the plan point each executed point belongs to (its heading's)
        self.step_ms: list[float] = []
        self.windows: list = []
        self.errors: list[tuple[float, float, float]] = []
        self.waited, self.holds, self.failure = 0.0, 0, ""

    def run(self) -> None:
        planner, sensor = self.planner, self.sensor
        now = 0.0
        while not planner.done:
            scene = sensor.scene(sensor.observe(now), self.predictive)
            began = time.perf_counter()
            try:
                planner.step(scene)
            except UnsafePlanError as exc:
                self.step_ms.append(1e3 * (time.perf_counter() - began))
                if not self._hold(scene, now, exc):
                    return
                now = float(planner.times[planner.step_index])
                continue
            self.step_ms.append(1e3 * (time.perf_counter() - began))
            self._record_window(scene, now)
            if not self._move(now):
                return
            now = float(planner.times[planner.step_index])

    def _hold(self, scene: Scene, now: float, reason: Exception, position: Any = None) -> bool:
        """Hold the tool safely for :data:`WAIT` s; False (and a failure) when the run stops."""
        if self.waited >= MAX_WAIT:
            self.failure = f"gave up after waiting {self.waited:.1f} s: {reason}"
            return False
        try:
            point = self.planner.hold(scene, WAIT, position)
        except UnsafePlanError as verdict:
            self.failure = f"stopped at t = {now:.2f} s before contact: {verdict}"
            return False
        self.waited += WAIT
        self.holds += 1
        self.times.append(float(self.planner.times[self.planner.step_index]))
        self.points.append(point)
        self.index.append(self.planner.step_index)
        return True

    def _move(self, now: float) -> bool:
        """Run the step to the planner's new point, observing every :data:`MAX_PERIOD` s."""
        planner, sensor = self.planner, self.sensor
        k = planner.step_index
        end_time, end = float(planner.times[k]), planner.point
        start = self.points[-1]
        pieces = int(np.ceil((end_time - now) / MAX_PERIOD - 1e-9))
        for j in range(1, max(pieces, 1)):
            t = now + (end_time - now) * j / pieces
            here = start + (end - start) * (j / pieces)
            scene = sensor.scene(sensor.observe(t), self.predictive)
            rest = np.vstack([here, end])
            gap = min(
                (
                    timed_gaps(
                        o, rest, np.array([t, end_time]), planner.margin if o.moving else 0.0
                    ).min()
                    for o in scene.obstacles
                ),
                default=np.inf,
            )
            self.times.append(t)
            self.points.append(here)
            self.index.append(k)
            if gap < planner.clearance:  # the rest of the step would enter an allowance
                planner.times[k:] += t - planner.times[k]
                return self._hold(scene, t, UnsafePlanError("a step's rest was blocked"), here)
        self.times.append(end_time)
        self.points.append(end)
        self.index.append(k)
        return True

    def _record_window(self, scene: Scene, now: float) -> None:
        """The window drawn in the figure, and the predictions' errors against the truth."""
        planner = self.planner
        k = planner.step_index
        window_times = planner.times[k : k + len(planner.window) - 1]
        first = None
        for o, (seen, true) in enumerate(
            zip(scene.obstacles, self.scenario.obstacles, strict=True)
        ):
            means, covs = seen.predict(window_times)
            sigma = np.sqrt(np.maximum(covs[:, 0, 0], 0.0))
            if o == 0:
                first = (means, sigma)
            if self.predictive:
                error = np.linalg.norm(true.predict(window_times)[0] - means, axis=1)
                near = np.linalg.norm(planner.window[1:] - means, axis=1)
                allowance = planner.margin * sigma
                self.errors.extend(zip(near, error, allowance, strict=True))
        self.windows.append((now, planner.window.copy(), *first))


def _coupled_dmp(
    nominal: np.ndarray, times: np.ndarray, sensor: _Sensor, gain: float
) -> tuple[np.ndarray, np.ndarray]:
    """A ``movement_primitives`` DMP of the nominal with the obstacle coupling term."""
    from movement_primitives.dmp import DMP, CouplingTermObstacleAvoidance2D

    from lfdkit.core.geometry import resample

    dt = 0.02
    grid = np.arange(0.0, times[-1] + 0.5 * dt, dt)
    path = resample(nominal, len(times))
    demo = np.column_stack([np.interp(grid, times, path[:, i]) for i in range(2)])
    # int_dt 4 ms (the package's default is 1 ms): the same path to 0.1 mm, 4× faster.
    dmp = DMP(n_dims=2, execution_time=float(grid[-1]), dt=dt, n_weights_per_dim=50, int_dt=0.004)
    dmp.imitate(grid, demo)
    dmp.configure(start_y=demo[0], goal_y=demo[-1])
    y, yd = demo[0].copy(), np.zeros(2)
    out_times, points = [0.0], [y.copy()]
    t = 0.0
    while t < grid[-1] - 1e-9:  # its execution time (it drifts back when stepped beyond)
        # The package's coupling term avoids one obstacle: the nearest estimate.
        estimates = np.asarray(sensor.observe(t), dtype=np.float64).reshape(-1, 2)
        nearest = estimates[np.argmin(np.linalg.norm(estimates - y, axis=1))]
        coupling = CouplingTermObstacleAvoidance2D(nearest, gamma=gain, fast=True)
        y, yd = dmp.step(y, yd, coupling_term=coupling)
        t += dt
        out_times.append(t)
        points.append(y.copy())
    return np.array(out_times), np.array(points)


def simulate_run(
    run: MovingRun, scenario: MovingScenario, *, render: bool = False, camera: str = "overview"
) -> SweepResult:
    """Replay a closed-loop sweep on the UR5 in MuJoCo, the obstacle on its true track.

    The cube starts in front of the brush; the dustpan stands at the goal.
    """
    keep = np.concatenate([[True], np.diff(run.times) > 0])  # waits: a point per time
    times, points = run.times[keep], run.points[keep]
    yaw = None if run.headings is None else run.headings[keep]
    task = SweepingTask.for_path(points, scenario.dustpan, Scene(scenario.obstacles))
    return simulate_timed_path(times, points, task, render=render, camera=camera, yaw=yaw)


def moving_figure(
    scenario: MovingScenario, runs: dict[str, MovingRun], *, at: float | None = None
) -> Any:
    """Top view of one scenario: the obstacle's track, one step's predictions, every method.

    Parameters
    ----------
    scenario : MovingScenario
    runs : dict of str to MovingRun
        By method; the predictive MPC's run gives the predictions.
    at : float, optional
        Time of the step whose prediction is drawn (default: the step at
        which the predicted obstacle is nearest its window).
    """
    import matplotlib.pyplot as plt
    from matplotlib.patches import Circle

    from lfdkit.tasks.sweeping.figures import draw_dustpan

    fig, (ax, side) = plt.subplots(1, 2, figsize=(13, 6.2), width_ratios=[2.2, 1])
    truth_times = np.linspace(0.0, max(r.times[-1] for r in runs.values()), 400)
    track = scenario.truth(truth_times)
    ax.plot(*track.T, color="0.5", linewidth=1.0, label="obstacle's true track")
    predictive = runs.get("predictive MPC")
    if predictive is not None and predictive.windows:
        if at is None:
            gaps = [np.linalg.norm(w[1][1:] - w[2], axis=1).min() for w in predictive.windows]
            index = int(np.argmin(gaps))
        else:
            index = int(np.argmin([abs(w[0] - at) for w in predictive.windows]))
        now, window, means, sigma = predictive.windows[index]
        seen = predictive.observations
        seen = seen[seen[:, 0] <= now + 1e-9]
        ax.plot(
            seen[:, 1],
            seen[:, 2],
            ".",
            color="tab:orange",
            markersize=2.5,
            label=f"observations up to t = {now:.2f} s",
        )
        ax.plot(
            *means.T,
            "x",
            color="tab:red",
            markersize=4,
            label="predicted positions over the horizon (2 sigma)",
        )
        for centre, s in zip(means, sigma, strict=True):
            ax.add_patch(
                Circle(centre, 2.0 * s, fill=False, color="tab:red", linewidth=0.6, alpha=0.7)
            )
        ax.add_patch(Circle(means[-1], scenario.obstacle.radius, color="tab:red", alpha=0.25))
        ax.plot(
            *window.T,
            "-",
            color="tab:green",
            linewidth=3.0,
            alpha=0.5,
            label="predictive MPC's window at that step",
        )
        truth_now = scenario.truth([now])[0]
        ax.add_patch(Circle(truth_now, scenario.obstacle.radius, color="0.3", alpha=0.6))
    colours = {
        "predictive MPC": "tab:green",
        "static MPC": "tab:purple",
        "DMP": "0.2",
        "DMP + coupling": "tab:blue",
    }
    for name, run in runs.items():
        mark = "  (collides)" if run.collided else ""
        ax.plot(
            *run.points.T,
            color=colours.get(name, "k"),
            linewidth=1.2,
            linestyle="--" if name == "DMP" else "-",
            label=f"{name}: clearance {1e3 * run.clearance:+.0f} mm{mark}",
        )
    draw_dustpan(ax, scenario.dustpan)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(
        f"{scenario.obstacle.label} sliding at {100 * scenario.speed:.1f} cm/s from "
        f"t = {scenario.start_time:.1f} s"
    )
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2)
    # Distance in time: brush–obstacle surface gap for each method.
    for name, run in runs.items():
        grid = np.arange(run.times[0], run.times[-1], 0.02)
        brush = np.column_stack([np.interp(grid, run.times, run.points[:, i]) for i in range(2)])
        gap = np.linalg.norm(brush - scenario.truth(grid), axis=1)
        gap -= scenario.obstacle.radius + 0.5 * BRUSH.width
        side.plot(
            grid,
            1e3 * gap,
            color=colours.get(name, "k"),
            label=name,
            linestyle="--" if name == "DMP" else "-",
        )
    side.axhline(0.0, color="tab:red", linewidth=0.8)
    side.set_ylim(-60, 250)
    side.set_xlabel("t (s)")
    side.set_ylabel("brush-obstacle gap (mm); < 0: collision")
    side.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2)  # off the data
    fig.tight_layout()
    return fig
