"""Tests for the sweeping task in batch: ``evaluate_scenario`` and ``lfdkit batch evaluate``.

The example skill (learned once for the module) is evaluated on random and
given scenes. The four checks nest (the plan is the same whether or not the
robot and MuJoCo follow, and the simulated outcome is the one
``execute_skill`` finds); random scene ``i`` of a seed is the same in any
batch; a grown batch only adds scenes; a scene the skill cannot plan for is
an error recorded in the file, not the end of the batch. The slow tests run
200 sweeping scenarios on a Dask LocalCluster of 2 worker processes, and
simulated MuJoCo sweeps on 2 local processes and on the Dask cluster, each equal to the
serial run.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from lfdkit.app.batch import make_executor, read_results
from lfdkit.datasets.emulation import CUP_RADIUS
from lfdkit.skill import Skill, learn
from lfdkit.tasks.sweeping import example_files
from lfdkit.tasks.sweeping.batch import CHECKS, evaluate_batch, evaluate_scenario, scenario
from lfdkit.tasks.sweeping.execution import execute_skill
from lfdkit.tasks.sweeping.scenarios import random_scenarios
from tests.app.test_cli import run_cli
from tests.conftest import example_skill_file_copy


@pytest.fixture(scope="module")
def skill_path(example_skill_file_once, tmp_path_factory) -> Path:
    return example_skill_file_copy(example_skill_file_once, tmp_path_factory.mktemp("skill"))


@pytest.fixture(scope="module")
def thesis_skill_path(tmp_path_factory) -> Path:
    """The example skill with the thesis's behaviour model: it plans each scene once.

    Whether executors agree does not depend on the model; the default one, with its
    safety floor, also plans each scene without it (about 1.8x the time a scene).
    """
    files = example_files()
    path = tmp_path_factory.mktemp("thesis_skill") / "skill.json"
    learn(files["demos"], files["scenes"], model="thesis").save(path)
    return path


def rows(path: Path) -> list[dict]:
    return sorted(read_results(path), key=lambda r: r["task"])


def test_random_scene_i_depends_on_the_seed_and_i_only():
    first = scenario(5, 3)
    again = scenario(5, 3)
    assert np.array_equal(first.scene.positions, again.scene.positions)
    assert np.array_equal(first.goal, again.goal)
    rng = np.random.default_rng(np.random.SeedSequence(5).spawn(4)[3])
    spawned = random_scenarios(1, rng)[0]
    assert np.array_equal(first.scene.positions, spawned.scene.positions)
    assert not np.array_equal(first.scene.positions, scenario(5, 4).scene.positions)
    assert not np.array_equal(first.scene.positions, scenario(6, 3).scene.positions)


def test_the_checks_nest(skill_path):
    text = skill_path.read_text()
    where = {"seed": 0, "index": 1}
    got = {check: evaluate_scenario(text, where, check) for check in CHECKS[:3]}
    assert all(row["plan"] == got["plan"]["plan"] for row in got.values())
    assert all(row["ok"] and row["failure"] is None for row in got.values())
    assert "robot" not in got["plan"]
    assert got["kinematics"]["robot"] == {"poses": got["robot"]["robot"]["poses"]}
    assert "simulation" not in got["robot"]
    assert got["robot"]["goal"] == scenario(0, 1).goal.tolist()
    assert json.loads(json.dumps(got["robot"])) == got["robot"]  # JSON-ready
    with pytest.raises(ValueError, match="check: expected one of"):
        evaluate_scenario(text, where, "teleport")


def test_the_plan_check_loads_neither_the_execution_pipeline_nor_scipy_interpolate(skill_path):
    """Issue 30: a worker that only plans starts without the robot's modules and SciPy's splines."""
    code = (
        "import json, sys\n"
        "from pathlib import Path\n"
        "from lfdkit.tasks.sweeping.batch import evaluate_scenario\n"
        f"row = evaluate_scenario(Path({str(skill_path)!r}).read_text(), "
        "{'seed': 0, 'index': 1}, 'plan')\n"
        "print(json.dumps([row['ok'], sorted(sys.modules)]))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=True
    )
    ok, modules = json.loads(done.stdout)
    assert ok and "lfdkit.emulate.planner" in modules  # it planned: the check can fail
    heavy = ("lfdkit.execute.pipeline", "lfdkit.tasks.sweeping.execution", "scipy.interpolate")
    assert not [m for m in modules if m.startswith(heavy)]


@pytest.mark.slow  # two MuJoCo sweeps
def test_the_simulated_check_is_what_execute_skill_finds(skill_path):
    text = skill_path.read_text()
    where = {"seed": 0, "index": 1}
    robot = evaluate_scenario(text, where, "robot")
    simulated = evaluate_scenario(text, where, "mujoco")
    same = {k: simulated[k] for k in robot if k not in ("check", "ok")}
    assert same == {k: v for k, v in robot.items() if k not in ("check", "ok")}
    assert simulated["check"] == "mujoco"
    drawn = scenario(0, 1)
    run = execute_skill(Skill.load(skill_path), drawn.start, drawn.goal, drawn.scene)
    found = simulated["simulation"]
    assert found["success"] == run.result.success == simulated["ok"]
    assert found["tracking_error_m"] == run.result.tracking_error
    assert found["touched"] == [int(i) for i in run.result.touched]


def test_a_grown_random_batch_only_adds_scenes(skill_path, tmp_path, capsys):
    argv = ["batch", "evaluate", skill_path, "--check", "plan", "--seed", 4]
    code, _, err = run_cli(capsys, *argv, "--random", 3, "-o", tmp_path / "grown.jsonl")
    assert code == 0, err
    assert "ran 3 of 3 scenes" in err
    code, _, err = run_cli(capsys, *argv, "--random", 5, "-o", tmp_path / "grown.jsonl")
    assert code == 0, err
    assert "ran 2 of 5 scenes" in err and "3 done before, skipped" in err
    code, _, err = run_cli(capsys, *argv, "--random", 5, "-o", tmp_path / "whole.jsonl")
    assert rows(tmp_path / "grown.jsonl") == rows(tmp_path / "whole.jsonl")
    assert [r["scenario"] for r in rows(tmp_path / "whole.jsonl")] == [
        {"seed": 4, "index": i} for i in range(5)
    ]


def test_scenes_of_a_file_with_one_the_skill_cannot_plan_for(skill_path, tmp_path, capsys):
    scenes = tmp_path / "scenes.csv"
    scenes.write_text(
        "demo,class,x,y,radius\n"
        "a,cup,-0.05,0.49,0\n"
        "a,marker,0.15,0.455,0\n"
        "b,cup,0.0,0.52,0.035\n"
        "c,bowl,0.0,0.47,0.04\n"
    )
    results = tmp_path / "r.jsonl"
    argv = ["batch", "evaluate", skill_path, "--scenes", scenes, "--goal", "0.36,0.5"]
    code, _, err = run_cli(capsys, *argv, "--check", "plan", "-o", results)
    assert code == 1
    assert "1 of 3 tasks failed (first: c: ValueError: " in err
    got = {r["task"]: r for r in read_results(results)}
    assert set(got) == {"a", "b", "c"}
    assert "bowl" in got["c"]["error"]
    assert got["a"]["ok"] and got["b"]["ok"]
    assert got["a"]["obstacles"][0] == ["cup", -0.05, 0.49, CUP_RADIUS]  # the class's radius
    assert got["b"]["obstacles"] == [["cup", 0.0, 0.52, 0.035]]
    assert got["a"]["goal"] == [0.36, 0.5]
    skill = Skill.load(skill_path)
    assert got["b"]["start"] == skill.path_[0].tolist()


@pytest.mark.slow  # starts 2 worker processes: 3-8 s on 2 shared cores
def test_a_worker_warning_reads_as_the_serial_run_s_one_line(skill_path, tmp_path, capsys):
    """Issue 30: a plan's warning in a worker is the serial run's one line, not a UserWarning.

    Two scenes with two obstacles closer than the clearances kept from them
    warn (each its own gap); the third does not.
    """
    scenes = tmp_path / "scenes.csv"
    scenes.write_text(
        "demo,class,x,y,radius\n"
        "a,cup,-0.05,0.47,0.03\n"
        "a,cup,0.02,0.47,0.03\n"
        "b,cup,0.0,0.45,0.03\n"
        "c,cup,-0.06,0.46,0.03\n"
        "c,marker,0.0,0.46,0.01\n"
    )
    argv = ["batch", "evaluate", skill_path, "--scenes", scenes, "--check", "plan", "-q"]
    code, _, serial = run_cli(capsys, *argv, "-o", tmp_path / "serial.jsonl")
    assert code == 0
    code, _, workers = run_cli(capsys, *argv, "--workers", 2, "-o", tmp_path / "workers.jsonl")
    assert code == 0
    lines = sorted(serial.splitlines())
    assert len(lines) == 2, serial
    assert all(line.startswith("lfdkit batch: warning: plan: obstacles 0 (") for line in lines)
    assert sorted(workers.splitlines()) == lines
    assert rows(tmp_path / "workers.jsonl") == rows(tmp_path / "serial.jsonl")


def test_evaluate_usage_errors(skill_path, tmp_path, capsys):
    out = ["-o", tmp_path / "r.jsonl"]
    code, _, err = run_cli(capsys, "batch", "evaluate", skill_path, *out)
    assert code == 2 and "--scenes FILE or --random N" in err
    code, _, err = run_cli(
        capsys, "batch", "evaluate", skill_path, "--random", 2, "--start", "0,0", *out
    )
    assert code == 2 and "--start/--goal are for --scenes" in err
    mm = tmp_path / "mm.json"
    Skill.load(skill_path).to_units("mm").save(mm)
    code, _, err = run_cli(capsys, "batch", "evaluate", mm, "--random", 2, *out)
    assert code == 1 and "a 2-D skill in metres" in err
    assert not (tmp_path / "r.jsonl").exists()


def test_a_scene_with_a_moving_obstacle_is_refused_with_the_reason(skill_path, tmp_path, capsys):
    scenes = tmp_path / "moving.csv"
    scenes.write_text(
        "demo,class,x,y,radius,vx,vy\na,cup,0.0,0.5,0.03,,\nb,cup,0.1,0.6,0.03,0,-0.1\n"
    )
    results = tmp_path / "r.jsonl"
    argv = ["batch", "evaluate", skill_path, "--scenes", scenes, "--check", "plan", "-q"]
    code, _, err = run_cli(capsys, *argv, "-o", results)
    assert code == 1 and err.count("\n") == 1
    assert f"{scenes}: scene 'b' has a moving obstacle; batch evaluate checks standing" in err
    assert "lfdkit plan" in err
    assert not results.exists()


@pytest.fixture(scope="module")
def dask_cluster():
    """One Dask LocalCluster of 2 worker processes for the module's two Dask tests: its
    start and its workers' imports (seconds on 2 cores) are paid once."""
    pytest.importorskip("distributed", reason='pip install "lfdkit[dask]"')
    with make_executor(dask_local=2) as executor:
        yield executor


