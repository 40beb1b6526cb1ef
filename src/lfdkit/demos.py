"""Demonstrations: the data model and file I/O.

A *demonstration set* is a plain ``list`` of float64 arrays, one per
demonstration, each of shape ``(n_points_j, n_dims)``. Lengths may differ
between demonstrations; ``n_dims`` is shared (2 or 3 normally, any ``>= 2``
accepted). Coordinates are in whatever unit the user works in (metres for
robot data); lfdkit never rescales them.

Optionally each demonstration carries its sample times, a float64 array of
shape ``(n_points_j,)`` in seconds, strictly increasing.

Files
-----
The format is chosen from the file suffix (case-insensitive):

``.csv``
    A header row, then one row per sample. Columns: ``demo`` (the
    demonstration id, integer or string, without surrounding spaces),
    optionally ``t`` or ``time`` (seconds), and the coordinates, named
    ``x, y[, z]`` or ``x1, x2, ..., xq``. The rows of one demonstration are
    consecutive, in time order; demonstrations are in file order. Numbers are
    decimal (``-0.5``, ``1e-3``; not ``0_5``, ``nan`` or ``inf``). Blank lines
    and lines starting with ``#`` are ignored. Columns with other names are
    ignored.
``.npz``
    Arrays ``demo_0, demo_1, ...`` (each ``(n_points_j, n_dims)``), optionally
    ``time_j`` for any ``j`` and ``ids`` (1-D, one per demonstration); or a
    single 3-D array ``demos`` of shape ``(n_demos, n_points, n_dims)`` with an
    optional 2-D ``times`` of shape ``(n_demos, n_points)``. Coordinates and
    times are real (float or integer dtype; complex, boolean, date and text
    arrays are refused). Never unpickled; other arrays in the archive are never
    decompressed. (Members of a zip archive cannot be memory-mapped, so each
    array needed is read once, after its size is checked.)
``.json``
    ``{"format": "lfdkit-demos", "version": 1, "n_dims": q, "demos":
    [{"id": ..., "points": [[x, y], ...], "t": [...]}, ...]}`` with ``"t"``
    (and ``"id"``) optional per demonstration.

Writing is atomic (see :func:`atomic_write`) and floats are written so that
a load after a save gives back bit-identical arrays in every format.

Reading is strict: anything that could change the data silently is an error
naming the file and the line, column, JSON path or array (repeated JSON
keys, numbers given as strings, non-real arrays, ``0_5`` in a CSV cell, ids
with spaces, the rows of one id in two places). Files larger than
:data:`MAX_FILE_BYTES`, JSON nested deeper than :data:`MAX_JSON_DEPTH`, and
``.npz`` archives with more than :data:`MAX_NPZ_MEMBERS` arrays or an array
over :data:`MAX_NPZ_ARRAY_BYTES` are refused before they are read, and only
the arrays needed are decompressed. FIFOs, devices and sockets are neither
read nor written.
"""

from __future__ import annotations

import contextlib
import csv
import io
import itertools
import json
import math
import os
import re
import secrets
import stat
import time
import zipfile
import zlib
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import IO, Any, Literal, overload

import numpy as np

from lfdkit._validation import check_demos, check_path, check_times, check_times_list

__all__ = [
    "JSON_FORMAT",
    "JSON_VERSION",
    "MAX_FILE_BYTES",
    "MAX_JSON_DEPTH",
    "MAX_NPZ_ARRAY_BYTES",
    "MAX_NPZ_MEMBERS",
    "STALE_TEMP_SECONDS",
    "SUPPORTED_SUFFIXES",
    "DemoId",
    "NotRegularFileError",
    "OutputExistsError",
    "atomic_write",
    "check_output_path",
    "json_float_array",
    "load_demos",
    "load_json",
    "path_csv",
    "save_demos",
    "save_path",
]

PathLike = str | os.PathLike[str]
"""A file-system path: ``str`` or any ``os.PathLike``."""

DemoId = int | str
"""Identifier of one demonstration in a file: an ``int`` or a non-empty ``str``."""

SUPPORTED_SUFFIXES: tuple[str, ...] = (".csv", ".json", ".npz")
"""File suffixes understood by :func:`load_demos` and :func:`save_demos`."""

JSON_FORMAT = "lfdkit-demos"
"""Value of the ``"format"`` field of a demonstrations JSON file."""

JSON_VERSION = 1
"""Newest JSON file-format version this module reads and the one it writes."""

MAX_FILE_BYTES = 256 * 1024**2
"""Largest demonstrations or scenes file (CSV, JSON or NPZ) read, in bytes (256 MiB).

Far above any recording (a 3-D demonstration sampled at 1 kHz for a minute is
about 4 MB of CSV); it bounds the memory a corrupt or hostile file can take."""

MAX_JSON_DEPTH = 64
"""Deepest nesting of arrays and objects accepted in an lfdkit JSON file.

lfdkit files nest a few levels (a skill file about six)."""

MAX_NPZ_MEMBERS = 10_000
"""Most arrays accepted in an ``.npz`` demonstrations file."""

MAX_NPZ_ARRAY_BYTES = 1024**3
"""Largest array read from an ``.npz`` file, in bytes once decompressed (1 GiB).

Checked from the archive's header before anything is decompressed; members
that are not demonstrations, times or ids are never decompressed."""

