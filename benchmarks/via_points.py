"""Via-point plans benchmark (issue 33): a skill sent through a held-out demonstration's points.

Run ``python benchmarks/via_points.py`` (``--quick``: 3 folds). Prints a table
and writes ``via_points.json`` to ``--output``
(``benchmarks/results/via_points`` by default).

Leave one demonstration out on ``walking`` (30 demos, 2-D) and ``da_vinci``
(4 demos, 3-D) of :func:`lfdkit.datasets.load_dataset` (seed 0): a
:class:`lfdkit.skill.Skill` (defaults) is learned from the others and plans
from the held-out demonstration's start to its goal

- with no via-point (the DMP's nominal alone),
- through 1 of its points (at half its length) and through 3 (a quarter,
  half, three quarters), each at the phase the skill's timing reaches that
  fraction of the length (:meth:`lfdkit.imitate.SpeedProfile.phase`),
- bent with the skill's ProMP (the demonstrations' covariance) and, the
  baseline, smoothly with no preferred direction (``promp_ = None``).

Scores: RMS distance from the held-out demonstration's points to the plan
(m), the farthest the plan passes from a via-point (m), and the median time
of a plan with and without via-points (ms, same run).
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import git_state, machine_info, package_versions, write_json

from lfdkit.core.geometry import polyline_distances, resample
from lfdkit.datasets import load_dataset
from lfdkit.skill import Skill

DATASETS = ("walking", "da_vinci")
ONE, THREE = np.array([0.5]), np.array([0.25, 0.5, 0.75])


def _rms(demo: np.ndarray, plan: np.ndarray) -> float:
    return float(np.sqrt(np.mean(polyline_distances(demo, plan) ** 2)))


def _via(skill: Skill, demo: np.ndarray, fractions: np.ndarray) -> list[tuple[float, Any]]:
    """The demonstration's points at these fractions of its length, at the skill's phases."""
    along = resample(demo, 1001)
    phases = skill.timing_.phase(fractions)
    return [(float(p), along[round(u * 1000)]) for p, u in zip(phases, fractions, strict=True)]


def held_out(name: str, folds: int) -> dict[str, Any]:
    demos = load_dataset(name, seed=0).demos
    scores: dict[str, list[float]] = {}
    misses, plain_ms, via_ms = [], [], []
    for h in range(min(folds, len(demos))):
        demo = demos[h]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            skill = Skill().fit_path([d for i, d in enumerate(demos) if i != h])
        smooth = Skill.from_dict({**skill.to_dict(), "promp": None})
        start, goal = demo[0], demo[-1]
        began = time.perf_counter()
        plain = skill.plan(start, goal).points
        plain_ms.append(1e3 * (time.perf_counter() - began))
        scores.setdefault("dmp", []).append(_rms(demo, plain))
        for label, fractions in (("1", ONE), ("3", THREE)):
            via = _via(skill, demo, fractions)
            targets = np.array([p for _, p in via])
            for kind, model in (("promp", skill), ("smooth", smooth)):
                began = time.perf_counter()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    plan = model.plan(start, goal, via=via).points
                if kind == "promp":
                    via_ms.append(1e3 * (time.perf_counter() - began))
                scores.setdefault(f"{kind}_{label}", []).append(_rms(demo, plan))
                misses.append(float(polyline_distances(targets, plan).max()))
    return {
        "dataset": name,
        "n_demos": len(demos),
        "folds": min(folds, len(demos)),
        "median_rms_m": {k: float(np.median(v)) for k, v in scores.items()},
        "max_via_miss_m": max(misses),
        "median_plan_ms": float(np.median(plain_ms)),
        "median_via_plan_ms": float(np.median(via_ms)),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="3 folds instead of 10")
    parser.add_argument("--output", type=Path, default=Path("benchmarks/results/via_points"))
    args = parser.parse_args(argv)
    folds = 3 if args.quick else 10
    rows = [held_out(name, folds) for name in DATASETS]
    print("\nHeld-out demonstration through its own points: median RMS distance to it, m")
    head = ("data", "folds", "DMP", "1 ProMP", "1 smooth", "3 ProMP", "3 smooth", "miss m")
    print(f"{head[0]:<10}{head[1]:>6}" + "".join(f"{h:>10}" for h in head[2:]))
    for r in rows:
        m = r["median_rms_m"]
        cells = [m["dmp"], m["promp_1"], m["smooth_1"], m["promp_3"], m["smooth_3"]]
        print(
            f"{r['dataset']:<10}{r['folds']:>6}"
            + "".join(f"{c:>10.4f}" for c in cells)
            + f"{r['max_via_miss_m']:>10.1e}"
        )
    print(
        "\nPlan time, median ms: "
        + ", ".join(
            f"{r['dataset']} {r['median_plan_ms']:.0f} without, "
            f"{r['median_via_plan_ms']:.0f} with via"
            for r in rows
        )
    )
    result = {
        "rows": rows,
        "machine": machine_info(),
        "git": git_state(),
        "packages": package_versions(["numpy"]),
    }
    args.output.mkdir(parents=True, exist_ok=True)
    out = write_json(args.output / "via_points.json", result)
    print(f"\nwrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
