"""Skill files: a fitted skill's state as one JSON document, written and read back strictly.

Format
------
One JSON object, ``{"format": "lfdkit-skill", "version": 1, ...}``, with
every number written exactly (floats round-trip bit for bit) and no pickle:

``params``
    The constructor parameters.
``n_dims``, ``units``
    Dimension of the paths and their unit (``"m"``, ``"cm"`` or ``"mm"``,
    also in ``params``); a file without ``units`` is in metres.
``path``
    The generalized path, ``(n_points, n_dims)`` nested lists.
``timing``
    Only when the timing was learned from timed demonstrations (or given):
    ``{"source": ..., "duration": T, "speed": [B-spline coefficients of the
    normalised speed], "demo_durations": [...]}``
    (:meth:`lfdkit.imitate.SpeedProfile.to_dict`). Without it the timing is
    the ``timing`` law over ``duration`` of ``params``; a file without it
    reads as before timings were learned (and an older lfdkit reading a file
    with it plans the same path with that law's timing).
``orientation``
    Only for a skill with the tool's orientation: ``{"mean": [[qx, qy, qz,
    qw], ...]}``, the mean orientation at each point of ``path`` (unit
    quaternions, one per row of ``path``). The orientation DMP is fitted on
    them again when the file is read (a deterministic fit, as the position
    DMP from ``path``), so the loaded skill plans the same orientations. A
    file without it is a skill without orientation; an older lfdkit reading
    a file with it ignores the field and plans positions only.
``dmp``
    The fitted DMP as it plans (:meth:`lfdkit.imitate.DMP.to_state` without
    its ``path``, which is ``path``): parameters, weights, training times,
    timing, the forced response at its knots and a SHA-256 ``checksum`` of
    them, with its own ``version``; its arrays as base64 of little-endian
    doubles (:func:`pack_arrays`: exact, and parsed 40 times faster than
    decimals). The reader restores it without refitting
    (milliseconds, where the fit takes 0.1 to 18 s), so a loaded skill plans
    to the bit as the saved one. A file without it (written before issue 30)
    is refitted on reading, as before; one whose checksum does not match (the
    path or the state edited) is refused. ``orientation.dmp`` holds the
    orientation DMP likewise (its own path included). An older lfdkit reading
    a file with them ignores them and refits.
``emulation``
    Only for a skill whose obstacle reward was fitted (issue 26): ``{"route":
    "lookahead" | "window" | "full" | "taut", "clearances": {class: units}[, "radii":
    {class: units}][, "frame": "path"][, "gaps": "open"][, "return_fraction": r]}``,
    the route planner its plans use, the clearance kept at least from each class's
    obstacles, the median radius of the obstacles each class was learned from, where not
    the world's, the frame the learned responses turn with, where they do, that the
    clearances give way between two obstacles, and where the slow-return model was
    chosen, its bound on the step back toward the nominal (a fraction of the action
    bound; without it, 1) (:attr:`lfdkit.skill.Skill.route_`,
    :attr:`lfdkit.skill.Skill.clearances_`, :attr:`lfdkit.skill.Skill.class_radii_`,
    :attr:`lfdkit.skill.Skill.frame_`, :attr:`lfdkit.skill.Skill.gaps_`,
    :attr:`lfdkit.skill.Skill.return_fraction_`). A file without it plans as
    before (MPC with lookahead, no learned clearance); an older lfdkit
    reading a file with it ignores it.
``promp``
    Only for a skill learned from demonstrations (issue 33): their ProMP
    (:meth:`lfdkit.imitate.ProMP.to_state`: parameters, basis width, the
    weights' mean and covariance as :func:`pack_arrays`), which shapes how
    plans bend through via-points. A file without it bends them smoothly; an
    older lfdkit reading a file with it ignores it.
``mimic``
    How the path was made: ``{"method": ..., "n_demos": ...}`` and the
    method's diagnostics.
``reward``
    ``null`` or ``{"nominal_weight": Q, "precisions": {class: (q, q) nested
    lists}}`` in 1/units².
``ioc``
    ``null`` or a summary of the reward fit (loss, stages, demonstrations,
    convergence, classes not learned, identifiability of each parameter).
``lfdkit``
    The version that wrote it.

The same state always gives the same document and the same bytes: it holds
no date and no run times (the ``"seconds"`` entries of the diagnostics are
left out), so skill files can be compared and cached.

This module knows the format only, not :class:`lfdkit.skill.Skill`: it turns
plain data (the parameters, the path, the reward's weight and matrices, the
diagnostics) into a document (:func:`to_document`) and reads a document back
field by field (:class:`SkillDocument`), each field checked and every error
naming the file and the field. The skill assembles itself from those fields.

Reading is strict (:func:`lfdkit.io.text.load_json`: no repeated keys, no
NaN, bounded depth), at most :data:`MAX_SKILL_FILE_BYTES`, and the numeric
parameters must lie in :data:`SKILL_FILE_LIMITS`. A file from a newer format
version, or one with a missing or broken field, is refused. Writing is
atomic (:func:`lfdkit.io.atomic.write_text`).
"""