@pytest.mark.slow  # cheap with the module's cluster (started for the tests below anyway)
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="a forkserver on Linux only")
def test_dask_local_workers_start_preloaded_as_local_processes_do(dask_cluster):
    """Issue 30: the workers fork from the preloaded fork server, numba loaded once for them.

    Run before the module's other Dask tests: no task has run on the workers yet
    (the kernels' CPU clock, restarted after the fork server's warm-up, is unset).
    A process has one fork server, started with the first batch's preload: run
    alone, this cluster's (numba: its task count is not known) starts it; after
    an earlier short batch in the same pytest process, the NumPy-only one
    already runs, so numba is expected exactly when the compiled preload is there.
    """

    def probe():
        import os
        import sys

        wanted = ("numba", "lfdkit.skill", "lfdkit.emulate.planner")
        compiled = "lfdkit.app.worker_preload_compiled" in sys.modules
        clock = sys.modules["lfdkit.core.kernels"]._clock["cpu_start"]
        return [m for m in wanted if m in sys.modules], compiled, clock, os.getpid()

    got = dask_cluster.client.run(probe)
    assert len(got) == 2
    assert len({compiled for _, compiled, _, _ in got.values()}) == 1  # one server for both
    for loaded, compiled, clock, pid in got.values():
        assert loaded == ["numba"] * compiled + ["lfdkit.skill", "lfdkit.emulate.planner"]
        assert clock is None and pid != os.getpid()


