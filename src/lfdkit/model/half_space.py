"""A half-space obstacle: a table top, a floor, a wall (2-D: a half-plane).

One class through the obstacle contract (:class:`lfdkit.model.scene.Obstacle`):
``position`` is a point of the boundary plane (put it under the workspace,
e.g. the table's middle: the reward's term sits there), ``normal`` points to
the free side, and ``radius`` lifts the surface (every point within
``radius`` of the half-space is solid). The solid is
``{x : normal · (x − position) ≤ radius}``: unbounded, so a table whose edges
lie far outside the workspace needs no size.

Geometry
--------
* :meth:`HalfSpace.distance` is exact: the height above the surface is
  linear along a segment, so a path's least height is at one of its points.
* :meth:`HalfSpace.anchors`: one Gaussian term at ``position``. The class's
  learned precision sets the response; across the plane it can be as wide as
  the workspace (a response that depends on the height only where the normal
  is a coordinate axis, since precisions are in world axes). A grid of terms
  on the plane would need a spacing, and an unbounded plane has no length.
* :meth:`HalfSpace.balls` exist only for a part, :meth:`HalfSpace.clipped`
  to the box ``[lower, upper]`` the planner can reach. Its surface is
  covered by one layer of balls of radius ``3e`` (``e`` the half-diagonal of a
  cell, at most 32 cells along a side) centred ``√8 e`` below it: they
  overhang the surface by ``(3 − √8) e`` (0.17 e; 4 mm over a 1.2 m box) and
  reach ``2√8 e`` deep. Below it, layers of cells twice as wide as the
  layer above, each ball again 3 half-diagonals, reach down to the box's
  deepest corner (a few layers, about 1,400 balls in 3-D); each deeper ball's
  top, and the planner's barrier zone a quarter of its radius beyond it, stay
  below the surface (its centre at least 3.75 half-diagonals deep).
* :meth:`HalfSpace.bounds` and :meth:`HalfSpace.outline`: the part in the
  clipped box (an unclipped half-space has infinite bounds and no outline;
  the plots clip it to what they draw).

The solid for MuJoCo is a plane geom (static: put it in the world body, not
a free body). A half-space cannot move (``motion`` is refused): a moving
obstacle is covered whole, and a half-space has no finite cover.

Files: the field ``normal`` (a point: ``normal_x, normal_y[, normal_z]`` in
CSV); e.g. ``{"class": "table", "shape": "half_space", "position": [0.5,
0.0, 0.0], "normal": [0, 0, 1]}``.
"""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any, ClassVar

import numpy as np

from lfdkit.core.geometry import convex_hull_2d
from lfdkit.core.rotations import quaternion_from_matrix
from lfdkit.model.scene import Obstacle, register_shape

__all__ = ["HalfSpace"]

#: Largest number of surface cells along a side of the clipped part.
MAX_CELLS_PER_SIDE = 32
#: A surface ball's radius in cell half-diagonals (its overhang is (R − √(R² − 1)) of one).
BALL_RADIUS_CELLS = 3.0
#: How far (in a layer's half-diagonals) each deeper layer's columns overlap the one above.
LAYER_OVERLAP = 0.5


def _up() -> np.ndarray:
    return np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True, eq=False)