_INDEXED_COORD = re.compile(r"x([1-9][0-9]*)")
_NPZ_DEMO = re.compile(r"demo_(0|[1-9][0-9]*)")
_NPZ_TIME = re.compile(r"time_(0|[1-9][0-9]*)")


# --------------------------------------------------------------------------- #
# Atomic writes
# --------------------------------------------------------------------------- #


class OutputExistsError(FileExistsError):
    """The file to write exists and overwriting was not allowed.

    A :class:`FileExistsError`, so existing handlers keep working. The message
    is worded for both audiences (the ``overwrite=True`` argument and a
    command line's ``--force``); :attr:`path` is the file, for a caller that
    words its own message.
    """

    def __init__(self, path: PathLike) -> None:
        self.path = Path(path)
        super().__init__(
            f"{self.path}: file already exists; allow overwriting to replace it "
            "(overwrite=True; --force on the command line)"
        )


class NotRegularFileError(OSError):
    """A path to read or write is a FIFO, device, socket or symbolic link, not a regular file.

    lfdkit reads and writes regular files only: reading a FIFO can block forever
    and replacing a device node or a link destroys something that is not a
    data file. The message names the path and what it is, in one line.
    """


STALE_TEMP_SECONDS = 600.0
"""Age (seconds since last modified) after which :func:`atomic_write` removes a
temporary file it left behind for the same target (a killed process)."""

_TEMP_SUFFIX = ".lfdkit.tmp"
# Temporary files: ".<name>.<12 hex digits>.lfdkit.tmp" (earlier versions wrote
# the same without "lfdkit"); the name is cut so the whole stays under NAME_MAX.
_TEMP_NAME_CHARS = 200
_TEMP_PATTERN = r"[0-9a-f]{12}(?:\.lfdkit)?\.tmp"


def _file_kind(mode: int) -> str:
    """Words for a file type from ``st_mode`` (for messages)."""
    if stat.S_ISDIR(mode):
        return "a directory"
    if stat.S_ISFIFO(mode):
        return "a named pipe (FIFO)"
    if stat.S_ISCHR(mode):
        return "a character device"
    if stat.S_ISBLK(mode):
        return "a block device"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISLNK(mode):
        return "a symbolic link"
    return "not a regular file"


def _check_output_target(target: Path) -> os.stat_result | None:
    """Stat of an existing regular-file target, ``None`` when absent; refuse anything else."""
    try:
        st = os.lstat(target)
    except FileNotFoundError:
        return None
    if stat.S_ISREG(st.st_mode):
        return st
    if stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(f"{target}: is a directory; give the path of a file to write")
    if stat.S_ISLNK(st.st_mode):
        try:
            points_to = os.readlink(target)
        except OSError:  # pragma: no cover - vanished meanwhile
            points_to = "?"
        raise NotRegularFileError(
            f"{target}: is a symbolic link (to '{points_to}'); lfdkit neither writes through "
            "nor replaces links; give the target's own path or remove the link"
        )
    raise NotRegularFileError(
        f"{target}: is {_file_kind(st.st_mode)}, not a regular file; lfdkit writes regular "
        "files only; give another path"
    )


def check_output_path(path: PathLike, *, overwrite: bool) -> os.stat_result | None:
    """Check that :func:`atomic_write` may write ``path``, before any work is done.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.
    overwrite : bool
        Whether an existing regular file may be replaced.

    Returns
    -------
    os.stat_result or None
        The status of the existing regular file, ``None`` if ``path`` is absent.

    Raises
    ------
    OutputExistsError, IsADirectoryError, NotRegularFileError
        As :func:`atomic_write`.
    """
    target = Path(path)
    existing = _check_output_target(target)
    if existing is not None and not overwrite:
        raise _exists_error(target)
    return existing


def _temp_prefix(target: Path) -> str:
    return f".{target.name[:_TEMP_NAME_CHARS]}."


def _remove_stale_temps(target: Path) -> None:
    """Remove this target's temporary files older than :data:`STALE_TEMP_SECONDS`.

    Only regular files named exactly like :func:`atomic_write`'s temporary
    files for ``target`` are touched; errors are ignored (best effort).
    """
    prefix = _temp_prefix(target)
    pattern = re.compile(re.escape(prefix) + _TEMP_PATTERN)
    cutoff = time.time() - STALE_TEMP_SECONDS
    with contextlib.suppress(OSError), os.scandir(target.parent) as entries:
        for entry in entries:
            if not entry.name.startswith(prefix) or not pattern.fullmatch(entry.name):
                continue
            with contextlib.suppress(OSError):
                st = entry.stat(follow_symlinks=False)
                if stat.S_ISREG(st.st_mode) and st.st_mtime < cutoff:
                    os.unlink(entry.path)


