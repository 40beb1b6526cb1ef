"""TP-GMM benchmark (issue 33, task frames): held-out frame poses against GMR and DMP re-targeting.

Run ``python benchmarks/tpgmm.py`` (``--quick``: fewer demonstrations and
one noise level; ``--figure docs/tpgmm.png`` also draws one held-out fold).
Prints a table and writes ``tpgmm.json`` to ``--output``
(``benchmarks/results/tpgmm`` by default).

The task (synthetic, with a known answer): sweeping into a dustpan. Each
demonstration starts at the brush's pose (start frame: origin within ±5 cm,
turned ±0.5 rad) and ends in the dustpan (object frame: 0.6 m ahead within
±15 cm, turned ±1.2 rad, in 3-D also tilted ±0.3 rad). It leaves the start
along the start frame's x axis with a bulge, and arrives along the dustpan's
x axis with another, blended by a smoothstep in the phase; on it lies a
smooth random wiggle (3 sines) and white noise (0.3 × the wiggle's scale).
Leave one demonstration out: every method is fitted on the others and
reproduces with the held-out demonstration's frames (its start and its
dustpan). Errors, medians over the folds: RMS distance at equal phase to the
held-out demonstration and to the noise-free path of its frames (the known
answer), distance of the end from the dustpan, and the angle between the
arrival (last 10 % of the phase) and the noise-free one.

Methods: ``TPGMM`` (10 components, start and dustpan frames) with the
product of components (default) or of per-frame paths, and with joint EM
(pbdlib-python's stacked EM) instead of EM over the phase; ``GMR`` of the
demonstrations in world coordinates (ignores the frames); a ``DMP`` fitted to
that GMR path and rolled out from the held-out start to the held-out dustpan
(``translate``, lfdkit's default, and ``spatial``, which turns the shape
towards the goal). No peer: pbdlib is not on PyPI, and Rofunc (PyPI) needs
Python < 3.9.

Then the skills, through their files, on the ``dustpan`` data set
(:func:`lfdkit.datasets.dustpan_demos`: the same kind of sweep in 2-D, 3 mm
wiggle): :class:`lfdkit.skill.TaskFrameSkill` saved, loaded and planned for the
held-out poses, against :class:`lfdkit.skill.Skill` planned from the held-out
start to the pan's position, scored against the known answer.
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

from lfdkit.imitate import DMP, TPGMM, TaskFrame
from lfdkit.mimic import GMR

N_POINTS = 100
ARRIVAL = 10  # last samples (of 100) that give the arrival direction


def _rotation(d: int, rng: np.random.Generator, turn: float, tilt: float) -> np.ndarray:
    """A rotation: about z by ±turn (2-D: the plane), in 3-D then about x by ±tilt."""
    a = rng.uniform(-turn, turn)
    c, s = np.cos(a), np.sin(a)
    if d == 2:
        return np.array([[c, -s], [s, c]])
    b = rng.uniform(-tilt, tilt)
    about_z = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    about_x = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(b), -np.sin(b)], [0.0, np.sin(b), np.cos(b)]])
    return about_z @ about_x


def frames_of_task(d: int, rng: np.random.Generator) -> list[TaskFrame]:
    """The brush's start frame and the dustpan's frame of one sweep."""
    start = TaskFrame(_rotation(d, rng, 0.5, 0.0), rng.uniform(-0.05, 0.05, d))
    ahead = np.zeros(d)
    ahead[0] = 0.6
    goal = TaskFrame(_rotation(d, rng, 1.2, 0.3), ahead + rng.uniform(-0.15, 0.15, d))
    return [start, goal]


def true_path(frames: list[TaskFrame], n: int = N_POINTS) -> np.ndarray:
    """The noise-free sweep for these frames, shape (n, d), metres."""
    d = frames[0].origin.shape[0]
    t = np.linspace(0.0, 1.0, n)
    leave = np.zeros((n, d))
    leave[:, 0], leave[:, 1] = 0.4 * t, 0.08 * np.sin(np.pi * t)
    arrive = np.zeros((n, d))
    arrive[:, 0], arrive[:, 1] = -0.4 * (1 - t), 0.05 * np.sin(np.pi * (1 - t))
    if d == 3:
        leave[:, 2], arrive[:, 2] = 0.05 * np.sin(np.pi * t), 0.03 * np.sin(np.pi * (1 - t))
    blend = (t * t * (3 - 2 * t))[:, None]
    return (1 - blend) * frames[0].to_world(leave) + blend * frames[1].to_world(arrive)


def demonstration(frames: list[TaskFrame], noise: float, rng: np.random.Generator) -> np.ndarray:
    path = true_path(frames)
    t = np.linspace(0.0, 1.0, len(path))[:, None]
    wiggle = sum(
        noise * rng.normal(size=path.shape[1]) * np.sin((k + 1) * np.pi * t + rng.uniform(0, 6))
        for k in range(3)
    )
    return path + wiggle + 0.3 * noise * rng.normal(size=path.shape)


def _dmp_path(gmr_path: np.ndarray, frames: list[TaskFrame], scaling: str) -> np.ndarray:
    dmp = DMP(scaling=scaling).fit(gmr_path)
    return dmp.rollout(frames[0].origin, frames[1].origin, n_steps=N_POINTS).positions


METHODS = (
    "TPGMM components",
    "TPGMM paths",
    "TPGMM joint EM",
    "GMR (world)",
    "DMP translate",
    "DMP spatial",
)


def _fit_and_reproduce(method: str, demos, frames, held_frames) -> tuple[np.ndarray, float, float]:
    """The path for the held-out frames, fit seconds, reproduce seconds."""
    start = time.perf_counter()
    if method.startswith("TPGMM"):
        options: dict[str, Any] = {"product": "paths"} if method.endswith("paths") else {}
        if method.endswith("joint EM"):
            options = {"em": "joint"}
        model = TPGMM(random_state=0, **options).fit(demos, frames)
        fitted = time.perf_counter()
        path = model.path(held_frames, N_POINTS)
    else:
        gmr = GMR(random_state=0, n_points=N_POINTS).fit(demos)
        fitted = time.perf_counter()
        if method.startswith("DMP"):
            path = _dmp_path(gmr.path_, held_frames, method.split()[1])
        else:
            path = gmr.path_
    done = time.perf_counter()
    return path, fitted - start, done - fitted


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    cosine = np.dot(a, b) / (np.linalg.norm(a) * np.linalg.norm(b))
    return float(np.arccos(np.clip(cosine, -1.0, 1.0)))


def _score_against_truth(
    scores: dict[str, list[float]], path: np.ndarray, truth: np.ndarray, target: np.ndarray
) -> None:
    """Append the RMS distance to the known path, the end's distance from ``target``, and the
    arrival's angle off the known one (the last :data:`ARRIVAL` samples)."""
    scores["truth"].append(float(np.sqrt(np.mean(np.sum((path - truth) ** 2, axis=1)))))
    scores["end"].append(float(np.linalg.norm(path[-1] - target)))
    arrival = path[-1] - path[-ARRIVAL]
    scores["arrival"].append(_angle(arrival, truth[-1] - truth[-ARRIVAL]))


