"""Seeded synthetic demonstration sets with a known ground truth (mimicking layer).

The thesis's data sets are not public, so each example is regenerated here from
an explicit *nominal* path: demonstrations are produced as perturbations of the
nominal, which is therefore the exact answer a generalized-path estimator
should recover (up to the finite number of demonstrations). Every generator
returns a :class:`DemoSet`.

Conventions
-----------
* Every random draw comes from ``numpy.random.Generator`` built by
  :func:`lfdkit.core.validation.check_random_state` from ``seed`` (``None``, an
  ``int`` or a ``Generator``); the same integer seed gives bit-identical arrays.
* Nominal curves are first built on a fine polyline (``4001`` points equally
  spaced in arc length, far finer than any demonstration); demonstrations are
  offsets of that fine polyline along its vertex normals
  (:func:`lfdkit.core.geometry.left_normals` in 2-D; in 3-D the planar da Vinci
  nominal's wall normal and in-plane normal), and are then resampled. The
  ``nominal`` returned in the :class:`DemoSet` is the same fine curve
  resampled to ``500`` points (its chord error is below ``1e-4`` of the noise).
* "Smooth" random deviations are sums of three sinusoids of the normalised arc
  length ``u in [0, 1]`` with random frequencies, phases and amplitudes, scaled
  so that their standard deviation over ``u`` is about the requested value.
  Their expected value is zero for every ``u``, so the nominal is the mean path.
* 2-D "band" examples (``noisy_band`` and the hard cases) share one S-shaped
  nominal: ``y = 1.5 sin(2 pi x / 10)``, ``x in [0, 10]`` m (length about
  11.9 m, smallest radius of curvature about 1.7 m).
* The closed and nearly closed shapes (:data:`CLOSED_DATASETS`: a circle, an
  "o", a figure-eight, a letter "a") are handwriting-sized, in millimetres,
  with 7 demonstrations each by default, like LASA's. The closed ones
  (circle, figure-eight) use *periodic* smooth offsets (whole numbers of
  cycles per turn) along periodic normals, so each demonstration starts and
  ends at exactly the same point.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from lfdkit.core.geometry import (
    arc_length,
    left_normals,
    point_tangents,
    resample,
    resample_between,
)
from lfdkit.core.units import check_units
from lfdkit.core.validation import check_demos, check_path, check_positive, check_random_state
from lfdkit.datasets._shared import SizedDemoSet, check_count_at_least, generate, smooth_offset

__all__ = [
    "CLOSED_DATASETS",
    "MIMIC_DATASETS",
    "RESIDUAL_SHAPES",
    "DemoSet",
    "Residual",
    "closed_circle",
    "da_vinci_walls",
    "deburring_circular",
    "deburring_linear",
    "different_extents",
    "draw_residuals",
    "figure_eight",
    "letter_a",
    "load_dataset",
    "local_detours",
    "loops",
    "nearly_closed_o",
    "noisy_band",
    "quasi_circular_band",
    "residual_profile",
    "uneven_sampling",
    "walking_corridor",
]

#: Points of the ground-truth ``nominal`` returned in every :class:`DemoSet`.
_N_NOMINAL = 500
#: Points of the fine construction polyline (nominal and offset curves).
_N_FINE = 4001
_TWO_PI = 2.0 * np.pi


# --------------------------------------------------------------------- data model
@dataclass(frozen=True, eq=False)
class DemoSet(SizedDemoSet):
    """A set of demonstrations with the ground-truth path they were generated around.

    Attributes
    ----------
    name : str
        Short name of the generator (a key of :data:`MIMIC_DATASETS`).
    demos : list of ndarray, each shape (n_j, q)
        The demonstrations, float64; lengths ``n_j`` may differ.
    nominal : ndarray, shape (M, q)
        Ground-truth generalized path, densely sampled (``M = 500`` for every
        generator here), running in the same direction as the demonstrations.
    units : str
        Unit of every coordinate, one of :data:`lfdkit.core.units.UNITS` (the
        generators here use ``"m"`` or ``"mm"``).
    material_side : int or None
        2-D deburring only: ``+1`` if the workpiece material lies on the left of
        ``nominal`` with respect to its direction of travel (the side of
        :func:`lfdkit.core.geometry.left_normals`), ``-1`` if on the right; ``None``
        for every other set.
    walls : tuple of ndarray, each shape (n_w, q)
        Polylines of environment constraints, for drawing and checks; may be empty.
    description : str
        How the set was made and what its ground truth is.

    Notes
    -----
    Equality is identity (``eq=False``): comparing arrays field by field would be
    ambiguous. The arrays themselves are not write-protected.
    """

    name: str
    demos: list[np.ndarray]
    nominal: np.ndarray
    units: str
    material_side: int | None = None
    walls: tuple[np.ndarray, ...] = ()
    description: str = ""

    def __post_init__(self) -> None:
        demos = check_demos(self.demos, "demos")
        q = demos[0].shape[1]
        nominal = check_path(self.nominal, "nominal", n_dims=q)
        check_units(self.units)
        if self.material_side not in (None, 1, -1):
            raise ValueError(f"material_side: expected +1, -1 or None, got {self.material_side!r}")
        if self.material_side is not None and q != 2:
            raise ValueError(f"material_side: defined for 2-D sets only, got {q} dimensions")
        walls = tuple(check_path(w, f"walls[{i}]", n_dims=q) for i, w in enumerate(self.walls))
        object.__setattr__(self, "demos", demos)
        object.__setattr__(self, "nominal", nominal)
        object.__setattr__(self, "walls", walls)
        if self.material_side is not None:
            object.__setattr__(self, "material_side", int(self.material_side))


# --------------------------------------------------------------------- helpers
def _fine(curve: np.ndarray) -> np.ndarray:
    """Resample a dense analytic polyline to the fine construction resolution."""
    return resample(curve, _N_FINE)


def _s_curve() -> np.ndarray:
    """Fine S-shaped nominal of the 2-D band examples, shape ``(_N_FINE, 2)``, metres."""
    x = np.linspace(0.0, 10.0, 20001)
    return _fine(np.column_stack((x, 1.5 * np.sin(_TWO_PI * x / 10.0))))


def _interp_at(path: np.ndarray, s_path: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points of the polyline ``path`` (vertex arc positions ``s_path``) at positions ``s``."""
    return np.column_stack([np.interp(s, s_path, path[:, k]) for k in range(path.shape[1])])


def _cut(path: np.ndarray, s_path: np.ndarray, s0: float, s1: float) -> np.ndarray:
    """Stretch of ``path`` between parameter values ``s0 < s1`` (vertices plus exact ends)."""
    inside = (s_path > s0) & (s_path < s1)
    ends = _interp_at(path, s_path, np.array([s0, s1]))
    return np.vstack((ends[:1], path[inside], ends[1:]))


