"""Demonstrators of our own making for the fidelity benchmark (``benchmarks/emulate_fidelity.py``).

Each *person* turns a task's nominal path and a scene into the path a person of
that kind would demonstrate. None of them calls lfdkit's planner or reward, so
the benchmark's ground truth stays the same while the emulation layer changes;
only :mod:`lfdkit.core.geometry` (resampling, normals) and the scene classes are used.

Kinds (two obstacle classes, ``cup`` of radius 3 cm and ``box`` of 5 cm, each
with its own behaviour):

* ``thesis``: the thesis's model (SPEC §3): reward ``−Q e² − Σ exp(−dᵀ P_c d)``
  with world-axis precisions per class, planned by its own receding-horizon MPC
  (horizon :data:`THESIS_HORIZON`, never told to lfdkit) with the thesis's
  action bound (one lateral step per step along the nominal) and no goal term.
  Each window is solved exactly (a max-plus dynamic programme over a 1 mm
  lateral grid: the reward is separable by point and the action bound couples
  neighbours only).
* ``margin``: keeps a fixed surface margin per class and otherwise takes the
  shortest path (length measured in the nominal's frame, so with nothing in
  the way it follows the task), by a dynamic programme over the same grid,
  then smoothed with the margin enforced again; starts and ends on the nominal.
  Equally short paths are many on the grid: a step wins only when shorter by
  more than round-off, so the person takes the same path in mm as in m
  (before, rounding chose, and in mm it demonstrated paths up to 2.5 cm away).
* ``field``: a DMP user's recording: the nominal's DMP (its deviation from the
  nominal obeys the DMP's spring-damper, α = 25, β = α/4, τ = 1 s) with a
  repulsive potential field per class (Khatib-style ``a_c (ρ_c/d − 1)`` on the
  surface distance ``d``, plus a rotational part so it slides round instead of
  stopping in front of an obstacle).
* ``late``: reacts only when an obstacle's surface is within a look-ahead
  distance, swerves steeply to a class clearance, holds it past the obstacle
  and returns slowly; it goes round a pair when their gap is below its
  clearances, and comes back to the goal over the last 8 % of the path.

Noise: smooth lateral noise along each path's normals, a sum of three sinusoids
(0.5-3 cycles per path, random phases and amplitudes) scaled to standard
deviation ``noise`` and tapered to zero over the first and last 10 % (so a
demonstration starts and ends where its person meant to); 1× is 2 mm.

Lengths are in metres times ``scale`` (``scale=1000`` gives millimetres: every
parameter is converted, nothing is computed in metres behind the scenes).
Every random draw comes from a ``numpy.random.Generator`` the caller seeds.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.ndimage import gaussian_filter1d, maximum_filter1d

from lfdkit.core.geometry import arc_length, left_normals, resample
from lfdkit.model.scene import Obstacle, Scene

CLASSES = ("cup", "box")
#: Physical radius of each class, metres.
RADIUS = {"cup": 0.03, "box": 0.05}
#: Standard deviation of the 1× demonstration noise, metres.
NOISE = 0.002
#: Horizon of the thesis person's MPC (not told to lfdkit).
THESIS_HORIZON = 5
#: Smallest clearance (metres) of a person's noise-free path: scenes where a person would
#: come closer are not used (twice the 2× noise's standard deviation plus 4 mm).
MIN_CLEARANCE = 0.012
KINDS = ("thesis", "margin", "field", "late")

_STATIONS = 100  # points along the nominal each person plans on
_GRID_STEP = 0.001  # lateral grid step, metres
_GRID_HALF = 0.3  # lateral grid half width, metres


class PersonFailed(RuntimeError):
    """The person has no path in this scene (it would collide or cannot get through)."""


# ----------------------------------------------------------------------------- geometry
@dataclass
class Frame:
    """Stations along a nominal with their left normals and a lateral grid.

    ``points[k] + e * normals[k]`` is the point at lateral offset ``e`` (units)
    from station ``k``.
    """

    nominal: np.ndarray
    scale: float = 1.0
    n_stations: int = _STATIONS
    points: np.ndarray = field(init=False)
    normals: np.ndarray = field(init=False)
    s: np.ndarray = field(init=False)
    grid: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.points = resample(np.asarray(self.nominal, dtype=float), self.n_stations)
        self.normals = left_normals(self.points)
        self.s = arc_length(self.points)
        self.ds = float(self.s[-1] / (self.n_stations - 1))
        self.step = _GRID_STEP * self.scale
        half = round(_GRID_HALF / _GRID_STEP)
        self.grid = np.arange(-half, half + 1) * self.step
        self.zero = half  # index of e = 0

    def at(self, offsets: np.ndarray) -> np.ndarray:
        """Points at lateral ``offsets`` (one per station), shape (n_stations, 2)."""
        return self.points + np.asarray(offsets)[:, None] * self.normals

    def grid_points(self) -> np.ndarray:
        """Every grid point, shape (n_stations, n_grid, 2)."""
        return self.points[:, None, :] + self.grid[None, :, None] * self.normals[:, None, :]

    def place(self, u: float, lateral: float, along: float = 0.0) -> np.ndarray:
        """Point at arc fraction ``u``, ``lateral`` left and ``along`` ahead (units)."""
        s = u * self.s[-1]
        p = np.array([np.interp(s, self.s, self.points[:, k]) for k in range(2)])
        n = np.array([np.interp(s, self.s, self.normals[:, k]) for k in range(2)])
        n /= np.linalg.norm(n)
        return p + lateral * n + along * np.array([n[1], -n[0]])

    def project(self, point: np.ndarray) -> tuple[int, float]:
        """Nearest station of ``point`` and its lateral offset there."""
        k = int(np.argmin(np.linalg.norm(self.points - point, axis=1)))
        return k, float((point - self.points[k]) @ self.normals[k])


def surface_distances(points: np.ndarray, scene: Scene) -> np.ndarray:
    """Distance of each point to each obstacle's surface, shape (..., n_obstacles)."""
    centres = np.array([o.position for o in scene.obstacles])
    radii = np.array([o.radius for o in scene.obstacles])
    return np.linalg.norm(points[..., None, :] - centres, axis=-1) - radii


