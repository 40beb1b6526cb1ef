"""Demonstration files: a demonstration set read and written in CSV, NPZ or JSON.

A demonstration set is the data model of :mod:`lfdkit.model.demos`: a list of
float64 arrays of shape ``(n_points_j, n_dims)``, optionally with sample
times in seconds and with one id (:data:`lfdkit.model.demos.DemoId`) per
demonstration.

Files
-----
The format is chosen from the file suffix (case-insensitive):

``.csv``
    A header row, then one row per sample. Columns: ``demo`` (the
    demonstration id, integer or string, without surrounding spaces; without
    a ``demo`` column the whole file is one demonstration, id ``0``, as a
    recorder writes one take), optionally ``t`` or ``time`` (seconds), and the coordinates, named
    ``x, y[, z]`` or ``x1, x2, ..., xq``, optionally the tool orientation
    ``qx, qy, qz, qw`` (a unit quaternion, all four or none), and optionally
    the pose of each task frame (:attr:`lfdkit.model.demos.Demo.frames`):
    ``frame_<name>_x, frame_<name>_y, frame_<name>_angle`` in 2-D,
    ``frame_<name>_x, _y, _z, _qx, _qy, _qz, _qw`` in 3-D, one pose per
    demonstration (the same on each of its rows; every demonstration has
    the same frames). The rows of one demonstration are
    consecutive, in time order; demonstrations are in file order. Numbers are
    decimal (``-0.5``, ``1e-3``; not ``0_5``, ``nan`` or ``inf``). Blank lines
    and lines starting with ``#`` are ignored. Columns with other names are
    ignored.
``.npz``
    Arrays ``demo_0, demo_1, ...`` (each ``(n_points_j, n_dims)``), optionally
    ``time_j`` and ``quat_j`` (orientations, ``(n_points_j, 4)``) for any
    ``j`` and ``ids`` (1-D, one per demonstration); or a
    single 3-D array ``demos`` of shape ``(n_demos, n_points, n_dims)`` with an
    optional 2-D ``times`` of shape ``(n_demos, n_points)``. Coordinates and
    times are real (float or integer dtype; complex, boolean, date and text
    arrays are refused). Never unpickled; other arrays in the archive are never
    decompressed. (Members of a zip archive cannot be memory-mapped, so each
    array needed is read once, after its size is checked.)
``.json``
    ``{"format": "lfdkit-demos", "version": 1, "n_dims": q, "demos":
    [{"id": ..., "points": [[x, y], ...], "t": [...], "q": [[qx, qy, qz, qw],
    ...], "frames": {"pan": {"position": [x, y], "angle": a}}}, ...]}`` with
    ``"t"``, ``"q"`` (and ``"id"``) optional per demonstration; ``"frames"``
    for every demonstration or none (in 3-D ``{"position": [x, y, z],
    "orientation": [qx, qy, qz, qw]}``). NPZ files hold no task frames.

Several files
-------------
:func:`load_demo_files` reads several files as one set (``lfdkit learn A.csv
B.csv ...``): their demonstrations in the order given; a CSV without a
``demo`` column is one demonstration whose id is its file's stem
(``take_03.csv`` is ``"take_03"``, so a scene file can name it); ids must
differ across files, and all files must agree on their dimension and on
whether they carry times, orientations and which task frames (one-line errors
naming both files).

Writing is atomic (see :func:`lfdkit.io.atomic.atomic_write`) and floats
are written so that a load after a save gives back bit-identical arrays in
every format.

Reading is strict (the primitives of :mod:`lfdkit.io.text`): anything that
could change the data silently is an error naming the file and the line,
column, JSON path or array (repeated JSON keys, numbers given as strings,
non-real arrays, ``0_5`` in a CSV cell, ids with spaces, the rows of one id
in two places). Files larger than :data:`lfdkit.io.text.MAX_FILE_BYTES`,
JSON nested deeper than :data:`lfdkit.io.text.MAX_JSON_DEPTH`, and ``.npz``
archives with more than :data:`MAX_NPZ_MEMBERS` arrays or an array over
:data:`MAX_NPZ_ARRAY_BYTES` are refused before they are read, and only the
arrays needed are decompressed. FIFOs, devices and sockets are neither read
nor written.
"""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
import os
import re
import zipfile
import zlib
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import IO, Any, Literal, overload

import numpy as np

from lfdkit.core.rotations import check_quaternions
from lfdkit.core.validation import check_demos, check_path, check_times, check_times_list
from lfdkit.io.atomic import atomic_write, check_output_path, write_text
from lfdkit.io.text import (
    Blocks,
    check_file_id,
    check_ids,
    check_input_file,
    csv_header,
    csv_number,
    csv_rows,
    format_of,
    header_hint,
    json_document,
    json_float_array,
    parse_id,
)
from lfdkit.model.demos import Demo, DemoId, PathLike, demo_fields

__all__ = [
    "FRAME_POSE_FIELDS",
    "JSON_FORMAT",
    "JSON_VERSION",
    "MAX_NPZ_ARRAY_BYTES",
    "MAX_NPZ_MEMBERS",
    "QUATERNION_COLUMNS",
    "SUPPORTED_SUFFIXES",
    "is_frame_name",
    "load_demo_files",
    "load_demos",
    "path_csv",
    "save_demos",
    "save_path",
]

SUPPORTED_SUFFIXES: tuple[str, ...] = (".csv", ".json", ".npz")
"""File suffixes understood by :func:`load_demos` and :func:`save_demos`."""

QUATERNION_COLUMNS: tuple[str, ...] = ("qx", "qy", "qz", "qw")
"""CSV columns of the optional tool orientation, a unit quaternion (scalar last)."""

FRAME_POSE_FIELDS: dict[int, tuple[str, ...]] = {
    2: ("x", "y", "angle"),
    3: ("x", "y", "z", "qx", "qy", "qz", "qw"),
}
"""A task frame's pose in a file, by the demonstrations' dimension: its CSV columns are
``frame_<name>_<field>`` (:attr:`lfdkit.model.demos.Demo.frames` holds the same numbers)."""

JSON_FORMAT = "lfdkit-demos"
"""Value of the ``"format"`` field of a demonstrations JSON file."""

JSON_VERSION = 1
"""Newest JSON file-format version this module reads and the one it writes."""

MAX_NPZ_MEMBERS = 10_000
"""Most arrays accepted in an ``.npz`` demonstrations file."""

MAX_NPZ_ARRAY_BYTES = 1024**3
"""Largest array read from an ``.npz`` file, in bytes once decompressed (1 GiB).

Checked from the archive's header before anything is decompressed; members
that are not demonstrations, times or ids are never decompressed."""

