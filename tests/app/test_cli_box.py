"""``lfdkit plan --obstacle CLASS:X,Y,sx=..,sy=..[,yaw=..]``: boxes from the command line."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lfdkit.model.box import Box
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill
from tests.app.test_cli import read_plan_csv, run_cli, usage_exit
from tests.conftest import example_skill_file_copy

GOAL = "0.36,0.5"


@pytest.fixture(scope="module")
def skill_path(example_skill_file_once, tmp_path_factory):
    return example_skill_file_copy(example_skill_file_once, tmp_path_factory.mktemp("box"))


def densely(points: np.ndarray, per_segment: int = 50) -> np.ndarray:
    """The polyline resampled with ``per_segment`` points on every segment (ends included)."""
    t = np.linspace(0.0, 1.0, per_segment, endpoint=False)[None, :, None]
    inner = points[:-1, None] + t * np.diff(points, axis=0)[:, None]
    return np.vstack([inner.reshape(-1, points.shape[1]), points[-1:]])


def test_a_box_on_the_command_line_is_planned_round_and_never_entered(capsys, skill_path):
    box = Box.from_yaw("cup", [0.0, 0.47], [0.08, 0.05], np.radians(30.0))
    skill = Skill.load(skill_path)
    assert box.distance(skill.nominal(None, [0.36, 0.5])) < 0  # the nominal crosses it
    arg = "cup:0.0,0.47,sx=0.08,sy=0.05,yaw=30deg"
    by_degrees = run_cli(capsys, "plan", skill_path, "--goal", GOAL, "--obstacle", arg)
    assert by_degrees[0] == 0, by_degrees[2]
    rows = read_plan_csv(by_degrees[1])[1]
    assert np.array_equal(rows, skill.plan(None, [0.36, 0.5], Scene((box,))))
    assert box.signed_distances(densely(rows)).min() > 0.0  # at clearance 0: a hard barrier
    # the same box in radians, keys in another order, spaces around tokens
    arg = f"cup:0.0, 0.47, yaw={math.radians(30.0)!r}rad, sy=0.05,sx=0.08"
    code, stdout, err = run_cli(capsys, "plan", skill_path, "--goal", GOAL, "--obstacle", arg)
    assert code == 0, err
    np.testing.assert_allclose(read_plan_csv(stdout)[1], rows, atol=1e-9)


def test_a_round_obstacle_stays_round_and_a_rounded_box_keeps_its_radius(capsys, skill_path):
    skill = Skill.load(skill_path)
    code, stdout, err = run_cli(
        capsys, "plan", skill_path, "--goal", GOAL, "--obstacle", "cup:0.0,0.47,r=0.03"
    )
    assert code == 0, err
    round_plan = skill.plan(None, [0.36, 0.5], Scene((Obstacle("cup", [0.0, 0.47], 0.03),)))
    assert np.array_equal(read_plan_csv(stdout)[1], round_plan)
    arg = "cup:0.0,0.47,sx=0.04,sy=0.02,r=0.01"
    code, stdout, err = run_cli(capsys, "plan", skill_path, "--goal", GOAL, "--obstacle", arg)
    assert code == 0, err
    box = Box.from_yaw("cup", [0.0, 0.47], [0.04, 0.02], 0.0, radius=0.01)
    assert np.array_equal(read_plan_csv(stdout)[1], skill.plan(None, [0.36, 0.5], Scene((box,))))


@pytest.mark.parametrize(
    ("arg", "fragments"),
    [
        ("cup:0,0.47,sx=0.08", ["missing its edge length sy=", "sx=, sy="]),
        ("cup:0,0.47,yaw=30deg", ["missing its edge length sx="]),
        ("cup:0,0.47,sx=0.08,sy=-0.05", ["sy in", "edge length must be a finite number >= 0"]),
        ("cup:0,0.47,sx=0.08,sy=nan", ["sy in", ">= 0"]),
        ("cup:0,0.47,sx=0.08,sy=0.05,sz=0.1", ["sz=", "a 2-D box has edges sx=, sy= only"]),
        ("cup:0,0.47,sx=0.08,sy=0.05,size=3", ["unknown key size=", "sx=, sy=, sz=, yaw="]),
        ("cup:0,0.47,sx=0.08,sy=0.05,sx=0.1", ["sx= is given twice", "give it once"]),
        ("cup:0,0.47,sx=0.08,sy=0.05,yaw=30", ["yaw in", "no unit", "yaw=30deg"]),
        ("cup:0,0.47,sx=0.08,sy=0.05,yaw=1_0deg", ["yaw in", "not a finite number"]),
        # In a row: 4-7 or 10 values only, numbers, edges >= 0, one turn, a unit quaternion.
        ("box:0.3,0,0.2,0.1,0.3,0.16,0,0", ["8 values", "CX,CY[,CZ],LX,LY[,LZ]"]),
        ("cup:0,0.47,0.08,-0.05", ["edge lengths must be finite numbers >= 0"]),
        ("cup:0,0.47,0.08,0.05,30", ["yaw in", "no unit"]),
        ("cup:0,0.47,0.08,0.05,30deg,yaw=1rad", ["yaw is given twice"]),
        ("box:0.3,0,0.2,0.1,0.3,0.16,0,0,0,0", ["quaternion"]),
    ],
    ids=[
        "missing",
        "yaw-only",
        "negative",
        "nan",
        "sz-2d",
        "unknown",
        "twice",
        "unitless",
        "bad",
        "row-count",
        "row-negative",
        "row-unitless",
        "row-yaw-twice",
        "row-zero-quaternion",
    ],
)
def test_bad_boxes_are_usage_errors_on_one_line(capsys, skill_path, arg, fragments):
    code, _, err = usage_exit(capsys, "plan", skill_path, "--obstacle", arg)
    assert code == 2
    (line,) = [line for line in err.splitlines() if "error:" in line]
    assert "--obstacle" in line
    for fragment in fragments:
        assert fragment in line, line


def test_help_documents_boxes(capsys, skill_path):
    code, stdout, _ = usage_exit(capsys, "plan", "--help")
    assert code == 0
    flat = " ".join(stdout.split())
    assert "sx=SX,sy=SY[,sz=SZ][,yaw=30deg|0.52rad]" in flat


@pytest.mark.parametrize(
    "row",
    [
        "cup:0.0,0.47,0.08,0.05,30deg",  # centre, edges, yaw
        "cup:0.0,0.47,0.08,0.05,0.5235987755982988rad",
    ],
)
def test_a_box_in_a_row_is_the_box_by_name(capsys, skill_path, row):
    by_name = run_cli(capsys, "plan", skill_path, "--goal", GOAL, "--obstacle",
                      "cup:0.0,0.47,sx=0.08,sy=0.05,yaw=30deg")  # fmt: skip
    in_a_row = run_cli(capsys, "plan", skill_path, "--goal", GOAL, "--obstacle", row)
    assert by_name[0] == 0 and in_a_row[0] == 0, in_a_row[2]
    np.testing.assert_allclose(read_plan_csv(in_a_row[1])[1], read_plan_csv(by_name[1])[1])


def test_a_3d_box_in_a_row_takes_a_quaternion() -> None:
    from lfdkit.app.cli.common import _obstacle

    half = np.sqrt(0.5)
    quaternion = _obstacle(f"carton:0.3,0,0.2,0.1,0.3,0.16,0,0,{half},{half}")
    by_yaw = _obstacle("carton:0.3,0,0.2,sx=0.1,sy=0.3,sz=0.16,yaw=90deg")
    assert quaternion[:4] == by_yaw[:4] == ("carton", [0.3, 0.0, 0.2], 0.0, None)
    assert quaternion[4][0] == by_yaw[4][0] == [0.1, 0.3, 0.16]
    np.testing.assert_allclose(quaternion[4][1], by_yaw[4][1], atol=1e-15)
    tilted = _obstacle("carton:0.3,0,0.2,0.1,0.3,0.16,0.38268343,0,0,0.92387953")  # 45° about x
    np.testing.assert_allclose(
        tilted[4][1], [np.sin(np.pi / 8), 0, 0, np.cos(np.pi / 8)], atol=1e-8
    )


def test_a_box_in_centimetres_is_the_box_in_metres(capsys, skill_path):
    metres = run_cli(capsys, "plan", skill_path, "--goal", GOAL, "--obstacle",
                     "cup:0.0,0.47,sx=0.08,sy=0.05,yaw=30deg")  # fmt: skip
    centimetres = run_cli(capsys, "plan", skill_path, "--units", "cm", "--goal", "36,50",
                          "--obstacle", "cup:0,47,sx=8,sy=5,yaw=30deg")  # fmt: skip
    assert metres[0] == 0 and centimetres[0] == 0, centimetres[2]
    np.testing.assert_allclose(
        read_plan_csv(centimetres[1])[1], 100.0 * read_plan_csv(metres[1])[1], atol=1e-6
    )


def test_a_3d_moving_box_is_read_with_its_height_turn_and_velocity() -> None:
    from lfdkit.app.cli.common import _obstacle

    label, position, radius, velocity, box, normal = _obstacle(
        "carton:0.5,0,0.1,sx=0.2,sy=0.1,sz=0.3,yaw=90deg,r=0.005,vx=0,vy=0.1,vz=0"
    )
    assert (label, position, radius, velocity) == ("carton", [0.5, 0.0, 0.1], 0.005, [0, 0.1, 0])
    assert box[0] == [0.2, 0.1, 0.3]
    np.testing.assert_allclose(box[1], [0.0, 0.0, np.sqrt(0.5), np.sqrt(0.5)], atol=1e-15)
    assert normal is None
    assert _obstacle("cup:0.1,0.45,r=0.03") == ("cup", [0.1, 0.45], 0.03, None, None, None)


# ------------------------------------------------------------ half-spaces: tables and walls
# A table under the sweep (its surface at y = 0.42, free side up) with a cup standing on it
# (sunk 5 mm; a cup that only touches it, ~1e-17 m apart in floating point, no longer
# warns: tests/emulate/test_gaps.py). The table is of the learned class "marker": the
# example skill knows only cups and markers.
TABLE = "marker:0,0.42,nx=0,ny=1"
TABLE_CUP = "cup:-0.02,0.455,r=0.04"


def test_a_table_with_a_cup_on_the_command_line_is_the_libraries_half_space(capsys, skill_path):
    from lfdkit.model.half_space import HalfSpace

    table = HalfSpace("marker", [0.0, 0.42], 0.0, [0.0, 1.0])
    cup = Obstacle("cup", [-0.02, 0.455], 0.04)
    skill = Skill.load(skill_path)
    argv = ("plan", skill_path, "--goal", GOAL, "--obstacle", TABLE, "--obstacle", TABLE_CUP)
    code, stdout, err = run_cli(capsys, *argv)
    assert code == 0, err
    rows = read_plan_csv(stdout)[1]
    np.testing.assert_allclose(
        rows, skill.plan(None, [0.36, 0.5], Scene((table, cup))), rtol=0, atol=1e-12
    )
    assert cup.distance(skill.nominal(None, [0.36, 0.5])) < 0  # the nominal crosses the cup
    # Never below the table top (its height is linear along a segment: the points suffice).
    assert rows[:, 1].min() > 0.42 and cup.distance(rows) > 0
    # A normal of any length is the same direction: nx=0,ny=5 is the same table.
    code, stdout, err = run_cli(capsys, *argv[:4], "--obstacle", "marker:0,0.42,ny=5,nx=0",
                                "--obstacle", TABLE_CUP)  # fmt: skip
    assert code == 0, err
    np.testing.assert_allclose(read_plan_csv(stdout)[1], rows, rtol=0, atol=1e-12)


def test_a_table_in_millimetres_is_the_table_in_metres(capsys, skill_path):
    metres = run_cli(capsys, "plan", skill_path, "--goal", GOAL, "--obstacle", TABLE,
                     "--obstacle", TABLE_CUP)  # fmt: skip
    # Position and radius are lengths (scaled); the normal is a direction (not scaled).
    millimetres = run_cli(capsys, "plan", skill_path, "--units", "mm", "--goal", "360,500",
                          "--obstacle", "marker:0,420,nx=0,ny=1",
                          "--obstacle", "cup:-20,455,r=40")  # fmt: skip
    assert metres[0] == 0 and millimetres[0] == 0, millimetres[2]
    np.testing.assert_allclose(
        read_plan_csv(millimetres[1])[1], 1e3 * read_plan_csv(metres[1])[1], atol=1e-6
    )


@pytest.mark.parametrize(
    ("arg", "fragments"),
    [
        ("marker:0,0.4,nx=0", ["missing its normal component ny=", "nx=, ny="]),
        ("marker:0,0.4,nx=0,ny=0", ["the normal nx=, ny= is zero", "nz=1"]),
        ("marker:0,0.4,nx=0,ny=1,nz=0", ["nz=", "2-D half-space's normal has nx=, ny= only"]),
        ("marker:0,0.4,nx=0,ny=up", ["ny in", "finite number"]),
        ("marker:0,0.4,nx=0,ny=1,sx=1,sy=1", ["either a box's", "not both"]),
        ("marker:0,0.4,nx=0,ny=1,vx=0,vy=0.1", ["cannot move"]),
        ("marker:0,0.4,nx=0,ny=1,ny=2", ["ny= is given twice"]),
    ],
    ids=["missing", "zero", "nz-2d", "nan", "box-too", "moving", "twice"],
)
def test_bad_half_spaces_are_usage_errors_on_one_line(capsys, skill_path, arg, fragments):
    code, _, err = usage_exit(capsys, "plan", skill_path, "--obstacle", arg)
    assert code == 2
    (line,) = [line for line in err.splitlines() if "error:" in line]
    assert "--obstacle" in line
    for fragment in fragments:
        assert fragment in line, line
    if "twice" not in line:  # the example of a good one
        assert "table:0,0,0.7,nx=0,ny=0,nz=1" in line, line


def test_a_half_space_with_too_few_coordinates_for_the_skill_is_one_line(capsys, skill_path):
    arg = "marker:0,0,0.4,nx=0,ny=0,nz=1"  # a good form, wrong for this skill: as a round one
    code, _, err = run_cli(capsys, "plan", skill_path, "--obstacle", arg)
    assert code == 1
    assert "--obstacle marker: 3 coordinates for a 2-D skill" in err and len(err.splitlines()) == 1


def test_a_3d_table_is_read_with_its_normal_and_help_documents_it(capsys) -> None:
    from lfdkit.app.cli.common import _obstacle

    assert _obstacle("table:0.5,0,0.7,nz=2,ny=0,nx=0,r=0.01") == (
        "table", [0.5, 0.0, 0.7], 0.01, None, None, [0.0, 0.0, 2.0]
    )  # fmt: skip
    code, stdout, _ = usage_exit(capsys, "plan", "--help")
    assert code == 0
    assert "CLASS:X,Y[,Z],nx=NX,ny=NY[,nz=NZ][,r=R]" in " ".join(stdout.split())
