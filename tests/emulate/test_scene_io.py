"""Tests for the scene file I/O of lfdkit.io.scenes: round trips, formats, errors."""

from __future__ import annotations

import json
import os
import re
import stat
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lfdkit.io.scenes import (
    SCENE_JSON_FORMAT,
    SCENE_JSON_VERSION,
    load_scene,
    load_scenes,
    save_scenes,
)
from lfdkit.model.scene import Obstacle, Scene

SUFFIXES = (".csv", ".json")


def _write(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8", newline="")
    return path


def _bits(x: object) -> bytes:
    """Exact bit pattern of a float64 array or float (distinguishes -0.0 from 0.0)."""
    return np.asarray(x, dtype=np.float64).tobytes()


def _assert_same(got: dict, want: dict) -> None:
    assert list(got) == list(want)  # ids, in order
    for did in want:
        assert [type(i) for i in got] == [type(i) for i in want]
        g, w = got[did], want[did]
        assert isinstance(g, Scene)
        assert g.labels == w.labels
        assert len(g) == len(w)
        for og, ow in zip(g.obstacles, w.obstacles, strict=True):
            assert og.position.dtype == np.float64
            assert np.array_equal(og.position, ow.position)
            assert _bits(og.position) == _bits(ow.position)
            assert og.radius == ow.radius
            assert _bits(og.radius) == _bits(ow.radius)


def _json_doc(scenes: list, **top: object) -> str:
    doc = {"format": SCENE_JSON_FORMAT, "version": SCENE_JSON_VERSION, "scenes": scenes}
    doc.update(top)
    return json.dumps(doc, indent=2)


# --------------------------------------------------------------------------- #
# Round trips
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize("suffix", SUFFIXES)
@pytest.mark.parametrize("q", [2, 3])
def test_round_trip_several_scenes_with_an_empty_one(tmp_path: Path, suffix: str, q: int) -> None:
    rng = np.random.default_rng(q)
    scenes = {
        0: Scene.from_arrays(["cup", "marker", "cup"], rng.normal(size=(3, q)), [0.03, 0.0, 1.5]),
        "free": Scene(),
        "b-7": Scene((Obstacle("box", -rng.random(q) * 1e-7, 2.5e-3),)),
        12: Scene(),
        -3: Scene.from_arrays(["cup"], np.full((1, q), -0.0)),
    }
    path = save_scenes(tmp_path / f"scenes{suffix}", scenes)
    assert path == tmp_path / f"scenes{suffix}"
    _assert_same(load_scenes(path), scenes)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_round_trip_only_empty_scenes(tmp_path: Path, suffix: str) -> None:
    scenes = {3: Scene(), "x": Scene()}
    _assert_same(load_scenes(save_scenes(tmp_path / f"s{suffix}", scenes)), scenes)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_round_trip_no_scene(tmp_path: Path, suffix: str) -> None:
    assert load_scenes(save_scenes(tmp_path / f"s{suffix}", {})) == {}


def test_csv_id_types_follow_the_canonical_integer_rule(tmp_path: Path) -> None:
    scenes = {"07": Scene(), "7": Scene(), "cup": Scene()}
    assert list(load_scenes(save_scenes(tmp_path / "s.csv", scenes))) == ["07", 7, "cup"]
    # JSON keeps the type of each id.
    assert list(load_scenes(save_scenes(tmp_path / "s.json", scenes))) == ["07", "7", "cup"]


_label = st.text(
    alphabet=st.characters(blacklist_categories=("Cs",)), min_size=1, max_size=8
).filter(lambda s: s == s.strip() and "\n" not in s and "\r" not in s)
_coord = st.floats(allow_nan=False, allow_infinity=False)
_radius = st.floats(min_value=0.0, allow_nan=False, allow_infinity=False)
_id = st.one_of(
    st.integers(-(10**12), 10**12),
    st.text(alphabet="abcXYZ_-.,\" ;'", min_size=1, max_size=6).filter(lambda s: s == s.strip()),
)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@pytest.mark.parametrize("suffix", SUFFIXES)
@given(data=st.data())
def test_round_trip_property(
    tmp_path_factory: pytest.TempPathFactory, suffix: str, data: st.DataObject
) -> None:
    q = data.draw(st.sampled_from([2, 3]), label="q")
    ids = data.draw(st.lists(_id, max_size=5, unique_by=str), label="ids")
    scenes = {}
    for did in ids:
        n = data.draw(st.integers(0, 4))
        scenes[did] = Scene(
            tuple(
                Obstacle(
                    data.draw(_label),
                    np.array(data.draw(st.lists(_coord, min_size=q, max_size=q))),
                    data.draw(_radius),
                )
                for _ in range(n)
            )
        )
    path = tmp_path_factory.mktemp("rt") / f"scenes{suffix}"
    save_scenes(path, scenes)
    _assert_same(load_scenes(path), scenes)


def test_suffix_is_case_insensitive_and_str_paths_work(tmp_path: Path) -> None:
    scenes = {0: Scene((Obstacle("cup", [1.0, 2.0]),))}
    for name in ("S.CSV", "S.Json"):
        path = str(tmp_path / name)
        save_scenes(path, scenes)
        _assert_same(load_scenes(path), scenes)


# --------------------------------------------------------------------------- #
# Hand-written files
# --------------------------------------------------------------------------- #


def test_csv_hand_written(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "scenes.csv",
        "# obstacles of the kitchen demonstrations\n"
        "Demo, Class ,X,Y,note,Radius\n"
        "\n"
        "b,cup,0.5,0.25,left one,0.03\n"
        "  # a comment between rows\n"
        'b,"big, cup",0.75,0.125,,0.5\n'
        "1,marker,1e-3,-2,,\n"
        "07,,,,nothing here,\n",
    )
    scenes = load_scenes(path)
    assert list(scenes) == ["b", 1, "07"]
    assert scenes["b"].labels == ("cup", "big, cup")
    assert np.array_equal(scenes["b"].positions, [[0.5, 0.25], [0.75, 0.125]])
    assert scenes["b"].radii.tolist() == [0.03, 0.5]
    assert scenes[1].labels == ("marker",)
    assert scenes[1].obstacles[0].position.tolist() == [0.001, -2.0]
    assert scenes[1].obstacles[0].radius == 0.0  # empty cell: default
    assert len(scenes["07"]) == 0


def test_csv_rows_of_one_demo_in_two_places_are_an_error(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "scenes.csv",
        "demo,class,x,y\nb,cup,0,0\nb,box,1,1\n1,cup,2,2\n\nb,cup,3,3\n",
    )
    with pytest.raises(ValueError) as info:
        load_scenes(path)
    assert str(info.value) == (
        f"{path} line 6: demo 'b' continues here, but its rows so far are lines 2-3 and other "
        "demos come between; the rows of one demo must be consecutive (two recordings with "
        "one id?)"
    )


@pytest.mark.parametrize("cell", [" 7", "7 "])
def test_csv_id_with_spaces_is_an_error(tmp_path: Path, cell: str) -> None:
    path = _write(tmp_path / "scenes.csv", f"class,x,y,demo\ncup,0,0,7\nbox,1,1,{cell}\n")
    with pytest.raises(ValueError) as info:
        load_scenes(path)
    assert str(info.value) == (
        f"{path} line 3, column 'demo': id {cell!r} has spaces around it; write ids without "
        "surrounding whitespace ('7')"
    )


@pytest.mark.parametrize("cell", ["0_5", "nan", "infinity", "1 5"])
def test_csv_strict_numbers(tmp_path: Path, cell: str) -> None:
    path = _write(tmp_path / "scenes.csv", f"demo,class,x,y,radius\n1,cup,{cell},0,0.1\n")
    with pytest.raises(ValueError, match=re.escape(f"{path} line 2, column 'x': ")):
        load_scenes(path)


def test_csv_without_demo_or_radius_column_is_one_scene_with_id_0(tmp_path: Path) -> None:
    path = _write(tmp_path / "one.csv", "class,x,y,z\ncup,1,2,3\nbox,4,5,6\n")
    assert list(load_scenes(path)) == [0]
    scene = load_scene(path)
    assert scene.labels == ("cup", "box")
    assert np.array_equal(scene.positions, [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]])
    assert scene.radii.tolist() == [0.0, 0.0]


