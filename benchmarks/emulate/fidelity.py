"""Fidelity of emulation: does a learned skill move around new obstacles as its person would?

Run ``python benchmarks/emulate_fidelity.py --quick`` (about 1 min with a warm
numba cache; the full run ``python benchmarks/emulate_fidelity.py`` about
5 min on the shared 2-core machine). Options: ``--seed N``; ``--units mm``
(the same study in millimetres); ``--people``, ``--sizes``, ``--per-family``;
``--skill-option key=value`` (repeatable, passed to
``lfdkit.skill.Skill(...)``), ``--plan-option key=value`` (to ``Skill.plan``)
and ``--fit-option key=value`` (to ``Skill.fit``), values read as Python
literals (``goal_approach=None``, ``planner='full'``), so variants of the
emulation layer can be compared side by side; ``--label`` names the run's
files. Prints one table, the median Pr per held-out family and the targets of
issue 26 as PASS/FAIL (worst over the settings run; exits 0 either way), and
writes ``fidelity[_<label>].json`` and ``fidelity[_<label>].png`` to
``--output`` (``benchmarks/results/emulate``). All work runs under
``threadpool_limits(1)``. Only lfdkit's public API is used (``Skill``,
``lfdkit.emulate.metrics``, the scene classes), so the same command runs on a changed
emulation layer.

Design
------
People (``benchmarks/emulate/people.py``, none of them uses lfdkit's planner):
``thesis`` (Gaussian reward per class, its own receding-horizon MPC with H = 5,
not told to lfdkit), ``margin`` (fixed surface margin per class, otherwise the
shortest path), ``field`` (a DMP with a repulsive potential field per class),
``late`` (reacts only within 8 cm, swerves steeply, returns slowly). Classes
``cup`` (r 3 cm) and ``box`` (r 5 cm), each with its own behaviour.

For each person, training size (4, 6, 10; quick: 6) and noise (1× = 2 mm and
2×; quick: both): ``Skill`` is fitted on 5 obstacle-free demonstrations of the
training task (a straight 0.8 m) and the first ``n`` of 10 single-obstacle
demonstrations (classes alternating) in their scenes. Held-out scenes, drawn
per seed and person (a draw where the person would come within 12 mm of an
obstacle or could not get through is redrawn): ``single`` (as in training),
``pair`` (a 3-10 cm gap), ``clutter`` (3-6 obstacles), ``pocket`` (a concave
arc of 4-5 cups), ``near_goal``, ``moved_goal`` (start and goal moved; the
person's own nominal is the task's, blended to the new ends) and ``new_task``
(an arc, an S-curve or a diagonal, 1-3 obstacles; the skill is
``copy.deepcopy(skill).fit_path(<5 free demonstrations of that task>)``, which
keeps the learned obstacle model). 4 scenes per family (quick: 2), the held-out
demonstrations with the same noise level as the training ones.

Each held-out scene is planned with ``skill.plan(start, goal, scene,
**plan_options)`` from the person's start to the task's goal and compared
with the person's path:

* Pr (thesis, SPEC §3): ``lfdkit.emulate.metrics.improvement(MSE_Mp, MSE_R)`` with
  ``MSE_Mp = mse_paths(skill.nominal(start, goal), person)`` and ``MSE_R`` the
  plan's; pooled (sums over the scenes, the thesis's), and per scene mean
  and median. 100 % is the person's path, 0 % no better than the nominal.
  Per-scene figures leave out *quiet* scenes, where the person's RMS distance
  from the nominal is below 5 mm (it hardly reacted, and Pr would divide by
  about the noise); for those the plan's largest RMS distance from the person
  is given instead (a plan that swerves where the person did not).
* Sides: per obstacle the person passes within 10 cm of, the side of the
  obstacle seen from the path at its closest point; agreement = same side.
* Collisions (``lfdkit.emulate.metrics.collisions``); clearance ratio = median over
  scenes of the plan's smallest clearance over the person's, and the
  smallest such ratio (``worst``).
* Gaps threaded: pairs of obstacles less than 15 cm apart (surface to surface)
  whose joining segment the plan crosses and the person's path does not.
* Ceilings per family, for every person (pooled Pr for the thesis person,
  the median per scene for the others: each target's measure): the
  person's own noise-free path against its noisy one (``noise``: what the
  noise leaves any plan), that path made to reach the goal (``goal``: its
  miss at the end clipped at one lateral step per step, :func:`goal_reaching`),
  and that carried onto the skill's nominal (``nominal``, :func:`carried`:
  the person's response at the same arc fraction and lateral offset from the
  skill's DMP nominal, which takes a moved goal or a new task its own way).
  The thesis's person has no goal term and ends 3-6 cm beside the goal when
  an obstacle is near it; a plan must reach the goal, so ``near_goal`` cannot
  score above about that ceiling (seeds 0-2: 72-77 %), nor ``pair`` at 2x
  noise above the noise one (the person hardly swerves: 68-78 %). The other
  people reach the goal themselves: their ``goal`` ceiling is the noise one.
  At 1x noise (quick; seed 0, and seed 1 for margin) every family's median ceiling is 85-100 %
  for the margin, field and late people (the skill's nominal costs moved_goal
  4-11 points): what they lose below that is the plan's obstacle response.
* Fit seconds (``Skill.fit``), plan milliseconds (median per scene), refused
  plans (any exception, recorded), train Pr (the training scenes replanned).
* DMP alone: the skill's nominal (its DMP, ``skill.nominal``) run as a DMP with
  movement_primitives' obstacle coupling term (``CouplingTermObstacleAvoidance2D``'s
  steering-angle equation, re-implemented in ``people.py``: the package is not
  a dependency), γ and β chosen on the training demonstrations.

Baseline (before the fidelity work: main at 0f01d8e, seed 0, full run, 305 s)
----------------------------------------------------------------------------
10 training demonstrations, 1× noise, 28 held-out scenes; lfdkit's plans had
0 collisions in all 24 settings.

===============  =========  =========  =====  ====  =========  =======  ========
person           Pr pooled  Pr median  sides  gaps  clearance  fit s    DMP Pr (median)
===============  =========  =========  =====  ====  =========  =======  ========
thesis MPC       4 %        91 %       79 %   3     0.98       1.0-2.7  −30 % (63 %)
fixed margin     60 %       83 %       90 %   8     0.75       1.5-3.7  15 % (51 %)
potential field  60 %       46 %       98 %   1     1.03       1.6-2.0  −686 % (−206 %)
late swerver     34 %       82 %       93 %   1     1.03       2.1-3.7  46 % (47 %)
===============  =========  =========  =====  ====  =========  =======  ========

(fit: two runs on the shared machine). Targets of issue 26, worst over the 24
settings: thesis Pr per family −48 % (clutter, 4 demonstrations, 2×), other
people's median Pr 31 % (field, 6, 2×), sides 86 % (margin, 4, 2×),
0 collisions, 108 gaps threaded, 30 plans refused, fit at most 3.7 s.
Seed 1 (``--seed 1``, 315 s; 10 demonstrations, 1×, pooled / median Pr):
thesis 44 % / 92 %, margin 57 % / 84 %, field −62 % / 34 %, late 46 % / 78 %;
over its 24 settings 0 collisions, 103 gaps threaded, 10 refused, sides down
to 75 % (late, 6, 2×).

Fewer demonstrations change little (thesis 4/6/10: the same figures to a point;
margin with 4 at 2× noise: pooled 25 %); with 6 potential-field demonstrations
15 of 28 plans are refused (``UnsafePlanError``: the plan ends 1-3 cm from the
goal). Per-family medians (10, 1×): thesis clutter −12 %, new tasks −9 %;
margin pairs 18 %; field near the goal 24 %; late new tasks −1170 % (the
person hardly swerved, the plan did). ``--quick`` (6 demonstrations, 14
scenes, about 45 s), pooled / median Pr at 1×: thesis 26 % / 90 %, margin
59 % / 73 %, field 63 % / 41 % (6 of 14 held-out plans refused), late
−11 % / 76 %; 0 collisions.

With the nearest goal join (branch ``emulate``, seed 0, full run, 1680 s on
the shared machine under load; 10 demonstrations, 1×, pooled / median Pr):
thesis 73 % / 96 %, margin 49 % / 83 %, field 52 % / 48 %, late 64 % / 84 %;
over the 24 settings 0 collisions, 0 refused, 22 gaps threaded, sides down to
86 % (margin, 4, 2×). Thesis medians per family: single 99 %, pair −964 %
(two of four pairs: the person hardly swerves, and the learned clearance
floor closes the gap it threads; ``model="thesis"`` plans them at 94 and
98 %), clutter 92 %, pocket 100 %, near the goal 76 % (69 % with the 10 %
goal ramp; the person has no goal term and ends 3-5 cm beside the goal: its
own path clipped to reach the goal within the action bound scores 76 %, so
no goal-reaching plan reaches 90 % there), moved goal 98 %, new tasks 94 %.
``--quick --seed 1``: thesis 53 % / 99 %, margin −13 % / 80 %, field −88 % /
34 %, late 62 % / 84 %. ``--skill-option model="'path'"`` (responses in the
nominal's frame), quick, 1×, pooled / median: seed 0 thesis 45 % / 96 %
(new tasks −118 %), margin 61 % / 86 %, field −0 % / 46 %, late 62 % / 83 %;
seed 1 thesis 51 % / 96 %, margin −74 % / 79 %, field −43 % / 35 %, late
57 % / 84 %.

Safety floor for every model (session 38, ``lfdkit.emulate.gaps``; seed 0,
quick, side by side with main 80cc6ac; pooled / median Pr, worst clearance
over the person's): thesis 10 1x 96 / 97 %, 0.60 → 96 / 97 %, 0.60 (the
floor would move that one plan's route, so it is dropped there and warned;
median clearance 0.98 → 1.08); thesis 6 1x 96 / 97 %, 0.65 → 95 / 97 %,
0.94; margin 6 1x 59 / 74 %, 1.03 → 69 / 89 %, 0.95 (clutter 30 → 90 %);
margin 6 2x 69 / 79 %, 0.35 → 69 / 76 %, 0.93; thesis 2x and field
unchanged; 0 collisions, 0 refused, gaps threaded unchanged (0-1).

The swerve fitted by its stretches alone (session 40, ``IOC(swerve_only=True)``;
quick, 10 demonstrations, field person, 1x / 2x, pooled / median Pr, sides,
worst clearance; before: all of θ refitted): seed 0 −2/89 %, 89 %, 0.52 and
−6/90 %, 89 %, 0.46 → 83/76 %, 100 %, 0.75 and 83/75 %, 100 %, 0.69 (clutter
median −148 → 86 %, new tasks −212 → 78 %); seed 1 (the swerve was left out
before) −101/34 %, 81 % and −33/44 %, 85 % → −14/75 %, 89 % and 31/73 %, 92 %;
seed 2 93/93 %, 100 %, 0.95 and 93/92 %, 100 %, 0.76 → 90/81 %, 100 %, 0.85 and
90/83 %, 100 %, 0.82. ``--units mm``: the same figures as metres (seeds 0 and
1, thesis and margin people: the same model chosen, Pr per scene within 0.01
points; before, the margin person demonstrated other paths in mm). The
thesis, margin and late people do not pass the swerve's gate (0.45: their
screens 0.98-0.99, 0.63-0.76, 0.56-0.72) and are unchanged.

The taut model (``"taut+typical"``, :func:`lfdkit.emulate.taut.taut_plan`: the
shortest path in the nominal's frame round the obstacles keeping the typical
demonstrated clearance; quick, 10 demonstrations, side by side with bf9ddff;
pooled / median Pr, sides): margin person seed 0 1x 68/74 %, 96 % -> 97/98 %,
100 %; 2x 69/74 %, 96 % -> 96/96 %, 100 % (clutter 27 -> 99 %, moved goal
54 -> 77 %, near the goal 40 -> 29 %: this person's ties between equally long
grid paths put a shallow swerve late or early, the taut string spreads it from
the start); seed 1 1x 78/84 % -> 97/96 %; 2x unchanged (78/83 %: the taut
model's cross-validated error 6 % above the demonstrated floor's, not chosen);
seed 2 1x 81/79 % -> 99/99 %, 2x 80/76 % -> 98/98 %. ``--sizes 5``, seed 0:
1x 52/57 % -> 74/96 %, 2x 12/61 % -> 71/91 %. Another fixed-margin person
(cup 3 cm, box 2.5 cm, smoothing 3; seed 0): 1x 74/82 % -> 94/93 %, 2x
75/76 % -> 93/90 %. The thesis's, potential-field and late people keep their
models and figures (seeds 0-2; its error is larger for their local swerves);
0 collisions, gaps threaded unchanged. Fit CPU time the same (margin person,
10 demonstrations: 2.8-3.2 s before, 2.9-3.0 s after); a taut plan takes a
fifth of the CPU time of the plan it replaces (5 against 23-25 ms).

A demonstration no plan of the reward takes on its side, left out of the fit
(``Skill.fit_reward``; quick, 10 demonstrations, pooled / mean / median Pr,
sides): the potential-field person, seed 3, passes a box 5 mm beside the path
15 cm away on its own side (demonstration 9); fitted with it, ``Q`` sat on its
plausibility wall and nothing held plans on their nominals (1x: −41/−7/90 %,
sides 71 %; clutter planned 10 cm off on the other side). Left out: 1x
79/43/94 %, sides 96 %; 2x 10/−52/41 %, 79 % → −12/−4/46 %, 83 % (there the
swerve candidate loses the choice on one fold's side flip, and window+closest
is chosen at a cross-validated median of 56 %). Seeds 0-2 (all four people on
seed 0) leave nothing out and are unchanged to the digit. Not this: the late
swerver, seed 2 (−26/−3/86 %, sides 76 %): its ``Q'`` fits at 1.1e-3, at the
wall, so on the S-curve the tails of boxes 15 cm ahead steer the plan off its
nominal from the start (×100 ``Q``: Pr −609 → 87 %); in one clutter scene
the route without the goal term keeps every side (Pr 78 %), but its way back
after the last box does not fit the action bound (the person returns at a
slope of about 3) and the goal-reaching plan takes the other side (−65 %).
Why ``Q'`` sits on its wall there: the thesis's bump pulls the plan back as
steeply as it went out, and this person returns at a fifth of that; the
closest the model comes to a slow return is nothing pulling back, so the fit
lowers ``Q`` to the wall (its loss flat there: ``Q`` reported unidentified,
relative error 7), and the swerve's stretches, fitted with that ``Q`` held,
gain nothing (training loss 0.99 of the thesis's).

The swerve chosen by its held-out error (``SWERVE_MARGIN``, 0.35 of the best
other model's), not screened by its training loss (0.45 of the thesis's):
quick, 10 demonstrations, side by side with 2f1f475. Seeds 0-3, all four
people, 1x and 2x: the same model chosen and the same figures to the digit
(held-out error over the best other model's: potential field 0.10-0.19,
late 0.64-1.07, margin 0.70-2.7, thesis 1.0-1.08; at the old screen the late
swerver's swerve, chosen by its held-out error alone, lost on seed 0:
pooled / median Pr 78/82 → −5/77 %, sides 100 → 85 %, new tasks −810 →
−11391 %). Potential-field people of other parameters (gains 20/35, 45/75,
60/100, 15/25 m/s², rotational part 0-1.0, reaches 4/7 and 9/15 cm; seeds
0-3): held-out ratios 0.07-0.20, the swerve chosen everywhere; the one whose
training ratio crossed 0.45 (no rotational part, seed 3, 2x: 0.452) lost it
before: 9/42 %, sides 83 % → 38/90 %, 83 % (window+closest → window/swerve).
Fit CPU seconds (seed 0, 1x, two fits each, the second): thesis 2.7 → 3.2,
margin 3.2 → 3.5, field 3.7 → 3.3, late 2.1 → 2.7 (the swerve's fit and
folds now run for every person).

The thesis target against the recorded and the noise-free path (quick, 10
demonstrations, pooled Pr per family, as measured / vs clean; both are in
the targets). Pairs at 2x noise: seed 0 65/94 %, seed 1 65/94 %, seed 2
79/98 %; the person hardly swerves there (RMS 7-9 mm from the nominal, the
noise 4 mm), so its own noise-free path scores 74-82 % against its recorded
one and no plan can pass 90 % by that measure (per scene: the plan's 64 and
74 % against that ceiling's 74 and 82 %, seed 0). Moved goals, seed 3:
−108/−109 % at 1x, one scene at −136 %: the cup stands 1-2 cm from both
nominals (the person's blended task nominal and the skill's DMP one), the
person passes it below and the plan above; the person itself planned on the
skill's nominal passes it above too (ceiling ``own`` −107 %), so the side is
the two nominals' coin flip, not the obstacle response. Left below 90 % on
both measures: seed 3 clutter 89/89 % and new tasks 88/89 %; near the goal
77-79 % everywhere (the ``goal`` ceiling, 76-78 %).
"""

