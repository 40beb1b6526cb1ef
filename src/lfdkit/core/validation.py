"""Input checks shared by every layer.

Each check raises ``ValueError`` (or ``TypeError`` for a wrong kind of object)
with a message that names the argument and says what was wrong, so that bad
input never surfaces as a traceback from deep inside NumPy.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any, Literal

import numpy as np

from lfdkit.core.options import MAX_HORIZON, MIN_HORIZON

__all__ = [
    "MAX_POINTS",
    "check_class_names",
    "check_count",
    "check_demos",
    "check_finite",
    "check_path",
    "check_point",
    "check_positive",
    "check_random_state",
    "check_state_array",
    "check_state_number",
    "check_times",
    "check_times_list",
    "check_values",
    "made_from_state",
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
    if n_points <= 3 < 10 <= dims:  # (q, n) for (n, q): no lfdkit path has 10 dimensions
        raise ValueError(
            f"{name}: got shape {arr.shape}, which looks transposed: one row per sample, "
            f"shape (n_points, n_dims), is expected; pass its transpose (.T)"
        )
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
        raise ValueError(
            f"{name}: contains {kind} at row {row}; remove or interpolate the missing samples"
        )
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


def check_point(
    value: Any,
    name: str,
    q: int,
    *,
    batch: str | None = None,
    style: Literal["shape", "point"] = "shape",
) -> np.ndarray:
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
    style : {"shape", "point"}
        Wording of the errors. ``"shape"``: in array terms ("expected shape (q,)"),
        ``TypeError`` for what is not numbers. ``"point"``: in the task's terms, for
        callers whose users give points ("expected a q-D point, got shape ..."),
        ``ValueError`` for every bad value.

    Returns
    -------
    ndarray of float64
    """
    error = TypeError if style == "shape" else ValueError
    if _not_numbers(value):
        # NumPy reads "0.36" and True as numbers; a coordinate given as text or a
        # flag is a mistake the caller should hear about, not a goal at (1, 0).
        raise error(f"{name}: expected {q} numbers, got strings or booleans: {value!r}")
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise error(f"{name}: expected {q} numbers, got {value!r}") from exc
    single = arr.shape == (q,)
    if not single and not (batch is not None and arr.ndim == 2 and arr.shape[1] == q):
        if style == "point":
            raise ValueError(f"{name}: expected a {q}-D point, got shape {arr.shape}")
        if batch is None:
            raise ValueError(f"{name}: expected shape ({q},), got {arr.shape}")
        raise ValueError(f"{name}: expected shape ({q},) or ({batch}, {q}), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: contains NaN or infinite values")
    return arr


def _not_numbers(value: Any) -> bool:
    """Whether ``value`` holds text or booleans, which NumPy would read as numbers."""
    if isinstance(value, (str, bytes, bool, np.bool_)):
        return True
    if isinstance(value, np.ndarray):
        return value.dtype.kind in "bUSO" and (
            value.dtype.kind != "O" or any(_not_numbers(v) for v in value.ravel().tolist())
        )
    if isinstance(value, (list, tuple)):
        return any(_not_numbers(v) for v in value)
    return False


