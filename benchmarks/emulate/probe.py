"""Probe: the fidelity study's kinds of person with parameters other than ours.

Run ``python benchmarks/emulate_probe.py`` (about 10 min on the shared 2-core
machine; ``--variants NAME ...`` runs some, ``--list`` names them). The
held-out evaluation of issue 26 has its own demonstrators, scenes, units and
noise; this builds the same kinds of person (:mod:`.people`) with other
margins, gains, rotations, look-aheads, return rates and MPC horizons, other
noise levels, training sizes and millimetres, and one new kind, and runs the
skill's defaults (``Skill(units=...).fit`` then ``Skill.plan``) on each as
:mod:`.fidelity` does (its :func:`~.fidelity.run_setting`, 2 held-out scenes per
family unless ``--per-family``). Prints one row per variant (pooled / median
Pr, sides, collisions, gaps threaded, refused, fit seconds, the model chosen
and the fit's warnings) and the targets of issue 26 per variant; writes
``probe[_<label>].json`` to ``--output``. Seeded (``--seed``, default 0): each
person sees the scenes of its base kind's streams, redrawn where it fails.

Variants (ours: thesis H = 5; margin cup 2 cm, box 4 cm; field gains 30/50 m/s²,
rotation 0.6; late look-ahead 8 cm, return slope 0.2, clearances 3/1.5 cm;
6 demonstrations, 1× noise = 2 mm, metres):

* ``thesis-h3``, ``thesis-h9``: the thesis person's MPC horizon 3 and 9;
* ``margin-x1.5``, ``margin-x0.5``: margins 3/6 cm and 1/2 cm;
* ``field-soft``, ``field-hard``: gains ×0.5 and rotation 0.25; gains ×2 and rotation 1.2;
* ``late-near``, ``late-far``: look-ahead 4 cm and return 0.1, clearances ×1.5;
  look-ahead 15 cm and return 0.5, clearances cup ×0.5 (1.5 cm), box 1 cm;
* ``<kind>``: our person (the reference row of the ones below);
* ``<kind>-noise0.5``, ``<kind>-noise3``: our person, noise 0.5× and 3×;
* ``<kind>-n4``, ``<kind>-n10``: our person, 4 and 10 demonstrations;
* ``<kind>-mm``: our person in millimetres (everything × 1000, ``units="mm"``);
  Pr, sides and gaps must equal the metres row's;
* ``asym-cup``: :class:`SidedPerson`, a fixed-margin person who always keeps
  cups on its left (goes round them on their right), whatever side of the path
  they stand; boxes as the margin person. A symmetric reward per class cannot
  express this: see what the skill does and whether it says so
  (``asym-cup-n10``: with 10 demonstrations).

People whose noise-free path comes closer than :data:`FLOOR` (8 mm; the
fidelity study's 12 mm is for 2× noise) are redrawn, so the 1 cm margins of
``margin-x0.5`` stay usable; rows with 3× noise keep the study's 12 mm.

Measured (seed 0, 2 scenes per family, 14 held-out scenes a row; pooled /
median Pr, sides; 0 collisions everywhere)
--------------------------------------------------------------------------
Meet the issue's targets: thesis H 3, 5, 9, 4 and 10 demonstrations, 0.5×
noise (95-96 % pooled); margin ×0.5, ×1, ×1.5, 0.5×/3× noise, 10
demonstrations (94-99 / 95-99 %, sides 100 %); field with 4 and 10
demonstrations (89 / 87-88 %); late with 10 (78 / 82 %). Millimetres: every
kind's per-scene Pr within 0.005 points of metres, the same model chosen,
the same sides and gaps (and ``Skill()`` left in metres on millimetre data
plans the same paths to the digit, with a units warning). Fail: field at 6
demonstrations (−51 / 86 %, sides 89 %; the same at 0.5× and 3× noise and in
mm: one clutter scene passed 2 of 3 on the other side, one new task 1 of 3),
``field-hard`` (53 / 91 %, sides 89 %); ``field-soft`` now passes (7 / 86 %,
sides 96 %; before, −159 / 31 %). Field's failures are two scenes, Q' on its
lower plausibility wall (warned): a plan holds the swerve it took at one
obstacle and goes round the next, clear of the nominal, on its far side (a
clutter scene, Pr −449 %; a curved new task passes the last box on the
outside, −439 %); a Q ten times larger fixes the first and costs the
training scenes 3 points of Pr. Fixed since for the first: the swerve's route reward pulls to
the nominal at twice the fitted Q (:data:`lfdkit.skill.selection.ROUTE_PULL`): field at 6
demonstrations 10 / 86 %, sides 96 %; ``field-hard`` 90 / 91 %, sides 96 %; the
curved new task still passes its last box on the outside. Late at 4-6
demonstrations (33-59 / 72-78 %, one pair threaded in most rows: the person
goes round pairs its single-obstacle training scenes never showed),
``late-near`` (85 % median, 2 pairs threaded), ``late-far`` (75 %); thesis at
3× noise (80 % pooled: one pair passed on the other side); margin with 4
demonstrations (one pair threaded). Causes (plotted): thesis 3×, a cup and a
box 9.0 cm apart that the person passes between within 1 cm of its nominal;
at 3× noise the model choice takes ``window+demonstrated`` and decides the
person does not thread gaps (``threads_gaps`` False; True at 1× and 2×), so
the typical clearances (cup 4.2 + box 5.4 cm) close the gap and the plan goes
round the cup 15 cm out (Pr −6421 %, against the noise-free path −18604 %).
Margin, 4 demonstrations: a cup and a box 6.0 cm apart, exactly the person's
margins together (2 + 4 cm); the box's margin is learned at 3.6 cm from two
box demonstrations (``P[box][y]`` unidentified), so the gap looks passable
(5.6 cm) and the taut plan threads it where the person went round (18 %).
Fixed since: the clearance consistency is measured above the demonstrations'
noise (their spread without obstacles, :data:`lfdkit.skill.selection.NOISE_SHARE`):
thesis 3× keeps ``window``, 80 → 95 % pooled (seed 1: 46 → 95 %); gaps within
two standard errors of the typical clearances stay closed
(:data:`lfdkit.emulate.gaps.GAP_STANDARD_ERRORS`): margin n4 74 → 97 %, no gap
threaded (seed 1: 97 %, as before), late n4 60 → 76 % pooled, 1 → 0 gaps
(seed 1: −28 %, 8 gaps, as before); the other rows unchanged.
Both rows crashed before (``ValueError: kind: unknown person`` in
``run_setting``'s ``own`` ceiling); they run now. ``asym-cup`` (keeps cups on its left):
before, its long-way cup demonstrations were left out as coin flips and the
cup class went unlearned, so 13 of 14 plans were refused; now kept (the fit
on all stands), with a warning naming the side preference: 0 refused,
median 81 %, sides 77 % (seeds 1-2: 57 / −23 %, sides 50 / 42 %, as before:
no symmetric reward passes a cup the long way round). Now the skill keeps the
detected side (:attr:`lfdkit.skill.Skill.side_preferences_`, balls that block
the other side: :func:`lfdkit.emulate.gaps.preferred_side_blockers`): pooled /
median Pr and sides 97 / 99 %, 100 % (seed 0), 86 / 98 %, 96 % (seed 1: one
pair of boxes threaded), 99 / 99 %, 100 % (seed 2); with 10 demonstrations the
same but seed 1 65 / 98 %, 93 %; 0 collisions, 0 refused.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from . import fidelity as F
from . import people as P

FLOOR = 0.008  # m: smallest clearance of a noise-free path (1x noise and less)


class _Floored:
    """Mixin: the noise-free path may come within ``floor`` (m) of an obstacle."""

    floor = P.MIN_CLEARANCE

    def clean(self, nominal, scene):
        path = self._path(P.Frame(nominal, self.scale), scene)
        if len(scene) and P.min_clearance(path, scene) < self.floor * self.scale:
            raise P.PersonFailed(f"{self.kind}: comes within {self.floor} m of an obstacle")
        return P.resample(path, self.n_points)


class ThesisP(_Floored, P.ThesisPerson):
    pass


class MarginP(_Floored, P.MarginPerson):
    pass


class FieldP(_Floored, P.FieldPerson):
    pass


class LateP(_Floored, P.LatePerson):
    pass


class SidedPerson(_Floored, P.MarginPerson):
    """A fixed-margin person who keeps every obstacle of ``label`` on its left.

    It goes round such an obstacle on the obstacle's right (lateral offset
    below the obstacle's at the stations the obstacle spans), even when the
    obstacle stands right of the path and the other way round is shorter.
    Other classes as :class:`people.MarginPerson`.
    """

    kind = "sided"

    def __init__(self, scale=1.0, n_points=100, *, label="cup", **kwargs):
        super().__init__(scale, n_points, **kwargs)
        self.label = label

    def describe(self) -> str:
        return f"keeps every {self.label} on its left; otherwise " + super().describe()

    def feasible(self, frame, scene):
        ok = super().feasible(frame, scene)
        for o in scene.obstacles:
            if o.label != self.label:
                continue
            k, lateral = frame.project(o.position)
            span = o.radius + self.margins[o.label]
            near = np.abs(frame.s - frame.s[k]) <= span
            ok[np.ix_(near, frame.grid >= lateral)] = False
        return ok

    def _path(self, frame, scene):
        path = super()._path(frame, scene)
        for o in scene.obstacles:
            if o.label == self.label and F.side(path, o.position) != 1:
                raise P.PersonFailed("sided: could not keep the obstacle on its left")
        return path


@dataclass
class Variant:
    name: str
    kind: str  # the base kind: its scenes, and its target (thesis or the others)
    make: object  # scale -> Person
    n: int = 6
    noise: float = 1.0
    scale: float = 1.0


def _variants() -> list[Variant]:
    out = [
        Variant("thesis-h3", "thesis", lambda s: ThesisP(s, horizon=3)),
        Variant("thesis-h9", "thesis", lambda s: ThesisP(s, horizon=9)),
        Variant("margin-x1.5", "margin", lambda s: MarginP(s, margins={"cup": 0.03, "box": 0.06})),
        Variant("margin-x0.5", "margin", lambda s: MarginP(s, margins={"cup": 0.01, "box": 0.02})),
        Variant(
            "field-soft",
            "field",
            lambda s: FieldP(s, gains={"cup": 15.0, "box": 25.0}, rotation=0.25),
        ),
        Variant(
            "field-hard",
            "field",
            lambda s: FieldP(s, gains={"cup": 60.0, "box": 100.0}, rotation=1.2),
        ),
        Variant(
            "late-near",
            "late",
            lambda s: LateP(
                s, lookahead=0.04, back_slope=0.1, clearances={"cup": 0.045, "box": 0.0225}
            ),
        ),
        Variant(
            "late-far",
            "late",
            lambda s: LateP(
                s, lookahead=0.15, back_slope=0.5, clearances={"cup": 0.015, "box": 0.01}
            ),
        ),
        Variant("asym-cup", "sided", lambda s: SidedPerson(s)),
        Variant("asym-cup-n10", "sided", lambda s: SidedPerson(s), n=10),
    ]
    ours = {"thesis": ThesisP, "margin": MarginP, "field": FieldP, "late": LateP}
    for kind, cls in ours.items():
        out += [
            Variant(kind, kind, cls),
            Variant(f"{kind}-noise0.5", kind, cls, noise=0.5),
            Variant(f"{kind}-noise3", kind, cls, noise=3.0),
            Variant(f"{kind}-n4", kind, cls, n=4),
            Variant(f"{kind}-n10", kind, cls, n=10),
            Variant(f"{kind}-mm", kind, cls, scale=1000.0),
        ]
    return out


VARIANTS = {v.name: v for v in _variants()}


def run_variant(v: Variant, seed: int, per_family: int, options) -> dict:
    person = v.make(v.scale)
    person.floor = P.MIN_CLEARANCE if v.noise > 2.0 else FLOOR
    data = F.person_data(v.kind, seed, v.scale, per_family, person=person)
    data["kind"] = v.name
    args = argparse.Namespace(quick=True)
    row = F.run_setting(data, v.n, v.noise, v.scale, args, options)
    row["variant"] = v.name
    row["base"] = v.kind
    row["description"] = data["description"]
    row["skipped"] = data["skipped"]
    return row


def verdict(row: dict) -> str:
    """The issue's targets for one row: what fails, or ``ok``."""
    if "fit_error" in row:
        return "FIT FAILED"
    h = row["held"]
    bad = []
    if row["base"] == "thesis":
        if (h.get("pr_pooled") or -np.inf) < 90.0:
            bad.append("Pr<90")
    else:
        if (h.get("pr_median") or -np.inf) < 80.0:
            bad.append("Pr<80")
        if (h.get("sides") or 0.0) < 0.9:
            bad.append("sides<90")
    if h.get("collisions"):
        bad.append("collisions")
    if h.get("gaps_threaded"):
        bad.append("gaps")
    if row["refused"]:
        bad.append("refused")
    return ",".join(bad) or "ok"


