"""Scene files: the scenes of one or several demonstrations, read and written.

A :class:`~lfdkit.model.scene.Scene` holds the obstacles of one environment; each
:class:`~lfdkit.model.scene.Obstacle` has a class label, a centre of shape ``(q,)`` with
``q`` 2 or 3, and a radius, both in the units of the paths (metres for
robot data). A *scene file* gives the scenes of one or several
demonstrations, keyed by demonstration id (:data:`lfdkit.model.demos.DemoId`, an
``int`` or a ``str``), so that they can be matched with a file of
demonstrations.

Files
-----
The format is chosen from the file suffix (case-insensitive). All the
positions in one file have the same dimension.

``.csv``
    A header row, then one row per obstacle. Columns: ``demo`` (the
    demonstration id; optional, a file without it is one scene with id
    ``0``), ``class`` (the obstacle label), the coordinates ``x, y`` or
    ``x, y, z`` and optionally ``radius`` (default 0). Obstacles of another
    shape than round (:data:`lfdkit.model.scene.OBSTACLE_SHAPES`) give it in a
    ``shape`` column (empty: round) and their fields in columns named after
    them: a capsule's axis end in ``end_x, end_y[, end_z]``. Column names are
    case-insensitive; columns with other names are ignored, as are blank
    lines and lines starting with ``#``. A moving obstacle of constant
    velocity gives it in ``vx, vy[, vz]`` (units/s; empty or absent: static;
    :class:`lfdkit.model.motion.ConstantVelocity`), columns written only when an
    obstacle moves. A row with a demo id and empty
    ``class``, coordinates and radius states that this demonstration was
    recorded without obstacles (an empty scene). The rows of one
    demonstration are consecutive; scenes and obstacles keep file order.
    Ids have no surrounding spaces; an id that is the canonical spelling of
    an integer (``"7"``, not ``"07"``) is read as ``int``. Numbers are
    decimal, as in :mod:`lfdkit.io.demos` (no ``0_5``, ``nan`` or ``inf``).
``.json``
    ``{"format": "lfdkit-scenes", "version": 1, "scenes": [{"demo": <id>,
    "obstacles": [{"class": "cup", "position": [x, y], "radius": 0.03},
    ...]}, ...]}``. ``"radius"`` is optional (default 0); another shape
    gives ``"shape"`` and its fields (a capsule: ``"shape": "capsule",
    "end": [x, y]``); a moving obstacle gives one of ``"velocity": [vx, vy]``,
    ``"trajectory": {"times": [...], "positions": [[x, y], ...]}`` or
    ``"observations": {"times": [...], "positions": [...], "noise": s}``
    (:mod:`lfdkit.model.motion`); ``"demo"`` is
    optional in a file with a single scene (id ``0``). A field of another
    shape than the obstacle's (``"end"`` on a round one) is refused, as in
    CSV, where a shape column of the other dimension (``end_z`` in a 2-D
    file) with a value is refused too. Other fields are ignored. Numbers must
    be JSON numbers (not strings or booleans).

Reading is strict and bounded as in :mod:`lfdkit.io.demos`, with the same
primitives (:mod:`lfdkit.io.text`: repeated keys, NaN literals, deep nesting
and files over :data:`lfdkit.io.text.MAX_FILE_BYTES` are errors naming the
file).

Writing is atomic (:func:`lfdkit.io.atomic.atomic_write`) and floats are written
with ``repr``, so :func:`load_scenes` after :func:`save_scenes` gives back
bit-identical positions and radii.
"""

from __future__ import annotations

import csv
import io
import json
import math
import os
from collections.abc import Mapping
from dataclasses import replace
from pathlib import Path
from typing import Any

import numpy as np

from lfdkit.io.atomic import check_output_path, write_text
from lfdkit.io.text import (
    Blocks,
    check_file_id,
    check_ids,
    csv_header,
    csv_number,
    csv_rows,
    format_of,
    header_hint,
    json_document,
    parse_id,
)
from lfdkit.model.demos import DemoId, PathLike
from lfdkit.model.motion import ConstantVelocity, Motion, Observations, Trajectory
from lfdkit.model.scene import OBSTACLE_SHAPES, Obstacle, Scene

__all__ = [
    "SCENE_JSON_FORMAT",
    "SCENE_JSON_VERSION",
    "SCENE_SUFFIXES",
    "load_scene",
    "load_scenes",
    "save_scenes",
]