def atomic_write(
    path: PathLike,
    writer: Callable[[IO[Any]], object],
    *,
    binary: bool = False,
    overwrite: bool = False,
    encoding: str = "utf-8",
) -> Path:
    """Write a file atomically: readers see the old file or the whole new one.

    ``writer`` is called with a file object open on a temporary file in the
    same directory as ``path``; when it returns, the data are flushed to disk
    and the temporary file is renamed onto ``path``. If ``writer`` raises (or
    the process is interrupted), the temporary file is removed, an existing
    ``path`` is left untouched, and the exception propagates.

    Parameters
    ----------
    path : str or os.PathLike
        Destination file. Its directory must exist.
    writer : callable
        ``writer(f)`` writes the whole content to the file object ``f``
        (its return value is ignored). ``f`` is a binary file when ``binary``
        is true, otherwise a text file with the given ``encoding`` opened with
        ``newline=""``, so line endings are written exactly as given (use
        ``"\\n"``; nothing is translated to the platform's convention).
    binary : bool
        Open the temporary file in binary (``"wb"``) rather than text mode.
    overwrite : bool
        Replace ``path`` if it is an existing regular file. When false, an
        existing ``path`` raises :class:`OutputExistsError`; the check is
        race-free where the file system supports hard links.
    encoding : str
        Text encoding (ignored when ``binary``).

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    OutputExistsError
        (a ``FileExistsError``) If ``path`` exists and ``overwrite`` is false.
    IsADirectoryError
        If ``path`` is a directory.
    NotRegularFileError
        (an ``OSError``) If ``path`` is a FIFO, device, socket or symbolic
        link, whatever ``overwrite`` says.
    FileNotFoundError
        If the directory of ``path`` does not exist.

    Notes
    -----
    Only a missing path or an existing regular file is written: a special
    file (FIFO, device, socket) is never replaced or written through, and
    neither is a symbolic link (whatever it points to), so ``overwrite``
    cannot turn ``/dev/null`` or a link into a regular file.

    A new file gets the usual permissions (``0o666`` less the umask); a
    replaced file keeps its permission bits.

    The temporary file is ``.<name>.<12 hex digits>.lfdkit.tmp`` next to
    ``path``. A process killed mid-write leaves it behind; the next write of
    the same ``path`` removes such files older than :data:`STALE_TEMP_SECONDS`
    (and nothing else).
    """
    target = Path(path)
    parent = target.parent
    if not parent.is_dir():
        raise FileNotFoundError(f"{target}: directory '{parent}' does not exist")
    existing = check_output_path(target, overwrite=overwrite)
    mode = stat.S_IMODE(existing.st_mode) if existing is not None else None
    _remove_stale_temps(target)

    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    while True:
        tmp = parent / f"{_temp_prefix(target)}{secrets.token_hex(6)}{_TEMP_SUFFIX}"
        try:
            fd = os.open(tmp, flags, 0o666)
            break
        except FileExistsError:  # pragma: no cover - 48 random bits collided
            continue
    try:
        try:
            f: IO[Any] = (
                os.fdopen(fd, "wb") if binary else os.fdopen(fd, "w", encoding=encoding, newline="")
            )
        except BaseException:
            os.close(fd)
            raise
        with f:
            writer(f)
            f.flush()
            os.fsync(f.fileno())
        if mode is not None:
            os.chmod(tmp, mode)
        if overwrite:
            # The target may have changed since the check; look again just before
            # the rename so that a FIFO or link put there meanwhile is not replaced.
            _check_output_target(target)
            os.replace(tmp, target)
        else:
            _rename_no_clobber(tmp, target)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise
    _fsync_dir(parent)
    return target


def _exists_error(target: Path) -> OutputExistsError:
    return OutputExistsError(target)


def _rename_no_clobber(tmp: Path, target: Path) -> None:
    """Move ``tmp`` to ``target``, failing if ``target`` exists."""
    try:
        os.link(tmp, target)  # atomic "create only if absent"
    except FileExistsError:
        raise _exists_error(target) from None
    except OSError:
        # Hard links unsupported here (e.g. FAT, some network file systems):
        # fall back to check-then-rename, which has a small race window.
        if os.path.lexists(target):
            raise _exists_error(target) from None
        os.replace(tmp, target)
    else:
        os.unlink(tmp)


