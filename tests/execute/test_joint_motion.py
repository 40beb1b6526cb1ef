"""The three joint motions answer ``duration``, ``n_joints`` and ``resample`` alike (one base).

Known answers: a joint path of 3 joints through 6 waypoints; the duration is the
last waypoint's time (the profile's grid end for :class:`Timing`), the fixed-rate
samples are :meth:`sample` on ``k / rate`` up to the first time at or after the
end (at rest at the last waypoint there), and a retimed motion's planned duration
is its plan's. The base cannot be made without a ``sample``.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from lfdkit.execute.joint_motion import JointMotion, RetimedMotion
from lfdkit.execute.timing import Timing, time_parameterize
from lfdkit.execute.trajectory import JointTrajectory, keep_timing

Q = np.array(
    [
        [0.0, -1.2, 0.8],
        [0.1, -1.0, 0.9],
        [0.3, -0.9, 0.7],
        [0.4, -1.1, 0.5],
        [0.6, -1.3, 0.6],
        [0.7, -1.2, 0.9],
    ]
)
PLAN_TIMES = np.array([0.0, 0.4, 0.9, 1.5, 2.2, 3.0])


@functools.cache
def motions() -> dict[str, JointMotion]:
    out: dict[str, JointMotion] = {
        "timing": time_parameterize(np.hstack([Q, np.zeros((6, 3))])),
        "kept": keep_timing(PLAN_TIMES, Q, 2.0, 20.0),  # within the limits: kept as planned
        "slowed": keep_timing(PLAN_TIMES / 10.0, Q, 2.0, 20.0),  # 10x too fast: slowed
    }
    try:
        from lfdkit.execute.jerk_limited import time_parameterize_ruckig

        out["ruckig"] = time_parameterize_ruckig(np.hstack([Q, np.zeros((6, 3))]))
    except ImportError:  # ruckig is optional
        pass
    return out


@pytest.mark.parametrize("name", ["timing", "kept", "slowed", "ruckig"])
def test_each_motion_resamples_at_a_fixed_rate_from_rest_to_rest(name) -> None:
    found = motions()
    if name not in found:
        pytest.skip("ruckig is not installed")
    motion = found[name]
    assert isinstance(motion, JointMotion)
    assert motion.n_joints == motion.waypoints.shape[1] == (3 if name in ("kept", "slowed") else 6)
    assert motion.duration == pytest.approx(motion.times[-1], rel=1e-9)
    rate = 50.0
    stream = motion.resample(rate)
    k = np.arange(len(stream.times))
    np.testing.assert_array_equal(stream.times, k / rate)
    assert stream.times[-2] < motion.duration <= stream.times[-1]
    again = motion.sample(stream.times)
    np.testing.assert_array_equal(stream.positions, again.positions)
    np.testing.assert_array_equal(stream.velocities, again.velocities)
    np.testing.assert_allclose(stream.positions[0], motion.waypoints[0], atol=1e-12)
    np.testing.assert_allclose(stream.positions[-1], motion.waypoints[-1], atol=1e-9)
    np.testing.assert_allclose(stream.velocities[-1], 0.0, atol=1e-12)


def test_a_retimed_motion_knows_its_plans_duration() -> None:
    found = motions()
    kept, slowed = found["kept"], found["slowed"]
    assert isinstance(kept, RetimedMotion) and isinstance(kept, JointTrajectory)
    assert kept.planned_duration == kept.duration == 3.0
    assert slowed.planned_duration == pytest.approx(0.3)
    assert slowed.duration > 3 * slowed.planned_duration
    assert not isinstance(found["timing"], RetimedMotion) and isinstance(found["timing"], Timing)


def test_the_base_needs_a_sample() -> None:
    with pytest.raises(TypeError, match="abstract"):
        JointMotion()  # type: ignore[abstract]
