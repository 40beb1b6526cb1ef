"""README.md runs top to bottom (issue 31): its shell and Python blocks, in order.

``tools/run_readme.py`` does the running (see its notes for what it leaves
out and why); the fast tests here check how it reads a README, the slow one
runs this one.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))

import run_readme  # noqa: E402

SAMPLE = """\
Text.

```bash
python -m pip install -e . && lfdkit demo
```

<!-- readme-run: skip (needs a robot) -->
```bash
ros2 bag record /tool_pose
```

```python
print("not shell")
```

```bash
pip install "x[y]"   # a comment
# only a comment
lfdkit plan skill.json --goal 0.36,0.5
```
"""


def test_the_shell_blocks_are_read_in_order_with_their_skip_reasons() -> None:
    blocks = run_readme.shell_blocks(SAMPLE)
    assert [b.line for b in blocks] == [3, 8, 16]
    assert [b.skip for b in blocks] == [None, "needs a robot", None]
    assert blocks[1].code == "ros2 bag record /tool_pose"


def test_installs_are_left_out_and_the_rest_of_the_line_kept() -> None:
    blocks = run_readme.shell_blocks(SAMPLE)
    assert run_readme.without_installs(blocks[0].code) == "lfdkit demo"
    assert run_readme.without_installs(blocks[2].code).splitlines() == [
        "# only a comment",
        "lfdkit plan skill.json --goal 0.36,0.5",
    ]


def test_a_failing_block_stops_the_run_naming_its_line(tmp_path) -> None:
    said: list[str] = []
    blocks = run_readme.shell_blocks("```bash\ntrue\n```\n\n```bash\necho out; false\ntrue\n```\n")
    assert run_readme.run_blocks(blocks, tmp_path, echo=said.append) == 1
    assert said[0].startswith("README.md:1: ran in ")
    assert said[1].startswith("README.md:5: FAILED (exit 1, ") and said[2] == "    out"


def test_python_blocks_share_one_session_and_a_failing_one_is_named(tmp_path) -> None:
    text = (
        "```python\nimport pathlib\nx = 6\n```\n\n"
        "```bash\necho made > made.txt\n```\n\n"
        "```python\nprint(x * 7, pathlib.Path('made.txt').read_text().strip())\n```\n\n"
        "```python\nraise ValueError(f'x is {x}')\n```\n"
    )
    blocks = run_readme.readme_blocks(text)
    assert [(b.line, b.lang) for b in blocks] == [
        (1, "python"),
        (6, "bash"),
        (10, "python"),
        (14, "python"),
    ]
    assert run_readme.shell_blocks(text) == [blocks[1]]
    said: list[str] = []
    assert run_readme.run_blocks(blocks[:3], tmp_path, echo=said.append) == 0
    assert all(": ran in " in line for line in said[:3]) and said[2].endswith(" s (python)")
    said.clear()
    # The names of the earlier blocks are there (x = 6): the failure is the block's own.
    assert run_readme.run_blocks(blocks, tmp_path, echo=said.append) == 1
    assert said[3].startswith("README.md:14: FAILED (an exception, ")
    assert said[-1] == "    ValueError: x is 6"


def test_every_readme_block_runs_or_says_why_not() -> None:
    """Skips are reasoned, and installs use the checkout (``-e ".[extra]"``), not an index."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    blocks = run_readme.readme_blocks(text)
    shell = [b for b in blocks if b.lang == "bash"]
    python = [b for b in blocks if b.lang == "python"]
    assert sum(b.skip is None for b in shell) >= 7
    assert sum(b.skip is None for b in python) >= 6
    assert all(b.skip is None or len(b.skip) > 10 for b in blocks)
    assert not any('pip install "lfdkit[' in b.code for b in blocks)


@pytest.mark.slow  # lfdkit demo, 30 more commands and the Python blocks (three learn a skill)
@pytest.mark.skipif(
    not os.environ.get("LFDKIT_RUN_README"),
    reason="runs the whole README (minutes): set LFDKIT_RUN_README=1 to run it",
)
def test_the_readme_runs_top_to_bottom(tmp_path) -> None:
    done = subprocess.run(
        [sys.executable, str(ROOT / "tools" / "run_readme.py"), "--keep", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=1800,  # 14 min measured with the Python blocks on a 2-core machine at load 15
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert "every block ran" in done.stdout
    made_by_shell = ("lfdkit-demo/report.html", "skill.json", "path.csv", "skill.png", "sweep.json")
    # The robot section's own inputs, made by lfdkit datasets export (nothing downloaded).
    made_by_shell += ("reach.json", "panda.urdf", "run_panda/trajectory.json", "reach_eval.json")
    made_by_python = ("my_skill.json", "sweep.script", "run_panda_py/summary.json")
    for made in made_by_shell + made_by_python:
        assert (tmp_path / made).is_file(), made