def min_clearance(path: np.ndarray, scene: Scene) -> float:
    """Smallest surface distance of a polyline (checked on a 4× denser resampling)."""
    if not len(scene):
        return np.inf
    dense = resample(path, 4 * len(path))
    return float(surface_distances(dense, scene).min())


def make_scene(items, scale: float = 1.0) -> Scene:
    """Scene of ``(label, position)`` items, radii from :data:`RADIUS` (scaled)."""
    return Scene(tuple(Obstacle(c, np.asarray(p, float), RADIUS[c] * scale) for c, p in items))


# ----------------------------------------------------------------------------- people
class Person:
    """Base: ``clean(nominal, scene)`` is the noise-free path (n_points, 2)."""

    kind = "person"

    def __init__(self, scale: float = 1.0, n_points: int = 100) -> None:
        self.scale = float(scale)
        self.n_points = int(n_points)

    def describe(self) -> str:
        raise NotImplementedError

    def clean(self, nominal: np.ndarray, scene: Scene) -> np.ndarray:
        path = self._path(Frame(nominal, self.scale), scene)
        if len(scene) and min_clearance(path, scene) < MIN_CLEARANCE * self.scale:
            raise PersonFailed(
                f"{self.kind}: the path comes within {MIN_CLEARANCE} m of an obstacle"
            )
        return resample(path, self.n_points)

    def _path(self, frame: Frame, scene: Scene) -> np.ndarray:
        raise NotImplementedError


