"""UR5 robot benchmark: kinematics, MuJoCo model and the sweeping experiment.

Run ``python benchmarks/robot.py`` (``--help`` for options; ``--quick`` for a
smoke run of about a minute; the full run takes about five). Prints one
table per section and a final targets table (PASS/FAIL/SKIP), writes ``robot.json`` to ``--output``
(``benchmarks/results/robot`` by default). Exits 0 even when a target fails.
All work runs under ``threadpoolctl.threadpool_limits(1)`` (one BLAS thread:
the machine has two cores and may be shared).

The model is :data:`lfdkit.execute.arm.UR5` with the kinematics of
:mod:`lfdkit.execute.ur5`: the thesis's standard DH table
(Table 6.3; ``d = (0.08916, 0, 0, 0.10915, 0.09465, 0.0823)`` m,
``a = (0, -0.425, -0.39225, 0, 0, 0)`` m, ``alpha = (π/2, 0, 0, π/2, -π/2, 0)``,
link transform ``Rz(θ) Tz(d) Tx(a) Rx(α)``), ``forward`` (FK) and ``inverse``
(closed-form IK, all eight branches, NaN rows where a branch does not exist).

Errors between two poses: position error = Euclidean distance of the
translations (m); rotation error = Frobenius norm ``‖R_a - R_b‖_F``
(dimensionless), also given as the angle of ``R_aᵀ R_b``,
``2 asin(‖R_a - R_b‖_F / (2√2))`` (rad; accurate near 0, unlike ``acos``).

Kinematics
==========

K1. FK cross-check
------------------
``N`` random configurations (10,000; 1,000 with ``--quick``), uniform in
``[-π, π]^6``. ``lfdkit.execute.ur5.forward`` against two independent
implementations of the same DH chain:

* roboticstoolbox-python: ``rtb.DHRobot([rtb.RevoluteDH(d, a, alpha), ...])``
  built from the thesis's table (NOT rtb's own ``models.DH.UR5``, whose
  parameters need not be the thesis's), ``robot.fkine(q_batch)``;
* pytransform3d: per configuration and joint, ``Rz(θ) Tz(d) Tx(a) Rx(α)`` as a
  product of ``transformations.transform_from(rotations.active_matrix_from_angle
  (...), ...)`` matrices.

Reported: max position and rotation error. Target: max position error
< 1e-9 m against rtb (SKIP when roboticstoolbox-python cannot be imported;
pytransform3d is a reference row judged the same way).

K2. IK round trip
-----------------
``N`` reachable poses (10,000; 1,000 with ``--quick``) ``forward(q)`` of
random ``q`` in ``[-π, π]^6``; ``inverse(poses, strict=False)`` returns all
branches. Every non-NaN solution is put through ``forward`` and compared with
its pose. Reported: poses, solutions checked, how many poses have 8/6/4/2 (or
another number of) valid branches, max position and rotation error over all
solutions, and the share of poses whose original ``q`` is among the solutions
(modulo 2π, max joint difference < 1e-6 rad); for information also the share
where it is the row ``branch(q)`` names. Targets: every solution within
1e-9 m and 1e-9 (Frobenius) of its pose; the original ``q`` recovered for
100 % of poses.

K3. Throughput
--------------
Median of 5 repeats (``time.perf_counter``) of ``forward`` on 10,000
configurations and ``inverse`` on 10,000 poses (1,000 each with ``--quick``),
as ms per call, µs per pose and poses per second, side by side with rtb:
``robot.fkine(q_batch)`` on the same configurations, and rtb's numerical IK
``robot.ik_LM(T, q0=...)`` (C++ Levenberg-Marquardt, random start from the
seeded generator, rtb's own random restarts) on the first 200 poses (50 with
``--quick``), timed per pose, twice: with rtb's default ``tol=1e-6`` and with
``tol=1e-24``. rtb's tolerance bounds its residual ``E = ½ eᵀ W e``, the SQUARE
of the pose error, so ``tol=1e-6`` lets the position be off by up to about
1.4 mm and ``tol=1e-24`` by about 1.4e-12 m (comparable with lfdkit's
closed form; the time per call hardly changes). The success count and the max
and median position errors of rtb's solutions are reported. Ratios are rtb's
time per pose over lfdkit's.

Note that rtb's numerical IK returns ONE solution per call (which of them
depends on the start), while lfdkit's ``inverse`` returns all eight branches
of every pose; the IK ratio compares one rtb solution with eight lfdkit ones.
Absolute times are noisy on this shared two-core machine; the ratios are what
matters. No speed targets.

Any arm (section A; ``--arms-only`` runs it alone, about a minute)
=================================================================

The URDFs of ``lfdkit/datasets/urdf`` (a UR5 written from the thesis's DH table,
a UR5e from UR's published DH table, a Panda from Franka's parameters), read by
:class:`lfdkit.execute.urdf.UrdfArm`.

A1. FK: random configurations within the joint limits (2,000; 300 with
``--quick``) against pinocchio (``pip install pin``; SKIP without it) and, for
the UR5, the DH arm. Target: max position error < 1e-9 m. Times per
configuration: lfdkit batched (NumPy), pinocchio in a Python loop (its API).

A2. Numerical IK: poses of random configurations, started 0.1 rad (uniform
per joint) away (200; 40 with ``--quick``); lfdkit's damped least squares
(:func:`lfdkit.execute.kinematics.solve_pose`) against the same loop on
pinocchio's C++ kinematics (``log6`` error, same damping, step cap and
tolerance). Success: position error < 1e-6 m. Ratio: lfdkit's time over
pinocchio's.

A3. The learned timing kept: a 6 s reach over a 0.2 m box (rest to rest)
through :func:`lfdkit.execute.pipeline.execute_plan` at speed fractions 1,
0.5, 0.2, 0.1 (1 and 0.5 with ``--quick``): executed over planned duration,
and the largest joint speed and acceleration as fractions of the limits in
force. Target: within 5 % of the learned duration at full limits.

A4. Time-optimal timing of the same joint path (the arm's full limits):
:func:`lfdkit.execute.timing.time_parameterize` against toppra (TOPP-RA,
``SplineInterpolator`` with the same natural spline in joint arc length,
joint velocity and acceleration constraints, ``ParametrizeConstAccel``):
durations, the largest fraction of a limit used (sampled at 5,001 instants),
wall times and their ratios. No target: reported side by side.

Simulation
==========

S1. MuJoCo kinematics
---------------------
``lfdkit.execute.mujoco`` builds the MuJoCo model from the same description; MuJoCo's
own flange pose (``flange_poses``, ``mj_kinematics``) is compared with
``ur5.forward`` on 2,000 random configurations (500 with ``--quick``).
Target: max position error < 1e-9 m.

S2. The sweeping experiment (thesis §6.4)
-----------------------------------------
The skill is learned from the shipped example (``lfdkit.tasks.sweeping``: sweeping
demonstrations with a cup and with a marker from the synthetic demonstrator,
seed 0), as ``lfdkit demo`` does. ``random_scenarios(N, seed)`` (60; 10 with
``--quick``) moves the dustpan and places a cup and a marker near the straight
sweep (``lfdkit.tasks.sweeping.scenarios``). Every scenario is planned by each
planner and executed in MuJoCo (``execute_sweep``: corner rounding 1 cm,
continuous IK, time-parameterised at 20 % of the UR5's joint limits,
joint position control):

* ``learned skill``: ``Skill.plan`` (MPC H=8) with the goal approach (0.1 m);
* ``learned, thesis end``: the same without the goal term (the thesis's model);
* ``replay generalized path``: the generalized path, unchanged;
* ``DMP alone``: the DMP carried to the new goal;
* ``DMP + coupling``: movement_primitives' ``DMP`` (30 weights) imitating the
  generalized path, with ``CouplingTermObstacleAvoidance2D`` (Hoffmann et al.
  2009) per obstacle, γ and β grid-searched on the training demonstrations
  (lowest MSE to the demonstrations, as in ``benchmarks/emulate/``);
* ``true reward``: the demonstrator's reward with the goal approach (a reference).

A run succeeds when the cube ends on the dustpan's floor, no cup or marker is
touched (any contact except with the table), and the flange stays within
5 mm of the planned flange position at every 2 ms step. Targets: the learned
skill succeeds in ≥ 95 % of at least 50 scenarios; its tracking error ≤ 5 mm.
Figures: ``robot_scenarios.png`` (top views of the first four scenarios) and,
where OpenGL (EGL) is available, ``robot_render.png`` (the learned skill's run
in scenario 0).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from _common import git_state, machine_info, package_versions
from threadpoolctl import threadpool_limits

from lfdkit.datasets import example_urdf
from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5
from lfdkit.execute.mujoco import flange_poses
from lfdkit.io import atomic_write
from lfdkit.io.skill_file import jsonable

#: Packages whose versions go into the JSON (later sections may append theirs).
VERSION_PACKAGES = [
    "lfdkit",
    "numpy",
    "scipy",
    "threadpoolctl",
    "roboticstoolbox-python",
    "spatialmath-python",
    "pytransform3d",
    "mujoco",
    "movement_primitives",
    "pin",
    "toppra",
]

N_FULL = 10_000
N_QUICK = 1_000
RTB_IK_FULL = 200
RTB_IK_QUICK = 50
SPEED_REPEATS = 5
FK_POS_TARGET = 1e-9  # m
IK_POS_TARGET = 1e-9  # m
IK_ROT_TARGET = 1e-9  # Frobenius norm of the rotation difference
RECOVER_TOL = 1e-6  # rad, max joint difference modulo 2π
RTB_IK_TOLS = (1e-6, 1e-24)
SIM_FK_FULL, SIM_FK_QUICK = 2_000, 500
SCENARIOS_FULL, SCENARIOS_QUICK = 60, 10
SUCCESS_TARGET = 0.95
MIN_SCENARIOS = 50
TRACKING_TARGET = 0.005  # m

_STARTED = time.perf_counter()


# ----------------------------------------------------------------------------- helpers
def progress(message: str) -> None:
    sys.stdout.flush()
    print(f"[{time.perf_counter() - _STARTED:6.1f} s] {message}", file=sys.stderr, flush=True)


def sci(x: float | None, digits: int = 2) -> str:
    return "—" if x is None or not np.isfinite(x) else f"{x:.{digits}e}"


def random_configurations(n: int, rng: np.random.Generator) -> np.ndarray:
    """``n`` configurations uniform in ``[-π, π]^6``, shape (n, 6), radians."""
    return rng.uniform(-np.pi, np.pi, size=(n, 6))


def pose_errors(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position error (m), rotation error ``‖R_a - R_b‖_F`` and its angle (rad), per pose."""
    pos = np.linalg.norm(a[..., :3, 3] - b[..., :3, 3], axis=-1)
    frob = np.linalg.norm(a[..., :3, :3] - b[..., :3, :3], axis=(-2, -1))
    angle = 2 * np.arcsin(np.minimum(frob / (2 * np.sqrt(2)), 1.0))
    return pos, frob, angle


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angles wrapped to ``[-π, π)``."""
    return np.mod(angle + np.pi, 2 * np.pi) - np.pi


def median_time(fn, repeats: int) -> tuple[float, list[float], Any]:
    """Median wall time (s) of ``repeats`` calls of ``fn``, all times, last result."""
    times, out = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times)), times, out


def import_rtb() -> tuple[Any, str | None]:
    """``(roboticstoolbox, None)``, or ``(None, reason)`` when it cannot be imported."""
    try:
        import roboticstoolbox as rtb
    except ImportError:
        return None, "roboticstoolbox-python not installed"
    except Exception as exc:  # e.g. a binary incompatibility with this numpy
        return None, f"roboticstoolbox-python failed to import ({type(exc).__name__}: {exc})"
    return rtb, None


def rtb_ur5(rtb) -> Any:
    """rtb ``DHRobot`` with the thesis's DH table (not rtb's own UR5 model)."""
    links = [
        rtb.RevoluteDH(d=float(d), a=float(a), alpha=float(alpha))
        for d, a, alpha in zip(UR5.d, UR5.a, UR5.alpha, strict=True)
    ]
    return rtb.DHRobot(links, name="UR5 (thesis DH)")


def rtb_fkine(robot, q: np.ndarray) -> np.ndarray:
    """rtb forward kinematics of a batch, shape (n, 4, 4)."""
    return np.asarray(robot.fkine(q).A, dtype=float).reshape(len(q), 4, 4)


def pytransform3d_forward(q: np.ndarray) -> np.ndarray:
    """The DH chain built from pytransform3d matrices, one configuration at a time."""
    from pytransform3d.rotations import active_matrix_from_angle
    from pytransform3d.transformations import transform_from

    eye = np.eye(3)
    # Tz(d) Tx(a) Rx(alpha) does not depend on the joint angle.
    fixed = [
        transform_from(eye, [0.0, 0.0, d])
        @ transform_from(eye, [a, 0.0, 0.0])
        @ transform_from(active_matrix_from_angle(0, alpha), np.zeros(3))
        for d, a, alpha in zip(UR5.d, UR5.a, UR5.alpha, strict=True)
    ]
    out = np.empty((len(q), 4, 4))
    for k, qk in enumerate(q):
        t = np.eye(4)
        for i in range(6):
            t = t @ transform_from(active_matrix_from_angle(2, qk[i]), np.zeros(3)) @ fixed[i]
        out[k] = t
    return out


def error_summary(reference: np.ndarray, poses: np.ndarray) -> dict:
    pos, frob, angle = pose_errors(reference, poses)
    return {
        "max_position_error_m": float(pos.max()),
        "max_rotation_error_frobenius": float(frob.max()),
        "max_rotation_error_rad": float(angle.max()),
        "mean_position_error_m": float(pos.mean()),
    }


# ------------------------------------------------------------------ K1. FK cross-check
def kinematics_crosscheck(n: int, rng: np.random.Generator) -> dict:
    """``ur5.forward`` against rtb and pytransform3d on ``n`` random configurations."""
    q = random_configurations(n, rng)
    poses = ur5.forward(q)
    refs: dict[str, dict] = {}

    rtb, reason = import_rtb()
    if rtb is None:
        refs["roboticstoolbox-python"] = {"skipped": reason}
    else:
        start = time.perf_counter()
        ref = rtb_fkine(rtb_ur5(rtb), q)
        refs["roboticstoolbox-python"] = {
            "call": "DHRobot([RevoluteDH(d, a, alpha) x 6]).fkine(q_batch)",
            "seconds": time.perf_counter() - start,
            **error_summary(ref, poses),
        }

    try:
        import pytransform3d  # noqa: F401
    except ImportError:
        refs["pytransform3d"] = {"skipped": "pytransform3d not installed"}
    else:
        start = time.perf_counter()
        ref = pytransform3d_forward(q)
        refs["pytransform3d"] = {
            "call": "transform_from(active_matrix_from_angle(...)) chain, per configuration",
            "seconds": time.perf_counter() - start,
            **error_summary(ref, poses),
        }
    return {"n": n, "references": refs}


# ------------------------------------------------------------------ K2. IK round trip
def ik_round_trip(n: int, rng: np.random.Generator) -> dict:
    """``forward(inverse(forward(q)))`` for every branch of ``n`` random poses."""
    q = random_configurations(n, rng)
    poses = ur5.forward(q)
    sols = ur5.inverse(poses, strict=False)  # (n, 8, 6)
    valid = ~np.isnan(sols).any(axis=-1)  # (n, 8)
    per_pose = valid.sum(axis=1)
    values, freq = np.unique(per_pose, return_counts=True)
    counts = {int(k): int(v) for k, v in zip(values, freq, strict=True)}

    idx_pose, idx_branch = np.nonzero(valid)
    fk = ur5.forward(sols[idx_pose, idx_branch])
    pos, frob, angle = pose_errors(fk, poses[idx_pose])

    # Original configuration among the solutions (modulo 2π).
    with np.errstate(invalid="ignore"):
        diff = np.abs(wrap(sols - q[:, None, :])).max(axis=-1)  # (n, 8), NaN rows -> NaN
    diff = np.where(valid, diff, np.inf)
    closest = diff.min(axis=1)
    recovered = closest < RECOVER_TOL
    named = ur5.branch(q)
    at_branch = diff[np.arange(n), named] < RECOVER_TOL

    worst = int(np.argmax(pos)) if len(pos) else None
    return {
        "n_poses": n,
        "n_solutions": int(valid.sum()),
        "branch_counts": counts,
        "poses_without_solution": int((per_pose == 0).sum()),
        "max_position_error_m": float(pos.max()) if len(pos) else None,
        "max_rotation_error_frobenius": float(frob.max()) if len(frob) else None,
        "max_rotation_error_rad": float(angle.max()) if len(angle) else None,
        "solutions_over_position_target": int((pos >= IK_POS_TARGET).sum()),
        "solutions_over_rotation_target": int((frob >= IK_ROT_TARGET).sum()),
        "worst_solution": None
        if worst is None
        else {
            "pose": int(idx_pose[worst]),
            "branch": int(idx_branch[worst]),
            "q_original": q[idx_pose[worst]].tolist(),
            "q_solution": sols[idx_pose[worst], idx_branch[worst]].tolist(),
        },
        "recovered": int(recovered.sum()),
        "recovered_fraction": float(recovered.mean()),
        "recovered_at_branch_row": int(at_branch.sum()),
        "max_recovery_joint_error_rad": float(closest[recovered].max())
        if recovered.any()
        else None,
        "not_recovered_q": q[~recovered][:10].tolist(),
        "recover_tol_rad": RECOVER_TOL,
    }


# ------------------------------------------------------------------ K3. throughput
def _per_pose(seconds: float, n: int) -> dict:
    return {
        "median_s": seconds,
        "ms": seconds * 1e3,
        "us_per_pose": seconds / n * 1e6,
        "poses_per_s": n / seconds,
    }


def kinematics_speed(n: int, quick: bool, seed: int = 0) -> dict:
    """Median times of lfdkit's FK/IK on ``n`` poses and rtb's fkine / ik_LM."""
    rng = np.random.default_rng([seed, 3])
    repeats = SPEED_REPEATS
    q = random_configurations(n, rng)
    poses = ur5.forward(q)
    out: dict[str, Any] = {"n": n, "repeats": repeats, "rows": {}}
    rows = out["rows"]

    t, times, _ = median_time(lambda: ur5.forward(q), repeats)
    rows["lfdkit forward"] = {"n": n, **_per_pose(t, n), "times_s": times}
    t, times, _ = median_time(lambda: ur5.inverse(poses), repeats)
    rows["lfdkit inverse (8 branches)"] = {"n": n, **_per_pose(t, n), "times_s": times}

    rtb, reason = import_rtb()
    if rtb is None:
        out["rtb_skipped"] = reason
        return out
    robot = rtb_ur5(rtb)
    t, times, _ = median_time(lambda: rtb_fkine(robot, q), repeats)
    rows["rtb fkine"] = {
        "n": n,
        **_per_pose(t, n),
        "times_s": times,
        "vs": "lfdkit forward",
        "ratio": t / rows["lfdkit forward"]["median_s"],
    }

    n_ik = RTB_IK_QUICK if quick else RTB_IK_FULL
    targets = poses[:n_ik]
    starts = rng.uniform(-np.pi, np.pi, size=(n_ik, 6))
    lfd_per_pose = rows["lfdkit inverse (8 branches)"]["median_s"] / n
    for tol in RTB_IK_TOLS:

        def solve_all(tol=tol):
            return [robot.ik_LM(T, q0=q0, tol=tol) for T, q0 in zip(targets, starts, strict=True)]

        t, times, sols = median_time(solve_all, repeats)
        q_rtb = np.array([s.q for s in sols], dtype=float)
        success = np.array([bool(s.success) for s in sols])
        pos, frob, _ = pose_errors(ur5.forward(q_rtb), targets)
        rows[f"rtb ik_LM tol={tol:g} (1 solution)"] = {
            "n": n_ik,
            **_per_pose(t, n_ik),
            "times_s": times,
            "vs": "lfdkit inverse (8 branches)",
            "ratio": (t / n_ik) / lfd_per_pose,
            "success": int(success.sum()),
            "max_position_error_m": float(pos.max()),
            "median_position_error_m": float(np.median(pos)),
            "max_rotation_error_frobenius": float(frob.max()),
        }
    return out


# ------------------------------------------------------------------ printing and targets
def print_kinematics(results: dict) -> None:
    cross = results["crosscheck"]
    print(
        f"\nK1. FK cross-check: lfdkit forward vs independent DH chains ({cross['n']:,} random q)"
    )
    print(f"{'reference':<24} {'max pos err m':>14} {'max rot err F':>14} {'max angle rad':>14}")
    for name, r in cross["references"].items():
        if "skipped" in r:
            print(f"{name:<24} skipped ({r['skipped']})")
            continue
        print(
            f"{name:<24} {sci(r['max_position_error_m']):>14} "
            f"{sci(r['max_rotation_error_frobenius']):>14} {sci(r['max_rotation_error_rad']):>14}"
        )

    ik = results["ik_round_trip"]
    print("\nK2. IK round trip: forward(inverse(forward(q))) over all branches")
    counts = ik["branch_counts"]
    shown = ", ".join(f"{k}: {counts.get(k, 0):,}" for k in (8, 6, 4, 2))
    other = {k: v for k, v in counts.items() if k not in (8, 6, 4, 2)}
    if other:
        shown += ", other " + ", ".join(f"{k}: {v:,}" for k, v in sorted(other.items()))
    rows = [
        ("poses", f"{ik['n_poses']:,}"),
        ("solutions checked", f"{ik['n_solutions']:,}"),
        ("poses by valid branches", shown),
        ("max position error m", sci(ik["max_position_error_m"])),
        ("max rotation error F", sci(ik["max_rotation_error_frobenius"])),
        ("max rotation angle rad", sci(ik["max_rotation_error_rad"])),
        (
            "original q recovered",
            f"{ik['recovered']:,}/{ik['n_poses']:,} ({100 * ik['recovered_fraction']:.2f} %), "
            f"max joint diff {sci(ik['max_recovery_joint_error_rad'])} rad",
        ),
        ("  ... at row branch(q)", f"{ik['recovered_at_branch_row']:,}/{ik['n_poses']:,}"),
    ]
    for label, value in rows:
        print(f"  {label:<26} {value}")

    speed = results["speed"]
    print(
        f"\nK3. Throughput (median of {speed['repeats']} repeats; rtb/lfdkit = ratio of time per "
        "pose)"
    )
    print(
        f"{'call':<36} {'poses':>6} {'ms':>10} {'µs/pose':>10} {'poses/s':>12} "
        f"{'rtb/lfdkit':>10}  accuracy"
    )
    for name, r in speed["rows"].items():
        ratio = f"{r['ratio']:.1f}x" if "ratio" in r else ""
        acc = ""
        if "success" in r:
            acc = (
                f"success {r['success']}/{r['n']}, pos err max {sci(r['max_position_error_m'])}"
                f" median {sci(r['median_position_error_m'])} m"
            )
        print(
            f"{name:<36} {r['n']:>6,} {r['ms']:>10.2f} {r['us_per_pose']:>10.2f} "
            f"{r['poses_per_s']:>12,.0f} {ratio:>10}  {acc}"
        )
    if "rtb_skipped" in speed:
        print(f"  rtb rows skipped ({speed['rtb_skipped']})")
    print(
        "  rtb ik_LM returns one solution per call, lfdkit inverse all eight branches; "
        "absolute times are noisy on a shared 2-core machine"
    )


def kinematics_targets(results: dict) -> list[dict]:
    targets = []
    for name in ("roboticstoolbox-python", "pytransform3d"):
        r = results["crosscheck"]["references"].get(name, {"skipped": "not run"})
        target = f"< {FK_POS_TARGET:g} m"
        if "skipped" in r:
            targets.append(
                {
                    "name": f"FK max position error vs {name}",
                    "value": f"skipped ({r['skipped']})",
                    "target": target,
                    "status": "SKIP",
                }
            )
            continue
        err = r["max_position_error_m"]
        targets.append(
            {
                "name": f"FK max position error vs {name}",
                "value": f"{err:.2e} m (rot {r['max_rotation_error_frobenius']:.2e})",
                "target": target,
                "status": "PASS" if err < FK_POS_TARGET else "FAIL",
            }
        )

    ik = results["ik_round_trip"]
    pos, rot = ik["max_position_error_m"], ik["max_rotation_error_frobenius"]
    ok = pos is not None and pos < IK_POS_TARGET and rot < IK_ROT_TARGET
    targets.append(
        {
            "name": f"IK every solution valid ({ik['n_solutions']:,} solutions)",
            "value": f"pos {sci(pos)} m, rot {sci(rot)}",
            "target": f"< {IK_POS_TARGET:g} m, < {IK_ROT_TARGET:g}",
            "status": "PASS" if ok else "FAIL",
        }
    )
    targets.append(
        {
            "name": f"IK original q recovered ({ik['n_poses']:,} poses)",
            "value": f"{100 * ik['recovered_fraction']:.2f} %",
            "target": "100 %",
            "status": "PASS" if ik["recovered"] == ik["n_poses"] else "FAIL",
        }
    )
    return targets


def print_targets(targets: list[dict]) -> None:
    print("\nTARGETS")
    print(f"  {'status':<6} {'target':<52} {'value':<40} required")
    for t in targets:
        print(f"  {t['status']:<6} {t['name']:<52} {t['value']:<40} {t['target']}")


# ----------------------------------------------------------------------------- S1. MuJoCo
def mujoco_crosscheck(n: int, rng: np.random.Generator) -> dict:
    """S1: MuJoCo's flange poses against ``ur5.forward``."""
    q = rng.uniform(-2 * np.pi, 2 * np.pi, size=(n, 6))
    start = time.perf_counter()
    poses = flange_poses(q)
    seconds = time.perf_counter() - start
    summary = error_summary(ur5.forward(q), poses)
    summary.update({"n": n, "seconds": seconds})
    return summary


