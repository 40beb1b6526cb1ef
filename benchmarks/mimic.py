"""Mimicking benchmark: every method on every data set over several seeds.

Run ``python benchmarks/mimic.py`` (``--help`` for options). Writes
``mimic.json`` and figures to ``--output`` (``benchmarks/results/mimic`` by
default). Sections (``--sections``, all by default; ``--quick``: comparison,
centres and startup with 2 seeds):

* ``comparison``: one table (e1, e2 mean ± sd over seeds, penetration, median
  runtime) of every method, and the issue's accuracy targets;
* ``scaling``: Mean-Path fit time for N demos × M points (against the
  straightforward Mean-Path side by side: ``benchmarks/mimic_speed.py``);
* ``centres``: the default Mean-Path centre chosen by measurement: e2 of
  ``MeanPath(center=c)`` for every centre on every data set (mean over
  seeds), each centre's ratio to the best one, and the target: the default
  within 1.1 times the best of the others on every set
  (``benchmarks/mimic_centres.py`` tests it on sets drawn apart from these:
  burrs, local detours, clean data, per case and seed);
* ``gmr``: GMR component selection, the exhaustive BIC search over 2 to 30
  components against the default ladder search (``select_n_components``), on
  10 demos × 200 points of each set: time, chosen count, BIC, and the
  held-out error of GMR with each choice; target: at most 2 s;
* ``startup``: fresh interpreters: the first ``MeanPath`` fit on 100 demos ×
  1000 points with numba compiling (no cache), then with the cache written by
  that run, and the same fit warm; the time to ``import lfdkit``,
  ``lfdkit.mimic``, ``lfdkit.skill`` and to print ``lfdkit --help``; targets:
  first fit at most 5 s, ``import lfdkit`` at most 1 s.

Peers, side by side in the same run (install with ``pip install -e .[bench]``):
the ``gmr`` package (same number of components as lfdkit's GMR, chosen by BIC),
tslearn's DBA and soft-DTW barycenters. The point-wise average after arc-length
resampling is lfdkit's own naive baseline.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from _common import git_state, machine_info

import lfdkit
from lfdkit.app.evaluation import (
    comparison_figures,
    format_table,
    gmr_components,
    lfdkit_methods,
    run_comparison,
    summarize,
)
from lfdkit.core.geometry import resample
from lfdkit.datasets import MIMIC_DATASETS, load_dataset
from lfdkit.emulate import metrics
from lfdkit.mimic import GMR, ComponentLimitWarning, MeanPath, select_n_components

#: Data sets with outliers, where the issue asks the default Mean-Path for half
#: the best peer's e2: one-sided residuals with no other noise, occasional swerves.
OUTLIER_SETS = ("deburring_linear", "deburring_circular", "local_detours")

#: Mean-Path's centres, the default first (``centres`` section).
CENTRES = ("adaptive", "mean", "median", "biweight")
#: The default centre's largest allowed ratio to the best of the others, on every set.
CENTRE_TARGET = 1.1
#: ``gmr`` section: the exhaustive search's candidates, its demos and points, its target.
GMR_CANDIDATES = range(2, 31)
GMR_DEMOS, GMR_POINTS, GMR_TARGET_S = 10, 200, 2.0
#: ``startup`` section: the first fit's size and target, and ``import lfdkit``'s.
STARTUP_DEMOS, STARTUP_POINTS, STARTUP_TARGET_S, IMPORT_TARGET_S = 100, 1000, 5.0, 1.0
SECTIONS = ("comparison", "scaling", "centres", "gmr", "startup")

PEERS = ("gmr (package)", "DBA (tslearn)", "soft-DTW (tslearn)", "arc-length average")


def _gmr_package(demoset, seed):
    from gmr import GMM

    k = gmr_components(demoset, seed)
    samples = np.vstack([np.column_stack((np.linspace(0, 1, len(d)), d)) for d in demoset.demos])
    gmm = GMM(n_components=k, random_state=seed).from_samples(samples, init_params="kmeans++")
    return gmm.predict(np.array([0]), np.linspace(0, 1, 100)[:, None])


def _tslearn_input(demoset):
    from tslearn.utils import to_time_series_dataset

    return to_time_series_dataset(demoset.demos)


def _dba(demoset, seed):
    from tslearn.barycenters import dtw_barycenter_averaging

    return dtw_barycenter_averaging(_tslearn_input(demoset), barycenter_size=100, max_iter=30)


def _soft_dtw(demoset, seed):
    from tslearn.barycenters import softdtw_barycenter

    # soft-DTW's gamma is in squared data units: scale the data to unit spread.
    stacked = np.vstack(demoset.demos)
    centre, scale = stacked.mean(axis=0), stacked.std()
    from lfdkit.core.geometry import resample

    demos = [resample((d - centre) / scale, 100) for d in demoset.demos]
    init = np.mean(demos, axis=0)
    return softdtw_barycenter(np.array(demos), gamma=0.01, max_iter=50, init=init) * scale + centre


PEER_METHODS = {
    "gmr (package)": _gmr_package,
    "DBA (tslearn)": _dba,
    "soft-DTW (tslearn)": _soft_dtw,
}


def band(n_demos: int, n_points: int, rng: np.random.Generator) -> list[np.ndarray]:
    """Demonstrations scattered smoothly about a half sine, with a little white noise."""
    s = np.linspace(0.0, np.pi, n_points)
    nominal = np.column_stack((s, np.sin(s)))
    normal = np.column_stack((-np.cos(s), np.ones_like(s))) / np.sqrt(1 + np.cos(s) ** 2)[:, None]
    demos = []
    for _ in range(n_demos):
        phase = rng.uniform(0, 2 * np.pi, 3)
        offset = sum(0.05 * np.sin((k + 1) * s + phase[k]) for k in range(3))
        demos.append(nominal + offset[:, None] * normal + rng.normal(0, 0.002, (n_points, 2)))
    return demos


def scaling_table(repeats: int = 5) -> list[dict]:
    """Mean-Path fit time for N demos × M points on a noisy band."""
    rows = []
    rng = np.random.default_rng(0)
    for n_points in (100, 1000):
        for n_demos in (2, 10, 100):
            demos = band(n_demos, n_points, rng)
            MeanPath(n_points=n_points).fit(demos)  # warm-up (numba compile, caches)
            times, iters = [], []
            for _ in range(repeats):
                start = time.perf_counter()
                mp = MeanPath(n_points=n_points).fit(demos)
                times.append(time.perf_counter() - start)
                iters.append(mp.n_iter_)
            rows.append(
                {
                    "n_demos": n_demos,
                    "n_points": n_points,
                    "time_s_median": float(np.median(times)),
                    "time_s_min": float(np.min(times)),
                    "iterations": int(np.median(iters)),
                    "us_per_demo_point_iteration": float(
                        np.median(times) / (n_demos * n_points * max(1, np.median(iters))) * 1e6
                    ),
                }
            )
    return rows


def check_targets(rows: list[dict]) -> list[dict]:
    """The issue's accuracy targets, per data set: pass/fail with the figures."""
    by = {(r["dataset"], r["method"]): r for r in rows}
    checks = []
    for name in dict.fromkeys(r["dataset"] for r in rows):
        peers = [by[(name, p)] for p in PEERS if (name, p) in by and not by[(name, p)]["errors"]]
        if not peers:
            continue
        best = min(peers, key=lambda r: r["e2_mean"])
        strict = name in OUTLIER_SETS
        variant = "Mean-Path"  # the default, center="adaptive"
        mp = by[(name, variant)]
        if strict:
            ok = mp["e2_mean"] <= 0.5 * best["e2_mean"]
            rule = "e2 <= 0.5 x best peer"
        else:
            ok = mp["e2_mean"] <= best["e2_mean"] + best["e2_sd"]
            rule = "e2 <= best peer + 1 sd"
        checks.append(
            {
                "dataset": name,
                "method": variant,
                "rule": rule,
                "e2": mp["e2_mean"],
                "best_peer": best["method"],
                "best_peer_e2": best["e2_mean"],
                "best_peer_sd": best["e2_sd"],
                "ratio": mp["e2_mean"] / best["e2_mean"],
                "pass": bool(ok),
            }
        )
        if mp["penetration_max"] is not None:
            checks.append(
                {
                    "dataset": name,
                    "method": variant,
                    "rule": "no penetration > 1 µm",
                    "penetration": mp["penetration_max"],
                    "pass": mp["penetration_max"] == 0.0,
                }
            )
    return checks