SCENE_SUFFIXES: tuple[str, ...] = (".csv", ".json")
"""File suffixes understood by :func:`load_scenes` and :func:`save_scenes`."""

SCENE_JSON_FORMAT = "lfdkit-scenes"
"""Value of the ``"format"`` field of a scenes JSON file."""

SCENE_JSON_VERSION = 1
"""Newest scenes JSON file-format version this module reads and the one it writes."""


# --------------------------------------------------------------------------- #
# Files
# --------------------------------------------------------------------------- #


def load_scenes(path: PathLike) -> dict[DemoId, Scene]:
    """Read the scenes of one or several demonstrations from a ``.csv`` or ``.json`` file.

    See the module docstring for the layout of each format.

    Parameters
    ----------
    path : str or os.PathLike
        File to read; its suffix selects the format.

    Returns
    -------
    dict of {int or str: Scene}
        One scene per demonstration id, in file order. Positions are float64
        arrays of shape ``(q,)`` and radii floats, in the units of the paths.
        A CSV file without a ``demo`` column gives one scene with id ``0``.

    Raises
    ------
    ValueError
        If the suffix is not supported or the content is malformed; the
        message names the file and the line and column (CSV) or the field
        (JSON, e.g. ``scenes[2].obstacles[0].position``) at fault.
    FileNotFoundError
        If the file does not exist.
    """
    fname = os.fspath(path)
    if _scene_format(fname) == ".csv":
        return _read_scenes_csv(fname)
    return _read_scenes_json(fname)


def load_scene(path: PathLike) -> Scene:
    """Read a file that holds exactly one scene (with any demonstration id, or none).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.csv`` or ``.json`` scene file (see the module docstring); a CSV
        file may omit the ``demo`` column.

    Returns
    -------
    Scene
        The scene; positions of shape ``(q,)`` and radii in the units of the paths.

    Raises
    ------
    ValueError
        If the file holds no scene or several (use :func:`load_scenes` for
        those), or as :func:`load_scenes`.
    FileNotFoundError
        If the file does not exist.
    """
    fname = os.fspath(path)
    scenes = load_scenes(fname)
    if len(scenes) != 1:
        if not scenes:
            raise ValueError(f"{fname}: holds no scene; load_scene expects exactly one")
        shown = ", ".join(repr(i) for i in list(scenes)[:5]) + (", ..." if len(scenes) > 5 else "")
        raise ValueError(
            f"{fname}: holds {len(scenes)} scenes (demo ids {shown}); load_scene expects "
            "exactly one; use load_scenes to read them all"
        )
    return next(iter(scenes.values()))


