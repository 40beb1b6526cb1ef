"""Run README.md's shell and Python blocks top to bottom in a fresh folder: the README is a test.

A new user copies the blocks in order; each must run as written, the files
it needs made by an earlier block (or shipped with lfdkit). This tool does
what that user does:

* every fenced ```` ```bash ```` block, in order, in one temporary folder
  (or ``--keep DIR``), each with ``bash -e -o pipefail``, so the first
  failing command fails its block;
* every ```` ```python ```` block, in the same order and folder, in one
  Python session that lives through the whole run: a block sees the names
  the Python blocks above it defined (``skill``, ``scene``), as a reader
  typing them into one interpreter would;
* ``lfdkit`` is this checkout's (``python -m lfdkit.app.cli`` with the
  running interpreter and its ``PYTHONPATH``), so a worktree tests its own
  code, not an installed copy;
* installs are left out: a command ``pip install ...`` or
  ``python -m pip install ...`` is dropped (and ``INSTALL && REST`` runs
  ``REST``): the test runs in the environment already installed;
* a block preceded by ``<!-- readme-run: skip (WHY) -->`` (invisible on the
  rendered page) is skipped, saying why: installs and the test suite itself,
  commands that need a robot, ROS, a browser or a cluster, long runs
  (benchmarks), and Python fragments that use names the reader supplies
  (``new_goal_orientation``). ``--list`` shows which blocks run and which are
  skipped.

Usage::

    python tools/run_readme.py            # every block; exit 1 at the first failure
    python tools/run_readme.py --list     # the blocks, run or skipped, with their lines
    python tools/run_readme.py --keep out # run in ./out (kept) instead of a temporary folder
    python tools/run_readme.py --only python  # only the Python blocks (or only shell)

Exit status 0 when every block runs, 1 at the first block that fails (its
line in README.md, the command's exit status and the last lines it printed).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import secrets
import shlex
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: The marker before a block that the run skips: ``<!-- readme-run: skip (WHY) -->``.
SKIP = re.compile(r"<!--\s*readme-run:\s*skip\s*\((?P<why>[^)]*)\)\s*-->")
_FENCE = re.compile(r"^```(?P<lang>[\w+-]*)\s*$")
_SHELLS = ("bash", "sh", "shell")
_INSTALL = re.compile(r"^\s*(?:python3?\s+-m\s+)?pip\s+install\b[^&#]*?(?:&&\s*|(?=#)|$)")


@dataclass(frozen=True)
class Block:
    """One fenced shell block of the README."""

    line: int  # of the opening fence, 1-based
    code: str
    skip: str | None  # why it is skipped, or None
    lang: str = "bash"  # "bash" (any shell) or "python"


def shell_blocks(text: str) -> list[Block]:
    """The ``bash``/``sh``/``shell`` blocks of a Markdown text, in order, with skip reasons."""
    return [block for block in readme_blocks(text) if block.lang == "bash"]


def readme_blocks(text: str) -> list[Block]:
    """The shell and ``python`` blocks of a Markdown text, in order, with skip reasons."""
    blocks: list[Block] = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        fence = _FENCE.match(lines[i])
        if fence is None:
            i += 1
            continue
        start, lang = i, fence.group("lang")
        i += 1
        body = []
        while i < len(lines) and not lines[i].startswith("```"):
            body.append(lines[i])
            i += 1
        i += 1  # the closing fence
        if lang not in (*_SHELLS, "python"):
            continue
        before = next((lines[k] for k in range(start - 1, -1, -1) if lines[k].strip()), "")
        marker = SKIP.search(before)
        why = marker.group("why") if marker else None
        kind = "python" if lang == "python" else "bash"
        blocks.append(Block(start + 1, "\n".join(body), why, kind))
    return blocks


def without_installs(code: str) -> str:
    """``code`` with its ``pip install`` commands left out (``INSTALL && REST`` keeps ``REST``)."""
    kept = []
    for line in code.splitlines():
        stripped = _INSTALL.sub("", line, count=1)
        if stripped.strip() and not stripped.lstrip().startswith("#"):
            kept.append(stripped)
        elif stripped is line:
            kept.append(line)  # a comment or blank line of the block, as it was
    return "\n".join(kept)


def _shim(folder: Path) -> Path:
    """A ``bin`` folder whose ``lfdkit`` runs this interpreter's ``lfdkit.app.cli``."""
    bin_dir = folder / ".readme-bin"
    bin_dir.mkdir(exist_ok=True)
    shim = bin_dir / "lfdkit"
    shim.write_text(f'#!/bin/sh\nexec {shlex.quote(sys.executable)} -m lfdkit.app.cli "$@"\n')
    shim.chmod(0o755)
    return bin_dir