# ------------------------------------------------------------------ centres
def _ratio(value: float, best: float) -> float:
    """value / best, 1 where both are zero (an exact path on every seed)."""
    if best > 0:
        return value / best
    return 1.0 if value == 0 else float("inf")


def centre_table(datasets: list[str], seeds: range) -> list[dict]:
    """e2 against the truth of ``MeanPath(center=c)`` for every centre, mean over seeds."""
    rows = []
    for name in datasets:
        errors: dict[str, list[float]] = {c: [] for c in CENTRES}
        times: dict[str, list[float]] = {c: [] for c in CENTRES}
        for seed in seeds:
            data = load_dataset(name, seed=seed)
            for centre in CENTRES:
                start = time.perf_counter()
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    path = MeanPath(n_points=100, center=centre).fit(data.demos).path_
                times[centre].append(time.perf_counter() - start)
                errors[centre].append(metrics.e2(resample(path, 100), data.nominal, n_points=100))
        e2 = {c: float(np.mean(v)) for c, v in errors.items()}
        best = min(e2.values())
        default = CENTRES[0]
        best_other = min(v for c, v in e2.items() if c != default)
        rows.append(
            {
                "dataset": name,
                "units": data.units,
                "e2": e2,
                "e2_sd": {c: float(np.std(v)) for c, v in errors.items()},
                "ratio_to_best": {c: _ratio(v, best) for c, v in e2.items()},
                "default": default,
                "default_ratio_to_best_other": _ratio(e2[default], best_other),
                "time_s_median": {c: float(np.median(v)) for c, v in times.items()},
                "pass": bool(e2[default] <= CENTRE_TARGET * best_other),
            }
        )
    return rows


