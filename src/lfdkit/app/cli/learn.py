"""``lfdkit learn``: a skill from demonstration files."""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

from lfdkit.app.cli.common import (
    CommandError,
    add_skill_param_options,
    elapsed,
    refuse_existing,
    skill_params,
    tell,
    working,
)

__all__ = ["add_options", "run_command"]


def run_command(args: argparse.Namespace) -> None:
    refuse_existing(args.output, args.force)
    with warnings.catch_warnings(record=True) as caught, working(args) as progress:
        warnings.simplefilter("always", UserWarning)
        with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn, numba)"):
            from lfdkit.skill import learn
        skill = learn(args.demos, args.scenes, progress=progress, **skill_params(args))
    fit = skill.ioc_info_ or {}
    if not fit.get("converged", True):
        raise CommandError(
            f"the obstacle reward fit did not converge ({fit['convergence_message']}); "
            "wrote nothing. Check the units and that each obstacle demonstration follows "
            "the path around its scene's obstacles, add demonstrations, or try --planner full"
        )
    for warning in caught:  # shown once each, after the fit, as main's handler shows them
        warnings.showwarning(warning.message, warning.category, warning.filename, warning.lineno)
    skill.save(args.output, overwrite=args.force)
    if args.verbosity >= 1:
        classes = ", ".join(skill.reward_.classes) if skill.reward_ is not None else "none"
        tell(
            args,
            f"learned from {skill.mimic_info_['n_demos']} clean demonstrations"
            + (f" and {skill.ioc_info_['n_demos']} around obstacles" if skill.ioc_info_ else "")
            + f" (obstacle classes: {classes}; lengths in {skill.units}) in "
            f"{elapsed(args):.1f} s; wrote {args.output}",
        )


def add_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "demos", type=Path, metavar="DEMOS", help="demonstrations (.csv, .npz or .json)"
    )
    parser.add_argument(
        "--scenes",
        type=Path,
        metavar="SCENES",
        help="obstacles of the obstacle demonstrations, by demo id (.csv or .json)",
    )
    parser.add_argument(
        "-o", "--output", type=Path, required=True, metavar="SKILL.json", help="skill file to write"
    )
    add_skill_param_options(parser)