# ----------------------------------------------------------------------------- S2. experiment
def coupling_planner(skill, training, quick: bool):
    """The DMP + Hoffmann coupling baseline, γ and β tuned on the training demonstrations."""
    sys.path.insert(0, str(Path(__file__).parent))
    import emulate as emulate_bench  # the same baseline as the emulation benchmark

    dmp = emulate_bench.peer_dmp(skill.path_)
    gammas, betas = (
        (emulate_bench.QUICK_GAMMAS, emulate_bench.QUICK_BETAS)
        if quick
        else (emulate_bench.DMP_GAMMAS, emulate_bench.DMP_BETAS)
    )
    demos, scenes = training.obstacle_demos, training.scenes
    grid = []
    for gamma in gammas:
        for beta in betas if gamma else betas[:1]:
            score = emulate_bench.dmp_score(dmp, demos, scenes, gamma, beta)
            grid.append({"gamma": gamma, "beta": beta, "train_mse": score})
    best = min(grid, key=lambda g: g["train_mse"])

    def plan(start: np.ndarray, goal: np.ndarray, scene) -> np.ndarray:
        dmp.configure(start_y=start, goal_y=goal)
        path = emulate_bench.dmp_rollout(dmp, scene, best["gamma"], best["beta"])
        if not np.all(np.isfinite(path)):
            raise ValueError("the coupled DMP diverged (NaN)")
        return path

    return plan, {"gamma": best["gamma"], "beta": best["beta"], "grid": grid}


