"""Recordings written by rosbags' own writers read back exactly (ROS 1, ROS 2 sqlite3 and MCAP)."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from lfdkit.core import rotations as rot
from lfdkit.io.recordings import (
    RecordingError,
    list_topics,
    read_frame_poses,
    read_joint_states,
    read_poses,
)
from lfdkit.model.timed_path import TimedPath
from tests.io.bags import KINDS, Sample, random_trajectory, write_recording

pr = pytest.importorskip("pytransform3d.rotations", reason="pip install pytransform3d")
pt = pytest.importorskip("pytransform3d.transformations", reason="pip install pytransform3d")

SRC = Path(__file__).resolve().parents[2] / "src"


def _samples(ns, pos, q, *, received_offset=1000, **kw):
    return [
        Sample(int(n) + received_offset, int(n), p, o, **kw)
        for n, p, o in zip(ns, pos, q, strict=True)
    ]


def _tf_messages(ns, pos, q, parent: str, child: str) -> list[Sample]:
    """One TFMessage per sample, holding the parent -> child transform."""
    return [
        Sample(
            s.received,
            s.stamp,
            transforms=[Sample(s.received, s.stamp, s.position, s.orientation, parent, child)],
        )
        for s in _samples(ns, pos, q)
    ]


def _same_rotation(a: np.ndarray, b: np.ndarray) -> float:
    """Largest quaternion difference up to sign, row by row."""
    return float(np.minimum(np.abs(a - b).max(1), np.abs(a + b).max(1)).max())


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize(
    "msgtype",
    [
        "geometry_msgs/msg/PoseStamped",
        "nav_msgs/msg/Odometry",
        "geometry_msgs/msg/TransformStamped",
    ],
)
def test_poses_read_back_exactly(tmp_path: Path, kind: str, msgtype: str) -> None:
    ns, pos, q = random_trajectory(40, seed=1)
    out = write_recording(tmp_path / "rec", kind, {"/pose": (msgtype, _samples(ns, pos, q))})
    rec = read_poses(out, "/pose")
    assert rec.msgtype == msgtype
    assert isinstance(rec, TimedPath) and rec.velocities is None  # the one timed-path record
    np.testing.assert_allclose(rec.positions, pos, rtol=0, atol=1e-9)
    assert _same_rotation(rec.orientations, q) < 1e-9
    assert rec.start_ns == ns[0]
    np.testing.assert_allclose(rec.times, (ns - ns[0]) * 1e-9, rtol=0, atol=1e-9)
    assert rec.stamps == "header"
    assert rec.notes == ()
    # signs made continuous: consecutive quaternions on one hemisphere
    assert np.all(np.einsum("ij,ij->i", rec.orientations[1:], rec.orientations[:-1]) > 0)


def test_a_plain_mcap_file_reads_like_its_bag_folder(tmp_path: Path) -> None:
    ns, pos, q = random_trajectory(10, seed=2)
    topics = {"/pose": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q))}
    folder = write_recording(tmp_path / "rec", "mcap", topics)
    (mcap,) = folder.glob("*.mcap")
    lone = tmp_path / "lone.mcap"
    lone.write_bytes(mcap.read_bytes())  # no metadata.yaml beside it
    a, b = read_poses(folder, "/pose"), read_poses(lone, "/pose")
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.times, b.times)
    assert [t.name for t in list_topics(lone)] == ["/pose"]


def test_receive_time_is_taken_where_the_header_stamp_is_zero(tmp_path: Path) -> None:
    ns, pos, q = random_trajectory(6, seed=3)
    samples = _samples(ns, pos, q)
    for s in samples[:2]:
        s.stamp = 0  # a publisher that never set the stamp
    out = write_recording(tmp_path / "rec", "sqlite3", {"/p": ("nav_msgs/msg/Odometry", samples)})
    rec = read_poses(out, "/p")
    assert rec.stamps == "mixed"
    assert any("no header stamp" in n for n in rec.notes)
    expected = np.r_[ns[:2] + 1000, ns[2:]]
    np.testing.assert_allclose(rec.times, (expected - expected[0]) * 1e-9, atol=1e-9)
    for s in samples:
        s.stamp = 0
    out = write_recording(tmp_path / "rec2", "mcap", {"/p": ("nav_msgs/msg/Odometry", samples)})
    assert read_poses(out, "/p").stamps == "receive"


def test_out_of_order_and_repeated_stamps_are_sorted_and_reported(tmp_path: Path) -> None:
    ns, pos, q = random_trajectory(6, seed=4)
    samples = _samples(ns, pos, q)
    samples[3].stamp = samples[2].stamp  # a repeat: the later message is kept
    samples[4].stamp, samples[5].stamp = samples[5].stamp, samples[4].stamp
    out = write_recording(
        tmp_path / "r", "ros1", {"/p": ("geometry_msgs/msg/PoseStamped", samples)}
    )
    rec = read_poses(out, "/p")
    assert len(rec.times) == 5
    assert np.all(np.diff(rec.times) > 0)
    np.testing.assert_array_equal(rec.positions, pos[[0, 1, 3, 5, 4]])
    assert any("repeated" in n for n in rec.notes)


def _rot(axis, angle):
    return np.r_[np.sin(angle / 2) * np.asarray(axis) / np.linalg.norm(axis), np.cos(angle / 2)]


@pytest.mark.parametrize("kind", KINDS)
def test_tf_chains_static_and_dynamic_transforms(tmp_path: Path, kind: str) -> None:
    """world -static-> base -dynamic-> tool -static-> tip; world:tip against pytransform3d."""
    ns, pos, q = random_trajectory(25, seed=5)
    static = [
        Sample(5, 5, (1.0, 2.0, 0.5), _rot([0, 0, 1], 0.7), "world", "base"),
        Sample(5, 5, (0.0, 0.0, 0.12), _rot([1, 1, 0], 0.3), "tool", "tip"),
    ]
    other = Sample(6, 6, (9.0, 9.0, 9.0), _rot([0, 1, 0], 1.0), "world", "camera")
    dynamic = _tf_messages(ns, pos, q, "base", "tool")
    out = write_recording(
        tmp_path / "tf",
        kind,
        {
            "/tf": ("tf2_msgs/msg/TFMessage", dynamic),
            "/tf_static": ("tf2_msgs/msg/TFMessage", [Sample(5, 5, transforms=[*static, other])]),
        },
    )

    def T(p, qxyzw):
        return pt.transform_from_pq(np.r_[p, qxyzw[3], qxyzw[:3]])

    T_wb = T(static[0].position, static[0].orientation)
    T_tt = T(static[1].position, static[1].orientation)
    T_wc = T(other.position, other.orientation)
    want = np.array([T_wb @ T(p, o) @ T_tt for p, o in zip(pos, q, strict=True)])
    rec = read_poses(out, "/tf", frame=("world", "tip"))
    assert rec.frame == ("world", "tip")
    np.testing.assert_allclose(rec.positions, want[:, :3, 3], atol=1e-9)
    got = np.array([pr.matrix_from_quaternion(np.r_[o[3], o[:3]]) for o in rec.orientations])
    np.testing.assert_allclose(got, want[:, :3, :3], atol=1e-9)
    np.testing.assert_allclose(rec.times, (ns - ns[0]) * 1e-9, atol=1e-9)
    # the other way round, and through a sibling branch (camera -> tip)
    back = read_poses(out, "/tf", frame=("tip", "world"))
    inv = np.array([np.linalg.inv(w) for w in want])
    np.testing.assert_allclose(back.positions, inv[:, :3, 3], atol=1e-9)
    side = read_poses(out, "/tf", frame=("camera", "tip"))
    np.testing.assert_allclose(
        side.positions, np.array([np.linalg.inv(T_wc) @ w for w in want])[:, :3, 3], atol=1e-9
    )


def test_ros1_tf_messages_of_the_older_tf_package(tmp_path: Path) -> None:
    ns, pos, q = random_trajectory(10, seed=20)
    dynamic = [
        Sample(
            s.received,
            s.stamp,
            transforms=[
                Sample(s.received, s.stamp, s.position, s.orientation, "/odom", "/base_link")
            ],
        )
        for s in _samples(ns, pos, q)
    ]
    out = write_recording(tmp_path / "tf", "ros1", {"/tf": ("tf/msg/tfMessage", dynamic)})
    rec = read_poses(out, "/tf", frame=("odom", "/base_link"))  # ROS 1's leading slashes
    assert rec.msgtype == "tf/msg/tfMessage" and rec.frame == ("odom", "base_link")
    np.testing.assert_allclose(rec.positions, pos, atol=1e-12)


def test_tf_errors_name_the_frames(tmp_path: Path) -> None:
    ns, pos, q = random_trajectory(5, seed=6)
    dynamic = _tf_messages(ns, pos, q, "base", "tool")
    out = write_recording(tmp_path / "tf", "mcap", {"/tf": ("tf2_msgs/msg/TFMessage", dynamic)})
    with pytest.raises(RecordingError, match=r"name the pair.*recorded: base:tool"):
        read_poses(out, "/tf")
    with pytest.raises(RecordingError, match=r"no frame 'map'.*frames present: base, tool"):
        read_poses(out, "/tf", frame=("map", "tool"))
    with pytest.raises(RecordingError, match="names 'tool' twice"):
        read_poses(out, "/tf", frame=("/tool", "tool"))
    with pytest.raises(RecordingError, match="applies to tf2_msgs/TFMessage"):
        write = write_recording(
            tmp_path / "p",
            "mcap",
            {"/p": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q))},
        )
        read_poses(write, "/p", frame=("a", "b"))


UR = (
    "shoulder_pan_joint",
    "shoulder_lift_joint",
    "elbow_joint",
    "wrist_1_joint",
    "wrist_2_joint",
    "wrist_3_joint",
)


@pytest.mark.parametrize("kind", KINDS)
def test_joint_states_become_ur5_tool_poses(tmp_path: Path, kind: str) -> None:
    from lfdkit.execute.recordings import tool_poses_from_joint_states
    from lfdkit.execute.ur5 import forward

    rng = np.random.default_rng(7)
    ns, _, _ = random_trajectory(15, seed=7)
    qs = rng.uniform(-2, 2, (15, 6))
    samples = []
    for n, row in zip(ns, qs, strict=True):
        joints = {"gripper_joint": 0.01}  # an extra joint, first: names decide, not order
        joints |= {f"ur5_{name}": float(v) for name, v in zip(UR[::-1], row[::-1], strict=True)}
        samples.append(Sample(int(n) + 7, int(n), joints=joints))
    out = write_recording(
        tmp_path / "js", kind, {"/joint_states": ("sensor_msgs/msg/JointState", samples)}
    )
    raw = read_joint_states(out, "/joint_states")
    assert raw.names[0] == "gripper_joint"
    assert isinstance(raw, TimedPath) and raw.velocities is None  # one timed-path record
    assert raw.positions.shape == (len(ns), 7) and not raw.positions.flags.writeable
    rec = tool_poses_from_joint_states(out, "/joint_states")
    T = forward(qs)
    np.testing.assert_allclose(rec.positions, T[:, :3, 3], atol=1e-12)
    want = np.array([pr.quaternion_from_matrix(R) for R in T[:, :3, :3]])  # w, x, y, z
    assert _same_rotation(rec.orientations, want[:, [1, 2, 3, 0]]) < 1e-9
    np.testing.assert_allclose(rec.times, (ns - ns[0]) * 1e-9, atol=1e-9)


def test_joint_states_without_the_arms_joints_are_refused(tmp_path: Path) -> None:
    from lfdkit.execute.recordings import tool_poses_from_joint_states

    samples = [Sample(k + 1, k + 1, joints={"a": 0.0, "b": 1.0}) for k in range(3)]
    out = write_recording(tmp_path / "js", "mcap", {"/js": ("sensor_msgs/msg/JointState", samples)})
    with pytest.raises(RecordingError, match=r"cannot find the UR5 joint 'shoulder_pan_joint'"):
        tool_poses_from_joint_states(out, "/js")


# --------------------------------------------------------------------------- #
# Bad input: one line each
# --------------------------------------------------------------------------- #


def _one_line(exc: pytest.ExceptionInfo) -> str:
    text = str(exc.value)
    assert "\n" not in text
    return text


@pytest.mark.parametrize("kind", KINDS)
def test_a_missing_topic_lists_the_topics_present(tmp_path: Path, kind: str) -> None:
    ns, pos, q = random_trajectory(4, seed=8)
    out = write_recording(
        tmp_path / "r",
        kind,
        {
            "/tool_pose": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q)),
            "/odom": ("nav_msgs/msg/Odometry", _samples(ns, pos, q)),
        },
    )
    with pytest.raises(RecordingError) as exc:
        read_poses(out, "/tool_poses")
    assert _one_line(exc) == (
        f"{out}: no topic '/tool_poses'; topics present: /odom (nav_msgs/msg/Odometry, "
        "4 messages); /tool_pose (geometry_msgs/msg/PoseStamped, 4 messages)"
    )


def test_a_wrong_message_type_is_named(tmp_path: Path) -> None:
    out = write_recording(
        tmp_path / "r", "sqlite3", {"/chatter": ("std_msgs/msg/String", [Sample(1, 1)] * 3)}
    )
    with pytest.raises(
        RecordingError,
        match=r"'/chatter' holds std_msgs/msg/String; lfdkit "
        r"reads PoseStamped, .*TFMessage here",
    ) as exc:
        read_poses(out, "/chatter")
    _one_line(exc)
    with pytest.raises(RecordingError, match="reads JointState here"):
        read_joint_states(out, "/chatter")


@pytest.mark.parametrize("kind", KINDS)
def test_an_empty_recording_or_topic_is_refused(tmp_path: Path, kind: str) -> None:
    empty = write_recording(tmp_path / "empty", kind, {})
    with pytest.raises(RecordingError, match=r"topics present: none \(the recording is empty\)"):
        read_poses(empty, "/tool_pose")
    silent = write_recording(
        tmp_path / "silent", kind, {"/tool_pose": ("geometry_msgs/msg/PoseStamped", [])}
    )
    with pytest.raises(RecordingError, match="'/tool_pose' has no messages"):
        read_poses(silent, "/tool_pose")
    ns, pos, q = random_trajectory(1, seed=9)
    one = write_recording(
        tmp_path / "one", kind, {"/p": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q))}
    )
    with pytest.raises(RecordingError, match="has 1 sample; a demonstration needs at least 2"):
        read_poses(one, "/p")


@pytest.mark.parametrize("kind", KINDS)
def test_a_truncated_recording_is_one_line(tmp_path: Path, kind: str) -> None:
    ns, pos, q = random_trajectory(200, seed=10)
    out = write_recording(
        tmp_path / "r", kind, {"/p": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q))}
    )
    files = [out] if out.is_file() else [p for p in out.iterdir() if p.suffix in (".db3", ".mcap")]
    for f in files:
        data = f.read_bytes()
        f.write_bytes(data[: len(data) // 2])
    target = files[0] if kind == "mcap" else out
    for path in {out, target}:
        with pytest.raises(RecordingError, match="cannot read the recording") as exc:
            read_poses(path, "/p")
        _one_line(exc)


def test_not_a_recording(tmp_path: Path) -> None:
    empty = tmp_path / "e.bag"
    empty.write_bytes(b"")
    with pytest.raises(RecordingError, match=r"e.bag: is empty \(0 bytes\)"):
        list_topics(empty)
    text = tmp_path / "notes.txt"
    text.write_text("hello")
    with pytest.raises(RecordingError, match=r"unknown recording type '\.txt'"):
        list_topics(text)
    with pytest.raises(RecordingError, match=r"without metadata\.yaml"):
        list_topics(tmp_path)
    with pytest.raises(FileNotFoundError):
        list_topics(tmp_path / "nothing.bag")
    garbage = tmp_path / "g.mcap"
    garbage.write_bytes(b"\x89MCAP0\r\n" + os.urandom(64))
    with pytest.raises(RecordingError, match="cannot read the recording"):
        list_topics(garbage)


# --------------------------------------------------------------------------- #
# The command
# --------------------------------------------------------------------------- #


def _lfdkit(*argv: str, cwd: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    return subprocess.run(
        [sys.executable, "-m", "lfdkit.app.cli", *argv],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=120,
    )


def _with_pauses(seed: int) -> tuple[np.ndarray, np.ndarray, list[tuple[float, float]]]:
    """Three strokes at 50 Hz with rest before, between (1 s, 0.8 s) and after."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, 9.0, 0.02)
    x = np.zeros_like(t)
    strokes = [(0.5, 2.5), (3.5, 5.5), (6.3, 8.3)]
    for a, b in strokes:
        x += (
            0.1 * np.clip((t - a) / (b - a), 0, 1) ** 2 * (3 - 2 * np.clip((t - a) / (b - a), 0, 1))
        )
    pos = np.c_[x, 0.05 * np.sin(8 * x), 0.2 + 0 * x] + rng.normal(0, 2e-5, (len(t), 3))
    return t, pos, strokes


