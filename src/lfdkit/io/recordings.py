"""Robot recordings: ROS 1 bags, ROS 2 bags (sqlite3 or MCAP storage) and MCAP files.

Read with the pure-Python `rosbags <https://gitlab.com/ternaris/rosbags>`_
library (``pip install "lfdkit[ros]"``; no ROS installation), imported only
when a recording is opened.

Recordings
----------
``NAME.bag``
    A ROS 1 bag.
``FOLDER/`` (with ``metadata.yaml``)
    A ROS 2 bag as ``ros2 bag record`` writes it, sqlite3 (``.db3``) or MCAP
    storage.
``NAME.mcap`` / ``NAME.db3``
    One storage file of a ROS 2 bag, or a plain MCAP file with ROS 2 (CDR)
    messages and their ``ros2msg``/``ros2idl`` schemas, as the ``mcap`` tools
    and Foxglove write them (types spelt ``pkg/Name`` are read as
    ``pkg/msg/Name``). MCAP files with other encodings (JSON, Protobuf, ROS 1
    messages) are refused with the reason.

Messages
--------
Poses (:func:`read_poses`) from ``geometry_msgs/PoseStamped``,
``PoseWithCovarianceStamped``, ``TransformStamped``, ``nav_msgs/Odometry``,
and ``tf2_msgs/TFMessage`` (``/tf``; ROS 1's ``tf/tfMessage`` too) with a
frame pair ``(parent, child)``:
the child's pose in the parent, chained through the frame tree over the
dynamic transforms of the topic and the static ones of ``/tf_static`` (both
directions: a frame pair that is not parent-first is inverted);
:func:`read_frame_poses` gives a frame pair's pose at given times (static or
interpolated), the task frames an import writes beside each demonstration
(an object's pose where the demonstration starts). Joint
positions (:func:`read_joint_states`) from ``sensor_msgs/JointState``;
:mod:`lfdkit.execute.recordings` turns them into tool poses. Both come as
timed paths (:class:`PoseRecording`, :class:`JointRecording`: each a
:class:`~lfdkit.model.timed_path.TimedPath` with the recording's metadata).

Timestamps
----------
Each sample's time is the message's header stamp; a message without a
header (none of those above) or with a zero stamp (publishers that never
set it) takes the time the recorder received it. The times returned are
seconds after the first sample, computed from integer nanoseconds (exact to
1 ns); the first sample's absolute time is kept as ``start_ns``. Samples are
put in time order; repeated stamps keep the last sample and are counted in
``notes``: nothing is dropped without a note.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from lfdkit.core.rotations import (
    check_quaternions,
    conjugate,
    continuous,
    matrix_from_quaternion,
    multiply,
    slerp,
)
from lfdkit.model.demos import PathLike
from lfdkit.model.timed_path import TimedPath

__all__ = [
    "INSTALL_HINT",
    "POSE_TYPES",
    "JointRecording",
    "PoseRecording",
    "RecordingError",
    "Topic",
    "joint_names",
    "list_topics",
    "read_frame_poses",
    "read_joint_states",
    "read_poses",
]

INSTALL_HINT = 'reading ROS bags and MCAP files needs rosbags: pip install "lfdkit[ros]"'

#: Message types :func:`read_poses` reads (ROS 2 spelling; ROS 1 bags map to the same).
POSE_TYPES = (
    "geometry_msgs/msg/PoseStamped",
    "geometry_msgs/msg/PoseWithCovarianceStamped",
    "geometry_msgs/msg/TransformStamped",
    "nav_msgs/msg/Odometry",
    "tf2_msgs/msg/TFMessage",
    "tf/msg/tfMessage",  # ROS 1's older tf package
)
JOINT_STATE = "sensor_msgs/msg/JointState"
_TF_STATIC = "/tf_static"


class RecordingError(ValueError):
    """A recording that cannot be read or does not hold what was asked for (one line)."""


@dataclass(frozen=True)
class Topic:
    """A topic of a recording: its name, message type and number of messages."""

    name: str
    msgtype: str
    count: int

    def __str__(self) -> str:
        return f"{self.name} ({self.msgtype}, {self.count} messages)"


@dataclass(frozen=True, eq=False, repr=False, kw_only=True)
class PoseRecording(TimedPath):
    """Poses read from one topic of a recording: a timed path and where it came from.

    A :class:`~lfdkit.model.timed_path.TimedPath` (read-only, no velocities:
    a recording has none) with the recording's metadata.

    Attributes
    ----------
    times : ndarray, shape (n,)
        Seconds after the first sample, strictly increasing.
    positions : ndarray, shape (n, 3)
        Positions in the message's units (metres in ROS).
    orientations : ndarray, shape (n, 4)
        Unit quaternions ``[x, y, z, w]``, signs made continuous.
    start_ns : int
        Absolute time of the first sample (nanoseconds since the epoch).
    topic, msgtype : str
    frame : tuple of str or None
        ``(parent, child)`` for transforms.
    stamps : str
        Where the times come from: ``"header"``, ``"receive"`` or ``"mixed"``.
    notes : tuple of str
        What was changed while reading (samples merged, times outside the
        span of every transform), for the report.
    """

    start_ns: int
    topic: str
    msgtype: str
    frame: tuple[str, str] | None = None
    stamps: str = "header"
    notes: tuple[str, ...] = field(default=())


@dataclass(frozen=True, eq=False, repr=False, kw_only=True)
class JointRecording(TimedPath):
    """Joint positions read from a ``sensor_msgs/JointState`` topic: a timed path and its joints.

    A :class:`~lfdkit.model.timed_path.TimedPath` (read-only, no velocities:
    a recording has none) with the joints' names and the recording's metadata.

    Attributes
    ----------
    times : ndarray, shape (n,)
        Seconds after the first sample, strictly increasing.
    positions : ndarray, shape (n, n_joints)
        Radians (revolute) or metres (prismatic).
    names : tuple of str
        The joints, in the column order of ``positions``.
    start_ns, topic, stamps, notes
        As :class:`PoseRecording`.
    """

    names: tuple[str, ...]
    start_ns: int
    topic: str
    stamps: str = "header"
    notes: tuple[str, ...] = field(default=())


# --------------------------------------------------------------------------- #
# Opening
# --------------------------------------------------------------------------- #


def _any_reader(path: Path) -> Any:
    """rosbags' AnyReader for ``path``, imported on first use (an optional dependency).

    ROS 2 bags written before Iron (Humble's sqlite3 storage) hold no message
    definitions; they are read with ROS 2 Humble's standard types, whose
    geometry_msgs, nav_msgs, sensor_msgs and tf2_msgs every ROS 2 release shares.
    """
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise RecordingError(INSTALL_HINT) from None
    return AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE))


@contextmanager
def _open(path: PathLike) -> Iterator[Any]:
    """An open ``rosbags`` AnyReader, every failure to open it as one line."""
    name = os.fspath(path)
    p = Path(name)
    if not p.exists():
        raise FileNotFoundError(2, "No such file or directory", name)
    if p.is_dir() and not (p / "metadata.yaml").exists():
        raise RecordingError(
            f"{name}: a folder without metadata.yaml is not a ROS 2 bag "
            "(give the bag folder, or its .db3/.mcap file)"
        )
    if p.is_file() and p.suffix not in (".bag", ".mcap", ".db3"):
        raise RecordingError(
            f"{name}: unknown recording type {p.suffix!r}; expected a ROS 1 .bag, a ROS 2 bag "
            "folder, or an .mcap or .db3 file"
        )
    if p.is_file() and p.stat().st_size == 0:
        raise RecordingError(f"{name}: is empty (0 bytes)")
    try:
        reader = _any_reader(p)
        reader.open()
    except (FileNotFoundError, RecordingError):
        raise
    except Exception as exc:  # rosbags' own errors, struct/zstd/sqlite errors on damaged files
        if "Profile is not ros2" in str(exc):
            raise RecordingError(
                f"{name}: an MCAP file without ROS 2 messages (its profile is not ros2: "
                "JSON, Protobuf or ROS 1 encoded?); lfdkit reads MCAP files of ROS 2 (CDR) "
                "messages"
            ) from None
        raise RecordingError(f"{name}: cannot read the recording ({_reason(exc)})") from None
    try:
        yield reader
    finally:
        reader.close()


def _reason(exc: BaseException) -> str:
    text = str(exc).splitlines()[0] if str(exc) else ""
    return text or type(exc).__name__


def _topics(reader: Any) -> list[Topic]:
    return [
        Topic(
            name, _normal(info.msgtype) if info.msgtype else "(several types)", int(info.msgcount)
        )
        for name, info in sorted(reader.topics.items())
    ]


def list_topics(path: PathLike) -> list[Topic]:
    """The topics of a recording, sorted by name.

    Raises
    ------
    RecordingError
        If rosbags is missing or the recording cannot be read (truncated,
        not a bag); one line naming the file.
    FileNotFoundError
        If ``path`` does not exist.
    """
    with _open(path) as reader:
        return _topics(reader)


def _present(topics: list[Topic]) -> str:
    return "; ".join(str(t) for t in topics) or "none (the recording is empty)"


def _is_tf(msgtype: str) -> bool:
    """tf2_msgs/TFMessage, or tf/tfMessage of ROS 1's older tf package."""
    return msgtype.lower().endswith("/tfmessage")


def _normal(msgtype: str) -> str:
    """``pkg/msg/Name`` also for ``pkg/Name`` (plain MCAP files and ROS 1 spell it so)."""
    parts = msgtype.split("/")
    return f"{parts[0]}/msg/{parts[1]}" if len(parts) == 2 else msgtype


def _connections(reader: Any, path: PathLike, topic: str, wanted: tuple[str, ...]) -> list[Any]:
    name = os.fspath(path)
    topics = _topics(reader)
    conns = [c for c in reader.connections if c.topic == topic]
    if not conns:
        raise RecordingError(f"{name}: no topic {topic!r}; topics present: {_present(topics)}")
    types = sorted({c.msgtype for c in conns})
    wrong = [t for t in types if _normal(t) not in wanted]
    if wrong:
        short = ", ".join(dict.fromkeys(w.rsplit("/", 1)[-1].replace("tfM", "TFM") for w in wanted))
        raise RecordingError(
            f"{name}: topic {topic!r} holds {', '.join(wrong)}; lfdkit reads {short} here"
        )
    return conns


def _messages(reader: Any, conns: list[Any], name: str) -> Iterator[tuple[Any, int, Any]]:
    # rosbags registers the types of a plain MCAP schema ("pkg/Name") as "pkg/msg/Name"
    known = reader.typestore.types
    names = {id(c): c.msgtype if c.msgtype in known else _normal(c.msgtype) for c in conns}
    try:
        for conn, received, raw in reader.messages(connections=conns):
            yield conn, received, reader.deserialize(raw, names[id(conn)])
    except RecordingError:
        raise
    except Exception as exc:  # damaged chunk, bad CDR, truncated file part-way
        raise RecordingError(f"{name}: cannot read the recording ({_reason(exc)})") from None


# --------------------------------------------------------------------------- #
# Times
# --------------------------------------------------------------------------- #


def _stamp_ns(msg: Any, received: int) -> tuple[int, bool]:
    """The header stamp in ns (and True), or the receive time (and False) if absent or zero."""
    header = getattr(msg, "header", None)
    if header is not None:
        stamp = header.stamp
        ns = int(stamp.sec) * 1_000_000_000 + int(getattr(stamp, "nanosec", 0))
        if ns != 0:
            return ns, True
    return int(received), False


def _order(stamps: list[int], from_header: list[bool]) -> tuple[np.ndarray, np.ndarray, str, list]:
    """Sort by time; of repeated stamps keep the last; the source word and the notes."""
    ns = np.asarray(stamps, dtype=np.int64)
    order = np.argsort(ns, kind="stable")
    ns = ns[order]
    notes = []
    last_of_each = np.r_[ns[1:] != ns[:-1], True]
    if not last_of_each.all():
        notes.append(
            f"{int((~last_of_each).sum())} samples repeated the time of the next one; "
            "kept the last of each"
        )
    keep = order[last_of_each]
    n_header = int(np.sum(np.asarray(from_header)[keep]))
    source = "header" if n_header == len(keep) else "receive" if n_header == 0 else "mixed"
    if source == "mixed":
        notes.append(
            f"{len(keep) - n_header} of {len(keep)} samples had no header stamp; "
            "took their receive time"
        )
    return keep, ns[last_of_each], source, notes


def _seconds(ns: np.ndarray) -> tuple[np.ndarray, int]:
    start = int(ns[0])
    return (ns - start).astype(np.float64) * 1e-9, start


def _need_samples(n: int, name: str, topic: str) -> None:
    if n == 0:
        raise RecordingError(f"{name}: topic {topic!r} has no messages")
    if n < 2:
        raise RecordingError(
            f"{name}: topic {topic!r} has {n} sample; a demonstration needs at least 2"
        )


# --------------------------------------------------------------------------- #
# Poses
# --------------------------------------------------------------------------- #


#: (position-like, quaternion-like) of each pose message type, by its short name.
_POSE_OF = {
    "PoseStamped": lambda m: (m.pose.position, m.pose.orientation),
    "PoseWithCovarianceStamped": lambda m: (m.pose.pose.position, m.pose.pose.orientation),
    "Odometry": lambda m: (m.pose.pose.position, m.pose.pose.orientation),
    "TransformStamped": lambda m: (m.transform.translation, m.transform.rotation),
}


def _xyz(v: Any) -> list[float]:
    return [float(v.x), float(v.y), float(v.z)]


def _xyzw(q: Any) -> list[float]:
    return [float(q.x), float(q.y), float(q.z), float(q.w)]


def read_poses(
    path: PathLike, topic: str, *, frame: tuple[str, str] | None = None
) -> PoseRecording:
    """Read the poses of one topic of a recording (see the module notes).

    Parameters
    ----------
    path : str or os.PathLike
        A ``.bag`` file, a ROS 2 bag folder, or an ``.mcap``/``.db3`` file.
    topic : str
        The topic, e.g. ``"/tool_pose"`` or ``"/tf"``.
    frame : (str, str), optional
        ``(parent, child)``: required for ``tf2_msgs/TFMessage`` topics (the
        child's pose in the parent); for other types it must be omitted.

    Returns
    -------
    PoseRecording

    Raises
    ------
    RecordingError
        One line naming the file: rosbags missing; unreadable or truncated
        recording; the topic missing (listing the topics present); a message
        type that holds no pose; fewer than 2 samples; a frame pair not
        connected by the transforms recorded; a quaternion that is not unit.
    FileNotFoundError
        If ``path`` does not exist.
    """
    name = os.fspath(path)
    with _open(path) as reader:
        conns = _connections(reader, path, topic, POSE_TYPES)
        msgtype = _normal(conns[0].msgtype)
        if _is_tf(msgtype):
            if frame is None:
                raise RecordingError(
                    f"{name}: topic {topic!r} holds transforms between frames; name the pair "
                    f"with a frame (parent:child); recorded: {_frame_pairs(reader, conns, name)}"
                )
            return _read_tf(reader, conns, name, topic, frame)
        if frame is not None:
            raise RecordingError(
                f"{name}: a frame pair applies to tf2_msgs/TFMessage topics; "
                f"{topic!r} holds {msgtype}"
            )
        # One flat row per message, built inline: this loop is the import's own cost
        # beside rosbags' deserialisation (benchmarks/recordings.py).
        rows: list[tuple] = []
        add = rows.append
        pose_of = {c.msgtype: _POSE_OF[c.msgtype.rsplit("/", 1)[-1]] for c in conns}
        for conn, received, msg in _messages(reader, conns, name):
            stamp = msg.header.stamp
            ns = stamp.sec * 1_000_000_000 + stamp.nanosec
            p, q = pose_of[conn.msgtype](msg)
            add((ns or received, ns != 0, p.x, p.y, p.z, q.x, q.y, q.z, q.w))
    _need_samples(len(rows), name, topic)
    keep, ns, source, notes = _order([r[0] for r in rows], [r[1] for r in rows])
    _need_samples(len(keep), name, topic)
    table = np.array([r[2:] for r in rows], dtype=np.float64)[keep]
    positions = np.ascontiguousarray(table[:, :3])
    orientations = _unit(table[:, 3:], name, topic)
    times, start = _seconds(ns)
    _finite(positions, name, topic)
    return PoseRecording(
        times,
        positions,
        orientations=orientations,
        start_ns=start,
        topic=topic,
        msgtype=msgtype,
        stamps=source,
        notes=tuple(notes),
    )


def _finite(positions: np.ndarray, name: str, topic: str) -> None:
    bad = ~np.isfinite(positions).all(axis=1)
    if bad.any():
        raise RecordingError(
            f"{name}: topic {topic!r}: sample {int(np.argmax(bad))} has a NaN or infinite position"
        )


def _unit(q: np.ndarray, name: str, topic: str) -> np.ndarray:
    try:
        return continuous(check_quaternions(q, f"{name}: topic {topic!r}: orientation"))
    except ValueError as exc:
        raise RecordingError(str(exc).replace(": row ", ": sample ")) from None


# --------------------------------------------------------------------------- #
# /tf
# --------------------------------------------------------------------------- #


@dataclass
class _Edge:
    """The transforms parent → child recorded for one child frame."""

    parent: str
    static: bool
    ns: list[int] = field(default_factory=list)
    from_header: list[bool] = field(default_factory=list)
    t: list[list[float]] = field(default_factory=list)
    q: list[list[float]] = field(default_factory=list)


def _frame(name: str) -> str:
    return name.lstrip("/")  # ROS 1 tf wrote "/base_link"


def _collect_tf(reader: Any, conns: list[Any], name: str) -> dict[str, _Edge]:
    """Every transform of ``conns`` and of /tf_static, by child frame."""
    static_conns = [c for c in reader.connections if c.topic == _TF_STATIC and _is_tf(c.msgtype)]
    edges: dict[str, _Edge] = {}
    wanted = {id(c) for c in conns} | {id(c) for c in static_conns}
    every = [c for c in reader.connections if id(c) in wanted]
    for conn, received, msg in _messages(reader, every, name):
        static = conn.topic == _TF_STATIC
        for tr in msg.transforms:
            parent, child = _frame(tr.header.frame_id), _frame(tr.child_frame_id)
            edge = edges.get(child)
            if edge is None:
                edge = edges[child] = _Edge(parent, static)
            elif edge.parent != parent:
                raise RecordingError(
                    f"{name}: frame {child!r} has two parents in the transforms recorded "
                    f"({edge.parent!r} and {parent!r})"
                )
            if static:  # the latest static transform of a frame holds
                edge.static = True
                edge.ns, edge.from_header, edge.t, edge.q = [0], [True], [], []
            ns, has = _stamp_ns(tr, received)
            if not static:
                edge.ns.append(ns)
                edge.from_header.append(has)
            edge.t.append(_xyz(tr.transform.translation))
            edge.q.append(_xyzw(tr.transform.rotation))
    return edges


def _frame_pairs(reader: Any, conns: list[Any], name: str) -> str:
    edges = _collect_tf(reader, conns, name)
    pairs = [f"{e.parent}:{child}" for child, e in sorted(edges.items())]
    return ", ".join(pairs[:20]) + (f" and {len(pairs) - 20} more" if len(pairs) > 20 else "")


def _chain(edges: dict[str, _Edge], frame: str) -> list[str]:
    """The frames from ``frame`` up to its root (``frame`` first)."""
    out = [frame]
    while out[-1] in edges:
        out.append(edges[out[-1]].parent)
        if len(out) > len(edges) + 1:
            break  # a cycle: cannot happen with one parent per frame, but never loop
    return out


def _read_tf(
    reader: Any, conns: list[Any], name: str, topic: str, frame: tuple[str, str]
) -> PoseRecording:
    edges = _collect_tf(reader, conns, name)
    chain = _tf_chain(edges, frame, name, topic, moving=True)
    times, start = _seconds(chain.ns)
    _finite(chain.positions, name, topic)
    return PoseRecording(
        times,
        chain.positions,
        orientations=chain.orientations,
        start_ns=start,
        topic=topic,
        msgtype=_normal(conns[0].msgtype),
        frame=chain.frame,
        stamps=chain.stamps,
        notes=tuple(chain.notes),
    )


@dataclass
class _Chain:
    """A frame pair's poses over the transforms recorded: at ``ns`` (one pose if static)."""

    frame: tuple[str, str]
    ns: np.ndarray
    positions: np.ndarray
    orientations: np.ndarray
    stamps: str
    notes: list[str]
    static: bool


def _tf_chain(
    edges: dict[str, _Edge], frame: tuple[str, str], name: str, topic: str, *, moving: bool
) -> _Chain:
    """The child's pose in the parent, chained through ``edges``.

    At the samples of the chain's dynamic transform with the most samples
    (within the span of every other dynamic one, interpolated there); a
    chain of static transforms only is one pose (``ns`` 0), refused where
    ``moving`` (a tool that never moves).
    """
    parent, child = (_frame(f) for f in frame)
    if parent == child:
        raise RecordingError(f"{name}: the frame pair names {parent!r} twice; give PARENT:CHILD")
    notes: list[str] = []
    known = sorted({*edges, *(e.parent for e in edges.values())})
    for f in (parent, child):
        if f not in known:
            raise RecordingError(
                f"{name}: no frame {f!r} in the transforms of {topic!r} and {_TF_STATIC}; "
                f"frames present: {', '.join(known) or 'none'}"
            )
    up_child, up_parent = _chain(edges, child), _chain(edges, parent)
    common = next((f for f in up_child if f in up_parent), None)
    if common is None:
        raise RecordingError(
            f"{name}: frames {parent!r} and {child!r} are not connected by the transforms "
            f"recorded (roots {up_parent[-1]!r} and {up_child[-1]!r})"
        )
    # T_parent_child = inv(T_common_parent) · T_common_child; each edge is T_edge.parent_child
    down_child = up_child[: up_child.index(common)]
    down_parent = up_parent[: up_parent.index(common)]
    used = [edges[f] for f in down_child + down_parent]
    dynamic = [e for e in used if not e.static]
    if not dynamic and moving:
        raise RecordingError(
            f"{name}: the transform {parent}:{child} is static only (one pose); "
            "nothing moves to import"
        )
    if dynamic:
        for e in dynamic:
            _need_samples(len(e.ns), name, topic)
        # Sample times: those of the dynamic transform with the most samples, within the
        # span of every other dynamic transform (interpolated there).
        main = max(dynamic, key=lambda e: len(e.ns))
        keep, ns, source, order_notes = _order(main.ns, main.from_header)
        notes += order_notes
        lo = max(min(e.ns) for e in dynamic)
        hi = min(max(e.ns) for e in dynamic)
        inside = (ns >= lo) & (ns <= hi)
        if not inside.all():
            notes.append(
                f"{int((~inside).sum())} samples of {len(ns)} lie outside the time span of "
                "another transform in the chain; left out"
            )
        keep, ns = keep[inside], ns[inside]
        _need_samples(len(ns), name, topic)
    else:  # one pose, at no time in particular
        main, keep, ns, source = None, np.zeros(1, dtype=np.int64), np.zeros(1, np.int64), "static"

    def poses_along(down: list[str]) -> tuple[np.ndarray, np.ndarray]:
        """T_common_frame for the chain from common down to a frame, at times ns."""
        t = np.zeros((len(ns), 3))
        q = np.tile([0.0, 0.0, 0.0, 1.0], (len(ns), 1))
        for f in reversed(down):  # from common downwards
            et, eq = _edge_at(edges[f], ns, main, keep, name, topic)
            t = t + np.einsum("nij,nj->ni", matrix_from_quaternion(q), et)
            q = multiply(q, eq)
        return t, q

    t_c, q_c = poses_along(down_child)
    t_p, q_p = poses_along(down_parent)
    q_pinv = conjugate(q_p)
    positions = np.einsum("nij,nj->ni", matrix_from_quaternion(q_pinv), t_c - t_p)
    orientations = continuous(multiply(q_pinv, q_c))
    return _Chain((parent, child), ns, positions, orientations, source, notes, not dynamic)


def read_frame_poses(
    path: PathLike, frame: tuple[str, str], at_ns: Any, *, topic: str = "/tf"
) -> tuple[np.ndarray, np.ndarray]:
    """A task frame's pose (an object's, from ``/tf`` and ``/tf_static``) at given times.

    Parameters
    ----------
    path : str or os.PathLike
        The recording.
    frame : (str, str)
        ``(parent, child)``: the child's pose in the parent (the frame the
        tool's poses are in), chained through the frame tree as
        :func:`read_poses` does.
    at_ns : array_like of int, shape (k,)
        Absolute times (ns since the epoch, as ``PoseRecording.start_ns``
        plus seconds × 1e9), e.g. where each demonstration starts.
    topic : str
        The tf topic (default ``"/tf"``; a recording with ``/tf_static``
        alone holds static frames).

    Returns
    -------
    positions : ndarray, shape (k, 3)
    orientations : ndarray, shape (k, 4)
        Unit quaternions ``[x, y, z, w]``. A static chain's one pose at every
        time; a moving one's interpolated between its samples (slerp).

    Raises
    ------
    RecordingError
        As :func:`read_poses` for /tf, and for a time outside the span of the
        chain's transforms (naming it and the span).
    """
    name = os.fspath(path)
    at = np.asarray(at_ns, dtype=np.int64).reshape(-1)
    with _open(path) as reader:
        present = {c.topic for c in reader.connections}
        if topic in present:
            conns = _connections(
                reader, path, topic, ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage")
            )
        elif _TF_STATIC in present:
            conns = []  # static frames only
        else:
            raise RecordingError(
                f"{name}: no {topic!r} or {_TF_STATIC} topic: the task frame "
                f"{frame[0]}:{frame[1]} needs the transforms recorded"
            )
        chain = _tf_chain(_collect_tf(reader, conns, name), frame, name, topic, moving=False)
    if chain.static:
        return np.repeat(chain.positions, len(at), axis=0), np.repeat(
            chain.orientations, len(at), 0
        )
    outside = (at < chain.ns[0]) | (at > chain.ns[-1])
    if outside.any():
        k = int(np.argmax(outside))
        span = (chain.ns[-1] - chain.ns[0]) / 1e9
        raise RecordingError(
            f"{name}: the task frame {chain.frame[0]}:{chain.frame[1]} has no transform at "
            f"{(at[k] - chain.ns[0]) / 1e9:+.3f} s from its first ({span:.3f} s recorded); "
            "record the object's transform for the whole demonstration"
        )
    return _interpolated(chain.ns, chain.positions, chain.orientations, at)


def _edge_at(
    edge: _Edge, ns: np.ndarray, main: _Edge | None, keep: np.ndarray, name: str, topic: str
) -> tuple[np.ndarray, np.ndarray]:
    """The edge's translation (n, 3) and rotation (n, 4) at times ``ns``."""
    t = np.asarray(edge.t, dtype=np.float64)
    q = _unit(np.asarray(edge.q, dtype=np.float64), name, topic)
    if edge.static:
        return np.repeat(t[-1:], len(ns), axis=0), np.repeat(q[-1:], len(ns), axis=0)
    if edge is main:
        return t[keep], q[keep]
    k, e_ns, _, _ = _order(edge.ns, edge.from_header)
    t, q = t[k], continuous(q[k])
    return _interpolated(e_ns, t, q, ns)


def _interpolated(
    stamps: np.ndarray, positions: np.ndarray, turns: np.ndarray, at: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Positions (linear) and rotations (slerp) at times ``at`` (ns) between samples at ``stamps``.

    Held at the first and last sample outside their span; one sample is held everywhere.
    """
    j = np.clip(np.searchsorted(stamps, at, side="right") - 1, 0, max(len(stamps) - 2, 0))
    if len(stamps) == 1:
        return positions[j], turns[j]
    # differences in integer nanoseconds: as floats, epoch times carry 256 ns of rounding
    u = np.clip((at - stamps[j]) / (stamps[j + 1] - stamps[j]), 0.0, 1.0)
    return positions[j] + u[:, None] * (positions[j + 1] - positions[j]), slerp(
        turns[j], turns[j + 1], u
    )


# --------------------------------------------------------------------------- #
# Joint states
# --------------------------------------------------------------------------- #


def joint_names(path: PathLike, topic: str) -> tuple[str, ...]:
    """Every joint named on a ``sensor_msgs/JointState`` topic, in order of first appearance.

    Several publishers may share the topic (an arm and its gripper); this is
    the union of their joints.
    """
    name = os.fspath(path)
    names: dict[str, None] = {}
    with _open(path) as reader:
        conns = _connections(reader, path, topic, (JOINT_STATE,))
        for _, _, msg in _messages(reader, conns, name):
            names.update(dict.fromkeys(str(n) for n in msg.name))
    return tuple(names)


def read_joint_states(
    path: PathLike, topic: str, *, joints: tuple[str, ...] | None = None
) -> JointRecording:
    """Read the joint positions of a ``sensor_msgs/JointState`` topic.

    Parameters
    ----------
    path : str or os.PathLike
        The recording.
    topic : str
        E.g. ``"/joint_states"``.
    joints : tuple of str, optional
        The joints to read, in this column order (other joints of the
        messages, a gripper's, are left out). By default the names of the
        first message. Messages that name no joints are read by position;
        messages without all of ``joints`` (another publisher's on the same
        topic) are left out, with a note.

    Raises
    ------
    RecordingError
        As :func:`read_poses`, and if no message has all of ``joints``.
    """
    name = os.fspath(path)
    with _open(path) as reader:
        conns = _connections(reader, path, topic, (JOINT_STATE,))
        stamps, headers, rows = [], [], []
        others: list[int] = []
        other_names: tuple[str, ...] = ()
        wanted = None if joints is None else tuple(joints)
        for k, (_, received, msg) in enumerate(_messages(reader, conns, name)):
            names = tuple(str(n) for n in msg.name)
            values = np.asarray(msg.position, dtype=np.float64)
            if wanted is None:
                wanted = names or tuple(f"joint_{i + 1}" for i in range(len(values)))
            if names:
                index = {n: i for i, n in enumerate(names)}
                missing = [j for j in wanted if j not in index]
                if missing:  # another publisher's joints on the same topic (a gripper's)
                    others.append(k)
                    if len(others) == 1:
                        other_names = names
                    continue
                if len(values) != len(names):
                    raise RecordingError(
                        f"{name}: topic {topic!r} message {k} names {len(names)} joints but "
                        f"has {len(values)} positions"
                    )
                values = values[[index[j] for j in wanted]]
            elif len(values) != len(wanted):
                raise RecordingError(
                    f"{name}: topic {topic!r} message {k} has {len(values)} positions and "
                    f"no names; expected {len(wanted)}"
                )
            ns, has = _stamp_ns(msg, received)
            stamps.append(ns)
            headers.append(has)
            rows.append(values)
    if others and not stamps:
        raise RecordingError(
            f"{name}: topic {topic!r}: no message has the joints {', '.join(wanted or ())}; "
            f"message {others[0]} has {', '.join(other_names)}"
        )
    _need_samples(len(stamps), name, topic)
    keep, ns, source, notes = _order(stamps, headers)
    if others:
        notes.insert(
            0,
            f"{len(others)} messages without the joints read (another publisher's, e.g. "
            f"{', '.join(other_names)}) left out",
        )
    positions = np.asarray(rows, dtype=np.float64)[keep]
    _finite(positions, name, topic)
    times, start = _seconds(ns)
    return JointRecording(
        times,
        positions,
        names=tuple(wanted or ()),
        start_ns=start,
        topic=topic,
        stamps=source,
        notes=tuple(notes),
    )
