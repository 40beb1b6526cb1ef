"""Tests for lfdkit.robot.urscript: URScript programs for a UR controller.

Programs are read back with a small regex-based reader written here, which
accepts only the exact shapes of lines the module documents.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np
import pytest

import lfdkit
from lfdkit.robot.poses import pose_vector, sweeping_poses, unwrap_rotvecs
from lfdkit.robot.timing import time_parameterize
from lfdkit.robot.urscript import format_number, urscript_program, write_urscript

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


def test_single_pose():
    prog = read_program(urscript_program([[0.4, 0.1, 0.192, np.pi, 0.0, 0.0]]))
    assert len(prog.movel) == 1


@pytest.mark.parametrize(
    "value",
    [0.0, -0.0, 1.0, -1.5, 0.192, np.pi, -np.pi / 2, 1e-12, -1e-12, 1e-9, 0.123456789123, 6.0],
)
def test_format_number_precision(value):
    text = format_number(value)
    assert re.fullmatch(NUM, text)
    assert text != "-0.0"
    assert abs(float(text) - value) <= PRECISION


def test_numbers_survive_at_stated_precision():
    rng = np.random.default_rng(0)
    poses = np.column_stack(
        (rng.uniform(-0.5, 0.5, (40, 3)), rng.uniform(-2 * np.pi, 2 * np.pi, (40, 3)))
    )
    prog = read_program(urscript_program(poses))
    got = np.array([m[0] for m in prog.movel])
    np.testing.assert_allclose(got, poses, rtol=0, atol=PRECISION)


# ------------------------------------------------------------------ servoj
def servo_stream(rate: float = 125.0):
    q = np.array(
        [
            [0.0, -1.57, 1.2, -1.2, -1.57, 0.0],
            [0.3, -1.4, 1.0, -1.1, -1.57, 0.3],
            [0.5, -1.5, 1.3, -1.3, -1.5, 0.6],
        ]
    )
    timing = time_parameterize(q, speed_fraction=0.2)
    times, qq, _, _ = timing.resample(rate)
    return times, qq


@pytest.mark.parametrize("rate", [125.0, 500.0])
def test_servoj_program(rate):
    times, q = servo_stream(rate)
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


# ------------------------------------------------------------------ errors
@pytest.mark.parametrize(
    ("kwargs", "error", "message"),
    [
        ({"speed": 0.0}, ValueError, "speed: must be > 0"),
        ({"speed": 1.5}, ValueError, "speed: must be <= 1 m/s"),
        ({"speed": np.nan}, ValueError, "speed: must be finite"),
        ({"acceleration": -1.0}, ValueError, "acceleration: must be > 0"),
        ({"acceleration": 50.0}, ValueError, "acceleration: must be <= 5"),
        ({"blend_radius": -0.01}, ValueError, "blend_radius: must be >= 0"),
        ({"blend_radius": 0.5}, ValueError, "blend_radius: .* not below half the shortest move"),
        ({"name": "1abc"}, ValueError, "name: must be a URScript identifier"),
        ({"name": "my prog"}, ValueError, "name: must be a URScript identifier"),
        ({"name": "end"}, ValueError, "name: 'end' is a reserved word"),
        ({"motion": "movej"}, ValueError, "motion: expected 'movel' or 'servoj'"),
        ({"times": [0.0, 0.008]}, ValueError, "times, joint_path: only used with motion='servoj'"),
        ({"header": "caf\u00e9"}, ValueError, "header: must be ASCII"),
        ({"header": 3}, TypeError, "header: expected a str"),
    ],
)
def test_movel_errors(kwargs, error, message):
    with pytest.raises(error, match=message):
        urscript_program(sweep_poses(10), **kwargs)


@pytest.mark.parametrize(
    ("poses", "message"),
    [
        (np.zeros((3, 5)), "poses: expected 6 columns"),
        (np.zeros(6), "poses: expected a 2-D array"),
        ([[0.4, 0.1, np.nan, 0, 0, 0]], "poses: contains NaN"),
        ([[0.4, 0.1, 0.2, np.inf, 0, 0]], "poses: contains an infinite value"),
        ([[400.0, 100.0, 192.0, 0, 0, 0]], "poses: row 0 is .* from the base .*millimetres"),
        (None, "poses: required with motion='movel'"),
    ],
)
def test_pose_errors(poses, message):
    with pytest.raises(ValueError, match=message):
        urscript_program(poses)


def test_blend_radius_against_shortest_move():
    poses = np.array([[0.4, 0.0, 0.2, 0, 0, 0], [0.41, 0.0, 0.2, 0, 0, 0], [0.5, 0, 0.2, 0, 0, 0]])
    read_program(urscript_program(poses, blend_radius=0.0049))
    with pytest.raises(ValueError, match=r"0.01 m between poses 0 and 1"):
        urscript_program(poses, blend_radius=0.005)
    repeated = np.vstack((poses[:1], poses))
    read_program(urscript_program(repeated))  # a repeated pose is fine without blending
    with pytest.raises(ValueError, match="blend_radius"):
        urscript_program(repeated, blend_radius=0.001)


def test_servoj_errors():
    times, q = servo_stream()
    ok = {"motion": "servoj", "joint_path": q, "times": times}
    jump = q.copy()
    jump[5:, 0] += 0.1  # 0.1 rad in one 8 ms step
    cases = [
        ({"joint_path": None}, "joint_path, times: both are required"),
        ({"times": None}, "joint_path, times: both are required"),
        ({"times": times[:-1]}, r"times: expected shape \(\d+,\)"),
        ({"times": times * 0.2}, r"times: step 0.0016 s is shorter than one controller period"),
        ({"times": np.r_[times[:-1], times[-1] + 0.001]}, "times: must be equally spaced"),
        ({"times": times[::-1]}, "times: must be equally spaced and increasing"),
        ({"times": np.r_[times[:-1], np.nan]}, "times: contains NaN"),
        ({"joint_path": q[:, :5]}, "joint_path: expected 6 columns"),
        ({"joint_path": q + 7.0}, r"joint_path: joint 0 at row 0 is .* outside the UR5 limits"),
        ({"joint_path": jump}, r"joint_path: joint 0 moves at 12.5\d* rad/s between rows 4 and 5"),
    ]
    for change, message in cases:
        with pytest.raises(ValueError, match=message):
            urscript_program(**{**ok, **change})
    with pytest.raises(ValueError, match="poses: not used with motion='servoj'"):
        urscript_program(sweep_poses(3), **ok)


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
    with pytest.raises(ValueError, match="program: is empty"):
        write_urscript(tmp_path / "a.script", "  \n")
    with pytest.raises(ValueError, match="program: must be ASCII"):
        write_urscript(tmp_path / "a.script", "# caf\u00e9\n")
    with pytest.raises(TypeError, match="program: expected a str"):
        write_urscript(tmp_path / "a.script", b"def x():\nend\n")
    with pytest.raises(FileNotFoundError):
        write_urscript(tmp_path / "missing" / "a.script", "def x():\nend\n")
    assert list(tmp_path.iterdir()) == []