def _failure_kind(failure: str) -> str:
    for prefix, kind in (
        ("touched", "touched an obstacle"),
        ("tracking", "tracking error"),
        ("cube missed", "cube missed the dustpan"),
        ("the robot cannot", "path not executable"),
        ("planning failed", "planning failed"),
        ("simulation became unstable", "unstable simulation"),
    ):
        if failure.startswith(prefix):
            return kind
    return failure


def sweeping_experiment(
    n_scenarios: int, seed: int, quick: bool, output: Path, *, planner_names=None
) -> dict:
    """S2: every planner on the same random unseen scenarios, executed in MuJoCo.

    ``planner_names`` keeps only those planners (``--figures-only``: the figure's four).
    """
    from lfdkit.io.training import read_training_data
    from lfdkit.skill import learn
    from lfdkit.tasks.sweeping import (
        default_planners,
        example_dataset,
        example_files,
        random_scenarios,
        run_experiment,
        summarize,
    )

    files = example_files()
    start = time.perf_counter()
    skill = learn(files["demos"], files["scenes"])
    learn_s = time.perf_counter() - start
    planners = default_planners(skill, example_dataset().true_reward)
    try:
        training = read_training_data(files["demos"], files["scenes"])
        planners["DMP + coupling"], coupling = coupling_planner(skill, training, quick)
    except ImportError as exc:
        coupling = {"skipped": f"movement_primitives not installed ({exc})"}
    order = ["learned skill", "learned, thesis end", "replay generalized path", "DMP alone"]
    order += [name for name in ("DMP + coupling", "true reward") if name in planners]
    if planner_names is not None:
        order = [name for name in order if name in planner_names]
    planners = {name: planners[name] for name in order}
    scenarios = random_scenarios(n_scenarios, seed)
    start = time.perf_counter()
    rows = run_experiment(scenarios, planners, progress=progress)
    run_s = time.perf_counter() - start
    failure_kinds: dict[str, dict[str, int]] = {name: {} for name in planners}
    for row in rows:
        kinds = failure_kinds[row["planner"]]
        for kind in {_failure_kind(f) for f in row["failures"]}:
            kinds[kind] = kinds.get(kind, 0) + 1
    figures = sweep_figures(scenarios, rows, planners["learned skill"], output)
    return {
        "n_scenarios": n_scenarios,
        "seed": seed,
        "learn_s": learn_s,
        "run_s": run_s,
        "summary": summarize(rows),
        "plan_s_median": {
            name: float(np.nanmedian([r["plan_s"] for r in rows if r["planner"] == name]))
            for name in planners
        },
        "failure_kinds": failure_kinds,
        "coupling": coupling,
        "figures": figures,
        "runs": [{k: v for k, v in row.items() if k != "result"} for row in rows],
    }