_INDEXED_COORD = re.compile(r"x([1-9][0-9]*)")
_NPZ_DEMO = re.compile(r"demo_(0|[1-9][0-9]*)")
_NPZ_TIME = re.compile(r"time_(0|[1-9][0-9]*)")
_NPZ_QUAT = re.compile(r"quat_(0|[1-9][0-9]*)")
# What a reader gives: points, times, ids, orientations and task frames per demonstration.
_Read = tuple[
    list[np.ndarray],
    list[np.ndarray | None],
    list[DemoId],
    list[np.ndarray | None],
    list[dict[str, np.ndarray] | None],
]
# A task frame's name: it names CSV columns frame_<name>_<field>.
_FRAME_NAME = r"[A-Za-z0-9][A-Za-z0-9_-]*"
_FRAME_COLUMN = re.compile(rf"frame_({_FRAME_NAME})_(x|y|z|angle|qx|qy|qz|qw)", re.I)


# --------------------------------------------------------------------------- #
# Public load / save
# --------------------------------------------------------------------------- #


@overload
def load_demos(
    path: PathLike, *, return_times: Literal[False] = ..., return_ids: Literal[False] = ...
) -> list[np.ndarray]: ...


@overload
def load_demos(
    path: PathLike, *, return_times: Literal[True], return_ids: Literal[False] = ...
) -> tuple[list[np.ndarray], list[np.ndarray | None]]: ...


@overload
def load_demos(
    path: PathLike, *, return_times: Literal[False] = ..., return_ids: Literal[True]
) -> tuple[list[np.ndarray], list[DemoId]]: ...


@overload
def load_demos(
    path: PathLike, *, return_times: Literal[True], return_ids: Literal[True]
) -> tuple[list[np.ndarray], list[np.ndarray | None], list[DemoId]]: ...


@overload
def load_demos(
    path: PathLike,
    *,
    return_times: bool = ...,
    return_ids: bool = ...,
    return_orientations: Literal[True],
) -> tuple[Any, ...]: ...


@overload
def load_demos(path: PathLike, *, as_records: Literal[True]) -> list[Demo]: ...


def load_demos(
    path: PathLike,
    *,
    return_times: bool = False,
    return_ids: bool = False,
    return_orientations: bool = False,
    as_records: bool = False,
) -> Any:
    """Read a demonstration set from a ``.csv``, ``.npz`` or ``.json`` file.

    See the module docstring for the layout of each format.

    Parameters
    ----------
    path : str or os.PathLike
        File to read; its suffix selects the format.
    return_times : bool
        Also return the per-demonstration sample times.
    return_ids : bool
        Also return the demonstration ids. CSV and NPZ store ids as text; an
        id that is the canonical spelling of an integer (``"7"``, ``"-2"``,
        not ``"07"``) is returned as ``int``, others as ``str``. Files without
        ids give ``0, 1, ..., n_demos - 1``.
    return_orientations : bool
        Also return the tool orientations (CSV columns ``qx, qy, qz, qw``).
    as_records : bool
        Return one :class:`~lfdkit.model.demos.Demo` record per demonstration
        instead (points, times, orientations, id and task frames together;
        the task frames are read only so).

    Returns
    -------
    demos : list of ndarray, each shape (n_points_j, n_dims)
        The demonstrations, float64, in file order.
    times : list of (ndarray, shape (n_points_j,), or None)
        Only if ``return_times``: sample times in seconds, ``None`` for a
        demonstration stored without times.
    ids : list of int or str
        Only if ``return_ids``: one id per demonstration.
    orientations : list of (ndarray, shape (n_points_j, 4), or None)
        Only if ``return_orientations``: unit quaternions ``[x, y, z, w]``
        (normalised; a row whose norm is off 1 by more than
        :data:`lfdkit.core.rotations.UNIT_NORM_TOLERANCE` is an error), ``None``
        for a demonstration stored without them.

    Raises
    ------
    ValueError
        If the suffix is not supported, the content is malformed or would be
        read ambiguously (see the module notes), or the file is over a size
        limit; the message names the file and, where it applies, the line,
        column, JSON path or array at fault.
    TypeError
        If a JSON value has the wrong type (e.g. a number given as a string).
    FileNotFoundError
        If the file does not exist.
    IsADirectoryError, NotRegularFileError
        If ``path`` is a directory, or a FIFO, device or socket (never opened).
    """
    if as_records and (return_times or return_ids or return_orientations):
        raise ValueError(
            "as_records: the records hold the times, ids and orientations; "
            "leave the return_* flags out"
        )
    fname = os.fspath(path)
    fmt = format_of(fname, SUPPORTED_SUFFIXES)
    quats: list[np.ndarray | None]
    if fmt == ".csv":
        demos, times, ids, quats, frames = _read_csv(fname)
    elif fmt == ".npz":
        demos, times, ids, quats, frames = _read_npz(fname)
    else:
        demos, times, ids, quats, frames = _read_json(fname)
    if as_records:
        return [
            Demo(points, t, quat, did, None, frame)
            for points, t, quat, did, frame in zip(demos, times, quats, ids, frames, strict=True)
        ]
    out: list[Any] = [demos]
    if return_times:
        out.append(times)
    if return_ids:
        out.append(ids)
    if return_orientations:
        out.append(quats)
    return demos if len(out) == 1 else tuple(out)


def load_demo_files(paths: Sequence[PathLike]) -> list[Demo]:
    """Read several demonstration files as one set of :class:`~lfdkit.model.demos.Demo` records.

    Each file as :func:`load_demos` reads it, in the order given; a CSV
    without a ``demo`` column is one demonstration with its file's stem as
    its id. One path is exactly :func:`load_demos` (its ids kept).

    Returns
    -------
    list of Demo
        As :func:`load_demos` with ``as_records=True``: points, times,
        orientations, id and task frames of each demonstration (no scenes).

    Raises
    ------
    ValueError
        For no path, a file given twice, :func:`load_demos`' errors, an id in two files, or
        files that differ in dimension, in having times or orientations, or in
        their task frames; the message names both files.
    """
    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    if not len(paths):
        raise ValueError("demos: no file given; give one or more demonstration files")
    keep_ids = len(paths) == 1
    records: list[Demo] = []
    first: dict[str, tuple[str, Any]] = {}  # property -> (first file, its value)
    owner: dict[str, str] = {}  # id as text -> its file
    named = [os.path.realpath(os.fspath(p)) for p in paths]
    for j, real in enumerate(named):
        if real in named[:j]:
            raise ValueError(
                f"{os.fspath(paths[j])}: given twice; give each demonstration file once"
            )
    for path in paths:
        fname = os.fspath(path)
        read = load_demos(path, as_records=True)
        if not keep_ids and format_of(fname, SUPPORTED_SUFFIXES) == ".csv" and not _has_demo(fname):
            read = [dataclasses.replace(read[0], id=_stem_id(fname))]
        head = read[0]
        facts = {  # what every file must share: said as "has ..."
            "dimension": f"{head.points.shape[1]}-D demonstrations",
            "times": "times (a t column)" if head.times is not None else "no times",
            "orientations": (
                "orientations (qx,qy,qz,qw)" if head.orientations is not None else "no orientations"
            ),
            "task frames": (
                f"task frames {', '.join(head.frames)}" if head.frames else "no task frames"
            ),
        }
        for name, value in facts.items():
            seen = first.setdefault(name, (fname, value))
            if seen[1] != value:
                raise ValueError(
                    f"{fname}: has {value}, but {seen[0]} has {seen[1]}; all demonstration "
                    f"files must agree on their {name}"
                )
        for did in (demo.id for demo in read):
            other = owner.setdefault(str(did), fname)
            if other != fname:
                raise ValueError(
                    f"{fname}: demo id {did!r} is also in {other}; give each demonstration "
                    "its own id (a CSV without a demo column is named by its file)"
                )
        records += read
    return records