def test_csv_header_only_without_demo_column_is_one_empty_scene(tmp_path: Path) -> None:
    path = _write(tmp_path / "free.csv", "class,x,y\n")
    scene = load_scene(path)
    assert isinstance(scene, Scene) and len(scene) == 0


def test_csv_utf8_bom_and_crlf(tmp_path: Path) -> None:
    path = tmp_path / "bom.csv"
    path.write_bytes("\ufeffdemo,class,x,y\r\n0,café,1,2\r\n".encode())
    scene = load_scene(path)
    assert scene.labels == ("café",)
    assert scene.obstacles[0].position.tolist() == [1.0, 2.0]


def test_load_scene_accepts_any_single_id(tmp_path: Path) -> None:
    path = _write(tmp_path / "s.csv", "demo,class,x,y,radius\nrun-4,cup,1,2,0.25\n")
    scene = load_scene(path)
    assert scene.labels == ("cup",) and scene.radii.tolist() == [0.25]


def test_json_hand_written(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "scenes.json",
        _json_doc(
            [
                {
                    "demo": "a",
                    "obstacles": [
                        {"class": "cup", "position": [0.5, 1], "radius": 0.03, "color": "red"},
                        {"class": "box", "position": [-1, 2.5e-3]},
                    ],
                },
                {"demo": 4, "obstacles": []},
            ],
            note="extra fields are ignored",
        ),
    )
    scenes = load_scenes(path)
    assert list(scenes) == ["a", 4]
    assert scenes["a"].labels == ("cup", "box")
    assert np.array_equal(scenes["a"].positions, [[0.5, 1.0], [-1.0, 0.0025]])
    assert scenes["a"].radii.tolist() == [0.03, 0.0]
    assert len(scenes[4]) == 0