from __future__ import annotations

import argparse
import ast
import copy
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from lfdkit.core.geometry import resample
from lfdkit.emulate.metrics import clearance, collisions, improvement, mse_paths
from lfdkit.model.scene import Scene

from . import people as P

try:  # issue 28 may move the module; the class is the public API either way
    from lfdkit.skill import Skill
except ImportError:  # pragma: no cover
    from lfdkit import Skill

SIZES = (4, 6, 10)
QUICK_SIZES = (6,)
NOISES = (1.0, 2.0)
POOL = 10
N_FREE = 5
ENCOUNTER = 0.10  # m: obstacles the person passes this close count for sides
GAP = 0.15  # m: pairs closer than this (surface to surface) count for gaps
QUIET = 0.005  # m: a person this close to the nominal (RMS) hardly reacted
GAMMAS = (0.0, 10.0, 30.0, 100.0, 300.0, 1000.0)
BETAS = (1.0, 20.0 / np.pi, 10.0)
QUICK_GAMMAS = (0.0, 100.0, 1000.0)
QUICK_BETAS = (20.0 / np.pi,)
_STARTED = time.perf_counter()


def progress(message: str) -> None:
    sys.stdout.flush()
    print(f"[{time.perf_counter() - _STARTED:6.1f} s] {message}", file=sys.stderr, flush=True)