@pytest.mark.slow
def test_60_scenarios_on_a_dask_local_cluster_equal_the_serial_run(
    thesis_skill_path, tmp_path, dask_cluster
):
    """60 random sweeping scenarios, each planned around its cup and marker to its dustpan
    (the ``plan`` check, ~30 ms a scene: a full MuJoCo sweep takes 1.5-3 s, too slow for
    many twice on 2 cores; the next test compares simulated sweeps, ``benchmarks/batch.py``
    times them). 60 still travel as chunks of ~8 (0.25 s of work) and then one by one at
    the end, as 200 did (200 took ~20 s of the suite)."""
    n = 60
    serial = evaluate_batch(thesis_skill_path, tmp_path / "serial.jsonl", random=n, check="plan")
    assert dask_cluster.workers == 2
    dask = evaluate_batch(
        thesis_skill_path, tmp_path / "dask.jsonl", random=n, check="plan", executor=dask_cluster
    )
    assert (serial.done, serial.failed, dask.done, dask.failed) == (n, 0, n, 0)
    expected = rows(tmp_path / "serial.jsonl")
    assert len(expected) == n
    # Rows in the tasks' order, though chunks finish in any order: the same file (issue 30).
    assert (tmp_path / "dask.jsonl").read_bytes() == (tmp_path / "serial.jsonl").read_bytes()
    assert sum(r["ok"] for r in expected) > n // 2  # most random scenes can be planned
    assert len({json.dumps(r["obstacles"]) for r in expected}) == n  # all different scenes