def test_json_single_scene_without_demo_has_id_0(tmp_path: Path) -> None:
    path = _write(
        tmp_path / "one.json",
        _json_doc([{"obstacles": [{"class": "cup", "position": [1, 2, 3]}]}]),
    )
    assert list(load_scenes(path)) == [0]
    scene = load_scene(path)
    assert scene.obstacles[0].position.tolist() == [1.0, 2.0, 3.0]
    assert scene.obstacles[0].radius == 0.0


# --------------------------------------------------------------------------- #
# Errors: formats and files
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize("name", ["s.npz", "s.txt", "scenes"])
def test_unsupported_suffix(tmp_path: Path, name: str) -> None:
    path = tmp_path / name
    with pytest.raises(ValueError, match=rf"{name}: unsupported file suffix.*\.csv, \.json"):
        load_scenes(path)
    with pytest.raises(ValueError, match=rf"{name}: unsupported file suffix.*\.csv, \.json"):
        save_scenes(path, {0: Scene()})
    assert not path.exists()


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_missing_file_raises_file_not_found(tmp_path: Path, suffix: str) -> None:
    with pytest.raises(FileNotFoundError):
        load_scenes(tmp_path / f"nope{suffix}")
    with pytest.raises(FileNotFoundError):
        load_scene(tmp_path / f"nope{suffix}")


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_load_scene_with_several_scenes(tmp_path: Path, suffix: str) -> None:
    path = save_scenes(tmp_path / f"many{suffix}", {0: Scene(), 1: Scene(), "c": Scene()})
    with pytest.raises(ValueError, match=rf"many\{suffix}: holds 3 scenes.*use load_scenes"):
        load_scene(path)


def test_load_scene_with_no_scene(tmp_path: Path) -> None:
    path = save_scenes(tmp_path / "none.json", {})
    with pytest.raises(ValueError, match=r"none\.json: holds no scene"):
        load_scene(path)


# --------------------------------------------------------------------------- #
# Errors: CSV
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize(
    ("header", "missing"),
    [("demo,x,y", "class"), ("demo,class,y,z", "x"), ("class,x", "y")],
)
def test_csv_missing_required_column(tmp_path: Path, header: str, missing: str) -> None:
    path = _write(tmp_path / "bad.csv", f"# note\n{header}\n")
    found = ", ".join(repr(h) for h in header.split(","))
    with pytest.raises(
        ValueError,
        match=rf"bad\.csv line 2: missing column '{missing}'; found columns: {re.escape(found)}",
    ):
        load_scenes(path)