def save_scenes(path: PathLike, scenes: Mapping[DemoId, Scene], *, overwrite: bool = False) -> Path:
    """Write the scenes of one or several demonstrations to a ``.csv`` or ``.json`` file.

    The write is atomic (:func:`lfdkit.io.atomic.write_text`) and exact:
    :func:`load_scenes` gives back bit-identical positions and radii, the
    labels and the ids in the same order. A CSV file stores ids as text, so
    a ``str`` id that spells a canonical integer (``"7"``) reads back as
    ``int``; JSON keeps the type.

    Parameters
    ----------
    path : str or os.PathLike
        Destination; its suffix selects the format.
    scenes : mapping of {int or str: Scene}
        One scene per demonstration id; scenes may be empty. Ids follow the
        rules of :func:`lfdkit.io.demos.save_demos` (unique also as text; a
        ``str`` id non-empty, without surrounding whitespace or line breaks,
        not starting with ``#``). All positions share one dimension, 2 or 3.
        CSV also needs labels without surrounding whitespace or line breaks.
    overwrite : bool
        Replace an existing file. When false an existing file raises
        ``FileExistsError`` and is left untouched.

    Returns
    -------
    pathlib.Path
        The file written, which :func:`load_scenes` reads back.

    Raises
    ------
    ValueError
        If the suffix is unsupported or the scenes cannot be stored.
    TypeError
        If ``scenes`` is not a mapping of ids to :class:`Scene`.
    FileExistsError, IsADirectoryError
        As :func:`lfdkit.io.atomic.write_text`: the file exists and
        ``overwrite`` is false, or ``path`` is a directory.
    """
    fname = os.fspath(path)
    fmt = _scene_format(fname)
    if not isinstance(scenes, Mapping):
        raise TypeError(
            f"scenes: expected a mapping of demo ids to Scene, got {type(scenes).__name__}"
        )
    keys = list(scenes)
    try:
        ids = check_ids(keys, len(keys))
    except (TypeError, ValueError) as exc:
        raise type(exc)(f"scenes: bad demo id among the keys ({exc})") from None
    values: list[Scene] = []
    dim: tuple[int, DemoId] | None = None
    for key, did in zip(keys, ids, strict=True):
        scene = scenes[key]
        if not isinstance(scene, Scene):
            raise TypeError(f"scenes[{did!r}]: expected a Scene, got {type(scene).__name__}")
        if scene.obstacles:
            q = scene.obstacles[0].position.size
            if dim is None:
                dim = (q, did)
            elif q != dim[0]:
                raise ValueError(
                    f"scenes[{did!r}]: {q}-D positions but scenes[{dim[1]!r}] is {dim[0]}-D; "
                    "all positions in a scene file must have the same dimension"
                )
        if fmt == ".csv":
            for k, o in enumerate(scene.obstacles):
                if o.motion is not None and not isinstance(o.motion, ConstantVelocity):
                    raise ValueError(
                        f"scenes[{did!r}].obstacles[{k}]: a {o.motion.kind} motion, which CSV "
                        "cannot store (only a constant velocity, vx, vy); use a .json file"
                    )
                if o.label != o.label.strip() or "\n" in o.label or "\r" in o.label:
                    raise ValueError(
                        f"scenes[{did!r}].obstacles[{k}]: label {o.label!r} has surrounding "
                        "whitespace or a line break, which CSV cannot store exactly; "
                        "use a .json file or clean the label"
                    )
        values.append(scene)
    q = 2 if dim is None else dim[0]

    check_output_path(fname, overwrite=overwrite)

    if fmt == ".csv":
        return write_text(fname, _scenes_csv_text(ids, values, q), overwrite=overwrite)
    return write_text(fname, _scenes_json_text(ids, values), overwrite=overwrite)


def _scene_format(fname: str) -> str:
    return format_of(fname, SCENE_SUFFIXES, "a scene file")


def _obstacle(
    where: str,
    label: str,
    position: list[float],
    radius: float,
    shape: type[Obstacle] = Obstacle,
    fields: Mapping[str, Any] | None = None,
    motion: Motion | None = None,
) -> Obstacle:
    """Build an obstacle, prefixing its validation errors with ``where`` (file and line/field)."""
    try:
        built = shape.from_fields(label, np.array(position, dtype=np.float64), radius, fields or {})
        return built if motion is None else replace(built, motion=motion)
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None


def _shape_named(where: str, name: str) -> type[Obstacle]:
    """The registered obstacle class of a shape name (empty: a round obstacle)."""
    if not name:
        return Obstacle
    try:
        return OBSTACLE_SHAPES[name]
    except KeyError:
        raise ValueError(
            f"{where}: unknown shape {name!r}; known shapes: {', '.join(OBSTACLE_SHAPES)}"
        ) from None


def _field_columns(q: int) -> dict[tuple[str, str], list[str]]:
    """CSV columns of every registered shape's fields: ``end`` → ``end_x, end_y[, end_z]``."""
    columns: dict[tuple[str, str], list[str]] = {}
    for shape in OBSTACLE_SHAPES.values():
        for name, kind in shape.field_kinds.items():
            columns[(shape.shape, name)] = (
                [f"{name}_{c}" for c in "xyz"[:q]] if kind == "point" else [name]
            )
    return columns


# --------------------------------------------------------------------------- #
# CSV
# --------------------------------------------------------------------------- #

_CSV_KNOWN = ("demo", "class", "x", "y", "z", "radius", "shape", "vx", "vy", "vz")