class ThesisPerson(Person):
    """The thesis's Gaussian reward per class, planned by its own receding-horizon MPC."""

    kind = "thesis"

    def __init__(
        self,
        scale: float = 1.0,
        n_points: int = 100,
        *,
        q: float = 20.0,
        precisions: dict | None = None,
        horizon: int = THESIS_HORIZON,
        slope: float = 1.0,
    ) -> None:
        super().__init__(scale, n_points)
        # 1/m²: cup response 13 cm along x, 3.8 cm across; box 16 cm and 5.8 cm.
        precisions = precisions or {"cup": (60.0, 700.0), "box": (40.0, 300.0)}
        self.q = q / self.scale**2
        self.precisions = {c: np.diag(p) / self.scale**2 for c, p in precisions.items()}
        self.horizon = int(horizon)
        self.slope = float(slope)

    def describe(self) -> str:
        p = {c: np.diag(m) * self.scale**2 for c, m in self.precisions.items()}
        return (
            f"thesis reward Q = {self.q * self.scale**2:g}, "
            + ", ".join(f"{c} P = diag({v[0]:g}, {v[1]:g})" for c, v in p.items())
            + f" 1/m²; its MPC H = {self.horizon}, slope {self.slope:g}, no goal term"
        )

    def rewards(self, frame: Frame, scene: Scene) -> np.ndarray:
        """Reward of every grid point, shape (n_stations, n_grid)."""
        pts = frame.grid_points()
        out = -self.q * np.broadcast_to(frame.grid**2, pts.shape[:2]).copy()
        for o in scene.obstacles:
            d = pts - o.position
            out -= np.exp(-np.einsum("kgi,ij,kgj->kg", d, self.precisions[o.label], d))
        return out

    def _path(self, frame: Frame, scene: Scene) -> np.ndarray:
        r = self.rewards(frame, scene)
        reach = max(1, int(np.floor(self.slope * frame.ds / frame.step + 1e-9)))
        size = 2 * reach + 1
        n = frame.n_stations
        idx = frame.zero
        chosen = [idx]
        for k in range(n - 1):
            h = min(self.horizon, n - 1 - k)
            value = r[k + h].copy()
            for j in range(h - 1, 0, -1):
                value = r[k + j] + maximum_filter1d(value, size, mode="nearest")
            lo, hi = max(0, idx - reach), min(len(frame.grid), idx + reach + 1)
            idx = lo + int(np.argmax(value[lo:hi]))
            chosen.append(idx)
        return frame.at(frame.grid[np.array(chosen)])


class MarginPerson(Person):
    """Keeps a fixed surface margin per class, otherwise the shortest smooth path."""

    kind = "margin"

    def __init__(
        self,
        scale: float = 1.0,
        n_points: int = 100,
        *,
        margins: dict | None = None,
        max_slope: float = 2.0,
        smoothing: float = 2.0,
    ) -> None:
        super().__init__(scale, n_points)
        self.margins = {
            c: m * self.scale for c, m in (margins or {"cup": 0.02, "box": 0.04}).items()
        }
        self.max_slope = float(max_slope)
        self.smoothing = float(smoothing)

    def describe(self) -> str:
        return (
            "fixed surface margin "
            + ", ".join(f"{c} {m / self.scale * 100:g} cm" for c, m in self.margins.items())
            + ", otherwise the shortest path in the nominal's frame, smoothed"
        )

    def feasible(self, frame: Frame, scene: Scene) -> np.ndarray:
        pts = frame.grid_points()
        ok = np.ones(pts.shape[:2], dtype=bool)
        for o in scene.obstacles:
            ok &= np.linalg.norm(pts - o.position, axis=-1) - o.radius >= self.margins[o.label]
        return ok

    def _path(self, frame: Frame, scene: Scene) -> np.ndarray:
        ok = self.feasible(frame, scene)
        n, g = ok.shape
        z = frame.zero
        if not ok[0, z] or not ok[-1, z]:
            raise PersonFailed("margin: start or goal within a margin")
        # Rounding must not decide (the same person in mm plans the same path): a
        # slope on a whole number of steps, and shorter only by more than round-off.
        reach = int(np.ceil(self.max_slope * frame.ds / frame.step * (1.0 - 1e-9)))
        shifts = np.arange(-reach, reach + 1)
        step_cost = np.hypot(frame.ds, shifts * frame.step)
        tie = 1e-9 * frame.ds
        cost = np.full(g, np.inf)
        cost[z] = 0.0
        back = np.zeros((n, g), dtype=np.int32)
        for k in range(1, n):
            best = np.full(g, np.inf)
            arg = np.zeros(g, dtype=np.int32)
            for d, c in zip(shifts, step_cost, strict=True):
                cand = np.full(g, np.inf)
                if d >= 0:
                    cand[d:] = cost[: g - d] + c
                else:
                    cand[:d] = cost[-d:] + c
                better = cand < best - tie
                best[better] = cand[better]
                arg[better] = d
            best[~ok[k]] = np.inf
            cost = best
            back[k] = arg
        if not np.isfinite(cost[z]):
            raise PersonFailed("margin: no path keeps the margins")
        idx = np.empty(n, dtype=int)
        idx[-1] = z
        for k in range(n - 1, 0, -1):
            idx[k - 1] = idx[k] - back[k, idx[k]]
        e = frame.grid[idx]
        for _ in range(4):
            e = gaussian_filter1d(e, self.smoothing, mode="nearest")
            e[0] = e[-1] = 0.0
            e = self._enforce(frame, scene, e)
        return frame.at(e)

    def _enforce(self, frame: Frame, scene: Scene, e: np.ndarray) -> np.ndarray:
        """Each offset inside a margin moved to the nearest offset that keeps it."""
        if not len(scene):
            return e
        out = e.copy()
        for k in range(frame.n_stations):
            pts = frame.points[k] + frame.grid[:, None] * frame.normals[k]
            ok = np.ones(len(frame.grid), dtype=bool)
            for o in scene.obstacles:
                ok &= np.linalg.norm(pts - o.position, axis=1) - o.radius >= self.margins[o.label]
            here = frame.points[k] + e[k] * frame.normals[k]
            inside = any(
                np.linalg.norm(here - o.position) - o.radius < self.margins[o.label]
                for o in scene.obstacles
            )
            if inside and ok.any():
                # Grid points are on the safe side of the margin; nearest one to e[k].
                out[k] = frame.grid[ok][np.argmin(np.abs(frame.grid[ok] - e[k]))]
        return out


