"""A periodic wipe with orientation, learned by a rhythmic pose DMP, run on the UR5 in MuJoCo.

Issue 33, item 3: a synthetic wipe (a 12 × 4 cm figure-eight on a table, the
tool rocking ±9° about two axes, period 1.6 s, 1 mm and 5 mrad of noise) is
learned from 3.3 cycles; two cycles at 1.25× the speed, with a smooth start
and stop, go through the execute pipeline (tool poses, inverse kinematics, the
plan's timing, 500 Hz samples) to the UR5's MuJoCo model. Known answers: the
commanded tool poses are the rollout's (position and orientation), the timing
is kept, and the simulated tool tracks within 2 mm.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation, Slerp

from lfdkit.core.rotations import angle_between, exp, multiply
from lfdkit.execute.arm import UR5
from lfdkit.execute.kinematics import forward
from lfdkit.execute.pipeline import UR_START, TaskDescription, execute_plan
from lfdkit.imitate import RhythmicPoseDMP

PERIOD = 1.6
#: Tool pointing down (180° about x), the wipe's mean orientation in the base frame.
DOWN = np.array([1.0, 0.0, 0.0, 0.0])


def wipe(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positions (m, base frame: 0.45 m in front, 0.1 m above the base) and orientations."""
    u = 2 * np.pi * t / PERIOD
    positions = np.c_[0.45 + 0.02 * np.sin(2 * u), 0.06 * np.sin(u), np.full_like(u, 0.1)]
    rock = np.outer(0.08 * np.sin(u), [1.0, 0.0, 0.0]) + np.outer(
        0.05 * np.sin(2 * u + 0.3), [0.0, 1.0, 0.0]
    )
    return positions, multiply(exp(rock), DOWN)


@pytest.fixture(scope="module")
def wiping():
    rng = np.random.default_rng(4)
    t = np.linspace(0.0, 3.3 * PERIOD, 400)
    positions, orientations = wipe(t)
    positions = positions + rng.normal(0.0, 1e-3, positions.shape)
    orientations = multiply(orientations, exp(rng.normal(0.0, 2.5e-3, (len(t), 3))))
    dmp = RhythmicPoseDMP().fit(positions, orientations, t)
    duration = 2 / 1.25 * PERIOD + 1.0 * PERIOD  # two fast cycles and the ramps
    plan = dmp.rollout(duration, frequency=1.25, ramp=0.5 * PERIOD)
    run = execute_plan(plan, UR5, TaskDescription(q_start=UR_START), speed_fraction=1.0, rate=500.0)
    return dmp, plan, run


def test_the_wipe_is_commanded_as_learned(wiping) -> None:
    dmp, plan, run = wiping
    assert dmp.period_ == pytest.approx(PERIOD, rel=2e-3)
    assert run.trajectory.slowdowns == ()  # the rhythm's timing kept
    assert run.trajectory.duration == pytest.approx(plan.times[-1], abs=1e-9)
    # The commanded tool poses at the samples are the rollout's, interpolated.
    tool = forward(UR5, run.samples.positions, run.task.tool)
    at = run.samples.times
    expected = np.column_stack([np.interp(at, plan.times, plan.positions[:, i]) for i in range(3)])
    assert np.linalg.norm(tool[:, :3, 3] - expected, axis=1).max() < 2e-4
    commanded = Rotation.from_matrix(tool[:, :3, :3]).as_quat()
    slerped = Slerp(plan.times, Rotation.from_quat(plan.orientations))(at).as_quat()
    assert angle_between(commanded, slerped).max() < 1e-4
    # The tool rocks as demonstrated (up to 0.17 rad from down), and ends at rest at the centre.
    assert 0.1 < angle_between(commanded, DOWN).max() < 0.25
    assert angle_between(commanded[-1], dmp.orientation_.centre_) < 1e-3


def test_the_wipe_tracks_within_2_mm_in_mujoco(wiping) -> None:
    pytest.importorskip("mujoco")
    from lfdkit.execute.simulation import simulate_execution

    _, _, run = wiping
    check = simulate_execution(run)
    assert check.tracking_error <= 0.002
    assert check.touched == ()