@pytest.mark.slow
def test_simulated_sweeps_on_dask_and_processes_equal_the_serial_run(
    skill_path, tmp_path, dask_cluster
):
    """Full MuJoCo sweeps, at 0.6 of the joint limits (3 times shorter than the thesis's
    0.2) so that the test stays short."""
    n = 4
    settings = {"random": n, "seed": 1, "check": "mujoco", "speed_fraction": 0.6}
    serial = evaluate_batch(skill_path, tmp_path / "serial.jsonl", **settings)
    assert serial.done == n
    expected = rows(tmp_path / "serial.jsonl")
    assert all("simulation" in r for r in expected)
    with make_executor(workers=2) as processes:
        evaluate_batch(skill_path, tmp_path / "processes.jsonl", executor=processes, **settings)
    evaluate_batch(skill_path, tmp_path / "dask.jsonl", executor=dask_cluster, **settings)
    for name in ("processes", "dask"):  # the same file, byte for byte (issue 30)
        assert (tmp_path / f"{name}.jsonl").read_bytes() == (
            tmp_path / "serial.jsonl"
        ).read_bytes(), name


@pytest.mark.slow  # a fresh interpreter that loads numba: ~2-3 s quiet
def test_a_robot_task_runs_on_numba_s_kernels_from_its_first_whatever_the_process(skill_path):
    """Issue 30: a robot check's row does not depend on the kernels a process had turned to.

    The timing law's NumPy form agrees with numba's to round-off only, and a
    fresh worker used to run it for its first second of CPU: a short batch on
    2 workers wrote rows that differed from the serial run's in the 13th digit
    of a motion's duration. The unit loads numba before its first robot task;
    the row in a fresh process equals this process's.
    """
    code = (
        "import json, sys\n"
        "from pathlib import Path\n"
        "from lfdkit.tasks.sweeping.batch import evaluate_scenario\n"
        "row = evaluate_scenario(Path(sys.argv[1]).read_text(), {'seed': 0, 'index': 3}, 'robot')\n"
        "print(json.dumps(['numba' in sys.modules, row]))\n"
    )
    env = {k: v for k, v in os.environ.items() if k != "LFDKIT_KERNELS"}
    done = subprocess.run(
        [sys.executable, "-c", code, str(skill_path)],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert done.returncode == 0, done.stderr[-500:]
    loaded, row = json.loads(done.stdout.strip().splitlines()[-1])
    assert loaded
    here = evaluate_scenario(Path(skill_path).read_text(), {"seed": 0, "index": 3}, "robot")
    assert row == json.loads(json.dumps(here))
