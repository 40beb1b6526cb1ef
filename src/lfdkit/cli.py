"""The ``lfdkit`` command.

Exit codes: 0 success, 1 the work failed (the reason on stderr in one line),
2 wrong usage (argparse). Progress goes to stderr; ``--quiet`` prints nothing on
success.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from lfdkit import __version__

__all__ = ["main"]


class CommandError(Exception):
    """A failure to report on one line, with exit code 1."""


def _say(args: argparse.Namespace, message: str, *, level: int = 1) -> None:
    """Progress on stderr: level 1 is shown by default, level 2 only with --verbose."""
    if args.verbosity >= level:
        print(message, file=sys.stderr, flush=True)


def _demo(args: argparse.Namespace) -> None:
    # Heavy imports here so that `lfdkit --help` stays instant.
    from lfdkit.datasets import MIMIC_DATASETS
    from lfdkit.demos import atomic_write
    from lfdkit.evaluation import (
        LFDKIT_METHODS,
        comparison_figures,
        format_table,
        run_comparison,
        summarize,
    )

    out: Path = args.output
    if out.exists() and not out.is_dir():
        raise CommandError(f"--output {out}: exists and is not a directory")
    names = args.datasets or list(MIMIC_DATASETS)
    unknown = [n for n in names if n not in MIMIC_DATASETS]
    if unknown:
        raise CommandError(
            f"--datasets: unknown {unknown[0]!r}; choose from {', '.join(MIMIC_DATASETS)}"
        )
    planned = [out / "mimic_table.txt", out / "mimic.json"]
    planned += [out / f"{n}.png" for n in names] + [out / f"{n}_mean_path.png" for n in names]
    clash = [p for p in planned if p.exists()]
    if clash and not args.force:
        raise CommandError(f"{clash[0]} exists; pass --force to overwrite the demo's files")
    out.mkdir(parents=True, exist_ok=True)

    total = len(names) * len(LFDKIT_METHODS)
    count = [0]
    started = time.perf_counter()

    def progress(run) -> None:
        count[0] += 1
        detail = f"failed: {run.error}" if run.error else f"{run.runtime_s * 1000:.0f} ms"
        _say(args, f"[{count[0]:>2}/{total}] {run.dataset:<20} {run.method:<20} {detail}")

    _say(args, f"lfdkit {__version__}: comparing generalized paths on {len(names)} data sets")
    runs = run_comparison(names, [args.seed], LFDKIT_METHODS, on_result=progress)
    rows = summarize(runs)
    table = format_table(rows)

    def save_figure(fig, path: Path) -> None:
        atomic_write(
            path, lambda f: fig.savefig(f, format="png", dpi=110), binary=True, overwrite=args.force
        )
        _say(args, f"wrote {path}", level=2)

    for filename, fig in comparison_figures(runs, seed=args.seed):
        save_figure(fig, out / filename)
    atomic_write(out / "mimic_table.txt", lambda f: f.write(table + "\n"), overwrite=args.force)
    payload = {"seed": args.seed, "summary": rows, "runs": [r.record() for r in runs]}
    atomic_write(
        out / "mimic.json", lambda f: json.dump(payload, f, indent=1), overwrite=args.force
    )
    if args.verbosity >= 1:
        print(table)
        _say(args, f"done in {time.perf_counter() - started:.1f} s; results in {out}/")


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="lfdkit",
        description="Robot learning from demonstration: mimic, imitate, emulate, execute.",
    )
    parser.add_argument("--version", action="version", version=f"lfdkit {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    demo = sub.add_parser(
        "demo",
        help="run the main example and write figures and a table",
        description="Compare Mean-Path, GMR, NLPCA and the arc-length average on the built-in "
        "data sets (known ground truth); write one figure per data set, a table and JSON.",
    )
    demo.add_argument(
        "-o",
        "--output",
        type=Path,
        default=Path("lfdkit-demo"),
        help="output directory (default: ./lfdkit-demo)",
    )
    demo.add_argument("--datasets", nargs="+", metavar="NAME", help="subset of data sets")
    demo.add_argument("--seed", type=int, default=0, help="data set seed (default 0)")
    demo.add_argument("-f", "--force", action="store_true", help="overwrite existing output files")
    loud = demo.add_mutually_exclusive_group()
    loud.add_argument(
        "-q",
        "--quiet",
        dest="verbosity",
        action="store_const",
        const=0,
        help="print nothing on success",
    )
    loud.add_argument(
        "-v",
        "--verbose",
        dest="verbosity",
        action="store_const",
        const=2,
        help="also list every file written",
    )
    demo.set_defaults(verbosity=1, handler=_demo)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``lfdkit`` console script; returns the exit code."""
    args = _parser().parse_args(argv)
    try:
        args.handler(args)
    except CommandError as exc:
        print(f"lfdkit {args.command}: error: {exc}", file=sys.stderr)
        return 1
    except (OSError, ValueError) as exc:
        print(f"lfdkit {args.command}: error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
