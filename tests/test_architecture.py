"""The architecture as a contract: the folders are the ladder; no module takes another's privates.

Every module of ``src/lfdkit`` is parsed with :mod:`ast` and *every* import is
collected, the ones inside functions included (lfdkit imports its heavy parts
where they are used, so a module-level check would miss most arrows). The rules:

1. **The ladder.** Each module sits on one floor (:data:`FLOORS`, the longest
   prefix wins) and imports only modules on its own floor or below::

       core < model < io < mimic < imitate < emulate < datasets < execute
            < skill < app < tasks < app.cli, app.teach

   ``app`` holds the figures, the report, batch runs and the comparison, which
   the tasks use; the user's ways in (``app.cli``, ``app.teach``) are the top
   floor, as they run everything, tasks included. ``lfdkit`` itself (the package
   ``__init__``) imports nothing of lfdkit and may be imported from any floor for
   ``__version__``. Inside the sweeping task each module imports only those before
   it in :data:`SWEEPING_ORDER`.
2. **Nothing imports the tests or the benchmarks** (from the package, nor the
   benchmarks a test module: a helper both need lives in the package).
3. **No private name crosses a module**: no ``from lfdkit.x import _name``; no
   private module (``lfdkit.emulate._planner_kernels``) imported from outside the
   package that holds it; and no ``Name._attr`` where ``Name`` was imported from
   another lfdkit module (``QuaternionDMP._error`` called from the skill). A name
   two modules share is public.
"""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

import pytest

import lfdkit

SRC = Path(lfdkit.__file__).resolve().parent
REPO = SRC.parent.parent

#: The floors, lowest first: the module-name prefixes on each.
FLOORS: tuple[tuple[str, ...], ...] = (
    ("lfdkit.core",),
    ("lfdkit.model",),
    ("lfdkit.io",),
    ("lfdkit.mimic",),
    ("lfdkit.imitate",),
    ("lfdkit.emulate",),
    ("lfdkit.datasets",),
    ("lfdkit.execute",),
    ("lfdkit.skill",),
    ("lfdkit.app",),
    ("lfdkit.tasks",),
    ("lfdkit.app.cli", "lfdkit.app.teach"),
)
#: The sweeping task's modules, each importing only those before it.
SWEEPING_ORDER = (
    "scenarios",
    "examples",
    "sim",
    "figures",
    "execution",
    "demo",
    "moving",
    "manoeuvres",
    "batch",
)


@dataclass(frozen=True)
class Import:
    """One imported lfdkit module (``target``) and the names taken from it, at a line."""

    importer: str
    target: str
    names: tuple[str, ...]
    line: int


