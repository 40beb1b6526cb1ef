"""A battery of bad and edge-case inputs across lfdkit's entry points, counted.

Run ``python benchmarks/bad_inputs.py``. Each case says what must happen: a
clean refusal (the CLI exits 1 or 2 with one line on stderr, no traceback;
the API raises ``ValueError``/``TypeError``/``OSError`` with a message), or a
correct result (checked). Every case runs in its own process with a time
limit, so a hang is counted, not waited for. Prints the counts (clean, silent
wrong result, traceback, hang, data lost) and a line per case that is not
clean; writes ``bad_inputs.json`` to ``--output``.
"""

from __future__ import annotations

import argparse
import json
import os
import pickle
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import numpy as np

SKILL_SETUP = """
from lfdkit.tasks.sweeping import example_files
from lfdkit.skill import learn
f = example_files()
skill = learn(f["demos"], f["scenes"])
skill.save(WORK / "skill.json", overwrite=True)
"""

CLEAN_DEMOS = "\n".join(
    ["demo,x,y"]
    + [
        f"{j},{x:.4f},{0.1 * np.sin(np.pi * x) + dy:.4f}"
        for j, dy in enumerate((0.0, 0.01, -0.01))
        for x in np.linspace(0, 1, 20)
    ]
)

# name, kind ("api" code or "cli" argv), what must happen ("error" or a check expression)
CASES: list[tuple[str, str, str, str]] = [
    # ------------------------------------------------------------------ demos files
    ("csv underscore number", "cli", "learn {w}/u.csv -o {w}/o.json", "error"),
    ("csv id with spaces", "cli", "learn {w}/sp.csv -o {w}/o.json", "error"),
    ("csv id blocks apart", "cli", "learn {w}/blocks.csv -o {w}/o.json", "error"),
    ("csv NaN", "cli", "learn {w}/nan.csv -o {w}/o.json", "error"),
    ("csv empty", "cli", "learn {w}/empty.csv -o {w}/o.json", "error"),
    ("csv one point", "cli", "learn {w}/one.csv -o {w}/o.json", "error"),
    ("csv 4-D", "cli", "learn {w}/four.csv -o {w}/o.json", "error"),
    ("json duplicate key", "cli", "learn {w}/dup.json -o {w}/o.json", "error"),
    ("json numbers as strings", "cli", "learn {w}/str.json -o {w}/o.json", "error"),
    ("json booleans", "cli", "learn {w}/bool.json -o {w}/o.json", "error"),
    ("json nested 100000", "cli", "learn {w}/deep.json -o {w}/o.json", "error"),
    ("pickle as demos", "cli", "learn {w}/p.json -o {w}/o.json", "error"),
    ("npz complex", "cli", "learn {w}/c.npz -o {w}/o.json", "error"),
    ("npz unused huge member", "api", "load_demos(WORK / 'bomb.npz')", "len(result) == 2"),
    ("reversed demo, gmr", "api", "fit_gmr_reversed()", "result"),
    # ------------------------------------------------------------------ skill files
    ("pickle as skill", "cli", "plan {w}/p.json", "error"),
    ("skill n_basis 1e4", "cli", "plan {w}/basis.json", "error"),
    ("skill duration 1e300", "cli", "plan {w}/duration.json", "error"),
    ("skill field missing", "cli", "plan {w}/missing.json", "error"),
    ("skill nested 100000", "cli", "plan {w}/deep.json", "error"),
    # ------------------------------------------------------------------ plan
    ("goal NaN", "cli", "plan {w}/skill.json --goal nan,0.5", "error"),
    ("goal 1e300", "cli", "plan {w}/skill.json --goal 1e300,0.5", "error"),
    ("horizon 13", "cli", "plan {w}/skill.json --horizon 13", "error"),
    ("unknown class", "cli", "plan {w}/skill.json --obstacle vase:0,0.46", "error"),
    ("negative clearance", "cli", "plan {w}/skill.json --clearance -0.01", "error"),
    ("goal approach 0", "cli", "plan {w}/skill.json --goal-approach 0", "error"),
    (
        "obstacle over the goal",
        "cli",
        "plan {w}/skill.json --obstacle cup:0.36,0.5,r=0.03 --goal 0.36,0.5",
        "error",
    ),
    ("big cup on the path", "api", "plan_big_cup()", "result >= 0"),
    # issue 27: refusals that became answers (or a named refusal)
    ("rod 1e6 m long past the goal", "api", "plan_far_rod()", "result > 4.5"),
    ("one observation beside the path", "api", "plan_one_observation()", "result > 0.1"),
    ("learn with a moving obstacle", "api", "learn_moving()", "error"),
    ("wall across the path", "api", "plan_wall()", "error"),
    ("output onto /dev/null", "cli", "plan {w}/skill.json -o /dev/null --force", "error"),
    ("output onto a FIFO", "cli", "plan {w}/skill.json -o {w}/fifo --force", "error"),
    ("output into a missing folder", "cli", "plan {w}/skill.json -o {w}/no/such.csv", "error"),
    ("output exists, no --force", "cli", "plan {w}/skill.json -o {w}/exists.csv", "error"),
    # ------------------------------------------------------------------ task frames (issue 33)
    (
        "frame moves within a demo",
        "cli",
        "learn {w}/moving.csv --task-frames -o {w}/o.json",
        "error",
    ),
    ("frame column missing", "cli", "learn {w}/half.csv --task-frames -o {w}/o.json", "error"),
    (
        "task frames, none recorded",
        "cli",
        "learn {w}/clean.csv --task-frames -o {w}/o.json",
        "error",
    ),
    (
        "frame NaN",
        "cli",
        "plan {w}/pan.json --frame start=0.2,-0.25,0 --frame pan=nan,0,0",
        "error",
    ),
    (
        "frame 1e300",
        "cli",
        "plan {w}/pan.json --frame start=0.2,-0.25,0 --frame pan=1e300,0,0",
        "error",
    ),
    ("frame missing", "cli", "plan {w}/pan.json --frame pan=0.6,-0.1,1", "error"),
    ("frame for a discrete skill", "cli", "plan {w}/skill.json --frame pan=0.6,-0.1,1", "error"),
    # ------------------------------------------------------------------ API
    ("plan start_offset NaN", "api", "plan_path_offset(np.nan)", "error"),
    ("plan 1e7 points", "api", "plan_points(10**7)", "error"),
    ("plan clearance NaN", "api", "plan_clearance_nan()", "error"),
    ("DMP goal 1e300", "api", "dmp_goal(1e300)", "error"),
    ("urscript degrees", "api", "urscript([[0.4, 0.1, 0.2, 0, 180.0, 0]])", "error"),
    ("urscript 1e300", "api", "urscript([[0.4, 0.1, 0.2, 0, 1e300, 0]])", "error"),
    ("urscript below base", "api", "urscript([[0.4, 0.1, -0.9, 0, 3.14, 0]])", "error"),
    ("urscript origin", "api", "urscript([[0, 0, 0, 0, 3.14, 0]])", "error"),
    ("urscript speed True", "api", "urscript([[0.4, 0.1, 0.2, 0, 3.14, 0]], speed=True)", "error"),
    ("servoj jump from rest", "api", "servoj_jump()", "error"),
]