def print_centres(rows: list[dict], n_seeds: int) -> None:
    print(
        f"\nMean-Path centres: e2 against the truth (units of the set), mean of {n_seeds} seeds, "
        "and its ratio to the best centre"
    )
    header = f"{'data set':<20}" + "".join(
        f"{c + (' (default)' if c == CENTRES[0] else ''):>21}" for c in CENTRES
    )
    print(header + f"{'default/best other':>20}")
    print("-" * (len(header) + 20))
    for r in rows:
        cells = "".join(f"{r['e2'][c]:>13.4g} ({r['ratio_to_best'][c]:.2f})" for c in CENTRES)
        verdict = "PASS" if r["pass"] else "FAIL"
        print(f"{r['dataset']:<20}{cells}{r['default_ratio_to_best_other']:>14.2f} {verdict}")
    worst = max(rows, key=lambda r: r["default_ratio_to_best_other"])
    print(
        f"default ({CENTRES[0]}): at most {worst['default_ratio_to_best_other']:.2f} times the "
        f"best other centre ({worst['dataset']}); target <= {CENTRE_TARGET}"
    )


# ------------------------------------------------------------------ GMR selection
def _gmr_held_out(demos: list[np.ndarray], k: int, seed: int) -> float:
    """Mean held-out distance of GMR(k): fitted on half the demos, scored on the others."""
    halves = (demos[0::2], demos[1::2])
    scores = []
    for train, test in (halves, halves[::-1]):
        if not train or not test or k > sum(len(d) for d in train):
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            path = GMR(n_components=k, random_state=seed).fit(train).path(100)
        scores += [metrics.held_out_distances(path, d)["mean"] for d in test]
    return float(np.mean(scores))


