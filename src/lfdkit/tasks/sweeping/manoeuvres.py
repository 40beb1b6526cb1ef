"""Obstacles that manoeuvre across the sweep: six kinds of held-out moving-obstacle scenarios.

:func:`lfdkit.tasks.sweeping.moving.moving_scenarios` slides a cup or marker
across the sweep at a constant 2–10 cm/s. The issue-27 battery showed what
that family does not test: obstacles that brake onto the path, stop and go,
turn, come in pairs, come head-on, or move fast. :func:`manoeuvre_scenarios`
draws those, :data:`KINDS`:

* ``"accelerating"`` — half speed up through the crossing, half brake
  (possibly to a stop on the path, the battery's braking cup);
* ``"stop-and-go"`` — brakes to a stop on the path when the brush gets
  there, stands 0.5–2 s, and goes on;
* ``"turning"`` — a circular arc through the crossing (radius ≥ 0.1 m);
* ``"two crossing"`` — two obstacles crossing from opposite sides;
* ``"head-on"`` — along the path towards the brush, at most 10° off it;
* ``"fast"`` — crossing at 15–30 cm/s.

Every track accelerates, brakes and turns at most :data:`MAX_ACCELERATION`
(0.3 m/s², centripetal ``v²/R`` included): the figure the tracker's
allowance covers (:class:`lfdkit.model.motion.ConstantVelocityKalman`'s
``max_acceleration``). A track starts and ends at rest (ramps at that
acceleration), is stored as a :class:`lfdkit.model.motion.Trajectory` sampled at
:data:`TRACK_RATE` (linear in between), starts at least 8 cm plus its radius
off the path (head-on: 10 cm ahead of the start), keeps
:data:`~lfdkit.tasks.sweeping.moving.BASE_CLEARANCE` from the robot's base
and, where it stands still within 15 cm of the path, :data:`STANDING_FROM_GOAL`
plus its radius from the goal and 15 cm plus its radius from the start (a
cup parked on the dustpan, or where the brush cannot pass it and return
to the nominal before the goal, is no scenario); a draw that breaks one of these is
redrawn. The crossing happens within ``slack`` s of the brush's passage on
the nominal timing.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from lfdkit.core.validation import check_positive, check_random_state
from lfdkit.model.motion import Trajectory
from lfdkit.model.scene import Obstacle
from lfdkit.tasks.sweeping.moving import (
    BASE_CLEARANCE,
    SLIDE_PAST,
    TRACKER_MAX_ACCELERATION,
    MovingScenario,
)
from lfdkit.tasks.sweeping.scenarios import Dustpan, obstacle

__all__ = ["KINDS", "MAX_ACCELERATION", "TRACK_RATE", "manoeuvre_scenarios"]

#: The scenario kinds.
KINDS = ("accelerating", "stop-and-go", "turning", "two crossing", "head-on", "fast")
#: Largest acceleration of any track (m/s²): speeding up, braking and turning.
MAX_ACCELERATION = TRACKER_MAX_ACCELERATION
#: Least distance (m, plus the radius) from the goal of an obstacle standing near the path:
#: the brush passes it and returns to the nominal (its 0.25 m goal approach) before the goal.
STANDING_FROM_GOAL = 0.35
#: Samples per second of a track (its Trajectory is linear between them).
TRACK_RATE = 200.0
_DT = 1.0 / TRACK_RATE


def _ramp(v: float, a: float) -> np.ndarray:
    """Speeds from 0 up to ``v`` at acceleration ``a``, one per sample."""
    n = max(math.ceil(v / (a * _DT)), 1)
    return np.linspace(0.0, v, n + 1)[:-1]


def _speeds(kind: str, rng: np.random.Generator, before: float) -> tuple[np.ndarray, int, float]:
    """A speed profile (per sample), the crossing sample, and the largest speed (m/s).

    ``before`` is the distance to cover before the crossing (m); the profile
    starts and ends at rest, with ramps at :data:`MAX_ACCELERATION`.
    """
    a_max = MAX_ACCELERATION
    if kind == "accelerating":
        a = rng.uniform(0.1, a_max)
        v_cross = rng.uniform(0.04, 0.12)
        if rng.random() < 0.5:  # speeding up through the crossing
            v0 = rng.uniform(0.02, 0.04)
            top = min(0.25, v_cross + a * 1.5)
            up = np.arange(v0, top, a * _DT)
            cross = int(np.searchsorted(up, v_cross))
            lead = max(int((before - up[:cross].sum() * _DT) / (v0 * _DT)), 0)
            head = np.concatenate([_ramp(v0, a_max), np.full(lead, v0)])
            after = np.full(int(SLIDE_PAST / (top * _DT)), top)
            profile = np.concatenate([head, up, after, _ramp(top, a_max)[::-1]])
            return profile, len(head) + cross, top
        top = min(0.25, v_cross + a * 1.0)  # braking through the crossing, to a stop
        down = np.arange(top, 0.0, -a * _DT)
        cross = int(np.searchsorted(-down, -v_cross))
        covered = down[:cross].sum() * _DT
        lead = max(int((before - covered) / (top * _DT)), 0)
        head = np.concatenate([_ramp(top, a_max), np.full(lead, top)])
        return np.concatenate([head, down, [0.0]]), len(head) + cross, top
    if kind == "stop-and-go":
        v = rng.uniform(0.05, 0.15)
        a = rng.uniform(0.1, a_max)
        down = np.arange(v, 0.0, -a * _DT)
        lead = max(int((before - down.sum() * _DT) / (v * _DT)), 0)
        head = np.concatenate([_ramp(v, a_max), np.full(lead, v), down])
        pause = np.zeros(int(rng.uniform(0.5, 2.0) / _DT))
        go = np.concatenate([_ramp(v, a), np.full(int(SLIDE_PAST / (v * _DT)), v)])
        profile = np.concatenate([head, pause, go, _ramp(v, a_max)[::-1]])
        return profile, len(head), v
    speeds = {"fast": (0.15, 0.30)}.get(kind, (0.02, 0.10))
    v = rng.uniform(*speeds)
    # a turning track speeds up and slows down at half the bound: with its centripetal
    # acceleration (at most 0.8 of it) the total stays within it
    ramp = _ramp(v, 0.5 * a_max if kind == "turning" else a_max)
    lead = max(int(before / (v * _DT)), 1)
    tail = int(SLIDE_PAST / (v * _DT))
    profile = np.concatenate([ramp, np.full(lead + tail, v), ramp[::-1]])
    return profile, len(ramp) + lead, v


def _track(
    crossing: np.ndarray, heading: np.ndarray, speeds: np.ndarray, cross: int, curvature: float
) -> np.ndarray:
    """Positions (n, 2) on a path of constant ``curvature`` (1/m), at ``crossing`` at ``cross``."""
    s = np.concatenate([[0.0], np.cumsum(0.5 * (speeds[1:] + speeds[:-1]) * _DT)])
    s -= s[cross]
    theta = math.atan2(heading[1], heading[0]) + curvature * s
    if curvature == 0.0:
        rel = s[:, None] * heading[None]
    else:  # the arc's exact positions
        t0 = theta[cross]
        rel = (
            np.column_stack([np.sin(theta) - math.sin(t0), -(np.cos(theta) - math.cos(t0))])
            / curvature
        )
    return crossing[None] + rel


def _draw_one(
    kind: str,
    rng: np.random.Generator,
    nominal: np.ndarray,
    times: np.ndarray,
    slack: float,
    side: float | None = None,
) -> Obstacle | None:
    """One manoeuvring obstacle, or None for a draw that breaks the module's rules."""
    n = len(nominal)
    k = round(rng.uniform(0.3, 0.7) * (n - 1))
    tangent = nominal[min(k + 1, n - 1)] - nominal[max(k - 1, 0)]
    tangent /= np.linalg.norm(tangent)
    label = "cup" if rng.random() < 0.5 else "marker"
    radius = obstacle(label, nominal[k]).radius
    if kind == "head-on":
        turn = math.radians(rng.uniform(-10.0, 10.0))
        base_heading = -tangent
    else:
        side = (1.0 if rng.random() < 0.5 else -1.0) if side is None else side
        turn = math.radians(rng.uniform(-30.0, 30.0))
        base_heading = -side * np.array([-tangent[1], tangent[0]])
    c, s = math.cos(turn), math.sin(turn)
    heading = np.array(
        [c * base_heading[0] - s * base_heading[1], s * base_heading[0] + c * base_heading[1]]
    )
    before = rng.uniform(0.08 + radius, 0.35)
    speeds, cross, top = _speeds(kind, rng, before)
    curvature = 0.0
    if kind == "turning":
        smallest = max(0.1, top * top / (0.8 * MAX_ACCELERATION))
        curvature = (1.0 if rng.random() < 0.5 else -1.0) / rng.uniform(smallest, 4 * smallest)
    track = _track(nominal[k], heading, speeds, cross, curvature)
    crossing_time = times[k] + rng.uniform(-slack, slack)
    stamps = crossing_time + _DT * (np.arange(len(speeds)) - cross)
    # off the path at the start (head-on: ahead of the brush's start), off the base
    if kind == "head-on":
        if np.linalg.norm(track[0] - nominal[0]) < 0.1 + radius + 0.1:
            return None
        if np.linalg.norm(nominal - track[0], axis=1).argmin() <= k:
            return None
    elif np.linalg.norm(nominal - track[0], axis=1).min() < 0.08 + radius:
        return None
    if np.linalg.norm(track, axis=1).min() < BASE_CLEARANCE:
        return None
    for end in (nominal[0], nominal[-1]):
        if np.linalg.norm(track[-1] - end) < 0.1 + radius:
            return None
    # where it stands still (a pause, the end) near the path: room to pass and come back
    still = track[speeds == 0.0]
    near = np.linalg.norm(nominal[None] - still[:, None], axis=2).min(axis=1) < 0.15 + radius
    still = still[near]
    if (
        len(still)
        and min(
            np.linalg.norm(still - nominal[-1], axis=1).min() - STANDING_FROM_GOAL,
            np.linalg.norm(still - nominal[0], axis=1).min() - 0.15,
        )
        < radius
    ):
        return None
    motion = Trajectory(stamps, track)
    at_zero = motion.predict(track[0], [0.0])[0][0]
    return Obstacle(label, at_zero, radius, motion=motion)


