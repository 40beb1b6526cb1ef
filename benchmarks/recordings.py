"""Recordings benchmark: importing ROS 1 / ROS 2 (sqlite3, MCAP) bags, exactness and speed.

Run ``python benchmarks/recordings.py`` (``--quick``: 2,000 messages instead
of 20,000). For each format a bag of ``N`` ``geometry_msgs/PoseStamped``
messages (100 Hz, a known trajectory, random unit quaternions) is written
with rosbags' own writer, then read:

* ``lfdkit``: :func:`lfdkit.io.recordings.read_poses` (open, select the topic,
  deserialise, stamps, sort, quaternion checks);
* ``rosbags``: the peer baseline, the bare ``AnyReader`` loop deserialising
  every message and collecting position, orientation and header stamp in
  Python lists (what any importer built on rosbags has to do).

Reported per format: median wall time of 3 reads, messages per second, the
ratio lfdkit / rosbags, and the largest error of the import against the
trajectory written (positions, quaternions up to sign, times in seconds).
Also the segmentation of the same samples (``segment_recording`` with
``split``). Targets: every error below 1e-9; lfdkit within 1.5x the bare
rosbags loop. Prints a table, writes ``recordings.json`` to ``--output``
(``benchmarks/results/recordings`` by default).
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))  # _common beside this file
from _common import git_state, machine_info, package_versions

from lfdkit.io import atomic_write
from lfdkit.io.recordings import read_poses
from lfdkit.io.segmentation import segment_recording

N_FULL, N_QUICK = 20_000, 2_000
FORMATS = ("ros1", "sqlite3", "mcap")
TOPIC = "/tool_pose"
MSGTYPE = "geometry_msgs/msg/PoseStamped"


def _trajectory(n: int, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    ns = 1_732_400_000 * 10**9 + np.arange(n, dtype=np.int64) * 10_000_000
    s = np.linspace(0, 1, n)
    pos = np.c_[np.sin(6 * s), np.cos(4 * s), 0.2 * s] + rng.normal(0, 1e-4, (n, 3))
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return ns, pos, q


def _write(path: Path, kind: str, ns, pos, q) -> Path:
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import StoragePlugin
    from rosbags.rosbag2 import Writer as Writer2
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS1_NOETIC if kind == "ros1" else Stores.ROS2_HUMBLE)
    T = ts.types
    if kind == "ros1":
        out, writer = path.with_suffix(".bag"), Writer1(path.with_suffix(".bag"))
    else:
        plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
        out, writer = path, Writer2(path, version=9, storage_plugin=plugin)
    with writer:
        conn = writer.add_connection(TOPIC, MSGTYPE, typestore=ts)
        for n, p, o in zip(ns.tolist(), pos.tolist(), q.tolist(), strict=True):
            stamp = T["builtin_interfaces/msg/Time"](sec=n // 10**9, nanosec=n % 10**9)
            H = T["std_msgs/msg/Header"]
            header = (
                H(seq=0, stamp=stamp, frame_id="base")
                if kind == "ros1"
                else H(stamp=stamp, frame_id="base")
            )
            pose = T["geometry_msgs/msg/Pose"](
                T["geometry_msgs/msg/Point"](x=p[0], y=p[1], z=p[2]),
                T["geometry_msgs/msg/Quaternion"](x=o[0], y=o[1], z=o[2], w=o[3]),
            )
            msg = T[MSGTYPE](header, pose)
            raw = (
                ts.serialize_ros1(msg, MSGTYPE)
                if kind == "ros1"
                else ts.serialize_cdr(msg, MSGTYPE)
            )
            writer.write(conn, n + 1000, raw)
    return out


def _bare_rosbags(path: Path) -> int:
    from rosbags.highlevel import AnyReader

    pos, quat, stamps = [], [], []
    with AnyReader([path]) as reader:
        conns = [c for c in reader.connections if c.topic == TOPIC]
        for conn, _, raw in reader.messages(connections=conns):
            m = reader.deserialize(raw, conn.msgtype)
            p, o = m.pose.position, m.pose.orientation
            pos.append((p.x, p.y, p.z))
            quat.append((o.x, o.y, o.z, o.w))
            stamps.append(m.header.stamp.sec * 10**9 + m.header.stamp.nanosec)
    return len(pos)


def _median_time(fn, repeats: int = 3) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).parent / "results" / "recordings"
    )
    parser.add_argument("--quick", action="store_true", help=f"{N_QUICK:,} messages")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args(argv)
    n = N_QUICK if args.quick else N_FULL
    ns, pos, q = _trajectory(n, args.seed)
    rows, targets = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for kind in FORMATS:
            path = _write(Path(tmp) / kind, kind, ns, pos, q)
            rec = read_poses(path, TOPIC)
            err_p = float(np.abs(rec.positions - pos).max())
            err_q = float(
                np.minimum(
                    np.abs(rec.orientations - q).max(1), np.abs(rec.orientations + q).max(1)
                ).max()
            )
            err_t = float(np.abs(rec.times - (ns - ns[0]) * 1e-9).max())
            ours = _median_time(lambda p=path: read_poses(p, TOPIC))
            peer = _median_time(lambda p=path: _bare_rosbags(p))
            seg = _median_time(
                lambda r=rec: segment_recording(r.times, r.positions, speed=1e-3, split=True)
            )
            rows.append(
                {
                    "format": kind,
                    "messages": n,
                    "lfdkit_s": ours,
                    "rosbags_s": peer,
                    "ratio": ours / peer,
                    "messages_per_s": n / ours,
                    "segment_s": seg,
                    "max_position_error": err_p,
                    "max_quaternion_error": err_q,
                    "max_time_error_s": err_t,
                }
            )
    print(f"Import of {n:,} PoseStamped messages (median of 3 reads)")
    head = (
        f"{'format':<8} {'lfdkit s':>9} {'rosbags s':>10} {'ratio':>6} {'msg/s':>9} "
        f"{'segment s':>10} {'pos err':>9} {'quat err':>9} {'time err':>9}"
    )
    print(head)
    for r in rows:
        print(
            f"{r['format']:<8} {r['lfdkit_s']:>9.3f} {r['rosbags_s']:>10.3f} {r['ratio']:>6.2f} "
            f"{r['messages_per_s']:>9,.0f} {r['segment_s']:>10.4f} "
            f"{r['max_position_error']:>9.1e} {r['max_quaternion_error']:>9.1e} "
            f"{r['max_time_error_s']:>9.1e}"
        )
        exact = max(r["max_position_error"], r["max_quaternion_error"], r["max_time_error_s"])
        targets.append(
            {"name": f"{r['format']}: import exact to 1e-9", "value": exact, "pass": exact < 1e-9}
        )
        targets.append(
            {
                "name": f"{r['format']}: within 1.5x the bare rosbags loop",
                "value": r["ratio"],
                "pass": r["ratio"] < 1.5,
            }
        )
    print("\nTargets")
    for t in targets:
        print(f"  {'PASS' if t['pass'] else 'FAIL'}  {t['name']} ({t['value']:.3g})")
    result = {
        "machine": machine_info(),
        "git": git_state(),
        "versions": package_versions(["rosbags", "numpy"]),
        "quick": args.quick,
        "rows": rows,
        "targets": targets,
    }
    args.output.mkdir(parents=True, exist_ok=True)
    text = json.dumps(result, indent=2) + "\n"
    out = args.output / "recordings.json"
    atomic_write(out, lambda f: f.write(text), overwrite=True, encoding="utf-8")
    print(f"\nwrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
