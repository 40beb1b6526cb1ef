"""Importing lfdkit, its estimators and its command line loads no heavy dependency.

numba (compiling), MuJoCo, matplotlib, scikit-learn, SciPy and Dask each take from a
fraction of a second to seconds to import: they are imported where they are
used, so ``import lfdkit``, ``import lfdkit.skill`` and ``lfdkit --help``
start in well under a second. Each check runs in a fresh interpreter (not a
timing test: it lists the modules loaded).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

HEAVY = ("numba", "mujoco", "matplotlib", "sklearn", "scipy", "dask", "distributed")

_HELP = "from lfdkit.app.cli import main\ntry:\n    main({})\nexcept SystemExit:\n    pass"

#: Statements to run in a fresh interpreter; none may load any of HEAVY.
STATEMENTS = (
    "import lfdkit",
    "import lfdkit.mimic",
    "import lfdkit.skill",
    "from lfdkit.mimic import MIMIC_METHODS, MeanPath, GMR, NLPCA",
    "import lfdkit.app.cli",
    _HELP.format("['--help']"),
    _HELP.format("['learn', '--help']"),
    "import lfdkit.app.batch",
    _HELP.format("['batch', 'evaluate', '--help']"),
)


def _loaded(statement: str) -> set[str]:
    """The top-level packages loaded in a fresh interpreter after ``statement``."""
    return {name.split(".")[0] for name in _loaded_modules(statement)}


def _loaded_modules(statement: str) -> set[str]:
    """Every module loaded in a fresh interpreter after ``statement``."""
    code = (
        "import contextlib, io, json, sys\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        + "".join(f"    {line}\n" for line in statement.splitlines())
        + "print(json.dumps(sorted(sys.modules)))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    return set(json.loads(result.stdout))


@pytest.mark.parametrize("statement", STATEMENTS)
def test_no_heavy_dependency_is_imported(statement: str) -> None:
    loaded = _loaded(statement)
    assert "lfdkit" in loaded
    assert not loaded & set(HEAVY), sorted(loaded & set(HEAVY))


def test_writing_files_loads_neither_numpy_nor_the_readers() -> None:
    """lfdkit.io loads its parts on use: a batch's results file needs only .atomic.

    Importing the package eagerly loaded the demonstration and scene readers and
    NumPy behind them: 0.2 s added to a batch's first results file.
    """
    loaded = _loaded("from lfdkit.io import check_output_path, atomic_write")
    assert "numpy" not in loaded
    modules = _loaded_modules("from lfdkit.io import check_output_path")
    assert "lfdkit.io.atomic" in modules
    assert not modules & {"lfdkit.io.demos", "lfdkit.io.scenes", "lfdkit.io.skill_file"}
    assert "lfdkit.io.scenes" in _loaded_modules("from lfdkit.io import load_scenes")


def test_the_heavy_parts_still_load_when_used() -> None:
    """The check above would pass on a broken import: the estimators still fit."""
    loaded = _loaded(
        "import numpy as np\n"
        "from lfdkit.mimic import GMR, MeanPath\n"
        "t = np.linspace(0, 1, 50)\n"
        "demos = [np.c_[t, np.sin(t) + 0.01 * k] for k in range(3)]\n"
        "MeanPath(n_points=20).fit(demos)\n"
        "GMR(n_components=2, random_state=0).fit(demos)"
    )
    assert {"numba", "sklearn", "scipy"} <= loaded
    assert not loaded & {"mujoco", "matplotlib"}


def test_loading_a_skill_imports_nothing_heavy_and_planning_no_scipy_interpolate(
    tmp_path,
) -> None:
    """Issue 30: loading is reading (no refit, no SciPy); one plan needs neither numba nor SciPy.

    A fresh process plans with the kernels' NumPy forms (``lfdkit.core.kernels``);
    with ``LFDKIT_KERNELS=numba`` the same plan loads numba (so the check can fail).
    """
    import numpy as np

    from lfdkit.emulate import Reward
    from lfdkit.skill import Skill

    u = np.linspace(0.0, 1.0, 50)
    path = np.column_stack([u, 0.2 * np.sin(np.pi * u)])
    skill = Skill(n_basis=15).use_path(path).adopt(Reward(1.0, {"cup": 400.0 * np.eye(2)}))
    saved = str(skill.save(tmp_path / "skill.json"))
    load = f"from lfdkit.skill import Skill\nskill = Skill.load({saved!r})"
    assert not _loaded(load) & set(HEAVY)
    code = (
        "import json, sys\n"
        f"{load}\n"
        "from lfdkit.model.scene import Scene\n"
        "skill.plan(goal=[1.1, 0.1], scene=Scene.from_arrays(['cup'], [[0.5, 0.25]], [0.05]))\n"
        "print(json.dumps(sorted(sys.modules)))\n"
    )
    loaded = {}
    for form in ("auto", "numba"):
        result = subprocess.run(
            [sys.executable, "-c", code],
            capture_output=True,
            text=True,
            timeout=300,
            check=True,
            env={**os.environ, "LFDKIT_KERNELS": form},
        )
        loaded[form] = set(json.loads(result.stdout))
    assert not {m.split(".")[0] for m in loaded["auto"]} & set(HEAVY)
    assert "numba" in loaded["numba"]  # the planner's compiled kernels: the check can fail
    modules = loaded["numba"]
    assert not {m for m in modules if m.startswith(("scipy.interpolate", "scipy.optimize"))}


#: Modules the packages load on first use only (PEP 562) that ``lfdkit plan`` never needs.
NOT_FOR_PLAN = (
    "lfdkit.emulate.ioc",
    "lfdkit.emulate.moving",
    "lfdkit.imitate.rhythmic",
    "lfdkit.imitate.tpgmm",
    "lfdkit.imitate.warp",
    "lfdkit.skill.periodic",
)


def test_plan_s_process_does_not_import_what_it_does_not_need(tmp_path) -> None:
    """Issue 30: ``lfdkit plan`` of a discrete skill loads no TP-GMM, rhythmic DMP or MPC."""
    import numpy as np

    from lfdkit.emulate import Reward
    from lfdkit.skill import Skill

    u = np.linspace(0.0, 1.0, 50)
    path = np.column_stack([u, 0.2 * np.sin(np.pi * u)])
    skill = Skill(n_basis=15).use_path(path).adopt(Reward(1.0, {"cup": 400.0 * np.eye(2)}))
    saved = str(skill.save(tmp_path / "skill.json"))
    argv = [saved, "--goal", "1.1,0.1", "--obstacle", "cup:0.5,0.25,r=0.05", "-o"]
    argv += [str(tmp_path / "path.csv"), "-q"]
    plan = f"from lfdkit.app.cli import main\nmain(['plan', *{argv!r}])"
    modules = _modules(plan)
    assert "lfdkit.emulate.planner" in modules and "lfdkit.imitate.dmp" in modules
    assert not modules & set(NOT_FOR_PLAN), sorted(modules & set(NOT_FOR_PLAN))
    # The names still resolve where they are listed, and load their module then.
    names = "from lfdkit.imitate import TPGMM\nfrom lfdkit.emulate import RecedingPlanner, IOC"
    names += "\nfrom lfdkit.skill import PeriodicSkill"
    assert set(NOT_FOR_PLAN) - {"lfdkit.imitate.warp"} <= _modules(names)


def _modules(statement: str) -> set[str]:
    """Every module (not only top-level packages) a fresh interpreter has after ``statement``."""
    code = statement + "\nimport json, sys\nprint(json.dumps(sorted(sys.modules)))\n"
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    return set(json.loads(result.stdout.splitlines()[-1]))


@pytest.mark.parametrize("package", ["lfdkit.emulate", "lfdkit.imitate", "lfdkit.skill"])
def test_a_lazy_package_lists_and_gives_every_name_of_its_all(package: str) -> None:
    import importlib

    module = importlib.import_module(package)
    assert set(module.__all__) <= set(dir(module))
    for name in module.__all__:
        assert getattr(module, name) is not None
    with pytest.raises(AttributeError, match="has no attribute 'nope'"):
        module.nope  # noqa: B018