def parse_options(items: list[str] | None, name: str) -> dict:
    """``key=value`` strings to a dict; values as Python literals, else strings."""
    out = {}
    for item in items or ():
        key, sep, value = item.partition("=")
        if not sep or not key:
            raise SystemExit(f"{name}: expected key=value, got {item!r}")
        try:
            out[key] = ast.literal_eval(value)
        except (ValueError, SyntaxError):
            out[key] = value
    return out


# ----------------------------------------------------------------------------- data
def _rng(seed: int, *keys: int) -> np.random.Generator:
    return np.random.default_rng([seed, *keys])


def person_data(
    kind: str, seed: int, scale: float, per_family: int, person: P.Person | None = None
) -> dict:
    """Clean paths of one person: free demos per task, training pool, held-out cases.

    ``person`` (default: ``kind``'s own, :func:`people.make_person`) is another
    person drawn with ``kind``'s scenes (the same random streams), as
    ``benchmarks/emulate/probe.py`` does with other parameters.
    """
    k = P.KINDS.index(kind) if kind in P.KINDS else len(P.KINDS)
    person = person or P.make_person(kind, scale)
    data = {"kind": kind, "description": person.describe(), "free": {}, "train": [], "held": []}
    # The person itself (a probe's variant is not its kind's own): run_setting's "own" ceiling.
    data["person"] = person
    for t, task in enumerate(("train", *P.NEW_TASKS)):
        nominal = P.task_nominal(task, scale)
        clean = person.clean(nominal, Scene())
        data["free"][task] = [(clean, (seed, k, 1, t, i)) for i in range(N_FREE)]

    def draw(family: str, rng, label=None):
        for _ in range(60):
            case = P.draw_case(family, rng, scale, label=label)
            if case is None:
                continue
            try:
                return case, person.clean(case.nominal, case.scene)
            except P.PersonFailed:
                continue
        return None

    for i in range(POOL):
        got = draw("train", _rng(seed, k, 2, i), label=P.CLASSES[i % 2])
        if got is None:
            raise RuntimeError(f"{kind}: no usable training scene {i}")
        data["train"].append((*got, (seed, k, 3, i)))
    data["skipped"] = []
    for f, family in enumerate(P.FAMILIES):
        for i in range(per_family):
            got = draw(family, _rng(seed, k, 4, f, i))
            if got is None:
                data["skipped"].append(f"{family} {i}")
                continue
            data["held"].append((*got, (seed, k, 5, f, i)))
    return data


