"""Split ``src/lfdkit/app/cli.py`` into the package ``src/lfdkit/app/cli/``: one module per command.

``python tools/split_cli.py`` (from the repository root) reads the one-file
command line and writes a thin entry point (``entry.py``: ``main``, the parser
assembly, the signal and warning plumbing), one module per command
(``learn.py``, ``plan.py``, ... each with ``run_command(args)`` and
``add_options(parser)``) and ``common.py`` (what several commands share:
errors, messages, progress, argument types, option groups), then removes
``cli.py``. It moves definitions verbatim (comments included); only names
change: a command's handler and option builder become ``run_command`` and
``add_options``, and a helper two modules share loses its underscore (a name
that crosses modules is public) or, for option builders, becomes ``add_*``.
A definition it does not know (added to ``cli.py`` after this script was
written) goes where it is used: the one command module that uses it, else
``common``. Unused imports are then removed with ``ruff check --fix``.

Kept as a script so that the split can be redone on a ``cli.py`` that other
branches edited meanwhile (merge them into ``cli.py`` first, then run this).
"""

from __future__ import annotations

import ast
import io
import keyword
import re
import subprocess
import sys
import tokenize
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SOURCE = ROOT / "src" / "lfdkit" / "app" / "cli.py"
PACKAGE = ROOT / "src" / "lfdkit" / "app" / "cli"

#: Each command module: its handler, its option builder, and the helpers only it uses.
COMMANDS = {
    "demo": ("_demo", "_demo_options", ["_demo_folder"]),
    "import_": ("_import", "_import_options", ["_frame_pair"]),
    "learn": ("_learn", "_learn_options", []),
    "plan": ("_plan", "_plan_options", ["_plan_with"]),
    "plot": ("_plot", "_plot_options", ["_plot_with"]),
    "execute": ("_execute", "_execute_options", []),
    "compare": ("_compare", "_compare_options", []),
    "datasets": ("_datasets", "_datasets_options", ["_list_datasets", "_export_dataset"]),
    "batch": ("_batch", "_batch_options", []),
    "bench": ("_bench", "_bench_options", ["_benchmarks_folder"]),
    "teach": ("_teach", "_teach_options", []),
}
ENTRY = [
    "_parser",
    "_NUMBER_OPTIONS",
    "_NEGATIVE",
    "_join_negative_points",
    "main",
    "_interrupt",
    "_SIZE_OPTIONS",
    "_too_large",
    "_warnings_as_lines",
]
#: Public names of shared helpers where stripping the underscore would be unclear.
PUBLIC = {
    "_say": "tell",
    "_numbers": "parse_numbers",
    "_quaternion": "parse_quaternion",
    "_orientations": "orientation_options",
    "_obstacle": "parse_obstacle",
    "_goal_approach": "parse_goal_approach",
    "_positive": "positive_or_none",
    "_fraction": "parse_fraction",
    "_loudness": "add_loudness_options",
    "_force": "add_force_option",
    "_planner_options": "add_planner_options",
    "_skill_file_options": "add_skill_file_options",
    "_orientation_options": "add_orientation_options",
    "_output_folder": "add_output_folder_option",
    "_units": "add_units_option",
    "_seed": "add_seed_option",
    "_skill_param_options": "add_skill_param_options",
    "_executor_options": "add_executor_options",
    "_results_option": "add_results_option",
}
DOCS = {
    "common": (
        "What several commands share: errors, messages, progress, argument types, option groups."
    ),
    "entry": (
        "The ``lfdkit`` entry point: the parser assembled from the command modules, ``main``,\n"
        "and the plumbing every command runs in (signals, warnings as lines, exit codes)."
    ),
    "demo": "``lfdkit demo``: the whole workflow on the built-in sweeping example.",
    "import_": "``lfdkit import``: demonstrations from ROS 1/2 bags and MCAP recordings.",
    "learn": "``lfdkit learn``: a skill from demonstration files.",
    "plan": "``lfdkit plan``: a path for a new start, goal and scene.",
    "plot": "``lfdkit plot``: a skill's reward, demonstrations and plan.",
    "execute": "``lfdkit execute``: a skill on a UR arm (poses, joints, URScript, a MuJoCo check).",
    "compare": "``lfdkit compare``: the mimicking methods on the built-in data sets.",
    "datasets": "``lfdkit datasets``: list the built-in data sets, or export one.",
    "batch": "``lfdkit batch``: many skills or many scenes, on local processes or Dask.",
    "bench": "``lfdkit bench``: the benchmarks of a folder or the source checkout.",
    "teach": "``lfdkit teach``: the local web page.",
}