def _fsync_dir(directory: Path) -> None:
    """Best-effort fsync of a directory so a rename survives a crash (POSIX)."""
    if os.name != "posix":  # pragma: no cover
        return
    with contextlib.suppress(OSError):
        fd = os.open(directory, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


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


def load_demos(path: PathLike, *, return_times: bool = False, return_ids: bool = False) -> Any:
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

    Returns
    -------
    demos : list of ndarray, each shape (n_points_j, n_dims)
        The demonstrations, float64, in file order.
    times : list of (ndarray, shape (n_points_j,), or None)
        Only if ``return_times``: sample times in seconds, ``None`` for a
        demonstration stored without times.
    ids : list of int or str
        Only if ``return_ids``: one id per demonstration.

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
    fname = os.fspath(path)
    fmt = _format_of(fname)
    if fmt == ".csv":
        demos, times, ids = _read_csv(fname)
    elif fmt == ".npz":
        demos, times, ids = _read_npz(fname)
    else:
        demos, times, ids = _read_json(fname)
    out: list[Any] = [demos]
    if return_times:
        out.append(times)
    if return_ids:
        out.append(ids)
    return demos if len(out) == 1 else tuple(out)


def save_demos(
    path: PathLike,
    demos: Sequence[Any],
    *,
    times: Sequence[Any | None] | None = None,
    ids: Sequence[DemoId] | None = None,
    overwrite: bool = False,
) -> Path:
    """Write a demonstration set to a ``.csv``, ``.npz`` or ``.json`` file.

    The write is atomic (:func:`atomic_write`) and exact: :func:`load_demos`
    gives back bit-identical float64 arrays.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; its suffix selects the format.
    demos : sequence of array_like, each shape (n_points_j, n_dims)
        The demonstrations; all share ``n_dims`` and have at least 2 points.
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
    overwrite : bool
        Replace an existing file. When false an existing file raises
        ``FileExistsError``.

    Returns
    -------
    pathlib.Path
        The path written.

    Raises
    ------
    ValueError
        If the suffix is unsupported or the inputs are invalid.
    OutputExistsError
        (a ``FileExistsError``) If the file exists and ``overwrite`` is false.
    IsADirectoryError
        If ``path`` is a directory.
    NotRegularFileError
        If ``path`` is a FIFO, device, socket or symbolic link
        (:func:`atomic_write`).
    """
    fname = os.fspath(path)
    fmt = _format_of(fname)
    arrs = check_demos(demos, "demos")
    n = len(arrs)
    time_arrs = check_times_list(times, arrs)
    id_list = _check_ids(ids, n)

    check_output_path(fname, overwrite=overwrite)

    if fmt == ".csv":
        if any(t is None for t in time_arrs) and any(t is not None for t in time_arrs):
            raise ValueError(
                f"{fname}: a CSV file stores times for all demonstrations or none; "
                "times has None for some demonstrations only"
            )

        def write_csv(f: IO[Any]) -> None:
            _write_csv(f, arrs, time_arrs, id_list)

        return atomic_write(fname, write_csv, overwrite=overwrite)
    if fmt == ".npz":
        arrays: dict[str, np.ndarray] = {}
        for j, (a, t) in enumerate(zip(arrs, time_arrs, strict=True)):
            arrays[f"demo_{j}"] = a
            if t is not None:
                arrays[f"time_{j}"] = t
        if ids is not None:
            arrays["ids"] = np.array([str(i) for i in id_list], dtype=np.str_)

        def write_npz(f: IO[Any]) -> None:
            np.savez_compressed(f, **arrays)  # float/str arrays only: no pickling

        return atomic_write(fname, write_npz, binary=True, overwrite=overwrite)

    def write_json(f: IO[Any]) -> None:
        _write_json(f, arrs, time_arrs, id_list)

    return atomic_write(fname, write_json, overwrite=overwrite)


def path_csv(points: Any) -> str:
    """One path as CSV text: a header ``x,y[,z]`` (or ``x1,...,xq``), one row per point.

    Floats are written exactly (``repr``), so parsing the text gives back the same array.
    """
    arr = check_path(points, "points", min_points=1)
    rows = "".join(",".join(repr(float(v)) for v in row) + "\n" for row in arr)
    return ",".join(_coord_header(arr.shape[1])) + "\n" + rows


def save_path(path: PathLike, points: Any, *, overwrite: bool = False) -> Path:
    """Write one path (e.g. a plan) as :func:`path_csv` text, atomically (:func:`atomic_write`)."""
    text = path_csv(points)
    return atomic_write(path, lambda f: f.write(text), overwrite=overwrite)


# --------------------------------------------------------------------------- #
# Shared helpers
# --------------------------------------------------------------------------- #


def _format_of(fname: str, supported: Sequence[str] = SUPPORTED_SUFFIXES, kind: str = "") -> str:
    """Lower-case suffix of ``fname`` if ``supported``; ``kind`` names the file in errors."""
    suffix = Path(fname).suffix.lower()
    if suffix not in supported:
        shown = repr(suffix) if suffix else "(none)"
        what = f" for {kind}" if kind else ""
        raise ValueError(
            f"{fname}: unsupported file suffix {shown}{what}; supported suffixes: "
            + ", ".join(supported)
        )
    return suffix


def _check_ids(ids: Sequence[DemoId] | None, n: int) -> list[DemoId]:
    if ids is None:
        return list(range(n))
    if isinstance(ids, (str, bytes)) or not isinstance(ids, (Sequence, np.ndarray)):
        raise TypeError("ids: expected a list with one int or str per demonstration")
    if len(ids) != n:
        raise ValueError(f"ids: got {len(ids)} ids for {n} demonstrations")
    out: list[DemoId] = []
    seen: dict[str, int] = {}
    for j, i in enumerate(ids):
        if isinstance(i, (bool, np.bool_)):
            raise TypeError(f"ids[{j}]: expected an int or str, got {i!r}")
        if isinstance(i, (int, np.integer)):
            val: DemoId = int(i)
        elif isinstance(i, str):
            if not i or i != i.strip() or "\n" in i or "\r" in i or i.startswith("#"):
                raise ValueError(
                    f"ids[{j}]: {i!r} is not a valid id; a str id must be non-empty, without "
                    "surrounding whitespace or line breaks, and must not start with '#'"
                )
            val = i
        else:
            raise TypeError(f"ids[{j}]: expected an int or str, got {type(i).__name__}")
        key = str(val)
        if key in seen:
            raise ValueError(f"ids[{j}]: {val!r} repeats ids[{seen[key]}]; ids must be unique")
        seen[key] = j
        out.append(val)
    return out


def _check_file_id(did: DemoId, where: str) -> None:
    """Apply :func:`save_demos`'s id rules to an id read from a file (so it can be written back)."""
    try:
        _check_ids([did], 1)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where}: {str(exc).removeprefix('ids[0]: ')}") from None


