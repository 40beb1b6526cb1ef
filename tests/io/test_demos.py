"""lfdkit.io (demonstration files and atomic writes) and the lfdkit.model.demos data model."""

from __future__ import annotations

import io
import json
import os
import re
import stat
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import lfdkit.io.demos as demos_io
import lfdkit.io.text as io_text
from lfdkit.io import (
    JSON_FORMAT,
    JSON_VERSION,
    STALE_TEMP_SECONDS,
    SUPPORTED_SUFFIXES,
    NotRegularFileError,
    OutputExistsError,
    atomic_write,
    load_demos,
    path_csv,
    save_demos,
    save_path,
)
from lfdkit.model.demos import Demo

FORMATS = [".csv", ".npz", ".json"]


def _bits_equal(a: np.ndarray, b: np.ndarray) -> bool:
    """Exact equality, bit for bit (distinguishes 0.0 from -0.0)."""
    return a.dtype == b.dtype == np.float64 and a.shape == b.shape and a.tobytes() == b.tobytes()


def _write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8")
    return path


def _m(path: Path, rest: str) -> str:
    """Regex matching a message that starts with the file name, then ``rest``."""
    return "^" + re.escape(str(path)) + rest


def _leftovers(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if p.name.endswith(".tmp"))


# --------------------------------------------------------------------------- #
# Hypothesis round trips
# --------------------------------------------------------------------------- #

finite = st.floats(allow_nan=False, allow_infinity=False, width=64)


@st.composite
def demo_sets(draw: st.DrawFn, with_times: bool) -> tuple[list[np.ndarray], list | None]:
    n_demos = draw(st.integers(1, 5))
    q = draw(st.integers(2, 3))
    demos, times = [], []
    for _ in range(n_demos):
        n = draw(st.integers(2, 30))
        vals = draw(st.lists(finite, min_size=n * q, max_size=n * q))
        demos.append(np.array(vals, dtype=np.float64).reshape(n, q))
        # sorted distinct finite floats are strictly increasing
        t = sorted(draw(st.lists(finite, min_size=n, max_size=n, unique=True)))
        times.append(np.array(t, dtype=np.float64))
    return demos, (times if with_times else None)


@pytest.mark.parametrize("suffix", FORMATS)
@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(data=st.data())
def test_round_trip_exact(tmp_path: Path, suffix: str, data: st.DataObject) -> None:
    with_times = data.draw(st.booleans(), label="with_times")
    demos, times = data.draw(demo_sets(with_times), label="demos")
    with tempfile.TemporaryDirectory(dir=tmp_path) as d:
        path = Path(d) / f"demos{suffix}"
        assert save_demos(path, demos, times=times) == path
        got, got_t, got_ids = load_demos(path, return_times=True, return_ids=True)
        assert _leftovers(Path(d)) == []
    assert len(got) == len(demos)
    for a, b in zip(demos, got, strict=True):
        assert _bits_equal(a, b)
    assert got_ids == list(range(len(demos)))
    if times is None:
        assert got_t == [None] * len(demos)
    else:
        for a, b in zip(times, got_t, strict=True):
            assert b is not None and _bits_equal(a, b)


@pytest.mark.parametrize("suffix", FORMATS)
def test_round_trip_special_values_and_ids(tmp_path: Path, suffix: str) -> None:
    demos = [
        np.array([[0.1, -0.0], [5e-324, 1.7976931348623157e308], [-2.2250738585072014e-308, 3.0]]),
        np.array([[1.0, 2.0], [1e22, -1e-22]]),
    ]
    times = [np.array([-1.5, 0.0, 1e-9]), np.array([0.0, 0.1])]
    path = tmp_path / f"d{suffix}"
    save_demos(path, demos, times=times, ids=["left arm, take 1", 42])
    got, got_t, ids = load_demos(path, return_times=True, return_ids=True)
    assert all(_bits_equal(a, b) for a, b in zip(demos, got, strict=True))
    assert all(_bits_equal(a, b) for a, b in zip(times, got_t, strict=True))
    assert ids == ["left arm, take 1", 42]


@pytest.mark.parametrize("suffix", FORMATS)
def test_round_trip_high_dimensional(tmp_path: Path, suffix: str) -> None:
    rng = np.random.default_rng(0)
    demos = [rng.normal(size=(7, 5)), rng.normal(size=(4, 5))]
    path = tmp_path / f"d{suffix}"
    save_demos(path, demos)
    got = load_demos(path)
    assert all(_bits_equal(a, b) for a, b in zip(demos, got, strict=True))


def test_load_returns_plain_list_without_flags(tmp_path: Path) -> None:
    path = save_demos(tmp_path / "d.json", [np.zeros((2, 2)), np.ones((3, 2))])
    got = load_demos(path)
    assert isinstance(got, list) and len(got) == 2
    _, ids = load_demos(path, return_ids=True)
    assert ids == [0, 1]


@pytest.mark.parametrize("suffix", FORMATS)
def test_demo_records_round_trip_as_the_parallel_lists_do(tmp_path: Path, suffix: str) -> None:
    demos = [np.array([[0.1, -0.0], [1.0, 2.0], [3.0, 5.0]]), np.array([[1.0, 2.0], [1e22, 0.5]])]
    times = [np.array([0.0, 0.5, 1.25]), np.array([0.0, 0.1])]
    turn = np.array([0.0, 0.0, np.sin(0.3), np.cos(0.3)])
    quats = [np.tile(turn, (3, 1)), np.tile([0.0, 0.0, 0.0, 1.0], (2, 1))]
    records = [
        Demo(d, t, q, key) for d, t, q, key in zip(demos, times, quats, ["a", 7], strict=True)
    ]
    path = save_demos(tmp_path / f"d{suffix}", records)
    back = load_demos(path, as_records=True)
    got, got_t, ids, got_q = load_demos(
        path, return_times=True, return_ids=True, return_orientations=True
    )
    assert [r.id for r in back] == ids == ["a", 7]
    for record, d, t, q in zip(back, got, got_t, got_q, strict=True):
        assert _bits_equal(record.points, d) and _bits_equal(record.times, t)
        np.testing.assert_array_equal(record.orientations, q)
        assert record.scene is None
    assert all(_bits_equal(a, b) for a, b in zip(demos, got, strict=True))
    with pytest.raises(ValueError, match=r"^as_records: the records hold the times"):
        load_demos(path, as_records=True, return_ids=True)
    with pytest.raises(ValueError, match=r"^ids: the Demo records carry their own ids"):
        save_demos(tmp_path / f"e{suffix}", records, ids=["b", "c"])


def test_partial_times_npz_and_json(tmp_path: Path) -> None:
    demos = [np.zeros((2, 2)), np.ones((3, 2))]
    times = [None, np.array([0.0, 1.0, 2.0])]
    for suffix in (".npz", ".json"):
        path = save_demos(tmp_path / f"d{suffix}", demos, times=times)
        _, got_t = load_demos(path, return_times=True)
        assert got_t[0] is None
        assert _bits_equal(got_t[1], times[1])


def test_suffix_is_case_insensitive(tmp_path: Path) -> None:
    path = save_demos(tmp_path / "D.CSV", [np.zeros((2, 2))])
    assert path.read_text().startswith("demo,x,y\n")
    assert len(load_demos(path)) == 1


def test_save_accepts_str_path(tmp_path: Path) -> None:
    path = str(tmp_path / "d.npz")
    save_demos(path, [[[0, 0], [1, 1]]])
    assert os.path.exists(path)  # np.savez must not append a second ".npz"
    assert _bits_equal(load_demos(path)[0], np.array([[0.0, 0.0], [1.0, 1.0]]))


# --------------------------------------------------------------------------- #
# CSV reading
# --------------------------------------------------------------------------- #


def test_csv_keeps_file_order_and_skips_blank_and_comment_lines(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "demos.csv",
        "# recorded 2024-01-01\n"
        "demo,x,y\n"
        "\n"
        "b,1,10\n"
        "   \n"
        "b,3,30\n"
        "# a comment between rows\n"
        "a,2,20\n"
        "a,4,40\n"
        "  # indented comment\n",
    )
    demos, ids = load_demos(path, return_ids=True)
    assert ids == ["b", "a"]
    np.testing.assert_array_equal(demos[0], [[1, 10], [3, 30]])
    np.testing.assert_array_equal(demos[1], [[2, 20], [4, 40]])