def _has_demo(fname: str) -> bool:
    """Whether a CSV file has a ``demo`` column."""
    _, header, _ = csv_header(fname)
    return "demo" in (h.strip().lower() for h in header)


def _stem_id(fname: str) -> DemoId:
    """The id of a one-demonstration CSV among several files: its stem."""
    did = parse_id(Path(fname).stem)
    check_file_id(did, f"{fname}: its name as a demo id")
    return did


def save_demos(
    path: PathLike,
    demos: Sequence[Any],
    *,
    times: Sequence[Any | None] | None = None,
    ids: Sequence[DemoId] | None = None,
    orientations: Sequence[Any | None] | None = None,
    frames: Sequence[Mapping[str, Any] | None] | None = None,
    overwrite: bool = False,
) -> Path:
    """Write a demonstration set to a ``.csv``, ``.npz`` or ``.json`` file.

    The write is atomic (:func:`lfdkit.io.atomic.write_text`; NPZ
    :func:`atomic_write`) and exact: :func:`load_demos`
    gives back bit-identical float64 arrays.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; its suffix selects the format.
    demos : sequence of array_like, each shape (n_points_j, n_dims), or of Demo
        The demonstrations; all share ``n_dims`` and have at least 2 points.
        As :class:`~lfdkit.model.demos.Demo` records, with their times,
        orientations and ids (then those are not given; scenes are not
        written: :func:`lfdkit.io.save_scenes` writes them).
    times : sequence of (array_like, shape (n_points_j,), or None), optional
        Sample times in seconds, finite and strictly increasing within each
        demonstration. ``None`` entries mean "no times" for that
        demonstration; CSV needs times for all demonstrations or none. A 2-D
        array of shape ``(n_demos, n_points)`` is accepted too.
    ids : sequence of int or str, optional
        Demonstration ids, unique (also once written as text: ``7`` and
        ``"7"`` clash). A ``str`` id must be non-empty, without surrounding
        whitespace or line breaks, and must not start with ``#``. Defaults to
        ``0, 1, ..., n_demos - 1``.
    orientations : sequence of (array_like, shape (n_points_j, 4), or None), optional
        Tool orientations as unit quaternions ``[x, y, z, w]``, one per
        sample: CSV columns ``qx, qy, qz, qw`` (for all demonstrations or
        none), NPZ arrays ``quat_j``, JSON fields ``"q"``. Each row is
        normalised; NaN/inf or a norm off 1 by more than
        :data:`lfdkit.core.rotations.UNIT_NORM_TOLERANCE` is refused.
    frames : sequence of (mapping of str to array_like, or None), optional
        The task frames' poses per demonstration, by name
        (:attr:`lfdkit.model.demos.Demo.frames`: 2-D ``[x, y, angle]``, 3-D
        ``[x, y, z, qx, qy, qz, qw]``): the same names in the same order for
        every demonstration, or None for all. CSV columns
        ``frame_<name>_<field>`` (:data:`FRAME_POSE_FIELDS`), JSON fields
        ``"frames"``; an NPZ file holds none (refused).
    overwrite : bool
        Replace an existing file. When false an existing file raises
        ``FileExistsError``.

    Returns
    -------
    pathlib.Path
        The file written, which :func:`load_demos` reads back.

    Raises
    ------
    ValueError
        If the suffix is unsupported or the inputs are invalid.
    OutputExistsError, IsADirectoryError, NotRegularFileError
        As :func:`atomic_write`: the file exists and ``overwrite`` is false
        (an ``OutputExistsError`` is a ``FileExistsError``), ``path`` is a
        directory, or a FIFO, device, socket or symbolic link.
    """
    separate = {"times": times, "ids": ids, "orientations": orientations, "frames": frames}
    fields = demo_fields(demos, "demos", given=separate)
    if fields is not None:
        demos, times, orientations = fields.points, fields.times, fields.orientations
        ids = None if all(key is None for key in fields.ids) else fields.ids
        frames = None if all(f is None for f in fields.frames) else fields.frames
    fname = os.fspath(path)
    fmt = format_of(fname, SUPPORTED_SUFFIXES)
    arrs = check_demos(demos, "demos")
    n = len(arrs)
    time_arrs = check_times_list(times, arrs)
    id_list = check_ids(ids, n)
    quats = _check_orientations(orientations, arrs, fmt)
    poses = _check_frames(frames, arrs, fmt)

    check_output_path(fname, overwrite=overwrite)

    if fmt == ".csv":
        if any(t is None for t in time_arrs) and any(t is not None for t in time_arrs):
            raise ValueError(
                f"{fname}: a CSV file stores times for all demonstrations or none; "
                "times has None for some demonstrations only"
            )

        text = _csv_text(arrs, time_arrs, id_list, quats, poses)
        return write_text(fname, text, overwrite=overwrite)
    if fmt == ".npz":
        arrays: dict[str, np.ndarray] = {}
        for j, (a, t) in enumerate(zip(arrs, time_arrs, strict=True)):
            arrays[f"demo_{j}"] = a
            if t is not None:
                arrays[f"time_{j}"] = t
            if quats is not None and quats[j] is not None:
                arrays[f"quat_{j}"] = quats[j]
        if ids is not None:
            arrays["ids"] = np.array([str(i) for i in id_list], dtype=np.str_)

        def write_npz(f: IO[Any]) -> None:
            np.savez_compressed(f, **arrays)  # float/str arrays only: no pickling

        return atomic_write(fname, write_npz, binary=True, overwrite=overwrite)

    text = _json_text(arrs, time_arrs, id_list, quats, poses)
    return write_text(fname, text, overwrite=overwrite)