from __future__ import annotations

import base64
import binascii
import json
import math
import os
from collections.abc import Collection, Mapping, Sequence
from pathlib import Path
from typing import Any, Self

import numpy as np

from lfdkit import __version__
from lfdkit.io.atomic import write_text
from lfdkit.io.text import json_float_array, load_json
from lfdkit.model.demos import PathLike

__all__ = [
    "MAX_REFIT_BASIS",
    "MAX_SKILL_FILE_BYTES",
    "PERIODIC_FORMAT",
    "ROUTES",
    "SKILL_FILE_LIMITS",
    "SKILL_FORMAT",
    "SKILL_VERSION",
    "TASK_FRAME_FORMAT",
    "SavedToSkillFile",
    "SkillDocument",
    "check_file_params",
    "check_skill_path",
    "is_periodic_document",
    "jsonable",
    "made_from_document",
    "pack_arrays",
    "read_skill_file",
    "to_document",
    "unpack_arrays",
    "write_skill_file",
]

SKILL_FORMAT = "lfdkit-skill"
"""Value of the ``"format"`` field of a skill file."""

SKILL_VERSION = 1
"""Newest skill-file version this module reads, and the one it writes."""

PERIODIC_FORMAT = "lfdkit-periodic-skill"
"""Value of the ``"format"`` field of a periodic skill file (:mod:`lfdkit.skill.periodic`)."""

TASK_FRAME_FORMAT = "lfdkit-task-frame-skill"
"""Value of the ``"format"`` field of a task-frame skill file (:mod:`lfdkit.skill.task_frames`)."""

#: Route planners a skill file may name (:attr:`lfdkit.skill.Skill.route_`).
ROUTES = ("lookahead", "window", "full", "taut")
#: Frames of the learned responses a skill file may name (:attr:`lfdkit.skill.Skill.frame_`).
FRAMES = ("world", "path")
#: Whether two obstacles' clearances may close the gap between them (``emulation.gaps``).
GAPS = ("closed", "open")

# Points of a path or plan: the planner's memory grows linearly with them.
_MAX_POINTS = 100_000

MAX_SKILL_FILE_BYTES = 32 * 1024**2
"""Largest skill file :func:`read_skill_file` reads, in bytes (32 MiB).

A skill with the longest path allowed (100 000 points in 3-D) takes about 8 MB."""

SKILL_FILE_LIMITS: dict[str, tuple[float, float]] = {
    "n_points": (3, _MAX_POINTS),
    "n_components": (1, 1000),
    "n_basis": (1, 1000),
    "duration": (0.0, 1e6),
    "max_slope": (0.0, 1e6),
}
"""Ranges :meth:`lfdkit.skill.Skill.load` accepts for the numeric ``params`` of a skill file.

``(low, high)``: integers ``low <= n <= high`` (``n_basis`` and
``duration`` may also be ``"auto"``); ``duration`` (seconds) and ``max_slope`` in ``(low, high]``.
Far beyond any robot task (DMPs use tens of basis functions), they keep a
corrupt or hostile file from asking for gigabytes or minutes
(``n_basis = 10**4``: the DMP's own limit, :data:`lfdkit.imitate.primitive.MAX_BASIS`,
is 1000; a file that stores the fitted DMP loads without refitting, one
without it refits in a time growing with ``n_basis**2``, 18 s at 1000) or
overflowing (``duration = 1e300``). The stored ``path`` has at most the ``n_points``
limit of rows."""

#: Most basis functions a file without the fitted DMP (``dmp``) may ask to refit: the
#: limit of every file before the DMP was stored (refitting 1000 takes about 18 s).
MAX_REFIT_BASIS = 200