def test_import_splits_a_recording_at_its_pauses(tmp_path: Path) -> None:
    t, pos, strokes = _with_pauses(11)
    ns = (1_700_000_000 * 10**9 + np.round(t * 1e9)).astype(np.int64)
    q = np.tile(_rot([0, 0, 1], 0.2), (len(t), 1))
    out = write_recording(
        tmp_path / "rec",
        "mcap",
        {"/tool_pose": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q))},
    )
    done = _lfdkit(
        "import", str(out), "--topic", "/tool_pose", "--split", "-o", "d.csv", "-v", cwd=tmp_path
    )
    assert done.returncode == 0, done.stderr
    assert "split at a pause of" in done.stderr
    assert "imported 3 demonstrations" in done.stderr
    assert "moves back" not in done.stderr
    from lfdkit.io import load_demos

    demos, times, quats = load_demos(
        tmp_path / "d.csv", return_times=True, return_orientations=True
    )
    assert len(demos) == 3
    for d, tt, qq, (a, b) in zip(demos, times, quats, strokes, strict=True):
        assert d.shape[1] == 3
        assert a - 0.05 < tt[0] < a + 0.15 and b - 0.15 < tt[-1] < b + 0.05  # rest trimmed
        np.testing.assert_allclose(qq, q[: len(qq)], atol=1e-12)
    # a second write needs --force; without --topic the topics are listed (exit 0, no -o)
    again = _lfdkit("import", str(out), "--topic", "/tool_pose", "-o", "d.csv", cwd=tmp_path)
    assert again.returncode == 1 and "pass --force" in again.stderr
    for listing in (["import", str(out)], ["import", str(out), "--list-topics", "-o", "e.csv"]):
        bare = _lfdkit(*listing, cwd=tmp_path)
        assert bare.returncode == 0, bare.stderr
        assert bare.stdout.splitlines() == [
            f"{out}:",
            "  /tool_pose (geometry_msgs/msg/PoseStamped, 450 messages)",
        ]
    no_output = _lfdkit("import", str(out), "--topic", "/tool_pose", cwd=tmp_path)
    assert no_output.returncode == 2 and "-o/--output: name the demonstrations" in no_output.stderr
    wrong = _lfdkit("import", str(out), "--topic", "/pose", "-o", "e.csv", cwd=tmp_path)
    assert wrong.returncode == 1 and len(wrong.stderr.strip().splitlines()) == 1
    assert "no topic '/pose'; topics present: /tool_pose" in wrong.stderr
    assert not (tmp_path / "e.csv").exists()