def manoeuvre_scenarios(
    kind: str,
    n: int,
    seed: Any,
    nominal: Any,
    times: Any,
    *,
    slack: float = 0.75,
) -> list[MovingScenario]:
    """Random sweeps with obstacles that manoeuvre across the nominal path (module notes).

    Parameters
    ----------
    kind : str
        One of :data:`KINDS`.
    n : int
    seed : int or numpy.random.Generator
    nominal : array_like, shape (K, 2)
        The brush's nominal path, a point per control step (m).
    times : array_like, shape (K,)
        When the brush is at each nominal point (s).
    slack : float
        Largest gap between a crossing and the brush's passage (s).

    Returns
    -------
    list of MovingScenario
        Its ``obstacle`` the first obstacle, ``others`` the second of a pair;
        ``speed`` the largest speed (m/s), ``start_time`` when the first starts
        moving, ``crossing_time`` when it crosses the path.
    """
    if kind not in KINDS:
        raise ValueError(f"kind: expected one of {', '.join(KINDS)}, got {kind!r}")
    n = check_positive(n, "n", integer=True)
    rng = check_random_state(seed)
    nominal = np.asarray(nominal, dtype=np.float64)
    times = np.asarray(times, dtype=np.float64)
    dustpan = Dustpan.for_sweep(nominal[0], nominal[-1])
    out: list[MovingScenario] = []
    while len(out) < n:
        side = 1.0 if rng.random() < 0.5 else -1.0
        first = _draw_one(kind, rng, nominal, times, slack, side)
        if first is None:
            continue
        others: tuple[Obstacle, ...] = ()
        if kind == "two crossing":
            second = _draw_one(kind, rng, nominal, times, slack, -side)
            if second is None or not _apart(first, second):
                continue
            others = (second,)
        track = first.motion
        moving = np.flatnonzero(np.any(np.diff(track.positions, axis=0) != 0.0, axis=1))
        start_time = float(track.times[moving[0]]) if moving.size else 0.0
        steps = np.linalg.norm(np.diff(track.positions, axis=0), axis=1) / np.diff(track.times)
        near = np.linalg.norm(nominal[None] - track.positions[:, None], axis=2).min(axis=1)
        out.append(
            MovingScenario(
                nominal[0].copy(),
                nominal[-1].copy(),
                dustpan,
                first,
                float(steps.max()),
                start_time,
                float(track.times[int(np.argmin(near))]),
                int(rng.integers(2**31)),
                others=others,
                kind=kind,
            )
        )
    return out


def _apart(a: Obstacle, b: Obstacle) -> bool:
    """Whether two tracked obstacles never overlap (on a common grid of their samples)."""
    grid = np.union1d(a.motion.times, b.motion.times)
    gap = np.linalg.norm(a.predict(grid)[0] - b.predict(grid)[0], axis=1)
    return bool(gap.min() > a.radius + b.radius + 0.01)