def module_name(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {module_name(p): p for p in sorted(SRC.rglob("*.py"))}


def _resolve(importer: str, is_package: bool, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = importer.split(".") if is_package else importer.split(".")[:-1]
    base = base[: len(base) - node.level + 1]
    return ".".join([*base, *([node.module] if node.module else [])])


def imports_of(name: str, tree: ast.AST, is_package: bool) -> list[Import]:
    """Every import of a module of ``top`` in a tree, at any depth; ``from p import m`` of a
    submodule ``m`` counts as importing ``p.m``."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [Import(name, a.name, (), node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            module = _resolve(name, is_package, node)
            for alias in node.names:
                sub = f"{module}.{alias.name}"
                target = sub if sub in MODULES else module
                found.append(Import(name, target, (alias.name,), node.lineno))
    return found


def floor(module: str) -> int:
    """The floor of an lfdkit module (its longest prefix in FLOORS)."""
    best, length = -1, -1
    for i, prefixes in enumerate(FLOORS):
        for prefix in prefixes:
            if (module == prefix or module.startswith(prefix + ".")) and len(prefix) > length:
                best, length = i, len(prefix)
    return best


def private_owner(module: str) -> str | None:
    """The package a private module belongs to (``lfdkit.emulate`` for ``…emulate._x``)."""
    parts = module.split(".")
    for i, part in enumerate(parts):
        if part.startswith("_") and not part.startswith("__"):
            return ".".join(parts[:i])
    return None


def _private(name: str) -> bool:
    return name.startswith("_") and not name.startswith("__")


def _parsed() -> dict[str, tuple[ast.AST, list[Import]]]:
    out = {}
    for name, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        out[name] = (tree, imports_of(name, tree, path.name == "__init__.py"))
    return out


PARSED = _parsed()


def ladder_violations(imports: list[Import]) -> list[str]:
    bad = []
    for imp in imports:
        if imp.target.split(".")[0] != "lfdkit":
            continue
        if imp.target == "lfdkit":
            if imp.importer == "lfdkit" or set(imp.names) - {"__version__"}:
                bad.append(f"{imp.importer}:{imp.line} takes {imp.names} from lfdkit")
            continue
        if imp.importer == "lfdkit":
            bad.append(f"lfdkit:{imp.line} (the package __init__) imports {imp.target}")
            continue
        low, high = floor(imp.target), floor(imp.importer)
        if low < 0 or high < 0:
            bad.append(f"{imp.importer}:{imp.line}: {imp.target} is on no floor")
        elif low > high:
            bad.append(f"{imp.importer}:{imp.line} imports {imp.target}, a floor above it")
        prefix = "lfdkit.tasks.sweeping."
        if imp.importer.startswith(prefix) and imp.target.startswith(prefix):
            a, b = imp.importer[len(prefix) :], imp.target[len(prefix) :]
            if SWEEPING_ORDER.index(b) >= SWEEPING_ORDER.index(a):
                bad.append(f"{imp.importer}:{imp.line} imports {imp.target}, after it")
    return bad


def private_violations(name: str, tree: ast.AST, imports: list[Import]) -> list[str]:
    bad = []
    imported = set()  # names bound here by an import from another lfdkit module
    for imp in imports:
        if imp.target.split(".")[0] != "lfdkit" or imp.target == name:
            continue
        owner = private_owner(imp.target)
        if owner is not None and not (name == owner or name.startswith(owner + ".")):
            bad.append(f"{name}:{imp.line} imports {imp.target}, private to {owner}")
        bad += [f"{name}:{imp.line} imports {imp.target}.{n}" for n in imp.names if _private(n)]
    for node in ast.walk(tree):
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            for alias in node.names:
                module = getattr(node, "module", None) or alias.name
                if module.split(".")[0] == "lfdkit" or getattr(node, "level", 0):
                    imported.add((alias.asname or alias.name).split(".")[0])
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and _private(node.attr)
            and isinstance(node.value, ast.Name)
            and node.value.id in imported
        ):
            bad.append(f"{name}:{node.lineno} uses {node.value.id}.{node.attr}")
    return bad


def test_every_module_is_on_a_floor() -> None:
    assert [m for m in MODULES if m != "lfdkit" and floor(m) < 0] == []


def test_each_module_imports_only_its_floor_and_those_below() -> None:
    bad = []
    for _tree, imports in PARSED.values():
        bad += ladder_violations(imports)
    assert bad == []


def test_no_private_name_crosses_a_module() -> None:
    bad = []
    for name, (tree, imports) in PARSED.items():
        bad += private_violations(name, tree, imports)
    assert bad == []


def test_nothing_imports_the_tests_or_the_benchmarks() -> None:
    bad = []
    folders = {"src": ("tests", "benchmarks", "_common"), "benchmarks": ("tests",)}
    folders["tests"] = ("benchmarks", "_common")
    for folder, forbidden in folders.items():
        for path in sorted((REPO / folder).rglob("*.py")):
            for imp in imports_of("x.y", ast.parse(path.read_text(encoding="utf-8")), False):
                if imp.target.split(".")[0] in forbidden:
                    bad.append(f"{path.relative_to(REPO)}:{imp.line} imports {imp.target}")
    assert bad == []


def test_the_package_root_holds_the_floors_only() -> None:
    loose = sorted(p.name for p in SRC.glob("*.py"))
    assert loose == ["__init__.py"]


# The checks must be able to fail: each rule on made-up modules.


def _tree(source: str, name: str = "lfdkit.mimic.fake") -> tuple[str, ast.AST, list[Import]]:
    tree = ast.parse(source)
    return name, tree, imports_of(name, tree, False)


def test_the_ladder_check_sees_an_upward_arrow_even_inside_a_function() -> None:
    _, _, imports = _tree("def f():\n    from lfdkit.skill import Skill\n")
    assert ladder_violations(imports) == [
        "lfdkit.mimic.fake:2 imports lfdkit.skill, a floor above it"
    ]
    _, _, imports = _tree("from lfdkit.core.geometry import resample\nfrom . import base\n")
    assert ladder_violations(imports) == []
    _, _, imports = _tree("from lfdkit import metrics\n")
    assert ladder_violations(imports) != []
    assert floor("lfdkit.app.cli") > floor("lfdkit.tasks.sweeping.demo") > floor("lfdkit.app.plot")


@pytest.mark.parametrize(
    "source",
    [
        "from lfdkit.imitate.orientation_dmp import QuaternionDMP\nQuaternionDMP._error(1, 2)\n",
        "from lfdkit.core.validation import _check\n",
        "import lfdkit.emulate._planner_kernels\n",
        "from lfdkit.emulate import _planner_kernels as k\n",
    ],
)
def test_the_private_check_sees_a_private_name_crossing(source: str) -> None:
    assert private_violations(*_tree(source)) != []


def test_the_private_check_lets_a_package_use_its_own_private_modules() -> None:
    name, tree, imports = _tree(
        "from lfdkit.emulate._planner_kernels import grid_walk\nself._x = 1\n",
        name="lfdkit.emulate.planner",
    )
    assert private_violations(name, tree, imports) == []


def test_the_execute_layer_holds_no_task() -> None:
    """execute/ is generic robot code: no name of a task (sweep, brush, dustpan, table) in it.

    The sweeping task's constants (its height, its poses, its table) live in
    lfdkit.tasks.sweeping; a name defined in execute/ that speaks of them has strayed.
    """
    words = ("sweep", "brush", "dustpan", "table")
    bad = []
    for path in sorted((SRC / "execute").glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in tree.body:
            targets = []
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                targets = [node.name]
            elif isinstance(node, ast.Assign):
                targets = [t.id for t in node.targets if isinstance(t, ast.Name)]
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                targets = [node.target.id]
            bad += [f"{path.name}: {n}" for n in targets if any(w in n.lower() for w in words)]
    assert bad == []