HELPERS = """
import numpy as np
from lfdkit.io import load_demos
from lfdkit.emulate import Reward, plan_path
from lfdkit.emulate.metrics import clearance as path_clearance
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.skill import Skill

def fit_gmr_reversed():
    from lfdkit.mimic import GMR
    x = np.linspace(0, 1, 40)
    demos = [np.column_stack([x, 0.1 * np.sin(np.pi * x) + dy]) for dy in (0, 0.01, -0.01)]
    demos[1] = demos[1][::-1]
    path = GMR(n_components=5, random_state=0).fit(demos).path(50)
    return path[0, 0] < 0.1 and path[-1, 0] > 0.9  # runs start to goal

def straight():
    x = np.linspace(0, 1, 100)
    return np.column_stack([x, 0 * x])

REWARD = Reward(10.0, {"cup": [2500.0, 4000.0]})

def plan_big_cup():
    scene = Scene((Obstacle("cup", [0.5, 0.03], radius=0.1),))
    return path_clearance(plan_path(REWARD, straight(), scene).points, scene)[0]

def plan_far_rod():
    from lfdkit.model.scene import Capsule
    scene = Scene((Capsule("cup", [5.6, 0.0], 0.03, [5.6 + 1e6, 0.0]),))
    return path_clearance(plan_path(REWARD, straight(), scene, clearance=0.01).points, scene)[0]

def plan_one_observation():
    import warnings
    from lfdkit.model.motion import Observations
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # it says it takes the cup as standing
        seen = Observations([0.0], [[0.5, 0.15]], 0.005)
    cup = Obstacle("cup", [0.5, 0.15], 0.03, motion=seen)
    times = np.linspace(0.0, 2.0, 100)
    plan = plan_path(REWARD, straight(), Scene((cup,)), times=times, clearance=0.01)
    return path_clearance(plan.points, Scene((cup.at(0.0),)))[0]

def learn_moving():
    from lfdkit.datasets import load_emulation_dataset
    from lfdkit.model.motion import ConstantVelocity
    from dataclasses import replace
    data = load_emulation_dataset("sweeping", seed=0)
    scenes = [Scene(tuple(replace(o, motion=ConstantVelocity([0.02, 0.0])) for o in s))
              for s in data.scenes[:2]]
    return Skill().fit(data.free_demos, data.demos[:2], scenes)

def plan_wall():
    wall = Scene(tuple(Obstacle("cup", [0.5, y], radius=0.03) for y in np.arange(-0.6, 0.61, 0.05)))
    return plan_path(REWARD, straight(), wall, max_slope=0.5)

def plan_path_offset(value):
    return plan_path(REWARD, straight(), Scene(), start_offset=[value])

def plan_points(n):
    return plan_path(REWARD, straight(), Scene(), n_points=n)

def plan_clearance_nan():
    return plan_path(REWARD, straight(), Scene((Obstacle("cup", [0.5, 0.0]),)), clearance=np.nan)

def dmp_goal(value):
    from lfdkit.imitate import DMP
    return DMP().fit(straight(), duration=1.0).rollout(goal=[value, value])

def urscript(poses, **kw):
    from lfdkit.execute.urscript import urscript_program
    return urscript_program(poses=poses, **kw)

def servoj_jump():
    from lfdkit.execute.urscript import urscript_program
    from lfdkit.execute.ur5 import inverse
    q = np.zeros((3, 6))
    q[:, 1] = -1.2; q[:, 2] = 1.5; q[:, 3] = -1.9; q[:, 4] = -1.57
    q[1:, 0] = 0.025
    return urscript_program(
        poses=None, motion="servoj", times=np.arange(3) * 0.008, joint_path=q
    )
"""


