"""``lfdkit compare``: the mimicking methods on the built-in data sets."""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from lfdkit import __version__
from lfdkit.app.cli.common import (
    CommandError,
    add_output_folder_option,
    add_seed_option,
    add_units_option,
    check_writable,
    tell,
    working,
)

__all__ = ["add_options", "run_command"]


def run_command(args: argparse.Namespace) -> None:
    # Heavy imports here so that `lfdkit --help` stays instant.
    from lfdkit.app.evaluation import (
        comparison_figures,
        format_table,
        lfdkit_methods,
        run_comparison,
        summarize,
    )
    from lfdkit.datasets import MIMIC_DATASETS
    from lfdkit.io import atomic_write

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
        raise CommandError(f"--output {out}: {clash[0]} exists; pass --force to overwrite it")
    out.mkdir(parents=True, exist_ok=True)
    check_writable(out, "--output", out)

    methods = lfdkit_methods()
    total = len(names) * len(methods)
    started = time.perf_counter()
    tell(args, f"lfdkit {__version__}: comparing generalized paths on {len(names)} data sets")
    with working(args) as progress:
        label = f"{len(methods)} methods on {len(names)} data sets"
        with progress.stage(label, total=total, unit="fit") as stage:

            def advance(run) -> None:
                detail = f"failed: {run.error}" if run.error else f"{run.runtime_s * 1000:.0f} ms"
                stage.advance(detail=f"{run.dataset} {run.method}: {detail}")

            runs = run_comparison(names, [args.seed], methods, on_result=advance, units=args.units)
    rows = summarize(runs)
    table = format_table(rows)

    def save_figure(fig, path: Path) -> None:
        atomic_write(
            path, lambda f: fig.savefig(f, format="png", dpi=110), binary=True, overwrite=args.force
        )
        tell(args, f"wrote {path}", level=2)

    for filename, fig in comparison_figures(runs, seed=args.seed):
        save_figure(fig, out / filename)
    atomic_write(out / "mimic_table.txt", lambda f: f.write(table + "\n"), overwrite=args.force)
    payload = {
        "seed": args.seed,
        "units": args.units,
        "summary": rows,
        "runs": [r.record() for r in runs],
    }
    atomic_write(
        out / "mimic.json", lambda f: json.dump(payload, f, indent=1), overwrite=args.force
    )
    if args.verbosity >= 1:
        print(table)
        tell(args, f"done in {time.perf_counter() - started:.1f} s; results in {out}/")


def add_options(parser: argparse.ArgumentParser) -> None:
    add_output_folder_option(parser, "lfdkit-compare")
    parser.add_argument("--datasets", nargs="+", metavar="NAME", help="subset of data sets")
    add_seed_option(parser, 0, "data set seed (default 0)")
    add_units_option(
        parser,
        None,
        "unit of the table's lengths and of the figures (default: each data set's own; the "
        "methods always run on the data as generated)",
    )