def test_csv_empty_file(tmp_path: Path) -> None:
    path = _write(tmp_path / "empty.csv", "\n# only a comment\n")
    with pytest.raises(ValueError, match=r"empty\.csv: no header row"):
        load_scenes(path)


def test_csv_duplicate_column(tmp_path: Path) -> None:
    path = _write(tmp_path / "dup.csv", "class,x,y,X\ncup,1,2,3\n")
    with pytest.raises(ValueError, match=r"dup\.csv line 1: duplicate column 'X'"):
        load_scenes(path)


@pytest.mark.parametrize(
    ("row", "column", "what"),
    [
        ("0,cup,abc,1,0", "x", "could not read 'abc' as a number"),
        ("0,cup,1,nan,0", "y", "value 'nan' is not finite"),
        ("0,cup,1,-inf,0", "y", "value '-inf' is not finite"),
        ("0,cup,1,2,1e999", "radius", "value '1e999' is not finite"),
        ("0,cup,1,2,wide", "radius", "could not read 'wide' as a number"),
        ("0,cup,1,2,-0.5", "radius", "radius '-0.5' is negative"),
        ("0,,1,2,0", "class", r"empty value, but the row has coordinates \(x, y\)"),
        ("0,,,2,", "class", r"empty value, but the row has coordinates \(y\)"),
        ("0,cup,,2,0", "x", "empty value; the row has class 'cup', so it needs coordinates"),
        ("0,cup,1,,", "y", "empty value; the row has class 'cup', so it needs coordinates"),
        (",cup,1,2,0", "demo", "empty value"),
    ],
)
def test_csv_bad_cell_names_file_line_and_column(
    tmp_path: Path, row: str, column: str, what: str
) -> None:
    path = _write(tmp_path / "bad.csv", f"demo,class,x,y,radius\n0,box,0,0,0\n\n{row}\n")
    with pytest.raises(ValueError, match=rf"bad\.csv line 4, column '{column}': {what}"):
        load_scenes(path)


def test_csv_empty_z_is_mixed_dimensions(tmp_path: Path) -> None:
    path = _write(tmp_path / "mixed.csv", "demo,class,x,y,z\n0,cup,1,2,3\n1,box,1,2,\n")
    with pytest.raises(ValueError, match=r"mixed\.csv line 3, column 'z': .*mixed 2-D and 3-D"):
        load_scenes(path)


def test_csv_wrong_number_of_fields(tmp_path: Path) -> None:
    path = _write(tmp_path / "short.csv", "demo,class,x,y\n0,cup,1,2\n0,cup,1\n")
    with pytest.raises(ValueError, match=r"short\.csv line 3: expected 4 fields .* got 3"):
        load_scenes(path)


def test_csv_empty_scene_row_conflicts_with_obstacles(tmp_path: Path) -> None:
    path = _write(tmp_path / "c.csv", "demo,class,x,y\n5,,,\n5,cup,1,2\n")
    with pytest.raises(ValueError, match=r"c\.csv line 3: gives demo '5' an obstacle.*line 2"):
        load_scenes(path)
    path = _write(tmp_path / "d.csv", "demo,class,x,y\n5,cup,1,2\n5,,,\n")
    with pytest.raises(
        ValueError, match=r"d\.csv line 3: marks demo '5' as having no obst.*line 2"
    ):
        load_scenes(path)


def test_csv_radius_without_obstacle(tmp_path: Path) -> None:
    path = _write(tmp_path / "r.csv", "demo,class,x,y,radius\n5,,,,0.1\n")
    with pytest.raises(ValueError, match=r"r\.csv line 2, column 'class': empty value.*radius"):
        load_scenes(path)


def test_csv_not_utf8(tmp_path: Path) -> None:
    path = tmp_path / "latin.csv"
    path.write_bytes("class,x,y\ncaf\xe9,1,2\n".encode("latin-1"))
    with pytest.raises(ValueError, match=r"latin\.csv: not UTF-8"):
        load_scenes(path)


