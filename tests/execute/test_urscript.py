"""Tests for lfdkit.execute.urscript: URScript programs for a UR controller.

Programs are read back with a small regex-based reader written here, which
accepts only the exact shapes of lines the module documents.
"""

from __future__ import annotations

import dataclasses
import re
import tempfile
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import lfdkit
from lfdkit.execute import ur5
from lfdkit.execute.arm import UR5, UR10
from lfdkit.execute.poses import pose_vector, unwrap_rotvecs
from lfdkit.execute.timing import time_parameterize
from lfdkit.execute.urscript import (
    DEFAULT_WORKSPACE,
    URScriptError,
    URScriptTypeError,
    Workspace,
    format_number,
    urscript_program,
    write_urscript,
)
from lfdkit.tasks.sweeping.scenarios import sweeping_poses
from tests.execute.arms import PLANAR

PRECISION = 5e-10 + 1e-15  # half a unit in the 9th decimal, plus rounding
NUM = r"-?\d+\.\d+"  # fixed point, no exponent
MOVEL = re.compile(rf"movel\(p\[(.*)\], a=({NUM}), v=({NUM}), r=({NUM})\)")
MOVEJ = re.compile(rf"movej\(\[(.*)\], a=({NUM}), v=({NUM})\)")
SERVOJ = re.compile(rf"servoj\(\[(.*)\], t=({NUM}), lookahead_time=({NUM}), gain=(\d+)\)")


@dataclass
class Program:
    header: list[str]
    name: str
    movel: list[tuple[np.ndarray, float, float, float]] = field(default_factory=list)
    movej: list[np.ndarray] = field(default_factory=list)
    servoj: list[tuple[np.ndarray, float, float, int]] = field(default_factory=list)


def numbers(text: str) -> np.ndarray:
    parts = [p.strip() for p in text.split(",")]
    assert all(re.fullmatch(NUM, p) for p in parts), text
    return np.array([float(p) for p in parts])


def read_program(text: str) -> Program:
    """Parse a generated program; fail on anything unexpected."""
    assert text.endswith("\n")
    assert text.isascii()
    lines = text.splitlines()
    header = []
    while lines and lines[0].startswith("#"):
        header.append(lines.pop(0))
    defs = [i for i, line in enumerate(lines) if line.startswith("def ")]
    ends = [i for i, line in enumerate(lines) if line == "end"]
    assert defs == [0], "exactly one def, right after the header"
    assert len(ends) == 1
    match = re.fullmatch(r"def ([A-Za-z_]\w*)\(\):", lines[0])
    assert match
    name = match.group(1)
    assert ends[0] == len(lines) - 2
    assert lines[-1] == f"{name}()", "the program ends with a call"
    prog = Program(header=header, name=name)
    for line in lines[1 : ends[0]]:
        assert line.startswith("  ") and not line.startswith("   ")
        body = line.strip()
        if m := MOVEL.fullmatch(body):
            p = numbers(m.group(1))
            assert p.shape == (6,)
            prog.movel.append((p, float(m.group(2)), float(m.group(3)), float(m.group(4))))
        elif m := MOVEJ.fullmatch(body):
            prog.movej.append(numbers(m.group(1)))
        elif m := SERVOJ.fullmatch(body):
            q = numbers(m.group(1))
            assert q.shape == (6,)
            prog.servoj.append((q, float(m.group(2)), float(m.group(3)), int(m.group(4))))
        else:
            raise AssertionError(f"unexpected line: {line!r}")
    return prog


def sweep_poses(n: int = 30) -> np.ndarray:
    phi = np.linspace(0, 1.5 * np.pi, n)
    path = np.column_stack((0.45 + 0.15 * np.cos(phi), 0.15 * np.sin(phi)))
    p = pose_vector(sweeping_poses(path))
    p[:, 3:] = unwrap_rotvecs(p[:, 3:])
    return p


# A configuration with the flange 0.4 m above the table, tool down (an IK solution of
# the pose diag(1, -1, -1) at (0.4, 0, 0.4)), for joint streams that stay above it.
Q_ABOVE = np.array([0.27638018, -3.13054767, 1.42036939, 0.13938196, -1.57079633, 1.84717651])
DT = 0.008  # one tick of a CB-series controller (125 Hz), s


# ------------------------------------------------------------------ movel
def test_movel_program_structure_and_numbers():
    poses = sweep_poses()
    text = urscript_program(poses, speed=0.2, acceleration=0.8, blend_radius=0.005)
    prog = read_program(text)
    assert prog.name == "lfdkit_sweep"
    head = "\n".join(prog.header)
    assert f"lfdkit {lfdkit.__version__}" in head
    assert re.search(r"\d{4}-\d\d-\d\d \d\d:\d\d:\d\d UTC", head)
    assert f"{len(poses)} poses" in head
    assert "metres" in head and "radians" in head
    assert len(prog.movel) == len(poses)
    assert not prog.servoj and not prog.movej
    for i, (p, a, v, r) in enumerate(prog.movel):
        np.testing.assert_allclose(p, poses[i], rtol=0, atol=PRECISION)
        assert (a, v) == (0.8, 0.2)
        assert r == (0.005 if i < len(poses) - 1 else 0.0)


def test_movel_defaults_and_name_and_header():
    poses = sweep_poses(5)
    text = urscript_program(poses, name="sweep_table", header="demo 3\nscene: kitchen")
    prog = read_program(text)
    assert prog.name == "sweep_table"
    assert "# demo 3" in prog.header and "# scene: kitchen" in prog.header
    assert [m[1:] for m in prog.movel] == [(1.2, 0.25, 0.0)] * 5