def _arc(fine: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Arc length along ``fine`` and its normalised form ``u in [0, 1]``."""
    s = arc_length(fine)
    return s, s / s[-1]


def _ramp(x: np.ndarray) -> np.ndarray:
    """Smooth step from 0 (``x <= 0``) to 1 (``x >= 1``), ``3x² − 2x³`` between."""
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


class _Band(NamedTuple):
    """A 2-D band set in the making: the fine nominal, its frame and the random draws.

    ``offsets[j]`` is demonstration ``j``'s smooth normal offset (sd ``noise``)
    and ``white[j]`` its white noise (sd ``0.05 noise``), drawn in that order.
    """

    fine: np.ndarray
    normals: np.ndarray
    s: np.ndarray
    n_points: int
    offsets: list[np.ndarray]
    white: list[np.ndarray]

    @classmethod
    def draw(
        cls, rng: np.random.Generator, fine: np.ndarray, n_demos: int, n_points: int, noise: float
    ) -> _Band:
        s, u = _arc(fine)
        offsets = [smooth_offset(rng, u, noise) for _ in range(n_demos)]
        white = [rng.normal(0.0, 0.05 * noise, (n_points, 2)) for _ in range(n_demos)]
        return cls(fine, left_normals(fine), s, n_points, offsets, white)

    def paths(self) -> list[np.ndarray]:
        """The fine nominal moved along its normals by each offset."""
        return [self.fine + o[:, None] * self.normals for o in self.offsets]

    def demos(self, paths: list[np.ndarray] | None = None) -> list[np.ndarray]:
        """Each path (default :meth:`paths`) resampled to ``n_points`` points, plus its noise."""
        paths = self.paths() if paths is None else paths
        return [resample(p, self.n_points) + w for p, w in zip(paths, self.white, strict=True)]


def _demo_set(
    name: str, demos: list[np.ndarray], fine: np.ndarray, units: str, description: str, **more: Any
) -> DemoSet:
    """The :class:`DemoSet` whose ground truth is the fine nominal, resampled to 500 points."""
    nominal = resample(fine, _N_NOMINAL)
    return DemoSet(name, demos, nominal, units, description=description, **more)


def _at_most(count: Any, name: str, n_demos: int) -> int:
    """How many of the ``n_demos`` demonstrations get a feature: 0 to ``n_demos``."""
    count = check_count_at_least(count, name, 0)
    if count > n_demos:
        raise ValueError(f"{name}: must be <= n_demos ({n_demos}), got {count}")
    return count


def _noise_below(noise: float, size: float, name: str, divisor: int) -> None:
    """Refuse a noise that could fold the shape: it must stay below ``size / divisor``."""
    if noise * divisor >= size:
        raise ValueError(
            f"noise: must be smaller than {name} / {divisor} ({size / divisor:g}), got {noise}"
        )


def _check_band(
    n_demos: Any, n_points: Any, noise: Any, noise_zero: bool = True
) -> tuple[int, int, float]:
    return (
        check_count_at_least(n_demos, "n_demos"),
        check_count_at_least(n_points, "n_points", 2),
        check_positive(noise, "noise", allow_zero=noise_zero),
    )


# --------------------------------------------------------------------- chapter 4
def quasi_circular_band(n_points: int = 100, offset: float = 0.6, seed: Any = None) -> DemoSet:
    """Two paths at uniform normal offsets around a quasi-circular nominal (thesis Fig 4.5).

    The nominal is ``r(theta) = 5 (1 + 0.08 sin 3 theta)`` m for ``theta`` from 0
    to 300 degrees (counter-clockwise, open). Demonstration 0 lies at ``+offset``
    along the nominal's left normal (inside), demonstration 1 at ``-offset``
    (outside); each is resampled to ``n_points`` points equally spaced in arc
    length, then every point is moved along the demonstration's own normal by an
    independent Gaussian jitter of sd ``0.01 * offset``.

    Parameters
    ----------
    n_points : int
        Points per demonstration (the thesis uses M = 100).
    offset : float
        Normal offset of the two demonstrations, metres (smaller than the
        smallest radius of curvature, about 3 m).
    seed : None, int or numpy.random.Generator
        Source of the jitter.

    Returns
    -------
    DemoSet
        Two demonstrations of shape ``(n_points, 2)`` in metres; ``nominal`` of
        shape ``(500, 2)``.
    """
    n_points = check_count_at_least(n_points, "n_points", 2)
    offset = check_positive(offset, "offset")
    rng = check_random_state(seed)
    theta = np.linspace(0.0, 5.0 * np.pi / 3.0, 20001)
    r = 5.0 * (1.0 + 0.08 * np.sin(3.0 * theta))
    fine = _fine(np.column_stack((r * np.cos(theta), r * np.sin(theta))))
    normals = left_normals(fine)
    jitter_sd = 0.01 * offset
    demos = []
    for sign in (1.0, -1.0):
        demo = resample(fine + sign * offset * normals, n_points)
        demo = demo + rng.normal(0.0, jitter_sd, n_points)[:, None] * left_normals(demo)
        demos.append(demo)
    return _demo_set(
        "quasi_circular",
        demos,
        fine,
        "m",
        "Thesis Fig 4.5: nominal r = 5(1 + 0.08 sin 3θ) m, θ in [0°, 300°]; two demos at "
        f"normal offsets ±{offset:g} m with jitter sd {jitter_sd:g} m along the normal, "
        f"{n_points} points each. Ground truth: the nominal.",
    )


def noisy_band(
    n_demos: int = 10, n_points: int = 100, noise: float = 0.15, seed: Any = None
) -> DemoSet:
    """Demonstrations scattered smoothly around an S-shaped 2-D nominal.

    Each demonstration is the nominal offset along its normal by a smooth random
    function (three sinusoids of 0.5-2.5 cycles per path length, sd about
    ``noise``), resampled to ``n_points`` points equally spaced in arc length,
    plus isotropic white noise of sd ``0.05 * noise`` at every point.

    Parameters
    ----------
    n_demos : int
    n_points : int
        Points per demonstration.
    noise : float
        Standard deviation of the smooth normal offset, metres.
    seed : None, int or numpy.random.Generator

    Returns
    -------
    DemoSet
        ``n_demos`` arrays of shape ``(n_points, 2)`` in metres; ``nominal`` of
        shape ``(500, 2)`` (the S-curve ``y = 1.5 sin(2π x / 10)``, ``x`` from 0 to 10).
    """
    n_demos, n_points, noise = _check_band(n_demos, n_points, noise)
    band = _Band.draw(check_random_state(seed), _s_curve(), n_demos, n_points, noise)
    return _demo_set(
        "noisy_band",
        band.demos(),
        band.fine,
        "m",
        f"S-shaped nominal; {n_demos} demos = smooth normal offsets (sd ≈ {noise:g} m) "
        f"+ white noise (sd {0.05 * noise:g} m), {n_points} points each. "
        "Ground truth: the nominal.",
    )


def walking_corridor(n_demos: int = 30, seed: Any = None, *, n_volunteers: int = 5) -> DemoSet:
    """Human walking paths from circle A along a corridor into a room to circle B (Fig 4.7).

    Geometry (metres): the corridor runs along ``x`` with walls at ``y = ±0.9``
    (1.8 m wide) from ``x = -1`` to ``x = 8.5``; the room spans
    ``x in [4.5, 8.5]``, ``y in [0.9, 5]`` and opens on the corridor through a
    door ``x in [5.8, 7.6]`` in the wall ``y = 0.9``. The nominal (the centre
    line) goes straight from A = (0, 0) to (5.5, 0), turns left on a 1.2 m
    radius arc to (6.7, 1.2), and goes straight to B = (6.7, 4); length
    about 10.2 m.

    Demonstration ``j`` belongs to volunteer ``j * n_volunteers // n_demos``
    (5 volunteers x 6 trials by default). It is the nominal plus, along its
    normal, the volunteer's smooth bias (sd 0.10 m, 0.3-1.5 cycles per path)
    and the trial's smooth deviation (sd 0.06 m, 0.5-3 cycles), both tapered
    to zero over the first and last 15 % of the path; plus a start displacement
    and a goal displacement, uniform in discs of radius 0.3 m around A and B and
    blended out over the first / last 20 %; resampled to 90-110 points
    (random per demo) equally spaced in arc length; plus white noise of sd
    0.01 m. The smooth parts are bounded, so every demo stays more than 0.15 m
    from every wall (0.4 m in practice) unless the white noise exceeds 10 sd.

    Parameters
    ----------
    n_demos : int
    seed : None, int or numpy.random.Generator
    n_volunteers : int
        Number of demonstrators, each with a personal bias.

    Returns
    -------
    DemoSet
        Demonstrations of shape ``(n_j, 2)``, ``90 <= n_j <= 110``, metres;
        ``nominal`` of shape ``(500, 2)`` from A to B; ``walls`` the three wall
        polylines.
    """
    n_demos = check_count_at_least(n_demos, "n_demos")
    n_volunteers = check_count_at_least(n_volunteers, "n_volunteers")
    rng = check_random_state(seed)
    # Centre line: straight, quarter turn to the left, straight.
    phi = np.linspace(-np.pi / 2.0, 0.0, 2001)
    centre = np.vstack(
        (
            np.column_stack((np.linspace(0.0, 5.5, 5001), np.zeros(5001))),
            np.column_stack((5.5 + 1.2 * np.cos(phi), 1.2 + 1.2 * np.sin(phi)))[1:],
            np.column_stack((np.full(3001, 6.7), np.linspace(1.2, 4.0, 3001)))[1:],
        )
    )
    fine = _fine(centre)
    normals = left_normals(fine)
    u = _arc(fine)[1]
    taper = _ramp(u / 0.15) * _ramp((1.0 - u) / 0.15)
    w_start, w_goal = 1.0 - _ramp(u / 0.2), 1.0 - _ramp((1.0 - u) / 0.2)

    def in_disc(radius: float) -> np.ndarray:
        r, ang = radius * np.sqrt(rng.random()), rng.uniform(0.0, _TWO_PI)
        return np.array([r * np.cos(ang), r * np.sin(ang)])

    biases = [smooth_offset(rng, u, 0.10, freq=(0.3, 1.5)) for _ in range(n_volunteers)]
    demos = []
    for j in range(n_demos):
        trial = smooth_offset(rng, u, 0.06, freq=(0.5, 3.0))
        d_start, d_goal = in_disc(0.3), in_disc(0.3)
        n_j = int(rng.integers(90, 111))
        bias = biases[j * n_volunteers // n_demos]
        path = (
            fine
            + (taper * (bias + trial))[:, None] * normals
            + w_start[:, None] * d_start
            + w_goal[:, None] * d_goal
        )
        demos.append(resample(path, n_j) + rng.normal(0.0, 0.01, (n_j, 2)))
    walls = (
        np.array([[-1.0, -0.9], [8.5, -0.9], [8.5, 5.0], [4.5, 5.0], [4.5, 0.9]]),
        np.array([[-1.0, 0.9], [5.8, 0.9]]),
        np.array([[7.6, 0.9], [8.5, 0.9]]),
    )
    return _demo_set(
        "walking",
        demos,
        fine,
        "m",
        f"Thesis Fig 4.7: {n_demos} walking paths by {n_volunteers} volunteers from circle A "
        "(0, 0) along a 1.8 m corridor and through a door to circle B (6.7, 4) in a room "
        "(radius 0.3 m). Ground truth: the corridor centre line from A to B.",
        walls=walls,
    )


#: Transport height of the da Vinci pick-and-place nominal (thesis Fig 4.10, §6.3), metres.
DA_VINCI_TOP = 0.035
_DA_VINCI_WALL_Y = 0.025  # the walls are the planes y = ±0.025 m


def da_vinci_polyline() -> np.ndarray:
    """The dense 3-D nominal of the da Vinci pick-and-place, before resampling (metres).

    In the plane ``y = 0``: from (0, 0, 0) up to z = 0.02, a 0.015 m radius
    corner, along ``x`` at the transport height :data:`DA_VINCI_TOP`, a corner
    down and down to (0.1, 0, 0.005); about 0.152 m long.
    """
    rad, top = 0.015, DA_VINCI_TOP
    a1 = np.linspace(np.pi, np.pi / 2.0, 2001)
    a2 = np.linspace(np.pi / 2.0, 0.0, 2001)
    xz = np.vstack(
        (
            np.column_stack((np.zeros(2001), np.linspace(0.0, top - rad, 2001))),
            np.column_stack((rad + rad * np.cos(a1), top - rad + rad * np.sin(a1)))[1:],
            np.column_stack((np.linspace(rad, 0.1 - rad, 5001), np.full(5001, top)))[1:],
            np.column_stack((0.1 - rad + rad * np.cos(a2), top - rad + rad * np.sin(a2)))[1:],
            np.column_stack((np.full(2001, 0.1), np.linspace(top - rad, 0.005, 2001)))[1:],
        )
    )
    return np.column_stack((xz[:, 0], np.zeros(len(xz)), xz[:, 1]))


def da_vinci_wall_outlines() -> tuple[np.ndarray, ...]:
    """The da Vinci walls, the planes ``y = ±0.025`` m, as closed rectangles of shape (5, 3).

    ``x`` in [-0.02, 0.12], ``z`` in [-0.01, 0.06] (metres), for drawing and checks.
    """
    return tuple(
        np.array(
            [
                [-0.02, y, -0.01],
                [0.12, y, -0.01],
                [0.12, y, 0.06],
                [-0.02, y, 0.06],
                [-0.02, y, -0.01],
            ]
        )
        for y in (-_DA_VINCI_WALL_Y, _DA_VINCI_WALL_Y)
    )


def da_vinci_walls(n_demos: int = 4, seed: Any = None, *, noise: float = 0.002) -> DemoSet:
    """3-D pick-and-place between two parallel walls (thesis Fig 4.10, da Vinci robot).

    Nominal (metres, in the plane ``y = 0``): from ``z_I`` = (0, 0, 0) lift
    vertically to z = 0.02, round a 0.015 m radius corner, travel along ``x`` at
    z = 0.035, round a corner down and lower vertically to ``z_G`` = (0.1, 0,
    0.005); length about 0.152 m. Walls: the planes ``y = ±0.025``, drawn as
    closed rectangles ``x in [-0.02, 0.12]``, ``z in [-0.01, 0.06]``.

    Each demonstration is the nominal displaced in its normal plane by two
    smooth random functions (sd ``noise`` each, 0.5-3 cycles per path),
    resampled to 90-110 points (random per demo) and perturbed by white noise
    of sd ``0.1 * noise``.

    Parameters
    ----------
    n_demos : int
    seed : None, int or numpy.random.Generator
    noise : float
        Standard deviation of each smooth normal component, metres.

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_j, 3)`` in metres; ``nominal`` of shape
        ``(500, 3)``; ``walls`` two closed 3-D rectangles of shape ``(5, 3)``.
    """
    n_demos = check_count_at_least(n_demos, "n_demos")
    noise = check_positive(noise, "noise", allow_zero=True)
    rng = check_random_state(seed)
    fine = _fine(da_vinci_polyline())
    # The nominal is planar: its normal plane is spanned by the wall normal (y axis)
    # and the in-plane normal (tangent × y axis), an exact parallel-transported frame.
    tangents = point_tangents(fine)
    n_wall = np.broadcast_to(np.array([0.0, 1.0, 0.0]), tangents.shape)
    n_plane = np.cross(tangents, n_wall)
    u = _arc(fine)[1]
    demos = []
    for _ in range(n_demos):
        o1 = smooth_offset(rng, u, noise, freq=(0.5, 3.0))
        o2 = smooth_offset(rng, u, noise, freq=(0.5, 3.0))
        n_j = int(rng.integers(90, 111))
        path = fine + o1[:, None] * n_wall + o2[:, None] * n_plane
        demos.append(resample(path, n_j) + rng.normal(0.0, 0.1 * noise, (n_j, 3)))
    return _demo_set(
        "da_vinci",
        demos,
        fine,
        "m",
        f"Thesis Fig 4.10: {n_demos} 3-D pick-and-place paths from z_I (0, 0, 0) up, along x "
        "between walls y = ±0.025 m and down to z_G (0.1, 0, 0.005); smooth normal "
        f"deviations sd {noise:g} m per normal direction. Ground truth: the nominal.",
        walls=da_vinci_wall_outlines(),
    )


# --------------------------------------------------------------------- deburring (§6.2)
#: Names of the seven deburring residual shapes (thesis Fig 6.2).
RESIDUAL_SHAPES: tuple[str, ...] = (
    "triangle",
    "rectangle",
    "half_disc",
    "trapezoid",
    "saw_tooth",
    "double_bump",
    "ramp",
)


def residual_profile(shape: str, u: Any) -> np.ndarray:
    """Height of a deburring residual as a fraction of its peak height.

    Parameters
    ----------
    shape : str
        One of :data:`RESIDUAL_SHAPES`:

        * ``"triangle"``: symmetric peak ``1 - |2u - 1|``;
        * ``"rectangle"``: flat top with steep flanks (5 % of the width each);
        * ``"half_disc"``: ``sqrt(1 - (2u - 1)**2)`` (a half-ellipse once scaled);
        * ``"trapezoid"``: flanks of 30 % of the width each;
        * ``"saw_tooth"``: three teeth, each rising over 80 % and falling over 20 %;
        * ``"double_bump"``: ``sin(2 pi u)**2``, two humps of full height;
        * ``"ramp"``: rises over 80 % of the width, drops over the last 20 %.
    u : array_like
        Position across the residual, 0 at its start and 1 at its end.

    Returns
    -------
    ndarray, same shape as ``u``
        Values in ``[0, 1]``; 0 at ``u = 0``, at ``u = 1`` and outside ``[0, 1]``.

    Raises
    ------
    ValueError
        If ``shape`` is not one of :data:`RESIDUAL_SHAPES`.
    """
    u = np.asarray(u, dtype=np.float64)
    inside = (u > 0.0) & (u < 1.0)
    v = np.clip(u, 0.0, 1.0)
    if shape == "triangle":
        h = 1.0 - np.abs(2.0 * v - 1.0)
    elif shape == "rectangle":
        h = np.minimum(1.0, np.minimum(v, 1.0 - v) / 0.05)
    elif shape == "half_disc":
        h = np.sqrt(np.clip(1.0 - (2.0 * v - 1.0) ** 2, 0.0, 1.0))
    elif shape == "trapezoid":
        h = np.minimum(1.0, np.minimum(v, 1.0 - v) / 0.3)
    elif shape == "saw_tooth":
        w = np.mod(3.0 * v, 1.0)
        h = np.minimum(w / 0.8, (1.0 - w) / 0.2)
    elif shape == "double_bump":
        h = np.sin(_TWO_PI * v) ** 2
    elif shape == "ramp":
        h = np.minimum(v / 0.8, (1.0 - v) / 0.2)
    else:
        raise ValueError(f"shape: unknown residual shape {shape!r}; valid: {list(RESIDUAL_SHAPES)}")
    return np.where(inside, np.clip(h, 0.0, 1.0), 0.0)


@dataclass(frozen=True)
class Residual:
    """One deburring residual left on one demonstrated profile.

    Attributes
    ----------
    demo : int
        Index of the demonstration.
    segment : int
        Index of the profile segment holding the residual.
    shape : str
        One of :data:`RESIDUAL_SHAPES`.
    start : float
        Arc-length position of the residual's start along the nominal, mm.
    width : float
        Extent along the nominal, mm (the residual lies within its segment).
    height : float
        Peak height outwards from the nominal (away from the material), mm.
    """

    demo: int
    segment: int
    shape: str
    start: float
    width: float
    height: float


def draw_residuals(
    n_demos: int,
    n_segments: int,
    profile_length: float,
    p_residual: float = 0.3,
    seed: Any = None,
) -> list[list[Residual]]:
    """Draw which segments of which profiles carry a residual, and its shape and size.

    The profile is split into ``n_segments`` segments of equal length. For each
    demonstration and segment a uniform draw below ``p_residual`` adds a residual
    whose shape is uniform over :data:`RESIDUAL_SHAPES`, height uniform in
    [0.5, 2] mm, width uniform in [35 %, 90 %] of the segment length, placed
    uniformly inside the segment. The same number of draws is made whatever
    ``p_residual``, so changing it only toggles residuals on or off.

    Parameters
    ----------
    n_demos, n_segments : int
    profile_length : float
        Length of the nominal profile, mm.
    p_residual : float
        Probability that a segment carries a residual, in [0, 1].
    seed : None, int or numpy.random.Generator

    Returns
    -------
    list of list of Residual
        ``result[j]`` holds demonstration ``j``'s residuals, ordered by segment.
    """
    n_demos = check_count_at_least(n_demos, "n_demos")
    n_segments = check_count_at_least(n_segments, "n_segments")
    profile_length = check_positive(profile_length, "profile_length")
    p_residual = check_positive(p_residual, "p_residual", allow_zero=True)
    if p_residual > 1.0:
        raise ValueError(f"p_residual: must be <= 1, got {p_residual!r}")
    rng = check_random_state(seed)
    shape = (n_demos, n_segments)
    active = rng.random(shape) < p_residual
    kind = rng.integers(0, len(RESIDUAL_SHAPES), shape)
    width_frac = rng.uniform(0.35, 0.9, shape)
    place = rng.random(shape)
    height = rng.uniform(0.5, 2.0, shape)
    seg_len = profile_length / n_segments
    out: list[list[Residual]] = []
    for j in range(n_demos):
        row = []
        for i in np.flatnonzero(active[j]):
            width = width_frac[j, i] * seg_len
            start = i * seg_len + place[j, i] * (seg_len - width)
            row.append(
                Residual(
                    demo=j,
                    segment=int(i),
                    shape=RESIDUAL_SHAPES[kind[j, i]],
                    start=float(start),
                    width=float(width),
                    height=float(height[j, i]),
                )
            )
        out.append(row)
    return out


def _residual_height(residuals: list[Residual], s: np.ndarray) -> np.ndarray:
    """Summed residual height (mm) at arc positions ``s`` (mm) along the nominal."""
    h = np.zeros_like(s)
    for r in residuals:
        h += r.height * residual_profile(r.shape, (s - r.start) / r.width)
    return h


def _deburring(
    kind: str,
    n_demos: Any,
    n_points: Any,
    seed: Any,
    n_segments: Any,
    p_residual: Any,
    noise: Any,
) -> DemoSet:
    n_demos = check_count_at_least(n_demos, "n_demos")
    n_points = check_count_at_least(n_points, "n_points", 2)
    n_segments = check_count_at_least(n_segments, "n_segments")
    noise = check_positive(noise, "noise", allow_zero=True)
    rng = check_random_state(seed)
    radius = 50.0
    length = 200.0 if kind == "linear" else np.pi * radius
    residuals = draw_residuals(n_demos, n_segments, length, p_residual, seed=rng)
    s = np.linspace(0.0, length, n_points)
    s_nom = np.linspace(0.0, length, _N_NOMINAL)

    if kind == "linear":
        # Travel along +x, material below (on the right): outwards is +y.
        def place(s_: np.ndarray, h: np.ndarray) -> np.ndarray:
            return np.column_stack((s_, h))

        material_side = -1
        shape_txt = "straight line of length 200 mm along +x, material below (y < 0)"
    else:
        # Counter-clockwise half circle, material inside the disc (on the left): outwards
        # is the radial direction.
        def place(s_: np.ndarray, h: np.ndarray) -> np.ndarray:
            phi = s_ / radius
            return (radius + h)[:, None] * np.column_stack((np.cos(phi), np.sin(phi)))

        material_side = 1
        shape_txt = (
            "half circle of radius 50 mm centred at the origin, from angle 0 to 180° "
            "counter-clockwise, material inside the disc"
        )
    demos = []
    for res in residuals:
        demo = place(s, _residual_height(res, s))
        if noise > 0:
            demo = demo + rng.normal(0.0, noise, demo.shape)
        demos.append(demo)
    return DemoSet(
        name=f"deburring_{kind}",
        demos=demos,
        nominal=place(s_nom, np.zeros(_N_NOMINAL)),
        units="mm",
        material_side=material_side,
        description=(
            f"Thesis §6.2: {shape_txt}; {n_demos} profiles sampled at {n_points} points equally "
            f"spaced along the nominal, {n_segments} equal segments, each carrying a residual "
            f"with probability {p_residual:g} (7 shapes, height 0.5-2 mm, outwards only); "
            f"measurement noise sd {noise:g} mm. Residuals are those of draw_residuals with the "
            "same seed. Ground truth: the nominal profile."
        ),
    )


def deburring_linear(
    n_demos: int = 10,
    n_points: int = 500,
    seed: Any = None,
    *,
    n_segments: int = 10,
    p_residual: float = 0.3,
    noise: float = 0.0,
) -> DemoSet:
    """Linear deburred profiles with random residuals (thesis §6.2, Fig 6.3a).

    The nominal is the segment from (0, 0) to (200, 0) mm, travelled along +x; the
    workpiece material lies below it (``y < 0``, on the right:
    ``material_side = -1``). It is split into ``n_segments`` segments of equal
    length; residuals (:func:`draw_residuals`, called first on the same random
    generator) displace the profile only outwards (``+y``), so with ``noise = 0``
    every demonstration satisfies ``y >= 0``. Each profile is sampled at
    ``n_points`` points equally spaced in ``x`` (as a profilometer would).

    Parameters
    ----------
    n_demos : int
    n_points : int
        Samples per profile.
    seed : None, int or numpy.random.Generator
    n_segments : int
        Segments of equal length (20 mm each by default).
    p_residual : float
        Probability that a segment carries a residual.
    noise : float
        Optional isotropic Gaussian measurement noise, sd in mm (may put points
        on the material side).

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_points, 2)`` in mm; ``nominal`` of shape ``(500, 2)``.
    """
    return _deburring("linear", n_demos, n_points, seed, n_segments, p_residual, noise)


def deburring_circular(
    n_demos: int = 10,
    n_points: int = 500,
    seed: Any = None,
    *,
    n_segments: int = 10,
    p_residual: float = 0.3,
    noise: float = 0.0,
) -> DemoSet:
    """Circular deburred profiles with random residuals (thesis §6.2, Fig 6.3b).

    The nominal is the half circle of radius 50 mm centred at the origin, from
    (50, 0) counter-clockwise to (-50, 0) (length 50π ≈ 157 mm). The workpiece
    is the disc, on the left of the direction of travel (``material_side = +1``);
    residuals displace the profile radially outwards only, so with ``noise = 0``
    every point has radius ``>= 50`` mm. Profiles are sampled at ``n_points``
    points equally spaced in angle. Other parameters as in
    :func:`deburring_linear` (segments are 15.7 mm long by default).

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_points, 2)`` in mm; ``nominal`` of shape ``(500, 2)``.
    """
    return _deburring("circular", n_demos, n_points, seed, n_segments, p_residual, noise)


# --------------------------------------------------------------------- hard cases
def different_extents(
    n_demos: int = 10,
    seed: Any = None,
    *,
    n_points: int = 100,
    noise: float = 0.15,
) -> DemoSet:
    """Demonstrations that start and stop at different places along the task.

    Built like :func:`noisy_band` on the same S-shaped curve (length ``L``),
    but demonstration ``j`` covers only the stretch of the curve between
    arc-length positions ``s0_j ~ U[0, 0.15 L]`` and ``s1_j ~ U[0.85 L, L]``
    (its smooth offset is a function of the position along the full curve, so
    the stretches agree where they overlap).

    The ground-truth ``nominal`` covers the *consensus extent*: the S-curve from
    ``median(s0_j)`` to ``median(s1_j)``. Demonstrations therefore both overhang
    the nominal and fall short of it at either end.

    Parameters
    ----------
    n_demos : int
    seed : None, int or numpy.random.Generator
    n_points : int
        Points per demonstration (equally spaced in arc length).
    noise : float
        Standard deviation of the smooth normal offset, metres.

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_points, 2)`` in metres; ``nominal`` of shape ``(500, 2)``.
    """
    n_demos, n_points, noise = _check_band(n_demos, n_points, noise)
    rng = check_random_state(seed)
    fine = _s_curve()
    normals = left_normals(fine)
    s_fine, u = _arc(fine)
    length = s_fine[-1]
    demos, starts, ends = [], [], []
    for _ in range(n_demos):
        s0 = rng.uniform(0.0, 0.15 * length)
        s1 = rng.uniform(0.85 * length, length)
        offset = smooth_offset(rng, u, noise)
        white = rng.normal(0.0, 0.05 * noise, (n_points, 2))
        piece = _cut(fine + offset[:, None] * normals, s_fine, s0, s1)
        demos.append(resample(piece, n_points) + white)
        starts.append(s0)
        ends.append(s1)
    s_start, s_end = float(np.median(starts)), float(np.median(ends))
    return DemoSet(
        name="different_extents",
        demos=demos,
        nominal=resample_between(fine, s_start, s_end, _N_NOMINAL),
        units="m",
        description=(
            f"S-shaped band, {n_demos} demos each covering [s0, s1] with s0 ~ U[0, 15 %] and "
            f"s1 ~ U[85 %, 100 %] of the length; smooth normal offsets sd ≈ {noise:g} m. "
            f"Ground truth: the S-curve from the median start ({s_start:.3f} m) to the median "
            f"end ({s_end:.3f} m) arc-length position."
        ),
    )


def local_detours(
    n_demos: int = 10,
    n_detours: int = 2,
    seed: Any = None,
    *,
    n_points: int = 100,
    noise: float = 0.02,
    detour_height: float = 0.75,
) -> DemoSet:
    """A :func:`noisy_band` set in which ``n_detours`` demonstrators swerve once.

    The base set is exactly ``noisy_band(n_demos, n_points, noise, seed)`` (same
    random draws, made first). Then ``n_detours`` distinct demonstrations are
    picked at random and each gets one raised-cosine bump added to its normal
    offset: support width 8 % of the length, centred uniformly in [20 %, 80 %]
    of it, height ``detour_height`` to a random side. The defaults describe a
    consistent demonstrator (2 cm smooth spread, as in kinesthetic teaching)
    who once swerves 0.75 m around something: the detour, not the noise,
    dominates the error. The other demonstrations are
    bit-identical to the base set's. The ground truth stays the nominal: a
    detour is an outlier, not part of the task.

    Parameters
    ----------
    n_demos : int
    n_detours : int
        Number of swerving demonstrations, ``0 <= n_detours <= n_demos``.
    seed : None, int or numpy.random.Generator
    n_points : int
    noise : float
        Standard deviation of the smooth normal offset, metres (> 0).
    detour_height : float
        Peak normal displacement of each swerve, metres (> 0).

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_points, 2)`` in metres; ``nominal`` of shape ``(500, 2)``.
    """
    n_demos, n_points, noise = _check_band(n_demos, n_points, noise, noise_zero=False)
    n_detours = _at_most(n_detours, "n_detours", n_demos)
    detour_height = check_positive(detour_height, "detour_height")
    rng = check_random_state(seed)
    band = _Band.draw(rng, _s_curve(), n_demos, n_points, noise)
    length = band.s[-1]
    chosen = np.sort(rng.choice(n_demos, size=n_detours, replace=False))
    width = 0.08 * length
    for j in chosen:
        centre = rng.uniform(0.2 * length, 0.8 * length)
        sign = 1.0 if rng.random() < 0.5 else -1.0
        x = (band.s - centre) / width
        bump = np.where(np.abs(x) < 0.5, 0.5 * (1.0 + np.cos(_TWO_PI * x)), 0.0)
        band.offsets[j] = band.offsets[j] + sign * detour_height * bump
    return _demo_set(
        "local_detours",
        band.demos(),
        band.fine,
        "m",
        f"noisy_band with {n_detours} of {n_demos} demos (indices {chosen.tolist()}) swerving "
        f"once: a bump of width 8 % of the length and height {detour_height:g} m. "
        "Ground truth: the nominal.",
    )


def uneven_sampling(
    n_demos: int = 10,
    seed: Any = None,
    *,
    noise: float = 0.15,
    points_range: tuple[int, int] = (60, 160),
    speed_ratio: float = 40.0,
) -> DemoSet:
    """A band whose demonstrations are sampled at very uneven speed.

    Geometry as in :func:`noisy_band` (smooth normal offsets of sd ``noise`` on
    the S-curve). Demonstration ``j`` has ``n_j`` points, uniform in
    ``points_range``; the spacing between consecutive samples along its arc
    length follows ``exp(c sin(2 pi f tau + phi))`` over the sample index
    ``tau in [0, 1]``, with ``c = ln(speed_ratio) / 2``, ``f ~ U[1, 2.5]`` cycles
    and a random phase: the demonstrator dwells (dense samples) in some parts
    and hurries (sparse samples) in others, so the largest to smallest spacing
    ratio within each demonstration is close to ``speed_ratio`` (at least 20
    with the defaults). No white noise is added, so the spacing is exactly the
    designed one.

    Parameters
    ----------
    n_demos : int
    seed : None, int or numpy.random.Generator
    noise : float
        Standard deviation of the smooth normal offset, metres.
    points_range : (int, int)
        Inclusive bounds on the number of points per demonstration.
    speed_ratio : float
        Ratio of the fastest to the slowest sampling speed, ``> 1``.

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_j, 2)`` in metres; ``nominal`` of shape ``(500, 2)``.
    """
    n_demos = check_count_at_least(n_demos, "n_demos")
    noise = check_positive(noise, "noise", allow_zero=True)
    lo, hi = (check_count_at_least(v, "points_range", 2) for v in points_range)
    if lo > hi:
        raise ValueError(f"points_range: expected (low, high) with low <= high, got {points_range}")
    speed_ratio = check_positive(speed_ratio, "speed_ratio")
    if speed_ratio <= 1.0:
        raise ValueError(f"speed_ratio: must be > 1, got {speed_ratio!r}")
    rng = check_random_state(seed)
    fine = _s_curve()
    normals = left_normals(fine)
    u = _arc(fine)[1]
    c = 0.5 * np.log(speed_ratio)
    demos = []
    for _ in range(n_demos):
        path = fine + smooth_offset(rng, u, noise)[:, None] * normals
        n_j = int(rng.integers(lo, hi + 1))
        f = rng.uniform(1.0, 2.5)
        phase = rng.uniform(0.0, _TWO_PI)
        tau = (np.arange(n_j - 1) + 0.5) / (n_j - 1)
        spacing = np.exp(c * np.sin(_TWO_PI * f * tau + phase))
        s_path = arc_length(path)
        s = np.concatenate(([0.0], np.cumsum(spacing)))
        s *= s_path[-1] / s[-1]
        demo = _interp_at(path, s_path, s)
        demo[-1] = path[-1]
        demos.append(demo)
    return _demo_set(
        "uneven_sampling",
        demos,
        fine,
        "m",
        f"S-shaped band, {n_demos} demos with smooth normal offsets sd ≈ {noise:g} m, "
        f"{lo}-{hi} points each, sampled with a speed ratio of {speed_ratio:g} between "
        "fast and slow parts. Ground truth: the nominal.",
    )


def loops(
    n_demos: int = 10,
    n_loops: int = 2,
    seed: Any = None,
    *,
    n_points: int = 100,
    noise: float = 0.15,
) -> DemoSet:
    """A :func:`noisy_band` set in which ``n_loops`` demonstrations make a small loop.

    The base set is exactly ``noisy_band(n_demos, n_points, noise, seed)`` (same
    random draws, made first). Then ``n_loops`` distinct demonstrations are picked
    at random; in each, the stretch of length ``pi R`` (``R = 3 * noise``) centred
    at a position uniform in [40 %, 60 %] of the length is replaced by a curl
    ``p(s) + R sin(2 pi tau) t(s) + sigma R (1 - cos(2 pi tau)) n(s)``
    (``tau`` from 0 to 1 over the stretch, ``t``, ``n`` the offset curve's tangent
    and left normal, ``sigma = ±1`` a random side): a closed loop of radius
    about ``R`` whose path genuinely crosses itself, joined with a continuous
    tangent. The ground truth stays the nominal.

    Parameters
    ----------
    n_demos : int
    n_loops : int
        Number of looping demonstrations, ``0 <= n_loops <= n_demos``.
    seed : None, int or numpy.random.Generator
    n_points : int
        Points per demonstration, equally spaced in arc length (the loop adds
        length, so looping demonstrations are sampled a little more coarsely).
    noise : float
        Standard deviation of the smooth normal offset, metres (> 0).

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_points, 2)`` in metres; ``nominal`` of shape ``(500, 2)``.
    """
    n_demos, n_points, noise = _check_band(n_demos, n_points, noise, noise_zero=False)
    n_loops = _at_most(n_loops, "n_loops", n_demos)
    rng = check_random_state(seed)
    band = _Band.draw(rng, _s_curve(), n_demos, n_points, noise)
    length = band.s[-1]
    chosen = np.sort(rng.choice(n_demos, size=n_loops, replace=False))
    radius = 3.0 * noise
    span = np.pi * radius
    paths = band.paths()
    for j in chosen:
        centre = rng.uniform(0.4 * length, 0.6 * length)
        side = 1.0 if rng.random() < 0.5 else -1.0
        path = paths[j]
        tau = np.clip((band.s - (centre - 0.5 * span)) / span, 0.0, 1.0)
        along = radius * np.sin(_TWO_PI * tau)
        across = side * radius * (1.0 - np.cos(_TWO_PI * tau))
        paths[j] = (
            path + along[:, None] * point_tangents(path) + across[:, None] * left_normals(path)
        )
    return _demo_set(
        "loops",
        band.demos(paths),
        band.fine,
        "m",
        f"noisy_band with {n_loops} of {n_demos} demos (indices {chosen.tolist()}) making a "
        f"closed self-crossing loop of radius ≈ {radius:g} m near mid-path. "
        "Ground truth: the nominal.",
    )


# --------------------------------------------------------------------- closed shapes
# Handwriting-sized shapes in millimetres (like LASA), drawn once: a closed circle,
# a nearly closed "o", a figure-eight and a letter "a" whose bowl comes back to its
# start before the down-stroke. Seven demonstrations each by default (as in LASA).


def _closed_normals(loop: np.ndarray) -> np.ndarray:
    """Unit left normals of a closed 2-D polyline (``loop[0] == loop[-1]``), periodic.

    The tangent at every vertex is the central difference with wrap-around, so
    the first and last normals are identical and an offset curve built with a
    periodic offset closes exactly.
    """
    body = loop[:-1]
    t = np.roll(body, -1, axis=0) - np.roll(body, 1, axis=0)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    n = np.column_stack((-t[:, 1], t[:, 0]))
    return np.vstack((n, n[:1]))


def _closed_demos(
    rng: np.random.Generator, fine: np.ndarray, n_demos: int, n_points: int, noise: float
) -> list[np.ndarray]:
    """Demonstrations of a closed nominal: periodic normal offsets, white noise, closed exactly.

    Each is the fine loop offset along its periodic normals by
    :func:`~lfdkit.datasets._shared.smooth_offset` with whole cycles (sd
    ``noise``, 1-4 cycles per loop), resampled to
    ``n_points`` points, plus white noise of sd ``0.05 noise``; its last point
    is then set equal to its first, so every demonstration starts and ends at
    exactly the same point.
    """
    normals = _closed_normals(fine)
    u = _arc(fine)[1]
    demos = []
    for _ in range(n_demos):
        offset = smooth_offset(rng, u, noise, (1, 4), whole_cycles=True)
        path = fine + offset[:, None] * normals
        path[-1] = path[0]
        demo = resample(path, n_points) + rng.normal(0.0, 0.05 * noise, (n_points, 2))
        demo[-1] = demo[0]
        demos.append(demo)
    return demos


def _closed_set(
    name: str,
    rng: np.random.Generator,
    fine: np.ndarray,
    n_demos: int,
    n_points: int,
    noise: float,
    description: str,
) -> DemoSet:
    """A closed data set in mm: the fine loop closed exactly, its demos and nominal."""
    fine[-1] = fine[0]
    nominal = resample(fine, _N_NOMINAL)
    nominal[-1] = nominal[0]
    return DemoSet(
        name=name,
        demos=_closed_demos(rng, fine, n_demos, n_points, noise),
        nominal=nominal,
        units="mm",
        description=description,
    )


def closed_circle(
    n_demos: int = 7,
    seed: Any = None,
    *,
    n_points: int = 200,
    radius: float = 20.0,
    noise: float = 1.0,
) -> DemoSet:
    """A full circle drawn once, counter-clockwise from the top: start = end.

    The nominal is the circle of radius ``radius`` mm centred at the origin,
    from (0, radius) counter-clockwise once round, back to (0, radius). Each
    demonstration is the circle offset radially by a smooth *periodic* random
    function (three sinusoids of 1-4 whole cycles per turn, sd about
    ``noise``), resampled to ``n_points`` points equally spaced in arc length,
    plus isotropic white noise of sd ``0.05 * noise``; its last point equals
    its first exactly (each demonstration is a closed curve, starting where
    the normal offset puts it on the top of the circle).

    Parameters
    ----------
    n_demos : int
    seed : None, int or numpy.random.Generator
    n_points : int
        Points per demonstration.
    radius : float
        Radius of the nominal circle, mm.
    noise : float
        Standard deviation of the smooth radial offset, mm (smaller than ``radius / 3``).

    Returns
    -------
    DemoSet
        ``n_demos`` arrays of shape ``(n_points, 2)`` in mm, each with
        ``demo[0] == demo[-1]``; ``nominal`` of shape ``(500, 2)`` with
        ``nominal[0] == nominal[-1]``.
    """
    n_demos, n_points, noise = _check_band(n_demos, n_points, noise)
    radius = check_positive(radius, "radius")
    _noise_below(noise, radius, "radius", 3)
    rng = check_random_state(seed)
    theta = np.linspace(0.5 * np.pi, 2.5 * np.pi, _N_FINE)
    fine = radius * np.column_stack((np.cos(theta), np.sin(theta)))
    return _closed_set(
        "closed_circle",
        rng,
        fine,
        n_demos,
        n_points,
        noise,
        f"Circle of radius {radius:g} mm drawn once counter-clockwise from the top, start = "
        f"end; {n_demos} closed demos = periodic smooth radial offsets (sd ≈ {noise:g} mm) "
        f"+ white noise (sd {0.05 * noise:g} mm), {n_points} points each. "
        "Ground truth: the circle.",
    )


def nearly_closed_o(
    n_demos: int = 7,
    seed: Any = None,
    *,
    n_points: int = 200,
    radius: float = 20.0,
    coverage: float = 0.96,
    noise: float = 1.0,
) -> DemoSet:
    """A handwritten "o" that stops just short of closing (``coverage`` of a circle).

    The nominal is the arc of the circle of radius ``radius`` mm centred at the
    origin from the top, (0, radius), counter-clockwise through
    ``coverage * 360`` degrees: it ends a gap of ``(1 - coverage) * 2 pi *
    radius`` (arc length; 5.0 mm with the defaults) short of its start. Each
    demonstration is the arc offset along its normal by a smooth random
    function (three sinusoids of 0.5-2.5 cycles per path, sd about ``noise``,
    not periodic), resampled to ``n_points`` points equally spaced in arc
    length, plus isotropic white noise of sd ``0.05 * noise``.

    Parameters
    ----------
    n_demos : int
    seed : None, int or numpy.random.Generator
    n_points : int
    radius : float
        Radius of the nominal circle, mm.
    coverage : float
        Fraction of the full circle drawn, in (0.5, 1).
    noise : float
        Standard deviation of the smooth normal offset, mm (smaller than ``radius / 3``).

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_points, 2)`` in mm; ``nominal`` of shape ``(500, 2)``.
    """
    n_demos, n_points, noise = _check_band(n_demos, n_points, noise)
    radius = check_positive(radius, "radius")
    coverage = check_positive(coverage, "coverage")
    if not 0.5 < coverage < 1.0:
        raise ValueError(f"coverage: expected a fraction in (0.5, 1), got {coverage!r}")
    _noise_below(noise, radius, "radius", 3)
    rng = check_random_state(seed)
    theta = 0.5 * np.pi + np.linspace(0.0, coverage * _TWO_PI, _N_FINE)
    fine = radius * np.column_stack((np.cos(theta), np.sin(theta)))
    band = _Band.draw(rng, fine, n_demos, n_points, noise)
    gap = (1.0 - coverage) * _TWO_PI * radius
    return _demo_set(
        "nearly_closed_o",
        band.demos(),
        fine,
        "mm",
        f"Handwritten 'o': {coverage * 100:g} % of a circle of radius {radius:g} mm, "
        f"counter-clockwise from the top, stopping {gap:.3g} mm (arc) short of its start; "
        f"{n_demos} demos = smooth normal offsets (sd ≈ {noise:g} mm) + white noise "
        f"(sd {0.05 * noise:g} mm), {n_points} points each. Ground truth: the arc.",
    )


def figure_eight(
    n_demos: int = 7,
    seed: Any = None,
    *,
    n_points: int = 200,
    size: float = 20.0,
    noise: float = 1.0,
) -> DemoSet:
    """An upright figure-eight drawn once, from its top and back: start = end, one crossing.

    The nominal is the lemniscate of Gerono ``x = (size / 2) sin 2t``,
    ``y = size * sin t`` for ``t`` from pi/2 to 5 pi/2: it starts at the top
    (0, size), goes left round the upper lobe, crosses itself at the origin,
    round the lower lobe (bottom at (0, -size)), crosses again at the origin
    and returns up to the top. Height ``2 size``, width ``size`` mm, length
    about ``6.1 size``; it is straight where it crosses itself and its smallest
    radius of curvature is about ``0.21 size`` (in the lobes' flanks), so an
    offset below ``size / 12`` times the smooth offsets' bound ``sqrt(6)`` never
    folds it. Demonstrations are
    built as in :func:`closed_circle`: periodic smooth normal offsets (sd about
    ``noise``, 1-4 whole cycles per figure), resampled to ``n_points`` points
    equally spaced in arc length, white noise of sd ``0.05 * noise``, last
    point equal to the first.

    Parameters
    ----------
    n_demos : int
    seed : None, int or numpy.random.Generator
    n_points : int
    size : float
        Half the height of the figure, mm.
    noise : float
        Standard deviation of the smooth normal offset, mm (smaller than ``size / 12``).

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_points, 2)`` in mm, each with ``demo[0] == demo[-1]``;
        ``nominal`` of shape ``(500, 2)`` with ``nominal[0] == nominal[-1]``.
    """
    n_demos, n_points, noise = _check_band(n_demos, n_points, noise)
    size = check_positive(size, "size")
    _noise_below(noise, size, "size", 12)
    rng = check_random_state(seed)
    t = np.linspace(0.5 * np.pi, 2.5 * np.pi, 40001)
    fine = _fine(np.column_stack((0.5 * size * np.sin(2.0 * t), size * np.sin(t))))
    return _closed_set(
        "figure_eight",
        rng,
        fine,
        n_demos,
        n_points,
        noise,
        f"Upright figure-eight (lemniscate of Gerono, height {2 * size:g} mm) drawn once "
        f"from the top, start = end, crossing itself at the origin; {n_demos} closed demos = "
        f"periodic smooth normal offsets (sd ≈ {noise:g} mm) + white noise "
        f"(sd {0.05 * noise:g} mm), {n_points} points each. Ground truth: the lemniscate.",
    )


def letter_a(
    n_demos: int = 7,
    seed: Any = None,
    *,
    n_points: int = 200,
    radius: float = 15.0,
    noise: float = 0.75,
    start_spread: float = 0.015,
) -> DemoSet:
    """A handwritten "a": round a bowl back to the start, then a down-stroke to a common end.

    Nominal (mm), built from arcs and a line and then shifted so that it ends
    at the origin (as LASA's demonstrations do): start S on the bowl, the
    circle of radius ``R = radius``, at 40 degrees (top right); once round the
    bowl counter-clockwise (over the top, down the left, along the bottom, up
    the right) exactly back to S; a tight clockwise turn of radius ``0.15 R``
    through 220 degrees, from heading up-left to heading straight down; a
    straight down-stroke at ``1.031 R`` right of the bowl's centre (it passes
    0.031 R outside the bowl's rightmost point) to ``1.2 R`` below the centre.
    Length about ``8.8 R``; the path comes back through its own start at 71 %
    of its length.

    Each demonstration is the nominal offset along its normal by a smooth
    random function (three sinusoids of 0.5-2.5 cycles per path, sd about
    ``noise``) tapered in over the first 15 % and out over the last 15 % of the
    length, plus a start displacement uniform in the disc of radius
    ``start_spread * H`` (``H = 2.2 R``, the letter's height) blended out over
    the first 20 %; resampled to ``n_points`` points equally spaced in arc
    length, plus white noise of sd ``0.05 * noise`` on every point but the
    last. Every demonstration therefore ends exactly at the origin, its start
    lies within ``start_spread * H`` of S (up to the white noise), and its bowl
    returns to within a few ``noise`` of its own start.

    Parameters
    ----------
    n_demos : int
    seed : None, int or numpy.random.Generator
    n_points : int
    radius : float
        Radius of the bowl, mm.
    noise : float
        Standard deviation of the smooth normal offset, mm (smaller than
        ``radius / 17``, so that the offsets, at most ``sqrt(6)`` times it,
        never fold the tight turn).
    start_spread : float
        Radius of the disc of start displacements as a fraction of the height,
        in [0, 0.1].

    Returns
    -------
    DemoSet
        Arrays of shape ``(n_points, 2)`` in mm, each ending at (0, 0);
        ``nominal`` of shape ``(500, 2)``.
    """
    n_demos, n_points, noise = _check_band(n_demos, n_points, noise)
    radius = check_positive(radius, "radius")
    start_spread = check_positive(start_spread, "start_spread", allow_zero=True)
    _noise_below(noise, radius, "radius", 17)
    if start_spread > 0.1:
        raise ValueError(f"start_spread: expected a fraction in [0, 0.1], got {start_spread!r}")
    rng = check_random_state(seed)
    r, rc, a0 = radius, 0.15 * radius, np.deg2rad(40.0)
    bowl_angle = a0 + np.linspace(0.0, _TWO_PI, 20001)
    bowl = r * np.column_stack((np.cos(bowl_angle), np.sin(bowl_angle)))
    start = bowl[0]
    # Heading at S is a0 + 90 degrees; the turn's centre lies on its right.
    centre = start + rc * np.array([np.cos(a0), np.sin(a0)])
    turn_angle = np.linspace(np.pi + a0, 0.0, 2001)
    turn = centre + rc * np.column_stack((np.cos(turn_angle), np.sin(turn_angle)))
    x_stroke = turn[-1, 0]
    stroke = np.column_stack((np.full(4001, x_stroke), np.linspace(turn[-1, 1], -1.2 * r, 4001)))
    curve = np.vstack((bowl, turn[1:], stroke[1:]))
    curve = curve - curve[-1]
    fine = _fine(curve)
    normals = left_normals(fine)
    u = _arc(fine)[1]
    taper = _ramp(u / 0.15) * _ramp((1.0 - u) / 0.15)
    w_start = 1.0 - _ramp(u / 0.2)
    spread = start_spread * 2.2 * r
    demos = []
    for _ in range(n_demos):
        offset = smooth_offset(rng, u, noise)
        rho, ang = spread * np.sqrt(rng.random()), rng.uniform(0.0, _TWO_PI)
        d_start = np.array([rho * np.cos(ang), rho * np.sin(ang)])
        white = rng.normal(0.0, 0.05 * noise, (n_points, 2))
        white[-1] = 0.0
        path = fine + (taper * offset)[:, None] * normals + w_start[:, None] * d_start
        demo = resample(path, n_points) + white
        demo[-1] = 0.0
        demos.append(demo)
    return _demo_set(
        "letter_a",
        demos,
        fine,
        "mm",
        f"Handwritten 'a' (bowl radius {radius:g} mm, height {2.2 * radius:g} mm): from the "
        "top right once round the bowl counter-clockwise back through the start, a tight "
        f"turn and a down-stroke to the origin; {n_demos} demos = smooth normal offsets (sd ≈ "
        f"{noise:g} mm, tapered at both ends) + start displacements within "
        f"{spread:.3g} mm ({start_spread * 100:g} % of the height) + white noise, all ending "
        "exactly at the origin. Ground truth: the nominal.",
    )


# --------------------------------------------------------------------- registry
#: Short name -> generator, for every synthetic mimicking data set.
MIMIC_DATASETS: dict[str, Callable[..., DemoSet]] = {
    "quasi_circular": quasi_circular_band,
    "noisy_band": noisy_band,
    "deburring_linear": deburring_linear,
    "deburring_circular": deburring_circular,
    "walking": walking_corridor,
    "da_vinci": da_vinci_walls,
    "different_extents": different_extents,
    "local_detours": local_detours,
    "uneven_sampling": uneven_sampling,
    "loops": loops,
}

#: Short name -> generator, for the closed and nearly closed handwriting shapes
#: (kept apart from :data:`MIMIC_DATASETS`, whose sets ``benchmarks/mimic.py`` and
#: ``lfdkit demo`` run by default). :func:`load_dataset` finds both.
CLOSED_DATASETS: dict[str, Callable[..., DemoSet]] = {
    "closed_circle": closed_circle,
    "nearly_closed_o": nearly_closed_o,
    "figure_eight": figure_eight,
    "letter_a": letter_a,
}


def load_dataset(name: str, seed: Any = None, **kwargs: Any) -> DemoSet:
    """Generate a synthetic data set by its short name.

    Parameters
    ----------
    name : str
        A key of :data:`MIMIC_DATASETS` or :data:`CLOSED_DATASETS`.
    seed : None, int or numpy.random.Generator
    **kwargs
        Passed to the generator.

    Returns
    -------
    DemoSet

    Raises
    ------
    ValueError
        If ``name`` is unknown; the message lists the valid names.
    """
    return generate({**MIMIC_DATASETS, **CLOSED_DATASETS}, "data set", name, seed, kwargs)