def min_jerk_motion(nominal: np.ndarray, n_steps: int) -> tuple[np.ndarray, np.ndarray]:
    """Positions and velocities (per unit time, duration 1) along ``nominal``, min-jerk timed."""
    s = arc_length(nominal)
    u = np.linspace(0.0, 1.0, n_steps)
    phase = u**3 * (10.0 - 15.0 * u + 6.0 * u**2)
    pos = np.column_stack([np.interp(phase * s[-1], s, nominal[:, k]) for k in range(2)])
    vel = np.gradient(pos, u, axis=0)
    return pos, vel


def dmp_with_coupling(
    nominal: np.ndarray, coupling, n_steps: int = 1000, overtime: float = 0.5
) -> np.ndarray:
    """The nominal's DMP (α = 25, β = α/4, τ = 1 s) with an extra acceleration ``coupling``.

    A DMP reproduces its demonstration exactly and is linear in the state, so
    with a coupling term ``C`` its deviation ``e`` from the nominal obeys
    ``ë = −αβ e − α ė + C(y, ẏ)``: integrated here (semi-implicit Euler), for
    ``overtime`` seconds past the execution time with the nominal at its goal
    (as a DMP keeps running until it converges). ``coupling(y, yd)`` returns an
    acceleration, shape (2,).
    """
    pos, vel = min_jerk_motion(nominal, n_steps)
    dt = 1.0 / (n_steps - 1)
    extra = round(overtime / dt)
    pos = np.vstack((pos, np.repeat(pos[-1:], extra, axis=0)))
    vel = np.vstack((vel, np.zeros((extra, 2))))
    n_steps = len(pos)
    stiffness, damping = 25.0 * 6.25, 25.0
    e = np.zeros(2)
    ed = np.zeros(2)
    out = np.empty_like(pos)
    for i in range(n_steps):
        y = pos[i] + e
        out[i] = y
        edd = -stiffness * e - damping * ed + coupling(y, vel[i] + ed)
        ed = ed + dt * edd
        e = e + dt * ed
    if not np.all(np.isfinite(out)):
        raise PersonFailed("dmp: diverged")
    return out