def test_single_pose_and_plain_lists():
    prog = read_program(urscript_program([[0.4, 0.1, 0.192, np.pi, 0.0, 0.0]]))
    assert len(prog.movel) == 1
    # ints, numpy scalars and fractions are real numbers too
    row = [Fraction(2, 5), np.float32(0.25), 0, np.float64(np.pi), np.int64(0), 0]
    prog = read_program(urscript_program([row]))
    np.testing.assert_allclose(prog.movel[0][0], [0.4, 0.25, 0.0, np.pi, 0.0, 0.0], atol=1e-9)


@pytest.mark.parametrize(
    "value",
    [0.0, -0.0, 1.0, -1.5, 0.192, np.pi, -np.pi / 2, 1e-12, -1e-12, 1e-9, 0.123456789123, 6.0],
)
def test_format_number_precision(value):
    text = format_number(value)
    assert re.fullmatch(NUM, text)
    assert text != "-0.0"
    assert abs(float(text) - value) <= PRECISION


@pytest.mark.parametrize(
    ("value", "error", "message"),
    [
        (1e300, URScriptError, r"value: 1e\+300 is too large to write"),
        (-1e9, URScriptError, r"value: -1e\+09 is too large"),
        (np.nan, URScriptError, "value: must be finite, got nan"),
        (True, URScriptTypeError, r"value: expected a real number, got True \(bool\)"),
        ("0.5", URScriptTypeError, "value: expected a real number, got '0.5'"),
        (1j, URScriptTypeError, "value: expected a real number, got 1j"),
    ],
)
def test_format_number_refuses(value, error, message):
    with pytest.raises(error, match=message):
        format_number(value)


# ------------------------------------------------------------------ pose refusals
GOOD = [0.4, 0.1, 0.2, np.pi, 0.0, 0.0]  # tool down, reachable


def poses_with(row: list, at: int = 2, n: int = 4) -> list:
    """``n`` good poses (spread along y) with ``row`` at index ``at``."""
    out = [[0.4, 0.05 * k, 0.2, np.pi, 0.0, 0.0] for k in range(n)]
    out[at] = row
    return out


@pytest.mark.parametrize(
    ("row", "error", "message"),
    [
        # the issue's cases
        (
            [0.4, 0.1, 0.2, 0, 180.0, 0],
            URScriptError,
            r"poses\[2\]: rotation vector \(0, 180, 0\) has norm 180 rad, more than π.*degrees",
        ),
        (
            [0.4, 0.1, 0.2, 1e300, 0, 0],
            URScriptError,
            r"poses\[2\]: rotation vector \(1e\+300, 0, 0\) has norm 1e\+300 rad",
        ),
        (
            [0.4, 0.1, -0.9, np.pi, 0, 0],
            URScriptError,
            r"poses\[2\]: position \(0.4, 0.1, -0.9\) m is outside the workspace: "
            r"z = -0.9 m is below 0 m \(under the table plane\)",
        ),
        (
            [0.0, 0.0, 0.0, 0, 0, 0],
            URScriptError,
            r"poses\[2\]: unreachable \(position \(0, 0, 0\) m\): too close to the base axis",
        ),
        (
            [0.0, 0.0, 0.0, np.pi, 0, 0],
            URScriptError,
            r"poses\[2\]: unreachable \(position \(0, 0, 0\) m\)",
        ),
        (
            [0.4, 0.1, 1e300, np.pi, 0, 0],
            URScriptError,
            r"poses\[2\]: position \(0.4, 0.1, 1e\+300\) m is outside the workspace: z = 1e\+300 m"
            r" is above 1.2 m \(millimetres passed as metres\?\)",
        ),
        (
            [400.0, 100.0, 192.0, np.pi, 0, 0],
            URScriptError,
            r"poses\[2\]: position \(400, 100, 192\) m is outside .*x = 400 m is above 1.2 m "
            r"\(millimetres",
        ),
        (
            [0.0, 0.9, 0.3, np.pi, 0, 0],  # inside the box, out of reach
            URScriptError,
            r"poses\[2\]: unreachable \(position \(0, 0.9, 0.3\) m\): too far",
        ),
        # values of the wrong kind, named where they are
        (
            [0.4, True, 0.2, np.pi, 0, 0],
            URScriptTypeError,
            r"poses\[2\] y: expected a real number, got True \(bool\)",
        ),
        (
            [0.4, 0.1, np.bool_(False), np.pi, 0, 0],
            URScriptTypeError,
            r"poses\[2\] z: expected a real number, got np.False_|poses\[2\] z: .*False",
        ),
        (["0.4", 0.1, 0.2, np.pi, 0, 0], URScriptTypeError, r"poses\[2\] x: .* got '0.4' \(str\)"),
        ([0.4, 0.1, 0.2, None, 0, 0], URScriptTypeError, r"poses\[2\] rx: .* got None"),
        ([0.4, 0.1, 0.2, np.pi, 1j, 0], URScriptTypeError, r"poses\[2\] ry: .* got 1j \(complex\)"),
        ([0.4, 0.1, 0.2, np.pi, 0, object()], URScriptTypeError, r"poses\[2\] rz: .* \(object\)"),
        ([0.4, 0.1, 0.2, np.pi, 0, [0.0]], URScriptTypeError, r"poses\[2\] rz: .* got \[0.0\]"),
        ([0.4, 0.1, np.nan, np.pi, 0, 0], URScriptError, r"poses\[2\] z: must be finite, got nan"),
        (
            [0.4, -np.inf, 0.2, np.pi, 0, 0],
            URScriptError,
            r"poses\[2\] y: must be finite, got -inf",
        ),
        (
            [10**400, 0.1, 0.2, np.pi, 0, 0],
            URScriptError,
            r"poses\[2\] x: 1000.*\.\.\. is not a usable",
        ),
        ([0.4, 0.1, 0.2, np.pi, 0], URScriptError, r"poses\[2\]: expected 6 numbers .* got 5"),
        (
            "0.4, 0.1, 0.2, 3.14, 0, 0",
            URScriptTypeError,
            r"poses\[2\]: expected a row of 6 numbers",
        ),
        (None, URScriptTypeError, r"poses\[2\]: expected a row of 6 numbers, got None"),
    ],
)
def test_pose_refusals_name_index_and_value(row, error, message):
    with pytest.raises(error, match=message) as info:
        urscript_program(poses_with(row))
    assert info.value.index == 2
    assert info.value.argument == "poses"


