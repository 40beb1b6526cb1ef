"""Helpers shared by the benchmark scripts: what the JSON records about the run."""

from __future__ import annotations

import json
import os
import platform
import subprocess
from collections.abc import Iterable
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np


def package_versions(packages: Iterable[str]) -> dict[str, str | None]:
    """Installed version of each distribution, None where it is not installed."""
    out: dict[str, str | None] = {}
    for package in packages:
        try:
            out[package] = metadata.version(package)
        except metadata.PackageNotFoundError:
            out[package] = None
    return out


def git_state() -> dict:
    """The checkout's commit and whether ``src/`` has uncommitted changes (None outside git)."""
    root = Path(__file__).resolve().parent.parent
    try:
        head = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=root, capture_output=True, text=True, check=True
        ).stdout.strip()
        dirty = subprocess.run(
            ["git", "status", "--porcelain", "--", "src"],
            cwd=root,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        return {"commit": head, "src_modified": bool(dirty)}
    except (OSError, subprocess.CalledProcessError):
        return {"commit": None, "src_modified": None}


def machine_info() -> dict:
    """Python version, CPU count, platform, processor and load average of this machine."""
    return {
        "python": platform.python_version(),
        "cpus": os.cpu_count(),
        "platform": platform.platform(),
        "processor": platform.processor(),
        "load_average": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
    }


def json_ready(value: Any, drop: Iterable[str] = ()) -> Any:
    """A JSON-ready copy: arrays and NumPy scalars as Python, non-finite floats as ``None``.

    Keys starting with ``_`` and those in ``drop`` (live objects kept for figures) are left out.
    """
    drop = frozenset(drop)
    if isinstance(value, dict):
        return {
            str(k): json_ready(v, drop)
            for k, v in value.items()
            if not str(k).startswith("_") and k not in drop
        }
    if isinstance(value, (list, tuple)):
        return [json_ready(v, drop) for v in value]
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return None
    return value


def write_json(path: Path, result: Any) -> Path:
    """Write ``result`` (made :func:`json_ready`) to ``path`` atomically, replacing it."""
    from lfdkit.io import atomic_write

    text = json.dumps(json_ready(result), indent=1) + "\n"
    return atomic_write(path, lambda f: f.write(text), overwrite=True)
