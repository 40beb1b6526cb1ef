"""Rhythmic DMP benchmark (issue 33): held-out cycles of periodic poses (position, orientation).

Run ``python benchmarks/rhythmic.py`` (``--quick``: 2 seeds instead of 5).
Prints a table and writes ``rhythmic.json`` to ``--output``
(``benchmarks/results/rhythmic`` by default).

Each case is a closed-form periodic movement (a wiping figure-eight in the
plane with a rocking tool, two harmonics each, the tool's rotation about two
axes), sampled unevenly with white noise. The DMPs learn from the first
``TRAIN`` cycles only (period learned, not given) and run on; the *held-out*
cycles that follow (``TEST``) are compared with the noise-free closed form:
RMS and worst position error (relative to the stroke's amplitude), RMS and
worst angle, and the period's relative error. The rollout starts on the cycle
(no ramp), so the held-out error is the learned cycle's and period's drift.
Also the time to fit and to roll out one cycle (pose: position and
orientation, 400 points a cycle), held (the exact solution) and with a
ramp (RK4, compiled; the first rollout compiles and is left out). No peer: movement_primitives
has no rhythmic primitive; MP_PyTorch 0.1.4 (the latest on PyPI) ships a rhythmic
basis and phase marked "TODO" that do not import (the benchmark tries and says
why; the ProMP comparison is in ``benchmarks/promp.py``). The reference is the
closed form.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import git_state, machine_info, package_versions, write_json

from lfdkit.core.rotations import angle_between, exp, multiply
from lfdkit.imitate import RhythmicPoseDMP

TRAIN, TEST = 3.3, 2.0  # cycles learned from, cycles held out
# (name, period s, stroke amplitude, its unit, position noise, angle noise rad)
CASES = (
    ("wipe, m, 1.5 s", 1.5, 0.10, "m", 0.002, 0.002),
    ("wipe, mm, 0.8 s, noisy", 0.8, 100.0, "mm", 5.0, 0.01),
    ("slow polish, cm, 4 s", 4.0, 3.0, "cm", 0.03, 0.001),
)


def movement(t: np.ndarray, period: float, amplitude: float) -> tuple[np.ndarray, np.ndarray]:
    u = 2 * np.pi * t / period
    positions = amplitude * np.c_[np.sin(u), 0.3 * np.sin(2 * u + 0.4), 0.1 * np.cos(u)]
    turn = np.outer(0.25 * np.sin(u + 0.2), [1.0, 0.0, 0.0]) + np.outer(
        0.1 * np.sin(2 * u), [0.0, 0.6, 0.8]
    )
    return positions, multiply(exp(turn), exp(np.array([0.1, 0.2, -0.3])))


def one_case(case: tuple, seed: int) -> dict[str, Any]:
    name, period, amplitude, _unit, noise, angle_noise = case
    rng = np.random.default_rng(seed)
    n = int(TRAIN * 120)
    t = np.r_[0.0, np.sort(rng.uniform(0.0, TRAIN * period, n - 1))]
    positions, orientations = movement(t, period, amplitude)
    positions = positions + rng.normal(0.0, noise, positions.shape)
    orientations = multiply(orientations, exp(rng.normal(0.0, angle_noise / 2, (n, 3))))
    start = time.perf_counter()
    pose = RhythmicPoseDMP().fit(positions, orientations, t)
    fit_s = time.perf_counter() - start
    total = (TRAIN + TEST) * period
    start = time.perf_counter()
    run = pose.rollout(total)
    roll_s = (time.perf_counter() - start) / (TRAIN + TEST)
    # Varying schedules (a smooth start and stop) take the integrated path.
    start = time.perf_counter()
    pose.rollout(total, ramp=period)
    ramp_s = (time.perf_counter() - start) / (TRAIN + TEST)
    held = run.times >= TRAIN * period
    true_p, true_q = movement(run.times[held], period, amplitude)
    error = np.linalg.norm(run.positions[held] - true_p, axis=1) / amplitude
    angle = angle_between(run.orientations[held], true_q)
    return {
        "case": name,
        "seed": seed,
        "period_rel_error": abs(pose.period_ / period - 1.0),
        "rms_position_rel": float(np.sqrt(np.mean(error**2))),
        "max_position_rel": float(error.max()),
        "rms_angle_mrad": 1e3 * float(np.sqrt(np.mean(angle**2))),
        "max_angle_mrad": 1e3 * float(angle.max()),
        "noise_rel": noise / amplitude,
        "angle_noise_mrad": 1e3 * angle_noise,
        "fit_ms": 1e3 * fit_s,
        "rollout_ms_per_cycle": 1e3 * roll_s,
        "rollout_ramp_ms_per_cycle": 1e3 * ramp_s,
    }


def mp_pytorch_rhythmic() -> str:
    """Whether MP_PyTorch's rhythmic primitive can run here, in one line."""
    try:
        from mp_pytorch.basis_gn.rhytmic_basis import RhythmicBasisGenerator  # noqa: F401
    except ImportError as exc:  # 0.1.4: its modules import names the package lacks
        return f"MP_PyTorch rhythmic primitive: not usable ({type(exc).__name__}: {exc})"
    return "MP_PyTorch rhythmic primitive: imports (not compared: no rollout API)"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2 seeds instead of 5")
    parser.add_argument("--output", type=Path, default=Path("benchmarks/results/rhythmic"))
    args = parser.parse_args(argv)
    seeds = range(2 if args.quick else 5)
    one_case(CASES[0], 0)  # compiles the RK4 kernel (or loads it from numba's cache)
    rows = [one_case(case, seed) for case in CASES for seed in seeds]
    print(f"\nHeld-out cycles ({TEST:g} after {TRAIN:g} learned), worst over {len(seeds)} seeds")
    head = ("case", "noise", "period err", "pos RMS", "pos max", "angle RMS", "angle max")
    print(
        f"{head[0]:<24}{head[1]:>14}{head[2]:>11}{head[3]:>9}{head[4]:>9}{head[5]:>11}{head[6]:>11}"
    )
    for case in CASES:
        mine = [r for r in rows if r["case"] == case[0]]
        worst = {k: max(r[k] for r in mine) for k in mine[0] if k not in ("case", "seed")}
        noise = f"{worst['noise_rel']:.0%}/{worst['angle_noise_mrad']:.0f}mrad"
        print(
            f"{case[0]:<24}{noise:>14}{worst['period_rel_error']:>11.1e}"
            f"{worst['rms_position_rel']:>9.2%}{worst['max_position_rel']:>9.2%}"
            f"{worst['rms_angle_mrad']:>9.2f}mr{worst['max_angle_mrad']:>9.2f}mr"
        )
    fit = np.median([r["fit_ms"] for r in rows])
    roll = np.median([r["rollout_ms_per_cycle"] for r in rows])
    ramp = np.median([r["rollout_ramp_ms_per_cycle"] for r in rows])
    print(
        f"\nmedian fit {fit:.0f} ms (position and orientation); rollout of a pose, 400 points "
        f"a cycle: {roll:.2f} ms per cycle held, {ramp:.2f} ms with a ramp (integrated)"
    )
    peer = mp_pytorch_rhythmic()
    print(peer)
    result = {
        "rows": rows,
        "peer": peer,
        "train_cycles": TRAIN,
        "test_cycles": TEST,
        "machine": machine_info(),
        "git": git_state(),
        "packages": package_versions(["numpy"]),
    }
    args.output.mkdir(parents=True, exist_ok=True)
    out = write_json(args.output / "rhythmic.json", result)
    print(f"\nwrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
