"""ProMP benchmark (issue 33): held-out accuracy of via-point conditioning, speed, a peer.

Run ``python benchmarks/promp.py`` (``--quick``: fewer timing repeats).
Prints two tables and writes ``promp.json`` to ``--output``
(``benchmarks/results/promp`` by default).

Accuracy, leave one demonstration out, on ``walking`` (30 demos, 2-D, m) and
``da_vinci`` (3-D, m) of :func:`lfdkit.datasets.load_dataset` (seed 0):
``ProMP(n_basis=15)`` fitted on the others; the held-out demonstration's
points at phase 0, 0.5 and 1 given as exact via-points (``covariance=0``);
RMS distance from the conditioned mean, at the held-out demonstration's own
phases, to its points, against the same for the unconditioned mean (the ratio
is what three via-points buy). Band: fraction of held-out coordinates within
the unconditioned model's ±2 std (0.95 for a Gaussian spread).

Speed: median of ``--repeats`` calls of fit (all demos), condition on 1 and on
3 via-points, the same 1-point conditioning for 1000 sets of points at once
(``condition_many``, time per set), ``mean_path(100)``, ``std(100)`` and
``sample(100, n_points=100)``; the same for ``movement_primitives.promp.ProMP``
side by side where it is installed (``imitate`` on the demos resampled to 100
points; ``condition_position``, three in turn for 3 points, which gives the
same model; one call per set; ``mean_trajectory``; ``var_trajectory``;
``sample_trajectories``), else "not installed". The peer is given our fitted
weight distribution, so both condition and roll out the same model.
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

from lfdkit.datasets import load_dataset
from lfdkit.imitate import ProMP

DATASETS = ("walking", "da_vinci")
N_BASIS = 15
VIA_PHASES = np.array([0.0, 0.5, 1.0])
N_SETS = 1000  # point sets conditioned at once in the batched row


def _point_at(demo: np.ndarray, phase: float) -> np.ndarray:
    s = np.linspace(0.0, 1.0, len(demo))
    return np.array([np.interp(phase, s, demo[:, k]) for k in range(demo.shape[1])])


def held_out(name: str) -> dict[str, Any]:
    demos = load_dataset(name, seed=0).demos
    rms_free, rms_via, inside, total = [], [], 0, 0
    for j, demo in enumerate(demos):
        model = ProMP(n_basis=N_BASIS).fit([d for i, d in enumerate(demos) if i != j])
        s = np.linspace(0.0, 1.0, len(demo))
        points = np.array([_point_at(demo, p) for p in VIA_PHASES])
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            via = model.condition(points, VIA_PHASES)
        if caught:
            print(f"  {name} demo {j}: {caught[0].message}")
        rms_free.append(np.sqrt(np.mean(np.sum((model.mean_at(s) - demo) ** 2, axis=1))))
        rms_via.append(np.sqrt(np.mean(np.sum((via.mean_at(s) - demo) ** 2, axis=1))))
        std = np.sqrt(np.einsum("nii->ni", model.covariance_at(s)))
        inside += int(np.sum(np.abs(demo - model.mean_at(s)) <= 2.0 * std))
        total += demo.size
    free, conditioned = float(np.median(rms_free)), float(np.median(rms_via))
    return {
        "dataset": name,
        "n_demos": len(demos),
        "n_dims": demos[0].shape[1],
        "median_rms_unconditioned_m": free,
        "median_rms_conditioned_m": conditioned,
        "ratio": conditioned / free,
        "within_2std": inside / total,
    }


def _median_time(call: Any, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def speed(repeats: int) -> list[dict[str, Any]]:
    demos = load_dataset("walking", seed=0).demos
    model = ProMP(n_basis=N_BASIS).fit(demos)
    one = model.mean_at([0.5])
    three = model.mean_at(VIA_PHASES) + np.array([[0.0, 0.0], [0.3, -0.3], [0.0, 0.0]])
    sets = one + np.random.default_rng(0).normal(0.0, 0.1, (N_SETS, 1, 2))
    # (operation, call, how many results one call gives: times are per result)
    ours = {
        "fit": (lambda: ProMP(n_basis=N_BASIS).fit(demos), 1),
        "condition 1 point": (lambda: model.condition(one, [0.5]), 1),
        "condition 3 points": (lambda: model.condition(three, VIA_PHASES), 1),
        f"condition 1 point, {N_SETS} sets (per set)": (
            lambda: model.condition_many(sets, [0.5]),
            N_SETS,
        ),
        "mean_path(100)": (lambda: model.mean_path(100), 1),
        "std(100)": (lambda: model.std(100), 1),
        "sample 100 x 100": (lambda: model.sample(100, n_points=100, seed=0), 1),
    }
    peer_calls: dict[str, Any] = {}
    try:
        from movement_primitives.promp import ProMP as PeerProMP
    except ImportError:
        PeerProMP = None
    if PeerProMP is not None:
        t = np.linspace(0.0, 1.0, 100)
        T = np.tile(t, (len(demos), 1))
        Y = np.stack(
            [
                np.c_[[np.interp(t, np.linspace(0, 1, len(d)), d[:, k]) for k in (0, 1)]].T
                for d in demos
            ]
        )
        peer = PeerProMP(n_dims=2, n_weights_per_dim=N_BASIS).from_weight_distribution(
            model.weights_mean_.copy(), model.weights_cov_.copy()
        )

        def peer_three() -> Any:
            out = peer
            for point, phase in zip(three, VIA_PHASES, strict=True):
                out = out.condition_position(point, t=phase, t_max=1.0)
            return out

        peer_calls = {
            "fit": (lambda: PeerProMP(n_dims=2, n_weights_per_dim=N_BASIS).imitate(T, Y), 1),
            "condition 1 point": (lambda: peer.condition_position(one[0], t=0.5, t_max=1.0), 1),
            "condition 3 points": (peer_three, 1),
            f"condition 1 point, {N_SETS} sets (per set)": (
                lambda: peer.condition_position(sets[0, 0], t=0.5, t_max=1.0),
                1,
            ),
            "mean_path(100)": (lambda: peer.mean_trajectory(t), 1),
            "std(100)": (lambda: np.sqrt(peer.var_trajectory(t)), 1),
            "sample 100 x 100": (
                lambda: peer.sample_trajectories(t, 100, np.random.RandomState(0)),
                1,
            ),
        }
    rows = []
    for what, (call, per) in ours.items():
        ours_s = _median_time(call, repeats) / per
        peer_s = None
        if what in peer_calls:
            peer_call, peer_per = peer_calls[what]
            peer_s = _median_time(peer_call, repeats) / peer_per
        rows.append(
            {
                "operation": what,
                "lfdkit_ms": 1e3 * ours_s,
                "movement_primitives_ms": None if peer_s is None else 1e3 * peer_s,
                "speedup": None if peer_s is None else peer_s / ours_s,
            }
        )
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="5 timing repeats instead of 50")
    parser.add_argument("--output", type=Path, default=Path("benchmarks/results/promp"))
    args = parser.parse_args(argv)
    repeats = 5 if args.quick else 50

    accuracy = [held_out(name) for name in DATASETS]
    print(f"\nHeld-out accuracy: ProMP(n_basis={N_BASIS}), via-points at phases 0, 0.5, 1")
    print(f"{'data':<10}{'demos':>6}{'free RMS m':>12}{'via RMS m':>11}{'ratio':>7}{'in 2std':>9}")
    for r in accuracy:
        print(
            f"{r['dataset']:<10}{r['n_demos']:>6}{r['median_rms_unconditioned_m']:>12.4f}"
            f"{r['median_rms_conditioned_m']:>11.4f}{r['ratio']:>7.2f}{r['within_2std']:>9.2f}"
        )
    timings = speed(repeats)
    print(f"\nSpeed on walking (median of {repeats}), ms")
    print(f"{'operation':<40}{'lfdkit':>9}{'movement_primitives':>21}{'speed-up':>10}")
    for r in timings:
        peer = (
            "not installed"
            if r["movement_primitives_ms"] is None
            else (f"{r['movement_primitives_ms']:.3f}")
        )
        ratio = "" if r["speedup"] is None else f"{r['speedup']:.1f}x"
        print(f"{r['operation']:<40}{r['lfdkit_ms']:>9.4f}{peer:>21}{ratio:>10}")

    result = {
        "accuracy": accuracy,
        "speed": timings,
        "repeats": repeats,
        "machine": machine_info(),
        "git": git_state(),
        "packages": package_versions(["numpy", "movement_primitives"]),
    }
    args.output.mkdir(parents=True, exist_ok=True)
    out = write_json(args.output / "promp.json", result)
    print(f"\nwrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