def gmr_table(datasets: list[str], seed: int = 0) -> list[dict]:
    """The exhaustive BIC search against the ladder, on 10 demos × 200 points of each set."""
    rows = []
    for name in datasets:
        data = load_dataset(name, seed=seed)
        demos = [resample(d, GMR_POINTS) for d in data.demos[:GMR_DEMOS]]
        row: dict = {"dataset": name, "n_demos": len(demos), "n_points": GMR_POINTS}
        for label, search in (("old", "exhaustive"), ("new", "ladder")):
            start = time.perf_counter()
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", ComponentLimitWarning)
                warnings.filterwarnings("ignore", module="lfdkit.mimic.orientation")
                k, scores = select_n_components(
                    demos, GMR_CANDIDATES, random_state=seed, search=search
                )
            row[label] = {
                "time_s": time.perf_counter() - start,
                "k": int(k),
                "fits": len(scores),
                "bic": float(scores[k]),
                "at_bound": any(issubclass(w.category, ComponentLimitWarning) for w in caught),
                "held_out_mean": _gmr_held_out(demos, k, seed),
            }
            print(f"  gmr {name:<20} {label}: k={k:>2} in {row[label]['time_s']:.2f} s",
                  file=sys.stderr, flush=True)  # fmt: skip
        row["same_k"] = row["old"]["k"] == row["new"]["k"]
        row["pass"] = bool(row["new"]["time_s"] <= GMR_TARGET_S)
        rows.append(row)
    return rows


def print_gmr(rows: list[dict]) -> None:
    print(
        f"\nGMR component selection by BIC over {GMR_CANDIDATES.start}..{GMR_CANDIDATES.stop - 1}"
        f" ({GMR_DEMOS} demos x {GMR_POINTS} points): exhaustive (old) against ladder (new);"
        " held-out: mean distance of GMR(k) fitted on half the demos to the other half"
    )
    print(
        f"{'data set':<20}{'time old':>9}{'time new':>9}{'ratio':>7}{'k old':>6}{'k new':>6}"
        f"{'fits':>6}{'BIC old':>10}{'BIC new':>10}{'held-out old':>13}{'new':>9}  target"
    )
    for r in rows:
        o, n = r["old"], r["new"]
        bound = "*" if n["at_bound"] else " "
        print(
            f"{r['dataset']:<20}{o['time_s']:>8.2f}s{n['time_s']:>8.2f}s"
            f"{o['time_s'] / n['time_s']:>6.1f}x{o['k']:>6}{n['k']:>5}{bound}{n['fits']:>6}"
            f"{o['bic']:>10.0f}{n['bic']:>10.0f}{o['held_out_mean']:>13.4g}"
            f"{n['held_out_mean']:>9.4g}  {'PASS' if r['pass'] else 'FAIL'}"
        )
    same = sum(r["same_k"] for r in rows)
    near = sum(abs(r["old"]["k"] - r["new"]["k"]) <= 2 for r in rows)
    bound = sum(r["new"]["at_bound"] for r in rows)
    print(
        f"same k on {same} of {len(rows)} sets, within 2 on {near}; new search at its upper "
        f"bound (*, ComponentLimitWarning) on {bound}; target: new <= {GMR_TARGET_S:g} s"
    )


# ------------------------------------------------------------------ startup
_FIT_SCRIPT = """
import json, sys, time
t0 = time.perf_counter()
import numpy as np
from lfdkit.mimic import MeanPath
t1 = time.perf_counter()
with np.load(sys.argv[1]) as archive:
    demos = [archive[k] for k in sorted(archive, key=lambda k: int(k[5:]))]
times = []
for _ in range(2):
    start = time.perf_counter()
    MeanPath(n_points=demos[0].shape[0]).fit(demos)
    times.append(time.perf_counter() - start)
print(json.dumps({"import_s": t1 - t0, "first_fit_s": times[0], "warm_fit_s": times[1]}))
"""

