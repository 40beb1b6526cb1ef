"""Runner of the emulation benchmark: options, the sections in order, the JSON record."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

from _common import git_state, json_ready, machine_info, package_versions
from threadpoolctl import threadpool_limits

from lfdkit.datasets.emulation import load_emulation_dataset

from . import __doc__ as BENCHMARK_DOC
from .baseline import dmp_baseline, print_dmp
from .common import held_out_names, nominal_variants, progress, reward_record
from .evaluation import evaluate, print_evaluation
from .figures import baseline_figure, heldout_figure, reward_figures, transfer_figure
from .recovery import fit_and_recover, noise_free_fits, print_fits
from .spec import DATASETS, DMP_DT, DMP_WEIGHTS, HORIZON, SPEED_HORIZON, THESIS, VARIANTS
from .speed import print_speed, speed
from .targets import check_targets, print_targets
from .transfer import composition_transfer, print_composition


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="benchmarks/emulate", description=BENCHMARK_DOC.splitlines()[0]
    )
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).resolve().parents[1] / "results" / "emulate"
    )
    parser.add_argument(
        "--quick",
        action="store_true",
        help="smoke run: nominal 'free' (else 'train') only, max_iter 2, no train MSE_R, "
        "small DMP grid, 1 fit round, SciPy limit 5 s, no finite-difference staged fit",
    )
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--datasets", nargs="*", default=list(DATASETS), metavar="NAME")
    parser.add_argument("--fit-repeats", type=int, default=None, help="fit rounds (default 3)")
    parser.add_argument("--repeats", type=int, default=None, help="planning rounds (default 15)")
    parser.add_argument("--scipy-limit", type=float, default=None, help="s per stage (120)")
    parser.add_argument("--figure-nominal", choices=VARIANTS, default="free")
    args = parser.parse_args(argv)
    quick = args.quick
    fit_repeats = args.fit_repeats or (1 if quick else 3)
    repeats = args.repeats or (3 if quick else 15)
    limit_s = args.scipy_limit or (5.0 if quick else 120.0)
    max_iter = 2 if quick else 200
    args.output.mkdir(parents=True, exist_ok=True)
    wall = time.perf_counter()

    with threadpool_limits(limits=1):
        progress("data sets and nominal paths ...")
        sets = {name: load_emulation_dataset(name, args.seed) for name in args.datasets}
        figure_variant = args.figure_nominal
        if figure_variant == "free" and not all(
            getattr(es, "free_demos", None) for es in sets.values()
        ):
            figure_variant = "train"
        include = (figure_variant,) if quick else VARIANTS
        variants = {name: nominal_variants(es, include) for name, es in sets.items()}
        for name, vs in variants.items():
            for variant, info in vs.items():
                progress(
                    f"   {name} / {variant}: {info['source']}, max deviation from the true "
                    f"nominal {info['deviation_max'] * 1e3:.1f} mm"
                )

        progress("1. fits ...")
        fits = fit_and_recover(sets, variants, max_iter)
        noise_free = [] if quick else noise_free_fits(list(sets), args.seed, max_iter)
        print_fits(fits, sets, noise_free)
        print("  nominal paths (deviation from the true nominal, max/mean mm):")
        for name, vs in variants.items():
            print(
                f"    {name:<16} "
                + "; ".join(
                    f"{v}: {i['deviation_max'] * 1e3:.1f}/{i['deviation_mean'] * 1e3:.1f}"
                    for v, i in vs.items()
                )
            )

        progress("2. evaluation ...")
        test_rows, held_rows = evaluate(sets, variants, fits, train_mse=not quick)
        print_evaluation(test_rows, held_rows)

        progress("3. DMP baseline ...")
        dmp_rows = dmp_baseline(sets, variants, test_rows, quick)
        print_dmp(dmp_rows)

        progress("4. speed ...")
        speed_result = speed(fit_repeats, repeats, quick, limit_s, sets.get("da_vinci_marker"))
        print_speed(speed_result)

        progress("5. composition and transfer ...")
        comp = composition_transfer(sets, variants, fits, figure_variant)
        print_composition(comp)

        progress("figures ...")
        figures = reward_figures(sets, variants, fits, test_rows, args.output)
        for name in (
            heldout_figure(sets, variants, fits, held_rows, figure_variant, args.output),
            transfer_figure(comp, args.output),
            baseline_figure(sets, variants, fits, dmp_rows, figure_variant, args.output),
        ):
            if name:
                figures.append(name)

    checks = check_targets(fits, test_rows, held_rows, dmp_rows, speed_result)
    print_targets(checks)
    wall = time.perf_counter() - wall
    print(f"\nwall time {wall:.1f} s")

    result = {
        "benchmark": "emulate",
        "created": time.strftime("%Y-%m-%dT%H:%M:%S"),
        "command": [sys.executable, *sys.argv] if argv is None else ["emulate", *argv],
        "quick": quick,
        "seed": args.seed,
        "machine": machine_info(),
        "versions": package_versions(
            ("lfdkit", "numpy", "scipy", "numba", "matplotlib", "movement_primitives")
        ),
        "git": git_state(),
        "wall_time_s": wall,
        "settings": {
            "horizon": HORIZON,
            "speed_horizon": SPEED_HORIZON,
            "max_iter": max_iter,
            "fit_repeats": fit_repeats,
            "repeats": repeats,
            "scipy_limit_s": limit_s,
            "figure_nominal": figure_variant,
            "dmp": {"n_weights_per_dim": DMP_WEIGHTS, "dt": DMP_DT, "execution_time": 1.0},
        },
        "thesis": THESIS,
        "datasets": {
            name: {
                "n_demos": es.n_demos,
                "n_dims": es.n_dims,
                "train": es.train,
                "test": es.test,
                "true_reward": reward_record(es.true_reward),
                "held_out": held_out_names(name, len(es.held_out_scenes)),
                "nominals": {
                    v: {k: i[k] for k in ("source", "warnings", "deviation_max", "deviation_mean")}
                    for v, i in variants[name].items()
                },
            }
            for name, es in sets.items()
        },
        "fits": fits,
        "noise_free_fits": noise_free,
        "test": test_rows,
        "held_out": held_rows,
        "dmp_baseline": dmp_rows,
        "speed": speed_result,
        "composition_transfer": comp,
        "figures": figures,
        "targets": checks,
    }
    out = args.output / "emulate.json"
    out.write_text(
        json.dumps(json_ready(result, drop=("ioc", "scene_obj", "reward_obj")), indent=1)
    )
    progress(f"\nwrote {out} and figures in {args.output}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