def check_times(
    times: Any,
    n_points: int,
    name: str = "times",
    *,
    of: str = "the demonstration",
    increasing: bool = True,
    style: Literal["samples", "shape"] = "samples",
) -> np.ndarray:
    """Validate the times (or phases) of the ``n_points`` samples of one path.

    Parameters
    ----------
    times : array_like, shape (n_points,)
    n_points : int
        Number of samples of the path the times belong to.
    name : str
        Argument name used in error messages.
    of : str
        The path, as error messages name it ("the demonstration", "path", "demos[2]").
    increasing : bool
        Whether the times must increase strictly (phases of GMR need not).
    style : {"samples", "shape"}
        Wording of the errors. ``"samples"``: a recorded demonstration's, naming the
        offending sample and its value (the file readers'). ``"shape"``: in array
        terms, as :func:`check_point` words them.

    Returns
    -------
    ndarray of float64, shape (n_points,)
        The times as given (not shifted).

    Raises
    ------
    TypeError
        If ``times`` cannot be read as numbers.
    ValueError
        For another shape, NaN or infinite values, or (``increasing``) a time
        that does not come after the one before it.
    """
    samples = style == "samples"
    try:
        arr = np.asarray(times, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        what = "a 1-D numeric array of times in seconds" if samples else "a 1-D numeric array"
        raise TypeError(f"{name}: expected {what}") from exc
    if not samples and arr.shape != (n_points,):
        raise ValueError(f"{name}: expected shape ({n_points},) to match {of}, got {arr.shape}")
    if samples and arr.ndim != 1:
        raise ValueError(f"{name}: expected a 1-D array of times, got shape {arr.shape}")
    if samples and arr.shape[0] != n_points:
        raise ValueError(f"{name}: has {arr.shape[0]} times but {of} has {n_points} points")
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size and samples:
        i = int(bad[0])
        raise ValueError(f"{name}: time at index {i} is {float(arr[i])!r}; times must be finite")
    if bad.size:
        raise ValueError(f"{name}: contains NaN or infinite values")
    step = np.flatnonzero(np.diff(arr) <= 0) if increasing else ()
    if len(step) and samples:
        i = int(step[0]) + 1
        raise ValueError(
            f"{name}: times must be strictly increasing; t[{i}] = {float(arr[i])!r} "
            f"is not after t[{i - 1}] = {float(arr[i - 1])!r}"
        )
    if len(step):
        raise ValueError(f"{name}: must increase strictly (row {int(step[0]) + 1} does not)")
    return arr


def check_times_list(
    times: Any,
    demos: Sequence[np.ndarray],
    *,
    missing: bool = True,
    increasing: bool = True,
    style: Literal["samples", "shape"] = "samples",
) -> list[np.ndarray | None]:
    """Validate one time array per demonstration (:func:`check_times` of each).

    Parameters
    ----------
    times : sequence of array_like, or ndarray of shape (n_demos, n_points)
        ``times[j]`` for ``demos[j]``; with ``missing``, ``None`` (all or one) for none.
    demos : sequence of ndarray
        The demonstrations, already validated (:func:`check_demos`).
    missing : bool
        Whether a demonstration may come without times (``None``).
    increasing, style
        As :func:`check_times`; ``style="shape"`` names ``demos[j]`` as the path.

    Returns
    -------
    list of ndarray (or None where ``missing`` allows it)
    """
    if times is None and missing:
        return [None] * len(demos)
    if isinstance(times, np.ndarray) and times.ndim == 2:
        times = list(times)  # (n_demos, n_points), matching a 3-D demos array
    if isinstance(times, (str, bytes, np.ndarray)) or not isinstance(times, Sequence):
        either = " (or None)" if missing else ""
        raise TypeError(
            f"times: expected a list with one 1-D array{either} per demonstration, "
            "or a 2-D array of shape (n_demos, n_points)"
        )
    if len(times) != len(demos):
        raise ValueError(f"times: got {len(times)} entries for {len(demos)} demonstrations")
    out: list[np.ndarray | None] = []
    for j, (t, demo) in enumerate(zip(times, demos, strict=True)):
        of = "the demonstration" if style == "samples" else f"demos[{j}]"
        given = t is not None or not missing
        out.append(
            check_times(t, len(demo), f"times[{j}]", of=of, increasing=increasing, style=style)
            if given
            else None
        )
    return out


def check_values(value: Any, name: str) -> np.ndarray:
    """Validate a 1-D array of finite numbers (phases, scores) at which to evaluate a model.

    A scalar is read as one value and a column of shape ``(n, 1)`` as its ``n``
    values. Returns a float64 array of shape ``(n,)``; ``TypeError`` for what
    is not numbers, ``ValueError`` for another shape or a NaN or infinite value.
    """
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected a numeric 1-D array") from exc
    if arr.ndim == 0:
        arr = arr.reshape(1)
    elif arr.ndim == 2 and arr.shape[1] == 1:
        arr = arr[:, 0]
    elif arr.ndim != 1:
        raise ValueError(f"{name}: expected a 1-D array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name}: contains NaN or an infinite value")
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


def check_class_names(classes: Any, name: str = "classes") -> list[str]:
    """Check a list of obstacle-class names (non-empty strings); return it as a list.

    A single string is refused (it would be read as its letters).
    """
    if (
        isinstance(classes, str)
        or not hasattr(classes, "__iter__")
        or not all(isinstance(c, str) and c for c in classes)
    ):
        raise ValueError(f"{name}: expected a list of class names, got {classes!r}")
    return list(classes)


def check_horizon(value: Any, name: str = "horizon") -> int:
    """Check a receding horizon: an integer from ``MIN_HORIZON`` to ``MAX_HORIZON``; return it.

    The one check of the horizon (:mod:`lfdkit.core.options` holds the bounds,
    4 to 12, the horizons the thesis found to work, §5.4): the skill, the
    planner, the moving-obstacle planner and IOC call it where the value enters.
    """
    horizon = check_positive(value, name, integer=True)
    if not MIN_HORIZON <= horizon <= MAX_HORIZON:
        raise ValueError(
            f"{name}: expected {MIN_HORIZON} <= H <= {MAX_HORIZON} (thesis §5.4), got {horizon}"
        )
    return horizon


def made_from_state(cls: type, state: Any, where: str, keys: Sequence[str]) -> Any:
    """An unfitted ``cls(**state["params"])``, its parameters validated, once every key is there.

    For an estimator's ``from_state`` (a skill file's section): ``state`` must
    be a mapping holding ``"params"`` (a mapping of constructor arguments) and
    each of ``keys``. Raises ``ValueError`` in one line starting with
    ``where`` (``"promp.width: missing field"``, ``"promp.params: n_basis: ..."``).
    """
    if not isinstance(state, Mapping):
        raise ValueError(f"{where}: expected an object, got {type(state).__name__}")
    for key in ("params", *keys):
        if key not in state:
            raise ValueError(f"{where}.{key}: missing field")
    if not isinstance(state["params"], Mapping):
        raise ValueError(f"{where}.params: expected an object, got {state['params']!r}")
    try:
        made = cls(**dict(state["params"]))
        made._validate_params()
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where}.params: {exc}") from None
    return made