def path_csv(
    points: Any, *, times: Any = None, velocities: Any = None, orientations: Any = None
) -> str:
    """One path as CSV text: a header ``[t,]x,y[,z][,qx,qy,qz,qw][,vx,vy[,vz]]``, one row a point.

    Parameters
    ----------
    points : array_like, shape (n, q)
        Positions (``x1,...,xq`` in the header beyond 3 dimensions).
    times : array_like, shape (n,), optional
        Seconds, finite and non-decreasing: a first column ``t``.
    velocities : array_like, shape (n, q), optional
        Units per second: last columns ``vx,vy[,vz]`` (``v1,...,vq`` beyond 3).
    orientations : array_like, shape (n, 4), optional
        Tool orientations, unit quaternions ``[x, y, z, w]``: columns
        ``qx,qy,qz,qw`` after the positions (as a demonstrations file has them).

    Returns
    -------
    str
        Floats written exactly (``repr``), so parsing the text gives back the
        same arrays.
    """
    arr = check_path(points, "points", min_points=1)
    n, q = arr.shape
    header = _coord_header(q)
    columns = [arr]
    if times is not None:
        t = check_times(times, n, "times", of="points", increasing=False, style="shape")
        if np.any(np.diff(t) < 0):
            raise ValueError("times: must not decrease")
        header = ["t", *header]
        columns.insert(0, t[:, None])
    if orientations is not None:
        header += list(QUATERNION_COLUMNS)
        columns.append(check_quaternions(orientations, "orientations", n=n))
    if velocities is not None:
        v = check_path(velocities, "velocities", min_points=1, n_dims=q)
        if v.shape[0] != n:
            raise ValueError(
                f"velocities: expected shape ({n}, {q}) to match points, got {v.shape}"
            )
        header += ["v" + c if q <= 3 else f"v{k}" for k, c in enumerate(_coord_header(q), 1)]
        columns.append(v)
    table = np.hstack(columns)
    rows = "".join(",".join(repr(float(v)) for v in row) + "\n" for row in table)
    return ",".join(header) + "\n" + rows


def save_path(
    path: PathLike,
    points: Any,
    *,
    times: Any = None,
    velocities: Any = None,
    orientations: Any = None,
    overwrite: bool = False,
) -> Path:
    """Write one path (e.g. a plan) as :func:`path_csv` text, atomically (:func:`write_text`).

    ``times`` (n,) s and ``velocities`` (n, q) units/s add the columns ``t``
    and ``vx,vy[,vz]``, ``orientations`` (n, 4) the columns ``qx,qy,qz,qw``;
    an existing file is replaced only with ``overwrite``.
    """
    text = path_csv(points, times=times, velocities=velocities, orientations=orientations)
    return write_text(path, text, overwrite=overwrite)


# --------------------------------------------------------------------------- #
# Shared helpers
# --------------------------------------------------------------------------- #


def _check_same_dims(arrs: list[np.ndarray], names: list[str], fname: str) -> None:
    q = arrs[0].shape[1]
    for a, name in zip(arrs[1:], names[1:], strict=True):
        if a.shape[1] != q:
            raise ValueError(
                f"{fname}: {name} has {a.shape[1]} dimensions but {names[0]} has {q}; "
                "all demonstrations in a file must have the same number of dimensions"
            )


# --------------------------------------------------------------------------- #
# CSV
# --------------------------------------------------------------------------- #


def _coord_header(q: int) -> list[str]:
    return ["x", "y", "z"][:q] if q <= 3 else [f"x{k}" for k in range(1, q + 1)]


def _csv_text(
    demos: list[np.ndarray],
    times: list[np.ndarray | None],
    ids: list[DemoId],
    quats: list[np.ndarray | None] | None = None,
    frames: list[dict[str, np.ndarray]] | None = None,
) -> str:
    f = io.StringIO()
    q = demos[0].shape[1]
    has_t = times[0] is not None
    w = csv.writer(f, lineterminator="\n")
    extra = list(QUATERNION_COLUMNS) if quats is not None else []
    if frames is not None:
        extra += [f"frame_{name}_{field}" for name in frames[0] for field in FRAME_POSE_FIELDS[q]]
    w.writerow(["demo", *(["t"] if has_t else []), *_coord_header(q), *extra])
    for j, (a, t, i) in enumerate(zip(demos, times, ids, strict=True)):
        sid = str(i)
        tl = t.tolist() if t is not None else None
        ql = quats[j].tolist() if quats is not None and quats[j] is not None else None
        poses = [repr(v) for pose in frames[j].values() for v in pose.tolist()] if frames else []
        for k, row in enumerate(a.tolist()):
            # repr() of a Python float is the shortest string that reads back exactly.
            w.writerow(
                [
                    sid,
                    *([repr(tl[k])] if tl is not None else []),
                    *map(repr, row),
                    *(map(repr, ql[k]) if ql is not None else []),
                    *poses,
                ]
            )
    return f.getvalue()


def _check_orientations(
    orientations: Sequence[Any | None] | None, demos: list[np.ndarray], fmt: str
) -> list[np.ndarray | None] | None:
    """Unit quaternions per demonstration (normalised) or None; CSV needs all or none."""
    if orientations is None:
        return None
    if len(orientations) != len(demos):
        raise ValueError(
            f"orientations: expected one (n_points_j, 4) array or None for each of the "
            f"{len(demos)} demonstrations, got {len(orientations)}"
        )
    given = [o is not None for o in orientations]
    if not any(given):
        return None
    if fmt == ".csv" and not all(given):
        raise ValueError(
            "orientations: a CSV file stores orientations for all demonstrations or none; "
            "orientations has None for some demonstrations only"
        )
    return [
        None if o is None else check_quaternions(o, f"orientations[{j}]", n=len(d))
        for j, (o, d) in enumerate(zip(orientations, demos, strict=True))
    ]


