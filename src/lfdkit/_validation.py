"""Input checks shared by every layer.

Each check raises ``ValueError`` (or ``TypeError`` for a wrong kind of object)
with a message that names the argument and says what was wrong, so that bad
input never surfaces as a traceback from deep inside NumPy.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = [
    "MAX_POINTS",
    "check_count",
    "check_demos",
    "check_finite",
    "check_path",
    "check_positive",
    "check_random_state",
]

#: Most points a caller may ask a function to produce (paths, resamplings,
#: rollouts): a million 3-D points are 24 MB; more is a typo, not a path, and
#: would end as a MemoryError deep inside NumPy.
MAX_POINTS = 1_000_000


def check_path(
    path: Any,
    name: str = "path",
    *,
    min_points: int = 2,
    n_dims: int | None = None,
    min_dims: int = 2,
) -> np.ndarray:
    """Validate one path and return it as a float64 array of shape ``(n_points, n_dims)``.

    Parameters
    ----------
    path : array_like, shape (n_points, n_dims)
        Sampled points, one row per sample.
    name : str
        Argument name used in error messages.
    min_points : int
        Fewest rows accepted.
    n_dims : int, optional
        Required number of columns; any number ``>= min_dims`` when omitted.
    min_dims : int
        Fewest columns accepted when ``n_dims`` is not given.

    Raises
    ------
    TypeError
        If ``path`` cannot be read as a numeric array.
    ValueError
        If the shape is wrong, there are too few points, or a value is NaN/inf.
    """
    try:
        arr = np.asarray(path, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected a numeric array of shape (n_points, n_dims)") from exc
    if arr.ndim != 2:
        raise ValueError(
            f"{name}: expected a 2-D array of shape (n_points, n_dims), got shape {arr.shape}"
        )
    n_points, dims = arr.shape
    if n_dims is not None and dims != n_dims:
        raise ValueError(f"{name}: expected {n_dims} columns (dimensions), got {dims}")
    if n_dims is None and dims < min_dims:
        raise ValueError(f"{name}: expected at least {min_dims} dimensions, got {dims}")
    if n_points < min_points:
        raise ValueError(f"{name}: needs at least {min_points} points, got {n_points}")
    bad = ~np.isfinite(arr)
    if bad.any():
        row = int(np.argwhere(bad)[0, 0])
        kind = "NaN" if np.isnan(arr[row]).any() else "an infinite value"
        raise ValueError(f"{name}: contains {kind} at row {row}")
    return arr


def check_demos(
    demos: Any,
    name: str = "demos",
    *,
    min_demos: int = 1,
    min_points: int = 2,
    n_dims: int | None = None,
    min_dims: int = 2,
) -> list[np.ndarray]:
    """Validate a set of demonstrations of possibly different lengths.

    Parameters
    ----------
    demos : sequence of array_like or ndarray
        Each demonstration of shape ``(n_points_j, n_dims)``, or one array of
        shape ``(n_demos, n_points, n_dims)``.
        The demonstrations. All must share ``n_dims``.
    name : str
        Argument name used in error messages.
    min_demos : int
        Fewest demonstrations accepted.
    min_points : int
        Fewest points accepted in each demonstration.
    n_dims : int, optional
        Required dimension; inferred from the first demonstration when omitted.
    min_dims : int
        Fewest spatial dimensions accepted when ``n_dims`` is inferred (GMR and
        NLPCA also take 1-D demonstrations).

    Returns
    -------
    list of ndarray, each shape (n_points_j, n_dims)
    """
    if isinstance(demos, np.ndarray):
        if demos.ndim == 2:
            raise ValueError(
                f"{name}: got one 2-D array; pass a list of (n_points, n_dims) arrays, "
                "e.g. [path] for a single demonstration"
            )
        if demos.ndim != 3:
            raise ValueError(
                f"{name}: expected a list of (n_points, n_dims) arrays or a 3-D array, "
                f"got shape {demos.shape}"
            )
        items: Sequence[Any] = list(demos)
    elif isinstance(demos, (str, bytes)) or not isinstance(demos, Sequence):
        raise TypeError(f"{name}: expected a list of (n_points, n_dims) arrays")
    else:
        items = demos
    if len(items) < min_demos:
        raise ValueError(f"{name}: needs at least {min_demos} demonstration(s), got {len(items)}")
    out = []
    for j, demo in enumerate(items):
        arr = check_path(
            demo, f"{name}[{j}]", min_points=min_points, n_dims=n_dims, min_dims=min_dims
        )
        if n_dims is None:
            n_dims = arr.shape[1]
        out.append(arr)
    return out


def check_point(value: Any, name: str, q: int, *, batch: str | None = None) -> np.ndarray:
    """Validate one point of ``q`` coordinates, or with ``batch`` a stack of them.

    Parameters
    ----------
    value : array_like, shape (q,) or, with ``batch``, (n, q)
    name : str
        Argument name used in error messages.
    q : int
        Number of coordinates.
    batch : str, optional
        Name of the leading axis when a stack of points is accepted (e.g. "n_rollouts").

    Returns
    -------
    ndarray of float64
    """
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected {q} numbers, got {value!r}") from exc
    if batch is None and arr.shape != (q,):
        raise ValueError(f"{name}: expected shape ({q},), got {arr.shape}")
    if batch is not None and (arr.ndim not in (1, 2) or arr.shape[-1] != q):
        raise ValueError(f"{name}: expected shape ({q},) or ({batch}, {q}), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: contains NaN or infinite values")
    return arr


def check_finite(value: Any, name: str) -> float:
    """Check a scalar parameter is a finite number; return it as a float."""
    try:
        out = float(value)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected a number, got {value!r}") from exc
    if not np.isfinite(out):
        raise ValueError(f"{name}: must be finite, got {value!r}")
    return out


def check_positive(value: Any, name: str, *, integer: bool = False, allow_zero: bool = False):
    """Check a scalar parameter is finite and positive (or non-negative); return it."""
    if integer:
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise TypeError(f"{name}: expected an integer, got {value!r}")
        value = int(value)
    else:
        value = check_finite(value, name)
    if value < 0 or (value == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name}: must be {bound}, got {value!r}")
    return value


def check_count(value: Any, name: str, *, minimum: int = 1, maximum: int = MAX_POINTS) -> int:
    """Check an integer size (a number of points, components, ...) is within bounds.

    Raises ``TypeError`` for a non-integer and ``ValueError`` naming ``name``
    and both bounds otherwise; returns it as an ``int``.
    """
    count = check_positive(value, name, integer=True, allow_zero=minimum <= 0)
    if not minimum <= count <= maximum:
        raise ValueError(f"{name}: expected {minimum:,} to {maximum:,}, got {count:,}")
    return count


def check_random_state(seed: Any) -> np.random.Generator:
    """Turn ``None``, an int or a ``Generator`` into a ``numpy.random.Generator``."""
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None or isinstance(seed, (int, np.integer)):
        return np.random.default_rng(seed)
    raise TypeError(f"seed: expected None, an int or a numpy Generator, got {type(seed).__name__}")
