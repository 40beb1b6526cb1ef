"""An oriented box obstacle: a carton, a table top, a shelf, a wall (2-D or 3-D).

One class through the obstacle contract (:class:`lfdkit.model.scene.Obstacle`):
a centre (``position``), edge lengths (``size``, one per axis of the data)
and an orientation (a unit quaternion ``[x, y, z, w]``, the box's own axes in
the data's frame; a 2-D box turns about ``z`` only). ``radius`` rounds it:
the solid is every point within ``radius`` of the box (0, the default, is a
sharp box), as a capsule is every point within its radius of a segment.

Geometry
--------
* :meth:`Box.distance` is exact (closed form, no sampling): in the box's
  frame the signed distance is ``|max(e, 0)| + min(max_i e_i, 0)`` with
  ``e = |x| − size/2``. Along one straight segment it is ``√(quadratic)``
  wherever the segment stays in one region (below, within or above the box
  on each axis) and linear inside, so its minimum over the segment is at an
  end, at a region change (``x_i = ±size_i/2``, ``x_i = 0``, or two faces
  equally near), or at the vertex of one region's quadratic: at most 49
  candidates per segment in 3-D, each evaluated exactly.
* :meth:`Box.anchors` (the reward's Gaussian terms): the centres of a grid
  of cells about as long as the box's shortest edge, and at most 8 along
  an edge (a cube is one term at its centre, a 1.0 × 0.6 table top 8 × 5
  terms), so the response follows the box's extent, not a ball at its
  centre.
* :meth:`Box.balls` (the planner's hard clearance): balls about the cells of
  a finer grid (a third of the shortest edge, at most 16 along an edge),
  each of the cell's half-diagonal plus ``radius``: their union contains
  the box, overhanging a cube's faces by at most 24 % of its half-edge.

Hard barrier: a box with volume (every edge > 0, or ``radius`` > 0) answers
:attr:`Box.has_extent` True, so the planner keeps out of a sharp box (radius
0) even at clearance 0, and refuses a start inside it. A flat box (an edge
0) at radius 0 is a plate or a segment: like a round obstacle of radius 0,
a hard barrier only with a clearance.

Files: the fields ``size`` (a point: ``size_x, size_y[, size_z]`` in CSV)
and ``qx, qy, qz, qw`` (numbers); e.g. ``{"class": "carton", "shape":
"box", "position": [0.5, 0.0, 0.1], "size": [0.2, 0.1, 0.2], "qx": 0,
"qy": 0, "qz": 0, "qw": 1}``.
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from lfdkit.core.geometry import convex_hull_2d
from lfdkit.core.rotations import check_quaternions, matrix_from_quaternion, quaternion_from_matrix
from lfdkit.model.scene import Obstacle, register_shape

__all__ = ["Box"]

#: Largest number of reward anchors along one edge (anchors: cells ≈ the shortest edge).
MAX_ANCHORS_PER_EDGE = 8
#: Largest number of covering balls along one edge (cells ≈ a third of the shortest edge).
MAX_BALLS_PER_EDGE = 16
#: A 2-D box's quaternion may tilt its z axis by at most this (the sine of the angle).
PLANAR_TOLERANCE = 1e-9


def _identity() -> np.ndarray:
    return np.array([0.0, 0.0, 0.0, 1.0])


@dataclass(frozen=True, eq=False)
class Box(Obstacle):
    """An oriented box: every point within ``radius`` of it (``radius`` 0: a sharp box).

    Attributes
    ----------
    size : ndarray, shape (q,)
        Edge lengths along the box's own axes (units of the paths), each >= 0.
    orientation : ndarray, shape (4,)
        Unit quaternion ``[x, y, z, w]`` turning the box's axes into the
        data's frame (identity: edges along the coordinate axes). A 2-D box
        turns about ``z`` only (``x = y = 0``); see :meth:`from_yaw`.
    """

    size: np.ndarray = field(default_factory=lambda: np.zeros(0))
    orientation: np.ndarray = field(default_factory=_identity)

    shape: ClassVar[str] = "box"
    field_kinds: ClassVar[Mapping[str, str]] = {
        "size": "point",
        "qx": "number",
        "qy": "number",
        "qz": "number",
        "qw": "number",
    }

    def __post_init__(self) -> None:
        super().__post_init__()
        size = np.asarray(self.size, dtype=np.float64)
        if size.shape != self.position.shape:
            raise ValueError(
                f"size: expected {self.position.size} edge lengths for a "
                f"{self.position.size}-D box, got shape {np.shape(self.size)} ({self.label!r})"
            )
        if not np.all(np.isfinite(size)) or np.any(size < 0):
            raise ValueError(
                f"size: edge lengths must be finite and >= 0, got {size.tolist()} ({self.label!r})"
            )
        try:
            quaternion = check_quaternions(self.orientation, "orientation", n=1)[0]
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{exc} ({self.label!r})") from None
        given = np.asarray(self.orientation, dtype=np.float64)
        if abs(float(np.linalg.norm(given)) - 1.0) <= 1e-12:
            quaternion = given.copy()  # unit already: kept to the bit (files round-trip)
        quaternion = quaternion if quaternion[3] >= 0 else -quaternion  # one sign per rotation
        rotation = matrix_from_quaternion(quaternion)
        if self.n_dims == 2 and np.hypot(rotation[0, 2], rotation[1, 2]) > PLANAR_TOLERANCE:
            raise ValueError(
                f"orientation: a 2-D box turns about z only (qx = qy = 0), got "
                f"{quaternion.tolist()} ({self.label!r}); use Box.from_yaw"
            )
        size.setflags(write=False)
        quaternion.setflags(write=False)
        object.__setattr__(self, "size", size)
        object.__setattr__(self, "orientation", quaternion)

    @classmethod
    def from_yaw(
        cls, label: str, position: Any, size: Any, yaw: float = 0.0, radius: float = 0.0
    ) -> Box:
        """A box turned by ``yaw`` (rad, anticlockwise) about ``z``: a 2-D box."""
        half = 0.5 * float(yaw)
        return cls(label, position, radius, size, [0.0, 0.0, np.sin(half), np.cos(half)])

    # ------------------------------------------------------------ frame
    @property
    def half(self) -> np.ndarray:
        """Half edge lengths, shape (q,)."""
        return 0.5 * self.size

    @cached_property
    def axes(self) -> np.ndarray:
        """The box's axes as the columns of a rotation matrix, shape (q, q)."""
        q = self.n_dims
        return _read_only(matrix_from_quaternion(self.orientation)[:q, :q])

    def to_local(self, points: np.ndarray) -> np.ndarray:
        """Points (n, q) in the box's frame (its centre at the origin, its edges along the axes)."""
        return (np.asarray(points, dtype=np.float64) - self.position) @ self.axes

    def corners(self) -> np.ndarray:
        """The box's corners, shape (2**q, q) (without the rounding ``radius``)."""
        signs = np.array(list(itertools.product((-1.0, 1.0), repeat=self.n_dims)))
        return self.position + (signs * self.half) @ self.axes.T

    def signed_distances(self, points: np.ndarray) -> np.ndarray:
        """Signed distance from each point (n, q) to the surface (negative inside), shape (n,)."""
        return _local_signed_distance(self.to_local(points), self.half) - self.radius

    def _grid(self, per_shortest: float, most: int) -> tuple[np.ndarray, np.ndarray]:
        """Centres (k, q) of a grid of cells over the box and the cells' half edges (q,).

        Cells are about ``shortest edge / per_shortest`` long, at most ``most`` along an edge.
        """
        longest = float(self.size.max())
        cell = max(float(self.size.min()) / per_shortest, longest / most)
        counts = np.ones(self.n_dims, int) if cell <= 0 else np.ceil(self.size / cell - 1e-9)
        counts = np.maximum(counts.astype(int), 1)
        halves = self.half / counts
        ticks = [(2.0 * np.arange(c) + 1.0 - c) * h for c, h in zip(counts, halves, strict=True)]
        local = np.array(list(itertools.product(*ticks)))
        return self.position + local @ self.axes.T, halves

    # ------------------------------------------------------------ the contract
    @property
    def has_extent(self) -> bool:
        """True for a box with volume: every edge > 0, or rounded (``radius`` > 0)."""
        return bool(self.radius > 0.0 or np.all(self.size > 0.0))

    # The IOC asks for the anchors at every evaluation of its loss: computed once
    # (the box is immutable) and handed out read-only.
    def anchors(self) -> np.ndarray:
        return self._anchors

    def balls(self) -> tuple[np.ndarray, np.ndarray]:
        return self._balls

    @cached_property
    def _anchors(self) -> np.ndarray:
        return _read_only(self._grid(1.0, MAX_ANCHORS_PER_EDGE)[0])

    @cached_property
    def _balls(self) -> tuple[np.ndarray, np.ndarray]:
        centres, halves = self._grid(3.0, MAX_BALLS_PER_EDGE)
        radii = np.full(centres.shape[0], float(np.linalg.norm(halves)) + self.radius)
        return _read_only(centres), _read_only(radii)

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        corners = self.corners()
        return corners.min(axis=0) - self.radius, corners.max(axis=0) + self.radius

    def distance(self, path: np.ndarray) -> float:
        path = np.asarray(path, dtype=np.float64)
        local = self.to_local(path)
        if local.shape[0] == 1:
            return float(_local_signed_distance(local, self.half)[0]) - self.radius
        start, step = local[:-1], np.diff(local, axis=0)
        near = _near_segments(local, self.half)
        if near is not None:
            start, step = start[near], step[near]
        t = _segment_candidates(start, step, self.half)
        points = start[:, None, :] + t[:, :, None] * step[:, None, :]
        best = _local_signed_distance(points.reshape(-1, self.n_dims), self.half).min()
        return float(best) - self.radius

    def extreme_point(self, direction: np.ndarray) -> np.ndarray:
        """Exact: the corner farthest along ``direction``, moved out by the rounding ``radius``."""
        unit = np.asarray(direction, dtype=np.float64)
        unit = unit / np.linalg.norm(unit)
        corners = self.corners()
        return corners[int(np.argmax(corners @ unit))] + self.radius * unit

    def outline(self, n_points: int = 64) -> np.ndarray:
        """The top view: the convex hull of the corners (rounded by ``radius``), closed."""
        corners = self.corners()[:, :2]
        hull = convex_hull_2d(corners)
        if self.radius > 0:
            around = np.linspace(0.0, 2.0 * np.pi, max(n_points // len(hull), 4))
            ring = np.column_stack([np.cos(around), np.sin(around)]) * self.radius
            hull = convex_hull_2d((hull[:, None, :] + ring[None]).reshape(-1, 2))
        return np.vstack([hull, hull[:1]])

    def fields(self) -> dict[str, Any]:
        qx, qy, qz, qw = (float(v) for v in self.orientation)
        return {"size": self.size, "qx": qx, "qy": qy, "qz": qz, "qw": qw}

    def solid(self, height: float) -> tuple[np.ndarray, dict[str, str]]:
        """A MuJoCo box: a 2-D box stands ``height`` tall on the plane, a 3-D one is where it is.

        The rounding ``radius`` is added to the half edges (MuJoCo boxes are sharp).
        """
        half = self.half + self.radius
        if self.n_dims == 2:
            centre = np.array([*self.position, 0.5 * float(height)])
            half = np.array([*half, 0.5 * float(height)])
        else:
            centre = self.position.copy()
        x, y, z, w = (float(v) for v in self.orientation)
        return centre, {
            "type": "box",
            "size": " ".join(repr(float(v)) for v in half),
            "quat": f"{w!r} {x!r} {y!r} {z!r}",  # MuJoCo: scalar first
        }

    def transformed(self, factor: float, flip: np.ndarray) -> Box:
        flip = np.asarray(flip, dtype=np.float64)
        full = np.ones(3)
        full[: flip.size] = flip
        # F R keeps the box if one of its own axes is flipped back (det +1):
        # a box is symmetric about each of its axes.
        own = np.ones(3)
        own[0] = float(np.prod(full))
        rotation = full[:, None] * matrix_from_quaternion(self.orientation) * own[None, :]
        return Box(
            self.label,
            factor * flip * self.position,
            factor * self.radius,
            factor * self.size,
            quaternion_from_matrix(rotation),
            motion=None if self.motion is None else self.motion.transformed(factor, flip),
        )

    @classmethod
    def from_fields(
        cls, label: str, position: Any, radius: float, fields: Mapping[str, Any]
    ) -> Box:
        missing = [name for name in cls.field_kinds if name not in fields]
        if missing:
            raise ValueError(
                f"{missing[0]}: a box needs its edge lengths 'size' and its orientation "
                f"'qx', 'qy', 'qz', 'qw' ({label!r})"
            )
        quaternion = [fields[name] for name in ("qx", "qy", "qz", "qw")]
        return cls(label, position, radius, fields["size"], quaternion)


register_shape(Box)


def _read_only(array: np.ndarray) -> np.ndarray:
    array = np.array(array, dtype=np.float64)
    array.setflags(write=False)
    return array


def _local_signed_distance(local: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Signed distance (n,) of points (n, q) in a box's frame to the box of half edges ``half``."""
    excess = np.abs(local) - half
    outside = np.sqrt(np.sum(np.maximum(excess, 0.0) ** 2, axis=1))
    return outside + np.minimum(excess.max(axis=1), 0.0)


def _near_segments(local: np.ndarray, half: np.ndarray) -> np.ndarray | None:
    """The segments of a polyline (n, q) in a box's frame that may hold its nearest point.

    Every point of a segment is at least ``max_i (m_i − h_i)`` from the box
    (signed; ``m_i`` the least ``|x_i|`` along it), and every segment's start
    is one of the candidates :meth:`Box.distance` takes the least of: a
    segment whose bound, less a tolerance far above the candidates' rounding,
    exceeds the nearest start's distance cannot hold the least candidate, so
    leaving it out gives the same number, to the bit, for a fraction of the
    work (3-D scenes with boxes: issue 34). None (all of them) for a path
    with a coordinate not finite.
    """
    if not np.all(np.isfinite(local)):
        return None
    a, b = np.abs(local[:-1]), np.abs(local[1:])
    least = np.where(local[:-1] * local[1:] <= 0.0, 0.0, np.minimum(a, b))
    bound = (least - half).max(axis=1)
    tolerance = 1e-9 * (a.max(axis=1) + b.max(axis=1) + float(half.max()))
    nearest = _local_signed_distance(local[:-1], half).min()
    return np.flatnonzero(bound - tolerance <= nearest)


def _segment_candidates(start: np.ndarray, step: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Parameters in [0, 1] (s, c) among which each segment's nearest point to the box lies.

    ``start + t · step`` (each (s, q), in the box's frame): the ends, every
    region change on one axis (``x_i ∈ {−h_i, 0, h_i}``) or between two
    (``|x_i| − h_i = |x_j| − h_j``, the nearest face switching inside), and
    the vertex of the squared distance of every region outside. Each family
    is one array operation; a region's sums over the axes it does not use
    add exact zeros, so every candidate is the number a column at a time gave
    (the nearest distance the same to the bit), in a third of the time (issue 34).
    """
    s = start.shape[0]
    axes, signs, pairs, regions, used = _candidate_tables(start.shape[1])
    i, j, si, sj = pairs
    with np.errstate(divide="ignore", invalid="ignore"):
        crossings = (signs * half[axes] - start[:, axes]) / step[:, axes]
        faces = (half[i] - half[j] - si * start[:, i] + sj * start[:, j]) / (
            si * step[:, i] - sj * step[:, j]
        )
        offset = np.where(used, start[:, None, :] - regions * half, 0.0)
        moves = np.where(used, step[:, None, :], 0.0)
        vertices = -np.sum(offset * moves, axis=2) / np.sum(moves**2, axis=2)
        ends = np.zeros((s, 2))
        ends[:, 1] = 1.0
        t = np.concatenate([ends, crossings, faces, vertices], axis=1)
    return np.clip(np.where(np.isfinite(t), t, 0.0), 0.0, 1.0)


@functools.lru_cache(maxsize=4)
def _candidate_tables(q: int) -> tuple:
    """:func:`_segment_candidates`' tables for ``q`` axes.

    The levels' axes and signs (3q each: −1, 0, 1 half edge per axis), the
    face pairs ``(i, j, sign i, sign j)`` (each an array), the regions
    outside (r, q: −1, 0 or 1 per axis) and the axes each uses (r, q, bool).
    """
    axes = np.repeat(np.arange(q), 3)
    signs = np.tile(np.array([-1.0, 0.0, 1.0]), q)
    faces = [
        (i, j, si, sj)
        for i, j in itertools.combinations(range(q), 2)
        for si, sj in itertools.product((-1.0, 1.0), repeat=2)
    ]
    pairs = (
        np.array([f[0] for f in faces], dtype=int),
        np.array([f[1] for f in faces], dtype=int),
        np.array([f[2] for f in faces]),
        np.array([f[3] for f in faces]),
    )
    regions = np.array([r for r in itertools.product((-1.0, 0.0, 1.0), repeat=q) if any(r)])
    used = regions != 0.0
    for table in (axes, signs, *pairs, regions, used):  # shared by every call: never written to
        table.setflags(write=False)
    return axes, signs, pairs, regions, used