# The parameters of SKILL_FILE_LIMITS that are counts (the others are reals).
_INTEGER_PARAMS = ("n_points", "n_components", "n_basis")


# --------------------------------------------------------------------------- #
# Writing
# --------------------------------------------------------------------------- #


def to_document(
    params: Mapping[str, Any],
    *,
    n_dims: int,
    units: str,
    path: np.ndarray,
    mimic_info: Mapping[str, Any],
    reward: tuple[float, Mapping[str, np.ndarray]] | None,
    ioc_info: Mapping[str, Any] | None,
    timing: Mapping[str, Any] | None = None,
    orientations: np.ndarray | None = None,
    emulation: Mapping[str, Any] | None = None,
    dmp: Mapping[str, Any] | None = None,
    orientation_dmp: Mapping[str, Any] | None = None,
    promp: Mapping[str, Any] | None = None,
) -> dict[str, Any]:
    """A skill's state as a JSON-ready dict (the format of the module notes).

    Parameters
    ----------
    params : mapping
        The skill's constructor parameters.
    n_dims : int
        Dimension of the paths, 2 or 3.
    units : str
        Unit of the paths.
    path : ndarray, shape (n_points, n_dims)
        The generalized path.
    mimic_info, ioc_info : mapping or None
        Diagnostics of the path and of the reward fit; their ``"seconds"``
        entries (run times) are left out at any depth, NumPy values become
        plain JSON values and non-finite floats ``None``.
    reward : (float, mapping of {str: ndarray (n_dims, n_dims)}) or None
        The reward's nominal weight and precision matrix per obstacle class.
    timing : mapping or None
        A learned timing (:meth:`lfdkit.imitate.SpeedProfile.to_dict`), or
        None when it is the law of ``params`` (then no ``timing`` field).
    orientations : ndarray, shape (n_points, 4), or None
        The mean orientation at each path point (unit quaternions), or None
        (then no ``orientation`` field).
    emulation : mapping or None
        ``{"route": str, "clearances": {class: float}, "radii": {class: float}}``
        (``radii``, ``frame`` and ``gaps`` optional), or None (then no
        ``emulation`` field).
    dmp : mapping or None
        The fitted DMP (:meth:`lfdkit.imitate.DMP.to_state`) without its
        ``path`` (the document's ``path``), or None (then no ``dmp`` field).
    orientation_dmp : mapping or None
        The fitted orientation DMP (:meth:`lfdkit.imitate.QuaternionDMP.to_state`),
        stored as ``orientation.dmp``; None for none.
    promp : mapping or None
        The demonstrations' ProMP (:meth:`lfdkit.imitate.ProMP.to_state`),
        stored as ``promp``; None for none.

    Returns
    -------
    dict
        The document, keys in file order.
    """
    reward_doc = None
    if reward is not None:
        weight, precisions = reward
        reward_doc = {
            "nominal_weight": float(weight),
            "precisions": {c: m.tolist() for c, m in precisions.items()},
        }
    document = {
        "format": SKILL_FORMAT,
        "version": SKILL_VERSION,
        "lfdkit": __version__,
        "params": jsonable(params),
        "n_dims": n_dims,
        "units": units,
        "path": path.tolist(),
    }
    if timing is not None:
        document["timing"] = jsonable(timing)
    if orientations is not None:
        document["orientation"] = {"mean": np.asarray(orientations, dtype=np.float64).tolist()}
        if orientation_dmp is not None:
            document["orientation"]["dmp"] = pack_arrays(orientation_dmp)
    if emulation is not None:
        document["emulation"] = jsonable(emulation)
    document |= {
        "mimic": _without_timing(jsonable(mimic_info)),
        "reward": reward_doc,
        "ioc": _without_timing(jsonable(ioc_info)),
    }
    if promp is not None:
        document["promp"] = pack_arrays(promp)
    if dmp is not None:  # last: the long arrays after what a reader looks at
        document["dmp"] = pack_arrays(dmp)
    return document


def check_skill_path(path: PathLike) -> Path:
    """``path`` as a ``Path``, refused when it is a directory (before any work is done).

    Raises
    ------
    IsADirectoryError
        If ``path`` is a directory.
    """
    target = Path(path)
    if target.is_dir():
        raise IsADirectoryError(f"{target}: is a directory; give a file name like skill.json")
    return target


