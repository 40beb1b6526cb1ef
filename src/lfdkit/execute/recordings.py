"""Tool poses from recorded joint states: forward kinematics of an arm description.

A kinesthetic-teaching log records ``sensor_msgs/JointState``;
:func:`tool_poses_from_joint_states` reads it (:func:`lfdkit.io.recordings.read_joint_states`)
and turns each configuration into the flange (or tool) pose in the base
frame with :func:`lfdkit.execute.ur5.forward`. The joints are found by the UR
drivers' names (:data:`UR_JOINT_NAMES`, with or without a prefix such as
``ur5_``), else, for messages without names, by position.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lfdkit.core.rotations import continuous, quaternion_from_matrix
from lfdkit.execute.arm import UR5, Arm
from lfdkit.execute.ur5 import forward
from lfdkit.io.recordings import PoseRecording, RecordingError, joint_names, read_joint_states
from lfdkit.model.demos import PathLike

__all__ = ["UR_JOINT_NAMES", "tool_poses_from_joint_states"]

#: The joint names of Universal Robots' ROS drivers, base to wrist.
UR_JOINT_NAMES = (
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
)


def tool_poses_from_joint_states(
    path: PathLike,
    topic: str,
    *,
    arm: Arm = UR5,
    tool: Any = None,
    joints: tuple[str, ...] | None = None,
) -> PoseRecording:
    """The tool poses of a recorded ``sensor_msgs/JointState`` topic.

    Parameters
    ----------
    path : str or os.PathLike
        The recording (see :mod:`lfdkit.io.recordings`).
    topic : str
        The joint-state topic, e.g. ``"/joint_states"``.
    arm : Arm
        The arm description (:data:`lfdkit.execute.arm.UR5` by default).
    tool : array_like, shape (4, 4), optional
        Flange→tool transform (metres); the flange pose without it.
    joints : tuple of str, optional
        The arm's joint names in the recording, base first; by default the UR
        drivers' names (a common prefix, ``ur5_shoulder_pan_joint``, is found).

    Returns
    -------
    PoseRecording
        Positions in metres in the base frame, orientations as unit
        quaternions, the joint recording's times; ``frame`` is
        ``("base", "tool")`` (or ``"flange"``).

    Raises
    ------
    RecordingError
        As :func:`lfdkit.io.recordings.read_joint_states`, or when the
        joints do not match the arm's.
    """
    wanted = joints
    if wanted is None:
        wanted = _ur_names(joint_names(path, topic), arm, path, topic)
    rec = read_joint_states(path, topic, joints=wanted)
    if rec.positions.shape[1] != arm.n_joints:
        raise RecordingError(
            f"{path}: topic {topic!r} has {rec.positions.shape[1]} joints; "
            f"the {arm.name} has {arm.n_joints}"
        )
    T = forward(rec.positions, tool=tool, arm=arm)
    return PoseRecording(
        rec.times,
        np.ascontiguousarray(T[:, :3, 3]),
        orientations=continuous(quaternion_from_matrix(T[:, :3, :3])),
        start_ns=rec.start_ns,
        topic=topic,
        msgtype="sensor_msgs/msg/JointState",
        frame=("base", "flange" if tool is None else "tool"),
        stamps=rec.stamps,
        notes=rec.notes,
    )


def _ur_names(names: tuple[str, ...], arm: Arm, path: PathLike, topic: str) -> tuple[str, ...]:
    """The recording's names of the UR joints (prefix allowed), or all of them if unnamed."""
    if all(n.startswith("joint_") for n in names) and len(names) == arm.n_joints:
        return names  # messages without names: read by position
    found = []
    for base in UR_JOINT_NAMES[: arm.n_joints]:
        match = [n for n in names if n == base or n.endswith("_" + base) or n.endswith("/" + base)]
        if len(match) != 1:
            raise RecordingError(
                f"{path}: topic {topic!r}: cannot find the {arm.name} joint {base!r} "
                f"among {', '.join(names)}; name the joints (base first)"
            )
        found.append(match[0])
    return tuple(found)