# --------------------------------------------------------------------------- #
# Errors: JSON
# --------------------------------------------------------------------------- #


def _ob(**kw: object) -> dict:
    return {"class": "cup", "position": [0.0, 1.0], **kw}


def _one(*obstacles: object) -> list:
    """A scenes list with one scene (id 0) holding ``obstacles``."""
    return [{"demo": 0, "obstacles": list(obstacles)}]


_OB0 = "scenes[0].obstacles[0]"

JSON_ERRORS = [
    (_one(_ob(position=[1, "a"])), f"{_OB0}.position[1]", "expected a number"),
    (_one(_ob(position=[1, True])), f"{_OB0}.position[1]", "expected a number"),
    (_one(_ob(position=[1])), f"{_OB0}.position", "expected a list of 2 or 3 numbers"),
    (_one(_ob(position=[1, 2, 3, 4])), f"{_OB0}.position", "expected a list of 2 or 3 numbers"),
    (_one(_ob(position="1, 2")), f"{_OB0}.position", "expected a list of 2 or 3 numbers"),
    (_one(_ob(radius=-0.1)), f"{_OB0}.radius", "radius -0.1 is negative"),
    (_one(_ob(radius="big")), f"{_OB0}.radius", "expected a number"),
    (_one(_ob(radius=None)), f"{_OB0}.radius", "expected a number"),
    (_one(_ob(), _ob(**{"class": ""})), "scenes[0].obstacles[1].class", "expected a non-empty"),
    (_one({"position": [0, 0]}), f"{_OB0}.class", "expected a non-empty string"),
    (_one("cup"), _OB0, "expected an object"),
    (
        [*_one(_ob()), {"demo": 1, "obstacles": [_ob(), _ob(position=[1, 2, 3])]}],
        "scenes[1].obstacles[1].position",
        f"has 3 coordinates but {_OB0}.position has 2; mixed 2-D and 3-D",
    ),
    (
        [
            {"demo": "a", "obstacles": []},
            {"demo": 1, "obstacles": []},
            {"demo": "a", "obstacles": []},
        ],
        "scenes[2].demo",
        "demo id 'a' repeats scenes[0]",
    ),
    (
        [{"demo": 7, "obstacles": []}, {"demo": "7", "obstacles": []}],
        "scenes[1].demo",
        "demo id '7'",
    ),
    ([*_one(), {"obstacles": []}], "scenes[1]", "missing field 'demo'"),
    ([{"demo": True, "obstacles": []}], "scenes[0].demo", "expected an int or a non-empty str"),
    ([{"demo": ""}], "scenes[0].demo", "expected an int or a non-empty str"),
    ([{"demo": 0}], "scenes[0].obstacles", "expected a list of obstacles"),
    ([3], "scenes[0]", "expected an object"),
]


@pytest.mark.parametrize(("scenes", "where", "what"), JSON_ERRORS)
def test_json_bad_field_names_file_and_path(
    tmp_path: Path, scenes: list, where: str, what: str
) -> None:
    path = _write(tmp_path / "bad.json", _json_doc(scenes))
    with pytest.raises(ValueError, match=re.escape(f"bad.json: {where}: {what}")):
        load_scenes(path)


def test_json_repeated_key_is_an_error(tmp_path: Path) -> None:
    text = _json_doc(_one(_ob(radius=0.5))).replace('"radius": 0.5', '"radius": 0.5, "radius": 1')
    path = _write(tmp_path / "dup.json", text)
    with pytest.raises(ValueError) as info:
        load_scenes(path)
    assert str(info.value) == (
        f"{path}: scenes[0].obstacles[0]: key 'radius' appears more than once in one object; "
        "each key may be given once"
    )


def test_json_repeated_scenes_list_is_an_error(tmp_path: Path) -> None:
    text = _json_doc(_one(_ob())).replace('"scenes":', '"scenes": [], "scenes":')
    path = _write(tmp_path / "dup.json", text)
    with pytest.raises(ValueError, match=re.escape(f"{path}: (top level): key 'scenes' appears")):
        load_scenes(path)