def write_skill_file(path: PathLike, document: Mapping[str, Any], *, overwrite: bool) -> Path:
    """Write :func:`to_document`'s output to ``path`` as indented JSON (:func:`write_text`).

    Returns the file written; an existing ``path`` raises
    :class:`~lfdkit.io.atomic.OutputExistsError` (a ``FileExistsError``)
    unless ``overwrite``.
    """
    text = json.dumps(document, indent=1, allow_nan=False)
    return write_text(path, text + "\n", overwrite=overwrite)


def jsonable(value: Any) -> Any:
    """``value`` in plain JSON types (NumPy scalars and arrays converted); non-finite floats None.

    Mappings become dicts with ``str`` keys, tuples lists; what a skill keeps
    in its diagnostics goes through this before it is stored.
    """
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return jsonable(value.tolist())
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    return value


def pack_arrays(value: Any) -> Any:
    """:func:`jsonable`, with float arrays as ``{"shape": [...], "float64le": base64}``.

    The bytes are the array's little-endian IEEE doubles: exact, and read
    back (:func:`unpack_arrays`) far faster than decimal numbers: a DMP of
    1000 basis functions stores 50 000 numbers, 1.1 MB of JSON decimals that
    took 0.2 s to parse, against 0.5 MB of base64 and a few milliseconds.
    """
    if isinstance(value, np.ndarray) and value.dtype.kind in "fiu":
        data = np.ascontiguousarray(value, dtype="<f8").tobytes()
        return {"shape": list(value.shape), "float64le": base64.b64encode(data).decode("ascii")}
    if isinstance(value, Mapping):
        return {str(k): pack_arrays(v) for k, v in value.items()}
    return jsonable(value)


def unpack_arrays(value: Any, where: str) -> Any:
    """:func:`pack_arrays`'s output with its arrays decoded; errors start with ``where``."""
    if isinstance(value, Mapping) and set(value) == {"shape", "float64le"}:
        shape, text = value["shape"], value["float64le"]
        if not isinstance(shape, list) or not all(
            isinstance(n, int) and not isinstance(n, bool) and 0 <= n <= _MAX_POINTS * 100
            for n in shape
        ):
            raise ValueError(f"{where}.shape: expected a list of counts, got {shape!r}")
        try:
            data = base64.b64decode(text.encode("ascii"), validate=True)
        except (AttributeError, UnicodeEncodeError, binascii.Error):
            raise ValueError(f"{where}.float64le: expected base64 text") from None
        if len(data) != 8 * math.prod(shape):
            raise ValueError(
                f"{where}.float64le: holds {len(data) // 8} numbers, the shape {shape} "
                f"needs {math.prod(shape)}"
            )
        array = np.frombuffer(data, dtype="<f8").astype(np.float64).reshape(shape)
        if not np.all(np.isfinite(array)):
            raise ValueError(f"{where}: contains NaN or infinite values")
        return array
    if isinstance(value, Mapping):
        return {k: unpack_arrays(v, f"{where}.{k}") for k, v in value.items()}
    return value


def _without_timing(value: Any) -> Any:
    """``value`` without its ``"seconds"`` entries, at any depth (run times vary run to run)."""
    if isinstance(value, dict):
        return {k: _without_timing(v) for k, v in value.items() if k != "seconds"}
    if isinstance(value, list):
        return [_without_timing(v) for v in value]
    return value


# --------------------------------------------------------------------------- #
# Reading
# --------------------------------------------------------------------------- #


def read_skill_file(path: PathLike) -> Mapping[str, Any]:
    """Parse a skill file strictly; the top-level object, its fields not yet checked.

    The file is read with :func:`lfdkit.io.text.load_json` (at most
    :data:`MAX_SKILL_FILE_BYTES`, UTF-8 text, valid JSON without repeated
    keys or NaN); anything else, or a document that is not a JSON object,
    raises ``ValueError`` naming the file. A missing file raises
    ``FileNotFoundError``.
    """
    name = os.fspath(path)
    data = load_json(name, max_bytes=MAX_SKILL_FILE_BYTES)
    if not isinstance(data, Mapping):
        raise ValueError(f"{name}: expected a JSON object at the top level")
    return data