def test_csv_integer_ids_time_alias_z_and_extra_columns(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "demos.csv",
        " Demo , Time ,X,Y,Z,label\n"
        "3,0.0,1,2,3,start\n3,0.5,4,5,6,end\n007,0,0,0,0,\n007,1,1,1,1,\n",
    )
    demos, times, ids = load_demos(path, return_times=True, return_ids=True)
    assert ids == [3, "007"]  # canonical integer spellings come back as int
    assert demos[0].shape == (2, 3)
    np.testing.assert_array_equal(times[0], [0.0, 0.5])


def test_csv_indexed_coordinates(tmp_path: Path) -> None:
    path = _write(tmp_path / "d.csv", "demo,t,x1,x2,x3,x4\n0,0,1,2,3,4\n0,1,5,6,7,8\n")
    (demo,) = load_demos(path)
    np.testing.assert_array_equal(demo, [[1, 2, 3, 4], [5, 6, 7, 8]])


def test_csv_quoted_fields_and_bom(tmp_path: Path) -> None:
    path = tmp_path / "d.csv"
    path.write_bytes(b'\xef\xbb\xbfdemo,x,y\r\n"a, b",1,2\r\n"a, b",3,4\r\n')
    demos, ids = load_demos(path, return_ids=True)
    assert ids == ["a, b"]
    np.testing.assert_array_equal(demos[0], [[1, 2], [3, 4]])


@pytest.mark.parametrize("suffix", [".csv", ".json"])
def test_text_not_utf8(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"demos{suffix}"
    path.write_bytes(b"demo,x,y\n\xff\xfe,1,2\n")
    with pytest.raises(ValueError, match=_m(path, r": not UTF-8 text")):
        load_demos(path)


def test_csv_malformed_row_names_line(tmp_path: Path) -> None:
    huge = "1" * 200_000  # beyond csv.field_size_limit()
    path = _write(tmp_path / "demos.csv", f"demo,x,y\na,0,0\na,{huge},1\n")
    with pytest.raises(ValueError, match=_m(path, r" line 3: malformed CSV")):
        load_demos(path)


def test_csv_without_time_column_gives_none_times(tmp_path: Path) -> None:
    path = _write(tmp_path / "d.csv", "demo,x,y\n0,1,2\n0,3,4\n")
    _, times = load_demos(path, return_times=True)
    assert times == [None]


def test_a_csv_without_a_demo_column_is_one_demonstration(tmp_path: Path) -> None:
    path = _write(tmp_path / "take.csv", "t,x,y,z\n0,1,2,3\n0.5,4,5,6\n1.5,7,8,9\n")
    demos, times, ids = load_demos(path, return_times=True, return_ids=True)
    assert ids == [0]
    np.testing.assert_array_equal(demos[0], [[1, 2, 3], [4, 5, 6], [7, 8, 9]])
    np.testing.assert_array_equal(times[0], [0.0, 0.5, 1.5])
    # Written back (with the demo column it then has), it reads the same.
    demos_io.save_demos(tmp_path / "back.csv", demos, times=times)
    again, again_times = load_demos(tmp_path / "back.csv", return_times=True)
    np.testing.assert_array_equal(again[0], demos[0])
    np.testing.assert_array_equal(again_times[0], times[0])


def test_several_files_are_one_set_named_by_their_stems(tmp_path: Path) -> None:
    rng = np.random.default_rng(5)
    takes = [rng.normal(size=(n, 3)) for n in (4, 7, 5)]
    paths = []
    for k, take in enumerate(takes):
        rows = "".join(",".join(repr(float(v)) for v in row) + "\n" for row in take)
        paths.append(_write(tmp_path / f"take_{k:02d}.csv", "x,y,z\n" + rows))
    # A file with its own demo column keeps its ids, after the others, in the order given.
    paths.append(_write(tmp_path / "more.csv", "demo,x,y,z\n7,0,0,0\n7,1,1,1\nb,2,2,2\nb,3,3,3\n"))
    records = demos_io.load_demo_files(paths)
    assert [demo.id for demo in records] == ["take_00", "take_01", "take_02", 7, "b"]
    for got, want in zip(records, takes, strict=False):
        np.testing.assert_array_equal(got.points, want)
    assert all(demo.times is None and demo.orientations is None for demo in records)
    # One path: exactly load_demos, its ids kept.
    assert [demo.id for demo in demos_io.load_demo_files([paths[0]])] == [0]
    assert [demo.id for demo in demos_io.load_demo_files(paths[0])] == [0]


@pytest.mark.parametrize(
    ("second", "expected"),
    [
        ("x,y\n0,0\n1,1\n", r"b\.csv: has 2-D demonstrations, but .*a\.csv has 3-D demon"),
        ("t,x,y,z\n0,0,0,0\n1,1,1,1\n", r"b\.csv: has times \(a t column\), but .*a\.csv has no"),
        ("demo,x,y,z\na,0,0,0\na,1,1,1\n", r"b\.csv: demo id 'a' is also in .*a\.csv"),
        (None, r"a\.csv: given twice; give each demonstration file once"),
    ],
    ids=["dimension", "times", "same-id", "twice"],
)
def test_files_that_disagree_are_refused_naming_both(tmp_path: Path, second, expected) -> None:
    first = _write(tmp_path / "a.csv", "x,y,z\n0,0,0\n1,1,1\n")
    other = first if second is None else _write(tmp_path / "b.csv", second)
    # "a" names the first file's one demonstration; "b.csv" may reuse it as an id.
    with pytest.raises(ValueError, match=expected) as info:
        demos_io.load_demo_files([first, other])
    assert "\n" not in str(info.value)
    with pytest.raises(ValueError, match="demos: no file given"):
        demos_io.load_demo_files([])


# --------------------------------------------------------------------------- #
# CSV errors: every message names the file, and the line/field where it applies
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("x,y\n0,1\n", r": the demonstration \(no demo column\) has 1 row; each .* at least 2"),
        ("x\n0\n1\n", r": missing column 'y'; found columns: 'x'"),
        ("demo,x\na,1\na,2\n", r": missing column 'y'; found columns: 'demo', 'x'"),
        ("demo,t\na,1\na,2\n", r": missing column 'x'; found columns: 'demo', 't'"),
        ("demo,x1\na,1\na,2\n", r": missing column 'x2'; found columns"),
        ("demo,x1,x2,x4\na,1,2,3\n", r": missing column 'x3'; found columns"),
        ("demo,x,y,x1\na,1,2,3\n", r": mixes coordinate naming"),
        ("demo,x,y,X\na,1,2,3\n", r": duplicate column 'X'"),
        ("demo,x,,y\na,1,2,3\n", r": header column 3 has no name"),
        ("demo,t,time,x,y\na,1,2,3,4\n", r": both 't' and 'time' columns"),
        ("", r": no header row; the file is empty"),
        ("# only a comment\n\n", r": no header row"),
        ("demo,x,y\n# nothing else\n", r": no data rows after the header"),
    ],
)
def test_csv_header_errors(tmp_path: Path, text: str, expected: str) -> None:
    path = _write(tmp_path / "demos.csv", text)
    with pytest.raises(ValueError, match=_m(path, expected)):
        load_demos(path)


def test_csv_missing_column_message_matches_spec(tmp_path: Path) -> None:
    path = _write(tmp_path / "demos.csv", "demo,x,t\na,1,0\na,2,1\n")
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == f"{path}: missing column 'y'; found columns: 'demo', 'x', 't'"


def test_csv_non_numeric_value_names_line_and_column(tmp_path: Path) -> None:
    # line 7 counts the comment and blank lines too
    path = _write(
        tmp_path / "demos.csv",
        "# header comment\ndemo,x,y\na,0,0\n\na,1,1\nb,2,2\nb,abc,3\n",
    )
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == f"{path} line 7, column 'x': could not read 'abc' as a number"


@pytest.mark.parametrize("cell", ["nan", "NaN", "inf", "-Infinity"])
def test_csv_non_finite_value_names_line(tmp_path: Path, cell: str) -> None:
    path = _write(tmp_path / "demos.csv", f"demo,x,y\na,0,0\na,1,{cell}\n")
    with pytest.raises(
        ValueError, match=_m(path, rf" line 3, column 'y': value '{cell}' is not finite")
    ):
        load_demos(path)


def test_csv_nan_time_names_line(tmp_path: Path) -> None:
    path = _write(tmp_path / "demos.csv", "demo,t,x,y\na,0,0,0\na,nan,1,1\n")
    with pytest.raises(ValueError, match=_m(path, r" line 3, column 't': value 'nan'")):
        load_demos(path)