def test_first_bad_pose_is_named():
    poses = sweep_poses(10)
    poses[7, 2] = -0.05
    with pytest.raises(URScriptError, match=r"poses\[7\]: position .* z = -0.05 m is below"):
        urscript_program(poses)
    poses[4, 4] = 4.0  # rotation checks come before the box
    with pytest.raises(URScriptError, match=r"poses\[4\]: rotation vector"):
        urscript_program(poses)


@pytest.mark.parametrize(
    ("poses", "error", "message"),
    [
        (np.zeros((3, 5)), URScriptError, r"poses: expected an array of shape \(n, 6\)"),
        (
            np.zeros(6),
            URScriptError,
            r"poses: expected an array of shape \(n, 6\), got shape \(6,\)",
        ),
        (np.ones((2, 6), dtype=bool), URScriptTypeError, r"poses\[0\] x: .* got .*True"),
        (np.ones((2, 6), dtype=complex), URScriptTypeError, r"poses\[0\] x: .* \(complex128\)"),
        (np.full((2, 6), "0.4"), URScriptTypeError, r"poses\[0\] x: .* got np.str_\('0.4'\)|'0.4'"),
        (np.array([GOOD, [0.4, 0.1, np.nan, 0, 0, 0]]), URScriptError, r"poses\[1\] z: .* nan"),
        (np.array([GOOD, [0.4, 0.1, 0.2, np.inf, 0, 0]]), URScriptError, r"poses\[1\] rx: .*inf"),
        (np.array([GOOD, GOOD], dtype=object), None, None),
        (np.zeros((0, 6)), URScriptError, r"poses: needs at least 1 row\(s\), got 0"),
        ([], URScriptError, r"poses: needs at least 1 row\(s\), got 0"),
        ({"x": 0.4}, URScriptTypeError, "poses: expected a list of rows .* got dict"),
        ("0.4", URScriptTypeError, "poses: expected a list of rows .* got str"),
        (0.4, URScriptTypeError, "poses: expected a list of rows .* got float"),
        (None, URScriptError, "poses: required with motion='movel'"),
    ],
)
def test_pose_array_refusals(poses, error, message):
    if error is None:
        read_program(urscript_program(poses))
        return
    with pytest.raises(error, match=message):
        urscript_program(poses)


def test_rotation_norm_tolerance():
    r = np.array([np.pi, 0.0, 0.0])
    urscript_program([[0.4, 0.1, 0.2, *(r * (1 + 2e-10))]])  # π + 6e-10: round-off
    with pytest.raises(URScriptError, match=r"poses\[0\]: rotation vector .* norm 3.14159 rad"):
        urscript_program([[0.4, 0.1, 0.2, *np.add(r, [2e-9, 0.0, 0.0])]])


# ------------------------------------------------------------------ workspace
def test_workspace_default_is_table_and_reach():
    assert DEFAULT_WORKSPACE == Workspace()
    assert DEFAULT_WORKSPACE.lower[2] == 0.0 and DEFAULT_WORKSPACE.check_reach
    urscript_program([[0.4, 0.1, 0.0, np.pi, 0, 0]])  # on the table plane: allowed
    with pytest.raises(URScriptError, match=r"z = -1e-06 m is below 0 m"):
        urscript_program([[0.4, 0.1, -1e-6, np.pi, 0, 0]])


def test_workspace_box_is_configurable():
    desk = Workspace(lower=(0.2, -0.3, 0.15), upper=(0.7, 0.3, 0.5))
    poses = sweep_poses(8)  # x in [0.3, 0.6], |y| <= 0.15, z = 0.192
    urscript_program(poses, workspace=desk)
    low = Workspace(lower=(0.2, -0.3, 0.2), upper=(0.7, 0.3, 0.5))
    with pytest.raises(URScriptError, match=r"poses\[0\]: .* z = 0.192 m is below 0.2 m$"):
        urscript_program(poses, workspace=low)
    narrow = Workspace(lower=(0.2, -0.1, 0.0), upper=(0.7, 0.1, 0.5))
    with pytest.raises(URScriptError, match=r"poses\[\d+\]: .* y = 0.1\d* m is above 0.1 m"):
        urscript_program(poses, workspace=narrow)


def test_workspace_unbounded_is_explicit_and_still_refuses_absurd_values():
    origin = [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0]]
    with pytest.raises(URScriptError, match="unreachable"):
        urscript_program(origin)
    free = Workspace.unbounded()
    assert not free.check_reach
    read_program(urscript_program(origin, workspace=free))
    read_program(urscript_program([[0.4, 0.1, -0.9, 0, 0, 0]], workspace=free))
    with pytest.raises(URScriptError, match=r"poses\[0\]: position .* x = 1e\+300 m is above 1000"):
        urscript_program([[1e300, 0, 0.2, 0, 0, 0]], workspace=free)
    with pytest.raises(URScriptError, match=r"poses\[0\]: rotation vector .* degrees"):
        urscript_program([[0.4, 0.1, 0.2, 0, 180.0, 0]], workspace=free)
    with pytest.raises(URScriptTypeError, match=r"workspace: expected a Workspace .*unbounded"):
        urscript_program(origin, workspace=None)


