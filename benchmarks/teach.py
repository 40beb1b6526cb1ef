"""Round trip of the teach page's live plan: browser request → uvicorn → Skill.plan → JSON.

A real uvicorn server (``lfdkit teach``'s, on a free loopback port) learns the
shipped sweeping example through the page's API, then answers ``POST
/api/plan`` for a 100-point 2-D plan while a cup is dragged across the path
(one kept-alive HTTP connection, as a browser tab uses), without and with the
reward heat map (84 x 48 cells, what the page asks for when a drag ends).
The planner's own time (:meth:`Skill.plan` in-process, the same scenes) is
the floor; the rest is HTTP, JSON and the clearance check.

Target (issue #16): round trip <= 100 ms for a 100-point 2-D plan (p95).
Prints a table and writes ``teach.json`` to ``--output``
(``benchmarks/results/teach`` by default).

    PYTHONPATH=src python benchmarks/teach.py [--requests 200]
"""

from __future__ import annotations

import argparse
import http.client
import json
import sys
import threading
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _common import git_state, machine_info, package_versions

from lfdkit.io import atomic_write

TARGET_MS = 100.0


def _request(conn: http.client.HTTPConnection, method: str, path: str, headers, body=None):
    data = None if body is None else json.dumps(body).encode()
    conn.request(method, path, body=data, headers={**headers, "Content-Type": "application/json"})
    answer = conn.getresponse()
    payload = answer.read()
    if answer.status >= 300:
        raise RuntimeError(f"{method} {path}: {answer.status} {payload[:200]!r}")
    return json.loads(payload)


def _drag(n: int) -> list[tuple[float, float]]:
    """A cup dragged from above the path down across it and along it (metres)."""
    s = np.linspace(0.0, 1.0, n)
    x = -0.25 + 0.5 * s
    y = 0.62 - 0.17 * np.minimum(2 * s, 1.0) + 0.015 * np.sin(9 * s)
    return list(zip(x.tolist(), y.tolist(), strict=True))


def _stats(values: list[float]) -> dict[str, float]:
    a = np.asarray(values)
    return {
        "median": float(np.median(a)),
        "p95": float(np.percentile(a, 95)),
        "max": float(a.max()),
        "n": len(a),
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--output", type=Path, default=Path(__file__).parent / "results" / "teach")
    parser.add_argument("--requests", type=int, default=200, help="plans per case")
    args = parser.parse_args(argv)

    from lfdkit.app.teach.app import SESSION_HEADER
    from lfdkit.app.teach.server import make_server
    from lfdkit.model.scene import Obstacle, Scene
    from lfdkit.skill import Skill

    server, sock = make_server("127.0.0.1", 0)
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    while not server.started:
        time.sleep(0.02)
    host, port = sock.getsockname()[:2]
    conn = http.client.HTTPConnection(host, port, timeout=120)
    try:
        session = _request(conn, "POST", "/api/session", {})["session"]
        headers = {SESSION_HEADER: session}
        example = _request(conn, "GET", "/api/example", headers)
        for demo in example["demos"]:
            demo["obstacles"] = example["marks"].get(demo["id"], [])
        drawing = {"demos": example["demos"], "obstacles": example["obstacles"]}
        started = time.perf_counter()
        _request(conn, "POST", "/api/learn", headers, drawing)
        while (status := _request(conn, "GET", "/api/learn", headers))["state"] == "running":
            time.sleep(0.05)
        if status["state"] != "done":
            raise RuntimeError(f"learning failed: {status['error']}")
        learn_s = time.perf_counter() - started
        print(f"learned the sweeping example through the page's API in {learn_s:.1f} s")
        conn.request("GET", "/api/export/skill", headers=headers)
        skill = Skill.from_dict(json.loads(conn.getresponse().read()))

        spots = _drag(args.requests)
        view = {"view": [-0.7, 0.7, 0.0, 0.8], "nx": 84, "ny": 48}
        results: dict[str, dict] = {}
        for case, heat in (("plan", None), ("plan + heat map", view)):
            trips, server_ms, free = [], [], 0
            for x, y in spots:
                body = {
                    "start": [-0.4, 0.45],
                    "goal": [0.4, 0.45],
                    "obstacles": [{"id": "o1", "class": "cup", "x": x, "y": y, "radius": 0.03}],
                }
                if heat:
                    body["heat"] = heat
                sent = time.perf_counter()
                plan = _request(conn, "POST", "/api/plan", headers, body)
                trips.append(1e3 * (time.perf_counter() - sent))
                server_ms.append(plan["plan_ms"])
                free += plan["collision_free"]
                assert len(plan["points"]) == 100
            results[case] = {
                "round_trip_ms": _stats(trips),
                "planner_ms_in_server": _stats(server_ms),
                "collision_free": free,
            }
        floor = []
        for x, y in spots:
            scene = Scene((Obstacle("cup", [x, y], 0.03),))
            sent = time.perf_counter()
            skill.plan([-0.4, 0.45], [0.4, 0.45], scene)
            floor.append(1e3 * (time.perf_counter() - sent))
        results["Skill.plan in-process"] = {"round_trip_ms": _stats(floor)}
    finally:
        conn.close()
        server.should_exit = True
        thread.join(timeout=10)
        sock.close()

    print(f"\n{len(spots)} plans of 100 points, a cup dragged across the path (ms)")
    print(f"{'case':<24}{'median':>9}{'p95':>9}{'max':>9}{'planner med':>13}{'clear':>7}")
    for case, row in results.items():
        trip = row["round_trip_ms"]
        planner = row.get("planner_ms_in_server", {}).get("median")
        shown = f"{planner:>13.1f}" if planner is not None else f"{'':>13}"
        clear = row.get("collision_free")
        print(
            f"{case:<24}{trip['median']:>9.1f}{trip['p95']:>9.1f}{trip['max']:>9.1f}{shown}"
            f"{'' if clear is None else clear:>7}"
        )
    p95 = results["plan"]["round_trip_ms"]["p95"]
    verdict = "PASS" if p95 <= TARGET_MS else "FAIL"
    ratio = p95 / results["Skill.plan in-process"]["round_trip_ms"]["p95"]
    print(
        f"\nround trip p95 {p95:.1f} ms (target <= {TARGET_MS:g}): {verdict}; "
        f"{ratio:.2f} x the in-process plan's p95"
    )
    record = {
        "target_ms": TARGET_MS,
        "pass": p95 <= TARGET_MS,
        "learn_seconds": learn_s,
        "cases": results,
        "machine": machine_info(),
        "packages": package_versions(["numpy", "numba", "starlette", "uvicorn"]),
        "git": git_state(),
    }
    args.output.mkdir(parents=True, exist_ok=True)
    target = args.output / "teach.json"
    atomic_write(target, lambda f: json.dump(record, f, indent=2), overwrite=True)
    print(f"wrote {target}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