def held_out(d: int, n_demos: int, noise: float, seed: int) -> tuple[list[dict], dict]:
    rng = np.random.default_rng(seed)
    frames = [frames_of_task(d, rng) for _ in range(n_demos)]
    demos = [demonstration(f, noise, rng) for f in frames]
    scores: dict[str, dict[str, list[float]]] = {
        m: {"demo": [], "truth": [], "end": [], "arrival": [], "fit": [], "reproduce": []}
        for m in METHODS
    }
    example: dict[str, Any] = {}
    for j in range(n_demos):
        train = [x for i, x in enumerate(demos) if i != j]
        train_frames = [x for i, x in enumerate(frames) if i != j]
        truth = true_path(frames[j])
        for method in METHODS:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # DMP's far-goal notes; scored below
                path, fit_s, reproduce_s = _fit_and_reproduce(
                    method, train, train_frames, frames[j]
                )
            s = scores[method]
            s["demo"].append(float(np.sqrt(np.mean(np.sum((path - demos[j]) ** 2, axis=1)))))
            _score_against_truth(s, path, truth, frames[j][1].origin)
            s["fit"].append(fit_s)
            s["reproduce"].append(reproduce_s)
            if j == 0:
                example[method] = path
        if j == 0:
            example.update(held=demos[0], truth=truth, demos=train, frames=frames)
    rows = [
        {
            "method": m,
            "rms_to_demo_m": float(np.median(s["demo"])),
            "rms_to_truth_m": float(np.median(s["truth"])),
            "end_error_m": float(np.median(s["end"])),
            "arrival_error_rad": float(np.median(s["arrival"])),
            "fit_ms": 1e3 * float(np.median(s["fit"])),
            "reproduce_ms": 1e3 * float(np.median(s["reproduce"])),
        }
        for m, s in scores.items()
    ]
    return rows, example