def make_files(work: Path) -> None:
    (work / "u.csv").write_text(CLEAN_DEMOS.replace("0.0526", "0_0526", 1) + "\n")
    lines = CLEAN_DEMOS.splitlines()
    (work / "sp.csv").write_text("\n".join([lines[0], " 7" + lines[1][1:], *lines[2:]]) + "\n")
    (work / "blocks.csv").write_text("\n".join([*lines, lines[1]]) + "\n")
    (work / "nan.csv").write_text("\n".join([lines[0], "0,nan,0.1", *lines[2:]]) + "\n")
    (work / "empty.csv").write_text("")
    (work / "one.csv").write_text("demo,x,y\n0,0.1,0.2\n")
    (work / "four.csv").write_text("demo,x,y,z,w\n0,1,2,3,4\n0,2,3,4,5\n0,3,4,5,6\n")
    demos = [[[float(x), 0.1 * float(x)] for x in np.linspace(0, 1, 10)] for _ in range(3)]
    body = json.dumps(
        {
            "format": "lfdkit-demos",
            "version": 1,
            "n_dims": 2,
            "demos": [{"id": str(j), "points": d} for j, d in enumerate(demos)],
        }
    )
    (work / "dup.json").write_text(body[:-1] + ', "demos": []}')
    (work / "str.json").write_text(body.replace("0.0,", '"0.0",', 1))
    (work / "bool.json").write_text(body.replace("0.0,", "true,", 1))
    (work / "deep.json").write_text("[" * 100000)
    (work / "p.json").write_bytes(pickle.dumps({"demos": demos}))
    np.savez(work / "c.npz", demo_0=np.ones((5, 2), dtype=complex))
    with open(work / "bomb.npz", "wb") as f:
        np.savez_compressed(
            f,
            demo_0=np.column_stack([np.linspace(0, 1, 10), np.zeros(10)]),
            demo_1=np.column_stack([np.linspace(0, 1, 10), np.full(10, 0.01)]),
            unused=np.zeros((2000, 1000, 100), dtype=np.uint8),  # 200 MB, ~200 kB on disk
        )
    skill = json.loads((work / "skill.json").read_text())
    for name, change in (
        ("basis", lambda d: d["params"].update(n_basis=10**4)),
        ("duration", lambda d: d["params"].update(duration=1e300)),
        ("missing", lambda d: d.pop("path")),
    ):
        data = json.loads(json.dumps(skill))
        change(data)
        (work / f"{name}.json").write_text(json.dumps(data))
    (work / "clean.csv").write_text(CLEAN_DEMOS + "\n")
    from lfdkit.datasets import export_dataset
    from lfdkit.io import load_demos
    from lfdkit.skill import TaskFrameSkill

    export_dataset("dustpan", work / "dustpan.csv")
    TaskFrameSkill().fit(load_demos(work / "dustpan.csv", as_records=True)).save(work / "pan.json")
    rows = (work / "dustpan.csv").read_text().splitlines()
    moved = rows[2].split(",")
    moved[-3] = str(float(moved[-3]) + 0.01)  # the pan 1 cm further on one row of demo 0
    (work / "moving.csv").write_text("\n".join([rows[0], rows[1], ",".join(moved), *rows[3:]]))
    half = [",".join(row.split(",")[:-1]) for row in rows]  # no frame_pan_angle
    (work / "half.csv").write_text("\n".join(half) + "\n")
    os.mkfifo(work / "fifo")
    (work / "exists.csv").write_text("precious\n")