class FieldPerson(Person):
    """A DMP with a repulsive (and rotational) potential field per class."""

    kind = "field"

    def __init__(
        self,
        scale: float = 1.0,
        n_points: int = 100,
        *,
        gains: dict | None = None,
        ranges: dict | None = None,
        rotation: float = 0.6,
    ) -> None:
        super().__init__(scale, n_points)
        # m/s² at d = ρ/2, and the field's reach ρ (surface distance), per class.
        self.gains = {c: a * self.scale for c, a in (gains or {"cup": 30.0, "box": 50.0}).items()}
        self.ranges = {c: r * self.scale for c, r in (ranges or {"cup": 0.06, "box": 0.10}).items()}
        self.rotation = float(rotation)

    def describe(self) -> str:
        return (
            "DMP (alpha 25, beta 6.25, tau 1 s) + repulsive field a (reach/d - 1): "
            + ", ".join(
                f"{c} a {self.gains[c] / self.scale:g} m/s², "
                f"reach {self.ranges[c] / self.scale * 100:g} cm"
                for c in self.gains
            )
            + f", rotational part {self.rotation:g}"
        )

    def coupling(self, scene: Scene):
        obstacles = [
            (o.position, o.radius, self.gains[o.label], self.ranges[o.label]) for o in scene
        ]

        def accel(y, yd):
            total = np.zeros(2)
            for centre, radius, gain, reach in obstacles:
                diff = y - centre
                dist = float(np.hypot(*diff))
                d = max(dist - radius, 0.03 * reach)
                if d >= reach:
                    continue
                away = diff / dist
                mag = gain * (reach / d - 1.0)
                # Rotational part: push sideways, to the side the obstacle is not on.
                left = np.array([-yd[1], yd[0]])
                norm = np.hypot(*left)
                side = 1.0 if (left @ -diff) < 0.0 else -1.0
                total += mag * away
                if norm > 0.0:
                    total += self.rotation * mag * side * left / norm
            return total

        return accel

    def _path(self, frame: Frame, scene: Scene) -> np.ndarray:
        path = dmp_with_coupling(frame.points, self.coupling(scene))
        if np.linalg.norm(path[-1] - frame.points[-1]) > 0.005 * self.scale:
            raise PersonFailed("field: stuck before the goal (a local minimum of the field)")
        # Drop the samples where it stands still at the goal before resampling.
        moving = np.linalg.norm(np.diff(path, axis=0), axis=1) > 1e-9 * self.scale
        return resample(path[np.r_[True, moving]], frame.n_stations)


class LatePerson(Person):
    """Reacts only within a look-ahead, swerves steeply, returns slowly."""

    kind = "late"

    def __init__(
        self,
        scale: float = 1.0,
        n_points: int = 100,
        *,
        lookahead: float = 0.08,
        clearances: dict | None = None,
        out_slope: float = 1.5,
        back_slope: float = 0.2,
    ) -> None:
        super().__init__(scale, n_points)
        self.lookahead = lookahead * self.scale
        self.clearances = {
            c: m * self.scale for c, m in (clearances or {"cup": 0.03, "box": 0.015}).items()
        }
        self.out_slope = float(out_slope)
        self.back_slope = float(back_slope)

    def describe(self) -> str:
        return (
            f"reacts within {self.lookahead / self.scale * 100:g} cm, clearance "
            + ", ".join(f"{c} {m / self.scale * 100:g} cm" for c, m in self.clearances.items())
            + f", out slope {self.out_slope:g}, back {self.back_slope:g}, to the goal over 8 %"
        )

    def _path(self, frame: Frame, scene: Scene) -> np.ndarray:
        items = []
        for o in scene.obstacles:
            k, lateral = frame.project(o.position)
            width = o.radius + self.clearances[o.label]
            items.append((frame.s[k], lateral, width))
        groups = _groups(scene, [w for _, _, w in items])
        e = np.zeros(frame.n_stations)
        for k in range(1, frame.n_stations):
            s = frame.s[k]
            near = {
                i for i, (so, _, w) in enumerate(items) if so - w - self.lookahead <= s <= so + w
            }
            # A connected barrier (clearance discs overlapping) is seen as a whole.
            seen = {j for i in near for j in groups[i]}
            active = [(items[i][1] - items[i][2], items[i][1] + items[i][2]) for i in seen]
            current = e[k - 1]
            target = 0.0
            if active:
                merged = _merge(active)
                inside = [iv for iv in merged if iv[0] < current < iv[1]]
                if inside:
                    lo, hi = inside[0]
                    target = lo if current - lo < hi - current else hi
                else:
                    # Free here: come back toward 0 but not through an interval.
                    lo = max([iv[1] for iv in merged if iv[1] <= current], default=-np.inf)
                    hi = min([iv[0] for iv in merged if iv[0] >= current], default=np.inf)
                    target = float(np.clip(0.0, lo, hi))
            outward = abs(target) > abs(current) or target * current < 0.0
            limit = (self.out_slope if outward else self.back_slope) * frame.ds
            e[k] = current + np.clip(target - current, -limit, limit)
        # Back onto the goal over the last 8 % (cosine blend).
        u = frame.s / frame.s[-1]
        w = np.clip((1.0 - u) / 0.08, 0.0, 1.0)
        e *= 0.5 - 0.5 * np.cos(np.pi * w)
        return frame.at(e)