#: The planners drawn in ``robot_scenarios.png``.
FIGURE_PLANNERS = ("learned skill", "DMP alone", "DMP + coupling", "replay generalized path")


def sweep_figures(scenarios, rows: list[dict], learned, output: Path) -> list[str]:
    """Top views of the first four scenarios; a MuJoCo render where OpenGL is available."""
    from matplotlib.figure import Figure

    from lfdkit.tasks.sweeping import SweepingTask, execute_sweep, sweep_figure

    output.mkdir(parents=True, exist_ok=True)
    shown = FIGURE_PLANNERS
    count = min(4, len(scenarios))
    # Equal-aspect panels of a 0.9 m x 0.3 m table strip: 2.1 inches a row leaves no gaps.
    fig = Figure(figsize=(13, 2.1 * ((count + 1) // 2) + 1.0), layout="constrained")
    axes = np.atleast_1d(fig.subplots((count + 1) // 2, 2)).ravel()
    for index in range(count):
        runs = {
            row["planner"]: row["result"]
            for row in rows
            if row["scenario"] == index and row["planner"] in shown and row["result"] is not None
        }
        sweep_figure(
            scenarios[index].dustpan,
            scenarios[index].scene,
            runs,
            ax=axes[index],
            title=f"scenario {index}",
            legend=False,
        )
    for ax in axes[count:]:
        ax.set_visible(False)
    entries: dict[str, object] = {}
    for ax in axes[:count]:
        for handle, label in zip(*ax.get_legend_handles_labels(), strict=True):
            entries.setdefault(label.split(" (")[0], handle)
    fig.legend(
        # two rows: one row of ten entries is wider than the figure (cut at both ends)
        list(entries.values()),
        list(entries),
        loc="outside lower center",
        ncols=(len(entries) + 1) // 2,
    )
    fig.suptitle(
        "Simulated sweeps: brush (flange) traces, cube traces dotted, squares where the cube "
        "rested; ok/failed per run in robot.json",
        fontsize=10,
    )
    names = ["robot_scenarios.png"]
    fig.savefig(output / names[0], dpi=110)
    scenario = scenarios[0]
    path = learned(scenario.start, scenario.goal, scenario.scene)
    task = SweepingTask.for_path(path, scenario.dustpan, scenario.scene)
    image = execute_sweep(path, task, render=True).image
    if image is not None:
        from lfdkit.tasks.sweeping.figures import render_figure

        picture = render_figure(image, scenario.scene, title="MuJoCo at the end of a learned sweep")
        picture.savefig(output / "robot_render.png", dpi=110)
        names.append("robot_render.png")
    return names


def print_simulation(results: dict) -> None:
    check = results["mujoco"]
    print("\nS1. MuJoCo model vs ur5.forward (the same DH table)")
    print(
        f"  {check['n']:,} random configurations: max position error "
        f"{sci(check['max_position_error_m'])} m, "
        f"max rotation error {sci(check['max_rotation_error_frobenius'])}"
    )
    exp = results["experiment"]
    print(
        f"\nS2. Sweeping in MuJoCo: {exp['n_scenarios']} random unseen scenarios "
        f"(seed {exp['seed']}); skill learned in {exp['learn_s']:.1f} s, "
        f"all runs {exp['run_s']:.0f} s"
    )
    header = (
        f"{'planner':26s} {'success':>8s} {'in pan':>7s} {'no touch':>9s} "
        f"{'track max mm':>13s} {'track med mm':>13s} {'motion s':>9s} {'plan ms':>8s}"
    )
    print(header)
    for name, row in exp["summary"].items():
        print(
            f"{name:26s} {row['success_rate']:8.0%} {row['cube_in_dustpan_rate']:7.0%} "
            f"{row['no_touch_rate']:9.0%} {row['tracking_max_m'] * 1e3:13.2f} "
            f"{row['tracking_median_m'] * 1e3:13.2f} {row['duration_median_s']:9.1f} "
            f"{exp['plan_s_median'][name] * 1e3:8.1f}"
        )
    print("  failures (runs with each kind):")
    for name, kinds in exp["failure_kinds"].items():
        text = ", ".join(f"{kind} {count}" for kind, count in sorted(kinds.items())) or "none"
        print(f"    {name:26s} {text}")
    coupling = exp["coupling"]
    if "skipped" in coupling:
        print(f"  DMP + coupling: {coupling['skipped']}")
    else:
        print(
            f"  DMP + coupling: gamma = {coupling['gamma']:g}, beta = {coupling['beta']:.3g} "
            "(lowest MSE to the training demonstrations)"
        )
    print("  'in pan': cube on the dustpan's floor; 'no touch': no cup or marker touched;")
    print("  tracking: flange vs planned flange position at every 2 ms step;")
    print("  'motion s': median length of the robot's motion at 20 % of the joint limits")


def simulation_targets(results: dict) -> list[dict]:
    check = results["mujoco"]
    exp = results["experiment"]
    learned = exp["summary"]["learned skill"]
    enough = exp["n_scenarios"] >= MIN_SCENARIOS
    success = learned["success_rate"] >= SUCCESS_TARGET
    return [
        {
            "name": "MuJoCo flange pose vs ur5.forward",
            "value": f"{sci(check['max_position_error_m'])} m",
            "target": f"< {FK_POS_TARGET:g} m",
            "status": "PASS" if check["max_position_error_m"] < FK_POS_TARGET else "FAIL",
        },
        {
            "name": f"learned skill success ({exp['n_scenarios']} scenarios)",
            "value": f"{learned['success_rate']:.1%}",
            "target": f">= {SUCCESS_TARGET:.0%} of >= {MIN_SCENARIOS}",
            # A --quick run has too few scenarios to judge the rate.
            "status": ("PASS" if success else "FAIL") if enough else "SKIP",
        },
        {
            "name": "learned skill tracking error",
            "value": f"{learned['tracking_max_m'] * 1e3:.2f} mm max",
            "target": f"<= {TRACKING_TARGET * 1e3:g} mm",
            "status": "PASS" if learned["tracking_max_m"] <= TRACKING_TARGET else "FAIL",
        },
    ]


# ------------------------------------------------------------------------------ output


# ----------------------------------------------------------------------------- A. any arm
DATA = example_urdf("ur5").parent  # the example arms lfdkit ships
ARM_FILES = {
    "UR5 (URDF)": ("ur5.urdf", None),
    "UR5e": ("ur5e.urdf", None),
    "Panda": ("panda.urdf", "panda_hand_tcp"),
}
ARM_FK_N = (2_000, 300)  # full, quick
ARM_IK_N = (200, 40)
ARM_FK_TARGET = 1e-9  # m against pinocchio and the DH UR5
TIMING_FRACTIONS = (1.0, 0.5, 0.2, 0.1)


def _urdf_arms() -> dict:
    from lfdkit.execute.urdf import UrdfArm

    return {name: UrdfArm(DATA / f, tip_link=tip) for name, (f, tip) in ARM_FILES.items()}


def _pinocchio_model(name: str):
    try:
        import pinocchio as pin
    except ImportError:
        return None, None
    file, tip = ARM_FILES[name]
    model = pin.buildModelFromUrdf(str(DATA / file))
    return pin, (model, model.createData(), model.getFrameId(tip or "flange"))


def arms_forward(quick: bool, rng: np.random.Generator) -> dict:
    """A1: URDF forward kinematics against pinocchio (and the UR5's DH table), and their speed."""
    n = ARM_FK_N[quick]
    rows = {}
    for name, arm in _urdf_arms().items():
        q = rng.uniform(arm.joint_limits[:, 0], arm.joint_limits[:, 1], (n, arm.n_joints))
        mine = arm.forward(q)
        row: dict[str, Any] = {"joints": arm.n_joints, "n": n}
        t_batch, _, _ = median_time(lambda q=q, arm=arm: arm.forward(q), 3)
        t_single, _, _ = median_time(
            lambda q=q, arm=arm: [arm.pose_and_jacobian(x) for x in q[:200]], 3
        )
        row["lfdkit_fk_us"] = 1e6 * t_batch / n
        row["lfdkit_fk_and_jacobian_single_us"] = 1e6 * t_single / 200
        if name == "UR5 (URDF)":
            row["max_error_vs_dh_m"] = float(
                np.abs(mine[:, :3, 3] - ur5.forward(q)[:, :3, 3]).max()
            )
        pin, ref = _pinocchio_model(name)
        if pin is not None:
            model, data, frame = ref
            pad = model.nq - arm.n_joints

            def pin_fk(q=q, model=model, data=data, frame=frame, pad=pad, pin=pin):
                out = np.empty((len(q), 4, 4))
                for k, x in enumerate(q):
                    pin.framesForwardKinematics(model, data, np.r_[x, np.zeros(pad)])
                    out[k] = data.oMf[frame].homogeneous
                return out

            t_pin, _, theirs = median_time(pin_fk, 3)
            row["max_error_vs_pinocchio_m"] = float(np.abs(mine - theirs).max())
            row["pinocchio_fk_us"] = 1e6 * t_pin / n
        rows[name] = row
    return rows


def arms_inverse(quick: bool, rng: np.random.Generator) -> dict:
    """A2: numerical IK from 0.1 rad away, lfdkit's DLS against the same loop on pinocchio."""
    from lfdkit.execute.kinematics import solve_pose

    n = ARM_IK_N[quick]
    rows = {}
    for name, arm in _urdf_arms().items():
        lo, hi = arm.joint_limits[:, 0], arm.joint_limits[:, 1]
        q = rng.uniform(lo + 0.2, hi - 0.2, (n, arm.n_joints))
        start = q + rng.uniform(-0.1, 0.1, q.shape)
        targets = arm.forward(q)
        t0 = time.perf_counter()
        solved = [solve_pose(arm, targets[k], start[k]) for k in range(n)]
        seconds = time.perf_counter() - t0
        pos = np.array([s[1] for s in solved])
        row: dict[str, Any] = {
            "poses": n,
            "lfdkit_success": float(np.mean(pos < 1e-6)),
            "lfdkit_max_position_error_m": float(pos.max()),
            "lfdkit_ms_per_pose": 1e3 * seconds / n,
        }
        pin, ref = _pinocchio_model(name)
        if pin is not None:
            model, data, frame = ref
            pad = model.nq - arm.n_joints

            def clik(
                target, q0, model=model, data=data, frame=frame, pad=pad, pin=pin, lo=lo, hi=hi
            ):
                dof = len(lo)
                # pinocchio's documented CLIK loop (log6 error, damped pseudo-inverse), same
                # damping, step cap and tolerance as lfdkit's.
                goal = pin.SE3(target[:3, :3], target[:3, 3])
                x = np.r_[q0, np.zeros(pad)]
                for _ in range(100):
                    pin.framesForwardKinematics(model, data, x)
                    err = pin.log6(data.oMf[frame].actInv(goal)).vector
                    if np.linalg.norm(err[:3]) < 1e-7 and np.linalg.norm(err[3:]) < 1e-6:
                        break
                    jac = pin.computeFrameJacobian(model, data, x, frame)[:, :dof]
                    step = jac.T @ np.linalg.solve(jac @ jac.T + 1e-6 * np.eye(6), err)
                    step *= min(1.0, 0.3 / np.abs(step).max())
                    x[:dof] = np.clip(x[:dof] + step, lo, hi)
                pin.framesForwardKinematics(model, data, x)
                return float(np.linalg.norm(data.oMf[frame].translation - target[:3, 3]))

            t0 = time.perf_counter()
            theirs = np.array([clik(targets[k], start[k]) for k in range(n)])
            seconds = time.perf_counter() - t0
            row["pinocchio_success"] = float(np.mean(theirs < 1e-6))
            row["pinocchio_ms_per_pose"] = 1e3 * seconds / n
            row["time_ratio_lfdkit_over_pinocchio"] = (
                row["lfdkit_ms_per_pose"] / row["pinocchio_ms_per_pose"]
            )
        rows[name] = row
    return rows


def _reach_plan():
    """A 6 s reach over a 0.2 m box, rest to rest, as Skill.plan times it (metres, seconds)."""
    from types import SimpleNamespace

    t = np.linspace(0.0, 6.0, 120)
    s = 0.5 - 0.5 * np.cos(np.pi * t / 6.0)
    p = np.column_stack([np.full_like(t, 0.45), -0.3 + 0.6 * s, 0.15 + 0.22 * np.sin(np.pi * s)])
    return SimpleNamespace(times=t, positions=p)


def arms_timing(quick: bool) -> dict:
    """A3/A4: the learned timing kept (duration ratios), and time-optimal timing against toppra."""
    from lfdkit.execute.arm import UR5 as DH_UR5
    from lfdkit.execute.pipeline import execute_plan
    from lfdkit.execute.timing import time_parameterize

    arms = {"UR5 (DH)": DH_UR5, **_urdf_arms()}
    kept: dict[str, Any] = {}
    optimal: dict[str, Any] = {}
    plan = _reach_plan()
    for name, arm in arms.items():
        kept[name] = {}
        joints = None
        for f in TIMING_FRACTIONS[: 2 if quick else None]:
            t0 = time.perf_counter()
            run = execute_plan(plan, arm, speed_fraction=f, rate=500.0)
            seconds = time.perf_counter() - t0
            qd, qdd = run.samples.velocities, run.samples.accelerations
            kept[name][f"{f:g}"] = {
                "duration_ratio": run.trajectory.duration / run.trajectory.planned_duration,
                "slowdowns": len(run.trajectory.slowdowns),
                "velocity_of_limit": float((np.abs(qd) / (f * arm.max_joint_speed)).max()),
                "acceleration_of_limit": float(
                    (np.abs(qdd) / (f * f * arm.max_joint_acceleration)).max()
                ),
                "seconds": seconds,
            }
            joints = run.trajectory.waypoints
        vmax, amax = arm.max_joint_speed, arm.max_joint_acceleration
        t_mine, _, timing = median_time(
            lambda j=joints, v=vmax, a=amax: time_parameterize(
                j, max_velocity=v, max_acceleration=a
            ),
            3,
        )
        row: dict[str, Any] = {"lfdkit_duration_s": timing.duration, "lfdkit_ms": 1e3 * t_mine}
        samples = timing.sample(np.linspace(0, timing.duration, 5001))
        v, a = samples.velocities, samples.accelerations
        row["lfdkit_limit_use"] = float(max((np.abs(v) / vmax).max(), (np.abs(a) / amax).max()))
        try:
            import toppra as ta
            import toppra.algorithm as algo
            import toppra.constraint as constraint
        except ImportError:
            row["toppra"] = "not installed"
        else:
            ta.setup_logging("WARNING")
            from lfdkit.core.geometry import arc_length

            keep = np.concatenate(([True], np.linalg.norm(np.diff(joints, axis=0), axis=1) > 1e-9))
            way = joints[keep]

            def run_toppra(way=way, vmax=vmax, amax=amax):
                path = ta.SplineInterpolator(arc_length(way), way, bc_type="natural")
                cons = [
                    constraint.JointVelocityConstraint(np.column_stack([-vmax, vmax])),
                    constraint.JointAccelerationConstraint(np.column_stack([-amax, amax])),
                ]
                return algo.TOPPRA(
                    cons, path, parametrizer="ParametrizeConstAccel"
                ).compute_trajectory()

            t_toppra, _, traj = median_time(run_toppra, 3)
            ts = np.linspace(0, traj.duration, 5001)
            use = max((np.abs(traj(ts, 1)) / vmax).max(), (np.abs(traj(ts, 2)) / amax).max())
            row.update(
                toppra_duration_s=float(traj.duration),
                toppra_ms=1e3 * t_toppra,
                toppra_limit_use=float(use),
                duration_ratio_lfdkit_over_toppra=timing.duration / float(traj.duration),
                time_ratio_lfdkit_over_toppra=t_mine / t_toppra,
            )
        optimal[name] = row
    return {"kept": kept, "optimal": optimal}


def print_arms(results: dict) -> None:
    print("\nA1. URDF forward kinematics (max position error, m; µs per configuration)")
    print(f"  {'arm':<12} {'joints':>6} {'vs pin':>10} {'vs DH':>10} {'lfdkit':>8} {'pin':>8}")
    for name, r in results["forward"].items():
        print(
            f"  {name:<12} {r['joints']:>6} {sci(r.get('max_error_vs_pinocchio_m')):>10} "
            f"{sci(r.get('max_error_vs_dh_m')):>10} {r['lfdkit_fk_us']:>8.1f} "
            f"{r.get('pinocchio_fk_us', float('nan')):>8.1f}"
        )
    print("\nA2. numerical IK from 0.1 rad away (success < 1e-6 m; ms per pose)")
    for name, r in results["inverse"].items():
        print(
            f"  {name:<12} lfdkit {r['lfdkit_success']:.0%} {r['lfdkit_ms_per_pose']:.2f} ms   "
            f"pinocchio CLIK {r.get('pinocchio_success', float('nan')):.0%} "
            f"{r.get('pinocchio_ms_per_pose', float('nan')):.2f} ms   ratio "
            f"{r.get('time_ratio_lfdkit_over_pinocchio', float('nan')):.2f}"
        )
    print("\nA3. the learned 6 s reach kept: executed / planned duration per speed fraction")
    for name, by_f in results["timing"]["kept"].items():
        cells = "  ".join(
            f"f={f}: x{r['duration_ratio']:.3f} (v {r['velocity_of_limit']:.2f}, "
            f"a {r['acceleration_of_limit']:.2f} of limit)"
            for f, r in by_f.items()
        )
        print(f"  {name:<12} {cells}")
    print("\nA4. time-optimal timing of the same joint path: lfdkit vs toppra")
    for name, r in results["timing"]["optimal"].items():
        if "toppra_duration_s" not in r:
            print(f"  {name:<12} lfdkit {r['lfdkit_duration_s']:.3f} s; toppra {r.get('toppra')}")
            continue
        print(
            f"  {name:<12} duration lfdkit {r['lfdkit_duration_s']:.3f} s, toppra "
            f"{r['toppra_duration_s']:.3f} s (ratio {r['duration_ratio_lfdkit_over_toppra']:.3f}); "
            f"limit use {r['lfdkit_limit_use']:.3f} / {r['toppra_limit_use']:.3f}; "
            f"time {r['lfdkit_ms']:.0f} / {r['toppra_ms']:.0f} ms (ratio "
            f"{r['time_ratio_lfdkit_over_toppra']:.2f})"
        )


def arms_targets(results: dict) -> list[dict]:
    out = []
    for name, r in results["forward"].items():
        for key in ("max_error_vs_pinocchio_m", "max_error_vs_dh_m"):
            if key in r:
                ok = r[key] < ARM_FK_TARGET
                out.append(
                    {
                        "status": "PASS" if ok else "FAIL",
                        "name": f"A1 {name} FK {key[10:]}",
                        "value": sci(r[key]),
                        "target": f"< {ARM_FK_TARGET:g} m",
                    }
                )
    for name, by_f in results["timing"]["kept"].items():
        r = by_f["1"]
        ok = abs(r["duration_ratio"] - 1.0) <= 0.05
        out.append(
            {
                "status": "PASS" if ok else "FAIL",
                "name": f"A3 {name} learned duration kept",
                "value": f"x{r['duration_ratio']:.3f}",
                "target": "within 5 % at full limits",
            }
        )
    return out


def write_json(path: Path, sections: dict, targets: list[dict], meta: dict) -> None:
    """Write ``meta``, the sections' results and the targets to ``path`` atomically."""
    result = {**meta, **sections, "targets": targets}
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(jsonable(result), indent=2, ensure_ascii=False) + "\n"
    atomic_write(path, lambda f: f.write(text), overwrite=True, encoding="utf-8")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=Path(__file__).parent / "results" / "robot")
    parser.add_argument(
        "--quick",
        action="store_true",
        help=f"smoke run: {N_QUICK:,} instead of {N_FULL:,} configurations/poses, "
        f"rtb IK on {RTB_IK_QUICK} instead of {RTB_IK_FULL} poses",
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--arms-only",
        action="store_true",
        help="only section A (URDF arms: FK/IK against pinocchio, the learned timing kept, "
        "time-optimal timing against toppra)",
    )
    parser.add_argument(
        "--figures-only",
        action="store_true",
        help="only redraw robot_scenarios.png and robot_render.png: the first four scenarios "
        "of the full run (same seed, full coupling grid), the four planners drawn; no JSON",
    )
    args = parser.parse_args(argv)
    quick = args.quick
    if args.figures_only:
        # random_scenarios draws scenario by scenario: the full run's first four are these.
        with threadpool_limits(limits=1):
            exp = sweeping_experiment(
                4, args.seed, quick, args.output, planner_names=FIGURE_PLANNERS
            )
        for name in exp["figures"]:
            print(f"wrote {args.output / name}")
        for name, row in exp["summary"].items():
            print(f"  {name:26s} success {row['success_rate']:.0%} of 4")
        return 0
    n = N_QUICK if quick else N_FULL
    wall = time.perf_counter()
    sections: dict[str, dict] = {}
    targets: list[dict] = []

    with threadpool_limits(limits=1):
        rng = np.random.default_rng(args.seed)
        progress("A. URDF arms ...")
        arms = {"forward": arms_forward(quick, rng), "inverse": arms_inverse(quick, rng)}
        arms["timing"] = arms_timing(quick)
        print_arms(arms)
        sections["arms"] = arms
        targets += arms_targets(arms)
    with threadpool_limits(limits=1):
        if args.arms_only:
            return _finish(args, argv, quick, n, wall, sections, targets)
        progress("K1. FK cross-check ...")
        kin = {"crosscheck": kinematics_crosscheck(n, rng)}
        progress("K2. IK round trip ...")
        kin["ik_round_trip"] = ik_round_trip(n, rng)
        progress("K3. throughput ...")
        kin["speed"] = kinematics_speed(n, quick, seed=args.seed)
        print_kinematics(kin)
        sections["kinematics"] = kin
        targets += kinematics_targets(kin)

        progress("S1. MuJoCo kinematics ...")
        simulation = {"mujoco": mujoco_crosscheck(SIM_FK_QUICK if quick else SIM_FK_FULL, rng)}
        progress("S2. sweeping experiment ...")
        simulation["experiment"] = sweeping_experiment(
            SCENARIOS_QUICK if quick else SCENARIOS_FULL, args.seed, quick, args.output
        )
        print_simulation(simulation)
        sections["simulation"] = simulation
        targets += simulation_targets(simulation)
    return _finish(args, argv, quick, n, wall, sections, targets)


def _finish(args, argv, quick, n, wall, sections, targets) -> int:
    print_targets(targets)
    wall = time.perf_counter() - wall
    print(f"\nwall time {wall:.1f} s")

    meta = {
        "benchmark": "robot",
        "created": time.strftime("%Y-%m-%dT%H:%M:%S"),
        "command": [sys.executable, *sys.argv] if argv is None else ["robot.py", *argv],
        "quick": quick,
        "seed": args.seed,
        "machine": machine_info(),
        "versions": package_versions(VERSION_PACKAGES),
        "git": git_state(),
        "wall_time_s": wall,
        "settings": {
            "n": n,
            "speed_repeats": SPEED_REPEATS,
            "rtb_ik_poses": RTB_IK_QUICK if quick else RTB_IK_FULL,
            "rtb_ik_tols": list(RTB_IK_TOLS),
            "recover_tol_rad": RECOVER_TOL,
            "dh": {"d": UR5.d.tolist(), "a": UR5.a.tolist(), "alpha": UR5.alpha.tolist()},
        },
    }
    # Section A alone does not overwrite the full run's file.
    path = args.output / ("robot_arms.json" if args.arms_only else "robot.json")
    write_json(path, sections, targets, meta)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