_IMPORTS = {
    "python -c pass": "pass",
    "import lfdkit": "import lfdkit",
    "import lfdkit.mimic": "import lfdkit.mimic",
    "import lfdkit.skill": "import lfdkit.skill",
    "lfdkit --help": "from lfdkit.app.cli import main\n"
    "try:\n    main(['--help'])\nexcept SystemExit:\n    pass",
}


def _fresh(code: str, *args: str, env: dict) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", code, *args],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        timeout=600,
    )


def startup_table(repeats: int = 5) -> dict:
    """Cold and warm Mean-Path fits and import times, each in a fresh interpreter.

    The package is copied without any ``__pycache__`` into a temporary folder,
    so that the first run compiles every numba function as after a fresh
    installation; it writes numba's cache there, which the second run loads.
    """
    source = Path(lfdkit.__file__).parent
    with tempfile.TemporaryDirectory(prefix="lfdkit-startup-") as tmp:
        shutil.copytree(source, Path(tmp) / "lfdkit", ignore=shutil.ignore_patterns("__pycache__"))
        env = {**os.environ, "PYTHONPATH": tmp, "PYTHONDONTWRITEBYTECODE": "1"}
        data = Path(tmp) / "demos.npz"
        demos = band(STARTUP_DEMOS, STARTUP_POINTS, np.random.default_rng(0))
        np.savez(data, **{f"demo_{i}": d for i, d in enumerate(demos)})
        runs = {}
        for label in ("no cache", "cache"):
            runs[label] = json.loads(_fresh(_FIT_SCRIPT, str(data), env=env).stdout)
            print(f"  startup: {label}: {runs[label]}", file=sys.stderr, flush=True)
        imports: dict[str, list[float]] = {k: [] for k in _IMPORTS}
        for _ in range(repeats):  # interleaved, so that a burst of load hits all alike
            for label, code in _IMPORTS.items():
                start = time.perf_counter()
                _fresh(code, env=env)
                imports[label].append(time.perf_counter() - start)
    return {
        "demos": STARTUP_DEMOS,
        "points": STARTUP_POINTS,
        "fits": runs,
        "imports_s_median": {k: float(np.median(v)) for k, v in imports.items()},
        "imports_s_min": {k: float(np.min(v)) for k, v in imports.items()},
        "repeats": repeats,
        "pass_first_fit": bool(runs["no cache"]["first_fit_s"] <= STARTUP_TARGET_S),
        "pass_import": bool(np.median(imports["import lfdkit"]) <= IMPORT_TARGET_S),
    }


