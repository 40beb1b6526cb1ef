"""Fuzzing every file reader: a clean load that round-trips, or lfdkit's own error.

Each reader (demonstrations from CSV, JSON and NPZ; scenes from CSV and JSON;
skill files) is given random bytes, random JSON documents, valid documents
with one value replaced, and random CSV cells. The property is the same
everywhere: the reader either returns data that survive save → load
unchanged, or raises ``ValueError`` or ``TypeError`` (the project's error
types, whose messages name the file), never another exception, within the
hypothesis deadline, and never writes a file (the directory is unchanged).
"""

from __future__ import annotations

import functools
import io
import json
import math
import tempfile
import zipfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, currently_in_test_context, event, given, settings
from hypothesis import strategies as st

from lfdkit.emulate import Reward
from lfdkit.io import JSON_FORMAT, JSON_VERSION, load_demos, save_demos
from lfdkit.io.scenes import SCENE_JSON_FORMAT, SCENE_JSON_VERSION, load_scenes, save_scenes
from lfdkit.skill import Skill

PROJECT_ERRORS = (ValueError, TypeError)

FUZZ = settings(
    max_examples=150,
    deadline=2000,  # milliseconds per example: a reader that hangs fails here
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)

# --------------------------------------------------------------------------- #
# Helpers
# --------------------------------------------------------------------------- #


def _listing(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


def _read_or_refuse(directory: Path, path: Path, reader: Callable[[Path], Any]) -> Any:
    """``reader(path)``, or ``None`` if it raised one of the project's errors with the file name.

    Fails on any other exception and if the reader changed the directory.
    """
    before = _listing(directory)
    try:
        result = reader(path)
    except PROJECT_ERRORS as exc:
        _note(f"refused: {type(exc).__name__}")
        message = str(exc)
        assert message.startswith(str(path)), f"message does not name the file: {message!r}"
        assert "\n" not in message, f"message is not one line: {message!r}"
        result = None
    assert _listing(directory) == before, "a reader wrote a file"
    if result is not None:
        _note("loaded")
    return result


def _note(outcome: str) -> None:
    """Count an outcome in hypothesis's statistics (``--hypothesis-show-statistics``)."""
    if currently_in_test_context():
        event(outcome)


def _bits_equal(a: np.ndarray | None, b: np.ndarray | None) -> bool:
    if a is None or b is None:
        return a is None and b is None
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


def _demos_round_trip(directory: Path, path: Path) -> None:
    """Load ``path``; if it loads, save and load again and compare bit for bit."""
    loaded = _read_or_refuse(
        directory, path, lambda p: load_demos(p, return_times=True, return_ids=True)
    )
    if loaded is None:
        return
    demos, times, ids = loaded
    assert all(d.dtype == np.float64 and np.isfinite(d).all() for d in demos)
    again_path = directory / f"again{path.suffix}"
    written = save_demos(again_path, demos, times=times, ids=ids)
    assert _listing(directory) == sorted([path.name, again_path.name])
    demos2, times2, ids2 = load_demos(written, return_times=True, return_ids=True)
    again_path.unlink()
    assert len(demos2) == len(demos)
    assert all(_bits_equal(a, b) for a, b in zip(demos, demos2, strict=True))
    assert all(_bits_equal(a, b) for a, b in zip(times, times2, strict=True))
    if path.suffix != ".npz" or ids2 != list(range(len(ids2))):
        assert [str(i) for i in ids2] == [str(i) for i in ids]


def _scenes_equal(a: dict, b: dict) -> bool:
    if [str(k) for k in a] != [str(k) for k in b]:
        return False
    for sa, sb in zip(a.values(), b.values(), strict=True):
        if sa.labels != sb.labels or not _bits_equal(sa.radii, sb.radii):
            return False
        if any(
            not _bits_equal(oa.position, ob.position)
            for oa, ob in zip(sa.obstacles, sb.obstacles, strict=True)
        ):
            return False
    return True


def _scenes_round_trip(directory: Path, path: Path) -> None:
    scenes = _read_or_refuse(directory, path, load_scenes)
    if scenes is None:
        return
    again_path = directory / f"again{path.suffix}"
    save_scenes(again_path, scenes)
    assert _listing(directory) == sorted([path.name, again_path.name])
    again = load_scenes(again_path)
    again_path.unlink()
    assert _scenes_equal(scenes, again)


def _skill_round_trip(directory: Path, path: Path) -> None:
    skill = _read_or_refuse(directory, path, Skill.load)
    if skill is None:
        return
    again_path = skill.save(directory / "again.json")
    again = Skill.load(again_path)
    assert again.to_dict() == skill.to_dict()
    assert again.save(directory / "third.json").read_bytes() == again_path.read_bytes()
    again_path.unlink()
    (directory / "third.json").unlink()


def _in_fresh_directory(test: Callable[[Path], None]) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        test(Path(tmp))


# --------------------------------------------------------------------------- #
# Strategies
# --------------------------------------------------------------------------- #

json_scalars = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**20), 10**20),
    st.floats(allow_nan=False, allow_infinity=False),
    st.text(max_size=8),
    st.sampled_from([" a", "#x", "a\nb", "", "7", "07", "0_5", "1.5", "NaN", "cup"]),
)
json_values = st.recursive(
    json_scalars,
    lambda inner: st.one_of(
        st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=6), inner, max_size=4)
    ),
    max_leaves=20,
)
small_floats = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)


