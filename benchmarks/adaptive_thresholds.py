"""Why MeanPath's adaptive centre needs eight intersections on a normal to cut any.

From a handful of values the robust scale is itself noisy: Gaussian spread alone
then often puts one value many "scales" from the start, and the centre would
cut it. For each count ``n`` of intersections on a normal (on a normal line,
q <= 2, and in a normal plane, q = 3) this draws Gaussian samples, takes each
sample's own start and scale (``_own_start_and_scale`` in
``lfdkit/mimic/mean_path.py``) and reports how often a value lies past the
core (4 scales: weight below 1) and past the cutoff (8: weight 0), next to the
rule ``_FEWEST_TO_CUT`` (fewer values: the centre is their mean).

    python benchmarks/adaptive_thresholds.py [--output DIR]   # table + adaptive_thresholds.json
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from lfdkit.mimic.mean_path import _CORE, _CUTOFF, _FEWEST_TO_CUT, _own_start_and_scale

COUNTS = (3, 4, 5, 6, 7, 8, 9, 10, 12, 15, 20, 30, 50)


def past(n: int, plane: bool, draws: int, rng: np.random.Generator) -> tuple[float, float]:
    """Fractions of ``draws`` Gaussian samples of ``n`` with a value past the core and cutoff."""
    q = 3 if plane else 1
    values = rng.normal(size=(draws, n, q))
    if plane:
        values[..., 2] = 0.0  # intersections lie in the normal plane
    start, scale = _own_start_and_scale(values, np.ones((draws, n), dtype=bool))
    z = np.linalg.norm(values - start[:, None, :], axis=2).max(axis=1) / scale
    return float(np.mean(z > _CORE)), float(np.mean(z > _CUTOFF))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=Path("."), help="folder for the JSON")
    parser.add_argument("--draws", type=int, default=50_000, help="samples per count (line)")
    args = parser.parse_args(argv)
    rng = np.random.default_rng(20261124)
    rows = []
    print(
        f"{'n':>3} | {'line: past core':>15} {'past cutoff':>11} | "
        f"{'plane: past core':>16} {'past cutoff':>11}"
    )
    for n in COUNTS:
        line = past(n, False, args.draws, rng)
        plane = past(n, True, max(args.draws // 5, 1000), rng)
        rows.append({"n": n, "line": line, "plane": plane})
        marks = ["" if n >= _FEWEST_TO_CUT[kind] else " (mean)" for kind in ("line", "plane")]
        print(
            f"{n:>3} | {line[0]:>15.2%} {line[1]:>11.2%}{marks[0]:<7} | "
            f"{plane[0]:>16.2%} {plane[1]:>11.2%}{marks[1]}"
        )
    print(f"fewest intersections to cut any: {_FEWEST_TO_CUT} (fewer: the mean)")
    args.output.mkdir(parents=True, exist_ok=True)
    out = args.output / "adaptive_thresholds.json"
    out.write_text(json.dumps({"fewest_to_cut": _FEWEST_TO_CUT, "rows": rows}, indent=1) + "\n")
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
