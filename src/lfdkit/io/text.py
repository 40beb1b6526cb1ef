"""Strict, bounded reading shared by every lfdkit file reader (demonstrations, scenes, skills).

Each primitive refuses what could change the data silently and words its
error with the file name and the line, column or JSON path at fault:

* files: :func:`read_bytes`, :func:`read_text` and :func:`check_input_file`
  read regular files only (a FIFO, device or socket is never opened), of at
  most :data:`MAX_FILE_BYTES`, as UTF-8 text;
* CSV: :func:`csv_header`, :func:`header_hint` (why a header lacks a column),
  :func:`content_lines` (blank and ``#`` lines skipped),
  :func:`csv_row`, :func:`csv_rows`, :func:`csv_number` (decimal numbers only: no ``0_5``,
  ``nan`` or ``inf``), :func:`csv_id` and :class:`Blocks` (ids without
  surrounding spaces, the rows of one id consecutive);
* demonstration ids: :func:`check_ids`, :func:`check_file_id` and
  :func:`parse_id`, the rules of a :data:`lfdkit.model.demos.DemoId` in a file;
* JSON: :func:`load_json` (no repeated keys, ``NaN`` literals or nesting
  deeper than :data:`MAX_JSON_DEPTH`), :func:`json_document` (the
  ``format`` and ``version`` fields of a versioned lfdkit file) and
  :func:`json_float_array`;
* :func:`format_of`: the format of a file from its suffix.
"""

from __future__ import annotations

import csv
import io
import itertools
import json
import math
import os
import re
import stat
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import IO, Any

import numpy as np

from lfdkit.core.numbers import DECIMAL
from lfdkit.io.atomic import NotRegularFileError, file_kind
from lfdkit.model.demos import DemoId

__all__ = [
    "MAX_FILE_BYTES",
    "MAX_JSON_DEPTH",
    "Blocks",
    "check_file_id",
    "check_ids",
    "check_input_file",
    "content_lines",
    "csv_header",
    "csv_id",
    "csv_number",
    "csv_row",
    "csv_rows",
    "format_of",
    "header_hint",
    "json_document",
    "json_float_array",
    "load_json",
    "parse_id",
    "read_bytes",
    "read_text",
]

MAX_FILE_BYTES = 256 * 1024**2
"""Largest demonstrations or scenes file (CSV, JSON or NPZ) read, in bytes (256 MiB).

Far above any recording (a 3-D demonstration sampled at 1 kHz for a minute is
about 4 MB of CSV); it bounds the memory a corrupt or hostile file can take."""

MAX_JSON_DEPTH = 64
"""Deepest nesting of arrays and objects accepted in an lfdkit JSON file.

lfdkit files nest a few levels (a skill file about six)."""


# --------------------------------------------------------------------------- #
# Files
# --------------------------------------------------------------------------- #


def format_of(fname: str, supported: Sequence[str], kind: str = "") -> str:
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


def read_bytes(fname: str, max_bytes: int | None = None) -> bytes:
    """Read a whole regular file of at most ``max_bytes`` bytes (default :data:`MAX_FILE_BYTES`).

    A FIFO, device or socket is refused before it is opened (reading one could
    block forever or never end); the size is checked before reading.
    """
    if max_bytes is None:
        max_bytes = MAX_FILE_BYTES
    check_input_file(fname, max_bytes)
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


def check_input_file(fname: str, max_bytes: int | None = None) -> None:
    """Refuse a directory, a special file (FIFO, device, socket) or a file over ``max_bytes``.

    ``max_bytes`` defaults to :data:`MAX_FILE_BYTES`.
    """
    if max_bytes is None:
        max_bytes = MAX_FILE_BYTES
    st = os.stat(fname)  # follows links: a link to a regular file is fine to read
    if stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(f"{fname}: is a directory; give the path of a file to read")
    if not stat.S_ISREG(st.st_mode):
        raise NotRegularFileError(
            f"{fname}: is {file_kind(st.st_mode)}, not a regular file; lfdkit reads "
            "regular files only"
        )
    if st.st_size > max_bytes:
        raise _too_large(fname, str(st.st_size), max_bytes)


def read_text(fname: str, max_bytes: int | None = None) -> str:
    """Read a UTF-8 text file (a leading byte-order mark is dropped), keeping line endings."""
    data = read_bytes(fname, max_bytes)
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


# --------------------------------------------------------------------------- #
# Demonstration ids
# --------------------------------------------------------------------------- #


