"""Rewrite the old module paths of lfdkit (before issue 28's ladder) in Python files.

``python tools/ladder_imports.py FILE...`` rewrites, in place, every import of
a module that moved (``from lfdkit.scene import Scene`` → ``from
lfdkit.model.scene import Scene``; ``from lfdkit import metrics`` → ``from
lfdkit.emulate import metrics``; ``lfdkit.robot.*`` → ``lfdkit.execute.*``,
...) and, with ``--everywhere``, every other mention of an old dotted path
(strings such as ``monkeypatch.setattr("lfdkit.cli._learn", ...)``, docstrings).
Names that left a module (``from lfdkit.skill import TimedPlan`` →
``from lfdkit.model.timed_path import TimedPlan``, :data:`MOVED_NAMES`) are
split off the import statement to their new homes.
Only import statements are touched otherwise, so a file's body stays as it was.
Then run ``ruff check --fix --select I`` on the files to sort the imports.

For code written against the old layout (a branch merged after the move). The
command line's private helpers moved again when ``app/cli.py`` was split
(``tools/split_cli.py``); references to them need a hand.
"""

from __future__ import annotations

import argparse
import ast
import re
import sys
from pathlib import Path

#: Old module (or package) path → new one; the longest match wins.
MOVED = {
    "lfdkit.geometry": "lfdkit.core.geometry",
    "lfdkit._geometry_kernels": "lfdkit.core._geometry_kernels",
    "lfdkit.rotations": "lfdkit.core.rotations",
    "lfdkit.units": "lfdkit.core.units",
    "lfdkit._validation": "lfdkit.core.validation",
    "lfdkit._estimator": "lfdkit.core.estimator",
    "lfdkit.progress": "lfdkit.core.progress",
    "lfdkit._threads": "lfdkit.core.threads",
    "lfdkit._options": "lfdkit.core.options",
    "lfdkit.scene": "lfdkit.model.scene",
    "lfdkit.motion": "lfdkit.model.motion",
    "lfdkit.demos": "lfdkit.model.demos",
    "lfdkit.segmentation": "lfdkit.io.segmentation",
    "lfdkit.metrics": "lfdkit.emulate.metrics",
    "lfdkit.robot": "lfdkit.execute",
    "lfdkit.cli": "lfdkit.app.cli",
    "lfdkit.teach": "lfdkit.app.teach",
    "lfdkit.report": "lfdkit.app.report",
    "lfdkit.plot": "lfdkit.app.plot",
    "lfdkit.batch": "lfdkit.app.batch",
    "lfdkit.evaluation": "lfdkit.app.evaluation",
    # removed aliases: their names live in these modules
    "lfdkit.emulate.scene": "lfdkit.model.scene",
    "lfdkit.examples": "lfdkit.tasks.sweeping",
}
_PATTERN = re.compile(
    r"\b(" + "|".join(re.escape(k) for k in sorted(MOVED, key=len, reverse=True)) + r")(?![\w])"
)
#: Modules moved out of the package root, for ``from lfdkit import NAME``.
_ROOT = {old.split(".")[1]: new for old, new in MOVED.items() if old.count(".") == 1}
#: Names that left a module for another: module → {name: its new module}.
MOVED_NAMES = {
    "lfdkit.skill": {
        "TimedPlan": "lfdkit.model.timed_path",
        "TrainingData": "lfdkit.io.training",
        "read_training_data": "lfdkit.io.training",
    },
}


def rewrite(text: str) -> str:
    """Old dotted paths in a text replaced by the new ones."""
    return _PATTERN.sub(lambda m: MOVED[m.group(1)], text)


def _split_from_lfdkit(text: str) -> str:
    """``from lfdkit import a, b`` with moved modules (or ``from lfdkit.skill import``
    with moved names) among the names: one statement per home."""
    tree = ast.parse(text)
    lines = text.splitlines(keepends=True)
    edits = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.ImportFrom) or node.level:
            continue
        if node.module != "lfdkit" and node.module not in MOVED_NAMES:
            continue
        moved = MOVED_NAMES.get(node.module, {})
        groups: dict[str, list[str]] = {}
        for alias in node.names:
            home = node.module
            if alias.name in moved:
                home = moved[alias.name]
            elif node.module == "lfdkit" and alias.name in _ROOT:
                home, name = _ROOT[alias.name].rsplit(".", 1)
                if name != alias.name:  # renamed (_validation → validation): keep the old name
                    alias_text = f"{name} as {alias.asname or alias.name}"
                    groups.setdefault(home, []).append(alias_text)
                    continue
            as_text = f" as {alias.asname}" if alias.asname else ""
            groups.setdefault(home, []).append(alias.name + as_text)
        if list(groups) != [node.module]:
            indent = lines[node.lineno - 1][: node.col_offset]
            statement = "".join(
                f"{indent if i else ''}from {home} import {', '.join(names)}\n"
                for i, (home, names) in enumerate(groups.items())
            )
            edits.append((node.lineno, node.end_lineno, indent + statement))
    for first, last, statement in sorted(edits, reverse=True):
        lines[first - 1 : last] = [statement]
    return "".join(lines)


def rewrite_file(path: Path, everywhere: bool) -> bool:
    """Rewrite one file in place; True if it changed."""
    text = path.read_text(encoding="utf-8")
    if everywhere:
        new = rewrite(text)
    else:
        lines = text.splitlines(keepends=True)
        for node in ast.walk(ast.parse(text)):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                for i in range(node.lineno - 1, node.end_lineno):
                    lines[i] = rewrite(lines[i])
        new = "".join(lines)
    new = _split_from_lfdkit(new)
    if new != text:
        path.write_text(new, encoding="utf-8")
    return new != text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="+", type=Path)
    parser.add_argument(
        "--everywhere", action="store_true", help="also strings, comments and docstrings"
    )
    args = parser.parse_args(argv)
    for path in args.files:
        if rewrite_file(path, args.everywhere):
            print(f"rewrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