@pytest.mark.parametrize(("row", "column"), [("a,,1", "x"), ("a,1, ", "y"), (",1,1", "demo")])
def test_csv_empty_cell(tmp_path: Path, row: str, column: str) -> None:
    path = _write(tmp_path / "demos.csv", f"demo,x,y\na,0,0\n{row}\n")
    with pytest.raises(ValueError, match=_m(path, rf" line 3, column '{column}': empty value")):
        load_demos(path)


def test_csv_wrong_field_count(tmp_path: Path) -> None:
    path = _write(tmp_path / "demos.csv", "demo,x,y\na,0,0\na,1\n")
    with pytest.raises(
        ValueError, match=_m(path, r" line 3: expected 3 fields \(demo, x, y\), got 2")
    ):
        load_demos(path)


def test_csv_single_row_demo(tmp_path: Path) -> None:
    path = _write(tmp_path / "demos.csv", "demo,x,y\na,0,0\na,1,1\nb,2,2\n")
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == (f"{path}: demo 'b' has 1 row; each demonstration needs at least 2")


@pytest.mark.parametrize("second", ["0.5", "0.4"])
def test_csv_times_not_strictly_increasing(tmp_path: Path, second: str) -> None:
    path = _write(
        tmp_path / "demos.csv",
        f"demo,t,x,y\na,0.0,0,0\nb,0.5,0,0\nb,{second},1,1\n",
    )
    with pytest.raises(
        ValueError,
        match=_m(
            path,
            rf" line 4, column 't': time {second} in demo 'b' is not after the previous "
            r"time 0\.5 \(line 3\); times must be strictly increasing",
        ),
    ):
        load_demos(path)


def test_csv_times_are_per_demo(tmp_path: Path) -> None:
    # each demonstration has its own clock
    path = _write(tmp_path / "d.csv", "demo,t,x,y\na,5,0,0\na,6,1,1\nb,0,0,0\nb,1,1,1\n")
    _, times = load_demos(path, return_times=True)
    np.testing.assert_array_equal(times[0], [5, 6])
    np.testing.assert_array_equal(times[1], [0, 1])


def test_csv_id_in_two_blocks_is_an_error_naming_both(tmp_path: Path) -> None:
    # two recordings pasted together under one id used to merge into one demonstration
    path = _write(
        tmp_path / "d.csv",
        "demo,x,y\n7,0,0\n7,1,1\n# second recording\n8,5,5\n8,6,6\n7,0,0\n7,2,2\n",
    )
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == (
        f"{path} line 7: demo '7' continues here, but its rows so far are lines 2-3 and other "
        "demos come between; the rows of one demo must be consecutive (two recordings with "
        "one id?)"
    )


@pytest.mark.parametrize("cell", [" 7", "7 ", "\t7", " 7 "])
def test_csv_id_with_surrounding_whitespace_is_an_error(tmp_path: Path, cell: str) -> None:
    # " 7" and "7" used to merge silently
    path = _write(tmp_path / "d.csv", f"x,y,demo\n0,0,7\n1,1,7\n2,2,{cell}\n")
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == (
        f"{path} line 4, column 'demo': id {cell!r} has spaces around it; write ids without "
        "surrounding whitespace ('7')"
    )


def test_csv_id_starting_with_hash_in_a_later_column(tmp_path: Path) -> None:
    path = _write(tmp_path / "d.csv", "x,y,demo\n0,0,#1\n1,1,#1\n")
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == (
        f"{path} line 2, column 'demo': '#1' is not a valid id; a str id must be non-empty, "
        "without surrounding whitespace or line breaks, and must not start with '#'"
    )


@pytest.mark.parametrize(
    ("cell", "hint"),
    [
        ("0_5", "; digit separators ('_') are not allowed"),
        ("1_000.5", "; digit separators ('_') are not allowed"),
        ("1 000", ""),
        ("0x10", ""),
        ("1e", ""),
        ("--1", ""),
        ("\uff11", ""),  # a full-width digit, which float() reads as 1
        ("٣", ""),  # an Arabic-Indic digit, which float() reads as 3
    ],
)
def test_csv_numbers_that_float_would_misread(tmp_path: Path, cell: str, hint: str) -> None:
    # float("0_5") is 5.0: the learned path moved 0.645 m from one such cell
    path = _write(tmp_path / "d.csv", f"demo,x,y\na,0,0\na,{cell},1\n")
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == (
        f"{path} line 3, column 'x': could not read {cell!r} as a number{hint}"
    )


@pytest.mark.parametrize(
    ("cell", "value"),
    [
        ("+1", 1.0),
        ("-0.5", -0.5),
        (".5", 0.5),
        ("5.", 5.0),
        ("1E-3", 1e-3),
        ("-0", -0.0),
        (" 2.5 ", 2.5),
        ("007", 7.0),
    ],
)
def test_csv_decimal_spellings_are_read(tmp_path: Path, cell: str, value: float) -> None:
    path = _write(tmp_path / "d.csv", f"demo,x,y\na,0,0\na,{cell},1\n")
    got = load_demos(path)[0][1, 0]
    assert got == value and np.signbit(got) == np.signbit(value)


@pytest.mark.parametrize("cell", ["1e999", "-1e400"])
def test_csv_overflowing_number_is_not_finite(tmp_path: Path, cell: str) -> None:
    path = _write(tmp_path / "d.csv", f"demo,x,y\na,0,0\na,{cell},1\n")
    with pytest.raises(ValueError, match=_m(path, rf" line 3, column 'x': value '{cell}' is not")):
        load_demos(path)


# --------------------------------------------------------------------------- #
# NPZ
# --------------------------------------------------------------------------- #


def test_npz_stacked_demos_array(tmp_path: Path) -> None:
    stacked = np.arange(24, dtype=float).reshape(2, 4, 3)
    path = tmp_path / "d.npz"
    np.savez(path, demos=stacked, times=np.tile(np.arange(4.0), (2, 1)))
    demos, times = load_demos(path, return_times=True)
    assert len(demos) == 2
    np.testing.assert_array_equal(demos[1], stacked[1])
    np.testing.assert_array_equal(times[0], [0, 1, 2, 3])


def test_npz_float32_and_int_arrays_become_float64(tmp_path: Path) -> None:
    path = tmp_path / "d.npz"
    np.savez(path, demo_0=np.ones((3, 2), np.float32), demo_1=np.zeros((2, 2), np.int64))
    demos = load_demos(path)
    assert all(d.dtype == np.float64 for d in demos)


@pytest.mark.parametrize(
    ("arrays", "expected"),
    [
        ({"other": np.zeros(3)}, r": no demonstrations; expected arrays 'demo_0'.*'other'"),
        ({"demo_0": np.zeros((2, 2)), "demo_2": np.zeros((2, 2))}, r": missing array 'demo_1'"),
        (
            {"demo_0": np.zeros((2, 2)), "time_1": np.zeros(2)},
            r": array 'time_1' has no matching 'demo_1'",
        ),
        (
            {"demo_0": np.zeros((2, 2)), "demos": np.zeros((1, 2, 2))},
            r": has both a 'demos' array and 'demo_j'",
        ),
        ({"demos": np.zeros((2, 2))}, r": array 'demos' must be 3-D"),
        (
            {"demo_0": np.zeros((2, 2)), "time_0": np.array([0.0, 0.0])},
            r": array 'time_0': times must be strictly increasing",
        ),
        (
            {"demo_0": np.zeros((3, 2)), "time_0": np.array([0.0, 1.0])},
            r": array 'time_0': has 2 times but the demonstration has 3 points",
        ),
        ({"demo_0": np.zeros((1, 2))}, r": array 'demo_0': needs at least 2 points"),
        (
            {"demo_0": np.array([[0.0, 0.0], [np.nan, 1.0]])},
            r": array 'demo_0': contains NaN at row 1",
        ),
        (
            {"demo_0": np.zeros((2, 2)), "ids": np.array(["a", "b"])},
            r": array 'ids' must be 1-D text or integers with one entry per demonstration",
        ),
    ],
)
def test_npz_errors(tmp_path: Path, arrays: dict, expected: str) -> None:
    path = tmp_path / "demos.npz"
    np.savez(path, **arrays)
    with pytest.raises(ValueError, match=_m(path, expected)):
        load_demos(path)