def skills_held_out(n_demos: int, seed: int) -> list[dict]:
    """The skills through their files, leave one out, on the ``dustpan`` data set.

    ``TaskFrameSkill`` (fitted, saved, loaded, planned for the held-out
    demonstration's start and pan poses) against ``Skill`` (the mimicked path's
    DMP, planned from the held-out start to the held-out pan's position: what
    re-targeting a goal point gives). Scored against the known answer
    (:func:`lfdkit.datasets.dustpan_sweep` of the held-out poses).
    """
    import tempfile

    from lfdkit.datasets import dustpan_demos, dustpan_sweep
    from lfdkit.model.demos import Demo
    from lfdkit.skill import Skill, TaskFrameSkill

    demos, times, frames = dustpan_demos(seed=seed, n_demos=n_demos, n_points=N_POINTS)
    records = [Demo(d, t, frames=f) for d, t, f in zip(demos, times, frames, strict=True)]
    names = ("TaskFrameSkill (file)", "Skill (DMP to the pan)")
    scores = {m: {"truth": [], "end": [], "arrival": [], "fit": [], "plan": []} for m in names}
    with tempfile.TemporaryDirectory() as folder:
        for j in range(n_demos):
            train = [r for i, r in enumerate(records) if i != j]
            start, pan = frames[j]["start"], frames[j]["pan"]
            truth = dustpan_sweep(start, pan, N_POINTS)
            for name in names:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")  # Skill.fit_path's note on the frames
                    began = time.perf_counter()
                    if name.startswith("TaskFrameSkill"):
                        file = TaskFrameSkill().fit(train).save(Path(folder) / f"{j}.json")
                        skill = TaskFrameSkill.load(file)
                        fitted = time.perf_counter()
                        path = skill.plan({"start": start, "pan": pan}, n_points=N_POINTS)
                        path = path.positions
                    else:
                        skill = Skill(n_points=N_POINTS).fit_path(train)
                        fitted = time.perf_counter()
                        path = np.asarray(skill.plan(demos[j][0], pan[:2]).points)
                    done = time.perf_counter()
                s = scores[name]
                _score_against_truth(s, path, truth, pan[:2])
                s["fit"].append(fitted - began)
                s["plan"].append(done - fitted)
    return [
        {
            "method": m,
            "rms_to_truth_m": float(np.median(s["truth"])),
            "end_error_m": float(np.median(s["end"])),
            "arrival_error_rad": float(np.median(s["arrival"])),
            "fit_ms": 1e3 * float(np.median(s["fit"])),
            "plan_ms": 1e3 * float(np.median(s["plan"])),
        }
        for m, s in scores.items()
    ]