def run_case(work: Path, kind: str, what: str, expect: str, limit: float) -> dict:
    if kind == "cli":
        argv = what.format(w=work).split()
        code = [sys.executable, "-m", "lfdkit.app.cli", *argv]
    else:
        script = (
            f"from pathlib import Path\nWORK = Path({str(work)!r})\n{HELPERS}\n"
            + textwrap.dedent(f"""
            try:
                result = {what}
            except (ValueError, TypeError, OSError) as exc:
                print("REFUSED", type(exc).__name__, str(exc).splitlines()[0][:200])
            else:
                ok = bool({expect if expect != "error" else "False"})
                print("RESULT", ok)
            """)
        )
        code = [sys.executable, "-c", script]
    try:
        done = subprocess.run(code, capture_output=True, text=True, timeout=limit, cwd=work)
    except subprocess.TimeoutExpired:
        return {"outcome": "hang"}
    err, out = done.stderr, done.stdout
    if "Traceback" in err:
        return {"outcome": "traceback", "detail": err.strip().splitlines()[-1][:200]}
    if kind == "cli":
        if expect == "error":
            lines = [line for line in err.strip().splitlines() if "error" in line]
            if done.returncode in (1, 2) and lines:
                return {"outcome": "clean", "detail": lines[-1][:200]}
            return {"outcome": "silent", "detail": f"exit {done.returncode}"}
    else:
        if out.startswith("REFUSED"):
            clean = expect == "error"
            return {"outcome": "clean" if clean else "silent", "detail": out.strip()[:200]}
        if out.startswith("RESULT True") and expect != "error":
            return {"outcome": "clean", "detail": "correct result"}
        return {"outcome": "silent", "detail": (out or err).strip()[:200]}
    return {"outcome": "silent", "detail": err[:200]}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).parent / "results" / "bad_inputs"
    )
    parser.add_argument("--limit", type=float, default=60.0, help="seconds per case")
    args = parser.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        work = Path(folder)
        subprocess.run(
            [
                sys.executable,
                "-c",
                f"from pathlib import Path\nWORK = Path({folder!r})\n" + SKILL_SETUP,
            ],
            check=True,
        )
        make_files(work)
        before = (work / "exists.csv").read_text()
        for name, kind, what, expect in CASES:
            row = {"case": name, **run_case(work, kind, what, expect, args.limit)}
            rows.append(row)
            print(f"{row['outcome']:>9}  {name}: {row.get('detail', '')}", file=sys.stderr)
        lost = int((work / "exists.csv").read_text() != before) + int(not (work / "fifo").is_fifo())
    counts = {
        k: sum(r["outcome"] == k for r in rows) for k in ("clean", "silent", "traceback", "hang")
    }
    counts["data_lost"] = lost
    print(f"\n{len(rows)} cases: " + ", ".join(f"{v} {k}" for k, v in counts.items()))
    for row in rows:
        if row["outcome"] != "clean":
            print(f"  {row['outcome']}: {row['case']} ({row.get('detail', '')})")
    args.output.mkdir(parents=True, exist_ok=True)
    (args.output / "bad_inputs.json").write_text(
        json.dumps({"counts": counts, "cases": rows}, indent=2)
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