class SkillDocument:
    """The fields of a parsed skill file, read one at a time, each checked.

    Construction checks the format and the version; each method then reads
    one field and returns plain data. Errors are ``ValueError`` starting with
    ``source`` and naming the field (``"f.json: reward.precisions.cup[0][1]:
    expected a number, got a string"``). A reader calls the methods in the
    order it needs the fields, so that a file with several faults is reported
    at the first one met.

    Parameters
    ----------
    data : mapping
        The parsed document (:func:`read_skill_file`, or :func:`to_document`'s
        output passed through JSON).
    source : str
        The file name (or another label) that starts every message.
    """

    def __init__(self, data: Any, source: str) -> None:
        field = _FieldReader(data, source)
        if field.get("format", str) != SKILL_FORMAT:
            raise ValueError(
                f"{source}: not an lfdkit skill (format {data.get('format')!r}, "
                f"expected {SKILL_FORMAT!r})"
            )
        version = field.get("version", int)
        if version > SKILL_VERSION:
            raise ValueError(
                f"{source}: skill file version {version} was written by a newer lfdkit "
                f"({data.get('lfdkit', '?')}); this lfdkit {__version__} reads up to version "
                f"{SKILL_VERSION}. Upgrade lfdkit"
            )
        if version < 1:
            raise ValueError(f"{source}: version: expected >= 1, got {version}")
        self.data: Mapping[str, Any] = data
        self.source = source
        self._field = field

    def params(self, known: Collection[str]) -> dict[str, Any]:
        """The constructor parameters, names among ``known``, in :data:`SKILL_FILE_LIMITS`."""
        params = self._field.get("params", dict)
        unknown = sorted(set(params) - set(known))
        if unknown:
            raise ValueError(f"{self.source}: params.{unknown[0]}: unknown parameter")
        check_file_params(params, self.source)
        return params

    def units(self) -> str | None:
        """The ``"units"`` field (the unit of every length), or None where the file has none.

        Which units are known is the skill's check, not the format's; a file
        without the field (or with ``null``) is read as one in metres.
        """
        if self.data.get("units") is None:
            return None
        return self._field.get("units", str)

    def n_dims(self) -> int:
        """Dimension of the paths, 2 or 3."""
        n_dims = self._field.get("n_dims", int)
        if n_dims not in (2, 3):
            raise ValueError(f"{self.source}: n_dims: expected 2 or 3, got {n_dims}")
        return n_dims

    def path(self, n_dims: int) -> np.ndarray:
        """The generalized path, finite float64 ``(n_points, n_dims)``, at most 100 000 points."""
        raw_path = self._field.get("path", list)
        if len(raw_path) > _MAX_POINTS:
            raise ValueError(
                f"{self.source}: path: has {len(raw_path)} points; a skill file holds at most "
                f"{_MAX_POINTS}"
            )
        return self._field.array("path", (None, n_dims))

    def timing(self) -> Mapping[str, Any] | None:
        """The learned timing's fields, not yet checked, or None when the file has none.

        :meth:`lfdkit.imitate.SpeedProfile.from_dict` reads and checks them.
        """
        value = self.data.get("timing")
        if value is not None and not isinstance(value, Mapping):
            raise ValueError(f"{self.source}: timing: expected an object")
        return value

    def orientations(self, n_points: int) -> np.ndarray | None:
        """The mean orientation at each path point, finite (``n_points``, 4); None without.

        Whether the rows are unit quaternions is the skill's check.
        """
        value = self.data.get("orientation")
        if value is None:
            return None
        sub = _FieldReader(value, self.source, "orientation.")
        return sub.array("mean", (n_points, 4))

    def dmp(self) -> Mapping[str, Any] | None:
        """The stored DMP state, arrays decoded (:func:`unpack_arrays`), or None without.

        Its fields are checked by :meth:`lfdkit.imitate.DMP.from_state`; a
        file without it is refitted by the reader.
        """
        return self._stored_state(self.data, "dmp")

    def orientation_dmp(self) -> Mapping[str, Any] | None:
        """The stored orientation DMP state (``orientation.dmp``), or None where there is none."""
        value = self.data.get("orientation")
        if not isinstance(value, Mapping):
            return None
        return self._stored_state(value, "dmp", "orientation.")

    def promp(self) -> Mapping[str, Any] | None:
        """The stored ProMP state, arrays decoded, or None without.

        Its fields are checked by :meth:`lfdkit.imitate.ProMP.from_state`.
        """
        return self._stored_state(self.data, "promp")

    def _stored_state(
        self, data: Mapping[str, Any], key: str, prefix: str = ""
    ) -> Mapping[str, Any] | None:
        value = data.get(key)
        if value is None:
            return None
        if not isinstance(value, Mapping):
            raise ValueError(f"{self.source}: {prefix}{key}: expected an object")
        return unpack_arrays(value, f"{self.source}: {prefix}{key}")

    def emulation(self) -> tuple[str, dict[str, float], str, str] | None:
        """``(route, {class: clearance}, frame, gaps)`` of a fitted reward, or None (none)."""
        value = self.data.get("emulation")
        if value is None:
            return None
        sub = _FieldReader(value, self.source, "emulation.")
        route = sub.get("route", str)
        if route not in ROUTES:
            raise ValueError(
                f"{self.source}: emulation.route: expected one of {', '.join(ROUTES)}, "
                f"got {route!r}"
            )
        frame = value.get("frame", "world")
        if frame not in FRAMES:
            raise ValueError(
                f"{self.source}: emulation.frame: expected one of {', '.join(FRAMES)}, "
                f"got {frame!r}"
            )
        gaps = value.get("gaps", "closed")
        if gaps not in GAPS:
            raise ValueError(
                f"{self.source}: emulation.gaps: expected one of {', '.join(GAPS)}, got {gaps!r}"
            )
        return route, self._lengths(sub.get("clearances", dict), "clearances"), frame, gaps

    def class_radii(self) -> dict[str, float]:
        """``{class: radius}`` of the obstacles the reward was fitted on (``emulation.radii``).

        Empty where the file has none (a file from before them, or a reward
        only adopted).
        """
        value = self.data.get("emulation")
        if value is None:
            return {}
        sub = _FieldReader(value, self.source, "emulation.")
        return self._lengths(sub.get("radii", dict), "radii") if "radii" in value else {}

    def side_preferences(self) -> dict[str, dict[str, Any]]:
        """``{class: {"side": "left", "right", "above" or "below", "within": units}}``.

        From ``emulation.sides``.

        The classes the demonstrations keep on one side of the path (issue 26);
        empty where the file has none (no preference, or a file from before them).
        With ``"clearance": units`` where the file has it (how far plans keep
        such an obstacle; older files: none).
        """
        value = self.data.get("emulation")
        if not isinstance(value, Mapping) or "sides" not in value:
            return {}
        sub = _FieldReader(value, self.source, "emulation.")
        out = {}
        for label, entry in sub.get("sides", dict).items():
            name = f"{self.source}: emulation.sides.{label}"
            # The sides of lfdkit.emulate.fidelity.SIDES (above and below: 3-D only).
            sides = ("left", "right", "above", "below")
            if not isinstance(entry, Mapping) or entry.get("side") not in sides:
                raise ValueError(
                    f"{name}: expected {{'side': 'left', 'right', 'above' or 'below', "
                    "'within': length}, "
                    f"got {entry!r}"
                )
            within = self._lengths({str(label): entry.get("within")}, "sides.within")
            out[str(label)] = {"side": entry["side"], "within": within[str(label)]}
            if "clearance" in entry:  # how far it is kept (older files: no margin of its own)
                kept = self._lengths({str(label): entry["clearance"]}, "sides.clearance")
                out[str(label)]["clearance"] = kept[str(label)]
        return out

    def swerve(self) -> dict[str, list[float]]:
        """``{class: [w_before, w_after]}`` of a swerve model (``emulation.swerve``; issue 26).

        Empty where the file has none (the thesis's symmetric responses, and
        every file from before the swerve model); the reward checks the values.
        """
        value = self.data.get("emulation")
        if not isinstance(value, Mapping) or "swerve" not in value:
            return {}
        sub = _FieldReader(value, self.source, "emulation.")
        return {
            str(c): sub.array(f"swerve.{c}", (2,), value=w).tolist()
            for c, w in sub.get("swerve", dict).items()
        }

    def return_fraction(self) -> float:
        """The slow-return model's bound (``emulation.return_fraction``, in (0, 1]; issue 26).

        1 (symmetric steps, the thesis's) where the file has none: every file
        from before the model, and skills that did not choose it.
        """
        value = self.data.get("emulation")
        if not isinstance(value, Mapping) or "return_fraction" not in value:
            return 1.0
        fraction = value["return_fraction"]
        if (
            isinstance(fraction, bool)
            or not isinstance(fraction, (int, float))
            or not 0.0 < fraction <= 1.0
        ):
            raise ValueError(
                f"{self.source}: emulation.return_fraction: expected a number in (0, 1], "
                f"got {fraction!r}"
            )
        return float(fraction)

    def _lengths(self, values: Mapping[str, Any], key: str) -> dict[str, float]:
        """``emulation.<key>``: ``{class: length}``, each a finite number >= 0."""
        out = {}
        for label, length in values.items():
            if isinstance(length, bool) or not isinstance(length, (int, float)):
                raise ValueError(
                    f"{self.source}: emulation.{key}.{label}: expected a number, got {length!r}"
                )
            if not math.isfinite(length) or length < 0.0:
                raise ValueError(
                    f"{self.source}: emulation.{key}.{label}: expected a finite number "
                    f">= 0, got {length!r}"
                )
            out[str(label)] = float(length)
        return out

    def mimic(self) -> dict[str, Any]:
        """How the path was made (``method``, ``n_demos`` and diagnostics)."""
        return self._field.get("mimic", dict)

    def reward(self, n_dims: int) -> tuple[float, dict[str, np.ndarray]] | None:
        """``(nominal weight, {class: precision matrix (n_dims, n_dims)})``, or None for no reward.

        The matrices are finite float64 arrays of the right shape; whether
        they make a valid reward is the reward's own check.
        """
        reward_data = self.data.get("reward")
        if reward_data is None:
            return None
        sub = _FieldReader(reward_data, self.source, "reward.")
        precisions = sub.get("precisions", dict)
        if any(not str(c) for c in precisions):
            raise ValueError(f"{self.source}: reward.precisions: a class name is empty")
        matrices = {
            str(c): sub.array(f"precisions.{c}", (n_dims, n_dims), value=m)
            for c, m in precisions.items()
        }
        weight = sub.get("nominal_weight", (int, float))
        return float(weight), matrices

    def ioc(self) -> dict[str, Any] | None:
        """The summary of the reward fit, or None (anything but an object reads as None)."""
        info = self.data.get("ioc")
        return dict(info) if isinstance(info, Mapping) else None