def _scenes_csv_text(ids: list[DemoId], scenes: list[Scene], q: int) -> str:
    f = io.StringIO()
    w = csv.writer(f, lineterminator="\n")
    # Round obstacles only: the plain columns. Other shapes add "shape" and their fields.
    shapes = {type(o) for scene in scenes for o in scene.obstacles} - {Obstacle}
    extra = [
        (shape.shape, name, cols)
        for (shape_name, name), cols in _field_columns(q).items()
        for shape in shapes
        if shape.shape == shape_name
    ]
    shape_columns = ["shape", *[c for _, _, cols in extra for c in cols]] if shapes else []
    # Velocity columns only when something moves: static files stay as they were.
    moving = any(o.motion is not None for scene in scenes for o in scene.obstacles)
    velocity_columns = ["vx", "vy", "vz"][:q] if moving else []
    w.writerow(["demo", "class", *["x", "y", "z"][:q], "radius", *shape_columns, *velocity_columns])
    blank = [""] * (len(shape_columns) + len(velocity_columns))
    for did, scene in zip(ids, scenes, strict=True):
        if not scene.obstacles:
            # The empty-scene row: an id with empty class, coordinates and radius.
            w.writerow([str(did), "", *([""] * q), "", *blank])
        for o in scene.obstacles:
            # repr() of a Python float is the shortest string that reads back exactly.
            row = [str(did), o.label, *map(repr, o.position.tolist()), repr(o.radius)]
            if shapes:
                row.append(o.shape)
                for shape_name, name, cols in extra:
                    if shape_name != o.shape:
                        row += [""] * len(cols)
                    else:
                        row += list(map(repr, np.ravel(o.fields()[name]).tolist()))
            if moving:
                velocity = o.motion.velocity.tolist() if o.motion is not None else [""] * q
                row += [v if v == "" else repr(v) for v in velocity]
            w.writerow(row)
    return f.getvalue()