def _parse_id(text: str) -> DemoId:
    """Turn a stored textual id back into an int when it is a canonical integer."""
    try:
        value = int(text)
    except ValueError:
        return text
    return value if str(value) == text else text


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


def _write_csv(
    f: IO[str],
    demos: list[np.ndarray],
    times: list[np.ndarray | None],
    ids: list[DemoId],
) -> None:
    q = demos[0].shape[1]
    has_t = times[0] is not None
    w = csv.writer(f, lineterminator="\n")
    w.writerow(["demo", *(["t"] if has_t else []), *_coord_header(q)])
    for a, t, i in zip(demos, times, ids, strict=True):
        sid = str(i)
        tl = t.tolist() if t is not None else None
        for k, row in enumerate(a.tolist()):
            # repr() of a Python float is the shortest string that reads back exactly.
            w.writerow([sid, *([repr(tl[k])] if tl is not None else []), *map(repr, row)])


def _read_bytes(fname: str, max_bytes: int | None = None) -> bytes:
    """Read a whole regular file of at most ``max_bytes`` bytes (default :data:`MAX_FILE_BYTES`).

    A FIFO, device or socket is refused before it is opened (reading one could
    block forever or never end); the size is checked before reading.
    """
    if max_bytes is None:
        max_bytes = MAX_FILE_BYTES
    _check_input_file(fname, max_bytes)
    with open(fname, "rb") as f:
        data = f.read(max_bytes + 1)
    if len(data) > max_bytes:  # grew since the check
        raise _too_large(fname, f"more than {max_bytes}", max_bytes)
    return data


def _too_large(fname: str, size: str, max_bytes: int) -> ValueError:
    return ValueError(
        f"{fname}: file too large ({size} bytes); lfdkit reads files of at most "
        f"{max_bytes} bytes ({max_bytes / 1024**2:g} MiB)"
    )


def _check_input_file(fname: str, max_bytes: int) -> None:
    """Refuse a directory, a special file (FIFO, device, socket) or a file over ``max_bytes``."""
    st = os.stat(fname)  # follows links: a link to a regular file is fine to read
    if stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(f"{fname}: is a directory; give the path of a file to read")
    if not stat.S_ISREG(st.st_mode):
        raise NotRegularFileError(
            f"{fname}: is {_file_kind(st.st_mode)}, not a regular file; lfdkit reads "
            "regular files only"
        )
    if st.st_size > max_bytes:
        raise _too_large(fname, str(st.st_size), max_bytes)


def _read_text(fname: str, max_bytes: int | None = None) -> str:
    """Read a UTF-8 text file (a leading byte-order mark is dropped), keeping line endings."""
    data = _read_bytes(fname, max_bytes)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        if data.startswith((b"\xff\xfe", b"\xfe\xff")):
            raise ValueError(f"{fname}: is UTF-16 text; save the file as UTF-8") from None
        if data.startswith(b"\x80") or b"\x00" in data[:4096]:  # 0x80: a pickle's first byte
            raise ValueError(
                f"{fname}: binary data, not text (a pickle, NumPy or other binary file?); "
                "this file type is read as UTF-8 text"
            ) from None
        raise ValueError(
            f"{fname}: not UTF-8 text (byte {exc.start}: {exc.reason}); save the file as UTF-8"
        ) from None


def _csv_row(fname: str, lineno: int, line: str) -> list[str]:
    try:
        return next(csv.reader([line]))
    except csv.Error as exc:
        raise ValueError(f"{fname} line {lineno}: malformed CSV ({exc})") from None


def _content_lines(f: IO[str]) -> Iterator[tuple[int, str]]:
    """Yield (1-based line number, line) for lines that are not blank or comments."""
    for lineno, line in enumerate(f, 1):
        s = line.strip()
        if s and not s.startswith("#"):
            yield lineno, line


def _csv_columns(fname: str, header: list[str]) -> tuple[int, int | None, list[int], list[str]]:
    """Locate the demo, time and coordinate columns; return their indices and names."""
    names = [h.strip() for h in header]
    found = ", ".join(repr(n) for n in names)
    keys = [n.lower() for n in names]
    for k, key in enumerate(keys):
        if not key:
            raise ValueError(f"{fname}: header column {k + 1} has no name; found columns: {found}")
        if keys.index(key) != k:
            raise ValueError(f"{fname}: duplicate column {names[k]!r}; found columns: {found}")
    pos = {key: k for k, key in enumerate(keys)}

    if "demo" not in pos:
        raise ValueError(f"{fname}: missing column 'demo'; found columns: {found}")
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
            raise ValueError(f"{fname}: missing column {c!r}; found columns: {found}")
    coord_cols = [pos[c] for c in want]
    return pos["demo"], t_col, coord_cols, [names[k] for k in coord_cols]