def check_file_params(params: Mapping[str, Any], source: str) -> None:
    """Types and ranges of a skill file's numeric ``params`` (:data:`SKILL_FILE_LIMITS`).

    Also refuses a ``horizon`` or ``random_state`` that is not an integer.
    Parameters not given are not checked. Errors start with ``source``.
    """
    for key, (low, high) in SKILL_FILE_LIMITS.items():
        if key not in params:
            continue
        value = params[key]
        where = f"{source}: params.{key}"
        if key in ("n_basis", "duration") and value == "auto":
            continue  # the DMP chooses the count; the path's length gives the duration
        integer = key in _INTEGER_PARAMS
        kinds = (int,) if integer else (int, float)
        if isinstance(value, bool) or not isinstance(value, kinds):
            kind = "an integer" if integer else "a number"
            raise ValueError(f"{where}: expected {kind}, got {value!r}")
        if integer and not low <= value <= high:
            raise ValueError(f"{where}: expected {int(low)} to {int(high)}, got {value}")
        if not integer and not (low < value <= high):
            raise ValueError(f"{where}: expected a value in ({low:g}, {high:g}], got {value!r}")
    for key in ("horizon", "random_state"):
        value = params.get(key)
        if isinstance(value, (bool, float, str)):
            raise ValueError(f"{source}: params.{key}: expected an integer, got {value!r}")