def _read_scenes_csv(fname: str) -> dict[DemoId, Scene]:
    header_line, header, lines = csv_header(fname)
    header = [h.strip() for h in header]
    found = ", ".join(repr(h) for h in header)
    pos: dict[str, int] = {}
    field_columns = _field_columns(3 if any(h.lower() == "z" for h in header) else 2)
    known = {*_CSV_KNOWN, *(c for cols in field_columns.values() for c in cols)}
    # Shape columns of the other dimension (end_z in a 2-D file): a value there is refused,
    # not dropped.
    other_dim = {c for cols in _field_columns(3).values() for c in cols} - known
    stray = [(k, name) for k, name in enumerate(header) if name.lower() in other_dim]
    for k, name in enumerate(header):
        key = name.lower()
        if key in known:
            if key in pos:
                raise ValueError(
                    f"{fname} line {header_line}: duplicate column {name!r}; found columns: {found}"
                )
            pos[key] = k
    for key in ("class", "x", "y"):
        if key not in pos:
            raise ValueError(
                f"{fname} line {header_line}: missing column {key!r}; found columns: {found}"
                + header_hint(header)
            )
    coord_keys = ["x", "y", "z"] if "z" in pos else ["x", "y"]
    coord_cols = [(pos[c], header[pos[c]]) for c in coord_keys]

    # Demo-id text -> (obstacles, line of the first obstacle, line of an empty-scene row).
    groups: dict[str, tuple[list[Obstacle], list[int], list[int]]] = {}
    blocks = Blocks(fname, header[pos["demo"]]) if "demo" in pos else None
    for lineno, row in csv_rows(fname, lines, header):
        if blocks is not None:
            did = blocks.id_of(row[pos["demo"]], lineno)
        else:
            did = "0"
        row = [c.strip() for c in row]
        obstacles, obstacle_lines, empty_lines = groups.setdefault(did, ([], [], []))
        label = row[pos["class"]]
        cells = [(row[c], name) for c, name in coord_cols]
        radius_cell = row[pos["radius"]] if "radius" in pos else ""
        velocity_cells = [(row[pos[c]], header[pos[c]]) for c in ("vx", "vy", "vz") if c in pos]
        shape_cell = row[pos["shape"]] if "shape" in pos else ""
        given_fields = {
            key: [row[pos[c]] for c in cols if c in pos] for key, cols in field_columns.items()
        }
        at = f"{fname} line {lineno}"
        for k, name in stray:
            if row[k]:
                raise ValueError(
                    f"{at}, column {name!r}: a value in a 2-D scene (the file has no 'z' "
                    "column); give z for every obstacle, or leave the column empty"
                )

        if not label:
            given = [name for cell, name in cells if cell]
            if given:
                raise ValueError(
                    f"{at}, column {header[pos['class']]!r}: empty value, but the row has "
                    f"coordinates ({', '.join(given)}); give the obstacle class (a row with "
                    "an empty class and no coordinates marks a demonstration without "
                    "obstacles)"
                )
            if any(cell for cell, _ in velocity_cells):
                raise ValueError(
                    f"{at}, column {header[pos['class']]!r}: empty value, but the row has "
                    "a velocity; give the obstacle class and coordinates"
                )
            if radius_cell or shape_cell or any(any(v) for v in given_fields.values()):
                raise ValueError(
                    f"{at}, column {header[pos['class']]!r}: empty value, but the row has "
                    f"a radius; give the obstacle class and coordinates"
                    if radius_cell
                    else f"{at}, column {header[pos['class']]!r}: empty value, but the row "
                    "has a shape or shape fields; give the obstacle class and coordinates"
                )
            if obstacle_lines:
                raise ValueError(
                    f"{at}: marks demo {did!r} as having no obstacles, but line "
                    f"{obstacle_lines[0]} gives it an obstacle"
                )
            empty_lines.append(lineno)
            continue
        if empty_lines:
            raise ValueError(
                f"{at}: gives demo {did!r} an obstacle, but line {empty_lines[0]} marks it "
                "as having no obstacles"
            )
        for cell, name in cells[:2]:
            if not cell:
                raise ValueError(
                    f"{at}, column {name!r}: empty value; the row has class {label!r}, "
                    "so it needs coordinates"
                )
        if len(cells) == 3 and not cells[2][0]:
            raise ValueError(
                f"{at}, column {cells[2][1]!r}: empty value in a file with a "
                f"{cells[2][1]!r} column; mixed 2-D and 3-D positions: give z for "
                "every obstacle, or drop the column for 2-D"
            )
        position = [csv_number(fname, lineno, name, cell) for cell, name in cells]
        radius = 0.0
        if radius_cell:
            rname = header[pos["radius"]]
            radius = csv_number(fname, lineno, rname, radius_cell)
            if radius < 0:
                raise ValueError(
                    f"{at}, column {rname!r}: radius {radius_cell!r} is negative; "
                    "a radius must be >= 0"
                )
        shape_column = header[pos["shape"]] if "shape" in pos else "shape"
        shape = _shape_named(f"{at}, column {shape_column!r}", shape_cell)
        fields = {}
        own_columns = {
            c for (o, _), cols in field_columns.items() if o == shape.shape for c in cols
        }
        for (owner, name), cells_given in given_fields.items():
            columns = [header[pos[c]] for c in field_columns[(owner, name)] if c in pos]
            if owner != shape.shape:
                shared = set(field_columns[(owner, name)]) <= own_columns
                if any(cells_given) and not shared:
                    raise ValueError(
                        f"{at}, column {columns[0]!r}: a {owner} field, but the obstacle "
                        f"is {shape.shape}; leave it empty or set the shape"
                    )
                continue
            wanted = field_columns[(owner, name)]
            if len(columns) != len(wanted) or not all(cells_given):
                raise ValueError(
                    f"{at}: a {owner} obstacle needs columns {', '.join(map(repr, wanted))} "
                    f"({name}), each with a value"
                )
            values = [
                csv_number(fname, lineno, column, cell)
                for column, cell in zip(columns, cells_given, strict=True)
            ]
            fields[name] = values if shape.field_kinds[name] == "point" else values[0]
        motion = None
        if any(cell for cell, _ in velocity_cells):
            wanted = ["vx", "vy", "vz"][: len(position)]
            given = [cell for cell, _ in velocity_cells[: len(position)]]
            if len(given) != len(wanted) or not all(given):
                raise ValueError(
                    f"{at}: a moving obstacle needs columns {', '.join(map(repr, wanted))}, "
                    "each with a value (all empty: static)"
                )
            motion = ConstantVelocity(
                [
                    csv_number(fname, lineno, name, cell)
                    for cell, name in velocity_cells[: len(position)]
                ]
            )
        obstacles.append(_obstacle(at, label, position, radius, shape, fields, motion))
        obstacle_lines.append(lineno)

    if "demo" not in pos and not groups:
        return {0: Scene()}  # a header-only single-scene file: no obstacles
    return {parse_id(did): Scene(tuple(g[0])) for did, g in groups.items()}


# --------------------------------------------------------------------------- #
# JSON
# --------------------------------------------------------------------------- #


