"""The file I/O layer: where names live, what each layer imports, and the aliases kept."""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

import lfdkit
import lfdkit.demos
import lfdkit.emulate
import lfdkit.emulate.scene
import lfdkit.io
import lfdkit.io.scenes
import lfdkit.scene
import lfdkit.skill

SRC = Path(lfdkit.__file__).resolve().parent

# What each module of the lower layers may import from lfdkit (module-level imports).
ALLOWED = {
    "motion.py": set(),  # how obstacles move: below the scene that carries it
    "scene.py": {"lfdkit.geometry", "lfdkit.motion"},
    "demos.py": set(),
    "io/atomic.py": {"lfdkit.demos"},
    "io/text.py": {"lfdkit.demos", "lfdkit.io.atomic"},
    "io/demos.py": {
        "lfdkit._validation",
        "lfdkit.demos",
        "lfdkit.io.atomic",
        "lfdkit.io.text",
        "lfdkit.rotations",
    },
    "io/scenes.py": {
        "lfdkit.demos",
        "lfdkit.io.atomic",
        "lfdkit.io.text",
        "lfdkit.motion",
        "lfdkit.scene",
    },
    "io/skill_file.py": {"lfdkit", "lfdkit.demos", "lfdkit.io.atomic", "lfdkit.io.text"},
}
LOWER = ("lfdkit.demos", "lfdkit.scene", "lfdkit.io")


def _imports(path: Path) -> list[ast.ImportFrom | ast.Import]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return [n for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom))]


@pytest.mark.parametrize("name", sorted(ALLOWED))
def test_the_lower_layers_import_only_what_is_below_them(name: str) -> None:
    found = set()
    for node in _imports(SRC / name):
        modules = [a.name for a in node.names] if isinstance(node, ast.Import) else [node.module]
        found |= {m for m in modules if m and m.split(".")[0] == "lfdkit"}
    assert found <= ALLOWED[name], f"{name} imports {sorted(found - ALLOWED[name])}"


def test_no_module_takes_private_names_from_the_data_models_or_io() -> None:
    offenders = []
    for path in sorted(SRC.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.ImportFrom) or not (node.module or "").startswith(LOWER):
                continue
            offenders += [
                f"{path.relative_to(SRC)}: {node.module}.{a.name}"
                for a in node.names
                if a.name.startswith("_") and not a.name.startswith("__")
            ]
    assert not offenders


def test_the_old_demos_names_are_forwarded_to_lfdkit_io() -> None:
    for name in (
        "load_demos",
        "save_demos",
        "save_path",
        "path_csv",
        "atomic_write",
        "check_output_path",
        "OutputExistsError",
        "NotRegularFileError",
        "load_json",
        "json_float_array",
        "SUPPORTED_SUFFIXES",
        "JSON_FORMAT",
        "JSON_VERSION",
        "MAX_FILE_BYTES",
        "MAX_JSON_DEPTH",
        "MAX_NPZ_MEMBERS",
        "MAX_NPZ_ARRAY_BYTES",
        "STALE_TEMP_SECONDS",
    ):
        assert getattr(lfdkit.demos, name) is getattr(lfdkit.io, name), name
        assert name in dir(lfdkit.demos)
    from lfdkit.demos import OutputExistsError, save_demos

    assert save_demos is lfdkit.io.save_demos
    assert issubclass(OutputExistsError, FileExistsError)
    with pytest.raises(AttributeError, match="has no attribute 'read_text'"):
        _ = lfdkit.demos.read_text  # a primitive of lfdkit.io.text, never public here


def test_importing_the_demos_data_model_does_not_import_the_files() -> None:
    env = {**os.environ, "PYTHONPATH": str(SRC.parent)}
    code = (
        "import sys, lfdkit.demos, lfdkit.scene; "
        "assert 'lfdkit.io' not in sys.modules; "
        "lfdkit.demos.load_demos; assert 'lfdkit.io' in sys.modules"
    )
    subprocess.run([sys.executable, "-c", code], check=True, env=env)


def test_the_scene_names_are_kept_in_emulate() -> None:
    for module in (lfdkit.emulate, lfdkit.emulate.scene):
        assert module.Scene is lfdkit.scene.Scene
        assert module.Obstacle is lfdkit.scene.Obstacle
        for name in ("load_scene", "load_scenes", "save_scenes"):
            assert getattr(module, name) is getattr(lfdkit.io, name)
    for name in ("SCENE_JSON_FORMAT", "SCENE_JSON_VERSION", "SCENE_SUFFIXES"):
        assert getattr(lfdkit.emulate.scene, name) == getattr(lfdkit.io.scenes, name)


def test_the_skill_file_constants_are_kept_in_skill() -> None:
    for name in ("SKILL_FORMAT", "SKILL_VERSION", "MAX_SKILL_FILE_BYTES", "SKILL_FILE_LIMITS"):
        assert getattr(lfdkit.skill, name) is getattr(lfdkit.io, name)
