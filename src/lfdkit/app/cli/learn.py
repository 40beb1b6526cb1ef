"""``lfdkit learn``: a skill from demonstration files."""

from __future__ import annotations

import argparse
import warnings
from pathlib import Path

from lfdkit.app.behaviour import side_words, slow_return_words
from lfdkit.app.cli import periodic, task_frames
from lfdkit.app.cli.common import (
    CommandError,
    add_skill_param_options,
    elapsed,
    refuse_existing,
    skill_params,
    tell,
    units_refusal,
    working,
)
from lfdkit.core.options import DEMONSTRATION_SPEED, POOR_FIDELITY, SKILL_DEFAULTS
from lfdkit.core.units import UnitsWarning

__all__ = ["add_options", "run_command", "timing_line"]


def run_command(args: argparse.Namespace) -> None:
    if args.task_frames:
        task_frames.learn(args)
        return
    task_frames.refuse_learn_options(args)
    if args.periodic:
        periodic.learn(args)
        return
    periodic.refuse_learn_options(args)
    refuse_existing(args.output, args.force)
    # Named in messages: the file, or the files (one demonstration each, as a recorder writes).
    source = args.demos[0] if len(args.demos) == 1 else f"{args.demos[0]} (and {_others(args)})"
    with warnings.catch_warnings(record=True) as caught, working(args) as progress:
        warnings.simplefilter("always", UserWarning)
        if args.units is None:  # implausible in metres and no unit given: refused, not learned
            warnings.simplefilter("error", UnitsWarning)
        with progress.stage("load lfdkit (NumPy, SciPy, scikit-learn, numba)"):
            from lfdkit.skill import learn
        try:
            skill = learn(args.demos, args.scenes, progress=progress, **skill_params(args))
        except UnitsWarning as exc:
            raise CommandError(units_refusal(source, exc, SKILL_DEFAULTS["units"])) from None
    fit = skill.ioc_info_ or {}
    if not fit.get("converged", True):  # one line, with what the warnings said would help
        said = [
            str(w.message).splitlines()[0]
            for w in caught
            if str(w.message) and not str(w.message).startswith("the reward fit did not")
        ]
        raise CommandError(
            f"the obstacle reward fit did not converge ({fit['convergence_message']}); "
            "wrote nothing. "
            + "".join(f"{text[0].upper()}{text[1:]}. " for text in said)
            + "Check the units and that each obstacle demonstration follows "
            "the path around its scene's obstacles, add demonstrations, or try --planner full"
        )
    for warning in caught:  # shown once each, after the fit, as main's handler shows them
        message = warning.message
        if isinstance(message, UnitsWarning):  # --units m given: learned, but said, as options
            message = UnitsWarning(
                f"{source}: {message.detail}: if that is their unit, pass --units {message.likely}"
            )
        warnings.showwarning(message, warning.category, warning.filename, warning.lineno)
    skill.save(args.output, overwrite=args.force)
    if args.verbosity >= 1:
        classes = ", ".join(skill.reward_.classes) if skill.reward_ is not None else "none"
        clean = skill.mimic_info_["n_demos"]
        around = skill.ioc_info_["n_demos"] if skill.ioc_info_ else 0
        tell(
            args,
            f"learned from {clean} clean demonstration{'s' * (clean != 1)}"
            + (f" and {around} around obstacles" if skill.ioc_info_ else "")
            + f" (obstacle classes: {classes}; lengths in {skill.units}) in "
            f"{elapsed(args):.1f} s; wrote {args.output}",
        )
    timing = timing_line(skill)
    if timing:
        tell(args, timing)
    for line in _fidelity_lines(skill):
        tell(args, line)


def _others(args: argparse.Namespace) -> str:
    """The other demonstration files, counted: "1 other file", "3 other files"."""
    n = len(args.demos) - 1
    return f"{n} other file{'s' * (n != 1)}"


def timing_line(skill: Skill) -> str:  # noqa: F821 (imported lazily)
    """What the skill's duration is and where it came from: said, since a robot will run it."""
    from lfdkit.core.geometry import path_length

    timing = skill.timing_
    length = path_length(skill.path_)
    speed = length / timing.duration
    moves = (
        f"{timing.duration:.3g} s for the {length:.3g} {skill.units} path "
        f"({speed:.3g} {skill.units}/s on average)"
    )
    if timing.source not in ("minimum_jerk", "uniform"):
        return f"timing learned from the demonstrations' times: {moves}"
    if skill.duration == "auto":
        return (
            f"the demonstrations carry no times: assumed {timing.duration:.3g} s for the "
            f"{length:.3g} {skill.units} path, a hand's typical demonstration pace "
            f"({DEMONSTRATION_SPEED:g} m/s on average); set it with --duration S here, or "
            "--duration/--speed on plan"
        )
    return f"the demonstrations carry no times: {moves}, as --duration gave"