class HalfSpace(Obstacle):
    """Every point on or below a plane: ``normal · (x − position) ≤ radius``.

    Attributes
    ----------
    normal : ndarray, shape (q,)
        Unit normal of the plane, pointing to the free side (stored
        normalised; any non-zero length is accepted).
    region : tuple of two ndarrays (q,) or None
        Set by :meth:`clipped` (keyword only): the box whose part
        :meth:`balls`, :meth:`bounds` and :meth:`outline` describe. None: the
        whole, unbounded half-space. Not written to scene files.
    """

    normal: np.ndarray = field(default_factory=_up)
    region: tuple[np.ndarray, np.ndarray] | None = field(default=None, kw_only=True, repr=False)

    shape: ClassVar[str] = "half_space"
    field_kinds: ClassVar[Mapping[str, str]] = {"normal": "point"}

    def __post_init__(self) -> None:
        super().__post_init__()
        normal = np.asarray(self.normal, dtype=np.float64)
        if normal.shape != self.position.shape:
            raise ValueError(
                f"normal: expected {self.n_dims} components for a {self.n_dims}-D half-space, "
                f"got shape {np.shape(self.normal)} ({self.label!r})"
            )
        # Scaled first: the norm of a tiny normal such as [0, 1e-211] underflows to 0.
        scale = float(np.max(np.abs(normal))) if np.all(np.isfinite(normal)) else np.nan
        length = scale * float(np.linalg.norm(normal / scale)) if scale > 0.0 else scale
        if not np.isfinite(length) or length == 0.0:
            raise ValueError(
                f"normal: must be finite and non-zero, got {normal.tolist()} ({self.label!r}); "
                "give the direction of the free side, e.g. [0, 0, 1] for a table top"
            )
        if self.motion is not None:
            raise ValueError(
                f"motion: a half-space cannot move ({self.label!r}); give it where it stands"
            )
        normal = normal / length if abs(length - 1.0) > 1e-12 else normal.copy()
        normal.setflags(write=False)
        object.__setattr__(self, "normal", normal)
        if self.region is not None:
            lower, upper = (np.array(v, dtype=np.float64) for v in self.region)
            if lower.shape != normal.shape or upper.shape != normal.shape:
                raise ValueError(f"region: expected two {self.n_dims}-D corners ({self.label!r})")
            if not (np.all(np.isfinite(lower)) and np.all(np.isfinite(upper))):
                raise ValueError(f"region: corners must be finite ({self.label!r})")
            lower, upper = np.minimum(lower, upper), np.maximum(lower, upper)
            lower.setflags(write=False)
            upper.setflags(write=False)
            object.__setattr__(self, "region", (lower, upper))

    # ------------------------------------------------------------ frame
    @property
    def surface_point(self) -> np.ndarray:
        """The point of the surface (the plane lifted by ``radius``) above ``position``."""
        return self.position + self.radius * self.normal

    @cached_property
    def frame(self) -> np.ndarray:
        """Columns: the plane's axes, then the normal (a rotation, shape (q, q))."""
        n = self.normal
        if self.n_dims == 2:
            return np.array([[n[1], n[0]], [-n[0], n[1]]])
        helper = np.eye(3)[int(np.argmin(np.abs(n)))]  # the axis least along the normal
        u = np.cross(n, helper)
        u /= np.linalg.norm(u)
        return np.column_stack([u, np.cross(n, u), n])

    def heights(self, points: np.ndarray) -> np.ndarray:
        """Signed height of each point (n, q) above the surface (negative inside), shape (n,)."""
        return (np.asarray(points, dtype=np.float64) - self.surface_point) @ self.normal

    def section(self) -> tuple[np.ndarray, np.ndarray]:
        """The clipped part's vertices (k, q) and its face on the surface (f, q), in order.

        The face runs round the plane's polygon inside the region (3-D; in
        2-D a segment's two ends); both are empty where the region lies wholly
        above the surface.

        Raises
        ------
        ValueError
            For an unclipped half-space.
        """
        lower, upper = self._region("section")
        q = self.n_dims
        corners = np.array(list(itertools.product(*zip(lower, upper, strict=True))))
        height = self.heights(corners)
        face = []
        for i, j in itertools.combinations(range(len(corners)), 2):
            if np.count_nonzero(corners[i] != corners[j]) != 1:
                continue  # not an edge of the box
            if (height[i] < 0.0) != (height[j] < 0.0):
                t = height[i] / (height[i] - height[j])
                face.append(corners[i] + t * (corners[j] - corners[i]))
        face += [c for c, h in zip(corners, height, strict=True) if h == 0.0]
        face_points = np.array(face).reshape(-1, q)
        if q == 3 and len(face_points) > 2:
            local = (face_points - face_points.mean(axis=0)) @ self.frame[:, :2]
            face_points = face_points[np.argsort(np.arctan2(local[:, 1], local[:, 0]))]
        vertices = np.vstack([corners[height < 0.0], face_points])
        return vertices, face_points

    def _region(self, what: str) -> tuple[np.ndarray, np.ndarray]:
        if self.region is None:
            raise ValueError(
                f"{what}: half-space {self.label!r} is unbounded; use its part in a box, "
                "clipped(lower, upper)"
            )
        return self.region

    # ------------------------------------------------------------ the contract
    @property
    def has_extent(self) -> bool:
        """Always True: a half-space has volume (a hard barrier at clearance 0)."""
        return True

    def anchors(self) -> np.ndarray:
        return self.position[None]

    def clipped(self, lower: np.ndarray, upper: np.ndarray) -> HalfSpace:
        lower, upper = np.asarray(lower, dtype=np.float64), np.asarray(upper, dtype=np.float64)
        if self.region is not None:  # the part of a part
            lower, upper = np.maximum(lower, self.region[0]), np.minimum(upper, self.region[1])
            upper = np.maximum(upper, lower)
        return replace(self, region=(lower, upper))

    def balls(self) -> tuple[np.ndarray, np.ndarray]:
        return self._balls

    @cached_property
    def _balls(self) -> tuple[np.ndarray, np.ndarray]:
        lower, upper = self._region("balls")
        q, frame = self.n_dims, self.frame
        corners = np.array(list(itertools.product(*zip(lower, upper, strict=True))))
        local = (corners - self.surface_point) @ frame  # plane coordinates, then height
        low, high = local[:, :-1].min(axis=0), local[:, :-1].max(axis=0)
        extent = high - low
        cell = float(extent.max()) / MAX_CELLS_PER_SIDE
        counts = np.ones(q - 1, int) if cell <= 0 else np.ceil(extent / cell - 1e-9).astype(int)
        counts = np.maximum(counts, 1)
        halves = 0.5 * extent / counts
        if not np.any(halves > 0):  # a region of no width across the plane
            halves = np.full(q - 1, 1e-9 * (1.0 + float(np.abs(self.surface_point).max())))
        deepest = float(-local[:, -1].min())
        centres, radii = [], []
        scale, bottom = 1, 0.0
        while True:
            # Layer j: cells 2^j as wide, balls of 3 half-diagonals, each covering a
            # cell's column √8 half-diagonals up and down from its centre.
            e = float(np.linalg.norm(halves)) * scale
            reach = float(np.sqrt(BALL_RADIUS_CELLS**2 - 1.0)) * e
            depth = reach if scale == 1 else max(bottom + reach - LAYER_OVERLAP * e, 3.75 * e)
            layer_counts = np.ceil(counts / scale).astype(int)
            ticks = [
                lo + (2.0 * np.arange(c) + 1.0) * h * scale
                for lo, c, h in zip(low, layer_counts, halves, strict=True)
            ]
            grid = np.array(list(itertools.product(*ticks)))
            centres.append(self.surface_point + grid @ frame[:, :-1].T - depth * self.normal)
            radii.append(np.full(len(grid), BALL_RADIUS_CELLS * e))
            bottom = depth + reach
            if bottom >= deepest:
                break
            scale *= 2
        return _read_only(np.concatenate(centres)), _read_only(np.concatenate(radii))

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        if self.region is None:
            # Unbounded except along a coordinate axis the normal points along.
            lower, upper = np.full(self.n_dims, -np.inf), np.full(self.n_dims, np.inf)
            for k in np.flatnonzero(np.abs(self.normal) == 1.0):
                if self.normal[k] > 0:
                    upper[k] = self.surface_point[k]
                else:
                    lower[k] = self.surface_point[k]
            return lower, upper
        vertices = self.section()[0]
        if not len(vertices):  # nothing of it in the region: its surface point
            return self.surface_point.copy(), self.surface_point.copy()
        return vertices.min(axis=0), vertices.max(axis=0)

    def distance(self, path: np.ndarray) -> float:
        return float(self.heights(np.atleast_2d(path)).min())

    def surface_gap(self, other: Obstacle) -> tuple[float, np.ndarray, np.ndarray]:
        """Exact for the whole half-space: the height of ``other``'s lowest point above it.

        Two whole half-spaces leave a slab between them only when they face
        each other (opposite normals); any others intersect (``-inf``). A
        clipped part is measured through the ball covers.
        """
        whole = self.region is None
        other_whole = isinstance(other, HalfSpace) and other.region is None
        if not whole:
            if other_whole:
                gap, theirs, mine = other.surface_gap(self)
                return gap, mine, theirs
            return self.cover_gap(other)
        if other_whole:
            if float(self.normal @ other.normal) > -1.0 + 1e-9:
                return -np.inf, self.position, other.position
            mine = self.surface_point
            gap = float(self.normal @ (other.position - self.position)) - self.radius - other.radius
            return gap, mine, mine + gap * self.normal
        lowest = other.extreme_point(-self.normal)
        height = float(self.heights(lowest[None])[0])
        return height, lowest - height * self.normal, lowest

    def outline(self, n_points: int = 64) -> np.ndarray:
        """The top view of the clipped part: a closed polygon (empty where it has none)."""
        vertices = self.section()[0] if self.region is not None else self._region("outline")
        if not len(vertices):
            return np.zeros((0, 2))
        hull = convex_hull_2d(vertices[:, :2])
        return np.vstack([hull, hull[:1]])

    def fields(self) -> dict[str, Any]:
        return {"normal": self.normal}

    def solid(self, height: float) -> tuple[np.ndarray, dict[str, str]]:
        """A MuJoCo plane on the surface (a 2-D half-plane: a wall ``height`` tall's middle).

        MuJoCo planes are static: the geom belongs in the world body.
        """
        normal = np.append(self.normal, 0.0) if self.n_dims == 2 else self.normal
        centre = self.surface_point
        if self.n_dims == 2:
            centre = np.append(centre, 0.5 * float(height))
        helper = np.eye(3)[int(np.argmin(np.abs(normal)))]
        u = np.cross(normal, helper)
        u /= np.linalg.norm(u)
        x, y, z, w = (
            float(v)
            for v in quaternion_from_matrix(np.column_stack([u, np.cross(normal, u), normal]))
        )
        return centre, {"type": "plane", "size": "0 0 1", "quat": f"{w!r} {x!r} {y!r} {z!r}"}

    def transformed(self, factor: float, flip: np.ndarray) -> HalfSpace:
        flip = np.asarray(flip, dtype=np.float64)
        region = None
        if self.region is not None:
            region = (factor * flip * self.region[0], factor * flip * self.region[1])
        return HalfSpace(
            self.label,
            factor * flip * self.position,
            factor * self.radius,
            flip * self.normal,
            region=region,
        )

    @classmethod
    def from_fields(
        cls, label: str, position: Any, radius: float, fields: Mapping[str, Any]
    ) -> HalfSpace:
        if "normal" not in fields:
            raise ValueError(
                f"normal: a half-space needs the normal of its plane, towards the free side "
                f"({label!r})"
            )
        return cls(label, position, radius, fields["normal"])


register_shape(HalfSpace)


def _read_only(array: np.ndarray) -> np.ndarray:
    array = np.array(array, dtype=np.float64)
    array.setflags(write=False)
    return array