def test_workspace_checks_positions_and_poses_on_their_own():
    desk = Workspace(lower=(0.2, -0.3, 0.15), upper=(0.7, 0.3, 0.5))
    inside = desk.check_positions([[0.4, 0.0, 0.2]])
    assert inside.dtype == np.float64 and inside.shape == (1, 3)
    below = r"^points\[1\]: position .* z = 0.1 m is below 0.15 m$"
    with pytest.raises(URScriptError, match=below):
        desk.check_positions([[0.4, 0.0, 0.2], [0.4, 0.0, 0.1]], "points")
    with pytest.raises(URScriptError, match=r"positions\[0\] z: must be finite, got nan"):
        desk.check_positions(np.array([[0.4, 0.0, np.nan]]))
    poses = sweep_poses(8)
    np.testing.assert_array_equal(desk.check_poses(poses), poses)
    with pytest.raises(URScriptError, match=r"^poses\[0\]: unreachable .* for the UR5$"):
        Workspace().check_poses([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0]])
    with pytest.raises(URScriptError, match=r"^path\[0\]: rotation vector .* degrees\)$"):
        Workspace().check_poses([[0.4, 0.1, 0.2, 0, 180.0, 0]], name="path")
    with pytest.raises(URScriptTypeError, match="arm: expected an Arm"):
        Workspace().check_poses(poses, arm="UR5")


def test_workspace_tool_moves_the_checked_point():
    tip = np.eye(4)
    tip[2, 3] = 0.19  # brush tip 0.19 m along the flange z axis (down when sweeping)
    brush = Workspace(tool=tip)
    assert brush.tool_matrix is not None and brush.tool_matrix[2, 3] == 0.19
    # a tip pose 2 mm above the table is a flange pose at 0.192 m: reachable
    urscript_program([[0.45, 0.1, 0.002, np.pi, 0, 0]], workspace=brush)
    # the servoj stream is checked at the tip: flange 0.192 m up puts the tip at 0.002 m,
    # and 0.15 m up puts it under the table
    for height, ok in ((0.192, True), (0.15, False)):
        pose = np.eye(4)
        pose[:3, :3] = np.diag([1.0, -1.0, -1.0])
        pose[:3, 3] = [0.45, 0.1, height]
        q = ur5.nearest_solution(pose, Q_ABOVE)
        stream = np.repeat(q[None], 3, axis=0)
        kwargs = {"motion": "servoj", "joint_path": stream, "times": np.arange(3) * DT}
        urscript_program(**kwargs)  # the flange itself is above the table
        if ok:
            urscript_program(**kwargs, workspace=brush)
        else:
            with pytest.raises(URScriptError, match=r"joint_path\[0\]: tool position .* z = -0.04"):
                urscript_program(**kwargs, workspace=brush)


@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"lower": (0, 0, 0), "upper": (1, 1, 0)}, URScriptError, "box is empty along z"),
        ({"lower": (0, 0, -np.inf)}, URScriptError, r"lower\[2\]: must be finite, got -inf"),
        ({"upper": (1, 1, 2000.0)}, URScriptError, r"upper\[2\]: must be within ±1000 m"),
        ({"upper": (1, 1)}, URScriptTypeError, "upper: expected 3 numbers"),
        ({"lower": (0, True, 0)}, URScriptTypeError, r"lower\[1\]: expected a real number"),
        ({"check_reach": 1}, URScriptTypeError, "check_reach: expected a bool"),
        ({"tool": np.zeros((4, 4))}, URScriptError, "tool: .*bottom row"),
        ({"tool": np.eye(3)}, URScriptError, r"tool: expected an array of shape \(n, 4\)"),
        ({"tool": np.eye(5, 4)}, URScriptError, r"tool: expected shape \(4, 4\), got \(5, 4\)"),
        (
            {"tool": [[1, 1, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]},
            URScriptError,
            "tool: rotation part is not orthonormal",
        ),
    ],
)
def test_workspace_refusals(kwargs, error, message):
    with pytest.raises(error, match=message):
        Workspace(**kwargs)


_CORNERS = st.one_of(
    st.lists(st.floats(allow_nan=True, allow_infinity=True), min_size=0, max_size=4),
    st.builds(np.array, st.lists(st.floats(-2, 2), min_size=3, max_size=3)),
    st.just(np.array(0.5)),
    st.none(),
    st.text(max_size=3),
    st.tuples(st.booleans(), st.integers(), st.floats()),
)


@settings(max_examples=150, deadline=2000)
@given(
    lower=_CORNERS,
    upper=_CORNERS,
    check_reach=st.one_of(st.booleans(), st.none(), st.integers()),
    tool=st.one_of(
        st.none(),
        st.just(np.eye(4)),
        st.lists(st.lists(st.floats(-2, 2), min_size=4, max_size=4), max_size=5),
        st.text(max_size=3),
    ),
)
def test_fuzzed_workspace_is_built_or_refused(lower, upper, check_reach, tool):
    try:
        box = Workspace(lower, upper, check_reach, tool)
    except URScriptError as exc:
        assert str(exc)
        return
    assert all(lo < hi for lo, hi in zip(box.lower, box.upper, strict=True))
    assert isinstance(box.check_reach, bool)