def print_startup(result: dict) -> None:
    n, m = result["demos"], result["points"]
    print(f"\nStart-up, fresh interpreters: MeanPath(n_points={m}).fit of {n} demos x {m} points")
    print(f"{'numba cache':<12}{'import':>9}{'first fit':>11}{'warm fit':>10}")
    for label, r in result["fits"].items():
        print(
            f"{label:<12}{r['import_s']:>8.2f}s{r['first_fit_s']:>10.2f}s{r['warm_fit_s']:>9.2f}s"
        )
    verdict = "PASS" if result["pass_first_fit"] else "FAIL"
    print(f"first fit with compilation: target <= {STARTUP_TARGET_S:g} s: {verdict}")
    print(f"wall time of a fresh interpreter, median (min) of {result['repeats']}:")
    for label, t in result["imports_s_median"].items():
        print(f"  {label:<22}{t:>6.2f} s ({result['imports_s_min'][label]:.2f} s)")
    verdict = "PASS" if result["pass_import"] else "FAIL"
    print(f"import lfdkit: target <= {IMPORT_TARGET_S:g} s: {verdict}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5, help="seeds per data set (default 5)")
    parser.add_argument("--datasets", nargs="*", default=list(MIMIC_DATASETS), metavar="NAME")
    parser.add_argument("--output", type=Path, default=Path(__file__).parent / "results" / "mimic")
    parser.add_argument("--no-peers", action="store_true", help="lfdkit methods only")
    parser.add_argument("--no-nlpca", action="store_true", help="skip NLPCA (the slowest)")
    parser.add_argument(
        "--sections",
        nargs="+",
        choices=SECTIONS,
        metavar="SECTION",
        help=f"what to run, of {', '.join(SECTIONS)} (default: all; --quick: "
        "comparison, centres, startup)",
    )
    parser.add_argument("--quick", action="store_true", help="2 seeds, fewer sections")
    args = parser.parse_args(argv)
    seeds = range(2 if args.quick else args.seeds)
    quick_sections = ("comparison", "centres", "startup")
    sections = args.sections or (quick_sections if args.quick else SECTIONS)
    args.output.mkdir(parents=True, exist_ok=True)
    warnings.filterwarnings("ignore", category=UserWarning, module="tslearn")
    result: dict = {
        "benchmark": "mimic",
        "created": time.strftime("%Y-%m-%dT%H:%M:%S"),
        "machine": machine_info(),
        "git": git_state(),
        "sections": list(sections),
        "seeds": list(seeds),
    }

    if "comparison" in sections:
        runs = comparison(args, seeds)
        rows = summarize(runs)
        checks = check_targets(rows)
        print_comparison(rows, checks)
        for filename, fig in comparison_figures(runs, seed=0, gmr_tube=True):
            fig.savefig(args.output / filename, dpi=110)
        result.update(summary=rows, targets=checks, runs=[r.record() for r in runs])

    if "centres" in sections:
        result["centres"] = centre_table(args.datasets, seeds)
        print_centres(result["centres"], len(seeds))

    if "gmr" in sections:
        result["gmr_selection"] = gmr_table(args.datasets)
        print_gmr(result["gmr_selection"])

    if "scaling" in sections:
        result["scaling"] = scaling_table()
        print("\nMean-Path scaling (noisy band, median of 5 fits)")
        print(f"{'N demos':>8} {'M points':>9} {'time':>11} {'iters':>6} {'µs/(N·M·iter)':>14}")
        for r in result["scaling"]:
            print(
                f"{r['n_demos']:>8} {r['n_points']:>9} {r['time_s_median'] * 1000:>8.1f} ms "
                f"{r['iterations']:>6} {r['us_per_demo_point_iteration']:>14.3f}"
            )

    if "startup" in sections:
        result["startup"] = startup_table()
        print_startup(result["startup"])

    result["machine_after"] = machine_info()
    out = args.output / "mimic.json"
    out.write_text(json.dumps(result, indent=1))
    print(f"\nwrote {out} (and figures) in {args.output}", file=sys.stderr)
    return 0


def comparison(args: argparse.Namespace, seeds: range) -> list:
    """Every method on every data set and seed (``comparison`` section)."""
    methods = dict(lfdkit_methods())
    if args.no_nlpca:
        methods.pop("NLPCA")
    if not args.no_peers:
        methods.update(PEER_METHODS)
    total = len(args.datasets) * len(seeds) * len(methods)
    done = [0]

    def progress(run):
        done[0] += 1
        status = "FAILED " + run.error if run.error else f"{run.runtime_s * 1000:8.1f} ms"
        print(
            f"[{done[0]:>4}/{total}] {run.dataset:<20} seed {run.seed} {run.method:<20} {status}",
            file=sys.stderr,
            flush=True,
        )

    return run_comparison(args.datasets, seeds, methods, on_result=progress)


def print_comparison(rows: list[dict], checks: list[dict]) -> None:
    print(format_table(rows))
    print("\nTargets")
    for c in checks:
        if "e2" in c:
            peer = f"{c['best_peer']} {c['best_peer_e2']:.4g} ± {c['best_peer_sd']:.2g}"
            figures = f"e2 {c['e2']:.4g} vs {peer}"
        else:
            figures = f"penetration {c['penetration']:.3g}"
        verdict = "PASS" if c["pass"] else "FAIL"
        print(f"  {verdict}  {c['dataset']:<20} {c['method']:<20} {c['rule']:<24} {figures}")


if __name__ == "__main__":
    raise SystemExit(main())