def check_state_array(
    state: Mapping[str, Any], key: str, where: str, shape: tuple[int | None, ...]
) -> np.ndarray:
    """``state[key]`` as a finite float64 array of ``shape`` (None: any non-zero size there).

    For an estimator's ``from_state`` (nested lists from a skill file, or an
    array). Raises ``ValueError`` in one line naming ``where.key``.
    """
    try:
        array = np.array(state[key], dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{where}.{key}: expected numbers of shape {shape}") from None
    if array.ndim != len(shape) or any(
        n == 0 or (want is not None and n != want)
        for n, want in zip(array.shape, shape, strict=False)
    ):
        raise ValueError(f"{where}.{key}: shape {array.shape}, expected {shape}")
    if not np.isfinite(array).all():
        raise ValueError(f"{where}.{key}: contains NaN or infinite values")
    return array


def check_state_number(state: Mapping[str, Any], key: str, where: str, *, positive: bool) -> float:
    """``state[key]``, a finite number > 0 (``positive``) or >= 0, as a float.

    Raises ``ValueError`` in one line naming ``where.key`` and the value (a
    bool, a string or a list is not a number).
    """
    value = state[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{where}.{key}: expected a number, got {value!r}")
    if not math.isfinite(value) or value < 0.0 or (positive and value == 0.0):
        wanted = "a positive number" if positive else "a number >= 0"
        raise ValueError(f"{where}.{key}: expected {wanted}, got {value!r}")
    return float(value)
