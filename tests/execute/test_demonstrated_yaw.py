"""Sweeping with the demonstrated tool heading instead of the path's tangent."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core import rotations as rot
from lfdkit.execute.poses import path_yaw, yaw_from_quaternions
from lfdkit.tasks.sweeping.scenarios import sweeping_poses


def _path() -> np.ndarray:
    s = np.linspace(0, 1, 60)
    return np.c_[0.3 + 0.4 * s, 0.2 * np.sin(2 * np.pi * s)]


@pytest.mark.parametrize("tool_down", [True, False])
def test_the_demonstrated_heading_is_followed(tool_down: bool) -> None:
    path = _path()
    tangent = path_yaw(path)
    held = tangent + 0.4 * np.sin(np.linspace(0, 3, len(path)))  # the demonstrator's wrist
    demonstrated = sweeping_poses(path, tool_down=tool_down, yaw=held)
    quats = rot.quaternion_from_matrix(demonstrated[:, :3, :3])
    np.testing.assert_allclose(yaw_from_quaternions(quats), held, atol=1e-12)
    again = sweeping_poses(path, tool_down=tool_down, yaw=yaw_from_quaternions(quats))
    np.testing.assert_allclose(again, demonstrated, atol=1e-12)
    # without yaw: the tangent, as before; yaw_offset adds to either
    np.testing.assert_allclose(
        sweeping_poses(path, tool_down=tool_down, yaw=tangent),
        sweeping_poses(path, tool_down=tool_down),
        atol=1e-15,
    )
    turned = sweeping_poses(path, yaw=held, yaw_offset=0.1)
    np.testing.assert_allclose(
        yaw_from_quaternions(rot.quaternion_from_matrix(turned[:, :3, :3])), held + 0.1, atol=1e-12
    )


def test_a_tilted_tool_keeps_its_heading() -> None:
    """The heading of a tool held tilted (not straight down) is its x axis on the table."""
    psi = np.linspace(-3, 3, 40)
    q = rot.multiply(rot.exp(np.c_[0 * psi, 0 * psi, psi / 2]), rot.exp([0.1, 0.05, 0.0]))
    got = yaw_from_quaternions(q)
    R = rot.matrix_from_quaternion(q)
    np.testing.assert_allclose(
        np.cos(got), R[:, 0, 0] / np.hypot(R[:, 0, 0], R[:, 1, 0]), atol=1e-12
    )
    assert np.all(np.abs(np.diff(got)) < 0.5)  # unwrapped


def test_bad_yaw() -> None:
    with pytest.raises(ValueError, match=r"yaw: expected shape \(60,\)"):
        sweeping_poses(_path(), yaw=np.zeros(3))
    with pytest.raises(ValueError, match="yaw: contains NaN"):
        sweeping_poses(_path(), yaw=np.full(60, np.nan))
    with pytest.raises(ValueError, match="no heading"):
        yaw_from_quaternions([[0.0, np.sqrt(0.5), 0.0, np.sqrt(0.5)]])  # x axis straight down