class _FieldReader:
    """Typed access to the fields of a parsed file, with errors that name the field."""

    def __init__(self, data: Any, source: str, prefix: str = "") -> None:
        if not isinstance(data, Mapping):
            raise ValueError(f"{source}: {prefix.rstrip('.') or 'file'}: expected an object")
        self.data, self.source, self.prefix = data, source, prefix

    def get(self, key: str, kind: Any) -> Any:
        if key not in self.data:
            raise ValueError(f"{self.source}: {self.prefix}{key}: missing field")
        value = self.data[key]
        kinds = kind if isinstance(kind, tuple) else (kind,)
        if (isinstance(value, bool) and bool not in kinds) or not isinstance(value, kinds):
            names = " or ".join(k.__name__ for k in kinds)
            raise ValueError(
                f"{self.source}: {self.prefix}{key}: expected {names}, got {type(value).__name__}"
            )
        return value

    def array(self, key: str, shape: tuple[int | None, ...], *, value: Any = None) -> np.ndarray:
        raw = self.get(key, list) if value is None else value
        where = f"{self.source}: {self.prefix}{key}"
        try:
            arr = json_float_array(raw, where, len(shape))
        except TypeError as exc:
            raise ValueError(str(exc)) from None
        if arr.ndim != len(shape) or any(
            s is not None and s != a for s, a in zip(shape, arr.shape, strict=True)
        ):
            want = " x ".join("n" if s is None else str(s) for s in shape)
            raise ValueError(f"{where}: expected shape {want}, got {arr.shape}")
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{where}: contains NaN or infinite values")
        return arr