def _scenes_json_text(ids: list[DemoId], scenes: list[Scene]) -> str:
    # One obstacle per line keeps the file readable and diff-friendly.
    # json writes floats with repr(), so values read back exactly.
    buf = io.StringIO()
    buf.write("{\n")
    buf.write(f'  "format": {json.dumps(SCENE_JSON_FORMAT)},\n')
    buf.write(f'  "version": {SCENE_JSON_VERSION},\n')
    buf.write('  "scenes": [')
    for j, (did, scene) in enumerate(zip(ids, scenes, strict=True)):
        buf.write(",\n" if j else "\n")
        buf.write(f'    {{"demo": {json.dumps(did)}, "obstacles": [')
        for k, o in enumerate(scene.obstacles):
            item = {"class": o.label, "position": o.position.tolist(), "radius": o.radius}
            if type(o) is not Obstacle:
                item["shape"] = o.shape
                item.update({key: np.ravel(v).tolist() for key, v in o.fields().items()})
                for key, kind in o.field_kinds.items():
                    if kind != "point":
                        item[key] = item[key][0]
            if o.motion is not None:
                item.update(_motion_json(o.motion))
            buf.write(",\n" if k else "\n")
            buf.write(f"      {json.dumps(item, allow_nan=False)}")
        buf.write("\n    ]}" if scene.obstacles else "]}")
    buf.write("\n  ]\n}\n" if scenes else "]\n}\n")
    return buf.getvalue()


_MOTION_KEYS = ("velocity", "trajectory", "observations")


def _motion_json(motion: Motion) -> dict[str, Any]:
    """A motion's JSON field (floats exact)."""
    if isinstance(motion, ConstantVelocity):
        return {"velocity": motion.velocity.tolist()}
    if isinstance(motion, Trajectory):
        return {
            "trajectory": {"times": motion.times.tolist(), "positions": motion.positions.tolist()}
        }
    if isinstance(motion, Observations):
        return {
            "observations": {
                "times": motion.times.tolist(),
                "positions": motion.positions.tolist(),
                "noise": motion.noise,
            }
        }
    raise ValueError(f"motion: a {type(motion).__name__} cannot be written to a scene file")


def _motion_of(fname: str, at: str, ob: Mapping[str, Any], q: int) -> Motion | None:
    """The motion of a JSON obstacle (None: static)."""
    given = [key for key in _MOTION_KEYS if key in ob]
    if not given:
        return None
    if len(given) > 1:
        raise ValueError(f"{fname}: {at}: give one of {', '.join(given)}, not several")
    key = given[0]
    value = ob[key]
    where = f"{fname}: {at}.{key}"

    def numbers(items: Any, name: str) -> list[float]:
        if not isinstance(items, list):
            raise ValueError(f"{where}.{name}: expected a list of numbers, got {items!r}")
        return [_json_number(fname, f"{at}.{key}.{name}[{i}]", v) for i, v in enumerate(items)]

    try:
        if key == "velocity":
            velocity = numbers(value, "")
            if len(velocity) != q:
                raise ValueError(f"expected {q} numbers, got {len(velocity)}")
            return ConstantVelocity(velocity)
        if not isinstance(value, dict) or "times" not in value or "positions" not in value:
            raise ValueError("expected an object with 'times' and 'positions'")
        times = numbers(value["times"], "times")
        raw = value["positions"]
        if not isinstance(raw, list) or not all(isinstance(p, list) and len(p) == q for p in raw):
            raise ValueError(f"positions: expected a list of {q}-number lists")
        positions = [numbers(p, f"positions[{i}]") for i, p in enumerate(raw)]
        if key == "trajectory":
            return Trajectory(times, positions)
        if "noise" not in value:
            raise ValueError("missing 'noise' (the observations' standard deviation)")
        noise = _json_number(fname, f"{at}.{key}.noise", value["noise"])
        return Observations(times, positions, noise)
    except ValueError as exc:
        message = str(exc)
        raise ValueError(message if message.startswith(fname) else f"{where}: {message}") from None