def _leaf_paths(doc: Any, prefix: tuple = ()) -> list[tuple]:
    """Paths (tuples of keys and indices) of every value in a JSON document."""
    paths = [prefix]
    if isinstance(doc, dict):
        for k, v in doc.items():
            paths += _leaf_paths(v, (*prefix, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            paths += _leaf_paths(v, (*prefix, i))
    return paths


def _replaced(doc: Any, path: tuple, value: Any) -> Any:
    if not path:
        return value
    copy = json.loads(json.dumps(doc))
    node = copy
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    return copy


@st.composite
def mutated(draw: st.DrawFn, doc: Any) -> str:
    """``doc`` with one value replaced, as text.

    Half the time the value is any JSON value (mostly refused), otherwise a
    number is replaced by another number (often still valid), so that both
    outcomes are exercised.
    """
    paths = _leaf_paths(doc)
    numbers = [p for p in paths if type(_at(doc, p)) in (int, float)]
    if numbers and draw(st.booleans()):
        where = draw(st.sampled_from(numbers))
        value = draw(st.one_of(small_floats, st.integers(-5, 300)))
    else:
        where = draw(st.sampled_from(paths))
        value = draw(json_values)
    return json.dumps(_replaced(doc, where, value))


def _at(doc: Any, path: tuple) -> Any:
    for key in path:
        doc = doc[key]
    return doc


def _valid_demos_doc() -> dict:
    return {
        "format": JSON_FORMAT,
        "version": JSON_VERSION,
        "n_dims": 2,
        "demos": [
            {"id": "a", "points": [[0.0, 0.5], [1.0, 1.5], [2.0, 2.5]], "t": [0.0, 0.1, 0.2]},
            {"id": 7, "points": [[0.0, -0.5], [1.0, -1.5]]},
        ],
    }


def _valid_scenes_doc() -> dict:
    return {
        "format": SCENE_JSON_FORMAT,
        "version": SCENE_JSON_VERSION,
        "scenes": [
            {"demo": "a", "obstacles": [{"class": "cup", "position": [0.1, 0.2], "radius": 0.03}]},
            {"demo": 7, "obstacles": []},
        ],
    }


@functools.cache
def _skill_doc() -> dict:
    """A small fitted skill with a reward, as its file dict (cached: fitting takes a moment)."""
    s = np.linspace(0.0, 1.0, 30)
    demos = [np.column_stack([s, 0.1 * k * np.sin(np.pi * s) + 0.4]) for k in (1, 2, 3)]
    skill = Skill(n_points=40, n_basis=8).fit_path(demos)
    skill.adopt(Reward(5.0, {"cup": [[400.0, 0.0], [0.0, 400.0]]}))
    return json.loads(json.dumps(skill.to_dict()))


# CSV cells: numbers, and what float() would also accept or misread.
csv_cells = st.one_of(
    small_floats.map(repr),
    st.sampled_from(
        [
            "0_5",
            "1_0",
            " 7",
            "7 ",
            "nan",
            "inf",
            "-Infinity",
            "1e999",
            "",
            " ",
            "0x1",
            "\uff11",
            '"1,2"',
            "#",
            "1e",
            ".",
            "-",
            "+.5",
            "5.",
            "1 2",
            "\t3",
        ]
    ),
    st.text(alphabet='0123456789.-+eE_ abx,"#\n', max_size=6),
)
csv_ids = st.one_of(
    st.sampled_from(["a", "b", "7", "07", " 7", "7 ", "", "#c", "a b"]),
    st.text(alphabet="ab7 #\t", max_size=3),
)


# --------------------------------------------------------------------------- #
# Demonstrations
# --------------------------------------------------------------------------- #


@FUZZ
@given(data=st.binary(max_size=2000), suffix=st.sampled_from([".csv", ".json", ".npz"]))
def test_demos_random_bytes(data: bytes, suffix: str) -> None:
    def check(directory: Path) -> None:
        path = directory / f"demos{suffix}"
        path.write_bytes(data)
        _demos_round_trip(directory, path)

    _in_fresh_directory(check)


@FUZZ
@given(text=st.one_of(json_values.map(json.dumps), mutated(_valid_demos_doc())))
def test_demos_random_json(text: str) -> None:
    def check(directory: Path) -> None:
        path = directory / "demos.json"
        path.write_text(text, encoding="utf-8")
        _demos_round_trip(directory, path)

    _in_fresh_directory(check)


@st.composite
def csv_cell(draw: st.DrawFn, valid: str) -> str:
    """``valid`` most of the time, otherwise a random or tricky cell."""
    return valid if draw(st.integers(0, 29)) else draw(csv_cells)


@st.composite
def demos_csv(draw: st.DrawFn) -> str:
    """A demonstrations CSV, mostly valid: blocks of rows per id, a few odd cells or ids."""
    header = draw(st.sampled_from(["demo,x,y", "demo,t,x,y", "x,y,demo,time", "demo,x,y,z"]))
    names = header.split(",")
    lines = [header]
    for block in range(draw(st.integers(1, 3))):
        did = draw(st.one_of(st.just(f"d{block}"), csv_ids))
        for k in range(draw(st.integers(1, 4))):
            valid = {"demo": did, "t": repr(0.25 * k), "time": repr(0.25 * k)}
            cells = [
                valid[n]
                if n in ("demo",)
                else draw(csv_cell(valid.get(n, repr(draw(small_floats)))))
                for n in names
            ]
            if draw(st.integers(0, 19)) == 0:
                cells[names.index("demo")] = draw(csv_ids)
            lines.append(",".join(cells))
    return "\n".join(lines) + "\n"


@FUZZ
@given(text=demos_csv())
def test_demos_random_csv(text: str) -> None:
    def check(directory: Path) -> None:
        path = directory / "demos.csv"
        path.write_text(text, encoding="utf-8")
        _demos_round_trip(directory, path)

    _in_fresh_directory(check)


npz_dtypes = st.sampled_from(
    ["<f8", "<f4", "<f2", "<i8", "<u1", "<c16", "|b1", "<M8[s]", "<m8[s]", "<U3", "|S2"]
)
npz_names = st.sampled_from(
    ["demo_0", "demo_1", "demo_2", "time_0", "time_1", "demos", "times", "ids", "other"]
)


@st.composite
def npz_archives(draw: st.DrawFn) -> bytes:
    """An .npz of a few arrays, mostly demonstrations; odd names, dtypes, shapes; flipped bytes."""
    arrays = {}
    n_demos = draw(st.integers(0, 3))
    for j in range(n_demos):
        arrays[f"demo_{j}"] = np.array(
            draw(st.lists(st.tuples(small_floats, small_floats), min_size=1, max_size=4))
        )
    for name in draw(st.lists(npz_names, min_size=0 if n_demos else 1, max_size=3, unique=True)):
        dtype = np.dtype(draw(npz_dtypes))
        shape = tuple(draw(st.lists(st.integers(0, 4), min_size=0, max_size=3)))
        values = draw(st.lists(small_floats, min_size=math.prod(shape), max_size=math.prod(shape)))
        raw = np.array(values, dtype=np.float64).reshape(shape)
        if dtype.kind in "USMm":
            arrays[name] = raw.astype(np.int64).astype(dtype)
        elif dtype.kind in "iu":
            arrays[name] = raw.clip(np.iinfo(dtype).min, np.iinfo(dtype).max).astype(dtype)
        else:
            arrays[name] = (
                raw.astype(dtype).clip(-1e4, 1e4) if dtype.kind == "f" else raw.astype(dtype)
            )
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    data = buffer.getvalue()
    if draw(st.integers(0, 3)) == 0:  # flip a byte somewhere
        i = draw(st.integers(0, len(data) - 1))
        data = data[:i] + bytes([data[i] ^ draw(st.integers(1, 255))]) + data[i + 1 :]
    return data


@FUZZ
@given(data=npz_archives())
def test_demos_random_npz(data: bytes) -> None:
    def check(directory: Path) -> None:
        path = directory / "demos.npz"
        path.write_bytes(data)
        _demos_round_trip(directory, path)

    _in_fresh_directory(check)


@FUZZ
@given(n_members=st.integers(1, 5), lie=st.integers(0, 10**12))
def test_npz_headers_that_lie_are_refused_quickly(n_members: int, lie: int) -> None:
    # a .npy header announcing a huge array in a tiny member: never allocated
    header = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        header, {"descr": "<f8", "fortran_order": False, "shape": (lie, 2)}
    )

    def check(directory: Path) -> None:
        path = directory / "demos.npz"
        with zipfile.ZipFile(path, "w") as zf:
            for j in range(n_members):
                zf.writestr(f"demo_{j}.npy", header.getvalue() + bytes(32))
        _demos_round_trip(directory, path)

    _in_fresh_directory(check)


# --------------------------------------------------------------------------- #
# Scenes
# --------------------------------------------------------------------------- #


@FUZZ
@given(data=st.binary(max_size=2000), suffix=st.sampled_from([".csv", ".json"]))
def test_scenes_random_bytes(data: bytes, suffix: str) -> None:
    def check(directory: Path) -> None:
        path = directory / f"scenes{suffix}"
        path.write_bytes(data)
        _scenes_round_trip(directory, path)

    _in_fresh_directory(check)


@FUZZ
@given(text=st.one_of(json_values.map(json.dumps), mutated(_valid_scenes_doc())))
def test_scenes_random_json(text: str) -> None:
    def check(directory: Path) -> None:
        path = directory / "scenes.json"
        path.write_text(text, encoding="utf-8")
        _scenes_round_trip(directory, path)

    _in_fresh_directory(check)


@FUZZ
@given(
    rows=st.lists(
        st.tuples(
            csv_ids, st.sampled_from(["cup", "", " box", "a,b"]), csv_cells, csv_cells, csv_cells
        ),
        min_size=0,
        max_size=6,
    ),
    header=st.sampled_from(["demo,class,x,y,radius", "class,x,y,demo,radius", "demo,class,x,y,z"]),
)
def test_scenes_random_csv(rows: list, header: str) -> None:
    names = header.split(",")
    lines = [header]
    for did, label, a, b, c in rows:
        cells = {"demo": did, "class": label, "x": a, "y": b, "radius": c, "z": c}
        lines.append(",".join(cells[name] for name in names))
    text = "\n".join(lines) + "\n"

    def check(directory: Path) -> None:
        path = directory / "scenes.csv"
        path.write_text(text, encoding="utf-8")
        _scenes_round_trip(directory, path)

    _in_fresh_directory(check)


# --------------------------------------------------------------------------- #
# Skill files
# --------------------------------------------------------------------------- #


@FUZZ
@given(data=st.binary(max_size=2000))
def test_skill_random_bytes(data: bytes) -> None:
    def check(directory: Path) -> None:
        path = directory / "skill.json"
        path.write_bytes(data)
        _skill_round_trip(directory, path)

    _in_fresh_directory(check)


# A file without a stored DMP refits it (n_basis <= 200: about 0.5 s, seconds under load).
@settings(FUZZ, deadline=20000)
@given(data=st.data())
def test_skill_random_json(data: st.DataObject) -> None:
    text = data.draw(st.one_of(json_values.map(json.dumps), mutated(_skill_doc())))

    def check(directory: Path) -> None:
        path = directory / "skill.json"
        path.write_text(text, encoding="utf-8")
        _skill_round_trip(directory, path)

    _in_fresh_directory(check)


def test_the_valid_documents_load() -> None:
    # the mutation fuzzers start from valid documents: they must load as they are
    def check(directory: Path) -> None:
        for name, doc in (
            ("demos.json", _valid_demos_doc()),
            ("scenes.json", _valid_scenes_doc()),
            ("skill.json", _skill_doc()),
        ):
            (directory / name).write_text(json.dumps(doc), encoding="utf-8")
        assert len(load_demos(directory / "demos.json")) == 2
        assert len(load_scenes(directory / "scenes.json")) == 2
        assert Skill.load(directory / "skill.json").reward_ is not None

    _in_fresh_directory(check)


def test_the_property_checks_can_fail() -> None:
    # the checks are not vacuous: other exceptions, unnamed files and writes are all caught
    def check(directory: Path) -> None:
        path = directory / "demos.csv"
        save_demos(path, [np.array([[0.0, 0.1], [1.0, 1.1]])])

        def raises(exc: Exception) -> Callable[[Path], None]:
            def reader(p: Path) -> None:
                raise exc

            return reader

        def writes(p: Path) -> None:
            p.with_name("stray.txt").write_text("x")

        with pytest.raises(KeyError):
            _read_or_refuse(directory, path, raises(KeyError("x")))
        with pytest.raises(AssertionError, match="does not name the file"):
            _read_or_refuse(directory, path, raises(ValueError("bad value")))
        with pytest.raises(AssertionError, match="not one line"):
            _read_or_refuse(directory, path, raises(ValueError(f"{path}: bad\nvalue")))
        with pytest.raises(AssertionError, match="a reader wrote a file"):
            _read_or_refuse(directory, path, writes)

    _in_fresh_directory(check)