def print_rows(rows: list[dict]) -> None:
    head = (
        f"{'variant':<17} {'n':>2} {'noise':>5} {'scenes':>6} {'pooled':>7} {'median':>7} "
        f"{'sides':>6} {'coll':>4} {'gaps':>4} {'refused':>7} {'fit s':>6} {'train':>6} "
        f"{'model':<22} verdict"
    )
    print("\n" + head)
    f = F._f
    for r in rows:
        if "fit_error" in r:
            print(f"{r['variant']:<17} fit failed: {r['fit_error']}")
            continue
        h = r["held"]
        print(
            f"{r['variant']:<17} {r['n_train']:>2} {r['noise']:>4g}x {h.get('n', 0):>6} "
            f"{f(h.get('pr_pooled')):>6}% {f(h.get('pr_median')):>6}% "
            f"{f(h.get('sides') and 100 * h['sides']):>5}% {h.get('collisions', 0):>4} "
            f"{h.get('gaps_threaded', 0):>4} {len(r['refused']):>7} {r['fit_s']:>6.1f} "
            f"{f(r['train'].get('pr_median')):>5}% {r['model'].get('chosen')!s:<22} "
            f"{verdict(r)}"
        )
    print("\nFit warnings (first 160 characters) and refused plans:")
    for r in rows:
        for w in r.get("fit_warnings", []):
            print(f"  {r['variant']}: warns: {w[:160]}")
        for m in r.get("refused", [])[:3]:
            print(f"  {r['variant']}: refused: {m}")