#: The Python session's loop: each block (a JSON line on stdin) is run in one namespace, in
#: the run's folder; its reply is one JSON line after a token no block prints.
_SESSION = """
import contextlib, io, json, sys, traceback
token, namespace, reply = sys.argv[1], {"__name__": "__main__"}, sys.stdout
for request in sys.stdin:
    block = json.loads(request)
    out, ok = io.StringIO(), True
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        try:
            exec(compile(block["code"], "README.md:%d" % block["line"], "exec"), namespace)
        except BaseException:
            traceback.print_exc()
            ok = False
    reply.write(token + " " + json.dumps({"ok": ok, "output": out.getvalue()}) + "\\n")
    reply.flush()
"""


class _PythonSession:
    """One Python interpreter that runs the README's Python blocks in a shared namespace."""

    def __init__(self, folder: Path, env: dict[str, str]) -> None:
        self.token = f"readme-run-{secrets.token_hex(8)}"
        self.process = subprocess.Popen(
            [sys.executable, "-c", _SESSION, self.token],
            cwd=folder,
            env=env,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.STDOUT,
            text=True,
        )

    def run(self, block: Block) -> tuple[bool, str]:
        """(ran without an exception, what it printed and the traceback)."""
        assert self.process.stdin is not None and self.process.stdout is not None
        self.process.stdin.write(json.dumps({"code": block.code, "line": block.line}) + "\n")
        self.process.stdin.flush()
        printed = []  # what the interpreter wrote past the block's redirection (C level)
        for line in self.process.stdout:
            if line.startswith(self.token + " "):
                reply = json.loads(line[len(self.token) + 1 :])
                return reply["ok"], "".join(printed) + reply["output"]
            printed.append(line)
        return False, "".join(printed) + "the Python session ended"

    def close(self) -> None:
        if self.process.stdin is not None:
            self.process.stdin.close()
        try:
            self.process.wait(timeout=30)
        except subprocess.TimeoutExpired:  # pragma: no cover - a block left a thread behind
            self.process.kill()
            self.process.wait()


def run_blocks(blocks: list[Block], folder: Path, *, echo=print) -> int:
    """Run the blocks in ``folder``; 0 when all ran, 1 at the first failure (said by ``echo``)."""
    env = dict(os.environ)
    env["PATH"] = f"{_shim(folder)}{os.pathsep}{env.get('PATH', '')}"
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT / "src"), env.get("PYTHONPATH")]))
    env.setdefault("MPLBACKEND", "Agg")
    started = time.perf_counter()
    session = None
    try:
        for block in blocks:
            if block.skip is not None:
                echo(f"README.md:{block.line}: skipped ({block.skip})")
                continue
            tic = time.perf_counter()
            if block.lang == "python":
                session = session or _PythonSession(folder, env)
                ok, output = session.run(block)
                status = "an exception"
            else:
                done = subprocess.run(
                    ["bash", "-e", "-o", "pipefail", "-c", without_installs(block.code)],
                    cwd=folder,
                    env=env,
                    capture_output=True,
                    text=True,
                )
                ok, output = done.returncode == 0, done.stdout + done.stderr
                status = f"exit {done.returncode}"
            seconds = time.perf_counter() - tic
            if not ok:
                echo(f"README.md:{block.line}: FAILED ({status}, {seconds:.1f} s)")
                for line in output.strip().splitlines()[-8:]:
                    echo(f"    {line}")
                return 1
            echo(f"README.md:{block.line}: ran in {seconds:.1f} s ({block.lang})")
    finally:
        if session is not None:
            session.close()
    echo(f"every block ran, in {time.perf_counter() - started:.1f} s, in {folder}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--readme", type=Path, default=ROOT / "README.md", help="the Markdown file")
    parser.add_argument("--keep", type=Path, metavar="DIR", help="run in DIR (made, kept)")
    parser.add_argument("--list", action="store_true", help="list the blocks; run nothing")
    parser.add_argument(
        "--only", choices=("bash", "python"), help="only the shell (bash) or the Python blocks"
    )
    args = parser.parse_args(argv)
    blocks = readme_blocks(args.readme.read_text(encoding="utf-8"))
    if args.only is not None:
        blocks = [block for block in blocks if block.lang == args.only]
    if args.list:
        for block in blocks:
            status = f"skipped ({block.skip})" if block.skip else "runs"
            first = block.code.strip().splitlines()[0] if block.code.strip() else ""
            print(f"README.md:{block.line}: {block.lang}: {status}: {first}")
        return 0
    if args.keep is not None:
        args.keep.mkdir(parents=True, exist_ok=True)
        return run_blocks(blocks, args.keep.resolve())
    with tempfile.TemporaryDirectory(prefix="lfdkit-readme-") as folder:
        return run_blocks(blocks, Path(folder))


if __name__ == "__main__":
    raise SystemExit(main())