def _groups(scene: Scene, widths) -> list[set[int]]:
    """For each obstacle, the obstacles connected to it by overlapping discs of ``widths``."""
    n = len(widths)
    parent = list(range(n))

    def root(i):
        while parent[i] != i:
            i = parent[i]
        return i

    pos = [o.position for o in scene.obstacles]
    for i in range(n):
        for j in range(i):
            if np.linalg.norm(pos[i] - pos[j]) < widths[i] + widths[j]:
                parent[root(i)] = root(j)
    members: dict[int, set[int]] = {}
    for i in range(n):
        members.setdefault(root(i), set()).add(i)
    return [members[root(i)] for i in range(n)]


def _merge(intervals):
    out = []
    for lo, hi in sorted(intervals):
        if out and lo <= out[-1][1]:
            out[-1] = (out[-1][0], max(out[-1][1], hi))
        else:
            out.append((lo, hi))
    return out


def make_person(kind: str, scale: float = 1.0, n_points: int = 100) -> Person:
    """The person of ``kind`` (one of :data:`KINDS`) with its default behaviour."""
    people = {
        "thesis": ThesisPerson,
        "margin": MarginPerson,
        "field": FieldPerson,
        "late": LatePerson,
    }
    if kind not in people:
        raise ValueError(f"kind: unknown person {kind!r}; choose from {', '.join(people)}")
    return people[kind](scale, n_points)


# ----------------------------------------------------------------------------- noise
def add_noise(path: np.ndarray, sd: float, rng: np.random.Generator) -> np.ndarray:
    """``path`` plus smooth lateral noise of standard deviation ``sd``, tapered at the ends.

    Always draws the same numbers from ``rng`` (also for ``sd = 0``), so a
    noise level scales one and the same noise shape.
    """
    freq = rng.uniform(0.5, 3.0, 3)
    phase = rng.uniform(0.0, 2 * np.pi, 3)
    amp = rng.uniform(0.5, 1.0, 3)
    s = arc_length(path)
    u = s / s[-1]
    wave = (amp[:, None] * np.sin(2 * np.pi * freq[:, None] * u + phase[:, None])).sum(0)
    wave *= sd / max(wave.std(), 1e-12)
    taper = np.sin(0.5 * np.pi * np.clip(np.minimum(u, 1.0 - u) / 0.1, 0.0, 1.0)) ** 2
    return resample(path + (wave * taper)[:, None] * left_normals(path), len(path))


# ----------------------------------------------------------------------------- tasks, scenes
def task_nominal(name: str, scale: float = 1.0, n: int = 400) -> np.ndarray:
    """A task's nominal path (n, 2): ``train`` straight 0.8 m along x, or a new task."""
    u = np.linspace(0.0, 1.0, n)
    if name == "train":
        path = np.column_stack((0.8 * u, np.zeros(n)))
    elif name == "arc":  # quarter circle, radius 0.5 m, turning left
        a = 0.5 * np.pi * u
        path = np.column_stack((0.5 * np.sin(a), 0.5 * (1.0 - np.cos(a))))
    elif name == "s_curve":
        path = np.column_stack((0.8 * u, 0.08 * np.sin(2.0 * np.pi * u)))
    elif name == "diagonal":
        path = np.column_stack((0.5 * u, 0.5 * u))
    else:
        raise ValueError(f"task: unknown task {name!r}")
    return resample(path * scale, n)


NEW_TASKS = ("arc", "s_curve", "diagonal")
FAMILIES = ("single", "pair", "clutter", "pocket", "near_goal", "moved_goal", "new_task")


