"""Atomic writes: a reader sees the old file or the whole new one, never half of it.

:func:`atomic_write` writes through a temporary file in the target's
directory, flushes it to disk and renames it onto the target; if the writer
fails or the process is interrupted, the temporary file is removed and an
existing target is left untouched. :func:`check_output_path` makes the same
checks on the target before any work is done, so that a long computation
does not end in a refused write.

Only a missing path or an existing regular file is written: a FIFO, device,
socket or symbolic link is refused (:class:`NotRegularFileError`), a
directory raises ``IsADirectoryError``, and an existing file is replaced
only when overwriting is allowed (:class:`OutputExistsError`, a
``FileExistsError``, otherwise). Temporary files left behind by a killed
process are removed by the next write of the same target once older than
:data:`STALE_TEMP_SECONDS`.
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import stat
import time
from collections.abc import Callable
from pathlib import Path
from typing import IO, Any

from lfdkit.model.demos import PathLike

__all__ = [
    "STALE_TEMP_SECONDS",
    "NotRegularFileError",
    "OutputExistsError",
    "atomic_write",
    "check_output_path",
    "file_kind",
    "write_text",
]


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


# Words for the file types other than a regular file, by their ``stat.S_IFMT`` value.
_FILE_KINDS = {
    stat.S_IFDIR: "a directory",
    stat.S_IFIFO: "a named pipe (FIFO)",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
    stat.S_IFLNK: "a symbolic link",
}


def file_kind(mode: int) -> str:
    """Words for a file type from ``st_mode`` (for messages)."""
    return _FILE_KINDS.get(stat.S_IFMT(mode), "not a regular file")


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
        f"{target}: is {file_kind(st.st_mode)}, not a regular file; lfdkit writes regular "
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


def write_text(path: PathLike, text: str, *, overwrite: bool = False) -> Path:
    """Write ``text`` to ``path`` atomically, as UTF-8: :func:`atomic_write` for a whole text.

    The text is written exactly as given (no newline added or translated).
    Returns the path written; refuses, as :func:`atomic_write` does, an
    existing file unless ``overwrite`` (:class:`OutputExistsError`, a
    ``FileExistsError``), a directory (``IsADirectoryError``), a FIFO,
    device, socket or symbolic link (:class:`NotRegularFileError`) and a
    missing directory (``FileNotFoundError``). A caller that does much work
    before writing checks the path first with :func:`check_output_path`.
    """
    return atomic_write(path, lambda f: f.write(text), overwrite=overwrite)


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