def _segments(source: str, tree: ast.Module) -> tuple[list[str], dict[str, str], list[str]]:
    """(import lines, {name: source of its definition with the comments above it}, order)."""
    lines = source.splitlines(keepends=True)
    imports, defs, order = [], {}, []
    body = tree.body[1:] if isinstance(tree.body[0], ast.Expr) else tree.body
    previous_end = tree.body[0].end_lineno if body is not tree.body else 0
    for node in body:
        start = min([node.lineno] + [d.lineno for d in getattr(node, "decorator_list", [])])
        # Comment lines right above a definition belong to it.
        first = start
        while first - 1 > previous_end and lines[first - 2].lstrip().startswith("#"):
            first -= 1
        text = "".join(lines[first - 1 : node.end_lineno])
        previous_end = node.end_lineno
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            imports.append(text)
            continue
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            name = node.name
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            target = node.targets[0] if isinstance(node, ast.Assign) else node.target
            name = target.id
        elif isinstance(node, ast.If):  # if __name__ == "__main__": the package's __main__.py
            continue
        else:
            raise SystemExit(f"cli.py line {node.lineno}: cannot place a {type(node).__name__}")
        if name == "__all__":
            continue
        defs[name], _ = text, order.append(name)
    return imports, defs, order


def _names_used(text: str) -> set[str]:
    return {n.id for n in ast.walk(ast.parse(text)) if isinstance(n, ast.Name)}


def _rename(text: str, mapping: dict[str, str]) -> str:
    """Rename NAME tokens (not attributes after a dot, not keyword arguments), in place."""
    lines = text.splitlines(keepends=True)
    tokens = list(tokenize.generate_tokens(io.StringIO(text).readline))
    edits = []
    names = re.compile(r"(?<![\w.])(" + "|".join(map(re.escape, mapping)) + r")(?!\w)")
    for i, tok in enumerate(tokens):
        if tok.type == tokenize.NAME and tok.string in mapping:
            before = tokens[i - 1].string if i else ""
            after = tokens[i + 1].string if i + 1 < len(tokens) else ""
            if before != "." and not (after == "=" and before in ("(", ",")):
                edits.append((tok.start, tok.end, mapping[tok.string]))
        elif tok.type == tokenize.STRING and re.match(r"(?i)r?f", tok.string) and mapping:
            # An f-string is one token before Python 3.12: rename inside its fields.
            new = names.sub(lambda m: mapping[m.group(1)], tok.string)
            if new != tok.string:
                if tok.start[0] != tok.end[0]:
                    raise SystemExit(f"a renamed name in a multi-line f-string: {tok.string!r}")
                edits.append((tok.start, tok.end, new))
    for (row, col), (_, end_col), new in sorted(edits, reverse=True):
        line = lines[row - 1]
        lines[row - 1] = line[:col] + new + line[end_col:]
    return "".join(lines)