# A decimal number as CSV files spell it: no digit separators ("0_5", which
# Python's float reads as 5), no inner spaces, no hexadecimal, no nan/inf words.
_CSV_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def _csv_number(fname: str, lineno: int, column: str, cell: str) -> float:
    """Read one CSV cell (already stripped) as a finite float, strictly.

    Accepts the decimal spellings ``12``, ``-0.5``, ``.5``, ``1.``, ``1e-3``;
    refuses what Python's ``float`` would also take (``0_5``, ``nan``, ``inf``,
    ``infinity``, spaces inside) so that no cell is read as another number.
    """
    where = f"{fname} line {lineno}, column {column!r}"
    if not cell:
        raise ValueError(f"{where}: empty value")
    if _CSV_NUMBER.fullmatch(cell) is None:
        try:
            value = float(cell)
        except ValueError:
            value = None
        if value is not None and not math.isfinite(value):
            raise ValueError(
                f"{where}: value {cell!r} is not finite; NaN and infinity are not allowed"
            )
        hint = "; digit separators ('_') are not allowed" if "_" in cell else ""
        raise ValueError(f"{where}: could not read {cell!r} as a number{hint}")
    value = float(cell)
    if not math.isfinite(value):  # e.g. 1e999
        raise ValueError(f"{where}: value {cell!r} is not finite; NaN and infinity are not allowed")
    return value


def _csv_id(fname: str, lineno: int, column: str, cell: str) -> str:
    """A demonstration id cell, refused when empty or padded with whitespace.

    Stripping would silently merge ``" 7"`` with ``"7"``; keeping the spaces
    would make two ids that print alike, so both are errors.
    """
    where = f"{fname} line {lineno}, column {column!r}"
    if not cell.strip():
        raise ValueError(f"{where}: empty value")
    if cell != cell.strip():
        raise ValueError(
            f"{where}: id {cell!r} has spaces around it; write ids without surrounding "
            f"whitespace ({cell.strip()!r})"
        )
    _check_file_id(cell, where)  # e.g. '#1' in a later column: not writable back
    return cell


class _Blocks:
    """The demonstration id of each CSV row, checked; the rows of one id must be consecutive."""

    def __init__(self, fname: str, column: str) -> None:
        self.fname, self.column = fname, column
        self.spans: dict[str, list[int]] = {}  # id -> [first line, last line]
        self.current: str | None = None

    def id_of(self, cell: str, lineno: int) -> str:
        """The id in ``cell`` (raw, unstripped) on line ``lineno``."""
        if cell == self.current:  # the common case: the block goes on
            self.spans[cell][1] = lineno
            return cell
        did = _csv_id(self.fname, lineno, self.column, cell)
        span = self.spans.get(did)
        if span is not None:
            raise ValueError(
                f"{self.fname} line {lineno}: demo {did!r} continues here, but its rows so far "
                f"are lines {span[0]}-{span[1]} and other demos come between; the rows of one "
                "demo must be consecutive (two recordings with one id?)"
            )
        self.spans[did] = [lineno, lineno]
        self.current = did
        return did


def _read_csv(
    fname: str,
) -> tuple[list[np.ndarray], list[np.ndarray | None], list[DemoId]]:
    with io.StringIO(_read_text(fname), newline="") as f:
        lines = _content_lines(f)
        first = next(lines, None)
        if first is None:
            raise ValueError(f"{fname}: no header row; the file is empty")
        header = _csv_row(fname, *first)
        demo_col, t_col, coord_cols, coord_names = _csv_columns(fname, header)
        colnames = [h.strip() for h in header]
        t_name = colnames[t_col] if t_col is not None else ""
        n_fields = len(header)

        groups: dict[str, tuple[list[list[float]], list[float], list[int]]] = {}
        blocks = _Blocks(fname, colnames[demo_col])
        for lineno, line in lines:
            row = _csv_row(fname, lineno, line)
            if len(row) != n_fields:
                raise ValueError(
                    f"{fname} line {lineno}: expected {n_fields} fields "
                    f"({', '.join(colnames)}), got {len(row)}"
                )
            did = blocks.id_of(row[demo_col], lineno)
            row = [c.strip() for c in row]
            pts, ts, linenos = groups.setdefault(did, ([], [], []))
            pts.append(
                [
                    _csv_number(fname, lineno, nm, row[c])
                    for c, nm in zip(coord_cols, coord_names, strict=True)
                ]
            )
            if t_col is not None:
                t = _csv_number(fname, lineno, t_name, row[t_col])
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
            raise ValueError(
                f"{fname}: demo {did!r} has {len(pts)} row; each demonstration needs at least 2"
            )
    demos = check_demos([g[0] for g in groups.values()], fname)
    times: list[np.ndarray | None] = [
        np.asarray(g[1], dtype=np.float64) if t_col is not None else None for g in groups.values()
    ]
    return demos, times, [_parse_id(d) for d in groups]


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
        _check_input_file(fname, MAX_FILE_BYTES)
        with open(fname, "rb") as f:
            if f.read(6) == b"\x93NUMPY":
                raise ValueError(f"{fname}: is a single .npy array, not an .npz archive")
        try:
            self.zip = zipfile.ZipFile(fname)
            infos = self.zip.infolist()
        except (zipfile.BadZipFile, zipfile.LargeZipFile, OSError, EOFError, ValueError) as exc:
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
) -> tuple[list[np.ndarray], list[np.ndarray | None], list[DemoId]]:
    with _NpzArchive(fname) as npz:
        return _read_npz_arrays(fname, npz)


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
            _parse_id(str(v)) if raw.dtype.kind == "U" else int(v) for v in raw.tolist()
        ]
        for j, did in enumerate(ids):
            _check_file_id(did, f"{fname}: array 'ids' entry {j}")
        if len({str(i) for i in ids}) != len(ids):
            raise ValueError(f"{fname}: array 'ids' has repeated ids")
    else:
        ids = list(range(len(demos)))
    return demos, times, ids