def check_ids(ids: Sequence[DemoId] | None, n: int) -> list[DemoId]:
    """The ids of ``n`` demonstrations, checked; ``0, 1, ..., n - 1`` when ``ids`` is None.

    An id is an ``int`` or a non-empty ``str`` without surrounding whitespace
    or line breaks, not starting with ``#`` (so that every format can store it
    and read it back), and ids are unique also as text (``7`` and ``"7"``
    clash). Errors name the entry (``ids[2]: ...``).
    """
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


def check_file_id(did: DemoId, where: str) -> None:
    """Apply :func:`check_ids`'s rules to an id read from a file (so it can be written back)."""
    try:
        check_ids([did], 1)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{where}: {str(exc).removeprefix('ids[0]: ')}") from None


def parse_id(text: str) -> DemoId:
    """Turn a stored textual id back into an int when it is a canonical integer."""
    try:
        value = int(text)
    except ValueError:
        return text
    return value if str(value) == text else text


# --------------------------------------------------------------------------- #
# CSV
# --------------------------------------------------------------------------- #


def csv_row(fname: str, lineno: int, line: str) -> list[str]:
    """The cells of one CSV line; a malformed line is an error naming the file and line."""
    try:
        return next(csv.reader([line]))
    except csv.Error as exc:
        raise ValueError(f"{fname} line {lineno}: malformed CSV ({exc})") from None


def content_lines(f: IO[str]) -> Iterator[tuple[int, str]]:
    """Yield (1-based line number, line) for lines that are not blank or comments."""
    for lineno, line in enumerate(f, 1):
        s = line.strip()
        if s and not s.startswith("#"):
            yield lineno, line


def csv_header(fname: str) -> tuple[int, list[str], Iterator[tuple[int, str]]]:
    """Read a CSV file: its header row (line number, cells) and the content lines after it.

    The lines are :func:`content_lines` (blank and ``#`` lines skipped), for
    :func:`csv_rows`; a file without a header row is an error.
    """
    lines = content_lines(io.StringIO(read_text(fname), newline=""))
    first = next(lines, None)
    if first is None:
        raise ValueError(f"{fname}: no header row; the file is empty")
    return first[0], csv_row(fname, *first), lines


def header_hint(names: Sequence[str]) -> str:
    """Why a CSV header may lack a column: ``""``, or a clause starting ``"; "`` with the fix.

    A file separated by ``;`` or tabs reads as one column named by the whole
    header; a file without a header row has numbers for column names.
    """
    for separator, word in ((";", "';'"), ("\t", "tab")):
        if len(names) == 1 and separator in names[0]:
            return f"; the file looks {word}-separated: write it with commas"
    if names and 2 * sum(_is_number(name) for name in names) >= len(names):
        return "; the first row holds numbers: the file needs a header row naming its columns"
    return ""


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def csv_rows(
    fname: str, lines: Iterator[tuple[int, str]], columns: Sequence[str]
) -> Iterator[tuple[int, list[str]]]:
    """(line number, cells) of each data row in ``lines``, which must have one cell per column.

    ``lines`` comes from :func:`content_lines` after the header row;
    ``columns`` are the header's names, listed in the error for a row with
    another number of fields.
    """
    for lineno, line in lines:
        row = csv_row(fname, lineno, line)
        if len(row) != len(columns):
            raise ValueError(
                f"{fname} line {lineno}: expected {len(columns)} fields "
                f"({', '.join(columns)}), got {len(row)}"
            )
        yield lineno, row


# A decimal number as CSV files spell it: no digit separators ("0_5", which
# Python's float reads as 5), no inner spaces, no hexadecimal, no nan/inf words.
_CSV_NUMBER = DECIMAL  # the one strict spelling (lfdkit.core.numbers), shared with the CLI


def csv_number(fname: str, lineno: int, column: str, cell: str) -> float:
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


def csv_id(fname: str, lineno: int, column: str, cell: str) -> str:
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
    check_file_id(cell, where)  # e.g. '#1' in a later column: not writable back
    return cell


class Blocks:
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
        did = csv_id(self.fname, lineno, self.column, cell)
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


# --------------------------------------------------------------------------- #
# JSON
# --------------------------------------------------------------------------- #


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
    text = read_text(fname, max_bytes)
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


def json_document(fname: str, fmt: str, newest: int, kind: str) -> dict[str, Any]:
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