_ROUTE_NAMES = {
    "lookahead": "MPC with lookahead along the global route",
    "window": "the thesis's MPC (each window's best)",
    "full": "the full-horizon optimum",
    "taut": "the shortest path round the obstacles",
}
_FLOOR_NAMES = {
    "demonstrated": "keeping the clearance the demonstrations kept",
    "closest": "keeping the closest clearance any demonstration kept",
    "typical": "keeping the clearance the demonstrations typically kept",
}


def _behaviour(name: str, row: dict) -> str:
    """A behaviour model in words (files before floors and frames name only the route)."""
    words = _ROUTE_NAMES[row.get("route", name)]
    floor = row.get("floor", "none")
    if floor != "none":
        words += f", {_FLOOR_NAMES[floor]}"
    if row.get("swerve") == "learned":
        words += ", swerve shaped along the path (early/late, steep/slow)"
    if row.get("return") == "slow":
        words += ", with a slow return"
    if row.get("frame", "world") == "path":  # the responses turn with the motion
        words += ", in the path frame"
    return words


def _fidelity_lines(skill: Skill) -> list[str]:  # noqa: F821 (imported lazily)
    """The model chosen, and one line per obstacle demonstration replanned badly (issue 26)."""
    selection = getattr(skill, "model_selection_", None)
    if not selection:
        return []
    held_out = selection.get("cross_validated", False)
    kind = "cross-validated" if held_out else "training replanning"

    def scores(name: str) -> str:
        row = selection["candidates"][name]
        if row["improvement_median"] is None:
            return "no scene planned"
        return (
            f"{kind} Pr median {row['improvement_median']:.0f} %, mean "
            f"{row['improvement_mean']:.0f} %, sides kept in {row['sides_agree']:.0%}"
        )

    chosen, runner = selection["chosen"], selection["runner_up"]
    candidates = selection["candidates"]
    line = f"obstacle behaviour planned with {_behaviour(chosen, candidates[chosen])}"
    line += f" ({scores(chosen)})"
    if candidates[chosen].get("return") == "slow":
        fit = getattr(skill, "ioc_info_", None) or {}
        slow = slow_return_words(
            float(getattr(skill, "return_fraction_", 1.0)),
            fit.get("demonstrated_return"),
            float(skill.max_slope),
            skill.units,
        )
        if slow is not None:
            line += f"; {slow}"
    if runner is not None:
        line += f"; runner-up {_behaviour(runner, candidates[runner])} ({scores(runner)})"
    median = candidates[chosen]["improvement_median"]
    if held_out and median is not None and median < POOR_FIDELITY:
        line += (
            f"; POOR: held-out demonstrations are emulated at {median:.0f} % "
            f"(below {POOR_FIDELITY:.0f} %)"
        )
    lines = [line]
    if skill.clearances_:
        kept = ", ".join(f"{c} {m:.3g} {skill.units}" for c, m in skill.clearances_.items())
        line = f"plans keep at least the clearance the demonstrations kept: {kept}"
        if getattr(skill, "gaps_", "closed") == "open":
            line += " (less between two obstacles closer than that: the gap stays open)"
        if selection.get("gaps_shown") == 0:
            line += (
                "; no demonstration passed two close obstacles, so whether to pass between "
                "them is a guess"
            )
        lines.append(line)
    sides = getattr(skill, "side_preferences_", {})
    if sides:
        lines.append(
            "plans keep the sides the demonstrations kept, the long way round where needed: "
            + side_words(sides, skill.units)
        )
    for row in skill.training_fidelity_ or []:
        name = f"obstacle demonstration {row.get('id', row['demo'])!r}"
        if "refused" in row:
            lines.append(f"{name}: no plan in its own scene ({row['refused']})")
            continue
        faults = []
        if row["improvement"] < 0.0:
            faults.append(f"replanned worse than its nominal (Pr {row['improvement']:.0f} %)")
        if not row["sides_agree"]:
            faults.append(f"passes {row['other_side']} obstacle(s) on the other side")
        if faults:
            lines.append(f"{name}: " + " and ".join(faults))
    return lines


def add_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "demos",
        type=Path,
        nargs="+",
        metavar="DEMOS",
        help="demonstrations: CSV files with a header row and one row per sample, columns "
        "x,y[,z] (or x1,x2,...; lengths in --units), optionally demo (the demonstration's id; "
        "without it the file is one demonstration, named by the file's stem), t or time "
        "(seconds, increasing; untimed demonstrations get a hand's pace), qx,qy,qz,qw (the "
        "tool's orientation, a unit quaternion); or .npz or .json (lfdkit.io.save_demos). "
        "Several files (one demonstration each, as a recorder writes them) are one set",
    )
    parser.add_argument(
        "--scenes",
        type=Path,
        metavar="SCENES",
        help="obstacles of the obstacle demonstrations, by demo id (.csv with columns "
        "demo,class,x,y[,z][,radius], or .json); a demonstration it does not list is clean",
    )
    parser.add_argument(
        "-o", "--output", type=Path, required=True, metavar="SKILL.json", help="skill file to write"
    )
    add_skill_param_options(parser)
    periodic.add_learn_options(parser)
    task_frames.add_learn_options(parser)