# --------------------------------------------------------------------------- #
# JSON
# --------------------------------------------------------------------------- #


def _write_json(
    f: IO[str],
    demos: list[np.ndarray],
    times: list[np.ndarray | None],
    ids: list[DemoId],
) -> None:
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
        sep = "," if j < len(demos) - 1 else ""
        buf.write(f"    {json.dumps(item, allow_nan=False)}{sep}\n")
    buf.write("  ]\n}\n")
    f.write(buf.getvalue())


# A JSON string, escapes included; an unterminated one runs to the end of the
# text (so the pattern never fails and is never retried: linear time).
_JSON_STRING = re.compile(r'"[^"\\]*(?:\\.[^"\\]*)*"?', re.DOTALL)
_NOT_BRACKET_BYTES = bytes(c for c in range(256) if c not in b"[]{}")


def _json_too_deep(text: str, max_depth: int) -> bool:
    """Whether arrays and objects in ``text`` nest deeper than ``max_depth`` (no recursion)."""
    if text.count("[") + text.count("{") <= max_depth:
        return False
    brackets = _JSON_STRING.sub("", text).encode("utf-8").translate(None, _NOT_BRACKET_BYTES)
    codes = np.frombuffer(brackets, dtype=np.uint8)
    steps = np.where((codes == ord("[")) | (codes == ord("{")), np.int32(1), np.int32(-1))
    return bool(steps.size) and int(np.cumsum(steps).max()) > max_depth


class _DuplicateKeys:
    """``object_pairs_hook`` that builds dicts and remembers those with a repeated key."""

    def __init__(self) -> None:
        self.found: list[tuple[dict[str, Any], str]] = []

    def __call__(self, pairs: list[tuple[str, Any]]) -> dict[str, Any]:
        obj = dict(pairs)
        if len(obj) != len(pairs) and not self.found:
            seen: set[str] = set()
            for key, _ in pairs:
                if key in seen:
                    self.found.append((obj, key))
                    break
                seen.add(key)
        return obj


def _json_path_of(doc: Any, target: object) -> str:
    """JSON path (``demos[2].points``) of the container ``target`` inside ``doc``, iteratively."""
    stack: list[tuple[Any, str]] = [(doc, "")]
    while stack:
        node, where = stack.pop()
        if node is target:
            return where or "(top level)"
        if isinstance(node, dict):
            stack.extend((v, f"{where}.{k}" if where else str(k)) for k, v in node.items())
        elif isinstance(node, list):
            stack.extend(
                (v, f"{where}[{i}]") for i, v in enumerate(node) if isinstance(v, (list, dict))
            )
    return "?"  # pragma: no cover - target is always in doc


_JSON_CONSTANT = re.compile(_JSON_STRING.pattern + r"|(-?Infinity|NaN)", re.DOTALL)


def _json_constant_line(text: str) -> str:
    """``: line L, column C`` of the first NaN/Infinity literal outside strings in ``text``."""
    for match in _JSON_CONSTANT.finditer(text):
        if match.group(1):
            start = match.start(1)
            line = text.count("\n", 0, start) + 1
            return f": line {line}, column {start - text.rfind(chr(10), 0, start)}"
    return ""  # pragma: no cover - json found one


def _reject_json_constant(name: str) -> None:
    raise _JSONConstantError(name)


class _JSONConstantError(ValueError):
    """A NaN or Infinity literal (Python's json extension to JSON)."""


def load_json(fname: str, *, max_bytes: int | None = None) -> Any:
    """Parse an lfdkit JSON file strictly, refusing anything that could lose data silently.

    Parameters
    ----------
    fname : str
        The file.
    max_bytes : int, optional
        Largest file accepted (default :data:`MAX_FILE_BYTES`).

    Returns
    -------
    object
        The parsed document (dicts, lists, str, int, float, bool, None).

    Raises
    ------
    ValueError
        For a file larger than ``max_bytes``, not UTF-8, not valid JSON
        (``"<file>: line L: not valid JSON at column C (...)"``), nested
        deeper than :data:`MAX_JSON_DEPTH`, with a repeated key in an object
        (the object's JSON path given; a repeated ``"demos"`` would otherwise
        keep only the last list), or with the non-standard ``NaN`` and
        ``Infinity`` literals.
    FileNotFoundError, IsADirectoryError, NotRegularFileError
        If the file is missing, a directory, or not a regular file.
    """
    text = _read_text(fname, max_bytes)
    if _json_too_deep(text, MAX_JSON_DEPTH):
        raise ValueError(
            f"{fname}: JSON nested too deep (more than {MAX_JSON_DEPTH} levels of arrays and "
            "objects); lfdkit files nest only a few levels"
        )
    duplicates = _DuplicateKeys()
    try:
        doc = json.loads(text, object_pairs_hook=duplicates, parse_constant=_reject_json_constant)
    except json.JSONDecodeError as exc:
        raise ValueError(
            f"{fname}: line {exc.lineno}: not valid JSON at column {exc.colno} ({exc.msg})"
        ) from None
    except _JSONConstantError as exc:
        raise ValueError(
            f"{fname}{_json_constant_line(text)}: {exc} is not a JSON number; NaN and "
            "infinity are not allowed in lfdkit files"
        ) from None
    except (ValueError, RecursionError) as exc:  # e.g. an integer of more than 4300 digits
        raise ValueError(f"{fname}: invalid JSON ({exc})") from None
    if duplicates.found:
        obj, key = duplicates.found[0]
        raise ValueError(
            f"{fname}: {_json_path_of(doc, obj)}: key {key!r} appears more than once in one "
            "object; each key may be given once"
        )
    return doc