def _check_frames(
    frames: Sequence[Mapping[str, Any] | None] | None, demos: list[np.ndarray], fmt: str
) -> list[dict[str, np.ndarray]] | None:
    """The task frames' poses per demonstration (:data:`FRAME_POSE_FIELDS`), checked; or None."""
    if frames is None or all(f is None for f in frames):
        return None
    if isinstance(frames, Mapping) or len(frames) != len(demos):
        got = "one mapping" if isinstance(frames, Mapping) else f"{len(frames)}"
        raise ValueError(
            f"frames: expected one mapping of named poses for each of the {len(demos)} "
            f"demonstrations, got {got}"
        )
    if fmt == ".npz":
        raise ValueError(
            "frames: an .npz demonstrations file holds no task frames; save as .csv or .json"
        )
    q = demos[0].shape[1]
    if q not in FRAME_POSE_FIELDS:
        raise ValueError(f"frames: task frames need 2-D or 3-D demonstrations, these are {q}-D")
    fields = FRAME_POSE_FIELDS[q]
    out: list[dict[str, np.ndarray]] = []
    for j, given in enumerate(frames):
        if not isinstance(given, Mapping) or not given:
            raise ValueError(
                f"frames[{j}]: expected a mapping of frame names to poses, got {given!r}; give "
                "every demonstration the same task frames (or none)"
            )
        poses: dict[str, list[float]] = {}
        for name, pose in given.items():
            _check_frame_name(name, f"frames[{j}]")
            try:
                arr = np.asarray(pose, dtype=np.float64)
            except (TypeError, ValueError):
                raise TypeError(f"frames[{j}][{name!r}]: expected {len(fields)} numbers") from None
            if arr.shape != (len(fields),):
                raise ValueError(
                    f"frames[{j}][{name!r}]: expected the {len(fields)} numbers "
                    f"[{', '.join(fields)}] of a {q}-D pose, got shape {arr.shape}"
                )
            if not np.all(np.isfinite(arr)):
                raise ValueError(f"frames[{j}][{name!r}]: contains NaN or an infinite value")
            poses[name] = arr.tolist()
        out.append(_frame_poses("frames", q, poses, f"demos[{j}]"))
    _same_frames("frames", out, [f"demos[{j}]" for j in range(len(out))])
    return out


def _csv_columns(
    fname: str, header: list[str]
) -> tuple[int | None, int | None, list[int], list[str]]:
    """Locate the demo (None: absent), time and coordinate columns; their indices and names."""
    names = [h.strip() for h in header]
    found = ", ".join(repr(n) for n in names)
    keys = [n.lower() for n in names]
    for k, key in enumerate(keys):
        if not key:
            raise ValueError(f"{fname}: header column {k + 1} has no name; found columns: {found}")
        if keys.index(key) != k:
            raise ValueError(f"{fname}: duplicate column {names[k]!r}; found columns: {found}")
    pos = {key: k for k, key in enumerate(keys)}

    # No demo column: the whole file is one demonstration (a recorder's take).
    if "t" in pos and "time" in pos:
        raise ValueError(
            f"{fname}: both 't' and 'time' columns present; keep one; found columns: {found}"
        )
    t_col = pos.get("t", pos.get("time"))

    xyz = [c for c in ("x", "y", "z") if c in pos]
    indexed = sorted((int(m.group(1)), key) for key in keys if (m := _INDEXED_COORD.fullmatch(key)))
    if xyz and indexed:
        raise ValueError(
            f"{fname}: mixes coordinate naming 'x, y, z' with 'x1, x2, ...'; "
            f"use one; found columns: {found}"
        )
    if indexed:
        want = [f"x{k}" for k in range(1, max(2, indexed[-1][0]) + 1)]
    else:
        want = ["x", "y", "z"] if "z" in pos else ["x", "y"]
    for c in want:
        if c not in pos:
            raise ValueError(
                f"{fname}: missing column {c!r}; found columns: {found}{header_hint(names)}"
            )
    coord_cols = [pos[c] for c in want]
    return pos.get("demo"), t_col, coord_cols, [names[k] for k in coord_cols]


def _quaternion_columns(fname: str, header: list[str]) -> list[int] | None:
    """Indices of the qx, qy, qz, qw columns: all four or none."""
    keys = [h.strip().lower() for h in header]
    present = [c for c in QUATERNION_COLUMNS if c in keys]
    if not present:
        return None
    if len(present) != 4:
        missing = ", ".join(c for c in QUATERNION_COLUMNS if c not in keys)
        raise ValueError(
            f"{fname}: orientation columns need all of qx, qy, qz, qw; missing {missing}"
        )
    return [keys.index(c) for c in QUATERNION_COLUMNS]


def _frame_columns(fname: str, header: list[str], q: int) -> dict[str, list[int]]:
    """Each task frame's pose columns (:data:`FRAME_POSE_FIELDS` order), by name; {} if none."""
    names = [h.strip() for h in header]
    found: dict[str, dict[str, int]] = {}
    for k, name in enumerate(names):
        if (m := _FRAME_COLUMN.fullmatch(name)) is not None:
            found.setdefault(m.group(1), {})[m.group(2).lower()] = k
    if not found:
        return {}
    if q not in FRAME_POSE_FIELDS:
        raise ValueError(
            f"{fname}: task frame columns (frame_{next(iter(found))}_...) need 2-D or 3-D "
            f"demonstrations, these are {q}-D"
        )
    fields = FRAME_POSE_FIELDS[q]
    columns: dict[str, list[int]] = {}
    for frame, have in found.items():
        missing = [f"frame_{frame}_{f}" for f in fields if f not in have]
        extra = [names[have[f]] for f in have if f not in fields]
        if missing or extra:
            wrong = f"missing {', '.join(missing)}" if missing else f"has {', '.join(extra)}"
            raise ValueError(
                f"{fname}: task frame {frame!r} {wrong}; a {q}-D frame's pose is "
                f"frame_{frame}_{{{','.join(fields)}}}"
            )
        columns[frame] = [have[f] for f in fields]
    return columns


def _frame_poses(fname: str, q: int, poses: dict[str, list[float]], where: str) -> dict[str, Any]:
    """One demonstration's frame poses, checked (a 3-D frame's quaternion normalised)."""
    out: dict[str, np.ndarray] = {}
    for frame, pose in poses.items():
        arr = np.asarray(pose, dtype=np.float64)
        if q == 3:
            try:
                arr[3:] = check_quaternions(arr[3:], "q")[0]
            except ValueError as exc:
                why = str(exc).removeprefix("q: row 0 ")
                raise ValueError(
                    f"{fname}: {where}, task frame {frame!r}: the orientation {why}"
                ) from None
        arr.setflags(write=False)
        out[frame] = arr
    return out