def noisy(clean: np.ndarray, key: tuple, level: float, scale: float) -> np.ndarray:
    return P.add_noise(clean, level * P.NOISE * scale, np.random.default_rng(list(key)))


# ----------------------------------------------------------------------------- measures
def _closest(path: np.ndarray, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Closest point of a polyline to ``point`` and the direction of its segment."""
    a, b = path[:-1], path[1:]
    ab = b - a
    t = np.clip(np.einsum("ij,ij->i", point - a, ab) / np.maximum((ab**2).sum(1), 1e-300), 0, 1)
    foot = a + t[:, None] * ab
    i = int(np.argmin(np.linalg.norm(foot - point, axis=1)))
    return foot[i], ab[i]


def side(path: np.ndarray, point: np.ndarray) -> int:
    """+1 when ``point`` is left of the path at the path's closest point, −1 right."""
    foot, direction = _closest(path, point)
    d = point - foot
    return 1 if direction[0] * d[1] - direction[1] * d[0] > 0.0 else -1


def crosses(path: np.ndarray, p: np.ndarray, q: np.ndarray) -> bool:
    """Whether the polyline crosses the segment ``p``–``q``."""
    a, b = path[:-1], path[1:]

    def orient(u, v, w):
        return (v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1]) - (v[..., 1] - u[..., 1]) * (
            w[..., 0] - u[..., 0]
        )

    o1, o2 = orient(a, b, p), orient(a, b, q)
    o3, o4 = orient(p, q, a), orient(p, q, b)
    return bool(np.any((o1 * o2 < 0) & (o3 * o4 < 0)))


def compare(plan: np.ndarray, person: np.ndarray, nominal: np.ndarray, scene: Scene, scale: float):
    """Measures of one plan against the person's path in one scene."""
    mse_mp = mse_paths(nominal, [person])
    mse_r = mse_paths(plan, [person])
    out = {
        "mse_mp": mse_mp,
        "mse_r": mse_r,
        "pr": improvement(mse_mp, mse_r) if mse_mp > 0 else None,
        "collisions": collisions(plan, scene),
        # The person hardly reacted: a per-scene Pr would divide by about the noise.
        "quiet": bool(np.sqrt(mse_mp) < QUIET * scale),
    }
    gaps_person = clearance(person, scene)
    gaps_plan = clearance(plan, scene)
    out["clear_person"] = float(gaps_person.min())
    out["clear_plan"] = float(gaps_plan.min())
    encounters = agree = 0
    for o, g in zip(scene.obstacles, gaps_person, strict=True):
        if g <= ENCOUNTER * scale:
            encounters += 1
            agree += side(plan, o.position) == side(person, o.position)
    out["encounters"], out["agree"] = encounters, agree
    threaded = person_threads = pairs = 0
    obs = scene.obstacles
    for i in range(len(obs)):
        for j in range(i):
            gap = np.linalg.norm(obs[i].position - obs[j].position) - obs[i].radius - obs[j].radius
            if gap >= GAP * scale:
                continue
            pairs += 1
            by_person = crosses(person, obs[i].position, obs[j].position)
            person_threads += by_person
            threaded += crosses(plan, obs[i].position, obs[j].position) and not by_person
    out["pairs"], out["gaps_threaded"], out["person_threads"] = pairs, threaded, person_threads
    return out


