"""Write small real recordings with rosbags' own writers (ROS 1, ROS 2 sqlite3, ROS 2 MCAP).

Each message is given as plain numbers; :func:`write_recording` builds the
messages of the ROS distribution's type store, serialises them and writes
them with the writer of the format asked for.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pytest

rosbags = pytest.importorskip(
    "rosbags", reason='rosbags is not installed: pip install "lfdkit[ros]" (or rosbags)'
)

from rosbags.rosbag1 import Writer as Writer1  # noqa: E402
from rosbags.rosbag2 import StoragePlugin  # noqa: E402
from rosbags.rosbag2 import Writer as Writer2  # noqa: E402
from rosbags.typesys import Stores, get_types_from_msg, get_typestore  # noqa: E402

KINDS = ("ros1", "sqlite3", "mcap")


@dataclass
class Sample:
    """One message: receive time, header stamp (ns; 0 = unset), and its content."""

    received: int
    stamp: int
    position: Any = (0.0, 0.0, 0.0)
    orientation: Any = (0.0, 0.0, 0.0, 1.0)
    parent: str = "world"
    child: str = "tool"
    joints: dict[str, float] = field(default_factory=dict)
    transforms: list[Sample] = field(default_factory=list)  # for TFMessage


def _typestore(kind: str):
    if kind == "ros1":
        ts = get_typestore(Stores.ROS1_NOETIC)
        for tf_type in ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage"):  # tf: ROS 1's older
            if tf_type not in ts.types:
                ts.register(
                    get_types_from_msg("geometry_msgs/TransformStamped[] transforms", tf_type)
                )
        return ts
    return get_typestore(Stores.ROS2_HUMBLE)


def _header(ts, kind: str, stamp: int, frame: str):
    t = ts.types["builtin_interfaces/msg/Time"](sec=stamp // 10**9, nanosec=stamp % 10**9)
    H = ts.types["std_msgs/msg/Header"]
    return H(seq=0, stamp=t, frame_id=frame) if kind == "ros1" else H(stamp=t, frame_id=frame)


def _pose(ts, s: Sample):
    P = ts.types["geometry_msgs/msg/Point"]
    Q = ts.types["geometry_msgs/msg/Quaternion"]
    x, y, z = (float(v) for v in s.position)
    qx, qy, qz, qw = (float(v) for v in s.orientation)
    return ts.types["geometry_msgs/msg/Pose"](P(x=x, y=y, z=z), Q(x=qx, y=qy, z=qz, w=qw))


def _transform(ts, kind: str, s: Sample):
    V = ts.types["geometry_msgs/msg/Vector3"]
    Q = ts.types["geometry_msgs/msg/Quaternion"]
    x, y, z = (float(v) for v in s.position)
    qx, qy, qz, qw = (float(v) for v in s.orientation)
    tr = ts.types["geometry_msgs/msg/Transform"](V(x=x, y=y, z=z), Q(x=qx, y=qy, z=qz, w=qw))
    return ts.types["geometry_msgs/msg/TransformStamped"](
        _header(ts, kind, s.stamp, s.parent), s.child, tr
    )


def _message(ts, kind: str, msgtype: str, s: Sample):
    short = msgtype.rsplit("/", 1)[-1]
    if short == "PoseStamped":
        return ts.types[msgtype](_header(ts, kind, s.stamp, s.parent), _pose(ts, s))
    if short == "Odometry":
        cov = np.zeros(36)
        pwc = ts.types["geometry_msgs/msg/PoseWithCovariance"](_pose(ts, s), cov)
        V = ts.types["geometry_msgs/msg/Vector3"]
        twist = ts.types["geometry_msgs/msg/Twist"](V(x=0.0, y=0.0, z=0.0), V(x=0.0, y=0.0, z=0.0))
        twc = ts.types["geometry_msgs/msg/TwistWithCovariance"](twist, cov)
        return ts.types[msgtype](_header(ts, kind, s.stamp, s.parent), s.child, pwc, twc)
    if short == "TransformStamped":
        return _transform(ts, kind, s)
    if short in ("TFMessage", "tfMessage"):
        return ts.types[msgtype]([_transform(ts, kind, t) for t in s.transforms])
    if short == "JointState":
        names = list(s.joints)
        values = np.array([s.joints[n] for n in names], dtype=np.float64)
        return ts.types[msgtype](
            _header(ts, kind, s.stamp, ""), names, values, np.zeros(0), np.zeros(0)
        )
    if short == "String":
        return ts.types[msgtype](data="hello")
    raise AssertionError(msgtype)


def write_recording(path: Path, kind: str, topics: dict[str, tuple[str, list[Sample]]]) -> Path:
    """Write ``topics`` (name → (message type, samples)) as a recording; returns its path.

    ``kind``: ``"ros1"`` writes ``path.bag``; ``"sqlite3"`` and ``"mcap"`` a ROS 2
    bag folder ``path``.
    """
    ts = _typestore(kind)
    if kind == "ros1":
        out = path.with_suffix(".bag")
        writer = Writer1(out)
    else:
        out = path
        plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
        writer = Writer2(out, version=9, storage_plugin=plugin)
    with writer:
        queue = []
        for topic, (msgtype, samples) in topics.items():
            conn = writer.add_connection(topic, msgtype, typestore=ts)
            for s in samples:
                msg = _message(ts, kind, msgtype, s)
                raw = (
                    ts.serialize_ros1(msg, msgtype)
                    if kind == "ros1"
                    else ts.serialize_cdr(msg, msgtype)
                )
                queue.append((s.received, conn, raw))
        for received, conn, raw in sorted(queue, key=lambda x: x[0]):
            writer.write(conn, received, raw)
    return out


def random_trajectory(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Times (ns), positions (n, 3) and unit quaternions (n, 4, w >= 0) of a known motion."""
    rng = np.random.default_rng(seed)
    ns = 1_700_000_000_123_456_789 + np.cumsum(rng.integers(5_000_000, 15_000_000, n))
    ns = ns - ns[0] + 1_700_000_000_123_456_789
    s = np.linspace(0.0, 1.0, n)
    pos = np.c_[0.4 * s, 0.2 * np.sin(3 * s), 0.1 + 0.05 * s] + rng.normal(0, 1e-3, (n, 3))
    q = rng.normal(size=4) + np.c_[0.2 * s, 0.1 * s, 0.3 * s, 0 * s]
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q *= np.sign(q[:, 3:4])
    return ns.astype(np.int64), pos, q