def _read_csv(
    fname: str,
) -> _Read:
    _, header, lines = csv_header(fname)
    demo_col, t_col, coord_cols, coord_names = _csv_columns(fname, header)
    q_cols = _quaternion_columns(fname, header)
    frame_cols = _frame_columns(fname, header, len(coord_cols))
    colnames = [h.strip() for h in header]
    t_name = colnames[t_col] if t_col is not None else ""

    groups: dict[str, tuple[list[list[float]], list[float], list[int]]] = {}
    quats: dict[str, list[list[float]]] = {}
    frames: dict[str, dict[str, tuple[list[float], int]]] = {}
    blocks = Blocks(fname, colnames[demo_col]) if demo_col is not None else None
    for lineno, row in csv_rows(fname, lines, colnames):
        did = blocks.id_of(row[demo_col], lineno) if blocks is not None else "0"
        row = [c.strip() for c in row]
        pts, ts, linenos = groups.setdefault(did, ([], [], []))
        pts.append(
            [
                csv_number(fname, lineno, nm, row[c])
                for c, nm in zip(coord_cols, coord_names, strict=True)
            ]
        )
        if q_cols is not None:
            quats.setdefault(did, []).append(
                [csv_number(fname, lineno, colnames[c], row[c]) for c in q_cols]
            )
        for frame, cols in frame_cols.items():
            pose = [csv_number(fname, lineno, colnames[c], row[c]) for c in cols]
            first, first_line = frames.setdefault(did, {}).setdefault(frame, (pose, lineno))
            for c, value, before in zip(cols, pose, first, strict=True):
                if value != before:
                    raise ValueError(
                        f"{fname} line {lineno}, column {colnames[c]!r}: task frame {frame!r} "
                        f"moves within demo {did!r} ({value!r} here, {before!r} on line "
                        f"{first_line}); a task frame is one pose per demonstration: give the "
                        "pose the object had on every row"
                    )
        if t_col is not None:
            t = csv_number(fname, lineno, t_name, row[t_col])
            if ts and t <= ts[-1]:
                raise ValueError(
                    f"{fname} line {lineno}, column {t_name!r}: time {t!r} in demo {did!r} "
                    f"is not after the previous time {ts[-1]!r} (line {linenos[-1]}); "
                    "times must be strictly increasing within a demonstration"
                )
            ts.append(t)
        linenos.append(lineno)

    if not groups:
        raise ValueError(f"{fname}: no data rows after the header")
    for did, (pts, _, _) in groups.items():
        if len(pts) < 2:
            what = f"demo {did!r}" if demo_col is not None else "the demonstration (no demo column)"
            raise ValueError(
                f"{fname}: {what} has {len(pts)} row; each demonstration needs at least 2"
            )
    demos = check_demos([g[0] for g in groups.values()], fname)
    times: list[np.ndarray | None] = [
        np.asarray(g[1], dtype=np.float64) if t_col is not None else None for g in groups.values()
    ]
    orientations: list[np.ndarray | None] = [None] * len(groups)
    if q_cols is not None:
        orientations = []
        for did, (_, _, linenos) in groups.items():
            try:
                orientations.append(check_quaternions(quats[did], "q"))
            except ValueError as exc:  # "q: row k ...": name the file's line instead
                row, _, why = str(exc).removeprefix("q: row ").partition(" ")
                raise ValueError(
                    f"{fname} line {linenos[int(row)]}, columns qx, qy, qz, qw: "
                    f"the orientation of demo {did!r} {why}"
                ) from None
    q = len(coord_cols)
    poses: list[dict[str, np.ndarray] | None] = [
        _frame_poses(fname, q, {f: p for f, (p, _) in frames[did].items()}, f"demo {did!r}")
        if frame_cols
        else None
        for did in groups
    ]
    return demos, times, [parse_id(d) for d in groups], orientations, poses


# --------------------------------------------------------------------------- #
# NPZ
# --------------------------------------------------------------------------- #


_DTYPE_WORDS = {
    "b": "booleans",
    "c": "complex numbers",
    "m": "time intervals",
    "M": "dates",
    "O": "Python objects, which lfdkit never unpickles",
    "S": "bytes",
    "U": "text",
    "V": "raw or structured records",
}


class _NpzArchive:
    """The arrays of an ``.npz`` file, decompressed one at a time and only on request.

    ``np.load`` would decompress any member it is asked for without a size
    check; here the zip directory's sizes and each array's ``.npy`` header are
    checked first, so a small archive cannot expand into gigabytes.
    """

    def __init__(self, fname: str) -> None:
        self.fname = fname
        check_input_file(fname)
        with open(fname, "rb") as f:
            if f.read(6) == b"\x93NUMPY":
                raise ValueError(f"{fname}: is a single .npy array, not an .npz archive")
        try:
            self.zip = zipfile.ZipFile(fname)
            infos = self.zip.infolist()
        except (
            zipfile.BadZipFile,
            zipfile.LargeZipFile,
            OSError,
            EOFError,
            ValueError,
            NotImplementedError,  # zipfile's "zip file version 10.9", a feature it lacks
        ) as exc:
            raise ValueError(f"{fname}: could not read as an .npz archive ({exc})") from None
        if len(infos) > MAX_NPZ_MEMBERS:
            self.zip.close()
            raise ValueError(
                f"{fname}: has {len(infos)} arrays; lfdkit reads .npz files of at most "
                f"{MAX_NPZ_MEMBERS}"
            )
        self.members: dict[str, zipfile.ZipInfo] = {}
        for info in infos:
            key = info.filename.removesuffix(".npy")
            if key in self.members:
                self.zip.close()
                raise ValueError(f"{fname}: array {key!r} is stored twice in the archive")
            self.members[key] = info

    def __enter__(self) -> _NpzArchive:
        return self

    def __exit__(self, *exc: object) -> None:
        self.zip.close()

    def read(
        self, key: str, kinds: str = "fiu", *, refused: Callable[[np.dtype], str] | None = None
    ) -> np.ndarray:
        """Read array ``key`` if its dtype kind is one of ``kinds`` (read-only array).

        ``refused(dtype)``, if given, words the error for another dtype.
        """
        info = self.members[key]
        where = f"{self.fname}: array {key!r}"
        if info.file_size > MAX_NPZ_ARRAY_BYTES:
            raise ValueError(
                f"{where} is {info.file_size} bytes once decompressed; lfdkit reads arrays of "
                f"at most {MAX_NPZ_ARRAY_BYTES} bytes ({MAX_NPZ_ARRAY_BYTES / 1024**3:g} GiB)"
            )
        if info.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
            raise ValueError(
                f"{where}: compression method {info.compress_type} is not one NumPy writes "
                "(stored or deflate)"
            )
        if info.flag_bits & 0x1:
            raise ValueError(f"{where}: is encrypted")
        try:
            with self.zip.open(info) as fp:
                version = np.lib.format.read_magic(fp)
                if version == (1, 0):
                    shape, fortran, dtype = np.lib.format.read_array_header_1_0(fp)
                elif version == (2, 0):
                    shape, fortran, dtype = np.lib.format.read_array_header_2_0(fp)
                else:
                    raise ValueError(f".npy format version {version} is not supported")
                if dtype.kind not in kinds or dtype.hasobject or dtype.names:
                    if refused is not None:
                        raise _RefusedArray(refused(dtype))
                    raise _RefusedArray(
                        f"{where}: holds {_DTYPE_WORDS.get(dtype.kind, 'values')} (dtype "
                        f"{dtype}); demonstrations and times must be real numbers (float or "
                        "integer arrays)"
                    )
                nbytes = math.prod(shape) * dtype.itemsize
                if nbytes > info.file_size:
                    raise ValueError(
                        f"header says shape {shape} of {dtype} ({nbytes} bytes) but the "
                        f"member holds {info.file_size} bytes"
                    )
                data = fp.read(nbytes)
        except _RefusedArray as exc:
            raise ValueError(str(exc)) from None
        except (
            zipfile.BadZipFile,
            zlib.error,
            OSError,
            EOFError,
            ValueError,
            TypeError,
            NotImplementedError,
            RuntimeError,
        ) as exc:
            raise ValueError(f"{where}: could not read array data ({exc})") from None
        if len(data) != nbytes:
            raise ValueError(f"{where}: could not read array data (truncated)")
        return np.frombuffer(data, dtype=dtype).reshape(shape, order="F" if fortran else "C")


