"""The package's seams: no module takes another module's private names.

A leading underscore marks what a module keeps to itself. Shared helpers live
in modules that are private to the *package* (``lfdkit._validation``,
``lfdkit.emulate._problem_kernels``) and are imported only from within that
package; their functions are public names.
"""

from __future__ import annotations

import ast
from pathlib import Path

import lfdkit

SRC = Path(lfdkit.__file__).resolve().parent


def _module_name(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _private_module(name: str) -> str | None:
    """The package a private module belongs to (``lfdkit.emulate`` for ``…emulate._x``)."""
    parts = name.split(".")
    for i, part in enumerate(parts):
        if part.startswith("_") and not part.startswith("__"):
            return ".".join(parts[:i])
    return None


def test_no_module_imports_private_names_or_private_modules_of_other_packages() -> None:
    offenders = []
    for path in sorted(SRC.rglob("*.py")):
        importer = _module_name(path)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("lfdkit"):
                names = [a.name for a in node.names]
                offenders += [
                    f"{importer}: {node.module}.{name}"
                    for name in names
                    if name.startswith("_") and not name.startswith("__")
                ]
                targets = [node.module]
            elif isinstance(node, ast.Import):
                targets = [a.name for a in node.names if a.name.startswith("lfdkit")]
            else:
                continue
            for target in targets:
                package = _private_module(target)
                if package is not None and not importer.startswith(package):
                    offenders.append(f"{importer}: imports {target}, private to {package}")
    assert offenders == []


def test_the_check_sees_a_private_import() -> None:
    # The rule's two halves on made-up module names (the check above must be able to fail).
    assert _private_module("lfdkit.emulate._problem_kernels") == "lfdkit.emulate"
    assert _private_module("lfdkit._validation") == "lfdkit"
    assert _private_module("lfdkit.emulate.planner") is None
    assert not "lfdkit.robot.urscript".startswith("lfdkit.emulate")
