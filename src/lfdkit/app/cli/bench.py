"""``lfdkit bench``: the benchmarks of a folder or the source checkout."""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

from lfdkit.app.cli.common import (
    CommandError,
    UsageError,
    tell,
)

__all__ = ["add_options", "run_command"]


def _benchmarks_folder(given: Path | None) -> Path:
    """``--benchmarks``, else ./benchmarks, else the source checkout's (an editable install)."""
    if given is not None:
        if not given.is_dir():
            raise UsageError(f"--benchmarks {given}: no such folder")
        return given
    checkout = Path(__file__).resolve().parents[4]
    places = [Path("benchmarks")]
    if (checkout / "pyproject.toml").is_file():  # not in an installed package
        places.append(checkout / "benchmarks")
    for folder in places:
        if folder.is_dir():
            return folder
    looked = " or ".join(str(folder.resolve()) for folder in places)
    raise UsageError(
        f"no benchmarks folder: looked for {looked}; pass --benchmarks DIR, or run from a "
        "source checkout of lfdkit"
    )


def run_command(args: argparse.Namespace) -> None:
    folder = _benchmarks_folder(args.benchmarks)
    # A benchmark is a script NAME.py or a package NAME/ with a __main__.py.
    scripts = {p.stem: p for p in folder.glob("*.py")}
    scripts.update({p.parent.name: p.parent for p in folder.glob("*/__main__.py")})
    available = sorted(name for name in scripts if not name.startswith("_"))
    names = args.names or available
    unknown = [n for n in names if n not in available]
    if unknown:
        raise CommandError(f"unknown benchmark {unknown[0]!r}; choose from {', '.join(available)}")
    for name in names:
        command = [sys.executable, str(scripts[name])]
        if args.quick:
            command.append("--quick")
        tell(args, f"lfdkit bench: {' '.join(command[1:])}")
        done = subprocess.run(
            command,
            cwd=folder.resolve().parent,
            stdout=subprocess.DEVNULL if args.verbosity < 1 else None,
        )
        if done.returncode != 0:
            raise CommandError(f"benchmark {name} failed with exit code {done.returncode}")


def add_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("names", nargs="*", metavar="NAME", help="benchmarks (default all)")
    parser.add_argument(
        "--benchmarks",
        type=Path,
        metavar="DIR",
        help="the benchmarks folder (default: ./benchmarks, else the source checkout's)",
    )
    parser.add_argument("--quick", action="store_true", help="smaller, faster runs")
