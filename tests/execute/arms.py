"""Arm descriptions shared by the robot tests."""

from __future__ import annotations

import numpy as np

from lfdkit.execute.arm import Arm

#: A planar arm of three joints (all twists 0, the joints' axes parallel): not UR-type.
PLANAR = Arm(
    name="planar 3R",
    d=(0.1, 0.0, 0.0),
    a=(0.3, 0.25, 0.1),
    alpha=(0.0, 0.0, 0.0),
    joint_limits=[[-np.pi, np.pi]] * 3,
    max_joint_speed=(1.0, 2.0, 3.0),
    max_joint_acceleration=5.0,
    link_masses=(1.0, 0.8, 0.3),
    link_radii=(0.04, 0.03, 0.02),
    kp=(500.0, 300.0, 100.0),
    kv=(20.0, 12.0, 4.0),
)
