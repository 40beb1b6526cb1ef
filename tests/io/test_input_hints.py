"""File readers say what is wrong with a file a new user wrote, not what a library tripped on."""

from __future__ import annotations

import pytest

from lfdkit.io import load_demos, load_scenes


@pytest.mark.parametrize(
    ("text", "hint"),
    [
        ("demo;x;y\na;0;0\na;1;1\n", "the file looks ';'-separated: write it with commas"),
        ("demo\tx\ty\na\t0\t0\na\t1\t1\n", "the file looks tab-separated: write it with commas"),
        ("a,0.0,0.5\na,1.0,0.5\n", "the first row holds numbers: the file needs a header row"),
    ],
)
def test_a_demonstrations_header_without_its_columns_says_why(tmp_path, text, hint) -> None:
    path = tmp_path / "demos.csv"
    path.write_text(text)
    with pytest.raises(ValueError, match=rf"missing column 'x'; found columns: .*; {hint}"):
        load_demos(path)


def test_a_scene_header_separated_by_semicolons_says_so(tmp_path) -> None:
    path = tmp_path / "scenes.csv"
    path.write_text("demo;class;x;y\na;cup;0;0.4\n")
    with pytest.raises(ValueError, match=r"missing column 'class'.*looks ';'-separated"):
        load_scenes(path)


def test_a_header_with_its_columns_gets_no_hint(tmp_path) -> None:
    path = tmp_path / "demos.csv"
    path.write_text("demo,x\na,0\na,1\n")
    with pytest.raises(ValueError, match=r"found columns: 'demo', 'x'$"):
        load_demos(path)


def test_an_npz_of_a_zip_version_python_cannot_read_is_refused_in_one_line(tmp_path) -> None:
    # Found by the readers' fuzz test: zipfile raised NotImplementedError from inside it.
    data = (
        b"PK\x03\x04-\x00\x00\x00\x00\x00\x00\x00!\x00\xa10\x8a\x81\xff\xff\xff\xff\xff\xff\xff"
        b"\xff\n\x00\x14\x00demo_0.npy\x01\x00\x10\x00\x88\x00\x00\x00\x00\x00\x00\x00\x88\x00"
        b"\x00\x00\x00\x00\x00\x00\x93NUMPY\x01\x00v\x00{'descr': '<f8', 'fortran_order': False,"
        b" 'shape': (), }" + b" " * 62 + b"\n\x00\x00\x00\x00\x00\x00\x00\x00PK\x01\x02-\x03m\x00"
        b"\x00\x00\x00\x00\x00\x00!\x00\xa10\x8a\x81\x88\x00\x00\x00\x88\x00\x00\x00\n\x00\x00"
        b"\x00\x00\x00\x00\x00\x00\x00\x00\x00\x80\x01\x00\x00\x00\x00demo_0.npyPK\x05\x06\x00"
        b"\x00\x00\x00\x01\x00\x01\x008\x00\x00\x00\xc4\x00\x00\x00\x00\x00"
    )
    path = tmp_path / "demos.npz"
    path.write_bytes(data)
    with pytest.raises(ValueError, match=r"could not read as an \.npz archive \(zip file version"):
        load_demos(path)