@pytest.mark.parametrize("text", ["[" * 100_000, '{"a":' * 100_000, "[{" * 40 + "}]" * 40])
def test_json_deep_nesting_is_a_clear_error(tmp_path: Path, text: str) -> None:
    path = _write(tmp_path / "deep.json", text)
    with pytest.raises(ValueError, match=re.escape(f"{path}: JSON nested too deep (more than 64")):
        load_scenes(path)


def test_files_over_the_size_cap_are_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import lfdkit.io.text

    for suffix in SUFFIXES:
        path = tmp_path / f"s{suffix}"
        save_scenes(path, {0: Scene((Obstacle("cup", [0.0, 1.0], 0.1),))})
        monkeypatch.setattr(lfdkit.io.text, "MAX_FILE_BYTES", path.stat().st_size - 1)
        with pytest.raises(ValueError, match=re.escape(f"{path}: file too large (")):
            load_scenes(path)
        monkeypatch.undo()


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs FIFOs")
def test_fifo_is_neither_read_nor_replaced(tmp_path: Path) -> None:
    from lfdkit.io import NotRegularFileError

    for suffix in SUFFIXES:
        fifo = tmp_path / f"pipe{suffix}"
        os.mkfifo(fifo)
        with pytest.raises(NotRegularFileError, match="is a named pipe"):
            load_scenes(fifo)
        with pytest.raises(NotRegularFileError, match="is a named pipe"):
            save_scenes(fifo, {0: Scene()}, overwrite=True)
        assert stat.S_ISFIFO(os.lstat(fifo).st_mode)


def test_json_overflowing_coordinate(tmp_path: Path) -> None:
    text = _json_doc([{"demo": 0, "obstacles": [_ob(position=[0.0, 123.0])]}])
    path = _write(tmp_path / "nf.json", text.replace("123.0", "1e999"))
    with pytest.raises(
        ValueError, match=r"nf\.json: scenes\[0\]\.obstacles\[0\]\.position\[1\]: .*not finite"
    ):
        load_scenes(path)


@pytest.mark.parametrize("value", ["NaN", "Infinity", "-Infinity"])
def test_json_non_finite_literal_names_line(tmp_path: Path, value: str) -> None:
    text = _json_doc([{"demo": 0, "obstacles": [_ob(position=[0.0, 123.0])]}])
    text = text.replace("123.0", value)
    line = text[: text.index(value)].count("\n") + 1
    path = _write(tmp_path / "nf.json", text)
    with pytest.raises(
        ValueError, match=rf"nf\.json: line {line}, column \d+: {value} is not a JSON number"
    ):
        load_scenes(path)


def test_json_newer_version(tmp_path: Path) -> None:
    path = _write(tmp_path / "new.json", _json_doc([], version=SCENE_JSON_VERSION + 1))
    with pytest.raises(
        ValueError,
        match=rf"new\.json: file format version {SCENE_JSON_VERSION + 1} was written by a newer "
        rf"lfdkit; this lfdkit reads up to version {SCENE_JSON_VERSION}",
    ):
        load_scenes(path)


@pytest.mark.parametrize("version", [0, "1", None, 1.0])
def test_json_bad_version(tmp_path: Path, version: object) -> None:
    path = _write(tmp_path / "v.json", _json_doc([], version=version))
    with pytest.raises(ValueError, match=r"v\.json: .*version"):
        load_scenes(path)


@pytest.mark.parametrize("fmt", ["lfdkit-demos", None, "scenes"])
def test_json_wrong_format(tmp_path: Path, fmt: object) -> None:
    path = _write(tmp_path / "f.json", _json_doc([], format=fmt))
    with pytest.raises(ValueError, match=rf"f\.json: field 'format' is {re.escape(repr(fmt))}"):
        load_scenes(path)


def test_json_that_does_not_parse(tmp_path: Path) -> None:
    path = _write(tmp_path / "broken.json", '{\n  "format": "lfdkit-scenes",\n  "version": 1,\n]')
    with pytest.raises(ValueError, match=r"broken\.json: line 4: not valid JSON at column \d+"):
        load_scenes(path)


