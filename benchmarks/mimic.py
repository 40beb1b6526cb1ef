"""Mimicking benchmark: every method on every data set over several seeds.

Run ``python benchmarks/mimic.py`` (``--help`` for options). Prints one table
(e1, e2 mean ± sd over seeds, penetration, median runtime), a scaling table for
Mean-Path, writes ``mimic.json`` and figures to ``--output``
(``benchmarks/results/mimic`` by default).

Peers, side by side in the same run (install with ``pip install -e .[bench]``):
the ``gmr`` package (same number of components as lfdkit's GMR, chosen by BIC),
tslearn's DBA and soft-DTW barycenters. The point-wise average after arc-length
resampling is lfdkit's own naive baseline.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from _common import machine_info

from lfdkit.datasets import MIMIC_DATASETS
from lfdkit.evaluation import (
    comparison_figures,
    format_table,
    gmr_components,
    lfdkit_methods,
    run_comparison,
    summarize,
)
from lfdkit.mimic import MeanPath

#: Data sets with outliers, where the issue asks for half the best peer's e2,
#: and the robust centre suited to each: one-sided residuals with no other noise
#: (the median lands on the clean profile), occasional swerves (the biweight).
ROBUST_VARIANT = {
    "deburring_linear": "Mean-Path (median)",
    "deburring_circular": "Mean-Path (median)",
    "local_detours": "Mean-Path (biweight)",
}

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
    from lfdkit.geometry import resample

    demos = [resample((d - centre) / scale, 100) for d in demoset.demos]
    init = np.mean(demos, axis=0)
    return softdtw_barycenter(np.array(demos), gamma=0.01, max_iter=50, init=init) * scale + centre


PEER_METHODS = {
    "gmr (package)": _gmr_package,
    "DBA (tslearn)": _dba,
    "soft-DTW (tslearn)": _soft_dtw,
}


def scaling_table(repeats: int = 5) -> list[dict]:
    """Mean-Path fit time for N demos × M points on a noisy band."""
    rows = []
    rng = np.random.default_rng(0)
    for n_points in (100, 1000):
        s = np.linspace(0.0, np.pi, n_points)
        nominal = np.column_stack((s, np.sin(s)))
        normal = (
            np.column_stack((-np.cos(s), np.ones_like(s))) / np.sqrt(1 + np.cos(s) ** 2)[:, None]
        )
        for n_demos in (2, 10, 100):
            demos = []
            for _ in range(n_demos):
                phase = rng.uniform(0, 2 * np.pi, 3)
                offset = sum(0.05 * np.sin((k + 1) * s + phase[k]) for k in range(3))
                demos.append(
                    nominal + offset[:, None] * normal + rng.normal(0, 0.002, (n_points, 2))
                )
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
        strict = name in ROBUST_VARIANT
        variant = ROBUST_VARIANT.get(name, "Mean-Path")
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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5, help="seeds per data set (default 5)")
    parser.add_argument("--datasets", nargs="*", default=list(MIMIC_DATASETS), metavar="NAME")
    parser.add_argument("--output", type=Path, default=Path(__file__).parent / "results" / "mimic")
    parser.add_argument("--no-peers", action="store_true", help="lfdkit methods only")
    parser.add_argument("--no-nlpca", action="store_true", help="skip NLPCA (the slowest)")
    parser.add_argument("--quick", action="store_true", help="2 seeds, no scaling table")
    args = parser.parse_args(argv)
    seeds = range(2 if args.quick else args.seeds)
    args.output.mkdir(parents=True, exist_ok=True)
    warnings.filterwarnings("ignore", category=UserWarning, module="tslearn")

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

    runs = run_comparison(args.datasets, seeds, methods, on_result=progress)
    rows = summarize(runs)
    print(format_table(rows))
    checks = check_targets(rows)
    print("\nTargets")
    for c in checks:
        if "e2" in c:
            peer = f"{c['best_peer']} {c['best_peer_e2']:.4g} ± {c['best_peer_sd']:.2g}"
            figures = f"e2 {c['e2']:.4g} vs {peer}"
        else:
            figures = f"penetration {c['penetration']:.3g}"
        verdict = "PASS" if c["pass"] else "FAIL"
        print(f"  {verdict}  {c['dataset']:<20} {c['method']:<20} {c['rule']:<24} {figures}")

    scaling = [] if args.quick else scaling_table()
    if scaling:
        print("\nMean-Path scaling (noisy band, median of 5 fits)")
        print(f"{'N demos':>8} {'M points':>9} {'time':>11} {'iters':>6} {'µs/(N·M·iter)':>14}")
        for r in scaling:
            print(
                f"{r['n_demos']:>8} {r['n_points']:>9} {r['time_s_median'] * 1000:>8.1f} ms "
                f"{r['iterations']:>6} {r['us_per_demo_point_iteration']:>14.3f}"
            )

    for filename, fig in comparison_figures(runs, seed=0, gmr_tube=True):
        fig.savefig(args.output / filename, dpi=110)
    result = {
        "benchmark": "mimic",
        "created": time.strftime("%Y-%m-%dT%H:%M:%S"),
        "machine": machine_info(),
        "seeds": list(seeds),
        "summary": rows,
        "targets": checks,
        "scaling": scaling,
        "runs": [r.record() for r in runs],
    }
    out = args.output / "mimic.json"
    out.write_text(json.dumps(result, indent=1))
    print(f"\nwrote {out} and figures in {args.output}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