def moved_nominal(nominal: np.ndarray, start_shift, goal_shift) -> np.ndarray:
    """The nominal with its start and goal moved, blended in by a min-jerk weight."""
    u = arc_length(nominal) / arc_length(nominal)[-1]
    w = (u**3 * (10.0 - 15.0 * u + 6.0 * u**2))[:, None]
    return nominal + (1.0 - w) * np.asarray(start_shift) + w * np.asarray(goal_shift)


@dataclass
class Case:
    """One demonstration setting: its task's nominal, start, goal and scene."""

    family: str
    task: str
    nominal: np.ndarray
    scene: Scene

    @property
    def start(self) -> np.ndarray:
        return self.nominal[0]

    @property
    def goal(self) -> np.ndarray:
        return self.nominal[-1]


def _label(rng) -> str:
    return CLASSES[int(rng.integers(2))]


def _separated(items, gap: float) -> bool:
    for i in range(len(items)):
        for j in range(i):
            (ci, pi), (cj, pj) = items[i], items[j]
            if np.linalg.norm(pi - pj) < RADIUS[ci] + RADIUS[cj] + gap:
                return False
    return True


def draw_case(family: str, rng: np.random.Generator, scale: float = 1.0, label: str | None = None):
    """One random case of ``family`` (metres times ``scale``); None when the draw is unusable."""
    m = scale
    task = "train"
    nominal = task_nominal("train", m)
    if family == "moved_goal":
        nominal = moved_nominal(
            nominal,
            (0.0, rng.uniform(-0.05, 0.05) * m),
            (rng.uniform(-0.1, 0.1) * m, rng.uniform(-0.15, 0.15) * m),
        )
    elif family == "new_task":
        task = NEW_TASKS[int(rng.integers(len(NEW_TASKS)))]
        nominal = task_nominal(task, m)
    frame = Frame(nominal, m)

    def side() -> float:
        return 1.0 if rng.random() < 0.5 else -1.0

    items = []
    if family in ("single", "moved_goal", "train"):
        c = label or _label(rng)
        items.append((c, frame.place(rng.uniform(0.3, 0.7), side() * rng.uniform(0.005, 0.05) * m)))
    elif family == "pair":
        c1, c2 = _label(rng), _label(rng)
        gap = rng.uniform(0.03, 0.10) * m
        centre = rng.uniform(-0.03, 0.03) * m
        u = rng.uniform(0.4, 0.6)
        items.append(
            (c1, frame.place(u, centre - gap / 2 - RADIUS[c1] * m, rng.uniform(-0.03, 0.03) * m))
        )
        items.append(
            (c2, frame.place(u, centre + gap / 2 + RADIUS[c2] * m, rng.uniform(-0.03, 0.03) * m))
        )
    elif family in ("clutter", "new_task"):
        n = int(rng.integers(3, 7)) if family == "clutter" else int(rng.integers(1, 4))
        us = np.linspace(0.2, 0.8, n) + rng.uniform(-0.3, 0.3, n) * 0.6 / n
        for u in us:
            items.append((_label(rng), frame.place(u, side() * rng.uniform(0.0, 0.08) * m)))
    elif family == "pocket":
        n = int(rng.integers(5, 7))  # 5 or 6 cups on a half circle: gaps of 2 cm or less
        # Its mouth faces the start; across the path, or a little beside it.
        centre_u, lateral = rng.uniform(0.45, 0.6), side() * rng.uniform(0.0, 0.12) * m
        radius = 0.1 * m
        for a in np.deg2rad(np.linspace(-90.0, 90.0, n)):
            items.append(
                ("cup", frame.place(centre_u, lateral + radius * np.sin(a), radius * np.cos(a)))
            )
    elif family == "near_goal":
        c = _label(rng)
        items.append(
            (c, frame.place(rng.uniform(0.86, 0.93), side() * rng.uniform(0.01, 0.05) * m))
        )
    else:
        raise ValueError(f"family: unknown {family!r}")
    if family != "pocket" and not _separated([(c, p / m) for c, p in items], 0.01):
        return None
    scene = make_scene(items, m)
    ends = np.array([nominal[0], nominal[-1]])
    if surface_distances(ends, scene).min() < 0.06 * m:  # start and goal clear of every margin
        return None
    return Case(family, task, nominal, scene)