@pytest.mark.parametrize("text", ["[]", '{"format": "lfdkit-scenes", "version": 1}'])
def test_json_wrong_structure(tmp_path: Path, text: str) -> None:
    path = _write(tmp_path / "s.json", text)
    with pytest.raises(ValueError, match=r"s\.json: (expected a JSON object|field 'scenes')"):
        load_scenes(path)


# --------------------------------------------------------------------------- #
# Saving
# --------------------------------------------------------------------------- #


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_save_refuses_to_overwrite(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"s{suffix}"
    old = {0: Scene((Obstacle("cup", [1.0, 2.0]),))}
    new = {"b": Scene((Obstacle("box", [3.0, 4.0], 0.5),)), "c": Scene()}
    save_scenes(path, old)
    before = path.read_bytes()
    expected = rf"s\{suffix}: file already exists; allow overwriting.*overwrite=True"
    with pytest.raises(FileExistsError, match=expected):
        save_scenes(path, new)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]  # no temporary left
    save_scenes(path, new, overwrite=True)
    _assert_same(load_scenes(path), new)


def test_save_csv_layout(tmp_path: Path) -> None:
    scenes = {
        "a": Scene((Obstacle("cup", [0.1, 0.2, 0.3], 0.03),)),
        2: Scene(),
    }
    path = save_scenes(tmp_path / "s.csv", scenes)
    assert path.read_text() == "demo,class,x,y,z,radius\na,cup,0.1,0.2,0.3,0.03\n2,,,,,\n"
    path = save_scenes(tmp_path / "t.csv", {0: Scene((Obstacle("cup", [1.0, 2.0]),))})
    assert path.read_text() == "demo,class,x,y,radius\n0,cup,1.0,2.0,0.0\n"


def test_save_json_layout(tmp_path: Path) -> None:
    path = save_scenes(tmp_path / "s.json", {"a": Scene((Obstacle("cup", [0.1, 0.2]),))})
    doc = json.loads(path.read_text())
    assert doc == {
        "format": "lfdkit-scenes",
        "version": 1,
        "scenes": [
            {"demo": "a", "obstacles": [{"class": "cup", "position": [0.1, 0.2], "radius": 0.0}]}
        ],
    }


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_save_rejects_mixed_dimensions(tmp_path: Path, suffix: str) -> None:
    scenes = {0: Scene((Obstacle("a", [0, 0]),)), 1: Scene(), 2: Scene((Obstacle("a", [0, 0, 0]),))}
    with pytest.raises(ValueError, match=r"scenes\[2\]: 3-D positions but scenes\[0\] is 2-D"):
        save_scenes(tmp_path / f"s{suffix}", scenes)
    assert not (tmp_path / f"s{suffix}").exists()


@pytest.mark.parametrize(
    ("scenes", "error", "match"),
    [
        ({7: Scene(), "7": Scene()}, ValueError, r"scenes: bad demo id.*repeats"),
        ({"#x": Scene()}, ValueError, r"scenes: bad demo id.*'#x' is not a valid id"),
        ({" a": Scene()}, ValueError, r"scenes: bad demo id.*' a' is not a valid id"),
        ({True: Scene()}, TypeError, r"scenes: bad demo id"),
        ({0: [Obstacle("cup", [0, 0])]}, TypeError, r"scenes\[0\]: expected a Scene"),
        ([Scene()], TypeError, r"scenes: expected a mapping"),
    ],
)
def test_save_rejects_bad_input(
    tmp_path: Path, scenes: object, error: type[Exception], match: str
) -> None:
    with pytest.raises(error, match=match):
        save_scenes(tmp_path / "s.json", scenes)  # type: ignore[arg-type]
    assert not (tmp_path / "s.json").exists()


@pytest.mark.parametrize("label", [" cup", "cup\n", "a\rb"])
def test_save_csv_rejects_labels_it_cannot_store(tmp_path: Path, label: str) -> None:
    scenes = {0: Scene((Obstacle(label, [0.0, 0.0]),))}
    with pytest.raises(ValueError, match=r"scenes\[0\]\.obstacles\[0\]: label .*use a \.json"):
        save_scenes(tmp_path / "s.csv", scenes)
    _assert_same(load_scenes(save_scenes(tmp_path / "s.json", scenes)), scenes)
