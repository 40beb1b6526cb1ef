"""Compare generalized-path methods on data sets with known ground truth.

Used by ``lfdkit demo`` and by ``benchmarks/mimic.py`` (which adds the peer
libraries as further methods). Every estimate is resampled to the same number
of points evenly in arc length before it is scored, so that sums over points
(e1, e2) compare like with like.

Lengths are reported in each data set's own unit (``"m"``, or ``"mm"`` for
the deburring and handwriting sets) unless a comparison asks for one unit for
all (``units=``): the methods always run on the data as generated, and their
scores and paths are converted (e1 in units², e2 and penetration in units).
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field, fields, replace

import numpy as np
from matplotlib.figure import Figure

from lfdkit.app.plot import comparison_figure, mean_path_figure
from lfdkit.core.geometry import resample
from lfdkit.core.units import check_units, conversion_factor
from lfdkit.datasets import DemoSet, load_dataset
from lfdkit.emulate import metrics
from lfdkit.mimic import (
    GMR,
    MIMIC_METHODS,
    ComponentLimitWarning,
    MeanPath,
    MimicMethod,
    MimicSettings,
    select_n_components,
)

__all__ = [
    "MethodRun",
    "comparison_figures",
    "format_table",
    "gmr_components",
    "lfdkit_methods",
    "run_comparison",
    "summarize",
]

#: A method takes a data set and a seed and returns a generalized path (m, q).
Method = Callable[[DemoSet, int], np.ndarray]

#: Penetration below this depth is below any machining precision (1 µm).
PENETRATION_TOLERANCE = {"mm": 1e-3, "cm": 1e-4, "m": 1e-6}

#: Candidate numbers of Gaussian components, chosen per data set by BIC.
GMR_CANDIDATES = (4, 8, 12, 16, 24, 32)


_COMPONENTS: dict[tuple[str, int], int] = {}


def gmr_components(demoset: DemoSet, seed: int) -> int:
    """Number of GMM components for a data set, chosen by BIC (no ground truth used).

    Remembered per (data set, seed) so that the peers compared with lfdkit's GMR
    use the same number without choosing it again.
    """
    key = (demoset.name, seed)  # the generators are deterministic in the seed
    if key not in _COMPONENTS:
        with warnings.catch_warnings():
            # The candidates are this comparison's fixed design: their largest is its cap.
            warnings.simplefilter("ignore", ComponentLimitWarning)
            _COMPONENTS[key] = select_n_components(
                demoset.demos, GMR_CANDIDATES, random_state=seed
            )[0]
    return _COMPONENTS[key]


def _registered(method: MimicMethod) -> Method:
    """A registered method run on a data set: 100 points, the seed, components by BIC."""

    def run(demoset: DemoSet, seed: int) -> np.ndarray:
        settings = MimicSettings(n_points=100, random_state=seed)
        if "n_components" in method.uses:
            settings = replace(settings, n_components=gmr_components(demoset, seed))
        return method.build(settings).fit(demoset.demos).path_

    return run


def lfdkit_methods() -> dict[str, Method]:
    """lfdkit's own methods, every one registered now, by display name.

    Each runs with 100 points and the data set's seed; a method with a number
    of components (:attr:`MimicMethod.uses`) gets it by BIC (:func:`gmr_components`).
    """
    return {m.label: _registered(m) for m in MIMIC_METHODS.values()}


@dataclass
class MethodRun:
    """One method on one data set with one seed.

    ``e1`` is in ``units`` squared, ``e2`` and ``penetration`` in ``units``,
    ``path`` (n, q) in ``units``, ``runtime_s`` in seconds.
    """

    dataset: str
    method: str
    seed: int
    e1: float
    e2: float
    penetration: float | None
    runtime_s: float
    path: np.ndarray = field(repr=False)
    error: str | None = None
    units: str = "m"

    def record(self) -> dict:
        """JSON-ready dictionary: every field but the path, in field order."""
        return {f.name: getattr(self, f.name) for f in fields(self) if f.name != "path"}


def run_comparison(
    datasets: Sequence[str],
    seeds: Iterable[int],
    methods: dict[str, Method],
    *,
    n_points: int = 100,
    on_result: Callable[[MethodRun], None] | None = None,
    units: str | None = None,
) -> list[MethodRun]:
    """Run every method on every data set and seed and score it.

    Parameters
    ----------
    datasets : sequence of str
        Names known to :func:`lfdkit.datasets.load_dataset`.
    seeds : iterable of int
        One data set instance per seed (the method gets the same seed).
    methods : dict
        Display name → method.
    n_points : int
        Points of the resampled estimate and of the nominal for e1/e2.
    on_result : callable, optional
        Called after each run (progress display).
    units : {"m", "cm", "mm"}, optional
        Unit of the scores and paths returned (default: each data set's own).
        The methods run on the data as generated either way.

    Returns
    -------
    list of MethodRun
        A method that raises is recorded with NaN scores and its error message.
    """
    if units is not None:
        check_units(units)
    runs = []
    for name in datasets:
        for seed in seeds:
            demoset = load_dataset(name, seed=seed)
            shown = demoset.units if units is None else units
            for method, fn in methods.items():
                start = time.perf_counter()
                try:
                    path = np.asarray(fn(demoset, seed), dtype=float)
                    elapsed = time.perf_counter() - start
                    run = _score(demoset, method, seed, path, elapsed, n_points, shown)
                except Exception as exc:
                    run = MethodRun(
                        name,
                        method,
                        seed,
                        np.nan,
                        np.nan,
                        None,
                        np.nan,
                        np.empty((0, demoset.nominal.shape[1])),
                        f"{type(exc).__name__}: {exc}",
                        shown,
                    )
                runs.append(run)
                if on_result is not None:
                    on_result(run)
    return runs


def _score(demoset, method, seed, path, elapsed, n_points, units) -> MethodRun:
    """Scores in the data set's units, reported in ``units``."""
    factor = conversion_factor(demoset.units, units)
    estimate = resample(path, n_points)
    depth = None
    if demoset.material_side is not None:
        depth = metrics.penetration(
            estimate,
            demoset.nominal,
            demoset.material_side,
            tolerance=PENETRATION_TOLERANCE[demoset.units],
        )[0]
    return MethodRun(
        dataset=demoset.name,
        method=method,
        seed=seed,
        e1=factor**2 * metrics.e1(estimate, demoset.demos),
        e2=factor * metrics.e2(estimate, demoset.nominal, n_points=n_points),
        penetration=None if depth is None else factor * depth,
        runtime_s=elapsed,
        path=factor * path,
        units=units,
    )


def summarize(runs: Sequence[MethodRun]) -> list[dict]:
    """Mean and standard deviation over seeds per (data set, method), in run order.

    Each row has the runs' ``units`` (e1 in units², e2 and penetration in units).
    """
    groups: dict[tuple[str, str], list[MethodRun]] = {}
    for run in runs:
        groups.setdefault((run.dataset, run.method), []).append(run)
    rows = []
    for (dataset, method), items in groups.items():
        e1 = np.array([r.e1 for r in items])
        e2 = np.array([r.e2 for r in items])
        pen = [r.penetration for r in items if r.penetration is not None]
        rows.append(
            {
                "dataset": dataset,
                "method": method,
                "units": items[0].units,
                "n_seeds": len(items),
                "e1_mean": float(np.mean(e1)),
                "e1_sd": float(np.std(e1)),
                "e2_mean": float(np.mean(e2)),
                "e2_sd": float(np.std(e2)),
                "penetration_max": float(np.max(pen)) if pen else None,
                "runtime_s_median": float(np.median([r.runtime_s for r in items])),
                "errors": sorted({r.error for r in items if r.error}),
            }
        )
    return rows


def format_table(rows: Sequence[dict]) -> str:
    """Plain-text table of :func:`summarize` rows, one block per data set.

    The ``units`` column gives each block's unit: e1 is in units², e2 and
    the penetration in units.
    """
    header = (
        f"{'data set':<20} {'units':<5} {'method':<22} {'e1 [units²]':>18} {'e2 [units]':>18} "
        f"{'penetr. [units]':>15} {'time':>9}"
    )
    lines = [header, "-" * len(header)]
    previous = None
    for row in rows:
        name = row["dataset"] if row["dataset"] != previous else ""
        units = row.get("units", "") if name else ""
        if previous is not None and name:
            lines.append("")
        previous = row["dataset"]
        pen = "" if row["penetration_max"] is None else f"{row['penetration_max']:.3g}"
        e1 = f"{row['e1_mean']:.4g} ± {row['e1_sd']:.2g}"
        e2 = f"{row['e2_mean']:.4g} ± {row['e2_sd']:.2g}"
        t = f"{row['runtime_s_median'] * 1000:.1f} ms"
        if row["errors"]:
            e1, e2, t = "failed", row["errors"][0][:18], ""
        lines.append(
            f"{name:<20} {units:<5} {row['method']:<22} {e1:>18} {e2:>18} {pen:>15} {t:>9}"
        )
    return "\n".join(lines)


def comparison_figures(
    runs: Sequence[MethodRun], seed: int, *, gmr_tube: bool = False
) -> Iterator[tuple[str, Figure]]:
    """The figures of a comparison, as (file name, figure) pairs, for one seed.

    Per data set: every method's path on the demonstrations (``NAME.png``) and,
    in 2-D, the Mean-Path with its Distance-Space and convergence
    (``NAME_mean_path.png``), with the GMR covariance tube if ``gmr_tube``.
    Drawn in the runs' units (:func:`run_comparison`'s ``units``).
    """
    for name in dict.fromkeys(r.dataset for r in runs):
        generated = load_dataset(name, seed=seed)
        units = next(r.units for r in runs if r.dataset == name)
        factor = conversion_factor(generated.units, units)
        demoset = _in_units(generated, units)
        paths = {
            r.method: r.path for r in runs if r.dataset == name and r.seed == seed and not r.error
        }
        yield (
            f"{name}.png",
            comparison_figure(
                demoset.demos,
                paths,
                nominal=demoset.nominal,
                walls=demoset.walls,
                units=demoset.units,
                title=f"{name} (seed {seed})",
            ),
        )
        if demoset.demos[0].shape[1] == 2:
            gmr = None
            if gmr_tube:
                k = gmr_components(generated, seed)
                # EM in the data set's own units, as the comparison's GMR ran.
                gmr = GMR(n_components=k, random_state=seed, length_scale=factor)
                gmr.fit(demoset.demos)
            yield (
                f"{name}_mean_path.png",
                mean_path_figure(
                    demoset.demos,
                    MeanPath().fit(demoset.demos),
                    units=demoset.units,
                    nominal=demoset.nominal,
                    gmr=gmr,
                    title=f"{name}: Mean-Path" + (" and GMR" if gmr_tube else ""),
                ),
            )


def _in_units(demoset: DemoSet, units: str) -> DemoSet:
    """``demoset`` with its demonstrations, nominal and walls in ``units`` (itself if they are)."""
    if units == demoset.units:
        return demoset
    factor = conversion_factor(demoset.units, units)
    return replace(
        demoset,
        demos=[factor * d for d in demoset.demos],
        nominal=factor * demoset.nominal,
        walls=tuple(factor * w for w in demoset.walls),
        units=units,
    )
