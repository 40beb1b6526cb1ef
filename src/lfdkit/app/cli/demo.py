"""``lfdkit demo``: the whole workflow on the built-in sweeping example."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

from lfdkit import __version__
from lfdkit.app.cli.common import (
    CommandError,
    add_output_folder_option,
    check_writable,
    tell,
    working,
)

__all__ = ["add_options", "run_command"]


def run_command(args: argparse.Namespace) -> None:
    with working(args) as progress:
        with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn, numba, MuJoCo)"):
            from lfdkit.tasks.sweeping.demo import demo_outputs, run_demo
        out = _demo_folder(args, demo_outputs)
        title = "the sweeping example, from demonstrations to new scenes"
        tell(args, f"lfdkit {__version__}: {title}")
        results = run_demo(out, overwrite=args.force, progress=progress, started=args.started)
    if args.verbosity >= 1:
        test = results["emulate"]["test"]
        unseen = [r for r in results["unseen"] if r["planner"] == "learned reward"]
        print(
            f"held-out sweeps: Pr {test['improvement']:.1f} % over replaying the nominal; "
            f"unseen scenes: {sum(r['collisions'] for r in unseen)} collisions in {len(unseen)}"
        )
        print(f"simulated UR5 sweep (MuJoCo): {results['execution']['summary']}")
        # The report's whole-run time: the same clock, from the command's start.
        total = results["seconds"]["total"]
        tell(args, f"done in {total:.1f} s; open {out / 'report.html'}")


def _demo_folder(args: argparse.Namespace, demo_outputs: Callable[[Path], list[Path]]) -> Path:
    """``--output`` of ``demo``, checked before the work: a folder, writable, no clash."""
    out: Path = args.output
    if out.exists() and not out.is_dir():
        raise CommandError(f"--output {out}: exists and is not a directory")
    clash = [p for p in demo_outputs(out) if p.exists()]
    if clash and not args.force:
        raise CommandError(f"--output {out}: {clash[0]} exists; pass --force to overwrite it")
    # The demo writes into a sibling folder and moves it into place at the end.
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise CommandError(
            f"--output {out}: cannot create folder {out.parent} ({exc.strerror or exc})"
        ) from None
    check_writable(out.parent, "--output", out)
    if out.is_dir():
        check_writable(out, "--output", out)
    return out


def add_options(parser: argparse.ArgumentParser) -> None:
    add_output_folder_option(parser, "lfdkit-demo")