@pytest.mark.parametrize("kind", KINDS)
def test_a_static_task_frame_reads_alike_in_every_recording_kind(tmp_path: Path, kind: str) -> None:
    # /tf_static alone (no /tf topic): the chain world -> table -> pan, one pose at any time.
    table = Sample(1, 1, (0.5, 0.0, 0.0), _rot([0, 0, 1], 0.5), "world", "table")
    pan = Sample(1, 1, (0.2, 0.1, 0.0), _rot([0, 0, 1], 0.25), "table", "pan")
    ns, pos, q = random_trajectory(5, seed=2)
    out = write_recording(
        tmp_path / "rec",
        kind,
        {
            "/tool_pose": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q)),
            "/tf_static": ("tf2_msgs/msg/TFMessage", [Sample(1, 1, transforms=[table, pan])]),
        },
    )
    positions, turns = read_frame_poses(out, ("world", "pan"), ns[[0, -1]])
    want = np.array([0.5, 0.0, 0.0]) + 0.2 * np.array([np.cos(0.5), np.sin(0.5), 0.0])
    want += 0.1 * np.array([-np.sin(0.5), np.cos(0.5), 0.0])
    np.testing.assert_allclose(positions, np.tile(want, (2, 1)), atol=1e-12)
    np.testing.assert_allclose(turns, np.tile(_rot([0, 0, 1], 0.75), (2, 1)), atol=1e-12)
    with pytest.raises(RecordingError, match=r"no frame 'lid' in the transforms"):
        read_frame_poses(out, ("world", "lid"), ns[:1])