# ------------------------------------------------------------------ movel arguments
@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"speed": True}, URScriptTypeError, r"speed: expected a real number, got True \(bool\)"),
        ({"speed": "0.2"}, URScriptTypeError, r"speed: expected a real number, got '0.2'"),
        ({"speed": None}, URScriptTypeError, r"speed: expected a real number, got None"),
        ({"speed": np.array(0.2)}, URScriptTypeError, r"speed: expected a real number"),
        ({"speed": 0.0}, URScriptError, "speed: must be > 0 m/s, got 0"),
        ({"speed": 1.5}, URScriptError, "speed: must be <= 1 m/s, got 1.5"),
        ({"speed": 250.0}, URScriptError, "speed: must be <= 1 m/s, got 250"),
        ({"speed": np.nan}, URScriptError, "speed: must be finite, got nan"),
        ({"acceleration": -1.0}, URScriptError, r"acceleration: must be > 0 m/s\^2, got -1"),
        ({"acceleration": 50.0}, URScriptError, "acceleration: must be <= 5"),
        ({"acceleration": False}, URScriptTypeError, "acceleration: expected a real number"),
        ({"blend_radius": -0.01}, URScriptError, "blend_radius: must be >= 0 m, got -0.01"),
        ({"blend_radius": 1e300}, URScriptError, r"blend_radius: must be <= 1 m, got 1e\+300"),
        ({"blend_radius": True}, URScriptTypeError, "blend_radius: expected a real number"),
        ({"blend_radius": 0.5}, URScriptError, "blend_radius: .* not below half the shortest move"),
        ({"name": "1abc"}, URScriptError, "name: must be a URScript identifier"),
        ({"name": "my prog"}, URScriptError, "name: must be a URScript identifier"),
        ({"name": "end"}, URScriptError, "name: 'end' is a reserved word"),
        ({"name": "movel"}, URScriptError, "name: 'movel' is a reserved word or a URScript"),
        ({"name": 3}, URScriptError, r"name: must be a URScript identifier \(.*\), got 3"),
        ({"motion": "movej"}, URScriptError, "motion: expected 'movel' or 'servoj'"),
        ({"motion": np.array(["movel"])}, URScriptError, "motion: expected 'movel' or 'servoj'"),
        ({"times": [0.0, 0.008]}, URScriptError, "times, joint_path: only used with motion='serv"),
        ({"header": "caf\u00e9"}, URScriptError, "header: must be ASCII"),
        ({"header": "a\nb\x00c"}, URScriptError, r"header: .* line 1 is 'b\\x00c'"),
        ({"header": 3}, URScriptTypeError, "header: expected a str"),
    ],
)
def test_movel_argument_refusals(kwargs, error, message):
    with pytest.raises(error, match=message):
        urscript_program(sweep_poses(10), **kwargs)


def test_errors_are_value_and_type_errors():
    # callers catching the built-in kinds keep working
    assert issubclass(URScriptError, ValueError)
    assert issubclass(URScriptTypeError, URScriptError) and issubclass(URScriptTypeError, TypeError)


def test_blend_radius_against_shortest_move():
    poses = np.array([[0.4, 0.0, 0.2, 0, 0, 0], [0.41, 0.0, 0.2, 0, 0, 0], [0.5, 0, 0.2, 0, 0, 0]])
    read_program(urscript_program(poses, blend_radius=0.0049))
    with pytest.raises(URScriptError, match=r"0.01 m between poses 0 and 1"):
        urscript_program(poses, blend_radius=0.005)
    repeated = np.vstack((poses[:1], poses))
    read_program(urscript_program(repeated))  # a repeated pose is fine without blending
    with pytest.raises(URScriptError, match="blend_radius"):
        urscript_program(repeated, blend_radius=0.001)


# ------------------------------------------------------------------ servoj
def servo_stream(rate: float = 125.0, speed_fraction: float = 0.2):
    q = np.array(
        [
            [0.0, -1.57, 1.2, -1.2, -1.57, 0.0],
            [0.3, -1.4, 1.0, -1.1, -1.57, 0.3],
            [0.5, -1.5, 1.3, -1.3, -1.5, 0.6],
        ]
    )
    timing = time_parameterize(q, speed_fraction=speed_fraction)
    samples = timing.resample(rate)
    times, qq = samples.times, samples.positions
    return times, qq


@pytest.mark.parametrize(("rate", "fraction"), [(125.0, 0.2), (500.0, 0.2), (125.0, 1.0)])
def test_servoj_program(rate, fraction):
    times, q = servo_stream(rate, fraction)
    text = urscript_program(motion="servoj", joint_path=q, times=times)
    prog = read_program(text)
    head = "\n".join(prog.header)
    assert f"{len(q)} samples" in head and "lfdkit" in head and "radians" in head
    assert len(prog.servoj) == len(q)
    assert not prog.movel
    assert len(prog.movej) == 1
    np.testing.assert_allclose(prog.movej[0], q[0], atol=PRECISION)
    for i, (qi, t, lookahead, gain) in enumerate(prog.servoj):
        np.testing.assert_allclose(qi, q[i], rtol=0, atol=PRECISION)
        assert t == pytest.approx(1.0 / rate, abs=1e-12)
        assert (lookahead, gain) == (0.1, 300)


def step_from_rest(step: float, joint: int = 0, dt: float = DT, n: int = 3):
    """A stream that holds Q_ABOVE, then steps ``joint`` by ``step`` and holds again."""
    q = np.repeat(Q_ABOVE[None], n, axis=0)
    q[1:, joint] += step
    return {"motion": "servoj", "joint_path": q, "times": np.arange(n) * dt}


def test_servoj_refuses_the_issues_step_from_rest():
    # 0.025 rad in 8 ms is 3.125 rad/s, under the 3.2 rad/s speed limit, but from rest it
    # needs 0.025 / 0.008² = 390.625 rad/s².
    with pytest.raises(
        URScriptError,
        match=r"joint_path\[1\] joint 0: a step of 0.025 rad in 0.008 s from rest at sample 0 "
        r"needs 390.625 rad/s\^2, above the UR5 limit of 15 rad/s\^2",
    ) as info:
        urscript_program(**step_from_rest(0.025))
    assert info.value.index == 1