def test_npz_object_arrays_are_never_unpickled(tmp_path: Path) -> None:
    path = tmp_path / "demos.npz"
    ragged = np.empty(2, dtype=object)
    ragged[0], ragged[1] = np.zeros((2, 2)), np.zeros((3, 2))
    np.savez(path, demo_0=ragged)
    with pytest.raises(
        ValueError, match=_m(path, r": array 'demo_0': holds Python objects, which lfdkit never")
    ):
        load_demos(path)


@pytest.mark.parametrize(
    ("array", "words"),
    [
        (np.ones((3, 2), dtype=complex), r"complex numbers \(dtype complex128\)"),
        (np.ones((3, 2), dtype=bool), r"booleans \(dtype bool\)"),
        (np.zeros((3, 2), dtype="datetime64[s]"), r"dates \(dtype datetime64\[s\]\)"),
        (np.zeros((3, 2), dtype="timedelta64[s]"), r"time intervals \(dtype timedelta64\[s\]\)"),
        (np.array([["1", "2"], ["3", "4"]]), r"text \(dtype <U1\)"),
        (
            np.zeros(3, dtype=[("x", float), ("y", float)]),
            r"raw or structured records \(dtype \[\('x', '<f8'\), \('y', '<f8'\)\]\)",
        ),
    ],
)
@pytest.mark.parametrize("layout", ["demo_0", "demos", "time_0"])
def test_npz_non_real_arrays_are_refused(
    tmp_path: Path, array: np.ndarray, words: str, layout: str
) -> None:
    path = tmp_path / "demos.npz"
    if layout == "demos":
        np.savez(path, demos=array[None])
    elif layout == "time_0":
        np.savez(path, demo_0=np.zeros((array.shape[0], 2)), time_0=array)
    else:
        np.savez(path, demo_0=array)
    with pytest.raises(ValueError) as info:
        load_demos(path)
    expected = rf": array '{layout}': holds {words}; demonstrations and times must be real"
    assert re.match(_m(path, expected), str(info.value))


def test_npz_float16_and_unsigned_are_real(tmp_path: Path) -> None:
    path = tmp_path / "d.npz"
    np.savez(
        path, demo_0=np.ones((3, 2), np.float16), demo_1=np.arange(4, dtype=np.uint8).reshape(2, 2)
    )
    demos = load_demos(path)
    np.testing.assert_array_equal(demos[1], [[0, 1], [2, 3]])


