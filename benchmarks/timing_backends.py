"""Joint-path timing backends side by side: lfdkit's TOPP-RA, toppra, ruckig (jerk-limited).

Run ``python benchmarks/timing_backends.py [--quick]``; prints two tables and
writes ``results/timing_backends.json``.

T1. Time-optimal timing of the same joint paths within the same velocity
and acceleration limits (times the speed fraction ``f``):
:func:`lfdkit.execute.timing.time_parameterize` with ``backend="lfdkit"``
(lfdkit's forward-backward profile), ``"toppra"`` (toppra's TOPP-RA on the
same spline and grid) and ``"ruckig"`` (lfdkit's, then jerk-limited through
its waypoints by ruckig, :mod:`lfdkit.execute.jerk_limited`). The paths:
random 200-waypoint UR5 joint walks, and the joint path of a learned-style
6 s reach over a box on the UR5 (DH), a UR5e and a Panda (URDFs of
``lfdkit/datasets/urdf``). Per backend: duration (s), the largest velocity,
acceleration and jerk over their limits (sampled at 5 kHz, jerk by finite
differences of the accelerations; the jerk limit is ruckig's default,
50 /s times the acceleration limit, for every backend), wall time (ms,
median of 3), and ruckig's largest distance from lfdkit's path at the same
segment fraction (rad).

T2. The person's timing kept (:func:`lfdkit.execute.pipeline.execute_plan`,
the reach at f = 0.5 and 0.2), then jerk-limited by ruckig through the same
waypoint states (:func:`~lfdkit.execute.jerk_limited.through_states`,
``keep_times``): executed / planned duration, jerk over the limit, wall time.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import git_state, json_ready, machine_info, package_versions

from lfdkit.datasets import example_urdf
from lfdkit.io.atomic import atomic_write

DATA = example_urdf("ur5").parent  # the example arms lfdkit ships
RATE = 5000.0  # Hz: where limits are checked
BACKENDS = ("lfdkit", "toppra", "ruckig")


def arms() -> dict[str, Any]:
    from lfdkit.execute.arm import UR5
    from lfdkit.execute.urdf import UrdfArm

    return {
        "UR5 (DH)": UR5,
        "UR5e": UrdfArm(DATA / "ur5e.urdf"),
        "Panda": UrdfArm(DATA / "panda.urdf", tip_link="panda_hand_tcp"),
    }


def reach_plan():
    """A 6 s reach over a 0.2 m box, rest to rest (metres, seconds), as in robot.py."""
    from types import SimpleNamespace

    t = np.linspace(0.0, 6.0, 120)
    s = 0.5 - 0.5 * np.cos(np.pi * t / 6.0)
    p = np.column_stack([np.full_like(t, 0.45), -0.3 + 0.6 * s, 0.15 + 0.22 * np.sin(np.pi * s)])
    return SimpleNamespace(times=t, positions=p)


def limit_use(traj, vmax, amax, jmax) -> dict[str, float]:
    samples = traj.resample(RATE)
    qd, qdd = samples.velocities, samples.accelerations
    jerk = np.diff(qdd, axis=0) * RATE
    return {
        "velocity_of_limit": float((np.abs(qd) / vmax).max()),
        "acceleration_of_limit": float((np.abs(qdd) / amax).max()),
        "jerk_of_limit": float((np.abs(jerk) / jmax).max()),
    }


def median_ms(fn, repeats: int = 3) -> tuple[float, Any]:
    times, out = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - start)
    return 1e3 * float(np.median(times)), out


def path_deviation(jerk_limited, reference) -> float:
    """Largest joint distance (rad) from the reference at the same (uniformly slowed) time."""
    t = np.linspace(0.0, jerk_limited.duration, 20_001)
    slow = jerk_limited.slowdown
    return float(
        np.abs(jerk_limited.sample(t).positions - reference.sample(t / slow).positions).max()
    )


def optimal_case(name: str, q: np.ndarray, arm, f: float) -> dict[str, Any]:
    from lfdkit.execute.jerk_limited import JERK_PER_ACCELERATION
    from lfdkit.execute.timing import time_parameterize

    vmax, amax = arm.max_joint_speed * f, arm.max_joint_acceleration * f * f
    jmax = JERK_PER_ACCELERATION * arm.max_joint_acceleration * f**3
    row: dict[str, Any] = {"case": name, "waypoints": len(q), "speed_fraction": f}
    made = {}
    for backend in BACKENDS:
        try:
            ms, traj = median_ms(
                lambda b=backend: time_parameterize(
                    q,
                    max_velocity=arm.max_joint_speed,
                    max_acceleration=arm.max_joint_acceleration,
                    speed_fraction=f,
                    backend=b,
                )
            )
        except ImportError as exc:
            row[backend] = {"skipped": str(exc)}
            continue
        made[backend] = traj
        row[backend] = {"duration_s": traj.duration, "ms": ms, **limit_use(traj, vmax, amax, jmax)}
    if "ruckig" in made:
        row["ruckig"]["deviation_rad"] = path_deviation(made["ruckig"], made["lfdkit"])
        row["ruckig"]["own_ms"] = row["ruckig"]["ms"] - row["lfdkit"]["ms"]
    for backend in made:
        row[backend]["duration_ratio"] = made[backend].duration / made["lfdkit"].duration
    return row


def kept_case(name: str, arm, f: float) -> dict[str, Any]:
    from lfdkit.execute.jerk_limited import JERK_PER_ACCELERATION, through_states
    from lfdkit.execute.pipeline import execute_plan

    run = execute_plan(reach_plan(), arm, speed_fraction=f, rate=500.0)
    spline = run.trajectory
    vmax, amax = arm.max_joint_speed * f, arm.max_joint_acceleration * f * f
    jmax = JERK_PER_ACCELERATION * arm.max_joint_acceleration * f**3
    row: dict[str, Any] = {"case": name, "speed_fraction": f}
    row["spline"] = {
        "duration_ratio": spline.duration / spline.planned_duration,
        **limit_use(spline, vmax, amax, jmax),
    }
    try:
        states = spline.sample(spline.times)
        ms, traj = median_ms(
            lambda: through_states(
                spline.times,
                states.positions,
                states.velocities,
                states.accelerations,
                max_velocity=vmax,
                max_acceleration=amax,
                max_jerk=jmax,
            )
        )
    except ImportError as exc:
        row["ruckig"] = {"skipped": str(exc)}
        return row
    row["ruckig"] = {
        "duration_ratio": traj.duration / spline.planned_duration,
        "ms": ms,
        "deviation_rad": path_deviation(traj, spline),
        **limit_use(traj, vmax, amax, jmax),
    }
    return row


def print_tables(optimal: list[dict], kept: list[dict]) -> None:
    print("\nT1. time-optimal timing: duration s (x lfdkit) | v, a, jerk over limit | ms")
    for row in optimal:
        print(f"  {row['case']} (f={row['speed_fraction']:g}, {row['waypoints']} waypoints)")
        for backend in BACKENDS:
            r = row[backend]
            if "skipped" in r:
                print(f"    {backend:<7} skipped: {r['skipped']}")
                continue
            extra = f"  deviation {r['deviation_rad']:.1e} rad" if "deviation_rad" in r else ""
            print(
                f"    {backend:<7} {r['duration_s']:8.3f} (x{r['duration_ratio']:.4f}) | "
                f"v {r['velocity_of_limit']:.3f} a {r['acceleration_of_limit']:.3f} "
                f"jerk {r['jerk_of_limit']:8.3g} | {r['ms']:8.1f} ms{extra}"
            )
    print("\nT2. the person's timing (6 s reach): executed/planned | v, a, jerk over limit")
    for row in kept:
        for kind in ("spline", "ruckig"):
            r = row[kind]
            if "skipped" in r:
                continue
            ms = f" | {r['ms']:.1f} ms, deviation {r['deviation_rad']:.1e} rad" if "ms" in r else ""
            print(
                f"  {row['case']:<9} f={row['speed_fraction']:<4g} {kind:<7} "
                f"x{r['duration_ratio']:.4f} | v {r['velocity_of_limit']:.3f} "
                f"a {r['acceleration_of_limit']:.3f} jerk {r['jerk_of_limit']:8.3g}{ms}"
            )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one random path, the UR5 only")
    parser.add_argument(
        "--output",
        type=Path,
        default=Path(__file__).parent / "results" / "timing_backends.json",
    )
    args = parser.parse_args(argv)
    from lfdkit.execute.pipeline import execute_plan

    machines = arms()
    if args.quick:
        machines = {"UR5 (DH)": machines["UR5 (DH)"]}
    optimal = []
    for seed in range(1 if args.quick else 3):
        q = np.cumsum(np.random.default_rng(seed).normal(0.0, 0.05, (200, 6)), axis=0)
        optimal.append(optimal_case(f"random UR5 walk, seed {seed}", q, machines["UR5 (DH)"], 1.0))
    for name, arm in machines.items():
        joints = execute_plan(reach_plan(), arm, speed_fraction=1.0).trajectory.waypoints
        for f in (1.0, 0.2):
            optimal.append(optimal_case(f"reach, {name}", joints, arm, f))
    kept = [kept_case(name, arm, f) for name, arm in machines.items() for f in (0.5, 0.2)]
    print_tables(optimal, kept)
    result = {
        "benchmark": "timing_backends",
        "quick": args.quick,
        "rate_hz": RATE,
        "versions": package_versions(["lfdkit", "numpy", "scipy", "toppra", "ruckig"]),
        "git": git_state(),
        "machine": machine_info(),
        "optimal": optimal,
        "kept": kept,
    }
    args.output.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(json_ready(result), indent=1) + "\n"
    atomic_write(args.output, lambda f: f.write(text), overwrite=True)
    print(f"\nwrote {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