def goal_reaching(path: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """``path`` made to end at ``goal``: its end's miss clipped at one lateral step per step.

    The nearest path to ``path`` that reaches ``goal`` within the thesis's action
    bound (slope 1; the step is ``path``'s mean): it leaves ``path`` only where
    the steps left are too few to come back. For a person who ends beside the
    goal (the thesis's person has no goal term), a goal-reaching plan can do
    little better against that person than this path does.
    """
    miss = path[-1] - goal
    size = float(np.linalg.norm(miss))
    if size == 0.0:
        return path
    step = float(np.mean(np.linalg.norm(np.diff(path, axis=0), axis=1)))
    left = (len(path) - 1 - np.arange(len(path))) * step
    return path - np.clip(1.0 - left / size, 0.0, 1.0)[:, None] * miss


def carried(path: np.ndarray, nominal: np.ndarray, onto: np.ndarray, scale: float) -> np.ndarray:
    """``path``'s response to ``nominal`` (arc position, lateral offset) carried onto ``onto``.

    Each point of ``path`` is projected on ``nominal`` (nearest of 2000 stations)
    and put at the same arc fraction and lateral offset from ``onto``. With
    ``onto`` the skill's nominal this is the person's obstacle response on the
    skill's own nominal: the best a plan can do against that person while its
    nominal carries the task to a moved goal (or a new task) its own way.
    """
    source, target = P.Frame(nominal, scale, 2000), P.Frame(onto, scale, 2000)
    out = np.empty_like(path)
    for i, point in enumerate(path):
        k, e = source.project(point)
        out[i] = target.points[k] + e * target.normals[k]
    return out


#: Ceilings (:func:`summary`): name and the per-scene key of the stand-in plan's MSE.
CEILINGS = (
    ("noise", "mse_clean"),
    ("goal", "mse_clean_goal"),
    ("nominal", "mse_clean_nominal"),
    ("own", "mse_own_nominal"),
)


def summary(scores: list[dict]) -> dict:
    """Pooled and per-scene figures of a list of :func:`compare` results."""
    done = [s for s in scores if s is not None and "mse_r" in s]
    if not done:
        return {"n": 0}
    prs = [s["pr"] for s in done if s["pr"] is not None and not s["quiet"]]
    quiet = [np.sqrt(s["mse_r"]) for s in done if s["quiet"]]
    enc = sum(s["encounters"] for s in done)
    ratios = [
        s["clear_plan"] / s["clear_person"]
        for s in done
        if "clear_person" in s and s["clear_person"] > 0
    ]
    return {
        "n": len(done),
        "pr_pooled": improvement(sum(s["mse_mp"] for s in done), sum(s["mse_r"] for s in done)),
        # Pr against the person's noise-free path: the noise divides no figure by itself.
        "pr_pooled_clean": improvement(
            sum(s["mse_mp_clean"] for s in done), sum(s["mse_r_clean"] for s in done)
        )
        if all("mse_mp_clean" in s for s in done)
        else None,
        "pr_mean": float(np.mean(prs)) if prs else None,
        "pr_median": float(np.median(prs)) if prs else None,
        "quiet": len(quiet),
        "quiet_rms_max": float(np.max(quiet)) if quiet else None,
        "sides": sum(s["agree"] for s in done) / enc if enc else None,
        "encounters": enc,
        "collisions": int(sum(s["collisions"] for s in done)),
        "gaps_threaded": int(sum(s.get("gaps_threaded", 0) for s in done)),
        "person_threads": int(sum(s.get("person_threads", 0) for s in done)),
        "clearance_ratio": float(np.median(ratios)) if ratios else None,
        "clearance_ratio_min": float(np.min(ratios)) if ratios else None,
        # Ceilings (pooled Pr, and median per scene like pr_median): the person's own
        # noise-free path, as it is (what the noise leaves), made to reach the goal
        # (:func:`goal_reaching`), and carried onto the skill's nominal (:func:`carried`).
        **{
            f"ceiling_{name}": improvement(
                sum(s["mse_mp"] for s in done), sum(s[key] for s in done)
            )
            for name, key in CEILINGS
            if all(key in s for s in done)
        },
        **{
            f"ceiling_{name}_median": float(
                np.median(
                    [
                        improvement(s["mse_mp"], s[key])
                        for s in done
                        if s["pr"] is not None and not s["quiet"]
                    ]
                )
            )
            for name, key in CEILINGS
            if prs and all(key in s for s in done)
        },
    }


# ----------------------------------------------------------------------------- DMP alone
def steering(scene: Scene, gamma: float, beta: float):
    """movement_primitives' ``CouplingTermObstacleAvoidance2D``, summed over obstacles.

    ``C = γ R ẏ θ exp(−βθ)`` with ``θ`` the angle between the velocity and the
    direction to the obstacle and ``R`` the quarter turn away from it.
    """
    centres = [o.position for o in scene.obstacles]

    def accel(y, yd):
        total = np.zeros(2)
        speed = float(np.hypot(*yd))
        for c in centres:
            d = c - y
            z = d[0] * yd[1] - d[1] * yd[0]
            turned = (1.0 if z >= 0.0 else -1.0) * np.array([-yd[1], yd[0]])
            cos = (d @ yd) / (np.hypot(*d) * speed + 1e-10)
            theta = np.arccos(np.clip(cos, -1.0, 1.0))
            total += gamma * turned * theta * np.exp(-beta * theta)
        return total

    return accel


def dmp_path(nominal: np.ndarray, scene: Scene, gamma: float, beta: float, n: int) -> np.ndarray:
    nominal = resample(nominal, 200)
    if gamma == 0.0 or not len(scene):
        return resample(nominal, n)
    path = P.dmp_with_coupling(nominal, steering(scene, gamma, beta), n_steps=500)
    moving = np.linalg.norm(np.diff(path, axis=0), axis=1) > 0.0
    return resample(path[np.r_[True, moving]], n)


def tune_dmp(skill, demos, scenes, goal, quick: bool) -> tuple[float, float]:
    best = (np.inf, 0.0, 0.0)
    nominals = [skill.nominal(d[0], goal) for d in demos]
    for gamma in QUICK_GAMMAS if quick else GAMMAS:
        for beta in (QUICK_BETAS if quick else BETAS) if gamma else BETAS[:1]:
            try:
                paths = [
                    dmp_path(nm, s, gamma, beta, len(d))
                    for nm, s, d in zip(nominals, scenes, demos, strict=True)
                ]
                score = mse_paths(paths, demos)
            except (P.PersonFailed, ValueError):
                continue
            if score < best[0]:
                best = (score, gamma, beta)
    return best[1], best[2]


# ----------------------------------------------------------------------------- one setting
def run_setting(data, n_train, level, scale, args, options) -> dict:
    skill_opts, plan_opts, fit_opts = options
    units = "mm" if scale == 1000.0 else "m"
    free = [noisy(c, key, level, scale) for c, key in data["free"]["train"]]
    train = data["train"][:n_train]
    demos = [noisy(clean, key, level, scale) for _, clean, key in train]
    scenes = [case.scene for case, _, _ in train]
    row = {"kind": data["kind"], "n_train": n_train, "noise": level, "refused": []}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        started = time.perf_counter()
        try:
            skill = Skill(units=units, **skill_opts).fit(free, demos, scenes, **fit_opts)
        except Exception as exc:  # recorded: a fit that fails is a result
            row["fit_error"] = f"{type(exc).__name__}: {exc}"
            return row
        row["fit_s"] = time.perf_counter() - started
    row["fit_warnings"] = sorted({str(w.message)[:200] for w in caught})
    info = getattr(skill, "ioc_info_", None) or {}
    row["ioc"] = {k: info.get(k) for k in ("loss", "converged", "not_learned", "seconds")}
    selection = getattr(skill, "model_selection_", None) or {}
    chosen = selection.get("candidates", {}).get(selection.get("chosen"), {})
    row["model"] = {
        "chosen": selection.get("chosen"),
        "runner_up": selection.get("runner_up"),
        "cv_pr_median": chosen.get("improvement_median"),
        "cv_pr_pooled": chosen.get("improvement_pooled"),
        "cross_validated": selection.get("cross_validated"),
        # the stretches' training loss over the thesis reward's, and the stretches learned
        "swerve_gain": selection.get("swerve_gain"),
        "swerve": selection.get("swerve"),
    }
    task_skills = {"train": skill}

    def skill_for(task: str):
        if task not in task_skills:
            own = [noisy(c, key, level, scale) for c, key in data["free"][task]]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                task_skills[task] = copy.deepcopy(skill).fit_path(own)
        return task_skills[task]

    def plan_one(sk, case, person, label):
        start, goal = person[0], case.goal
        try:
            nominal = sk.nominal(start, goal)
            t = time.perf_counter()
            plan = np.asarray(sk.plan(start, goal, case.scene, **plan_opts))
            elapsed = time.perf_counter() - t
        except Exception as exc:  # a refused plan is a result
            row["refused"].append(f"{label}: {type(exc).__name__}: {str(exc)[:160]}")
            return None, None, None
        return plan, nominal, elapsed

    # Training scenes replanned.
    train_scores = []
    for j, ((case, _, _), demo) in enumerate(zip(train, demos, strict=True)):
        plan, nominal, _ = plan_one(skill, case, demo, f"train {j}")
        if plan is not None:
            train_scores.append(compare(plan, demo, nominal, case.scene, scale))
    row["train"] = summary(train_scores)

    # The probe's people carry parameters of their own (and names make_person does not know).
    person_model = data.get("person") or P.make_person(data["kind"], scale)
    gamma, beta = tune_dmp(skill, demos, scenes, P.task_nominal("train", scale)[-1], args.quick)
    row["dmp_gamma"], row["dmp_beta"] = gamma, beta
    scores, dmp_scores, times, examples = [], [], [], {}
    for i, (case, clean, key) in enumerate(data["held"]):
        person = noisy(clean, key, level, scale)
        sk = skill_for(case.task)
        label = f"{case.family} {case.task} {i}"
        plan, nominal, elapsed = plan_one(sk, case, person, label)
        dmp = dmp_path(sk.nominal(person[0], case.goal), case.scene, gamma, beta, len(person))
        dmp_score = compare(dmp, person, sk.nominal(person[0], case.goal), case.scene, scale)
        dmp_score["family"] = case.family
        dmp_scores.append(dmp_score)
        if plan is None:
            scores.append({"family": case.family, "refused": True})
            continue
        times.append(elapsed)
        score = compare(plan, person, nominal, case.scene, scale)
        score["family"] = case.family
        score["mse_clean"] = mse_paths(clean, [person])
        score["mse_clean_goal"] = mse_paths(goal_reaching(clean, case.goal), [person])
        score["mse_clean_nominal"] = mse_paths(
            carried(goal_reaching(clean, case.goal), case.nominal, nominal, scale), [person]
        )
        score["mse_mp_clean"] = mse_paths(nominal, [clean])
        score["mse_r_clean"] = mse_paths(plan, [clean])
        # The person itself run on the skill's nominal (its side choice there), made to reach
        # the goal: unlike `carried`, it keeps no side the other nominal would not give.
        try:
            own = person_model.clean(resample(nominal, 400), case.scene)
            score["mse_own_nominal"] = mse_paths(goal_reaching(own, case.goal), [person])
        except P.PersonFailed:
            score["mse_own_nominal"] = score["mse_clean_nominal"]
        scores.append(score)
        examples.setdefault(case.family, (case, person, plan, dmp, nominal))
    row["held"] = summary(scores)
    row["dmp"] = summary(dmp_scores)
    row["by_family"] = {f: summary([s for s in scores if s.get("family") == f]) for f in P.FAMILIES}
    row["scenes"] = scores
    row["plan_ms"] = float(np.median(times) * 1e3) if times else None
    row["_examples"] = examples
    row["_train"] = (demos, scenes)
    return row


def warm_up(scale: float, options) -> None:
    """One small untimed fit and plan, so numba's compilation is not in the first fit's time."""
    progress("warm-up fit (compiles the numba kernels on a cold cache) ...")
    person = P.make_person("late", scale)
    nominal = P.task_nominal("train", scale)
    free = [noisy(person.clean(nominal, Scene()), (0, i), 1.0, scale) for i in range(3)]
    rng = np.random.default_rng(0)
    cases = [P.draw_case("train", rng, scale, label=c) for c in P.CLASSES]
    demos = [person.clean(c.nominal, c.scene) for c in cases]
    units = "mm" if scale == 1000.0 else "m"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            skill = Skill(units=units, **options[0]).fit(
                free, demos, [c.scene for c in cases], **options[2]
            )
            skill.plan(demos[0][0], nominal[-1], cases[0].scene, **options[1])
        except Exception as exc:  # the real settings record their own errors
            progress(f"   warm-up failed: {type(exc).__name__}: {exc}")


# ----------------------------------------------------------------------------- output
def _f(x, fmt="{:.0f}", none="—"):
    return none if x is None or (isinstance(x, float) and not np.isfinite(x)) else fmt.format(x)


def print_table(rows: list[dict], scale: float) -> None:
    print(
        "\nFidelity on held-out scenes (Pr %: pooled / mean / median per scene where the person"
        " reacted; quiet: scenes where it did not (RMS from the nominal < 5 mm), and the plan's"
        " largest RMS distance from the person there; sides: agreement"
        " with the person; coll: collisions; gaps: threaded where the person went round;"
        " clear: plan / person smallest clearance, median over the scenes, worst: the smallest;"
        " DMP: the skill's DMP with movement_primitives' coupling term)"
    )
    head = (
        f"{'person':<7} {'n':>2} {'noise':>5} {'scenes':>6} {'Pr pooled':>9} {'mean':>6} "
        f"{'median':>6} {'quiet':>9} {'sides':>6} {'coll':>4} {'gaps':>4} {'clear':>5} "
        f"{'worst':>5} "
        f"{'refused':>7} "
        f"{'fit s':>6} {'plan ms':>7} {'train Pr':>8} {'DMP Pr':>7} {'DMP med':>7} "
        f"{'DMP sides':>9} {'DMP coll':>8}"
    )
    print(head)
    for r in rows:
        if "fit_error" in r:
            print(
                f"{r['kind']:<7} {r['n_train']:>2} {r['noise']:>4.0f}x  "
                f"fit failed: {r['fit_error']}"
            )
            continue
        h, d, t = r["held"], r["dmp"], r["train"]
        quiet_mm = h.get("quiet_rms_max") and 1e3 * h["quiet_rms_max"] / scale
        print(
            f"{r['kind']:<7} {r['n_train']:>2} {r['noise']:>4.0f}x {h.get('n', 0):>6} "
            f"{_f(h.get('pr_pooled')):>8}% {_f(h.get('pr_mean')):>5}% {_f(h.get('pr_median')):>5}% "
            f"{h.get('quiet', 0):>2} {_f(quiet_mm):>3} mm "
            f"{_f(h.get('sides') and 100 * h['sides']):>5}% {h.get('collisions', 0):>4} "
            f"{h.get('gaps_threaded', 0):>4} {_f(h.get('clearance_ratio'), '{:.2f}'):>5} "
            f"{_f(h.get('clearance_ratio_min'), '{:.2f}'):>5} "
            f"{len(r['refused']):>7} {r['fit_s']:>6.1f} {_f(r['plan_ms'], '{:.1f}'):>7} "
            f"{_f(t.get('pr_pooled')):>7}% {_f(d.get('pr_pooled')):>6}% "
            f"{_f(d.get('pr_median')):>6}% "
            f"{_f(d.get('sides') and 100 * d['sides']):>8}% {d.get('collisions', 0):>8}"
        )
    print("\nMedian Pr % per held-out family (largest training set, 1x noise):")
    print(f"{'person':<7} " + " ".join(f"{f:>10}" for f in P.FAMILIES))
    for r in rows:
        if (
            "by_family" not in r
            or r["noise"] != 1.0
            or r["n_train"] != max(x["n_train"] for x in rows)
        ):
            continue
        print(
            f"{r['kind']:<7} "
            + " ".join(f"{_f(r['by_family'][f].get('pr_median')):>9}%" for f in P.FAMILIES)
        )
    print(
        "\nPr % per family / its ceilings (the target's measure: pooled for the thesis person,"
        " median per scene for the others): the person's noise-free path as it is (noise), made"
        " to reach the goal (goal: the thesis person has no goal term, and a plan must reach the"
        " goal), and that carried onto the skill's nominal (nominal: what is left when the"
        " skill's DMP takes the task to a moved goal or a new task its own way)"
    )
    columns = (*P.FAMILIES, "all")
    print(f"{'person':<7} {'n':>2} {'noise':>5} " + " ".join(f"{f:>15}" for f in columns))
    for r in rows:
        if "by_family" not in r:
            continue
        suffix = "" if r["kind"] == "thesis" else "_median"
        measure = "pr_pooled" if r["kind"] == "thesis" else "pr_median"
        cells = []
        for f in columns:
            b = r["held"] if f == "all" else r["by_family"][f]
            cells.append(
                "/".join(
                    _f(b.get(key))
                    for key in (measure, *(f"ceiling_{c}{suffix}" for c, _ in CEILINGS))
                )
            )
        print(
            f"{r['kind']:<7} {r['n_train']:>2} {r['noise']:>4.0f}x "
            + " ".join(f"{c:>15}" for c in cells)
        )
    print("\nPooled Pr % per family against the person's noise-free path (as measured / vs clean):")
    for r in rows:
        if "by_family" not in r:
            continue
        cells = [
            f"{_f(b.get('pr_pooled'))}/{_f(b.get('pr_pooled_clean'))}"
            for b in (*(r["by_family"][f] for f in P.FAMILIES), r["held"])
        ]
        print(
            f"{r['kind']:<7} {r['n_train']:>2} {r['noise']:>4.0f}x "
            + " ".join(f"{c:>15}" for c in cells)
        )
    print("\nBehaviour model chosen (Skill.model_selection_; CV: its cross-validated Pr median):")
    for r in rows:
        m = r.get("model") or {}
        if m.get("chosen"):
            print(
                f"{r['kind']:<7} {r['n_train']:>2} {r['noise']:>4.0f}x {m['chosen']:<22} "
                f"CV {_f(m.get('cv_pr_median')):>5}%  runner-up {m.get('runner_up')}"
                f"  swerve gain {_f(m.get('swerve_gain'), '{:.2f}')}"
            )
    for r in rows:
        for message in r.get("refused", [])[:3]:
            print(f"  refused ({r['kind']} n={r['n_train']} {r['noise']:.0f}x) {message}")


def check_targets(rows: list[dict]) -> list[dict]:
    """The issue's targets (issue 26), each with the worst value over the settings run."""
    fitted = [r for r in rows if "held" in r]
    checks = []

    def add(name, value, ok, note=""):
        checks.append({"target": name, "value": value, "pass": bool(ok), "note": note})

    failed = [f"{r['kind']} n={r['n_train']} {r['noise']:g}x" for r in rows if "fit_error" in r]
    add("every fit succeeds", len(failed), not failed, "; ".join(failed))
    thesis = [
        (r["by_family"][f].get("pr_pooled"), f, r)
        for r in fitted
        if r["kind"] == "thesis"
        for f in P.FAMILIES
        if r["by_family"][f].get("n")
    ]
    if thesis:
        worst, family, r = min(thesis, key=lambda t: t[0])
        ceiling = r["by_family"][family].get("ceiling_goal")
        add(
            "thesis person: pooled Pr >= 90 % in every family",
            worst,
            worst >= 90.0,
            f"worst: {family}, n={r['n_train']}, {r['noise']:g}x; the person's own path,"
            f" noise-free and reaching the goal: {_f(ceiling)} %",
        )
        # The same against the person's noise-free path: at 2x noise a person who hardly
        # swerves (pairs) leaves any plan, its own clean path included, 68-82 % against the
        # recorded one; this says what the plan loses to the person's behaviour alone.
        clean = [
            (r["by_family"][f].get("pr_pooled_clean"), f, r)
            for r in fitted
            if r["kind"] == "thesis"
            for f in P.FAMILIES
            if r["by_family"][f].get("pr_pooled_clean") is not None
        ]
        if clean:
            worst, family, r = min(clean, key=lambda t: t[0])
            ceiling = r["by_family"][family].get("ceiling_goal")
            add(
                "thesis person: pooled Pr >= 90 % in every family, against its noise-free path",
                worst,
                worst >= 90.0,
                f"worst: {family}, n={r['n_train']}, {r['noise']:g}x; the person's own path"
                f" reaching the goal, against the recorded one: {_f(ceiling)} %",
            )
    others = [r for r in fitted if r["kind"] != "thesis" and r["held"].get("n")]
    if others:
        r = min(others, key=lambda r: r["held"]["pr_median"] or -np.inf)
        value = r["held"]["pr_median"]
        add(
            "other people: median Pr >= 80 %",
            value,
            value is not None and value >= 80.0,
            f"worst: {r['kind']} n={r['n_train']} {r['noise']:g}x",
        )
        r = min(others, key=lambda r: r["held"]["sides"] or 0.0)
        add(
            "other people: side agreement >= 90 %",
            100 * (r["held"]["sides"] or 0.0),
            (r["held"]["sides"] or 0.0) >= 0.9,
            f"worst: {r['kind']} n={r['n_train']} {r['noise']:g}x",
        )
    add("0 collisions", sum(r["held"].get("collisions", 0) for r in fitted), True)
    checks[-1]["pass"] = checks[-1]["value"] == 0
    gaps = sum(r["held"].get("gaps_threaded", 0) for r in fitted)
    add("0 gaps threaded the person went round", gaps, gaps == 0)
    refused = sum(len(r["refused"]) for r in fitted)
    add("no plan refused (the person got through)", refused, refused == 0)
    ten = [r["fit_s"] for r in fitted if r["n_train"] == 10]
    if ten:
        add("fit <= 5 s with 10 demonstrations", max(ten), max(ten) <= 5.0, "includes the path")
    return checks


def print_targets(checks: list[dict]) -> None:
    print("\nTargets of issue 26 (worst over the settings run):")
    for c in checks:
        value = c["value"]
        shown = f"{value:.1f}" if isinstance(value, float) else str(value)
        note = f"  ({c['note']})" if c["note"] else ""
        print(f"  {'PASS' if c['pass'] else 'FAIL'}  {c['target']}: {shown}{note}")


def figure(rows: list[dict], path: Path, scale: float) -> str | None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    chosen = {}
    for r in rows:
        if "_examples" in r and r["noise"] == 1.0:
            chosen[r["kind"]] = r  # the largest training set, as rows are in order
    if not chosen:
        return None
    preferred = ("clutter", "pocket", "new_task", "pair", "near_goal", "moved_goal", "single")
    fig, axes = plt.subplots(len(chosen), 4, figsize=(17, 3.6 * len(chosen)), squeeze=False)
    unit = "mm" if scale == 1000.0 else "m"
    for ax_row, (kind, r) in zip(axes, chosen.items(), strict=True):
        demos, scenes = r["_train"]
        ax = ax_row[0]
        for demo, scene in zip(demos, scenes, strict=True):
            line = ax.plot(*demo.T, lw=1)[0]
            for o in scene:
                ax.add_patch(plt.Circle(o.position, o.radius, fill=False, color=line.get_color()))
        ax.set_title(f"{kind}: {len(demos)} training demonstrations")
        # Three families with a plan (a refused plan has nothing to draw).
        families = [f for f in preferred if f in r["_examples"]][:3]
        for ax in ax_row[1 + len(families) :]:
            ax.set_axis_off()
        for ax, family in zip(ax_row[1:], families, strict=False):
            case, person, plan, dmp, nominal = r["_examples"][family]
            for o in case.scene:
                ax.add_patch(
                    plt.Circle(o.position, o.radius, color="0.6" if o.label == "cup" else "0.35")
                )
            ax.plot(*nominal.T, ":", color="0.5", label="nominal (skill's DMP)")
            ax.plot(*person.T, "k-", lw=2, label="held-out person")
            ax.plot(*plan.T, "C3-", label="lfdkit plan")
            ax.plot(*dmp.T, "C0--", label="DMP + coupling")
            ax.set_title(f"{kind}: {family}, {case.task} task")
        for ax in ax_row[: 1 + len(families)]:
            ax.set_aspect("equal")
            ax.set_xlabel(f"x [{unit}]")
            ax.set_ylabel(f"y [{unit}]")
            ax.autoscale_view()
    handles, labels = next(
        ax.get_legend_handles_labels() for ax in axes[:, 1:].ravel() if ax.get_lines()
    )
    fig.legend(handles, labels, loc="lower center", ncol=4)
    fig.suptitle(
        "Emulation fidelity (1x noise, largest training set): cups light grey (r 3 cm), "
        "boxes dark grey (r 5 cm); first column: the training demonstrations and their obstacles"
    )
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(path, dpi=80)
    plt.close(fig)
    return path.name


def main(argv: list[str] | None = None) -> int:
    from _common import git_state, json_ready, machine_info, package_versions

    from lfdkit.io import atomic_write

    parser = argparse.ArgumentParser(
        prog="benchmarks/emulate_fidelity.py", description=__doc__.splitlines()[0]
    )
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).resolve().parents[1] / "results" / "emulate"
    )
    parser.add_argument(
        "--quick", action="store_true", help="6 demonstrations, 2 scenes per family"
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--units", choices=("m", "mm"), default="m")
    parser.add_argument("--people", nargs="*", default=list(P.KINDS), choices=P.KINDS)
    parser.add_argument("--sizes", nargs="*", type=int, default=None)
    parser.add_argument(
        "--per-family", type=int, default=None, help="scenes per family (4; quick 2)"
    )
    parser.add_argument("--skill-option", action="append", metavar="KEY=VALUE")
    parser.add_argument("--plan-option", action="append", metavar="KEY=VALUE")
    parser.add_argument("--fit-option", action="append", metavar="KEY=VALUE")
    parser.add_argument("--label", default="", help="suffix of the output files")
    args = parser.parse_args(argv)
    options = (
        parse_options(args.skill_option, "--skill-option"),
        parse_options(args.plan_option, "--plan-option"),
        parse_options(args.fit_option, "--fit-option"),
    )
    sizes = args.sizes or (QUICK_SIZES if args.quick else SIZES)
    per_family = args.per_family or (2 if args.quick else 4)
    scale = 1000.0 if args.units == "mm" else 1.0
    args.output.mkdir(parents=True, exist_ok=True)
    wall = time.perf_counter()
    rows, people = [], {}
    with threadpool_limits(limits=1):
        warm_up(scale, options)
        for kind in args.people:
            progress(f"{kind}: demonstrations ...")
            data = person_data(kind, args.seed, scale, per_family)
            people[kind] = {
                "description": data["description"],
                "held_out": [
                    f"{c.family} ({c.task}, {len(c.scene)} obstacles)" for c, _, _ in data["held"]
                ],
                "skipped": data["skipped"],
            }
            for n in sizes:
                for level in NOISES:
                    progress(f"{kind}: {n} demonstrations, {level:g}x noise ...")
                    rows.append(run_setting(data, n, level, scale, args, options))
    print_table(rows, scale)
    checks = check_targets(rows)
    print_targets(checks)
    suffix = f"_{args.label}" if args.label else ""
    fig_name = figure(rows, args.output / f"fidelity{suffix}.png", scale)
    wall = time.perf_counter() - wall
    print(f"\nwall time {wall:.1f} s")
    result = {
        "benchmark": "emulate_fidelity",
        "created": time.strftime("%Y-%m-%dT%H:%M:%S"),
        "command": [sys.executable, *sys.argv] if argv is None else ["emulate_fidelity", *argv],
        "quick": args.quick,
        "seed": args.seed,
        "units": args.units,
        "options": {"skill": options[0], "plan": options[1], "fit": options[2]},
        "machine": machine_info(),
        "versions": package_versions(("lfdkit", "numpy", "scipy", "numba")),
        "git": git_state(),
        "wall_time_s": wall,
        "people": people,
        "rows": rows,
        "targets": checks,
        "figure": fig_name,
    }
    out = args.output / f"fidelity{suffix}.json"
    text = json.dumps(json_ready(result), indent=1)
    atomic_write(out, lambda f: f.write(text), overwrite=True)
    progress(f"wrote {out}")
    return 0
