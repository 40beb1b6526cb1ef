"""Gaps between obstacles: a clearance floor that keeps them open, and what the demos showed.

A learned clearance floor (:func:`lfdkit.emulate.fidelity.demonstrated_clearances`)
is a hard margin added to each obstacle's radius. Around a lone obstacle it
keeps a plan at least as far as the demonstrations came (issue 26, item 4).
Between two obstacles it does more: where their surfaces are closer than the
two floors together, the margins overlap and close the gap, so the plan
goes around both. Training scenes of single obstacles cannot tell whether
the person would have done that.

* A person who keeps a fixed margin goes around (a closed gap is right).
* The thesis's person threads gaps narrower than the clearance it keeps
  from one obstacle, because its Gaussians sum to a minimum between them.
  The fidelity benchmark's thesis pairs went from 87 % to −16,555 % median Pr
  with every gap closed.

:func:`open_gap_margins` keeps the floor where an obstacle stands alone and
lets it give way between two: each obstacle's margin takes at most
:data:`GAP_SHARE` of the gap to any other, so the middle three fifths of a
gap stay free to pass, but only where the gap is at least :data:`PASSABLE`
times the larger floor (the clearance kept from either obstacle alone:
a person who passed a lone cup at 2 cm does not squeeze through 1.65 cm).
The skill's model without a floor of its own plans with this one (a safety
floor that closes only such narrow gaps). A model with a floor keeps the
gaps closed. Either way a floor never opens a gap: a plan it turns through
one the plan without it went round keeps less of it
(:func:`passes_a_new_gap`).

Measured (``python benchmarks/emulate_fidelity.py --quick --seed 0 --sizes 10
--people thesis``, 1x noise): the thesis's person passed one obstacle of a
9 cm gap at 1.6 cm (18 % of it), against the 4-5 cm it kept from a lone one;
a cap at a quarter of the gap on each side (the pair's margins together at
most half of it) pushed that plan onto another route (Pr 99 → 5 %).

A model with a floor keeps closed also the gaps its floors leave open but the
clearances the demonstrations typically kept would not (:func:`close_narrow_gaps`,
the median per class): the floors are a low quantile with room for noise, and a
person who keeps a margin passes only where both margins fit. Measured
(``--quick --sizes 10 --people margin``, seed 0): the fixed-margin person (2 and
4 cm) went round a 59.7 mm gap that floors of 15.8 + 28.8 mm left open (its
demonstrations kept 21.7 + 39.7 mm, median), and the plan threaded it.

A closed gap leaves two ways round the pair, and the plan with the floor is free
to take either; the person meets the first of the two and passes it as its
response does. :func:`side_blockers` keeps that side (the side the plan without
the floor passes the obstacle nearer the start on) with a ball that blocks the
other way: for a pair alone (no third obstacle in a closed gap: a pocket has more
ways round than two) whose first is met first (two abreast: the shorter way stands).
Measured (``--quick --sizes 10 --people late``, seed 0): a pair of
cups with a 62.5 mm gap closed, the plan went round both on the other side
from the person (that scene's Pr 1 % then -214 %; with the blocker 74 %).

Whether the floor gives way (gaps open, above) where the gap is narrower than
:data:`PASSABLE` floors is the demonstrations' to say, not the floor's: where
planning held-out ones with the closest any other came fits them worse than
with no floor at all (:data:`lfdkit.skill.selection.CONSISTENT_CLEARANCE`),
the person answers a smooth reward, not a margin, and threads every gap the
learned response threads (the thesis's person, seeds 1 and 2: 2.0-2.3 cm from
each of two boxes 4.5-4.9 cm apart, against 4.1-5.0 cm from a lone one, which
closed them; the pair scenes' Pr about -10,000 % to -29,000 %).

Where the training scenes show a gap across the path that the person went round
(the nominal passes between two obstacles, the demonstration round both), the
demonstrations decide the width: :func:`declined_gap_width` is the widest such
gap, in units of the clearances the person typically kept from the two classes,
below the narrowest one it threaded; the skill's plans keep every gap across the
path narrower than that closed, whatever the model (:func:`close_declined_gaps`,
then the side blockers). Without such a scene nothing changes. The fidelity
benchmark's training scenes hold one obstacle each, so there it changes nothing:
its late swerver goes round held-out gaps of 1.25-5.8 times the clearances it kept
(seeds 1-3; it sees the bands of every obstacle within its look-ahead as one wall
and returns slowly), which no single-obstacle demonstration shows. With four of
its ten training scenes pairs instead, it declined gaps of 0.91-1.04 of them
(seeds 1-3), about its two margins together, and the held-out figures stayed as
they were; with four clutter scenes no gap across the path was shown.

The same balls keep a side the demonstrations prefer (:func:`preferred_side_blockers`):
a person who keeps a class on one side of the path (a cup always on their left,
:func:`lfdkit.emulate.fidelity.side_preferences`) goes the long way round where
the obstacle stands on the other side, which no symmetric reward does. A row of
:data:`PREFERRED_CHAIN` balls beside each such obstacle near the nominal blocks
the side the person never took; every route planner (MPC, full horizon, taut)
then goes round it on the person's side. Measured on the fidelity probe's person
who keeps cups on its left (``python benchmarks/emulate_probe.py --variants
asym-cup asym-cup-n10 --seed S``; 14 held-out scenes; pooled / median Pr, sides
kept; before → after): seed 0, 6 demonstrations, −4 / 81 %, 77 % → 97 / 99 %,
100 % (10: the same); seed 1, −50 / 57 %, 50 % → 86 / 98 %, 96 % (10: 65 / 98 %,
93 %); seed 2, −41 / −23 %, 42 % → 99 / 99 %, 100 % (10: the same); 0 collisions
and 0 refused throughout. What is left: a pair of boxes of a new task (seed 1)
threaded after the cup before them was passed the person's way. A ball alone
near the goal was gone round (seed 1: sides 82 %); a row that ends at twice the
long way's width was gone round in clutter (seed 1, 86 %). The skill's plans with a
preference take about twice as long (the taut route's grid spans the row).
In 3-D (the last axis up) a class may also be kept above or below the path (a person
who passes over boxes): rows on the obstacle's other sides across the path, every 45
degrees (balls on three sides alone left the corners open: the *over* person of
``benchmarks/boxes3d.py`` slipped under a carton's corner), those beside it level with its
top along the way passed, so the way over stays as open as
without them (risen above it, they left only a slot and plans passed 7 cm over a box the
learned response passes at 2.4 cm). Each row's balls touch only at points, so
between two rows beyond their first balls there were holes (the *over* person, seed
3, passed under the shelf through one, and 9 of its 10 folds found no preference): balls
sized as a row's fill them, in the plane across the path through the obstacle out to
the shortest row's reach, none rising above its top (:func:`_fill_holes`, at most
:data:`MAX_FILL`). Measured (``python benchmarks/boxes3d.py --people over --seed S``,
side by side with the rows alone): seed 3 ratio to the DMP alone 1.03 → 0.37, sides 8
→ 9 of 10 (the other a coin flip: a nominal through the shelf's centre), seeds 0-2 the
same to 0.01 cm; a plan with the rows 1.16 times the CPU (39 balls against 15).
Past an obstacle kept so, the learned response pushes the plan the other way (the
shorter way round), towards it: nothing learned holds it off, and with the tool's
clearance alone the *over* person's plans passed the shelf at 0.76-0.79 of the
clearance the person kept (6.8-9.0 cm against 8.7-10.9). Such an obstacle keeps its
class's learned floor (:func:`preferred_side_margins`, from
:func:`lfdkit.emulate.fidelity.kept_sides`: 0.8 times the 10 % quantile of the
clearances the demonstrations kept), as a skill's floor is kept. Measured (same
command, side by side with 5662600, 10 folds; ratio to the DMP alone, clearance / the
person's): seeds 0-3 0.20 / 0.17 / 0.18 / 0.37 → 0.12 / 0.11 / 0.13 / 0.32,
0.76-0.79 → 0.92-0.95, sides and collisions unchanged. The typical clearance (the median)
as the margin overshot (1.11-1.49 of the person's: a hard margin holds the whole pass
as far as the person came at its nearest) and did not bring the plans nearer the
person (seeds 0, 1, 3: 1.52 / 1.59 / 2.97 cm against 1.57 / 1.25 / 2.90); kept from
the blockers instead, it refused 4 of 10 folds (seed 0). The fidelity probe's person
who keeps cups on its left (``asym-cup``, seed 0) is unchanged: its chosen model's
floor (the typical clearance) is the larger.

Two obstacles one behind the other along the path are no gap across it, yet a
person who holds its swerve does not weave between them either
(:func:`held_pairs`): where their lateral bands (centre offset plus and minus
radius and the clearance typically kept) overlap and they stand within the
reach of the swerve shown round a lone obstacle (:func:`swerve_reach`, where
the demonstration stays at least 0.9 of its largest distance from the nominal:
held, not on its way out or back),
it is still swerved round the first when it meets the second, and goes round
both. :func:`bridge_blockers` closes such pairs with a row of balls inside their
convex hull and keeps the group's first obstacle on the side away from its
centre. For a skill whose floor is kept whole (gaps closed), not the taut
route. Measured (``python benchmarks/emulate_fidelity.py --quick --sizes 10
--people late --seed S``, side by side with 9580d4a; pooled / median Pr, sides,
gaps threaded): seed 1 1x 63/85 %, 89 %, 2 -> 85/85 %, 100 %, 0 (2x the same);
seed 3 1x 40/86 %, 92 %, 3 -> 75/88 %, 100 %, 0; seed 3 2x 40/81 %, 92 %, 3 ->
-49/81 %, 88 %, 0 (a clutter scene goes round its wall on the other side from
the person, Pr 8 -> -227 %); seeds 0 and 2 unchanged (seed 2's S-curve pair,
23 cm apart along the path, is beyond the held reach of 18 cm). At half the
largest distance the reach (26-28 cm) joined pairs the late swerver weaves
through (seed 2: Pr 90 -> -960 %), and the fixed-margin person's (its swerve a
long triangle: 41 cm at half, 8 cm at 0.9) in clutter (seed 1, 2x: sides 100
-> 76 %). The thesis's, margin and field people unchanged (seeds 0 and 1).
The bands are those of clearances learned from few noisy demonstrations, so a
pair is held only where they overlap by more than the two clearances'
allowances (:func:`clearance_allowance`, 2 standard errors): the late
swerver, seed 3, 2x, learned 3.25 cm from cups where it keeps 3 cm, so the bands
of a cup beside the path and the next cup 14 cm on overlapped by 2.5 mm (its
allowance 3.3 mm) where the person keeps a 5 mm lane; joined, the cup beside the path
became the first of a wall of five, and the plan went round the whole wall on
the other side from the person (Pr -227 %, 1 of 4 sides). Same command, side
by side with b9ab7ef: seed 3 2x -77/81 %, 84 % -> 46/81 %, 96 % (that scene
97 %); seeds 0-2 and seed 3 1x unchanged (seed 1's held clutter pair overlaps
by 3 cm and stays held).

:func:`gaps_closed_by` finds the pairs a floor would close.
:func:`demonstrated_gaps` counts the training scenes that show one, which
tells whether the demonstrations can decide between the two.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterable, Mapping, Sequence

import numpy as np

from lfdkit.core.geometry import arc_length, polyline_distances, segment_tangents
from lfdkit.emulate.fidelity import CLEARANCE_FACTOR, SIDES, lateral_axes, passing_sides
from lfdkit.emulate.problem import Corridor
from lfdkit.model.scene import Obstacle, Scene

__all__ = [
    "ABREAST",
    "BLOCKER_REACH",
    "BRIDGE_FILL",
    "DECLINED_OVERLAP",
    "GAP_SHARE",
    "GAP_STANDARD_ERRORS",
    "PASSABLE",
    "PREFERRED_CHAIN",
    "REACH_LEVEL",
    "SIDE_BLOCKER",
    "TOUCHING",
    "abreast_pairs",
    "bridge_blockers",
    "clearance_allowance",
    "close_declined_gaps",
    "close_narrow_gaps",
    "closes_a_threaded_gap",
    "declined_gap_width",
    "demonstrated_gaps",
    "gaps_closed_by",
    "held_pairs",
    "open_gap_margins",
    "passable_pairs",
    "passes_a_new_gap",
    "preferred_side_blockers",
    "preferred_side_margins",
    "side_blockers",
    "surface_gaps",
    "swerve_reach",
    "threaded_pairs",
]

#: The most of the gap to another obstacle one obstacle's margin may take when gaps stay
#: open: a plan may pass anywhere in the middle three fifths of a gap.
GAP_SHARE = 0.2
#: A gap stays closed, gaps open or not, where it is narrower than this times the larger
#: floor of its two obstacles: the clearance the demonstrations kept from either alone
#: (a floor is :data:`~lfdkit.emulate.fidelity.CLEARANCE_FACTOR` of it). A person who passed
#: a lone cup at 2 cm does not squeeze through a gap of less than 2 cm; the thesis's person
#: threads gaps of 4.5-9 cm against the 4-5 cm it kept from a lone obstacle. Measured
#: (fidelity benchmark, seed 1): the fixed-margin person (2 cm from a cup) went round a
#: pocket of cups 1.65 cm apart that the plan threaded (Pr -141 %, 6 gaps).
PASSABLE = 1.0 / CLEARANCE_FACTOR
#: Where gaps stay closed, a gap within this many standard errors of the clearances
#: typically kept from its two obstacles stays closed too (:func:`clearance_allowance`):
#: a clearance learned from few noisy demonstrations is a guess. The probe's fixed-margin
#: person, 4 demonstrations, seed 0: a 6.0 cm gap, exactly its margins (2 + 4 cm), against
#: a box margin learned at 3.6 cm from two demonstrations (noise 2 mm): the plan threaded
#: it where the person went round. Two standard errors (a 95 % interval).
GAP_STANDARD_ERRORS = 2.0
#: The label of a ball :func:`side_blockers` puts in a scene (no class of a person's).
SIDE_BLOCKER = "<other side>"
#: A side blocker's radius, as a fraction of its distance to the nearer of the task's start
#: and goal: under a half, so that the ball keeps clear of both.
BLOCKER_REACH = 0.45
#: Balls in a row beside an obstacle passed on one side by preference
#: (:func:`preferred_side_blockers`): one alone, near the goal, is small enough to go
#: round (the probe's person who keeps cups on its left, seed 1: a cup 4 cm before the
#: goal passed the short way round a 4.3 cm ball).
PREFERRED_CHAIN = 3
#: Largest number of balls that fill the holes between the rows of a 3-D preferred side
#: (:func:`preferred_side_blockers`): the *over* person's shelf took all 24.
MAX_FILL = 24
#: A gap is across the path, one a path passes through, where the segment between the two
#: obstacles' nearest surface points makes at least 45 degrees with the path (its cosine at
#: most this): two obstacles one behind the other along the path leave a way past on the
#: same side of both, or a weave from one side to the other, which their gap does not decide.
ABREAST = float(np.cos(np.pi / 4))
#: How far two margins that close a declined gap overlap: together this times the gap
#: (:func:`close_declined_gaps`), so no plan point fits between them.
DECLINED_OVERLAP = 1.05
#: Two obstacles closer than this times the scene's size (its largest coordinate plus
#: radius) touch: floating point leaves a cup standing on a table 3e-17 m above it.
TOUCHING = 1e-9
#: The part of its largest distance from the nominal at which a demonstration counts as
#: swerved (:func:`swerve_reach`).
REACH_LEVEL = 0.9
#: Radius of the balls that close a held pair (:func:`bridge_blockers`), as a fraction of the
#: smaller obstacle's radius: inside the pair's convex hull.
BRIDGE_FILL = 0.9


def surface_gaps(scene: Scene) -> np.ndarray:
    """Surface-to-surface distance between every two obstacles of a scene.

    Parameters
    ----------
    scene : Scene

    Returns
    -------
    ndarray, shape (n_obstacles, n_obstacles)
        Units; negative where two overlap, ``inf`` on the diagonal. As each
        pair's shapes measure it (:meth:`lfdkit.model.scene.Obstacle.surface_gap`: exact for
        round obstacles and for anything against a whole half-space, through
        the balls that cover them otherwise).
    """
    n = len(scene)
    out = np.full((n, n), np.inf)
    for i in range(n):
        for j in range(i):
            out[i, j] = out[j, i] = scene.obstacles[i].surface_gap(scene.obstacles[j])[0]
    return out


def gaps_closed_by(margins: np.ndarray, scene: Scene) -> list[tuple[int, int, float]]:
    """The pairs of obstacles whose margins together close the gap between them.

    Parameters
    ----------
    margins : ndarray, shape (n_obstacles,)
        Clearance kept from each obstacle's surface (units).
    scene : Scene

    Returns
    -------
    list of (int, int, float)
        ``(i, j, gap)`` with ``i < j`` and ``0 < gap < margins[i] + margins[j]``
        (two obstacles that touch leave no gap to close: a gap within
        :data:`TOUCHING` of the scene's size is a touch, such as a cup standing
        on a table, 3e-17 m apart in floating point).
    """
    gaps = surface_gaps(scene)
    touch = TOUCHING * float(
        np.max(np.abs(scene.positions), initial=0.0) + np.max(scene.radii, initial=0.0)
    )
    closed = (margins[:, None] + margins[None, :] > gaps) & (gaps > touch)
    i, j = np.nonzero(np.triu(closed, k=1))
    return [(int(a), int(b), float(gaps[a, b])) for a, b in zip(i, j, strict=True)]


def clearance_allowance(
    scenes: Sequence[Scene], classes: Sequence[str], noise: float | None
) -> dict[str, float]:
    """Per class, how far the clearance typically kept may be short of the person's.

    Each demonstration's clearance from an obstacle is the person's margin
    plus the noise there, so a class's typical clearance, learned from the
    ``n`` obstacles of that class the demonstrations went round, is uncertain
    by ``sqrt(noise / n)``; the allowance is :data:`GAP_STANDARD_ERRORS` of
    those.

    Parameters
    ----------
    scenes : sequence of Scene
        The training scenes (their obstacles are counted per class).
    classes : sequence of str
        The classes to give an allowance.
    noise : float or None
        The demonstrations' noise, a mean squared distance (units²; e.g.
        :func:`lfdkit.emulate.metrics.demonstration_spread`); None: unknown.

    Returns
    -------
    dict
        ``{class: units}`` for each class that some scene holds; empty where
        ``noise`` is unknown or not positive.
    """
    if noise is None or not np.isfinite(noise) or noise <= 0.0:
        return {}
    counts = Counter(label for scene in scenes for label in scene.labels)
    sd = float(np.sqrt(noise))
    return {c: GAP_STANDARD_ERRORS * sd / np.sqrt(counts[c]) for c in classes if counts[c]}


def close_narrow_gaps(
    margins: np.ndarray,
    kept: np.ndarray,
    scene: Scene,
    *,
    wide: np.ndarray | None = None,
    path: np.ndarray | None = None,
) -> np.ndarray:
    """Margins raised so that they close every gap narrower than the clearances kept.

    A person who keeps a margin from each obstacle passes between two only
    where the gap leaves room for both margins: ``gap >= kept[i] + kept[j]``.
    The floors are lower than what the person kept (a low quantile, times
    :data:`~lfdkit.emulate.fidelity.CLEARANCE_FACTOR`, room for noise), so
    two floors may leave open a gap the person would not take (the fidelity
    benchmark's fixed-margin person, 2 and 4 cm: a 59.7 mm gap left open by
    floors of 15.8 + 28.8 mm, and threaded). Each obstacle of such a pair
    keeps at least its ``kept`` clearance, which closes the gap.

    Parameters
    ----------
    margins : ndarray, shape (n_obstacles,)
        Each obstacle's floor (units).
    kept : ndarray, shape (n_obstacles,)
        The clearance the demonstrations typically kept from each obstacle's
        class (units; e.g. the median, the person's margin give or take noise).
    scene : Scene
    wide : ndarray, shape (n_obstacles,), optional
        ``kept`` with room for how uncertain it is (:func:`clearance_allowance`):
        gaps across ``path`` (:func:`abreast_pairs`) narrower than these close
        too, with them. Not a gap one behind the other along the path: it
        leaves a way past on the same side of both, and a margin learned a
        little short does not decide a weave (issue 34's boxes, 22 cm apart
        along the path, 2 mm past the typical clearances together: closed,
        the plan kept 17 cm from a box the person passed at 11).
    path : ndarray, shape (n, q), optional
        The nominal, with ``wide``.

    Returns
    -------
    ndarray, shape (n_obstacles,)
        ``margins`` where no such gap is left open; ``max(margins, kept)`` for
        the obstacles of each pair ``(i, j)`` with ``0 < gap < kept[i] +
        kept[j]`` (:func:`gaps_closed_by` with ``kept``) that ``margins`` leave
        open, ``max(margins, wide)`` for those across ``path`` with ``0 < gap
        < wide[i] + wide[j]``.
    """
    margins = np.asarray(margins, dtype=np.float64).copy()
    kept = np.asarray(kept, dtype=np.float64)
    if (wide is None) != (path is None):
        raise ValueError(
            "wide, path: give both (the allowance closes only gaps across the path) or neither"
        )
    if wide is not None and np.shape(wide) != (len(scene),):
        raise ValueError(
            f"wide: expected one clearance per obstacle, shape ({len(scene)},), "
            f"got {np.shape(wide)}"
        )
    if len(scene) < 2:
        return margins
    closing = {(i, j): (gap, kept) for i, j, gap in gaps_closed_by(kept, scene)}
    if wide is not None:  # and path, checked above
        wide = np.asarray(wide, dtype=np.float64)
        widened = {(i, j): gap for i, j, gap in gaps_closed_by(wide, scene)}
        for pair in abreast_pairs(list(widened), scene, path):
            closing[pair] = (widened[pair], wide)
    for (i, j), (gap, by) in sorted(closing.items()):
        if margins[i] + margins[j] <= gap:
            margins[i], margins[j] = max(margins[i], by[i]), max(margins[j], by[j])
    return margins


def close_declined_gaps(
    margins: np.ndarray, kept: np.ndarray, width: float, scene: Scene, path: np.ndarray
) -> tuple[np.ndarray, list[tuple[int, int]]]:
    """Margins raised so that they close every gap across ``path`` narrower than ``width``.

    For each pair with ``0 < gap < width (kept[i] + kept[j])`` across
    ``path`` (:func:`abreast_pairs`, as :func:`declined_gap_width` counts
    them) that ``margins`` leave open, each of the two keeps at least its ``kept``
    clearance, and more where that leaves the gap open: shares of
    :data:`DECLINED_OVERLAP` times the gap in proportion to ``kept`` (a gap
    twice the two clearances closes with twice each, no more).

    Parameters
    ----------
    margins : ndarray, shape (n_obstacles,)
        Each obstacle's floor (units).
    kept : ndarray, shape (n_obstacles,)
        The clearance the demonstrations typically kept from each obstacle's class (units).
    width : float
        :func:`declined_gap_width`: gaps narrower than this many clearances kept are closed.
    scene : Scene
    path : ndarray, shape (n, q)
        The nominal.

    Returns
    -------
    margins : ndarray, shape (n_obstacles,)
    pairs : list of (int, int)
        The pairs narrower than ``width`` (closed now, or by ``margins`` already).
    """
    margins = np.asarray(margins, dtype=np.float64).copy()
    kept = np.asarray(kept, dtype=np.float64)
    pairs = gaps_closed_by(width * kept, scene) if len(scene) > 1 else []
    across = set(abreast_pairs([(i, j) for i, j, _ in pairs], scene, path))
    pairs = [(i, j, gap) for i, j, gap in pairs if (i, j) in across]
    for i, j, gap in pairs:
        if margins[i] + margins[j] <= gap:
            share = max(1.0, DECLINED_OVERLAP * gap / (kept[i] + kept[j]))
            margins[i], margins[j] = (
                max(margins[i], share * kept[i]),
                max(margins[j], share * kept[j]),
            )
    return margins, [(i, j) for i, j, _ in pairs]


def open_gap_margins(
    margins: np.ndarray,
    scene: Scene,
    share: float = GAP_SHARE,
    pairs: Sequence[tuple[int, int]] | None = None,
) -> np.ndarray:
    """Margins lowered so that no two of them close the gap between their obstacles.

    Each margin is capped at ``share`` times the gap to its nearest
    neighbour, so between any two obstacles at least ``1 − 2 share`` of the
    gap stays free; a lone obstacle keeps its whole margin, and two that
    overlap keep none. With ``pairs``, only those gaps are opened (the
    others stay as the margins leave them).

    Parameters
    ----------
    margins : ndarray, shape (n_obstacles,)
        Clearance to keep from each obstacle's surface (units, >= 0).
    scene : Scene
    share : float
        The part of a gap one obstacle's margin may take, in [0, 0.5).
    pairs : sequence of (int, int), optional
        The gaps to open (default: every one), e.g. :func:`threaded_pairs`.

    Returns
    -------
    ndarray, shape (n_obstacles,)
    """
    margins = np.asarray(margins, dtype=np.float64)
    if len(scene) < 2 or not margins.any():
        return margins.copy()
    gaps = surface_gaps(scene)
    if pairs is not None:
        chosen = np.full(gaps.shape, np.inf)
        for i, j in pairs:
            chosen[i, j] = chosen[j, i] = gaps[i, j]
        gaps = chosen
    nearest = np.maximum(gaps.min(axis=1), 0.0)
    return np.minimum(margins, share * nearest)


def passable_pairs(
    pairs: Sequence[tuple[int, int]], margins: np.ndarray, scene: Scene, factor: float = PASSABLE
) -> list[tuple[int, int]]:
    """Those of ``pairs`` whose gap is at least ``factor`` times the larger of their two margins.

    Parameters
    ----------
    pairs : sequence of (int, int)
        E.g. :func:`threaded_pairs` of the plan without a floor.
    margins : ndarray, shape (n_obstacles,)
        The floor of each obstacle (units).
    scene : Scene
    factor : float

    Returns
    -------
    list of (int, int)
    """
    gaps = surface_gaps(scene)
    return [(i, j) for i, j in pairs if gaps[i, j] >= factor * max(margins[i], margins[j])]


def threaded_pairs(path: np.ndarray, scene: Scene, n_samples: int = 16) -> list[tuple[int, int]]:
    """The pairs of obstacles a path passes between (through the gap between their surfaces).

    The path passes between two obstacles when it comes within
    ``gap / n_samples`` of the segment joining their surfaces (sampled at
    ``n_samples`` points; a path crossing it in the plane comes within
    half a sample spacing), in any number of dimensions.

    Parameters
    ----------
    path : ndarray, shape (n, q)
    scene : Scene
        Round obstacles are judged by their centres and radii, other shapes
        by the balls nearest each other (:meth:`Obstacle.balls`).
    n_samples : int

    Returns
    -------
    list of (int, int)
        ``(i, j)`` with ``i < j``; only pairs with a positive gap.
    """
    out = []
    t = np.linspace(0.0, 1.0, n_samples)[:, None]
    for i in range(len(scene)):
        for j in range(i + 1, len(scene)):
            # The surface points nearest each other, and the segment between them.
            gap, end_i, end_j = scene.obstacles[i].surface_gap(scene.obstacles[j])
            if not 0.0 < gap < np.inf:
                continue
            samples = end_i + t * (end_j - end_i)
            if polyline_distances(samples, path).min() <= gap / n_samples:
                out.append((i, j))
    return out


def closes_a_threaded_gap(margins: np.ndarray, scene: Scene, path: np.ndarray) -> bool:
    """Whether ``margins`` close a gap between two obstacles that ``path`` passes through.

    A floor that does moves the route on purpose (the plan goes round both).

    Parameters
    ----------
    margins : ndarray, shape (n_obstacles,)
        Clearance kept from each obstacle's surface (units).
    scene : Scene
    path : ndarray, shape (n, q)
        The plan without the margins.
    """
    closed = {(i, j) for i, j, _ in gaps_closed_by(margins, scene)}
    return bool(closed) and bool(closed.intersection(threaded_pairs(path, scene)))


def passes_a_new_gap(path: np.ndarray, reference: np.ndarray, scene: Scene) -> bool:
    """Whether ``path`` passes between two obstacles that ``reference`` does not pass between.

    A clearance floor makes obstacles larger: it may close a gap (the plan
    goes round both), never open one. A plan with a floor that threads a gap
    the plan without it went round was turned there by the floor blocking a
    receding horizon part-way (:meth:`lfdkit.skill.Skill.plan_details` then
    keeps less of the floor).

    Parameters
    ----------
    path, reference : ndarray, each (n, q)
        The plan with a floor and the plan without it.
    scene : Scene
    """
    threaded = threaded_pairs(path, scene)
    return bool(threaded) and not set(threaded) <= set(threaded_pairs(reference, scene))


def demonstrated_gaps(
    scenes: Sequence[Scene], clearances: dict[str, float], *, within: float = 2.0
) -> int:
    """How many training scenes show two obstacles that their classes' floors would close.

    Parameters
    ----------
    scenes : sequence of Scene
        The scenes of the obstacle demonstrations.
    clearances : dict
        ``{class: units}``, the floor learned per class.
    within : float
        A pair counts when its gap is below ``within`` times the two floors together
        (near enough that the person's choice there says something).

    Returns
    -------
    int
        The number of scenes with at least one such pair: 0 means the
        demonstrations cannot tell whether the person passes between two
        obstacles or goes around both.
    """
    count = 0
    for scene in scenes:
        if len(scene) < 2:
            continue
        margins = np.array([clearances.get(label, 0.0) for label in scene.labels])
        count += bool(gaps_closed_by(within * margins, scene))
    return count


def abreast_pairs(
    pairs: Sequence[tuple[int, int]], scene: Scene, path: np.ndarray, cosine: float = ABREAST
) -> list[tuple[int, int]]:
    """Those of ``pairs`` whose gap lies across ``path`` (:data:`ABREAST`).

    Parameters
    ----------
    pairs : sequence of (int, int)
    scene : Scene
    path : ndarray, shape (n, q)
        E.g. the nominal; its direction is read at its point nearest the gap's middle.
    cosine : float
        The largest ``|cos|`` of the angle between the gap and the path.

    Returns
    -------
    list of (int, int)
    """
    path = np.asarray(path, dtype=np.float64)
    tangents = segment_tangents(path)
    out = []
    for i, j in pairs:
        _, end_i, end_j = scene.obstacles[i].surface_gap(scene.obstacles[j])
        across = end_j - end_i
        k = int(np.argmin(np.linalg.norm(path - 0.5 * (end_i + end_j), axis=1)))
        tangent = tangents[min(k, len(tangents) - 1)]
        norm = float(np.linalg.norm(across))
        if norm > 0.0 and abs(across @ tangent) <= cosine * norm:
            out.append((i, j))
    return out


def declined_gap_width(
    demos: Sequence[np.ndarray],
    scenes: Sequence[Scene],
    nominals: Sequence[np.ndarray],
    kept: dict[str, float],
) -> float | None:
    """The gap width, in the clearances typically kept, below which the demonstrations go round.

    A training scene *offers* a gap where its nominal passes between two
    obstacles; the demonstration *declines* it where it goes round both
    instead, and *threads* it where it passes between them (offered or
    not). Only gaps across the nominal count (:func:`abreast_pairs`): two
    obstacles one behind the other along it are passed on one side or
    woven through whatever their gap (the late swerver of the fidelity
    benchmark, in clutter: it kept one side past obstacles 20-50 cm apart
    along the path, 2.4-13 times the clearances it kept, and wove through
    others 3.2-4 times them). Each gap is measured in units of what the person typically kept
    from its two classes together, ``gap / (kept[a] + kept[b])``, so the
    bound carries to other classes, units and scenes. The widest declined
    gap that is narrower than every threaded one bounds what the person
    takes: narrower gaps are declined. No wider: the clearances kept are
    medians of noisy demonstrations, and a tenth more closed a gap the
    fidelity benchmark's late swerver threads (its pair training scenes,
    seed 3: declined at 0.94 of its clearances, a held-out pair at 1.01
    threaded, gone round on the other side: Pr -4,005 %). Where a threaded
    gap is narrower than every declined one, width does not decide (None).

    A person who keeps a margin declines gaps narrower than its two margins
    together (width 1); a late swerver who sees the bands of several
    obstacles ahead as one wall declines wider ones too; the thesis's person
    threads gaps narrower than the clearance it keeps from a lone obstacle.
    The demonstrations say which, where they show a gap.

    Parameters
    ----------
    demos : sequence of ndarray, each (n, q)
        The obstacle demonstrations.
    scenes : sequence of Scene
        Their scenes.
    nominals : sequence of ndarray, each (m, q)
        Each demonstration's nominal (the path without obstacles).
    kept : dict
        ``{class: units}``, the clearance the demonstrations typically kept
        (e.g. the median per class); a pair with a class not in it is left out.

    Returns
    -------
    float or None
        The width ``w``: a gap with ``gap < w (kept[a] + kept[b])`` across the
        path is one this person goes round; None where the scenes show no
        declined gap narrower than every threaded one (then nothing changes).
    """
    declined, threaded = [], []
    for demo, scene, nominal in zip(demos, scenes, nominals, strict=True):
        if len(scene) < 2:
            continue
        gaps = surface_gaps(scene)
        taken = set(threaded_pairs(np.asarray(demo, dtype=np.float64), scene))
        offered = set(threaded_pairs(np.asarray(nominal, dtype=np.float64), scene))
        for i, j in abreast_pairs(sorted(taken | offered), scene, nominal):
            pair = kept.get(scene.labels[i], 0.0) + kept.get(scene.labels[j], 0.0)
            if pair <= 0.0:
                continue
            (threaded if (i, j) in taken else declined).append(gaps[i, j] / pair)
    narrowest = min(threaded, default=np.inf)
    below = [w for w in declined if w < narrowest]
    if not below:
        return None
    return float(max(below))


def side_blockers(
    path: np.ndarray,
    nominal: np.ndarray,
    scene: Scene,
    margins: np.ndarray,
    ends: np.ndarray,
    n_points: int = 100,
) -> list[tuple[int, Obstacle]]:
    """Balls that keep a plan round each closed gap on the side ``path`` passes it.

    Where ``margins`` close the gap between two obstacles that ``path`` (the
    plan without them: the learned response) passes between, and close no
    gap from either to a third, a plan keeping them goes round both, on
    either side. A person meets the obstacle nearer
    the start first and passes it as its response does (the late swerver,
    seed 0: round a pair of cups on the side away from the first, where the
    plan, free to choose, went round the other side: Pr 1 -> -214 %); so the
    way round keeps the side ``path`` passes that first obstacle on, where it
    is met first: the other's centre lies beyond its extent along the
    nominal (two abreast are met at once; the plan keeps its own way round,
    the shorter). One ball
    per such pair blocks the other way: it touches the first obstacle's
    margin on the side away from ``path`` and reaches outwards, away from the
    task's start and goal (radius :data:`BLOCKER_REACH` of its distance to the
    nearer one). It has no response (label :data:`SIDE_BLOCKER`); the planner
    keeps out of it as out of a hard radius.

    Parameters
    ----------
    path : ndarray, shape (n, q)
        The plan without the margins, in the nominal's direction.
    nominal : ndarray, shape (m, q)
    scene : Scene
    margins : ndarray, shape (n_obstacles,)
        Clearance kept from each obstacle's surface (units).
    ends : ndarray, shape (2, q)
        The task's start and goal.
    n_points : int
        Points of the corridor the sides are read on.

    Returns
    -------
    list of (int, Obstacle)
        The first obstacle and its blocker, one per closed gap of a pair
        alone that ``path`` threads and whose first obstacle it passes on a
        known side; empty where there is none.
    """
    closed = {(i, j) for i, j, _ in gaps_closed_by(margins, scene)}
    # A pair alone: among three or more obstacles the margins join (clutter, a pocket)
    # there are more ways round than two, and the first one's side does not pick one
    # (the late swerver, seed 1: round a pocket of five, Pr 87 -> -240 % with a blocker).
    joined = np.zeros(len(scene), dtype=int)
    for i, j in closed:
        joined[i] += 1
        joined[j] += 1
    alone = {(i, j) for i, j in closed if joined[i] == joined[j] == 1}
    pairs = sorted(alone.intersection(threaded_pairs(path, scene))) if alone else []
    if not pairs:
        return []
    corridor = Corridor.from_path(nominal, n_points)
    sides = passing_sides(path, corridor, scene)
    rel = corridor.points[None] - scene.positions[:, None]
    nearest = np.argmin(np.einsum("okq,okq->ok", rel, rel), axis=1)  # along the nominal
    out: list[tuple[int, Obstacle]] = []
    along = arc_length(corridor.points)
    for pair in pairs:
        first, second = sorted(pair, key=lambda o: (int(nearest[o]), o))
        k = int(min(nearest[first], corridor.n_points - 2))
        tangent = corridor.points[k + 1] - corridor.points[k]
        tangent /= np.linalg.norm(tangent)
        centres, radii = scene.obstacles[first].balls()
        extent = float(np.max((centres - scene.positions[first]) @ tangent + radii))
        # Met first only where the second lies beyond it along the path: two abreast
        # are met at once, and the plan's own way round is the shorter one (the
        # fixed-margin person, seed 2: two boxes 5 mm apart along the path, Pr 79 -> -314 %
        # round the longer way).
        if along[nearest[second]] - along[nearest[first]] <= extent or not np.any(sides[first]):
            continue
        away = -sides[first] @ corridor.normals[nearest[first]]
        away /= np.linalg.norm(away)
        ball = _blocker(scene.obstacles[first], away, float(margins[first]), ends)
        if ball is not None:
            out.append((first, ball))
    return out


def _blocker(
    obstacle: Obstacle, away: np.ndarray, margin: float, ends: np.ndarray
) -> Obstacle | None:
    """The ball touching ``obstacle``'s margin on the side ``away`` (unit) and reaching outwards.

    Radius :data:`BLOCKER_REACH` of its touching point's distance to the nearer
    of ``ends`` (the task's start and goal, (2, q)); None where that is 0.
    """
    centres, radii = obstacle.balls()
    touch = obstacle.position + away * (
        float(np.max((centres - obstacle.position) @ away + radii)) + margin
    )
    reach = BLOCKER_REACH * float(np.linalg.norm(ends - touch, axis=1).min())
    return Obstacle(SIDE_BLOCKER, touch + away * reach, reach) if reach > 0.0 else None


def preferred_side_blockers(
    nominal: np.ndarray,
    scene: Scene,
    preferences: Mapping[str, tuple[str, float]],
    ends: np.ndarray,
    n_points: int = 100,
) -> list[tuple[int, Obstacle]]:
    """Balls that keep a plan on the side of each obstacle its class is passed on by preference.

    A person who keeps a class on one side
    (:func:`lfdkit.emulate.fidelity.side_preferences`: a cup always on their
    left) goes the long way round where the obstacle stands on that side of
    the path; a symmetric reward passes it the short way. Each obstacle of
    such a class that stands in the way (the nominal passes nearer its
    surface than ``within``) gets a row of :data:`PREFERRED_CHAIN` balls on
    its other side, along the nominal's normal at the obstacle's nearest
    nominal point: the first touches the obstacle's surface, each next one
    the last one's far side, each of radius :data:`BLOCKER_REACH` of its
    touching point's distance to the nearer of the task's start and goal (as
    :func:`side_blockers`' ball). One alone can be gone round where it is
    small (near the goal); the row reaches about six times as far. Any planner
    that keeps out of hard radii then passes the obstacle on the preferred
    side, the long way round where it must. In 3-D (the last axis up,
    :func:`lfdkit.emulate.fidelity.lateral_axes`) a row every 45 degrees
    round it across the path but on the side passed and the two diagonals
    beside that: a box kept below the path gets rows on its left, right,
    underside and lower diagonals, and the plan passes over it. An obstacle
    beyond the nominal's start or goal gets none, nor one where the nominal
    runs near vertical.

    Parameters
    ----------
    nominal : ndarray, shape (m, q)
        q = 2 or 3.
    scene : Scene
        Static obstacles.
    preferences : mapping
        ``{class: (side, within)}``: ``side`` ``"left"`` or ``"right"`` (in
        3-D also ``"above"`` or ``"below"``, :data:`~lfdkit.emulate.fidelity.SIDES`),
        the side of the path the class is kept on, seen along the nominal;
        ``within`` (units) how near the nominal must pass an obstacle's
        surface for it to be in the way.
    ends : ndarray, shape (2, q)
        The task's start and goal.
    n_points : int
        Points of the corridor the nominal's normals are read on.

    Returns
    -------
    list of (int, Obstacle)
        Each blocked obstacle and one of its blockers (label
        :data:`SIDE_BLOCKER`), the row's balls in order.
    """
    q = np.shape(nominal)[1]
    named = ("left", "right") if q == 2 else tuple(SIDES)
    wanted = [
        o
        for o, obstacle in enumerate(scene.obstacles)
        if obstacle.label in preferences and preferences[obstacle.label][0] in named
    ]
    if not wanted or q not in (2, 3):
        return []
    gaps = scene.distances(np.asarray(nominal, dtype=np.float64))
    corridor = Corridor.from_path(nominal, n_points)
    out: list[tuple[int, Obstacle]] = []
    for o in wanted:
        obstacle = scene.obstacles[o]
        side, within = preferences[obstacle.label]
        if gaps[o] >= within:
            continue
        rel = corridor.points - obstacle.position
        k = int(np.argmin(np.einsum("kq,kq->k", rel, rel)))
        if k in (0, corridor.n_points - 1):
            continue
        if q == 2:
            t = corridor.tangents[k]
            left = np.array([-t[1], t[0]]) / np.linalg.norm(t)
            # Kept on the path's left: the path passes on the obstacle's right, blocked on its left.
            blocked = [left if side == "left" else -left]
        else:
            axes = lateral_axes(corridor.tangents[k])
            if axes is None:  # a path near vertical: no left or up across it
                continue
            # Kept below the path: the path passes over it, blocked on its other sides: beside
            # it, below it and on the diagonals between (balls leave the corners open).
            axis, sign = SIDES[side]
            passed = -sign * axes[axis]
            turns = np.arange(8) * np.pi / 4
            around = np.cos(turns)[:, None] * axes[0] + np.sin(turns)[:, None] * axes[1]
            blocked = [d for d in around if float(d @ passed) < 0.5]
        rows: list[Obstacle] = []
        for away in blocked:
            reached = 0.0
            for _ in range(PREFERRED_CHAIN):  # each ball beyond the last, larger away from the ends
                ball = _blocker(obstacle, away, reached, ends)
                if ball is None:
                    break
                reached += 2.0 * ball.radius
                if q == 3 and abs(float(away @ passed)) < 0.5:
                    ball = _flush(obstacle, ball, passed, ends)
                rows.append(ball)
        if q == 3 and rows:
            rows += _fill_holes(obstacle, rows, axes, passed, blocked, ends)
        out += [(o, ball) for ball in rows]
    return out


def preferred_side_margins(
    scene: Scene, blocked: Iterable[int], clearances: Mapping[str, float]
) -> np.ndarray:
    """The clearance a plan keeps from each obstacle it passes on a preferred side.

    Past an obstacle kept on its side by :func:`preferred_side_blockers`, the
    plan goes the way the learned response does not: the response pushes it
    the other way (the shorter way round), towards the obstacle, so nothing
    learned holds it off; without a margin it passes at the tool's clearance
    where the person kept more. It keeps its class's learned clearance floor
    instead (:func:`lfdkit.emulate.fidelity.kept_sides`), a hard margin like a
    skill's floor.

    Parameters
    ----------
    scene : Scene
    blocked : iterable of int
        The obstacles kept on a side (the first items of
        :func:`preferred_side_blockers`' pairs; repeats allowed).
    clearances : mapping
        ``{class: units}``, the clearance kept from each class's obstacles
        passed by preference; a class left out keeps none.

    Returns
    -------
    ndarray, shape (n_obstacles,)
        Units, 0 for an obstacle not blocked.
    """
    margins = np.zeros(len(scene))
    for o in set(blocked):
        margins[o] = max(float(clearances.get(scene.labels[o], 0.0)), 0.0)
    return margins


def _fill_holes(
    obstacle: Obstacle,
    rows: list[Obstacle],
    axes: np.ndarray,
    passed: np.ndarray,
    blocked: list[np.ndarray],
    ends: np.ndarray,
) -> list[Obstacle]:
    """Balls that close the holes between the rows round a 3-D obstacle kept on one side.

    The rows' balls (every 45 degrees, each touching the next at a point) leave holes
    between two rows beyond their first balls: the benchmark's *over* person (seed 3)
    passed under a shelf it keeps below through one. In the plane across the path
    through the obstacle (where every row's centre lies), the points on the blocked
    side (not above the obstacle's extent along ``passed``) out to the shortest row's
    reach are sampled; the uncovered one nearest the obstacle gets a ball centred on
    it, as large as a row's ball there (:data:`BLOCKER_REACH` of its distance to the
    nearer end) but not rising above that extent, until none is left (or
    :data:`MAX_FILL` balls).
    """
    centre = obstacle.position
    cover, cover_radii = obstacle.balls()
    top = float(np.max((cover - centre) @ passed + cover_radii))
    reach = min(
        max(float((b.position - centre) @ d) + b.radius for b in rows if _along(b, centre, d))
        for d in blocked
        if any(_along(b, centre, d) for b in rows)
    )
    smallest = min(b.radius for b in rows)
    turns = np.deg2rad(np.arange(0.0, 360.0, 3.0))
    spokes = np.cos(turns)[:, None] * axes[0] + np.sin(turns)[:, None] * axes[1]
    distances = np.arange(1, 1 + int(np.ceil(4.0 * reach / smallest))) * (0.25 * smallest)
    points = (centre + distances[:, None, None] * spokes[None]).reshape(-1, centre.size)
    height = (points - centre) @ passed
    todo = height <= top - 0.1 * smallest  # the blocked side, below the way over
    todo &= np.linalg.norm(points - centre, axis=1) <= reach

    def outside(balls_at: np.ndarray, radii: np.ndarray) -> None:
        # Only the points still to do: the same numbers for them, a fraction of the work.
        among = np.flatnonzero(todo)
        gap = np.linalg.norm(points[among, None] - balls_at[None], axis=2) - radii[None]
        todo[among] = np.all(gap > 0.0, axis=1)

    outside(cover, cover_radii)
    outside(np.array([b.position for b in rows]), np.array([b.radius for b in rows]))
    order = np.argsort(np.linalg.norm(points - centre, axis=1), kind="stable")
    out: list[Obstacle] = []
    for i in order:
        if len(out) >= MAX_FILL:
            break
        if not todo[i]:
            continue
        radius = min(
            BLOCKER_REACH * float(np.linalg.norm(ends - points[i], axis=1).min()),
            top - float(height[i]),
        )
        todo[i] = False
        if radius < 0.1 * smallest:
            continue
        out.append(Obstacle(SIDE_BLOCKER, points[i], radius))
        todo &= np.linalg.norm(points - points[i], axis=1) > radius
    return out


def _along(ball: Obstacle, centre: np.ndarray, direction: np.ndarray) -> bool:
    """Whether ``ball`` is one of the row along ``direction`` (unit) from ``centre``."""
    offset = ball.position - centre
    return float(offset @ direction) > 0.9 * float(np.linalg.norm(offset))


def _flush(obstacle: Obstacle, ball: Obstacle, passed: np.ndarray, ends: np.ndarray) -> Obstacle:
    """A ball beside ``obstacle`` moved along ``passed`` (unit) until its top is level with it.

    A row beside an obstacle (3-D, :func:`preferred_side_blockers`) that rose above the
    obstacle would leave only a narrow slot to pass it the preferred way; level with the
    obstacle's extent along ``passed`` it leaves that side open. Kept where it is where
    moved it would come within a tenth of its radius of the task's start or goal.
    """
    centres, radii = obstacle.balls()
    top = float(np.max((centres - obstacle.position) @ passed + radii))
    moved = ball.position + passed * (
        top - ball.radius - float((ball.position - obstacle.position) @ passed)
    )
    if float(np.linalg.norm(ends - moved, axis=1).min()) <= 1.1 * ball.radius:
        return ball
    return Obstacle(SIDE_BLOCKER, moved, ball.radius)


def _stations(path: np.ndarray, points: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Arc length along ``path`` (2-D) of each point's foot, its signed lateral offset, the foot.

    Left of the path's direction is positive.
    """
    a, b = path[:-1], path[1:]
    ab = b - a
    length = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    rel = points[:, None, :] - a[None]
    t = np.clip(np.einsum("pij,ij->pi", rel, ab) / length, 0.0, 1.0)
    feet = a[None] + t[..., None] * ab[None]
    seg = np.argmin(np.linalg.norm(points[:, None, :] - feet, axis=2), axis=1)
    rows = np.arange(len(points))
    foot = feet[rows, seg]
    d = points - foot
    cross = ab[seg, 0] * d[:, 1] - ab[seg, 1] * d[:, 0]
    lateral = np.sign(cross) * np.linalg.norm(d, axis=1)
    starts = np.concatenate([[0.0], np.cumsum(np.sqrt(length))])
    along = starts[seg] + t[rows, seg] * np.sqrt(length[seg])
    return along, lateral, foot


def swerve_reach(
    demos: Sequence[np.ndarray],
    scenes: Sequence[Scene],
    nominals: Sequence[np.ndarray],
    *,
    level: float = REACH_LEVEL,
) -> tuple[float, float] | None:
    """How far along the path a demonstration's swerve round a lone obstacle lasts (2-D).

    For each demonstration with one obstacle (that it swerved round at all),
    the stretch of the nominal over which its distance from the nominal is
    at least ``level`` times its largest: how far before the obstacle's
    station the swerve reached that, and how far after it stayed there.
    The medians over the demonstrations. At the default level (a swerve
    *held*): the fidelity benchmark's late swerver, which holds its clearance
    from reacting to past the obstacle, 11.5-12.4 cm before and 5.6-7.2 cm
    after (seeds 0-3, 1x); the thesis's Gaussian bump 9-10 and 10-11 cm; the
    fixed-margin person's long triangle about 4 and 4 cm (41 cm in all at
    half its size).

    Parameters
    ----------
    demos, scenes, nominals : sequences
        The obstacle demonstrations (each (n, 2)), their scenes and nominals.
    level : float
        The part of the largest distance that counts as swerved, in (0, 1).

    Returns
    -------
    (before, after) : tuple of float or None
        Units; None without a 2-D single-obstacle demonstration.
    """
    before, after = [], []
    for demo, scene, nominal in zip(demos, scenes, nominals, strict=True):
        demo, nominal = np.asarray(demo, dtype=np.float64), np.asarray(nominal, dtype=np.float64)
        if len(scene) != 1 or demo.shape[1] != 2 or len(nominal) < 2:
            continue
        along, lateral, _ = _stations(nominal, demo)
        size = np.abs(lateral)
        if not size.max() > 0.0:
            continue
        station = _stations(nominal, scene.positions[:1])[0][0]
        swerved = along[size >= level * size.max()]
        before.append(max(station - float(swerved.min()), 0.0))
        after.append(max(float(swerved.max()) - station, 0.0))
    if not before:
        return None
    return float(np.median(before)), float(np.median(after))


def held_pairs(
    scene: Scene,
    path: np.ndarray,
    kept: np.ndarray,
    reach: tuple[float, float],
    cosine: float = 1.0,
    allowance: np.ndarray | None = None,
) -> list[tuple[int, int]]:
    """Pairs that a held swerve cannot pass between (2-D).

    In ``path``'s frame each obstacle covers a lateral band, its centre's
    offset plus and minus its radius and ``kept``. Two obstacles whose bands
    overlap leave no lateral room between them that keeps both clearances:
    a path between them must cross from one side to the other in the
    distance along the path between them. Where that distance is within the
    demonstrated swerve's reach (``reach``: before + after,
    :func:`swerve_reach`), the person is still swerved round the first when it
    meets the second, and goes round both on one side. Pairs whose surfaces
    touch are a wall already; only balls of a radius count (the row of
    :func:`bridge_blockers` fits inside their hull). Pairs at 45 degrees or more to the path count
    too (the late swerver, seed 1, 2x: two boxes 9.2 cm apart along the path
    and 9.6 cm across it, their 3.1 cm gap threaded): a gap straight across
    the path with overlapping bands is one narrower than the two clearances
    kept, closed anyway (:func:`close_narrow_gaps`).

    Parameters
    ----------
    scene : Scene
    path : ndarray, shape (n, 2)
        The nominal.
    kept : ndarray, shape (n_obstacles,)
        The clearance typically kept from each obstacle (units).
    reach : (float, float)
        The swerve's reach before and after an obstacle along the path (units).
    cosine : float
        As :func:`abreast_pairs`: pairs more nearly across the path than this
        are left out (default 1: none).
    allowance : ndarray, shape (n_obstacles,), optional
        How far each of ``kept`` may be over the person's own clearance
        (units, :func:`clearance_allowance`); a pair is held only where the
        bands still overlap with each narrowed by it (default: none).

    Returns
    -------
    list of (int, int)
    """
    path = np.asarray(path, dtype=np.float64)
    n = len(scene)
    if n < 2 or path.shape[1] != 2 or scene.moving:
        return []
    along, lateral, _ = _stations(path, scene.positions)
    kept = np.asarray(kept, dtype=np.float64)
    if allowance is not None:
        kept = kept - np.clip(np.asarray(allowance, dtype=np.float64), 0.0, kept)
    half = scene.radii + kept
    span = float(reach[0]) + float(reach[1])
    gaps = surface_gaps(scene)
    # Balls of a radius only: a row of balls fits inside their hull.
    round_ = [type(o) is Obstacle and o.radius > 0.0 for o in scene.obstacles]
    candidates = [
        (i, j)
        for i in range(n)
        for j in range(i + 1, n)
        if round_[i]
        and round_[j]
        and gaps[i, j] > 0.0
        and abs(lateral[i] - lateral[j]) < half[i] + half[j]
        and abs(along[i] - along[j]) <= span
    ]
    if cosine >= 1.0:
        return candidates
    abreast = set(abreast_pairs(candidates, scene, path, cosine))
    return [p for p in candidates if p not in abreast]


def bridge_blockers(
    scene: Scene,
    pairs: Sequence[tuple[int, int]],
    path: np.ndarray,
    kept: np.ndarray,
    ends: np.ndarray,
) -> list[Obstacle]:
    """Balls that close each of ``pairs`` and keep each group's first obstacle on its near side.

    Between the two centres of each pair, a row of balls of a little under
    the smaller radius, overlapping each other and both obstacles: no path
    passes between the two, and the row stays inside their convex hull, so
    it blocks no way round both. The obstacles the pairs join form groups;
    the first of a group along ``path`` is passed the shorter way, on the
    side of the path away from its centre (a person meets it first and
    swerves away from it), with a ball beside it on the other side
    (:func:`_blocker`); none where its centre lies within a tenth of its
    radius of the path, or where another of the group is met within its
    radius along the path (two abreast: met at once), nor for any group where
    the groups' firsts lie on both sides of the path.

    Parameters
    ----------
    scene : Scene
    pairs : sequence of (int, int)
        E.g. :func:`held_pairs`.
    path : ndarray, shape (n, 2)
        The nominal.
    kept : ndarray, shape (n_obstacles,)
        The clearance typically kept from each obstacle (units).
    ends : ndarray, shape (2, 2)
        The task's start and goal.

    Returns
    -------
    list of Obstacle
        Labelled :data:`SIDE_BLOCKER`.
    """
    if not pairs:
        return []
    path = np.asarray(path, dtype=np.float64)
    out: list[Obstacle] = []
    parent = list(range(len(scene)))

    def root(i: int) -> int:
        while parent[i] != i:
            i = parent[i]
        return i

    for i, j in pairs:
        a, b = scene.obstacles[i], scene.obstacles[j]
        radius = BRIDGE_FILL * min(a.radius, b.radius)
        length = float(np.linalg.norm(b.position - a.position))
        count = max(int(np.ceil(length / (1.5 * radius))), 1)  # overlapping
        for t in np.linspace(0.0, 1.0, count + 1):
            out.append(Obstacle(SIDE_BLOCKER, a.position + t * (b.position - a.position), radius))
        parent[root(i)] = root(j)
    along, lateral, foot = _stations(path, scene.positions)
    groups: dict[int, list[int]] = {}
    for i, j in pairs:
        for o in (i, j):
            members = groups.setdefault(root(o), [])
            if o not in members:
                members.append(o)
    sides: list[tuple[bool, Obstacle]] = []
    for members in groups.values():
        first = min(members, key=lambda o: (along[o], o))
        obstacle = scene.obstacles[first]
        offset = scene.positions[first] - foot[first]
        # Met first only where it leads the others by more than its radius: two abreast
        # (a pocket's arms) are met at once, and the plan keeps its own way round.
        ahead = min((along[o] - along[first] for o in members if o != first), default=np.inf)
        if ahead <= obstacle.radius or abs(lateral[first]) <= 0.1 * obstacle.radius:
            continue
        ball = _blocker(
            obstacle, offset / np.linalg.norm(offset), float(kept[first]), np.asarray(ends)
        )
        if ball is not None:
            sides.append((bool(lateral[first] > 0.0), ball))
    # Groups whose firsts lie on both sides of the path (a pocket's two arms, the late
    # swerver, seed 1: the way round each blocked the other's, Pr 87 -> -229 %): the ways
    # round are more than two, and the plan keeps its own.
    if len({left for left, _ in sides}) == 1:
        out.extend(ball for _, ball in sides)
    return out