def test_servoj_acceleration_limit_is_the_known_answer():
    # from rest, a step s in one tick dt needs s / dt²; the limit 15 rad/s² allows
    # s = 15 dt² (0.96 mrad at 125 Hz), then the stop after it needs the same.
    limit = UR5.max_joint_acceleration[0] * DT**2
    hold = step_from_rest(limit * (1 - 1e-6), joint=3)
    hold["joint_path"] = np.vstack((hold["joint_path"][:2], hold["joint_path"][1:]))
    hold["times"] = np.arange(4) * DT
    read_program(urscript_program(**hold))
    with pytest.raises(URScriptError, match=r"joint_path\[1\] joint 3: .* needs 15.0000\d* rad"):
        urscript_program(**step_from_rest(limit * (1 + 1e-6), joint=3))


def test_servoj_refuses_a_sudden_speed_change_and_a_sudden_stop():
    times, q = servo_stream(125.0, 0.2)
    bumped = q.copy()
    bumped[50:, 2] += 0.003  # +0.375 rad/s between samples 49 and 50
    with pytest.raises(
        URScriptError, match=r"joint_path\[49\] joint 2: a speed change from .* to .* rad/s needs"
    ):
        urscript_program(motion="servoj", joint_path=bumped, times=times)
    # cut mid-motion: the program ends while the joints are moving
    k = int(np.argmax(np.abs(np.diff(q[:, 0]))))
    with pytest.raises(
        URScriptError, match=rf"joint_path\[{k}\] joint \d: stopping after the last sample from"
    ):
        urscript_program(motion="servoj", joint_path=q[: k + 1], times=times[: k + 1])


def test_servoj_errors():
    times, q = servo_stream()
    ok = {"motion": "servoj", "joint_path": q, "times": times}
    jump = q.copy()
    jump[5:, 0] += 0.1  # 0.1 rad in one 8 ms step
    listed = q.tolist()
    listed[3][4] = True
    cases = [
        ({"joint_path": None}, URScriptError, "joint_path, times: both are required"),
        ({"times": None}, URScriptError, "joint_path, times: both are required"),
        ({"times": times[:-1]}, URScriptError, r"times: expected shape \(\d+,\)"),
        ({"times": times * 0.2}, URScriptError, r"times: step 0.0016 s is outside \[0.002, 1\] s"),
        ({"times": times * 200}, URScriptError, r"times: step 1.6 s is outside \[0.002, 1\] s"),
        ({"times": times * 1e300}, URScriptError, r"times: step 8e\+297 s is outside"),
        ({"times": np.r_[times[:-1], times[-1] + 0.001]}, URScriptError, "times: must be equally"),
        ({"times": times[::-1]}, URScriptError, "times: must be equally spaced and increasing"),
        ({"times": np.r_[times[:-1], np.nan]}, URScriptError, r"times\[\d+\]: must be finite"),
        ({"times": [True] * len(q)}, URScriptTypeError, r"times\[0\]: expected a real number"),
        ({"times": "0.008"}, URScriptTypeError, "times: expected a sequence of numbers"),
        ({"times": times[:, None]}, URScriptError, r"times: expected shape \(n,\)"),
        ({"joint_path": q[:, :5]}, URScriptError, r"joint_path: expected an array of shape"),
        ({"joint_path": listed}, URScriptTypeError, r"joint_path\[3\] joint 4: .* got True"),
        (
            {"joint_path": q + 7.0},
            URScriptError,
            r"joint_path\[0\] joint 0: 7 rad is outside the UR5 joint limits \[-6.28319, 6.28319\]",
        ),
        (
            {"joint_path": jump},
            URScriptError,
            r"joint_path\[5\] joint 0: moves at 12.5\d* rad/s from sample 4, above .* 3.2 rad/s",
        ),
        ({"joint_path": q[:1], "times": times[:1]}, URScriptError, r"needs at least 2 row\(s\)"),
    ]
    for change, error, message in cases:
        with pytest.raises(error, match=message):
            urscript_program(**{**ok, **change})
    with pytest.raises(URScriptError, match="poses: not used with motion='servoj'"):
        urscript_program(sweep_poses(3), **ok)


def test_servoj_refuses_a_tool_under_the_table():
    q = np.zeros((3, 6))  # stretched out along -x: flange 5.5 mm under the base plane
    with pytest.raises(
        URScriptError,
        match=r"joint_path\[0\]: tool position \(-0.81725, -0.19145, -0.00549\) m is outside the "
        r"workspace: z = -0.00549 m is below 0 m \(under the table plane\)",
    ):
        urscript_program(motion="servoj", joint_path=q, times=np.arange(3) * DT)
    urscript_program(
        motion="servoj", joint_path=q, times=np.arange(3) * DT, workspace=Workspace.unbounded()
    )


# ------------------------------------------------------------------ properties
@st.composite
def sweeping_pose_rows(draw):
    """Tool-down sweeping poses on a random spiral path within the UR5's reach."""
    n = draw(st.integers(2, 25))
    steps = draw(st.lists(st.floats(0.01, 0.25), min_size=n - 1, max_size=n - 1))
    angle = draw(st.floats(-np.pi, np.pi)) + np.concatenate(([0.0], np.cumsum(steps)))
    radius = np.array(draw(st.lists(st.floats(0.25, 0.7), min_size=n, max_size=n)))
    path = np.column_stack((radius * np.cos(angle), radius * np.sin(angle)))
    height = draw(st.floats(0.0, 0.45))
    yaw = draw(st.floats(-np.pi, np.pi))
    p = pose_vector(sweeping_poses(path, height=height, yaw_offset=yaw))
    p[:, 3:] = unwrap_rotvecs(p[:, 3:])  # tool-down: every norm stays π
    return p