def _zip_bomb(path: Path, member: str, n_bytes: int, **arrays: np.ndarray) -> None:
    """An .npz with the given arrays plus ``member``: a zero array of ``n_bytes``, compressed."""
    import zipfile

    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        header, {"descr": "<f8", "fortran_order": False, "shape": (n_bytes // 8,)}
    )
    np.savez_compressed(path, **arrays)
    with zipfile.ZipFile(path, "a", compression=zipfile.ZIP_DEFLATED) as zf:
        with zf.open(member + ".npy", "w", force_zip64=True) as f:
            f.write(header.getvalue())
            chunk = bytes(1 << 20)
            for _ in range(n_bytes // len(chunk)):
                f.write(chunk)


def test_npz_unused_members_are_never_decompressed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import zipfile

    # np.load-style reading decompressed every member, e.g. a bomb stored as a "thumbnail"
    path = tmp_path / "bomb.npz"
    _zip_bomb(path, "thumbnail", 16 << 20, demo_0=np.zeros((3, 2)), ids=np.array(["a"]))
    opened: list[str] = []
    real_open = zipfile.ZipFile.open

    def spy(self, name, *args, **kwargs):
        opened.append(name.filename if isinstance(name, zipfile.ZipInfo) else name)
        return real_open(self, name, *args, **kwargs)

    monkeypatch.setattr(zipfile.ZipFile, "open", spy)
    demos, ids = load_demos(path, return_ids=True)
    assert len(demos) == 1 and ids == ["a"]
    assert sorted(opened) == ["demo_0.npy", "ids.npy"]


def test_npz_oversized_member_is_refused_from_its_header(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "bomb.npz"
    _zip_bomb(path, "demo_0", 64 << 20)
    monkeypatch.setattr(demos_io, "MAX_NPZ_ARRAY_BYTES", 32 << 20)
    started = time.perf_counter()
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert time.perf_counter() - started < 1.0
    size = (64 << 20) + 128
    assert str(info.value) == (
        f"{path}: array 'demo_0' is {size} bytes once decompressed; lfdkit reads arrays of "
        f"at most {32 << 20} bytes (0.03125 GiB)"
    )


def test_npz_header_larger_than_member_is_refused(tmp_path: Path) -> None:
    import zipfile

    path = tmp_path / "lie.npz"
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        header, {"descr": "<f8", "fortran_order": False, "shape": (10**9, 3)}
    )
    with zipfile.ZipFile(path, "w") as zf:
        zf.writestr("demo_0.npy", header.getvalue() + bytes(48))
    with pytest.raises(
        ValueError,
        match=_m(
            path,
            r": array 'demo_0': could not read array data \(header says shape \(1000000000, 3\)",
        ),
    ):
        load_demos(path)


def test_npz_too_many_members(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "many.npz"
    np.savez(path, **{f"demo_{j}": np.zeros((2, 2)) for j in range(5)})
    monkeypatch.setattr(demos_io, "MAX_NPZ_MEMBERS", 4)
    with pytest.raises(
        ValueError, match=_m(path, r": has 5 arrays; lfdkit reads .npz files of at most 4$")
    ):
        load_demos(path)


def test_npz_fortran_order_array(tmp_path: Path) -> None:
    path = tmp_path / "f.npz"
    demo = np.asfortranarray(np.arange(12.0).reshape(6, 2))
    np.savez(path, demo_0=demo)
    np.testing.assert_array_equal(load_demos(path)[0], demo)


def test_npz_not_an_archive(tmp_path: Path) -> None:
    path = _write(tmp_path / "demos.npz", "definitely not a zip file\n")
    with pytest.raises(ValueError, match="^" + re.escape(str(path))):
        load_demos(path)


def test_npz_single_npy_payload(tmp_path: Path) -> None:
    path = tmp_path / "demos.npz"
    with open(path, "wb") as f:
        np.save(f, np.zeros((2, 2, 2)))
    with pytest.raises(ValueError, match=_m(path, r": is a single \.npy array")):
        load_demos(path)


def test_npz_ids_follow_the_rules_of_save(tmp_path: Path) -> None:
    path = tmp_path / "d.npz"
    np.savez(path, demo_0=np.zeros((2, 2)), demo_1=np.ones((2, 2)), ids=np.array(["7", " 7"]))
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == (
        f"{path}: array 'ids' entry 1: ' 7' is not a valid id; a str id must be non-empty, "
        "without surrounding whitespace or line breaks, and must not start with '#'"
    )


def test_npz_ids_integer_array(tmp_path: Path) -> None:
    path = tmp_path / "d.npz"
    np.savez(path, demo_0=np.zeros((2, 2)), demo_1=np.ones((2, 2)), ids=np.array([10, 20]))
    assert load_demos(path, return_ids=True)[1] == [10, 20]


# --------------------------------------------------------------------------- #
# JSON
# --------------------------------------------------------------------------- #


def _json_doc(**overrides: object) -> dict:
    doc: dict = {
        "format": JSON_FORMAT,
        "version": JSON_VERSION,
        "n_dims": 2,
        "demos": [{"id": "a", "points": [[0, 0], [1, 1]]}, {"points": [[2, 2], [3, 3]]}],
    }
    doc.update(overrides)
    return doc


def test_json_minimal_file_and_default_ids(tmp_path: Path) -> None:
    path = _write(tmp_path / "d.json", json.dumps(_json_doc()))
    demos, times, ids = load_demos(path, return_times=True, return_ids=True)
    assert ids == ["a", 1]
    assert times == [None, None]
    np.testing.assert_array_equal(demos[1], [[2, 2], [3, 3]])


@pytest.mark.parametrize(
    ("doc", "expected"),
    [
        (_json_doc(format="something"), r": field 'format' is 'something'; expected"),
        (
            _json_doc(version=2),
            r": file format version 2 was written by a newer lfdkit; this lfdkit reads up to "
            r"version 1; upgrade lfdkit",
        ),
        (_json_doc(version=0), r": unknown file format version 0"),
        (_json_doc(version="1"), r": field 'version' must be an integer"),
        (_json_doc(n_dims=1), r": field 'n_dims' must be an integer >= 2"),
        (_json_doc(demos=[]), r": field 'demos' must be a non-empty list"),
        (
            _json_doc(demos=[{"id": "a", "points": [[0, 0], [1, 1]]}, {"id": "b"}]),
            r": demos\[1\]: missing field 'points'",
        ),
        (
            _json_doc(demos=[{"id": "a", "points": [[0, 0], [1, 1]], "t": [0, 1, 2]}]),
            r": demos\[0\] \(id 'a'\) field 't': has 3 times but the demonstration has 2",
        ),
        (
            _json_doc(demos=[{"id": 1, "points": [[0, 0]]}]),
            r": demos\[0\] \(id 1\) field 'points': needs at least 2 points",
        ),
        (
            _json_doc(
                demos=[{"id": "a", "points": [[0, 0], [1, 1]]}, {"id": "a", "points": [[0, 0]]}]
            ),
            r": demos\[1\]: id 'a' repeats demos\[0\]",
        ),
    ],
)
def test_json_errors(tmp_path: Path, doc: dict, expected: str) -> None:
    path = _write(tmp_path / "demos.json", json.dumps(doc))
    with pytest.raises(ValueError, match=_m(path, expected)):
        load_demos(path)


def test_json_invalid_syntax_names_line(tmp_path: Path) -> None:
    path = _write(tmp_path / "demos.json", '{\n  "format": "lfdkit-demos",\n  oops\n}\n')
    with pytest.raises(ValueError, match=_m(path, r": line 3: not valid JSON at column 3 \(")):
        load_demos(path)


def test_json_non_finite_point(tmp_path: Path) -> None:
    # Python's json writes the non-standard literal NaN; lfdkit refuses it where it stands
    text = json.dumps(_json_doc(demos=[{"id": "a", "points": [[0, 0], [float("nan"), 1]]}]))
    text = text.replace('"format"', '\n  "format"')
    path = _write(tmp_path / "demos.json", text)
    column = text.index("NaN") - text.index("\n")
    with pytest.raises(
        ValueError, match=_m(path, rf": line 2, column {column}: NaN is not a JSON number")
    ):
        load_demos(path)


def test_json_bad_id_type(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "demos.json", json.dumps(_json_doc(demos=[{"id": 1.5, "points": [[0, 0]]}]))
    )
    with pytest.raises(TypeError, match=_m(path, r": demos\[0\]: field 'id' must be an int")):
        load_demos(path)


@pytest.mark.parametrize("did", [" a", "a ", "#a", "a\nb", ""])
def test_json_ids_follow_the_rules_of_save(tmp_path: Path, did: str) -> None:
    # anything load_demos accepts can be written back (and matched with a CSV file)
    doc = _json_doc(demos=[{"id": did, "points": [[0, 0], [1, 1]]}])
    path = _write(tmp_path / "demos.json", json.dumps(doc))
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == (
        f"{path}: demos[0]: field 'id': {did!r} is not a valid id; a str id must be non-empty, "
        "without surrounding whitespace or line breaks, and must not start with '#'"
    )


def test_json_duplicate_demos_key_is_an_error(tmp_path: Path) -> None:
    # the case: a second "demos" key silently replaced the first (4 demos became 2)
    four = json.dumps([{"points": [[k, 0], [k, 1]]} for k in range(4)])
    two = json.dumps([{"points": [[k, 0], [k, 1]]} for k in range(2)])
    text = (
        f'{{"format": "{JSON_FORMAT}", "version": 1, "n_dims": 2,\n'
        f' "demos": {four},\n "demos": {two}}}\n'
    )
    path = _write(tmp_path / "demos.json", text)
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == (
        f"{path}: (top level): key 'demos' appears more than once in one object; "
        "each key may be given once"
    )


def test_json_duplicate_nested_key_names_its_path(tmp_path: Path) -> None:
    text = json.dumps(_json_doc()).replace('"id": "a"', '"id": "a", "id": "b"')
    path = _write(tmp_path / "demos.json", text)
    with pytest.raises(
        ValueError, match=_m(path, r": demos\[0\]: key 'id' appears more than once")
    ):
        load_demos(path)


@pytest.mark.parametrize(
    ("point", "where", "kind"),
    [
        ('"0.5"', r"demos\[0\]\.points\[1\]\[0\]", "a string"),
        ("true", r"demos\[0\]\.points\[1\]\[0\]", "a boolean"),
        ("null", r"demos\[0\]\.points\[1\]\[0\]", "null"),
    ],
)
def test_json_numbers_must_be_numbers(tmp_path: Path, point: str, where: str, kind: str) -> None:
    text = json.dumps(_json_doc()).replace("[[0, 0], [1, 1]]", f"[[0, 0], [{point}, 1]]")
    path = _write(tmp_path / "demos.json", text)
    with pytest.raises(TypeError, match=_m(path, rf": {where}: expected a number, got {kind}")):
        load_demos(path)


def test_json_times_as_strings_are_an_error(tmp_path: Path) -> None:
    doc = _json_doc(demos=[{"id": "a", "points": [[0, 0], [1, 1]], "t": [0, "1"]}])
    path = _write(tmp_path / "demos.json", json.dumps(doc))
    with pytest.raises(
        TypeError, match=_m(path, r": demos\[0\]\.t\[1\]: expected a number, got a")
    ):
        load_demos(path)


def test_json_ragged_points_name_the_row(tmp_path: Path) -> None:
    doc = _json_doc(demos=[{"id": "a", "points": [[0, 0], [1, 1, 1]]}])
    path = _write(tmp_path / "demos.json", json.dumps(doc))
    with pytest.raises(ValueError, match=_m(path, r": demos\[0\]\.points\[1\]: has 3 numbers but")):
        load_demos(path)


def test_json_huge_integer_is_an_error(tmp_path: Path) -> None:
    text = json.dumps(_json_doc()).replace("[[0, 0], [1, 1]]", f"[[0, 0], [1{'0' * 400}, 1]]")
    path = _write(tmp_path / "demos.json", text)
    with pytest.raises(ValueError, match=_m(path, r": demos\[0\]\.points: a number is too large")):
        load_demos(path)


@pytest.mark.parametrize("depth", [65, 1000, 100_000])
def test_json_deep_nesting_is_a_clear_error(tmp_path: Path, depth: int) -> None:
    path = _write(tmp_path / "demos.json", "[" * depth + "]" * depth)
    with pytest.raises(ValueError, match=_m(path, r": JSON nested too deep \(more than 64 levels")):
        load_demos(path)


def test_json_nesting_inside_strings_does_not_count(tmp_path: Path) -> None:
    doc = _json_doc(demos=[{"id": "[" * 500 + '\\"{', "points": [[0, 0], [1, 1]]}])
    path = _write(tmp_path / "demos.json", json.dumps(doc))
    assert load_demos(path, return_ids=True)[1] == ["[" * 500 + '\\"{']


def test_json_unterminated_string_is_invalid_json(tmp_path: Path) -> None:
    path = _write(tmp_path / "demos.json", '{"format": "lfdkit-demos' + '\\"[' * 10_000)
    with pytest.raises(ValueError, match=_m(path, r": line 1: not valid JSON at column 12 \(")):
        load_demos(path)


@pytest.mark.parametrize("suffix", FORMATS)
def test_file_too_large_is_refused_before_reading(
    tmp_path: Path, suffix: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / f"demos{suffix}"
    save_demos(path, [np.zeros((50, 2))])
    size = path.stat().st_size
    monkeypatch.setattr(io_text, "MAX_FILE_BYTES", size - 1)
    with pytest.raises(ValueError) as info:
        load_demos(path)
    assert str(info.value) == (
        f"{path}: file too large ({size} bytes); lfdkit reads files of at most {size - 1} "
        f"bytes ({(size - 1) / 1024**2:g} MiB)"
    )
    monkeypatch.setattr(io_text, "MAX_FILE_BYTES", size)
    assert len(load_demos(path)) == 1


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
@pytest.mark.parametrize("suffix", FORMATS)
def test_reading_a_fifo_is_refused_without_blocking(tmp_path: Path, suffix: str) -> None:
    fifo = tmp_path / f"pipe{suffix}"
    os.mkfifo(fifo)
    with pytest.raises(NotRegularFileError, match=_m(fifo, r": is a named pipe \(FIFO\), not a")):
        load_demos(fifo)


# --------------------------------------------------------------------------- #
# Mixed dimensions
# --------------------------------------------------------------------------- #


def test_mixed_dims_json(tmp_path: Path) -> None:
    doc = _json_doc(
        n_dims=3,
        demos=[
            {"id": "a", "points": [[0, 0, 0], [1, 1, 1]]},
            {"id": "b", "points": [[0, 0], [1, 1]]},
        ],
    )
    path = _write(tmp_path / "demos.json", json.dumps(doc))
    with pytest.raises(
        ValueError,
        match=_m(
            path,
            r": demos\[1\] \(id 'b'\): points have 2 dimensions but the file declares n_dims = 3",
        ),
    ):
        load_demos(path)


def test_mixed_dims_npz(tmp_path: Path) -> None:
    path = tmp_path / "demos.npz"
    np.savez(path, demo_0=np.zeros((2, 3)), demo_1=np.zeros((2, 2)))
    with pytest.raises(
        ValueError,
        match=_m(
            path,
            r": array 'demo_1' has 2 dimensions but array 'demo_0' has 3; "
            r"all demonstrations in a file must have the same number of dimensions",
        ),
    ):
        load_demos(path)


@pytest.mark.parametrize("suffix", FORMATS)
def test_mixed_dims_refused_on_save(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"demos{suffix}"
    with pytest.raises(ValueError, match=r"demos\[1\]: expected 3 columns"):
        save_demos(path, [np.zeros((2, 3)), np.zeros((2, 2))])
    assert not path.exists()


# --------------------------------------------------------------------------- #
# Suffixes, overwrite, directories
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize("name", ["demos.txt", "demos", "demos.csv.gz"])
def test_unknown_suffix(tmp_path: Path, name: str) -> None:
    path = tmp_path / name
    path.write_text("x")
    expected = _m(path, r": unsupported file suffix .*; supported suffixes: \.csv, \.json, \.npz")
    with pytest.raises(ValueError, match=expected):
        load_demos(path)
    with pytest.raises(ValueError, match=expected):
        save_demos(path, [np.zeros((2, 2))], overwrite=True)
    assert path.read_text() == "x"
    assert SUPPORTED_SUFFIXES == (".csv", ".json", ".npz")


@pytest.mark.parametrize("suffix", FORMATS)
def test_refuses_overwrite_then_overwrites(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"demos{suffix}"
    first = [np.zeros((2, 2))]
    second = [np.ones((3, 2)), np.full((2, 2), 2.0)]
    save_demos(path, first)
    before = path.read_bytes()
    with pytest.raises(
        OutputExistsError,
        match=_m(path, r": file already exists; allow overwriting to replace it \(overwrite=True"),
    ):
        save_demos(path, second)
    assert path.read_bytes() == before
    save_demos(path, second, overwrite=True)
    got = load_demos(path)
    assert len(got) == 2 and _bits_equal(got[0], second[0])
    assert _leftovers(tmp_path) == []


def test_refuses_directory(tmp_path: Path) -> None:
    path = tmp_path / "looks_like_a_file.csv"
    path.mkdir()
    with pytest.raises(IsADirectoryError, match=_m(path, r": is a directory")):
        save_demos(path, [np.zeros((2, 2))], overwrite=True)
    with pytest.raises(IsADirectoryError, match=_m(path, r": is a directory")):
        atomic_write(path, lambda f: f.write("x"), overwrite=True)


def test_missing_parent_directory(tmp_path: Path) -> None:
    path = tmp_path / "nope" / "d.csv"
    with pytest.raises(FileNotFoundError, match="does not exist"):
        save_demos(path, [np.zeros((2, 2))])


def test_load_missing_file(tmp_path: Path) -> None:
    with pytest.raises(FileNotFoundError):
        load_demos(tmp_path / "absent.csv")


# --------------------------------------------------------------------------- #
# save_demos argument checks
# --------------------------------------------------------------------------- #


def test_csv_needs_times_for_all_or_none(tmp_path: Path) -> None:
    path = tmp_path / "demos.csv"
    with pytest.raises(ValueError, match=_m(path, r": a CSV file stores times for all")):
        save_demos(path, [np.zeros((2, 2))] * 2, times=[None, [0.0, 1.0]])
    assert not path.exists()


@pytest.mark.parametrize(
    ("times", "error", "expected"),
    [
        ([[0.0, 0.0]], ValueError, r"times\[0\]: times must be strictly increasing"),
        ([[0.0, np.inf]], ValueError, r"times\[0\]: time at index 1 is inf"),
        ([[0.0, 1.0, 2.0]], ValueError, r"times\[0\]: has 3 times but the demonstration has 2"),
        ([[[0.0, 1.0]]], ValueError, r"times\[0\]: expected a 1-D array"),
        ([], ValueError, r"times: got 0 entries for 1 demonstrations"),
        (np.zeros(2), TypeError, r"times: expected a list"),
        (np.zeros((1, 2)), ValueError, r"times\[0\]: times must be strictly increasing"),
    ],
)
def test_save_validates_times(tmp_path: Path, times: object, error: type, expected: str) -> None:
    with pytest.raises(error, match=expected):
        save_demos(tmp_path / "d.json", [np.zeros((2, 2))], times=times)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("ids", "error", "expected"),
    [
        (["a", "a"], ValueError, r"ids\[1\]: 'a' repeats ids\[0\]"),
        ([7, "7"], ValueError, r"ids\[1\]: '7' repeats ids\[0\]"),
        (["a", ""], ValueError, r"ids\[1\]: '' is not a valid id"),
        (["a", " b"], ValueError, r"ids\[1\]: ' b' is not a valid id"),
        (["a", "#b"], ValueError, r"ids\[1\]: '#b' is not a valid id"),
        (["a", "b\nc"], ValueError, r"is not a valid id"),
        (["a", True], TypeError, r"ids\[1\]: expected an int or str"),
        (["a", 1.0], TypeError, r"ids\[1\]: expected an int or str"),
        (["a"], ValueError, r"ids: got 1 ids for 2 demonstrations"),
    ],
)
def test_save_validates_ids(tmp_path: Path, ids: list, error: type, expected: str) -> None:
    with pytest.raises(error, match=expected):
        save_demos(tmp_path / "d.csv", [np.zeros((2, 2))] * 2, ids=ids)
    assert not (tmp_path / "d.csv").exists()


def test_save_validates_demos_with_check_demos(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"demos\[0\]: contains NaN at row 1"):
        save_demos(tmp_path / "d.csv", [np.array([[0.0, 0.0], [np.nan, 0.0]])])
    with pytest.raises(ValueError, match=r"demos\[0\]: needs at least 2 points"):
        save_demos(tmp_path / "d.csv", [np.zeros((1, 2))])
    with pytest.raises(ValueError, match=r"demos: needs at least 1 demonstration"):
        save_demos(tmp_path / "d.csv", [])
    assert _leftovers(tmp_path) == [] and not (tmp_path / "d.csv").exists()


def test_save_accepts_3d_demos_and_2d_times(tmp_path: Path) -> None:
    stacked = np.arange(12, dtype=float).reshape(2, 3, 2)
    t = np.tile([0.0, 0.5, 1.0], (2, 1))
    path = save_demos(tmp_path / "d.csv", stacked, times=t)
    demos, times = load_demos(path, return_times=True)
    assert _bits_equal(demos[1], stacked[1]) and _bits_equal(times[0], t[0])


def test_numpy_integer_ids(tmp_path: Path) -> None:
    path = save_demos(tmp_path / "d.json", [np.zeros((2, 2))], ids=[np.int64(5)])
    assert load_demos(path, return_ids=True)[1] == [5]


# --------------------------------------------------------------------------- #
# atomic_write
# --------------------------------------------------------------------------- #


def test_atomic_write_text_and_binary(tmp_path: Path) -> None:
    text_path = atomic_write(tmp_path / "a.txt", lambda f: f.write("é\nline 2\n"))
    assert text_path.read_bytes() == "é\nline 2\n".encode()  # no newline translation
    bin_path = atomic_write(tmp_path / "b.bin", lambda f: f.write(b"\x00\xff"), binary=True)
    assert bin_path.read_bytes() == b"\x00\xff"
    assert _leftovers(tmp_path) == []


def test_atomic_write_failing_writer_leaves_original(tmp_path: Path) -> None:
    path = tmp_path / "keep.csv"
    path.write_text("original\n")

    def writer(f) -> None:
        f.write("half written")
        raise RuntimeError("boom")

    with pytest.raises(RuntimeError, match="boom"):
        atomic_write(path, writer, overwrite=True)
    assert path.read_text() == "original\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.csv"]


def test_atomic_write_failing_writer_creates_nothing(tmp_path: Path) -> None:
    def writer(f) -> None:
        f.write(b"partial")
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(tmp_path / "new.npz", writer, binary=True)
    assert list(tmp_path.iterdir()) == []


def test_save_demos_failure_mid_write_leaves_original(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    path = save_demos(tmp_path / "d.npz", [np.zeros((2, 2))])
    before = path.read_bytes()

    def broken(*args: object, **kwargs: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(np, "savez_compressed", broken)
    with pytest.raises(OSError, match="disk full"):
        save_demos(path, [np.ones((2, 2))], overwrite=True)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["d.npz"]


def test_atomic_write_refuses_existing(tmp_path: Path) -> None:
    path = tmp_path / "a.txt"
    path.write_text("old")
    with pytest.raises(FileExistsError, match=_m(path, r": file already exists")):
        atomic_write(path, lambda f: f.write("new"))
    assert path.read_text() == "old"
    atomic_write(path, lambda f: f.write("new"), overwrite=True)
    assert path.read_text() == "new"
    assert _leftovers(tmp_path) == []


def test_atomic_write_refuses_file_created_during_write(tmp_path: Path) -> None:
    # another process creates the target while we write: it must not be clobbered
    path = tmp_path / "race.txt"

    def writer(f) -> None:
        path.write_text("theirs")
        f.write("ours")

    with pytest.raises(FileExistsError):
        atomic_write(path, writer)
    assert path.read_text() == "theirs"
    assert _leftovers(tmp_path) == []


@pytest.mark.skipif(os.name != "posix", reason="POSIX permission bits")
def test_atomic_write_permissions(tmp_path: Path) -> None:
    plain = tmp_path / "plain.txt"
    plain.write_text("x")
    made = atomic_write(tmp_path / "made.txt", lambda f: f.write("x"))
    assert made.stat().st_mode == plain.stat().st_mode  # umask applies, not mkstemp's 0o600
    os.chmod(plain, 0o640)
    atomic_write(plain, lambda f: f.write("y"), overwrite=True)
    assert plain.stat().st_mode & 0o777 == 0o640  # replaced file keeps its mode


def test_exists_error_names_path_and_both_ways_to_allow(tmp_path: Path) -> None:
    path = tmp_path / "a.txt"
    path.write_text("old")
    with pytest.raises(OutputExistsError) as info:
        atomic_write(path, lambda f: f.write("new"))
    assert isinstance(info.value, FileExistsError) and info.value.path == path
    assert str(info.value) == (
        f"{path}: file already exists; allow overwriting to replace it "
        "(overwrite=True; --force on the command line)"
    )


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
@pytest.mark.parametrize("overwrite", [False, True])
def test_atomic_write_never_replaces_a_fifo(tmp_path: Path, overwrite: bool) -> None:
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    expected = _m(fifo, r": is a named pipe \(FIFO\), not a regular file; lfdkit writes regular")
    with pytest.raises(NotRegularFileError, match=expected):
        atomic_write(fifo, lambda f: f.write("x"), overwrite=overwrite)
    with pytest.raises(NotRegularFileError, match=expected):
        save_demos(fifo, [np.zeros((2, 2))], overwrite=overwrite)
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe.csv"]


@pytest.mark.skipif(not os.path.exists("/dev/null"), reason="needs /dev/null")
def test_atomic_write_never_replaces_a_device() -> None:
    with pytest.raises(NotRegularFileError, match=r"^/dev/null: is a character device, not a"):
        atomic_write("/dev/null", lambda f: f.write("x"), overwrite=True)
    assert stat.S_ISCHR(os.lstat("/dev/null").st_mode)


@pytest.mark.skipif(os.name != "posix", reason="POSIX symbolic links")
@pytest.mark.parametrize("points_to", ["real.txt", "missing.txt", "/dev/null"])
def test_atomic_write_refuses_symbolic_links(tmp_path: Path, points_to: str) -> None:
    real = tmp_path / "real.txt"
    real.write_text("kept")
    link = tmp_path / "link.txt"
    link.symlink_to(points_to)
    with pytest.raises(NotRegularFileError, match=_m(link, r": is a symbolic link \(to '")):
        atomic_write(link, lambda f: f.write("new"), overwrite=True)
    assert link.is_symlink() and os.readlink(link) == points_to
    assert real.read_text() == "kept"


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_target_turned_into_fifo_during_write_is_not_replaced(tmp_path: Path) -> None:
    path = tmp_path / "a.txt"
    path.write_text("old")

    def writer(f) -> None:
        path.unlink()
        os.mkfifo(path)
        f.write("new")

    with pytest.raises(NotRegularFileError, match="named pipe"):
        atomic_write(path, writer, overwrite=True)
    assert stat.S_ISFIFO(os.lstat(path).st_mode)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.txt"]


def test_temporary_file_name_is_recognisably_ours(tmp_path: Path) -> None:
    path = tmp_path / "skill.json"
    seen: list[str] = []

    def writer(f) -> None:
        seen.extend(p.name for p in tmp_path.iterdir())
        f.write("{}")

    atomic_write(path, writer)
    assert len(seen) == 1 and re.fullmatch(r"\.skill\.json\.[0-9a-f]{12}\.lfdkit\.tmp", seen[0])


def test_stale_temporary_files_of_the_target_are_removed(tmp_path: Path) -> None:
    path = tmp_path / "skill.json"
    old = time.time() - STALE_TEMP_SECONDS - 60
    ours_stale = [".skill.json.0123456789ab.lfdkit.tmp", ".skill.json.ba9876543210.tmp"]
    kept = [
        ".skill.json.0123456789ac.lfdkit.tmp",  # ours but recent: a write in progress
        ".other.json.0123456789ab.lfdkit.tmp",  # another target's
        ".skill.json.notours.tmp",  # not our naming
        ".skill.json.0123456789ab.lfdkit.tmp.bak",
        "skill.json.0123456789ab.lfdkit.tmp",
    ]
    for name in ours_stale + kept:
        (tmp_path / name).write_text("x")
        if name != kept[0]:
            os.utime(tmp_path / name, (old, old))
    os.mkdir(tmp_path / ".skill.json.fedcba987654.lfdkit.tmp")  # not a regular file: kept
    os.utime(tmp_path / ".skill.json.fedcba987654.lfdkit.tmp", (old, old))
    atomic_write(path, lambda f: f.write("{}"))
    remaining = sorted(p.name for p in tmp_path.iterdir())
    assert remaining == sorted([*kept, ".skill.json.fedcba987654.lfdkit.tmp", "skill.json"])


def test_long_file_name_still_writes(tmp_path: Path) -> None:
    path = tmp_path / ("n" * 250 + ".csv")
    save_demos(path, [np.zeros((2, 2))])
    assert len(load_demos(path)) == 1
    assert _leftovers(tmp_path) == []


def test_path_csv_with_times_and_velocities(tmp_path) -> None:
    rng = np.random.default_rng(4)
    for q, header in (
        (2, "t,x,y,vx,vy"),
        (3, "t,x,y,z,vx,vy,vz"),
        (4, "t,x1,x2,x3,x4,v1,v2,v3,v4"),
    ):
        points, velocities = rng.normal(size=(6, q)), rng.normal(size=(6, q))
        times = np.cumsum(rng.uniform(0.1, 1.0, 6)) - 0.1
        lines = path_csv(points, times=times, velocities=velocities).splitlines()
        assert lines[0] == header
        parsed = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
        np.testing.assert_array_equal(parsed, np.c_[times, points, velocities])
    assert path_csv(points, times=times).splitlines()[0] == "t,x1,x2,x3,x4"
    target = save_path(tmp_path / "timed.csv", points, times=times, velocities=velocities)
    assert target.read_text() == path_csv(points, times=times, velocities=velocities)
    with pytest.raises(FileExistsError):
        save_path(target, points, times=times)
    with pytest.raises(ValueError, match="times: contains NaN"):
        path_csv(points, times=np.r_[times[:-1], np.nan])
    with pytest.raises(ValueError, match="times: must not decrease"):
        path_csv(points, times=times[::-1])
    with pytest.raises(ValueError, match=r"times: expected shape \(6,\)"):
        path_csv(points, times=times[:3])
    with pytest.raises(ValueError, match=r"velocities: expected shape \(6, 4\)"):
        path_csv(points, velocities=velocities[:3])


def test_path_csv_is_exact_and_save_path_never_overwrites(tmp_path) -> None:
    rng = np.random.default_rng(3)
    for q, header in ((2, "x,y"), (3, "x,y,z"), (4, "x1,x2,x3,x4")):
        points = rng.normal(size=(7, q)) * 10.0 ** rng.integers(-9, 9, size=(7, q))
        lines = path_csv(points).splitlines()
        assert lines[0] == header
        parsed = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
        np.testing.assert_array_equal(parsed, points)
    target = tmp_path / "plan.csv"
    save_path(target, points)
    with pytest.raises(FileExistsError):
        save_path(target, points[:2])
    assert target.read_text() == path_csv(points)
    with pytest.raises(ValueError, match="points: contains NaN"):
        path_csv([[0.0, np.nan]])


# --------------------------------------------------------------------------- #
# Task frames (TP-GMM's object poses)
# --------------------------------------------------------------------------- #


def _framed_records(q: int, seed: int = 0) -> list[Demo]:
    """Three demonstrations, each with a start frame and a pan frame (2-D or 3-D poses)."""
    rng = np.random.default_rng(seed)
    records = []
    for j in range(3):
        if q == 2:
            poses = {f: np.r_[rng.normal(size=2), rng.uniform(-3, 3)] for f in ("start", "pan")}
        else:
            turns = rng.normal(size=(2, 4))
            turns /= np.linalg.norm(turns, axis=1, keepdims=True)
            pairs = zip(("start", "pan"), turns, strict=True)
            poses = {f: np.r_[rng.normal(size=3), t] for f, t in pairs}
        records.append(Demo(rng.normal(size=(4 + j, q)), None, None, f"take{j}", None, poses))
    return records


@pytest.mark.parametrize("q", [2, 3])
@pytest.mark.parametrize("suffix", [".csv", ".json"])
def test_task_frames_round_trip(tmp_path: Path, q: int, suffix: str) -> None:
    # Positions and angles come back bit for bit, a 3-D frame's quaternion normalised
    # (as the tool orientations are); a second round trip changes nothing more than that.
    records = _framed_records(q)
    path = save_demos(tmp_path / f"d{suffix}", records)
    back = load_demos(path, as_records=True)
    for record, got in zip(records, back, strict=True):
        assert _bits_equal(record.points, got.points)
        assert list(got.frames) == ["start", "pan"]
        for name, pose in record.frames.items():
            if q == 2:
                assert _bits_equal(pose, got.frames[name])
            else:
                assert _bits_equal(pose[:3], got.frames[name][:3])
                np.testing.assert_allclose(got.frames[name][3:], pose[3:], rtol=0, atol=4e-16)
    again = load_demos(save_demos(tmp_path / f"e{suffix}", back), as_records=True)
    for first, second in zip(back, again, strict=True):
        for name in first.frames:
            np.testing.assert_allclose(second.frames[name], first.frames[name], rtol=0, atol=4e-16)


def test_task_frame_columns_are_read_from_a_hand_written_csv(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "d.csv",
        "demo,x,y,frame_pan_x,frame_pan_y,frame_pan_angle\n"
        "a,0,0,0.5,0.25,1.5\na,1,1,0.5,0.25,1.5\nb,0,0,-1,2,0\nb,1,2,-1,2,0\n",
    )
    a, b = load_demos(path, as_records=True)
    np.testing.assert_array_equal(a.frames["pan"], [0.5, 0.25, 1.5])
    np.testing.assert_array_equal(b.frames["pan"], [-1.0, 2.0, 0.0])
    assert load_demos(save_demos(tmp_path / "n.csv", [a.points]), as_records=True)[0].frames is None


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (
            "demo,x,y,frame_pan_x,frame_pan_y,frame_pan_angle\n0,0,0,1,2,0\n0,1,1,1.5,2,0\n",
            r" line 3, column 'frame_pan_x': task frame 'pan' moves within demo '0' "
            r"\(1.5 here, 1.0 on line 2\); a task frame is one pose per demonstration",
        ),
        (
            "demo,x,y,frame_pan_x,frame_pan_y\n0,0,0,1,2\n0,1,1,1,2\n",
            r": task frame 'pan' missing frame_pan_angle; a 2-D frame's pose is "
            r"frame_pan_\{x,y,angle\}",
        ),
        (
            "demo,x,y,frame_pan_x,frame_pan_y,frame_pan_angle,frame_pan_qw\n0,0,0,1,2,0,1\n"
            "0,1,1,1,2,0,1\n",
            r": task frame 'pan' has frame_pan_qw; a 2-D frame's pose",
        ),
        (
            "demo,x1,x2,x3,x4,frame_pan_x\n0,0,0,0,0,1\n0,1,1,1,1,1\n",
            r": task frame columns \(frame_pan_...\) need 2-D or 3-D demonstrations, these are 4-D",
        ),
        (
            "demo,x,y,z,frame_p_x,frame_p_y,frame_p_z,frame_p_qx,frame_p_qy,frame_p_qz,frame_p_qw\n"
            "0,0,0,0,1,2,3,0,0,0,2\n0,1,1,1,1,2,3,0,0,0,2\n",
            r": demo '0', task frame 'p': the orientation has norm 2; a unit quaternion",
        ),
    ],
)
def test_bad_task_frame_columns_are_one_line_errors(
    tmp_path: Path, text: str, expected: str
) -> None:
    path = _write(tmp_path / "d.csv", text)
    with pytest.raises(ValueError, match=_m(path, expected)):
        load_demos(path, as_records=True)


@pytest.mark.parametrize(
    ("frames", "expected"),
    [
        ([{"pan": [1.0, 2.0, 0.0]}, None], r"^frames\[1\]: expected a mapping of frame names"),
        (
            [{"pan": [1.0, 2.0, 0.0]}, {"lid": [1.0, 2.0, 0.0]}],
            r"^frames: demos\[1\] has task frames lid, but demos\[0\] has pan; every",
        ),
        (
            [{"pan": [1.0, 2.0]}] * 2,
            r"^frames\[0\]\['pan'\]: expected the 3 numbers \[x, y, angle\]",
        ),
        ([{"pan": [1.0, np.nan, 0.0]}] * 2, r"^frames\[0\]\['pan'\]: contains NaN"),
        ([{"a pan": [1.0, 2.0, 0.0]}] * 2, r"^frames\[0\]: a task frame's name is letters"),
        ([{"pan": [1.0, 2.0, 0.0]}], r"^frames: expected one mapping of named poses for each"),
    ],
)
def test_bad_task_frames_are_refused_on_save(tmp_path: Path, frames: list, expected: str) -> None:
    demos = [np.zeros((2, 2)), np.ones((3, 2))]
    with pytest.raises(ValueError, match=expected):
        save_demos(tmp_path / "d.csv", demos, frames=frames)
    assert not list(tmp_path.iterdir())


def test_an_npz_file_refuses_task_frames(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match=r"^frames: an \.npz demonstrations file holds no task"):
        save_demos(tmp_path / "d.npz", _framed_records(2))


def test_json_task_frames_errors(tmp_path: Path) -> None:
    item = {"points": [[0, 0], [1, 1]], "frames": {"pan": {"position": [1, 2], "angle": 0.5}}}
    doc = {"format": JSON_FORMAT, "version": JSON_VERSION, "n_dims": 2}
    path = _write(
        tmp_path / "d.json", json.dumps({**doc, "demos": [item, {**item, "frames": None}]})
    )
    with pytest.raises(ValueError, match=_m(path, r": demos\[1\] \(id 1\) has task frames none")):
        load_demos(path, as_records=True)
    bad = {**item, "frames": {"pan": {"position": [1, 2], "orientation": [0, 0, 0, 1]}}}
    path = _write(tmp_path / "e.json", json.dumps({**doc, "demos": [bad]}))
    with pytest.raises(ValueError, match=r"\['pan'\]: expected the keys 'position' and 'angle'"):
        load_demos(path, as_records=True)
    bad = {**item, "frames": {"pan": {"position": [1, 2], "angle": "0.5"}}}
    path = _write(tmp_path / "f.json", json.dumps({**doc, "demos": [bad]}))
    with pytest.raises(TypeError, match=r"\['pan'\]\.angle: expected a number \(rad\)"):
        load_demos(path, as_records=True)


def test_files_must_agree_on_their_task_frames(tmp_path: Path) -> None:
    records = _framed_records(2)
    first = save_demos(tmp_path / "a.csv", records[:1])
    second = save_demos(tmp_path / "b.csv", [records[1].points], ids=["other"])
    with pytest.raises(ValueError, match=r"b\.csv: has no task frames, but .*a\.csv has task "):
        demos_io.load_demo_files([first, second])