def made_from_document(
    cls: type,
    data: Any,
    fmt: str,
    newest: int,
    keys: Sequence[str],
    *,
    source: str,
    kind: str,
) -> Any:
    """An unfitted ``cls(**data["params"])`` of a skill file of another kind, once its header holds.

    Checks what every kind's file shares: a JSON object, ``format`` = ``fmt``,
    a ``version`` from 1 to ``newest``, each of ``keys`` (besides ``params``)
    present, the parameters valid for ``cls``, and ``units`` equal to the
    parameters' (when the file has both). One-line ``ValueError`` starting
    with ``source`` and naming the field; ``kind`` names the file's kind
    (``"periodic skill"``).
    """
    from lfdkit import __version__

    if not isinstance(data, Mapping):
        raise ValueError(f"{source}: expected a JSON object at the top level")
    if data.get("format") != fmt:
        raise ValueError(
            f"{source}: not an lfdkit {kind} (format {data.get('format')!r}, expected {fmt!r})"
        )
    version = data.get("version")
    if isinstance(version, bool) or not isinstance(version, int) or version < 1:
        raise ValueError(f"{source}: version: expected a positive integer, got {version!r}")
    if version > newest:
        raise ValueError(
            f"{source}: version {version} was written by a newer lfdkit "
            f"({data.get('lfdkit', '?')}); this lfdkit {__version__} reads up to version "
            f"{newest}: upgrade lfdkit"
        )
    for key in ("params", *keys):
        if key not in data:
            raise ValueError(f"{source}: {key}: missing field")
    params = data["params"]
    if not isinstance(params, Mapping):
        raise ValueError(f"{source}: params: expected an object, got {params!r}")
    try:
        made = cls(**params)
        made._validate_params()
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{source}: params: {exc}") from None
    if "units" in data and data["units"] != getattr(made, "units", data["units"]):
        raise ValueError(
            f"{source}: units: {data['units']!r} does not match params.units {made.units!r}"
        )
    return made


class SavedToSkillFile:
    """``save`` and ``load`` of a skill kind that has ``to_dict`` and ``from_dict``.

    One home for what every kind of skill file shares: the write is atomic
    and never over a file unless asked (:func:`write_skill_file`), the read
    strict and bounded (:func:`read_skill_file`); the kind's ``from_dict``
    checks the fields, naming the file, and never refits.
    """

    def save(self, path: PathLike, *, overwrite: bool = False) -> Path:
        """Write the skill as JSON, atomically; returns the file written.

        Raises ``FileExistsError`` if ``path`` exists and ``overwrite`` is
        false, ``IsADirectoryError`` if it is a directory.
        """
        target = check_skill_path(path)
        return write_skill_file(target, self.to_dict(), overwrite=overwrite)  # type: ignore[attr-defined]

    @classmethod
    def load(cls, path: PathLike) -> Self:
        """Read a skill written by :meth:`save` (strict JSON, bounded size; never refits).

        Raises
        ------
        FileNotFoundError
            If the file does not exist.
        ValueError
            For a file that is binary (e.g. a pickle), larger than
            :data:`MAX_SKILL_FILE_BYTES`, not valid JSON, of another kind,
            from a newer version, or with a broken or out-of-range field (the
            message names the file and the field).
        """
        name = os.fspath(path)
        return cls.from_dict(read_skill_file(name), source=name)  # type: ignore[attr-defined]


def is_periodic_document(data: Any) -> bool:
    """Whether a parsed skill file (:func:`read_skill_file`) is periodic.

    Here, with the format, so a reader tells the two kinds apart without
    importing the periodic skill (its rhythmic DMPs) for a discrete one.
    """
    return isinstance(data, Mapping) and data.get("format") == PERIODIC_FORMAT