def _json_kind(value: Any) -> str:
    """Words for a JSON value's type, for messages."""
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, str):
        return "a string"
    if value is None:
        return "null"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, dict):
        return "an object"
    return "a number"


def json_float_array(value: Any, where: str, ndim: int) -> np.ndarray:
    """A float64 array from JSON nested lists of numbers, refusing strings and booleans.

    Parameters
    ----------
    value : object
        Parsed JSON: a list of numbers (``ndim`` 1) or a list of lists of numbers (``ndim`` 2).
    where : str
        File and JSON path of ``value`` for messages (``"f.json: demos[0].points"``).
    ndim : {1, 2}
        Nesting expected.

    Returns
    -------
    ndarray of float64, ``ndim`` dimensions
        Not yet checked for shape or finiteness.

    Raises
    ------
    TypeError
        If an element is not a number (a string such as ``"0.5"``, a boolean,
        null) or a level is not a list; the message gives the element's path.
    ValueError
        If rows differ in length or a number does not fit a float64.
    """
    rows = value if ndim == 2 else [value]
    if not isinstance(rows, list):
        raise TypeError(f"{where}: expected an array of arrays of numbers, got {_json_kind(rows)}")
    # Whole-document type checks in C (set of types); the Python loops run only on error.
    if not set(map(type, rows)) <= {list}:
        i, row = next((i, row) for i, row in enumerate(rows) if not isinstance(row, list))
        at = f"{where}[{i}]" if ndim == 2 else where
        raise TypeError(f"{at}: expected an array of numbers, got {_json_kind(row)}")
    if not set(map(type, itertools.chain.from_iterable(rows))) <= {int, float}:
        for i, row in enumerate(rows):
            for j, v in enumerate(row):
                if type(v) not in (int, float):
                    at = f"{where}[{i}][{j}]" if ndim == 2 else f"{where}[{j}]"
                    raise TypeError(f"{at}: expected a number, got {_json_kind(v)} ({v!r:.40})")
    if ndim == 2 and rows and len(set(map(len, rows))) > 1:
        k = next(i for i, row in enumerate(rows) if len(row) != len(rows[0]))
        raise ValueError(
            f"{where}[{k}]: has {len(rows[k])} numbers but {where}[0] has {len(rows[0])}; "
            "every point needs the same number of coordinates"
        )
    try:
        return np.array(value, dtype=np.float64)
    except OverflowError:
        raise ValueError(f"{where}: a number is too large for a 64-bit float") from None


def _json_document(fname: str, fmt: str, newest: int, kind: str) -> dict[str, Any]:
    """Parse a versioned lfdkit JSON file and check its ``format`` and ``version`` fields.

    Shared by every lfdkit JSON reader; ``kind`` names the content in messages
    (e.g. ``"scene"``). Parsing is strict (:func:`load_json`).
    """
    doc = load_json(fname)
    if not isinstance(doc, dict):
        raise ValueError(f"{fname}: expected a JSON object at the top level")
    found = doc.get("format")
    if found != fmt:
        raise ValueError(
            f"{fname}: field 'format' is {found!r}; expected {fmt!r} (not an lfdkit {kind} file)"
        )
    version = doc.get("version")
    if isinstance(version, bool) or not isinstance(version, int):
        raise ValueError(f"{fname}: field 'version' must be an integer, got {version!r}")
    if version > newest:
        raise ValueError(
            f"{fname}: file format version {version} was written by a newer lfdkit; this "
            f"lfdkit reads up to version {newest}; upgrade lfdkit to read it"
        )
    if version < 1:
        raise ValueError(f"{fname}: unknown file format version {version}")
    return doc


def _read_json(
    fname: str,
) -> tuple[list[np.ndarray], list[np.ndarray | None], list[DemoId]]:
    doc = _json_document(fname, JSON_FORMAT, JSON_VERSION, "demonstrations")
    q = doc.get("n_dims")
    if isinstance(q, bool) or not isinstance(q, int) or q < 2:
        raise ValueError(f"{fname}: field 'n_dims' must be an integer >= 2, got {q!r}")
    items = doc.get("demos")
    if not isinstance(items, list) or not items:
        raise ValueError(f"{fname}: field 'demos' must be a non-empty list of demonstrations")

    demos: list[np.ndarray] = []
    times: list[np.ndarray | None] = []
    ids: list[DemoId] = []
    seen: dict[str, int] = {}
    for j, item in enumerate(items):
        where = f"{fname}: demos[{j}]"
        if not isinstance(item, dict):
            raise ValueError(f"{where}: expected an object with 'points' (and optional 'id', 't')")
        did = item.get("id", j)
        if isinstance(did, bool) or not isinstance(did, (int, str)):
            raise TypeError(f"{where}: field 'id' must be an int or str, got {did!r}")
        _check_file_id(did, f"{where}: field 'id'")
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
        ids.append(did)
    return check_demos(demos, fname, n_dims=q), times, ids