@settings(max_examples=60, deadline=2000)
@given(
    poses=sweeping_pose_rows(),
    speed=st.floats(1e-3, 1.0),
    acceleration=st.floats(1e-3, 5.0),
    blend_fraction=st.floats(0.0, 0.99),
)
def test_movel_round_trip_on_random_sweeps(poses, speed, acceleration, blend_fraction):
    seg = np.linalg.norm(np.diff(poses[:, :3], axis=0), axis=1)
    blend = blend_fraction * 0.5 * seg.min()
    prog = read_program(
        urscript_program(poses, speed=speed, acceleration=acceleration, blend_radius=blend)
    )
    got = np.array([m[0] for m in prog.movel])
    np.testing.assert_allclose(got, poses, rtol=0, atol=PRECISION)
    for i, (_, a, v, r) in enumerate(prog.movel):
        assert abs(a - acceleration) <= PRECISION and abs(v - speed) <= PRECISION
        assert abs(r - (blend if i < len(poses) - 1 else 0.0)) <= PRECISION


@settings(max_examples=25, deadline=5000)
@given(
    offsets=st.lists(
        st.lists(st.floats(-0.1, 0.1), min_size=6, max_size=6), min_size=1, max_size=4
    ),
    fraction=st.floats(0.05, 1.0),
    rate=st.sampled_from([125.0, 250.0, 500.0]),
)
def test_servoj_round_trip_on_random_trajectories(offsets, fraction, rate):
    waypoints = Q_ABOVE + np.vstack(([0.0] * 6, offsets))
    if np.linalg.norm(np.diff(waypoints, axis=0), axis=1).max() < 1e-3:
        waypoints[-1, 0] += 0.05  # time_parameterize needs some motion
    samples = time_parameterize(waypoints, speed_fraction=fraction).resample(rate)
    times, q = samples.times, samples.positions
    prog = read_program(urscript_program(motion="servoj", joint_path=q, times=times))
    got = np.array([s[0] for s in prog.servoj])
    np.testing.assert_allclose(got, q, rtol=0, atol=PRECISION)
    assert all(abs(s[1] - 1.0 / rate) <= PRECISION for s in prog.servoj)


@settings(max_examples=60, deadline=2000)
@given(step=st.floats(1e-7, 0.02), rate=st.sampled_from([125.0, 500.0]))
def test_servoj_step_from_rest_refused_exactly_above_the_limit(step, rate):
    dt = 1.0 / rate
    needed = step / dt**2  # from rest, then the stop after it needs as much
    kwargs = step_from_rest(step, dt=dt)
    if step / dt > UR5.max_joint_speed[0] * (1 + 1e-8):  # the speed limit is checked first
        with pytest.raises(URScriptError, match=r"joint_path\[1\] joint 0: moves at .* rad/s"):
            urscript_program(**kwargs)
    elif needed <= UR5.max_joint_acceleration[0] * (1 - 1e-9):
        read_program(urscript_program(**kwargs))
    elif needed > UR5.max_joint_acceleration[0] * (1 + 1e-8):
        with pytest.raises(URScriptError, match=r"joint_path\[1\] joint 0: a step of") as info:
            urscript_program(**kwargs)
        value = float(re.search(r"needs (\S+) rad/s", str(info.value)).group(1))
        assert value == pytest.approx(needed, rel=1e-5)


_SCALARS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(-(10**400), 10**400),
    st.booleans(),
    st.none(),
    st.text(max_size=5),
    st.complex_numbers(max_magnitude=10),
    st.just(object()),
    st.sampled_from([np.float32(0.3), np.int8(1), np.bool_(True), np.nan, Fraction(1, 3)]),
)
_ROWS = st.one_of(
    st.lists(st.lists(_SCALARS, min_size=5, max_size=7), max_size=4),
    st.lists(
        st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6).map(
            lambda r: [r[0], r[1], abs(r[2]), *(np.array(r[3:]) * np.pi)]
        ),
        min_size=1,
        max_size=4,
    ),
    st.builds(
        np.array,
        st.lists(st.lists(st.floats(-4, 4), min_size=6, max_size=6), min_size=1, max_size=3),
        dtype=st.sampled_from([np.float64, np.float32, np.int64, bool, complex, object, str]),
    ),
    _SCALARS,
)


_FUZZ = {
    "poses": _ROWS,
    "name": st.one_of(st.text(max_size=8), _SCALARS),
    "motion": st.one_of(st.sampled_from(["movel", "servoj", "movej"]), _SCALARS),
    "speed": _SCALARS,
    "acceleration": _SCALARS,
    "blend_radius": _SCALARS,
    "times": st.one_of(_ROWS, st.lists(_SCALARS, max_size=4)),
    "joint_path": _ROWS,
    "header": st.one_of(st.text(max_size=12), _SCALARS),
    "workspace": st.sampled_from([Workspace.unbounded(), None, "box", DEFAULT_WORKSPACE.lower]),
}
_VALID_MOVEL = {"poses": [[0.4, 0.1, 0.2, np.pi, 0.0, 0.0], [0.45, 0.1, 0.2, np.pi, 0.0, 0.0]]}
_VALID_SERVOJ = {
    "motion": "servoj",
    "joint_path": np.repeat(Q_ABOVE[None], 3, axis=0),
    "times": np.arange(3) * DT,
}