class _RefusedArray(ValueError):
    """An array whose dtype lfdkit does not read."""


def _read_npz(
    fname: str,
) -> _Read:
    with _NpzArchive(fname) as npz:
        demos, times, ids = _read_npz_arrays(fname, npz)
        quat_idx = sorted(int(m.group(1)) for k in npz.members if (m := _NPZ_QUAT.fullmatch(k)))
        stray = [k for k in quat_idx if k >= len(demos)]
        if stray:
            raise ValueError(f"{fname}: array 'quat_{stray[0]}' has no matching 'demo_{stray[0]}'")
        quats: list[np.ndarray | None] = [None] * len(demos)
        for j in quat_idx:
            quats[j] = check_quaternions(
                npz.read(f"quat_{j}"), f"{fname}: array 'quat_{j}'", n=len(demos[j])
            )
    return demos, times, ids, quats, [None] * len(demos)  # NPZ holds no task frames


def _read_npz_arrays(
    fname: str, npz: _NpzArchive
) -> tuple[list[np.ndarray], list[np.ndarray | None], list[DemoId]]:
    data = npz.members  # names only: each array is read when needed
    found = ", ".join(repr(k) for k in sorted(data)) or "(none)"
    demo_idx = sorted(int(m.group(1)) for k in data if (m := _NPZ_DEMO.fullmatch(k)))
    time_idx = sorted(int(m.group(1)) for k in data if (m := _NPZ_TIME.fullmatch(k)))

    if "demos" in data:
        if demo_idx or time_idx:
            raise ValueError(
                f"{fname}: has both a 'demos' array and 'demo_j'/'time_j' arrays; "
                f"use one layout; found arrays: {found}"
            )
        stacked = npz.read("demos")
        if stacked.ndim != 3:
            raise ValueError(
                f"{fname}: array 'demos' must be 3-D, shape (n_demos, n_points, n_dims), "
                f"got shape {stacked.shape}"
            )
        demos = check_demos(stacked, f"{fname}: array 'demos'")
        if "times" in data:
            t2 = npz.read("times")
            if t2.ndim != 2 or t2.shape[0] != len(demos):
                raise ValueError(
                    f"{fname}: array 'times' must have shape (n_demos, n_points) = "
                    f"{stacked.shape[:2]}, got {t2.shape}"
                )
            times: list[np.ndarray | None] = [
                check_times(t2[j], d.shape[0], f"{fname}: array 'times' row {j}")
                for j, d in enumerate(demos)
            ]
        else:
            times = [None] * len(demos)
    else:
        if not demo_idx:
            raise ValueError(
                f"{fname}: no demonstrations; expected arrays 'demo_0', 'demo_1', ... "
                f"or a 3-D array 'demos'; found arrays: {found}"
            )
        for j, k in enumerate(demo_idx):
            if j != k:
                raise ValueError(
                    f"{fname}: missing array 'demo_{j}' (found 'demo_{k}'); "
                    "demonstrations must be numbered 0, 1, 2, ... without gaps"
                )
        stray = [k for k in time_idx if k >= len(demo_idx)]
        if stray:
            raise ValueError(f"{fname}: array 'time_{stray[0]}' has no matching 'demo_{stray[0]}'")
        names = [f"array 'demo_{j}'" for j in demo_idx]
        demos = [
            check_path(npz.read(f"demo_{j}"), f"{fname}: {nm}")
            for j, nm in zip(demo_idx, names, strict=True)
        ]
        _check_same_dims(demos, names, fname)
        demos = check_demos(demos, fname)
        times = [
            check_times(npz.read(f"time_{j}"), d.shape[0], f"{fname}: array 'time_{j}'")
            if f"time_{j}" in data
            else None
            for j, d in enumerate(demos)
        ]

    if "ids" in data:
        ids_rule = (
            f"{fname}: array 'ids' must be 1-D text or integers with one entry per "
            f"demonstration ({len(demos)})"
        )
        raw = npz.read("ids", "Uiu", refused=lambda dtype: f"{ids_rule}, got dtype {dtype}")
        if raw.ndim != 1 or raw.shape[0] != len(demos):
            raise ValueError(f"{ids_rule}, got dtype {raw.dtype} and shape {raw.shape}")
        ids: list[DemoId] = [
            parse_id(str(v)) if raw.dtype.kind == "U" else int(v) for v in raw.tolist()
        ]
        for j, did in enumerate(ids):
            check_file_id(did, f"{fname}: array 'ids' entry {j}")
        if len({str(i) for i in ids}) != len(ids):
            raise ValueError(f"{fname}: array 'ids' has repeated ids")
    else:
        ids = list(range(len(demos)))
    return demos, times, ids


# --------------------------------------------------------------------------- #
# JSON
# --------------------------------------------------------------------------- #


def _json_text(
    demos: list[np.ndarray],
    times: list[np.ndarray | None],
    ids: list[DemoId],
    quats: list[np.ndarray | None] | None = None,
    frames: list[dict[str, np.ndarray]] | None = None,
) -> str:
    # One demonstration per line keeps the file readable and diff-friendly.
    # json writes floats with repr(), so values read back exactly.
    buf = io.StringIO()
    buf.write("{\n")
    buf.write(f'  "format": {json.dumps(JSON_FORMAT)},\n')
    buf.write(f'  "version": {JSON_VERSION},\n')
    buf.write(f'  "n_dims": {demos[0].shape[1]},\n')
    buf.write('  "demos": [\n')
    for j, (a, t, i) in enumerate(zip(demos, times, ids, strict=True)):
        item: dict[str, Any] = {"id": i, "points": a.tolist()}
        if t is not None:
            item["t"] = t.tolist()
        if quats is not None and quats[j] is not None:
            item["q"] = quats[j].tolist()
        if frames is not None:
            q = a.shape[1]
            item["frames"] = {
                name: {"position": pose[:q].tolist(), "angle": float(pose[2])}
                if q == 2
                else {"position": pose[:q].tolist(), "orientation": pose[q:].tolist()}
                for name, pose in frames[j].items()
            }
        sep = "," if j < len(demos) - 1 else ""
        buf.write(f"    {json.dumps(item, allow_nan=False)}{sep}\n")
    buf.write("  ]\n}\n")
    return buf.getvalue()