def main(argv: list[str] | None = None) -> int:
    from _common import git_state, json_ready, machine_info

    parser = argparse.ArgumentParser(
        prog="benchmarks/emulate_probe.py", description=__doc__.splitlines()[0]
    )
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).resolve().parents[1] / "results" / "emulate"
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--variants", nargs="*", default=None, choices=sorted(VARIANTS))
    parser.add_argument("--list", action="store_true", help="name the variants and exit")
    parser.add_argument("--per-family", type=int, default=2)
    parser.add_argument("--skill-option", action="append", metavar="KEY=VALUE")
    parser.add_argument("--plan-option", action="append", metavar="KEY=VALUE")
    parser.add_argument("--fit-option", action="append", metavar="KEY=VALUE")
    parser.add_argument("--label", default="")
    args = parser.parse_args(argv)
    if args.list:
        print("\n".join(VARIANTS))
        return 0
    options = (
        F.parse_options(args.skill_option, "--skill-option"),
        F.parse_options(args.plan_option, "--plan-option"),
        F.parse_options(args.fit_option, "--fit-option"),
    )
    names = args.variants or list(VARIANTS)
    args.output.mkdir(parents=True, exist_ok=True)
    wall = time.perf_counter()
    rows = []
    with threadpool_limits(limits=1):
        F.warm_up(1.0, options)
        for name in names:
            F.progress(f"{name} ...")
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                row = run_variant(VARIANTS[name], args.seed, args.per_family, options)
            rows.append(row)
            print_rows([row])
    print_rows(rows)
    wall = time.perf_counter() - wall
    print(f"\nwall time {wall:.1f} s")
    result = {
        "benchmark": "emulate_probe",
        "created": time.strftime("%Y-%m-%dT%H:%M:%S"),
        "command": [sys.executable, *sys.argv] if argv is None else ["emulate_probe", *argv],
        "seed": args.seed,
        "options": {"skill": options[0], "plan": options[1], "fit": options[2]},
        "machine": machine_info(),
        "git": git_state(),
        "wall_time_s": wall,
        "rows": [
            {k: v for k, v in r.items() if not k.startswith("_")} | {"verdict": verdict(r)}
            for r in rows
        ],
    }
    suffix = f"_{args.label}" if args.label else ""
    out = args.output / f"probe{suffix}.json"
    out.write_text(json.dumps(json_ready(result), indent=1))
    F.progress(f"wrote {out}")
    return 0