def main() -> int:
    source = SOURCE.read_text(encoding="utf-8")
    tree = ast.parse(source)
    module_doc = ast.get_docstring(tree, clean=False) or ""
    imports, defs, order = _segments(source, tree)
    identifiers = {t.string for t in tokenize.generate_tokens(io.StringIO(source).readline)}

    home: dict[str, str] = {name: "entry" for name in ENTRY}
    for module, (handler, options, helpers) in COMMANDS.items():
        for name in (handler, options, *helpers):
            home[name] = module
    missing = [n for n in home if n not in defs]
    if missing:
        raise SystemExit(f"cli.py has no {missing}: update COMMANDS/ENTRY in {__file__}")
    # The rest: where it is used, transitively; common when more than one module uses it.
    uses = {name: _names_used(text) & set(defs) for name, text in defs.items()}
    changed = True
    while changed:
        changed = False
        for name in order:
            if name in home:
                continue
            users = [u for u in order if name in uses[u] and u != name]
            if users and all(u in home for u in users):  # placed once all its users are
                places = {home[u] for u in users}
                home[name] = places.pop() if len(places) == 1 else "common"
                changed = True
    for name in order:
        home.setdefault(name, "common")
    # A name used outside its module is public.
    crossing = {
        name
        for user in order
        for name in uses[user]
        if home[name] != home[user] and home[name] not in ("entry",) and name.startswith("_")
    }
    rename = {}
    for handler, options, _ in COMMANDS.values():
        rename[handler] = "run_command"
        rename[options] = "add_options"
    for name in crossing - set(rename):
        rename[name] = PUBLIC.get(name, name.lstrip("_"))
    clashes = sorted(
        new for old, new in rename.items() if new in identifiers and new not in ("run_command",)
    )
    if clashes or any(keyword.iskeyword(n) for n in rename.values()):
        raise SystemExit(f"new names already used in cli.py: {clashes}")

    PACKAGE.mkdir(exist_ok=True)
    header_imports = "".join(imports)
    modules = ["common", "entry", *COMMANDS]
    for module in modules:
        names = [n for n in order if home[n] == module]
        if module == "entry":
            # The command table names each command's functions by module attribute, so that a
            # test (or a user) replacing ``learn.run_command`` is seen by the next main().
            local = {}
            for command, (handler, options, _) in COMMANDS.items():
                local[handler] = f"{command}.run_command"
                local[options] = f"{command}.add_options"
            mapping = {**{k: v for k, v in rename.items() if k not in local}, **local}
        else:
            mapping = rename
        body = "\n\n".join(_rename(defs[n], mapping).rstrip("\n") + "\n" for n in names)
        used = set()
        for n in names:
            used |= _names_used(defs[n])
        imported_here = []
        common_names = sorted(
            {rename.get(n, n) for n in used if n in home and home[n] == "common" and n not in names}
        )
        if module != "common" and common_names:
            imported_here.append(
                "from lfdkit.app.cli.common import (\n"
                + "".join(f"    {n},\n" for n in common_names)
                + ")\n"
            )
        if module == "entry":
            imported_here.append("from lfdkit.app.cli import " + ", ".join(sorted(COMMANDS)) + "\n")
        others = sorted(
            {
                home[n]
                for n in used
                if n in home and home[n] not in ("common", module) and module != "entry"
            }
        )
        if others:
            raise SystemExit(f"{module} uses {others}: move the helper to common")
        public = sorted(rename.get(n, n) for n in names if not rename.get(n, n).startswith("_"))
        all_line = "__all__ = [" + ", ".join(f'"{n}"' for n in public) + "]\n\n\n"
        text = (
            f'"""{DOCS[module]}"""\n\n'
            + header_imports
            + "".join(imported_here)
            + "\n"
            + all_line
            + body
        )
        if module == "bench":  # src/lfdkit/app/cli/bench.py: the checkout is 4 folders up
            text = re.sub(r"\.resolve\(\)\.parents\[\d\]", ".resolve().parents[4]", text)
        (PACKAGE / f"{module}.py").write_text(text, encoding="utf-8")
    (PACKAGE / "__init__.py").write_text(
        f'"""{module_doc.rstrip()}\n\n'
        "Modules: :mod:`.entry` (``main``, the parser, the plumbing), one module per\n"
        "command (:mod:`.learn`, :mod:`.plan`, ... each with ``run_command(args)`` and\n"
        '``add_options(parser)``) and :mod:`.common` (what several commands share).\n"""\n\n'
        "from lfdkit.app.cli.entry import main\n\n"
        '__all__ = ["main"]\n',
        encoding="utf-8",
    )
    (PACKAGE / "__main__.py").write_text(
        '"""``python -m lfdkit.app.cli``: the ``lfdkit`` command."""\n\n'
        "from lfdkit.app.cli.entry import main\n\n"
        "raise SystemExit(main())\n",
        encoding="utf-8",
    )
    SOURCE.unlink()
    files = [str(p) for p in sorted(PACKAGE.glob("*.py"))]
    subprocess.run(["ruff", "check", "--fix", "-q", "--select", "F401,I", *files], check=False)
    subprocess.run(["ruff", "format", "-q", *files], check=False)
    for module in modules:
        print(f"{module}: {sum(1 for n in order if home[n] == module)} definitions")
    return 0


if __name__ == "__main__":
    sys.exit(main())
