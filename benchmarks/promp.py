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

Speed: median over ``--repeats`` blocks (each about 1 ms of calls; wall and
CPU time; the blocks of one row alternate between lfdkit and the peers, so a
change of load falls on both) of fit (all demos); condition on 1 via-point
at a phase seen before and at a new phase every call; on 3 via-points at
phases seen before (0, 0.5, 1) and at 3 new phases every call; the last two
with the conditioned covariance read (``weights_cov_``: lfdkit forms it on
first read, the peer in every call, so only these rows compare the same
work; the peer's ``weight_cov`` read too); the same
1-point conditioning for 1000 sets of points at once (``condition_many``,
time per set); condition and roll out (1 point, then ``mean_path(100)``; 1
point at a new phase, then ``std(100)``, which forms the conditioned
covariance lfdkit forms only when read); ``mean_path(100)``, ``std(100)``
and ``sample(100, n_points=100)``; the same for
``movement_primitives.promp.ProMP`` side by side where it is installed
(``imitate`` on the demos resampled to 100 points; ``condition_position``,
three in turn for 3 points, which gives the same model; one call per set;
``mean_trajectory``; ``var_trajectory``; ``sample_trajectories``), else "not
installed". The peer is given our fitted weight distribution, so both
condition and roll out the same model. ``--kernels`` (default ``numba``)
sets ``LFDKIT_KERNELS``: conditioning is a compiled kernel with a NumPy
twin, and a process that conditions many times runs the compiled one.

MP_PyTorch (``mp_pytorch``, benchmark-only: it needs PyTorch, and lfdkit does
not depend on either) where it imports: its ``ProMP`` (float64, linear phase,
normalised RBFs with ``basis_bandwidth_factor=1``: the same basis as ours)
given our weight distribution (the covariance plus 1e-12 of its largest
entry on the diagonal: it takes a Cholesky factor), ``learn_mp_params_from_trajs``
on the resampled demos (batched) and the weights' mean and covariance for
fit, ``get_traj_pos``, ``get_traj_pos_std`` and ``sample_trajectories`` (new
inputs each call: it caches results for unchanged inputs). It has no
conditioning on via-points. The largest differences of its mean path and of
its variances (``get_traj_pos_cov(reg=0)``: by default it adds 1e-4 of the
largest variance to each) from ours are printed (agreement check).
"""

from __future__ import annotations

import argparse
import os
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


def _block_size(call: Any) -> int:
    """How many calls fill about a millisecond (so microsecond calls are not timer noise).

    Sized by the fastest of five calls after one that warms up: sized by a single
    call, a first call's one-time costs (numba loading a kernel) or a call the
    machine preempted made the blocks single calls, each cold after the other
    library's block (the first conditioning row took 2x its steady time).
    """
    call()
    fastest = np.inf
    for _ in range(5):
        start = time.perf_counter()
        call()
        fastest = min(fastest, time.perf_counter() - start)
    return max(1, min(1000, int(1e-3 / max(fastest, 1e-7))))


def _time_block(call: Any, per_block: int) -> tuple[float, float]:
    """Wall and CPU seconds (this process, all threads) of one call, over one block."""
    wall, cpu = time.perf_counter(), time.process_time()
    for _ in range(per_block):
        call()
    return (time.perf_counter() - wall) / per_block, (time.process_time() - cpu) / per_block


def _median_times(calls: list[Any], repeats: int) -> list[tuple[float, float]]:
    """Median wall and CPU seconds of one call of each of ``calls``, over ``repeats`` blocks.

    The calls' blocks alternate (ours, a peer's, ours, ...), so a change of the
    machine's load falls on all of them alike; CPU time is kept too, since the
    machine is shared.
    """
    sizes = [_block_size(call) for call in calls]
    samples: list[list[tuple[float, float]]] = [[] for _ in calls]
    for _ in range(repeats):
        for call, size, kept in zip(calls, sizes, samples, strict=True):
            kept.append(_time_block(call, size))
    return [
        (float(np.median([w for w, _ in kept])), float(np.median([c for _, c in kept])))
        for kept in samples
    ]


def _new_phases(phases: Any) -> list[float]:
    """Three new phases in increasing order (from the iterator ``phases``)."""
    return sorted(next(phases) for _ in range(3))


def _resampled(demos: list[np.ndarray], t: np.ndarray) -> np.ndarray:
    """The demos at phases ``t``, shape (n_demos, len(t), n_dims) (the peers' input)."""
    return np.stack(
        [
            np.c_[[np.interp(t, np.linspace(0, 1, len(d)), d[:, k]) for k in range(d.shape[1])]].T
            for d in demos
        ]
    )


def mp_pytorch_calls(model: ProMP, demos: list[np.ndarray], t: np.ndarray) -> dict[str, Any]:
    """MP_PyTorch's ProMP on our weight distribution: timed calls and an agreement check.

    Returns ``{}`` with a message printed where it does not import.
    """
    try:
        import torch
        from mp_pytorch.basis_gn import NormalizedRBFBasisGenerator
        from mp_pytorch.mp import ProMP as TorchProMP
        from mp_pytorch.phase_gn import LinearPhaseGenerator
    except ImportError as exc:
        print(f"  MP_PyTorch: not installed ({exc}); pip install mp_pytorch torch to compare")
        return {}
    torch.set_num_threads(1)  # small tensors: threads only wait (as for BLAS below)
    f64 = torch.float64

    def make() -> Any:
        phase = LinearPhaseGenerator(tau=1.0, dtype=f64)
        basis = NormalizedRBFBasisGenerator(
            phase, num_basis=N_BASIS, basis_bandwidth_factor=1, dtype=f64
        )
        return TorchProMP(basis, num_dof=model.n_dims_, dtype=f64)

    peer = make()
    times = torch.as_tensor(t, dtype=f64)
    n_weights = len(model.weights_mean_)
    cov = model.weights_cov_ + 1e-12 * np.abs(model.weights_cov_).max() * np.eye(n_weights)
    mean = torch.tensor(np.array(model.weights_mean_))  # a copy: ours is read-only
    root = torch.linalg.cholesky(torch.as_tensor(cov))
    trajs = torch.as_tensor(_resampled(demos, t))
    batch_times = times.expand(len(demos), -1)

    def fit() -> Any:
        weights = make().learn_mp_params_from_trajs(batch_times, trajs)["params"]
        return weights.mean(0), torch.cov(weights.T)

    def rollout() -> Any:
        return peer.get_traj_pos(times=times, params=mean)

    def band() -> Any:
        return peer.get_traj_pos_std(times=times, params_L=root)

    def samples() -> Any:
        torch.manual_seed(0)
        return peer.sample_trajectories(times=times, params=mean, params_L=root, num_smp=100)

    # Agreement on the same weights (their covariance has the 1e-12 jitter; ours not).
    mean_gap = float(np.abs(rollout().numpy() - model.mean_path(len(t))).max())
    # Variances, relative (where the band is 0, all demos starting together, the
    # square root turns the jitter's 1e-12 into 1e-6 of the band's width). Its
    # band adds 1e-4 of the largest variance to each (``reg``); compared without.
    cov_paths = peer.get_traj_pos_cov(times=times, params_L=root, reg=0.0)
    theirs_var = torch.diagonal(cov_paths).reshape(model.n_dims_, -1).T.numpy()
    ours_var = model.std(len(t)) ** 2
    std_gap = float(np.abs(theirs_var - ours_var).max() / ours_var.max())
    print(
        f"  MP_PyTorch on our weights: mean path within {mean_gap:.1e} m of ours, "
        f"variances within {std_gap:.1e} of the largest"
    )
    return {
        "fit": (fit, 1),
        "mean_path(100)": (rollout, 1),
        "std(100)": (band, 1),
        "sample 100 x 100": (samples, 1),
        "agreement": {"mean_path_max_m": mean_gap, "variance_max_relative": std_gap},
    }


def _peers(peer_calls: dict, torch_calls: dict) -> list[tuple[str, dict]]:
    """The peers' names with their timed calls."""
    return [("movement_primitives", peer_calls), ("mp_pytorch", torch_calls)]


def speed(repeats: int) -> tuple[list[dict[str, Any]], dict[str, Any] | None]:
    demos = load_dataset("walking", seed=0).demos
    model = ProMP(n_basis=N_BASIS).fit(demos)
    one = model.mean_at([0.5])
    three = model.mean_at(VIA_PHASES) + np.array([[0.0, 0.0], [0.3, -0.3], [0.0, 0.0]])
    sets = one + np.random.default_rng(0).normal(0.0, 0.1, (N_SETS, 1, 2))
    # A new phase every call (none repeats, so nothing kept per phase helps).
    fresh = np.random.default_rng(1).uniform(0.05, 0.95, 6000 * (repeats + 1)).tolist()
    ours_phases, peer_phases = iter(fresh), iter(fresh)
    # (operation, call, how many results one call gives: times are per result)
    ours = {
        "fit": (lambda: ProMP(n_basis=N_BASIS).fit(demos), 1),
        "condition 1 point (phase seen before)": (lambda: model.condition(one, [0.5]), 1),
        "condition 1 point (new phase)": (lambda: model.condition(one, [next(ours_phases)]), 1),
        "condition 3 points (phases seen before)": (
            lambda: model.condition(three, VIA_PHASES),
            1,
        ),
        "condition 3 points (new phases)": (
            lambda: model.condition(three, _new_phases(ours_phases)),
            1,
        ),
        # lfdkit forms a conditioned covariance when first read, the peer in every call:
        # with it read, both do the same work.
        "condition 1 point (new phase) + weights_cov_": (
            lambda: model.condition(one, [next(ours_phases)]).weights_cov_,
            1,
        ),
        "condition 3 points (new phases) + weights_cov_": (
            lambda: model.condition(three, _new_phases(ours_phases)).weights_cov_,
            1,
        ),
        f"condition 1 point, {N_SETS} sets (per set)": (
            lambda: model.condition_many(sets, [0.5]),
            N_SETS,
        ),
        "condition 1 point + mean_path(100)": (
            lambda: model.condition(one, [0.5]).mean_path(100),
            1,
        ),
        "condition 1 point (new phase) + std(100)": (
            lambda: model.condition(one, [next(ours_phases)]).std(100),
            1,
        ),
        "mean_path(100)": (lambda: model.mean_path(100), 1),
        "std(100)": (lambda: model.std(100), 1),
        "sample 100 x 100": (lambda: model.sample(100, n_points=100, seed=0), 1),
    }
    peer_calls: dict[str, Any] = {}
    t = np.linspace(0.0, 1.0, 100)
    try:
        from movement_primitives.promp import ProMP as PeerProMP
    except ImportError:
        PeerProMP = None
    if PeerProMP is not None:
        T = np.tile(t, (len(demos), 1))
        Y = _resampled(demos, t)
        peer = PeerProMP(n_dims=2, n_weights_per_dim=N_BASIS).from_weight_distribution(
            model.weights_mean_.copy(), model.weights_cov_.copy()
        )

        def peer_three(phases: Any) -> Any:
            out = peer
            for point, phase in zip(three, phases, strict=True):
                out = out.condition_position(point, t=phase, t_max=1.0)
            return out

        peer_calls = {
            "fit": (lambda: PeerProMP(n_dims=2, n_weights_per_dim=N_BASIS).imitate(T, Y), 1),
            "condition 1 point (phase seen before)": (
                lambda: peer.condition_position(one[0], t=0.5, t_max=1.0),
                1,
            ),
            "condition 1 point (new phase)": (
                lambda: peer.condition_position(one[0], t=next(peer_phases), t_max=1.0),
                1,
            ),
            "condition 3 points (phases seen before)": (lambda: peer_three(VIA_PHASES), 1),
            "condition 3 points (new phases)": (
                lambda: peer_three(_new_phases(peer_phases)),
                1,
            ),
            "condition 1 point (new phase) + weights_cov_": (
                lambda: peer.condition_position(one[0], t=next(peer_phases), t_max=1.0).weight_cov,
                1,
            ),
            "condition 3 points (new phases) + weights_cov_": (
                lambda: peer_three(_new_phases(peer_phases)).weight_cov,
                1,
            ),
            f"condition 1 point, {N_SETS} sets (per set)": (
                lambda: peer.condition_position(sets[0, 0], t=0.5, t_max=1.0),
                1,
            ),
            "condition 1 point + mean_path(100)": (
                lambda: peer.condition_position(one[0], t=0.5, t_max=1.0).mean_trajectory(t),
                1,
            ),
            "condition 1 point (new phase) + std(100)": (
                lambda: np.sqrt(
                    peer.condition_position(one[0], t=next(peer_phases), t_max=1.0).var_trajectory(
                        t
                    )
                ),
                1,
            ),
            "mean_path(100)": (lambda: peer.mean_trajectory(t), 1),
            "std(100)": (lambda: np.sqrt(peer.var_trajectory(t)), 1),
            "sample 100 x 100": (
                lambda: peer.sample_trajectories(t, 100, np.random.RandomState(0)),
                1,
            ),
        }
    torch_calls = mp_pytorch_calls(model, demos, t)
    agreement = torch_calls.pop("agreement", None)
    rows = []
    for what, (call, per) in ours.items():
        peers = [
            (name, calls[what]) for name, calls in _peers(peer_calls, torch_calls) if what in calls
        ]
        timed = _median_times([call] + [peer_call for _, (peer_call, _) in peers], repeats)
        ours_s, ours_cpu = (x / per for x in timed[0])
        row: dict[str, Any] = {
            "operation": what,
            "lfdkit_ms": 1e3 * ours_s,
            "lfdkit_cpu_ms": 1e3 * ours_cpu,
        }
        peer_times = {name: t for (name, _), t in zip(peers, timed[1:], strict=True)}
        for name, calls in _peers(peer_calls, torch_calls):
            peer_s = peer_cpu = None
            if name in peer_times:
                peer_per = calls[what][1]
                peer_s, peer_cpu = (x / peer_per for x in peer_times[name])
            row[f"{name}_ms"] = None if peer_s is None else 1e3 * peer_s
            row[f"{name}_cpu_ms"] = None if peer_cpu is None else 1e3 * peer_cpu
            row[f"speedup_{name}"] = None if peer_s is None else peer_s / ours_s
            row[f"cpu_speedup_{name}"] = (
                None if peer_cpu is None or not ours_cpu else peer_cpu / ours_cpu
            )
        rows.append(row)
    return rows, agreement


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="5 timing repeats instead of 50")
    parser.add_argument("--output", type=Path, default=Path("benchmarks/results/promp"))
    parser.add_argument(
        "--kernels",
        choices=("auto", "numba", "numpy"),
        default="numba",
        help="LFDKIT_KERNELS for the run (default numba: the steady state of a process that "
        "conditions many times, where 'auto' arrives after 1 s of CPU)",
    )
    args = parser.parse_args(argv)
    repeats = 5 if args.quick else 50
    os.environ["LFDKIT_KERNELS"] = args.kernels

    accuracy = [held_out(name) for name in DATASETS]
    print(f"\nHeld-out accuracy: ProMP(n_basis={N_BASIS}), via-points at phases 0, 0.5, 1")
    print(f"{'data':<10}{'demos':>6}{'free RMS m':>12}{'via RMS m':>11}{'ratio':>7}{'in 2std':>9}")
    for r in accuracy:
        print(
            f"{r['dataset']:<10}{r['n_demos']:>6}{r['median_rms_unconditioned_m']:>12.4f}"
            f"{r['median_rms_conditioned_m']:>11.4f}{r['ratio']:>7.2f}{r['within_2std']:>9.2f}"
        )
    timings, agreement = speed(repeats)
    print(
        f"\nSpeed on walking (median of {repeats} blocks), wall ms; speed-up = peer / lfdkit "
        "(wall, and CPU time of this process)"
    )
    print(
        f"{'operation':<48}{'lfdkit':>9}{'movement_primitives':>21}{'speed-up':>10}{'CPU':>8}"
        f"{'MP_PyTorch':>12}{'speed-up':>10}"
    )
    for r in timings:
        cells = []
        for name in ("movement_primitives", "mp_pytorch"):
            ms, ratio = r[f"{name}_ms"], r[f"speedup_{name}"]
            cells.append("-" if ms is None else f"{ms:.4f}")
            cells.append("" if ratio is None else f"{ratio:.1f}x")
        cpu = r["cpu_speedup_movement_primitives"]
        print(
            f"{r['operation']:<48}{r['lfdkit_ms']:>9.4f}{cells[0]:>21}{cells[1]:>10}"
            f"{'' if cpu is None else f'{cpu:.1f}x':>8}{cells[2]:>12}{cells[3]:>10}"
        )
    print("  '-': the peer has no such operation (MP_PyTorch: no via-point conditioning)")
    print(f"  LFDKIT_KERNELS={args.kernels}; blocks of each row alternate between the libraries")

    result = {
        "accuracy": accuracy,
        "speed": timings,
        "mp_pytorch_agreement": agreement,
        "repeats": repeats,
        "kernels": args.kernels,
        "machine": machine_info(),
        "git": git_state(),
        "packages": package_versions(["numpy", "movement_primitives", "mp_pytorch", "torch"]),
    }
    args.output.mkdir(parents=True, exist_ok=True)
    out = write_json(args.output / "promp.json", result)
    print(f"\nwrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
