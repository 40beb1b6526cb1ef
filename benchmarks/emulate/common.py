"""Helpers of the emulation benchmark's sections: progress, timing, formatting, plans, nominals."""

from __future__ import annotations

import sys
import time
import warnings

import numpy as np

from lfdkit.core.geometry import project_onto_polyline
from lfdkit.emulate import Reward
from lfdkit.emulate.metrics import clearance, collisions, mse_paths
from lfdkit.mimic import MeanPath
from lfdkit.model.scene import Scene

from .spec import HELD_OUT_NAMES

# ----------------------------------------------------------------------------- helpers
_STARTED = time.perf_counter()


def progress(message: str) -> None:
    sys.stdout.flush()
    print(f"[{time.perf_counter() - _STARTED:6.1f} s] {message}", file=sys.stderr, flush=True)


def timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def pct(x: float | None) -> str:
    return "—" if x is None or not np.isfinite(x) else f"{100 * x:.1f}%"


def sci(x: float | None, digits: int = 2) -> str:
    return "—" if x is None or not np.isfinite(x) else f"{x:.{digits}e}"


def reward_record(reward: Reward) -> dict:
    return {
        "Q": float(reward.nominal_weight),
        "precisions": {c: np.diag(m).tolist() for c, m in reward.precisions.items()},
    }


def reward_text(reward: Reward) -> str:
    parts = [f"Q={reward.nominal_weight:.4g}"]
    for label, matrix in reward.precisions.items():
        parts.append(f"{label}=[{', '.join(f'{v:.4g}' for v in np.diag(matrix))}]")
    return " ".join(parts)


def mean_path(demos, **kwargs) -> tuple[np.ndarray, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        path = MeanPath(**kwargs).fit(demos).path_
    return path, [f"{w.category.__name__}: {w.message}" for w in caught]


def safe_plan(fn) -> tuple[np.ndarray | None, str | None]:
    """``fn()`` returns a Plan; errors (e.g. a start inside an obstacle) are recorded."""
    try:
        return fn().points, None
    except Exception as exc:  # recorded, never fatal
        return None, f"{type(exc).__name__}: {exc}"


def scene_metrics(path: np.ndarray | None, scene: Scene, reference: np.ndarray | None) -> dict:
    if path is None:
        return {"collisions": None, "min_clearance": None, "mse_to_true": None}
    gaps = clearance(path, scene)
    return {
        "collisions": collisions(path, scene),
        "min_clearance": float(gaps.min()) if gaps.size else None,
        "mse_to_true": None if reference is None else mse_paths(path, [reference]),
    }


def held_out_names(name: str, n: int) -> list[str]:
    names = list(HELD_OUT_NAMES.get(name, ()))
    return names if len(names) == n else [f"held-out {i}" for i in range(n)]


def nominal_variants(es, include) -> dict[str, dict]:
    """The nominal paths a set is learned with (module notes)."""
    out = {}
    if "train" in include:
        path, caught = mean_path(es.train_demos, center="biweight")
        out["train"] = {
            "path": path,
            "source": "MeanPath(center='biweight') of the training demonstrations",
            "warnings": caught,
        }
    free = getattr(es, "free_demos", None)
    if "free" in include and free:
        path, caught = mean_path(free)
        out["free"] = {
            "path": path,
            "source": f"MeanPath() of the {len(free)} obstacle-free demonstrations",
            "warnings": caught,
        }
    if "true" in include:
        out["true"] = {"path": es.nominal, "source": "true nominal (reference)", "warnings": []}
    for info in out.values():
        distance = project_onto_polyline(info["path"], es.nominal)[2]
        info["deviation_max"] = float(distance.max())
        info["deviation_mean"] = float(distance.mean())
    return out
