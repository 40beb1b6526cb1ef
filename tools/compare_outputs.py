"""Compare two folders of lfdkit outputs file by file: the check that a refactoring changed nothing.

``python tools/compare_outputs.py BEFORE AFTER`` prints one line per file and
exits 1 when a file differs beyond round-off. Text files (CSV, URScript,
HTML, logs) must be byte-identical; JSON documents equal with numbers within
``--tol`` (relative to max(1, |x|)); CSV files whose text differs are
compared number by number within ``--tol`` (and say so); PNGs equal pixel for pixel (decoded
with matplotlib); NPZ archives array for array within ``--tol``. Lines
matching ``--ignore`` (a regular expression; default: wall-clock timings and
dates, see :data:`TIMING`) are masked in text files before comparing, and JSON
keys named in ``--ignore-keys`` are skipped (wall-clock fields).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

import numpy as np

#: Wall-clock text: "3.3 s", "936 ms", dates and times of day, the HTML report's timing cells
#: ("learned in", "whole run" and the last column, plan (ms), of its planner table).
TIMING = (
    r"\d+(\.\d+)? ?(ms|s)\b|\d{4}-\d\d-\d\d[T ][\d:.]+Z?( UTC)?|\bin \d"
    r'|<td class="num">\d+</td></tr>'
)


def _json_equal(a, b, tol: float, skip: frozenset[str], where: str = "") -> str | None:
    if isinstance(a, dict) and isinstance(b, dict):
        if set(a) - skip != set(b) - skip:
            return f"{where}: keys {sorted(set(a) ^ set(b))}"
        for key in a:
            if key in skip:
                continue
            found = _json_equal(a[key], b[key], tol, skip, f"{where}.{key}")
            if found:
                return found
        return None
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return f"{where}: length {len(a)} vs {len(b)}"
        for i, (x, y) in enumerate(zip(a, b, strict=True)):
            found = _json_equal(x, y, tol, skip, f"{where}[{i}]")
            if found:
                return found
        return None
    numbers = (int, float)
    if isinstance(a, numbers) and isinstance(b, numbers) and not isinstance(a, bool):
        if a == b or abs(a - b) <= tol * max(1.0, abs(a), abs(b)):
            return None
        return f"{where}: {a!r} vs {b!r}"
    return None if a == b else f"{where}: {a!r} vs {b!r}"


def _csv_difference(lines_a: list[str], lines_b: list[str]) -> float | None:
    """Largest relative difference of two CSV texts' numbers; None if they differ otherwise."""
    worst = 0.0
    for x, y in zip(lines_a, lines_b, strict=True):
        cells_a, cells_b = x.split(","), y.split(",")
        if len(cells_a) != len(cells_b):
            return None
        for a, b in zip(cells_a, cells_b, strict=True):
            if a == b:
                continue
            try:
                u, v = float(a), float(b)
            except ValueError:
                return None
            worst = max(worst, abs(u - v) / max(1.0, abs(u), abs(v)))
    return worst


def compare(before: Path, after: Path, tol: float, ignore: str, skip: frozenset[str]) -> str:
    """'identical', 'equal within tol' or what differs, for one pair of files."""
    raw_a, raw_b = before.read_bytes(), after.read_bytes()
    if raw_a == raw_b:
        return "identical"
    suffix = before.suffix.lower()
    if suffix == ".json" or suffix == ".jsonl":
        if suffix == ".json":
            docs_a, docs_b = [json.loads(raw_a)], [json.loads(raw_b)]
        else:
            docs_a = [json.loads(x) for x in raw_a.decode().splitlines() if x.strip()]
            docs_b = [json.loads(x) for x in raw_b.decode().splitlines() if x.strip()]
        found = _json_equal(docs_a, docs_b, tol, skip)
        return f"DIFFERS {found}" if found else f"equal within {tol:g}"
    if suffix == ".png":
        from matplotlib.image import imread

        pa, pb = imread(before), imread(after)
        if pa.shape != pb.shape:
            return f"DIFFERS image size {pa.shape} vs {pb.shape}"
        n = int(np.any(pa != pb, axis=-1).sum()) if pa.ndim == 3 else int((pa != pb).sum())
        return "same pixels (metadata differs)" if n == 0 else f"DIFFERS in {n} pixels"
    if suffix == ".npz":
        with np.load(before) as za, np.load(after) as zb:
            if sorted(za.files) != sorted(zb.files):
                return "DIFFERS members"
            for key in za.files:
                x, y = za[key], zb[key]
                if x.shape != y.shape or (
                    x.dtype.kind == "f" and not np.allclose(x, y, rtol=tol, atol=tol)
                ):
                    return f"DIFFERS {key}"
                if x.dtype.kind != "f" and not np.array_equal(x, y):
                    return f"DIFFERS {key}"
        return f"equal within {tol:g}"
    try:
        lines_a, lines_b = raw_a.decode().splitlines(), raw_b.decode().splitlines()
    except UnicodeDecodeError:
        return "DIFFERS (binary)"
    if suffix == ".csv" and len(lines_a) == len(lines_b):
        worst = _csv_difference(lines_a, lines_b)
        if worst is not None and worst <= tol:
            return f"numbers within {worst:.1e} (relative; text differs)"
    drop = re.compile(ignore)
    kept_a = [re.sub(drop, "#", x) for x in lines_a]
    kept_b = [re.sub(drop, "#", x) for x in lines_b]
    if kept_a == kept_b:
        return "equal except timings"
    for i, (x, y) in enumerate(zip(kept_a, kept_b, strict=False)):
        if x != y:
            at = next(j for j, (c, d) in enumerate(zip(x + "\0", y + "\1", strict=False)) if c != d)
            return f"DIFFERS line {i + 1}: {x[at - 30 : at + 50]!r} vs {y[at - 30 : at + 50]!r}"
    return f"DIFFERS length {len(lines_a)} vs {len(lines_b)} lines"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("--tol", type=float, default=1e-12)
    parser.add_argument("--ignore", default=TIMING)
    parser.add_argument("--ignore-keys", default="seconds,plan_ms,elapsed,created,date")
    args = parser.parse_args(argv)
    skip = frozenset(args.ignore_keys.split(","))
    files_a = {p.relative_to(args.before) for p in args.before.rglob("*") if p.is_file()}
    files_b = {p.relative_to(args.after) for p in args.after.rglob("*") if p.is_file()}
    bad = 0
    for name in sorted(files_a ^ files_b):
        print(f"{name}: only in {'before' if name in files_a else 'after'}")
        bad += 1
    for name in sorted(files_a & files_b):
        verdict = compare(args.before / name, args.after / name, args.tol, args.ignore, skip)
        bad += verdict.startswith("DIFFERS")
        print(f"{name}: {verdict}")
    print(f"{len(files_a & files_b)} files compared, {bad} differ")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