def draw(example: dict[str, Any], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(10, 4.6))
    for k, demo in enumerate(example["demos"]):
        ax.plot(*demo.T, color="0.75", lw=1, label="training demonstrations" if k == 0 else None)
    for f_index, pair in enumerate(example["frames"]):
        for frame, color in zip(pair, ("tab:purple", "tab:brown"), strict=True):
            x_axis = frame.matrix[:, 0] * 0.06
            held = f_index == 0
            ax.annotate(
                "",
                xy=frame.origin + x_axis,
                xytext=frame.origin,
                arrowprops={"arrowstyle": "->", "color": color, "lw": 2.0 if held else 0.8},
            )
    ax.plot(*example["truth"].T, "k--", lw=2, label="held-out frames: known answer")
    ax.plot(*example["held"].T, color="k", lw=0.8, alpha=0.6, label="held-out demonstration")
    styles = {
        "TPGMM components": ("tab:blue", "TP-GMM (start + dustpan frames)"),
        "DMP translate": ("tab:orange", "DMP to the held-out goal (translate)"),
        "DMP spatial": ("tab:red", "DMP to the held-out goal (spatial)"),
        "GMR (world)": ("tab:green", "GMR, world coordinates"),
    }
    for method, (color, label) in styles.items():
        ax.plot(*example[method].T, color=color, lw=2, label=label)
    ax.plot([], [], color="tab:purple", label="start frames' x axes (held-out: bold)")
    ax.plot([], [], color="tab:brown", label="dustpan frames' x axes (held-out: bold)")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("Sweeping into a dustpan turned and moved: one held-out fold")
    ax.legend(fontsize=7, loc="lower left", bbox_to_anchor=(1.01, 0.0))
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    print(f"wrote {path}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="8 demonstrations, one noise level")
    parser.add_argument("--output", type=Path, default=Path("benchmarks/results/tpgmm"))
    parser.add_argument("--figure", type=Path, help="also draw one held-out fold (2-D) here")
    args = parser.parse_args(argv)
    n_demos = 8 if args.quick else 12
    settings = [(2, 0.005), (3, 0.005)] if args.quick else [(2, 0.005), (2, 0.02), (3, 0.005)]
    results = []
    for d, noise in settings:
        rows, example = held_out(d, n_demos, noise, seed=0)
        results.append({"n_dims": d, "noise_m": noise, "n_demos": n_demos, "rows": rows})
        print(
            f"\n{d}-D sweep into a dustpan, {n_demos} demonstrations, wiggle {1e3 * noise:g} mm, "
            "leave one out (medians)"
        )
        print(
            f"{'method':<18}{'RMS demo cm':>12}{'RMS truth cm':>13}{'end cm':>8}"
            f"{'arrival deg':>12}{'fit ms':>8}{'reproduce ms':>13}"
        )
        for r in rows:
            print(
                f"{r['method']:<18}{100 * r['rms_to_demo_m']:>12.2f}"
                f"{100 * r['rms_to_truth_m']:>13.2f}{100 * r['end_error_m']:>8.2f}"
                f"{np.degrees(r['arrival_error_rad']):>12.1f}"
                f"{r['fit_ms']:>8.1f}{r['reproduce_ms']:>13.2f}"
            )
        if args.figure is not None and d == 2 and noise == settings[0][1]:
            draw(example, args.figure)
    n_skill = 8 if args.quick else 12
    skills = skills_held_out(n_skill, seed=0)
    print(
        f"\nThe skills through their files: the dustpan data set (lfdkit.datasets), {n_skill} "
        "sweeps, leave one out (medians)"
    )
    header = f"{'RMS truth cm':>13}{'end cm':>8}{'arrival deg':>12}{'fit ms':>8}{'plan ms':>9}"
    print(f"{'method':<24}{header}")
    for r in skills:
        print(
            f"{r['method']:<24}{100 * r['rms_to_truth_m']:>13.2f}{100 * r['end_error_m']:>8.2f}"
            f"{np.degrees(r['arrival_error_rad']):>12.1f}{r['fit_ms']:>8.1f}{r['plan_ms']:>9.2f}"
        )
    result = {
        "settings": results,
        "skills": {"data": "dustpan", "n_demos": n_skill, "rows": skills},
        "machine": machine_info(),
        "git": git_state(),
        "packages": package_versions(["numpy", "scikit-learn"]),
        "peer": "none: pbdlib is not on PyPI; rofunc needs Python < 3.9",
    }
    args.output.mkdir(parents=True, exist_ok=True)
    out = write_json(args.output / "tpgmm.json", result)
    print(f"\nwrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