def test_a_task_frame_is_posed_where_each_demonstration_starts(tmp_path: Path) -> None:
    # Three strokes split at their pauses; a dustpan standing still (/tf_static, under a
    # table frame) and a lid moved by hand between strokes (/tf): each demonstration gets
    # both frames' poses at its first sample, planar ones as x, y and the turn about z.
    t, pos, strokes = _with_pauses(12)
    ns = (1_700_000_000 * 10**9 + np.round(t * 1e9)).astype(np.int64)
    q = np.tile(_rot([0, 0, 1], 0.2), (len(t), 1))
    table = Sample(1, 1, (0.5, 0.0, 0.0), _rot([0, 0, 1], 0.5), "world", "table")
    pan = Sample(1, 1, (0.2, 0.1, 0.0), _rot([0, 0, 1], 0.25), "table", "pan")
    upright = Sample(1, 1, (0.1, 0.0, 0.0), _rot([0, 1, 0], -np.pi / 2), "world", "upright")
    lid_x = np.interp(t, [0.0, 3.0, 3.2, 9.0], [0.3, 0.3, 0.6, 0.6])  # moved in the 1st pause
    lid = _tf_messages(ns, np.c_[lid_x, 0 * t, 0 * t], q, "world", "lid")
    out = write_recording(
        tmp_path / "rec",
        "mcap",
        {
            "/tool_pose": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q)),
            "/tf": ("tf2_msgs/msg/TFMessage", lid),
            "/tf_static": (
                "tf2_msgs/msg/TFMessage",
                [Sample(1, 1, transforms=[table, pan, upright])],
            ),
        },
    )
    starts = ns[[int(np.searchsorted(t, a)) for a, _ in strokes]]
    positions, turns = read_frame_poses(out, ("world", "pan"), starts)
    want = np.array([0.5, 0.0]) + 0.2 * np.array([np.cos(0.5), np.sin(0.5)])
    want += 0.1 * np.array([-np.sin(0.5), np.cos(0.5)])
    np.testing.assert_allclose(positions[:, :2], np.tile(want, (3, 1)), atol=1e-12)
    np.testing.assert_allclose(turns, np.tile(_rot([0, 0, 1], 0.75), (3, 1)), atol=1e-12)
    lid_at, _ = read_frame_poses(out, ("world", "lid"), [ns[0], ns[len(ns) // 2]])
    np.testing.assert_allclose(lid_at[:, 0], [0.3, 0.6], atol=1e-12)
    with pytest.raises(RecordingError, match=r"task frame world:lid has no transform at -1\.000 s"):
        read_frame_poses(out, ("world", "lid"), [ns[0] - 10**9])
    done = _lfdkit(
        "import", str(out), "--topic", "/tool_pose", "--split", "--planar",
        "--task-frame", "world:pan", "--task-frame", "world:lid=moved_lid",
        "-o", "d.csv", cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    from lfdkit.io import load_demos

    records = load_demos(tmp_path / "d.csv", as_records=True)
    assert len(records) == 3 and [list(r.frames) for r in records] == [["pan", "moved_lid"]] * 3
    for record in records:
        np.testing.assert_allclose(record.frames["pan"], [*want, 0.75], atol=1e-12)
    assert [round(float(r.frames["moved_lid"][0]), 9) for r in records] == [0.3, 0.6, 0.6]
    done = _lfdkit(
        "import", str(out), "--topic", "/tool_pose", "--split", "--task-frame", "world:pan",
        "-o", "d3.csv", cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    for record in load_demos(tmp_path / "d3.csv", as_records=True):  # 3-D: x, y, z and quaternion
        np.testing.assert_allclose(record.frames["pan"][:2], want, atol=1e-12)
        np.testing.assert_allclose(record.frames["pan"][3:], _rot([0, 0, 1], 0.75), atol=1e-12)
    bad = _lfdkit(
        "import", str(out), "--topic", "/tool_pose", "--task-frame", "world:a/b", "-o", "e.csv",
        cwd=tmp_path,
    )  # fmt: skip
    assert bad.returncode == 2 and "rename it with world:a/b=NAME" in bad.stderr
    # A frame whose x axis points up has no turn about z: refused for --planar, 3-D kept.
    bad = _lfdkit(
        "import", str(out), "--topic", "/tool_pose", "--split", "--planar",
        "--task-frame", "world:upright", "-o", "e.csv", cwd=tmp_path,
    )  # fmt: skip
    assert bad.returncode == 2 and not (tmp_path / "e.csv").exists()
    assert (
        "--task-frame world:upright: where demonstration 1 of rec starts, its x axis "
        "points straight up or down" in bad.stderr
    ), bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1
    done = _lfdkit(
        "import", str(out), "--topic", "/tool_pose", "--split", "--task-frame", "world:upright",
        "-o", "e.csv", cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr


def test_import_then_learn(tmp_path: Path) -> None:
    """Several recordings, one demonstration each, planar: lfdkit learn reads the file."""
    paths = []
    for k in range(3):
        t, pos, _ = _with_pauses(20 + k)
        keep = (t > 3.3) & (t < 5.8)  # the middle stroke, with rest at both ends
        ns = (1_700_000_000 * 10**9 + np.round(t[keep] * 1e9)).astype(np.int64)
        p = pos[keep] + [0.0, 0.002 * k, 0.0]
        q = np.tile([0.0, 0.0, 0.0, 1.0], (len(p), 1))
        paths.append(
            str(
                write_recording(
                    tmp_path / f"r{k}",
                    "ros1",
                    {"/pose": ("geometry_msgs/msg/PoseStamped", _samples(ns, p, q))},
                )
            )
        )
    done = _lfdkit("import", *paths, "--topic", "/pose", "--planar", "-o", "d.csv", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "imported 3 demonstrations" in done.stderr
    header = (tmp_path / "d.csv").read_text().splitlines()[0]
    assert header == "demo,t,x,y,qx,qy,qz,qw"
    learn = _lfdkit("learn", "d.csv", "-o", "skill.json", "-q", cwd=tmp_path)
    assert learn.returncode == 0, learn.stderr
    assert (tmp_path / "skill.json").exists()


def test_a_humble_sqlite3_bag_without_message_definitions(tmp_path: Path) -> None:
    """rosbag2 before Iron stores no definitions: the standard ROS 2 types are used."""
    import sqlite3

    ns, pos, q = random_trajectory(8, seed=12)
    out = write_recording(
        tmp_path / "r", "sqlite3", {"/p": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q))}
    )
    (db,) = out.glob("*.db3")
    with sqlite3.connect(db) as con:
        con.execute("DELETE FROM message_definitions")
    np.testing.assert_allclose(read_poses(out, "/p").positions, pos, atol=1e-9)


def test_without_rosbags_the_error_says_how_to_install(tmp_path: Path, monkeypatch) -> None:
    ns, pos, q = random_trajectory(3, seed=13)
    out = write_recording(
        tmp_path / "r", "ros1", {"/p": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q))}
    )
    monkeypatch.setitem(sys.modules, "rosbags.highlevel", None)  # import fails
    with pytest.raises(RecordingError, match=r'^reading ROS bags .* pip install "lfdkit\[ros\]"$'):
        list_topics(out)


def test_two_moving_links_are_interpolated_exactly_where_the_motion_is_linear(
    tmp_path: Path,
) -> None:
    """world->base at 10 Hz (straight line, constant turn about z), base->tool at 100 Hz.

    Linear interpolation of a straight-line translation and slerp of a
    constant-rate turn about a fixed axis are exact, so the chain is known in
    closed form at the tool's stamps; the tool's samples outside the base's
    span are left out, with a note.
    """
    t0 = 1_700_000_000 * 10**9

    def base_at(ns):
        s = (ns - t0) * 1e-9
        return np.c_[0.1 * s, -0.2 * s, 0 * s], rot.exp(np.c_[0 * s, 0 * s, 0.15 * s])

    base_ns = t0 + np.arange(0, 21) * 100_000_000  # 0 .. 2 s
    tool_ns = t0 - 50_000_000 + np.arange(0, 220) * 10_000_000  # -0.05 .. 2.14 s
    bp, bq = base_at(base_ns)
    rng = np.random.default_rng(14)
    tp = rng.normal(0, 0.1, (len(tool_ns), 3))
    tq = rot.exp(rng.normal(0, 0.3, (len(tool_ns), 3)))

    def tf(ns, p, q, parent, child):
        return [
            Sample(int(n), int(n), transforms=[Sample(int(n), int(n), pp, qq, parent, child)])
            for n, pp, qq in zip(ns, p, q, strict=True)
        ]

    out = write_recording(
        tmp_path / "two",
        "mcap",
        {
            "/tf": (
                "tf2_msgs/msg/TFMessage",
                tf(base_ns, bp, bq, "world", "base") + tf(tool_ns, tp, tq, "base", "tool"),
            )
        },
    )
    rec = read_poses(out, "/tf", frame=("world", "tool"))
    inside = (tool_ns >= base_ns[0]) & (tool_ns <= base_ns[-1])
    assert len(rec.times) == inside.sum() == 201
    assert any("outside the time span" in n for n in rec.notes)
    wp, wq = base_at(tool_ns[inside])
    want_p = wp + np.einsum("nij,nj->ni", rot.matrix_from_quaternion(wq), tp[inside])
    np.testing.assert_allclose(rec.positions, want_p, atol=1e-12)
    assert rot.angle_between(rec.orientations, rot.multiply(wq, tq[inside])).max() < 1e-12
    np.testing.assert_allclose(rec.times, (tool_ns[inside] - t0) * 1e-9, atol=1e-9)


def test_import_joint_states_on_the_command_line(tmp_path: Path) -> None:
    from lfdkit.execute.ur5 import forward

    ns, _, _ = random_trajectory(30, seed=15)
    u = np.linspace(0, 1, 30)[:, None]
    qs = np.array([0.0, -1.2, 1.4, -1.8, -1.57, 0.0]) + u * [0.6, 0.2, -0.3, 0.1, 0.0, 0.4]
    samples = [
        Sample(int(n), int(n), joints=dict(zip(UR, map(float, row), strict=True)))
        for n, row in zip(ns, qs, strict=True)
    ]
    out = write_recording(
        tmp_path / "js", "ros1", {"/joint_states": ("sensor_msgs/msg/JointState", samples)}
    )
    done = _lfdkit(
        "import", str(out), "--topic", "/joint_states", "--no-trim", "-o", "d.csv", cwd=tmp_path
    )
    assert done.returncode == 0, done.stderr
    from lfdkit.io import load_demos

    (d,), (q,) = load_demos(tmp_path / "d.csv", return_orientations=True)
    T = forward(qs)
    np.testing.assert_allclose(d, T[:, :3, 3], atol=1e-12)
    assert rot.angle_between(q, rot.quaternion_from_matrix(T[:, :3, :3])).max() < 1e-9
    frame = _lfdkit(
        "import",
        str(out),
        "--topic",
        "/joint_states",
        "--frame",
        "a:b",
        "-o",
        "e.csv",
        cwd=tmp_path,
    )
    assert frame.returncode == 2 and "--frame applies to tf topics" in frame.stderr


def test_import_options_and_a_recording_at_rest(tmp_path: Path) -> None:
    ns, pos, q = random_trajectory(20, seed=16)
    still = np.tile(pos[:1], (20, 1))
    out = write_recording(
        tmp_path / "r", "mcap", {"/p": ("geometry_msgs/msg/PoseStamped", _samples(ns, still, q))}
    )
    done = _lfdkit("import", str(out), "--topic", "/p", "-o", "d.csv", cwd=tmp_path)
    assert done.returncode == 1
    assert done.stderr.strip().splitlines() == [
        f"lfdkit import: error: {out}: the tool never moves faster than --pause-speed 0.01 "
        "units/s (top speed 0): nothing to import; lower --pause-speed"
    ]
    bad = _lfdkit(
        "import", str(out), "--topic", "/p", "--pause-time", "-1", "-o", "d.csv", cwd=tmp_path
    )
    assert bad.returncode == 2 and "--pause-time: expected a positive number" in bad.stderr


@pytest.mark.parametrize(
    "kind", ["ros1-lz4", "ros1-bz2", "mcap-message", "sqlite3-message", "mcap-file"]
)
def test_compressed_recordings(tmp_path: Path, kind: str, monkeypatch) -> None:
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import Writer as Writer2
    from rosbags.rosbag2.enums import CompressionFormat, CompressionMode

    fmt, algo = kind.split("-")
    if fmt == "ros1":
        setup = Writer1.open

        def compressed(self):
            self.set_compression(getattr(Writer1.CompressionFormat, algo.upper()))
            setup(self)

        monkeypatch.setattr(Writer1, "open", compressed)
    else:
        setup2 = Writer2.open

        def compressed2(self):
            self.set_compression(getattr(CompressionMode, algo.upper()), CompressionFormat.ZSTD)
            setup2(self)

        monkeypatch.setattr(Writer2, "open", compressed2)
    ns, pos, q = random_trajectory(30, seed=17)
    out = write_recording(
        tmp_path / "c", fmt, {"/p": ("geometry_msgs/msg/PoseStamped", _samples(ns, pos, q))}
    )
    np.testing.assert_allclose(read_poses(out, "/p").positions, pos, atol=1e-12)


def test_joint_states_of_two_publishers_on_one_topic(tmp_path: Path) -> None:
    """An arm and its gripper publish /joint_states: the gripper's messages are left out."""
    from lfdkit.execute.recordings import tool_poses_from_joint_states
    from lfdkit.io.recordings import joint_names

    ns, _, _ = random_trajectory(12, seed=18)
    samples = []
    for k, n in enumerate(ns):
        if k % 3 == 1:
            samples.append(Sample(int(n), int(n), joints={"finger_joint": 0.02}))
        else:
            samples.append(Sample(int(n), int(n), joints={j: 0.1 * k for j in UR}))
    out = write_recording(
        tmp_path / "js", "sqlite3", {"/joint_states": ("sensor_msgs/msg/JointState", samples)}
    )
    assert joint_names(out, "/joint_states") == (*UR, "finger_joint")
    rec = tool_poses_from_joint_states(out, "/joint_states")
    assert len(rec.times) == 8
    assert rec.notes == (
        "4 messages without the joints read (another publisher's, e.g. finger_joint) left out",
    )
    with pytest.raises(RecordingError, match="no message has the joints elbow"):
        read_joint_states(out, "/joint_states", joints=("elbow",))


POSE_STAMPED_MSG = """std_msgs/Header header
geometry_msgs/Pose pose
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: builtin_interfaces/Time
int32 sec
uint32 nanosec
================================================================================
MSG: geometry_msgs/Pose
geometry_msgs/Point position
geometry_msgs/Quaternion orientation
================================================================================
MSG: geometry_msgs/Point
float64 x
float64 y
float64 z
================================================================================
MSG: geometry_msgs/Quaternion
float64 x
float64 y
float64 z
float64 w
"""


def test_a_plain_mcap_written_by_the_mcap_tools(tmp_path: Path) -> None:
    """Foxglove's mcap-ros2 writer: types spelt pkg/Name, no rosbag2 metadata."""
    writer_module = pytest.importorskip("mcap_ros2.writer", reason="pip install mcap-ros2-support")
    ns, pos, q = random_trajectory(12, seed=19)
    path = tmp_path / "plain.mcap"
    with open(path, "wb") as f:
        w = writer_module.Writer(f)
        schema = w.register_msgdef("geometry_msgs/PoseStamped", POSE_STAMPED_MSG)
        for n, p, o in zip(ns.tolist(), pos.tolist(), q.tolist(), strict=True):
            message = {
                "header": {"stamp": {"sec": n // 10**9, "nanosec": n % 10**9}, "frame_id": "b"},
                "pose": {
                    "position": dict(zip("xyz", p, strict=True)),
                    "orientation": dict(zip("xyzw", o, strict=True)),
                },
            }
            w.write_message("/tool_pose", schema, message, log_time=n + 5, publish_time=n)
        w.finish()
    assert list_topics(path)[0].msgtype == "geometry_msgs/msg/PoseStamped"
    rec = read_poses(path, "/tool_pose")
    np.testing.assert_allclose(rec.positions, pos, atol=1e-12)
    np.testing.assert_allclose(rec.times, (ns - ns[0]) * 1e-9, atol=1e-9)


def test_an_mcap_of_json_messages_is_refused_with_the_reason(tmp_path: Path) -> None:
    mcap_writer = pytest.importorskip("mcap.writer", reason="pip install mcap")
    path = tmp_path / "json.mcap"
    with open(path, "wb") as f:
        w = mcap_writer.Writer(f)
        w.start()
        sid = w.register_schema(name="Pose", encoding="jsonschema", data=b'{"type":"object"}')
        cid = w.register_channel(topic="/tool_pose", message_encoding="json", schema_id=sid)
        for i in range(3):
            w.add_message(channel_id=cid, log_time=i, data=b'{"x": 1}', publish_time=i)
        w.finish()
    with pytest.raises(RecordingError, match="an MCAP file without ROS 2 messages") as exc:
        read_poses(path, "/tool_pose")
    _one_line(exc)