def _read_json(
    fname: str,
) -> _Read:
    doc = json_document(fname, JSON_FORMAT, JSON_VERSION, "demonstrations")
    q = doc.get("n_dims")
    if isinstance(q, bool) or not isinstance(q, int) or q < 2:
        raise ValueError(f"{fname}: field 'n_dims' must be an integer >= 2, got {q!r}")
    items = doc.get("demos")
    if not isinstance(items, list) or not items:
        raise ValueError(f"{fname}: field 'demos' must be a non-empty list of demonstrations")

    demos: list[np.ndarray] = []
    times: list[np.ndarray | None] = []
    ids: list[DemoId] = []
    quats: list[np.ndarray | None] = []
    frames: list[dict[str, np.ndarray] | None] = []
    seen: dict[str, int] = {}
    for j, item in enumerate(items):
        where = f"{fname}: demos[{j}]"
        if not isinstance(item, dict):
            raise ValueError(f"{where}: expected an object with 'points' (and optional 'id', 't')")
        did = item.get("id", j)
        if isinstance(did, bool) or not isinstance(did, (int, str)):
            raise TypeError(f"{where}: field 'id' must be an int or str, got {did!r}")
        check_file_id(did, f"{where}: field 'id'")
        if str(did) in seen:
            raise ValueError(f"{where}: id {did!r} repeats demos[{seen[str(did)]}]")
        seen[str(did)] = j
        if "points" not in item:
            raise ValueError(f"{where}: missing field 'points'")
        raw_points = json_float_array(item["points"], f"{fname}: demos[{j}].points", 2)
        arr = check_path(raw_points, f"{where} (id {did!r}) field 'points'")
        if arr.shape[1] != q:
            raise ValueError(
                f"{where} (id {did!r}): points have {arr.shape[1]} dimensions but the file "
                f"declares n_dims = {q}; all demonstrations must have n_dims dimensions"
            )
        demos.append(arr)
        times.append(
            check_times(
                json_float_array(item["t"], f"{fname}: demos[{j}].t", 1),
                arr.shape[0],
                f"{where} (id {did!r}) field 't'",
            )
            if item.get("t") is not None
            else None
        )
        quats.append(
            check_quaternions(
                json_float_array(item["q"], f"{fname}: demos[{j}].q", 2),
                f"{where} (id {did!r}) field 'q'",
                n=arr.shape[0],
            )
            if item.get("q") is not None
            else None
        )
        frames.append(_json_frames(fname, item.get("frames"), q, j, did))
        ids.append(did)
    _same_frames(fname, frames, [f"demos[{j}] (id {did!r})" for j, did in enumerate(ids)])
    return check_demos(demos, fname, n_dims=q), times, ids, quats, frames


def _json_frames(
    fname: str, value: Any, q: int, j: int, did: DemoId
) -> dict[str, np.ndarray] | None:
    """``demos[j].frames`` of a JSON file as poses (:data:`FRAME_POSE_FIELDS`), or None."""
    if value is None:
        return None
    where = f"{fname}: demos[{j}] (id {did!r}) field 'frames'"
    if q not in FRAME_POSE_FIELDS:
        raise ValueError(f"{where}: task frames need 2-D or 3-D demonstrations, these are {q}-D")
    turn = "angle" if q == 2 else "orientation"
    if not isinstance(value, dict) or not value:
        raise ValueError(
            f"{where}: expected an object of named frames, e.g. "
            f'{{"pan": {{"position": [...], "{turn}": ...}}}}'
        )
    poses: dict[str, list[float]] = {}
    for name, frame in value.items():
        at = f"{where}[{name!r}]"
        _check_frame_name(name, at)
        if not isinstance(frame, dict) or set(frame) != {"position", turn}:
            got = sorted(frame) if isinstance(frame, dict) else type(frame).__name__
            raise ValueError(f"{at}: expected the keys 'position' and {turn!r}, got {got}")
        position = json_float_array(frame["position"], f"{at}.position", 1)
        if position.shape != (q,):
            raise ValueError(f"{at}.position: expected {q} numbers, got {position.shape[0]}")
        if q == 2:
            angle = frame["angle"]
            if isinstance(angle, bool) or not isinstance(angle, (int, float)):
                raise TypeError(f"{at}.angle: expected a number (rad), got {angle!r}")
            rest = [float(angle)]
        else:
            rest = json_float_array(frame["orientation"], f"{at}.orientation", 1).tolist()
            if len(rest) != 4:
                raise ValueError(f"{at}.orientation: expected [qx, qy, qz, qw], got {len(rest)}")
        pose = [*position.tolist(), *rest]
        if not all(math.isfinite(v) for v in pose):
            raise ValueError(f"{at}: contains NaN or an infinite value")
        poses[name] = pose
    return _frame_poses(fname, q, poses, f"demos[{j}] (id {did!r})")


def is_frame_name(name: Any) -> bool:
    """Whether ``name`` can name a task frame: letters, digits, ``_`` and ``-``, starting
    with a letter or digit (it names the CSV columns ``frame_<name>_x, ...``)."""
    return isinstance(name, str) and re.fullmatch(_FRAME_NAME, name) is not None


def _check_frame_name(name: Any, where: str) -> None:
    """A task frame's name (:func:`is_frame_name`), or a one-line error starting with ``where``."""
    if not is_frame_name(name):
        raise ValueError(
            f"{where}: a task frame's name is letters, digits, '_' and '-', starting with a "
            f"letter or digit (it names CSV columns frame_<name>_x, ...), got {name!r}"
        )


def _same_frames(fname: str, frames: Sequence[Mapping[str, Any] | None], names: list[str]) -> None:
    """Every demonstration has the same task frames, in the same order, or none has any."""
    first = frames[0]
    for frame, name in zip(frames, names, strict=True):
        if (frame is None) != (first is None) or (
            frame is not None and first is not None and list(frame) != list(first)
        ):
            mine = ", ".join(frame) if frame else "none"
            theirs = ", ".join(first) if first else "none"
            raise ValueError(
                f"{fname}: {name} has task frames {mine}, but {names[0]} has {theirs}; every "
                "demonstration needs the same task frames in the same order (or none)"
            )