@settings(max_examples=400, deadline=2000, suppress_health_check=[HealthCheck.too_slow])
@given(
    base=st.sampled_from([_VALID_MOVEL, _VALID_SERVOJ]),
    changes=st.lists(st.sampled_from(sorted(_FUZZ)), min_size=1, max_size=3, unique=True).flatmap(
        lambda keys: st.fixed_dictionaries({k: _FUZZ[k] for k in keys})
    ),
)
def test_fuzzed_arguments_give_a_program_or_a_urscript_error(base, changes):
    kwargs = {**base, **changes}
    try:
        text = urscript_program(**kwargs)
    except URScriptError as exc:
        event(f"refused: {exc.argument}")
        assert str(exc)  # a message, never a bare error
        return
    event("program")
    prog = read_program(text)  # a program is always well formed, every number written
    assert len(prog.movel) + len(prog.servoj) >= 1


@settings(max_examples=100, deadline=2000)
@given(
    program=st.one_of(st.text(max_size=40), st.binary(max_size=10), _SCALARS),
    filename=st.sampled_from(["a.script", "sub/../b.script", "c"]),
    overwrite=st.booleans(),
)
def test_fuzzed_write_urscript_writes_only_the_target(program, filename, overwrite):
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        (root / "sub").mkdir()
        target = root / filename
        try:
            out = write_urscript(target, program, overwrite=overwrite)
        except URScriptError:
            assert sorted(p.name for p in root.iterdir()) == ["sub"]
            return
        assert out == target
        # Bytes, not read_text: universal newlines would turn a written "\r\n" into "\n".
        written = target.read_bytes().decode()
        assert written == (program if program.endswith("\n") else program + "\n")
        assert sorted(p.name for p in root.rglob("*")) == sorted(["sub", target.name])


# ------------------------------------------------------------------ writing
def test_write_urscript(tmp_path):
    text = urscript_program(sweep_poses(4))
    out = write_urscript(tmp_path / "sweep.script", text)
    assert out == tmp_path / "sweep.script"
    assert out.read_bytes() == text.encode("ascii")
    with pytest.raises(FileExistsError, match="already exists"):
        write_urscript(out, "def other():\nend\n")
    assert out.read_text() == text  # untouched
    other = urscript_program(sweep_poses(6))
    write_urscript(out, other, overwrite=True)
    assert out.read_text() == other
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sweep.script"]  # no temporary left


def test_write_urscript_errors(tmp_path):
    with pytest.raises(URScriptError, match="program: is empty"):
        write_urscript(tmp_path / "a.script", "  \n")
    with pytest.raises(URScriptError, match="program: must be ASCII"):
        write_urscript(tmp_path / "a.script", "# caf\u00e9\n")
    with pytest.raises(URScriptTypeError, match="program: expected a str"):
        write_urscript(tmp_path / "a.script", b"def x():\nend\n")
    with pytest.raises(FileNotFoundError):
        write_urscript(tmp_path / "missing" / "a.script", "def x():\nend\n")
    assert list(tmp_path.iterdir()) == []


# ------------------------------------------------------------------ the arm
def test_joint_stream_is_checked_against_the_arms_limits():
    """A base move timed for the UR5 (3.2 rad/s) is too fast for the UR10 (120°/s)."""
    q = np.repeat(Q_ABOVE[None], 2, axis=0)
    q[1, 0] += 2.0
    samples = time_parameterize(q).resample(125.0)
    times, stream = samples.times, samples.positions
    read_program(urscript_program(motion="servoj", joint_path=stream, times=times))
    with pytest.raises(
        URScriptError,
        match=r"joint 0: moves at .* rad/s from sample .*, above the UR10 limit "
        r"of 2.0944 rad/s",
    ):
        urscript_program(motion="servoj", joint_path=stream, times=times, arm=UR10)
    # Timed for the UR10, the same move passes.
    samples = time_parameterize(q, arm=UR10).resample(125.0)
    times, stream = samples.times, samples.positions
    read_program(urscript_program(motion="servoj", joint_path=stream, times=times, arm=UR10))
    # Joint limits are the arm's too.
    narrow = dataclasses.replace(UR10, name="UR10 narrow", joint_limits=[[-1.0, 1.0]] * 6)
    with pytest.raises(URScriptError, match=r"outside the UR10 narrow joint limits \[-1, 1\]"):
        urscript_program(motion="servoj", joint_path=stream, times=times, arm=narrow)


def test_reach_is_the_arms():
    """Tool-down poses 0.95 m out: beyond the UR5's reach, within the UR10's."""
    path = np.column_stack((np.linspace(-0.2, 0.2, 5), np.full(5, 0.95)))
    poses = pose_vector(sweeping_poses(path))
    poses[:, 3:] = unwrap_rotvecs(poses[:, 3:])
    with pytest.raises(URScriptError, match=r"poses\[0\]: unreachable .* for the UR5"):
        urscript_program(poses)
    prog = read_program(urscript_program(poses, arm=UR10))
    assert len(prog.movel) == 5


def test_arm_must_be_a_ur_arm():
    with pytest.raises(URScriptTypeError, match="arm: expected an Arm") as info:
        urscript_program(sweep_poses(), arm="UR10")
    assert info.value.argument == "arm"
    with pytest.raises(URScriptError, match="arm: URScript drives UR arms; planar 3R does not"):
        urscript_program(sweep_poses(), arm=PLANAR)


def test_a_500_hz_stream_whose_step_rounds_just_under_2_ms_is_accepted():
    # Times from a resampler: the mean step can land a rounding error below 0.002 s.
    times = np.arange(40) * (0.002 * (1 - 1e-12))
    q = np.repeat(Q_ABOVE[None], 40, axis=0)
    prog = read_program(urscript_program(motion="servoj", joint_path=q, times=times))
    assert len(prog.servoj) == 40
    with pytest.raises(URScriptError, match=r"times: step 0\.0019 s is outside"):
        urscript_program(motion="servoj", joint_path=q, times=np.arange(40) * 0.0019)
