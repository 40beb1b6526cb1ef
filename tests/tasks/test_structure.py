"""Tests for the place of lfdkit.tasks: on top of the layers, and the old paths into it.

No module below the tasks imports one (the command line and the teach page, on top, do); the
modules of the sweeping task import only the ones before them
(scenarios → examples → sim → figures → execution → demo → batch) and no private name of another
module. The old import paths of the sweeping task (``lfdkit.robot.sim``,
``lfdkit.examples``, ``lfdkit.plot.sweep_figure``) find the moved names with a
``DeprecationWarning`` and import nothing of the task until then.
"""

from __future__ import annotations

import ast
import importlib
import subprocess
import sys
from pathlib import Path

import pytest

import lfdkit
import lfdkit.tasks.sweeping as sweeping

SRC = Path(lfdkit.__file__).parent
ORDER = ("scenarios", "examples", "sim", "figures", "execution", "demo", "moving", "batch")


def imported_modules(path: Path) -> list[tuple[str, list[str]]]:
    """(module, names) of every import statement in a file, at any depth."""
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            found.append((node.module, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            found += [(a.name, []) for a in node.names]
    return found


def test_no_module_below_the_tasks_imports_one():
    for path in SRC.rglob("*.py"):
        relative = path.relative_to(SRC)
        if relative.parts[0] in ("tasks", "teach") or relative == Path("cli.py"):
            continue
        for module, _ in imported_modules(path):
            assert not module.startswith("lfdkit.tasks"), f"{relative} imports {module}"


@pytest.mark.parametrize("name", ORDER)
def test_sweeping_modules_import_only_those_before_them_and_no_private_name(name):
    path = SRC / "tasks" / "sweeping" / f"{name}.py"
    allowed = {f"lfdkit.tasks.sweeping.{m}" for m in ORDER[: ORDER.index(name)]}
    for module, names in imported_modules(path):
        if module.startswith("lfdkit.tasks"):
            assert module in allowed, f"{name} imports {module}"
        if module.startswith("lfdkit"):
            private = [n for n in names if n.startswith("_") and not n.startswith("__")]
            assert not private, f"{name} imports {private} from {module}"


@pytest.mark.parametrize(
    ("old", "name"),
    [
        ("lfdkit.robot.sim", "execute_sweep"),
        ("lfdkit.robot.sim", "Dustpan"),
        ("lfdkit.robot.sim", "CUBE_SIZE"),
        ("lfdkit.examples", "example_files"),
        ("lfdkit.examples.sweeping_demo", "run_demo"),
        ("lfdkit.examples.sweeping_sim", "random_scenarios"),
        ("lfdkit.examples.sweeping_sim", "GOAL_APPROACH"),
        ("lfdkit.plot", "sweep_figure"),
    ],
)
def test_old_paths_find_the_moved_names_with_a_warning(old, name):
    module = importlib.import_module(old)
    vars(module).pop(name, None)  # found once, the name is kept: look it up afresh
    with pytest.warns(DeprecationWarning, match=rf"{old}\.{name} moved to lfdkit\.tasks"):
        found = getattr(module, name)
    assert found is getattr(sweeping, name)
    with pytest.raises(AttributeError):
        module.no_such_name  # noqa: B018


def test_old_paths_import_nothing_of_the_task():
    script = (
        "import sys, warnings\n"
        "warnings.simplefilter('error')\n"
        "import lfdkit.robot.sim, lfdkit.examples, lfdkit.examples.sweeping_demo\n"
        "import lfdkit.examples.sweeping_sim, lfdkit.plot, lfdkit.datasets, lfdkit.robot.mujoco\n"
        "print(sorted(m for m in sys.modules if m.startswith('lfdkit.tasks')))\n"
    )
    run = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert run.returncode == 0, run.stderr[-2000:]
    assert run.stdout.strip() == "[]"