def _json_number(fname: str, where: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{fname}: {where}: expected a number, got {value!r}")
    try:
        x = float(value)
    except OverflowError:
        x = math.inf
    if not math.isfinite(x):
        raise ValueError(
            f"{fname}: {where}: value {value!r} is not finite; NaN and infinity are not allowed"
        )
    return x


def _read_scenes_json(fname: str) -> dict[DemoId, Scene]:
    doc = json_document(fname, SCENE_JSON_FORMAT, SCENE_JSON_VERSION, "scene")
    items = doc.get("scenes")
    if not isinstance(items, list):
        raise ValueError(f"{fname}: field 'scenes' must be a list of scenes, got {items!r}")

    out: dict[DemoId, Scene] = {}
    seen: dict[str, int] = {}
    dim: tuple[int, str] | None = None
    for j, item in enumerate(items):
        where = f"scenes[{j}]"
        if not isinstance(item, dict):
            raise ValueError(f"{fname}: {where}: expected an object with 'demo' and 'obstacles'")
        if "demo" in item:
            did = item["demo"]
            if isinstance(did, bool) or not isinstance(did, (int, str)) or did == "":
                raise ValueError(
                    f"{fname}: {where}.demo: expected an int or a non-empty str, got {did!r}"
                )
            check_file_id(did, f"{fname}: {where}.demo")
        elif len(items) == 1:
            did = 0
        else:
            raise ValueError(
                f"{fname}: {where}: missing field 'demo'; it is optional only in a file with "
                f"a single scene, and this one has {len(items)}"
            )
        if str(did) in seen:
            raise ValueError(
                f"{fname}: {where}.demo: demo id {did!r} repeats scenes[{seen[str(did)]}]; "
                "give each demonstration one scene entry"
            )
        seen[str(did)] = j
        raw = item.get("obstacles")
        if not isinstance(raw, list):
            raise ValueError(
                f"{fname}: {where}.obstacles: expected a list of obstacles (empty for a scene "
                f"without obstacles), got {raw!r}"
            )
        obstacles: list[Obstacle] = []
        for k, ob in enumerate(raw):
            at = f"{where}.obstacles[{k}]"
            if not isinstance(ob, dict):
                raise ValueError(
                    f"{fname}: {at}: expected an object with 'class', 'position' and "
                    f"optional 'radius', got {ob!r}"
                )
            label = ob.get("class")
            if not isinstance(label, str) or not label:
                raise ValueError(f"{fname}: {at}.class: expected a non-empty string, got {label!r}")
            position = ob.get("position")
            if not isinstance(position, list) or len(position) not in (2, 3):
                raise ValueError(
                    f"{fname}: {at}.position: expected a list of 2 or 3 numbers, got {position!r}"
                )
            coords = [_json_number(fname, f"{at}.position[{i}]", v) for i, v in enumerate(position)]
            if dim is None:
                dim = (len(coords), f"{at}.position")
            elif len(coords) != dim[0]:
                raise ValueError(
                    f"{fname}: {at}.position: has {len(coords)} coordinates but {dim[1]} has "
                    f"{dim[0]}; mixed 2-D and 3-D positions in one file"
                )
            radius = 0.0
            if "radius" in ob:
                radius = _json_number(fname, f"{at}.radius", ob["radius"])
                if radius < 0:
                    raise ValueError(
                        f"{fname}: {at}.radius: radius {ob['radius']!r} is negative; "
                        "a radius must be >= 0"
                    )
            shape_name = ob.get("shape", "")
            if not isinstance(shape_name, str):
                raise ValueError(f"{fname}: {at}.shape: expected a shape name, got {shape_name!r}")
            shape = _shape_named(f"{fname}: {at}.shape", shape_name)
            fields = {}
            for name, kind in shape.field_kinds.items():
                if name not in ob:
                    raise ValueError(f"{fname}: {at}: a {shape.shape} obstacle needs {name!r}")
                value = ob[name]
                if kind == "point":
                    if not isinstance(value, list) or len(value) != len(coords):
                        raise ValueError(
                            f"{fname}: {at}.{name}: expected a list of {len(coords)} numbers, "
                            f"got {value!r}"
                        )
                    fields[name] = [
                        _json_number(fname, f"{at}.{name}[{i}]", v) for i, v in enumerate(value)
                    ]
                else:
                    fields[name] = _json_number(fname, f"{at}.{name}", value)
            for owner in OBSTACLE_SHAPES.values():
                for name in owner.field_kinds:
                    if name in ob and name not in shape.field_kinds:
                        raise ValueError(
                            f"{fname}: {at}.{name}: a {owner.shape} field, but the obstacle is "
                            f"{shape.shape}; leave it out or set the shape"
                        )
            motion = _motion_of(fname, at, ob, len(coords))
            obstacles.append(
                _obstacle(f"{fname}: {at}", label, coords, radius, shape, fields, motion)
            )
        out[did] = Scene(tuple(obstacles))
    return out
