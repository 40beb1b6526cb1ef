"""Tests for lfdkit.tasks.sweeping.examples: the shipped example files of the sweeping task."""

from __future__ import annotations

from pathlib import Path

import pytest

import lfdkit.tasks.sweeping as sweeping
from lfdkit.tasks.sweeping.examples import example_files, write_example_files


def test_shipped_example_files_are_what_the_demonstrator_writes(tmp_path: Path) -> None:
    written = write_example_files(tmp_path)
    files = example_files()
    assert set(files) == set(written) == {"demos", "scenes", "test_demos", "test_scenes"}
    for stem, path in files.items():
        assert path.read_bytes() == written[stem].read_bytes(), stem


def test_the_files_ship_beside_the_task_as_package_data() -> None:
    for path in example_files().values():
        assert path.parent == Path(sweeping.__file__).parent / "data"
        assert path.is_file()
    pyproject = Path(__file__).parents[3] / "pyproject.toml"
    if pyproject.is_file():  # a source checkout: the files are declared package data
        assert '"tasks/*/data/*.csv"' in pyproject.read_text()


def test_unknown_example_names_the_available_ones() -> None:
    with pytest.raises(ValueError, match=r"^name: no example 'wiping'; available: sweeping$"):
        example_files("wiping")
