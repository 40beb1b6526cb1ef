"""Mean-Path's default centre against each fixed centre, on held-out-style data sets.

The default centre (``MeanPath(center="adaptive")``) must be as good as the best
of lfdkit's fixed centres (``mean``, ``median``, ``biweight``) on every kind of
data a user brings, not only on the ten built-in sets it was chosen on. This
benchmark draws its own sets, none of them the built-in generators:

* machined profiles with burrs (one-sided: outwards only; two-sided: either
  side), on a straight and on a circular profile, white measurement noise, the
  burrs covering 5-30 % of each profile, 2-20 times the noise high, 6-20
  profiles (the corners of that box and its middle, each a case);
* the sweep (``--kinds sweep``, not in the default run): the same profiles with
  burrs covering 10 and 20 %, 3 and 10 times the noise high, on 8 and 16
  profiles (32 cases): values between the box's, where a rule fitted to its
  corners was never looked at. Every case within 1.05 of the best fixed centre
  (seeds 0-4: worst 1.017; 500-504: 1.033);
* local detours: a smooth band (sd ``sigma`` about an arch), a minority of the
  demonstrations (2-4 of 8-14) taking one detour of the band's size (2-4 sigma);
* clean sets: the same profiles and band without burrs or detours (Gaussian
  noise only).

For every case x seed it reports e2 (against the truth) of the default and of
each fixed centre, the default's ratio to the best fixed one and to the plain
mean, and what the default chose (``center_choice_``). Targets (issue 32): the
default within 1.05 times the best fixed centre on every case (mean over
seeds), and at most 1.02 times the plain mean's e2 on the clean sets. On the
detour sets the peers run side by side: the arc-length average always, the
soft-DTW barycentre (tslearn, if installed), DBA (tslearn) and GMR (gmr) with
``--all-peers``; goal, the best lfdkit centre at most 0.5 times the best peer's
error. Beside them two oracles, the same seed's draws: the mean of the same
demonstrations with their detours erased (``detour_band`` with height 0), and
the mean with each detour's stretch dropped from its demonstration
(``dropped=True``: there the others' mean alone), what a centre that told the
detours perfectly and ignored them reaches (it matches Mean-Path with those
stretches weighted 0 within 0.3 %). No centre does better on average: the
band's spread across demonstrations is Gaussian, and there the mean of the
demonstrations left is the efficient estimate.

Measured (seeds 0-4, ``--all-peers``), detours of the band's size (2-4 sds,
2-4 of 8-14 demonstrations): the dropped oracle is 0.89-0.95 times the best
peer (soft-DTW, or the average), the default 0.96-1.02, the best lfdkit centre
0.79-0.99 (the median or biweight, by the seeds' chance: on seeds 200-209 the
mean beats both there). The band's own spread (sd ``sigma`` per
demonstration, smooth) dominates the error, not the detours, so the 0.5 goal
is out of reach of any centre on these sets: the error is floored by the
comparison, not by the rule. On held-out seeds 300-309 with other sizes and
counts (``detour_band`` directly; dropped oracle, default, over the best of
the average and soft-DTW): 3 of 10 at 1, 2, 3 sds 1.00, 0.98, 0.94 and 1.00,
0.99, 0.98; 2 of 10 at 2 sds 1.00 and 1.00; 4 of 10 at 3 sds 0.90 and 0.99;
2 of 6 at 2 sds 0.95 and 0.99; 6 of 20 at 3 sds 0.94 and 0.99. What a
detection rule could still gain there is the default's distance to the
oracle, 0-9 %; the detour feature (a demonstration's distance from its own
slow offset, ``MeanPath``'s module notes, "Detours") cannot tell such detours:
their peaks are 1.0-4.4 robust scales (seeds 0-9), while 5 % of the
demonstrations without a detour reach 1.6-2.7 somewhere and the largest
3.5-12.7. Lowering its threshold from 5 to 3 or 2.5 scales gained 0-5 % on
those sets and lost 1.4-3 % on clean smooth bands (10 demonstrations on seeds
200-209: 0.995 -> 1.014 and 1.023 times the mean), so it stays.

The kind ``detours-dominant`` (3 of 10 demonstrations, detours 12 and 20 band
sds high) is where the detours rather than the spread dominate. At 12 sds the
best peer is the arc-length average (soft-DTW 1.11 times it) and the dropped
oracle 0.69 times it on seeds 0-4, the default 0.69 (0.56 and 0.58 on seeds
300-309); the goal is reached from about 15 sds: at 16 sds, seeds 300-309,
default 0.48 (oracle 0.48; 4 of 14: 0.44 and 0.43), at 20 sds 0.41 (0.40; 2
of 8: 0.50 and 0.47), at 30 sds 0.34 (0.33). Since the default erases such
detours in smooth bands it stays within 1-3 % of the dropped oracle there (7 %
where 2 of 8 detour 20 sds).

Resolution: the table gives a 90 % interval of the default / best fixed ratio
over resampled seeds. For the burr cases its width is about 0.06 (median; up
to 0.25) with 5 seeds, 0.04 (0.18) with 10, 0.03 (0.13) with 20: resolving
the 1.05 target takes 20 seeds or more (``--seeds 20 --jobs 2``).

    python benchmarks/mimic_centres.py [--seeds 5] [--first-seed 0] [--quick]
        [--kinds burrs sweep detours clean] [--no-peer] [--all-peers] [--jobs 2]
        [--output DIR]    # table + mimic_centres.json

Seeds 0-4 are the ones the default was developed on; ``--first-seed 100``
and ``--first-seed 200`` draw held-out ones.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from collections import Counter
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
from _common import git_state, machine_info, write_json

from lfdkit.core.geometry import arc_length, left_normals, resample
from lfdkit.emulate import metrics
from lfdkit.mimic import MeanPath
from lfdkit.mimic.baselines import pointwise_average

#: Fixed centres compared with the default.
FIXED = ("mean", "median", "biweight")
#: Targets: default / best fixed centre (every case), default / mean (clean cases).
TARGET_BEST, TARGET_CLEAN = 1.05, 1.02
#: Goal on the detour sets: best lfdkit centre / best peer, of these (the arc-length
#: average always; soft-DTW with tslearn; DBA and GMR with ``--all-peers``).
TARGET_PEER = 0.5
PEERS = ("average", "soft-DTW", "DBA", "GMR")


# ------------------------------------------------------------------ generators
def _fine_line(length: float, n: int = 4001) -> np.ndarray:
    return np.column_stack((np.linspace(0.0, length, n), np.zeros(n)))


def _fine_arc(radius: float, span: float, n: int = 4001) -> np.ndarray:
    phi = np.linspace(-0.5 * span, 0.5 * span, n)
    return radius * np.column_stack((np.sin(phi), -np.cos(phi)))  # a bowl, clockwise normals


def _fine_arch(n: int = 4001) -> np.ndarray:
    """A lopsided arch (parabola with a drift), metres."""
    x = np.linspace(0.0, 1.2, n)
    return np.column_stack((x, 0.8 * x * (1.2 - x) + 0.1 * np.sin(3.0 * x)))


def _bump(u: np.ndarray, shape: str) -> np.ndarray:
    """Burr profile over ``u`` in [0, 1] (0 outside), peak 1."""
    inside = (u > 0.0) & (u < 1.0)
    v = np.clip(u, 0.0, 1.0)
    if shape == "cosine":
        h = 0.5 * (1.0 - np.cos(2.0 * np.pi * v))
    elif shape == "triangle":
        h = 1.0 - np.abs(2.0 * v - 1.0)
    elif shape == "plateau":
        h = np.minimum(1.0, np.minimum(v, 1.0 - v) / 0.15)
    else:  # "spike": steep rise, long tail (a rolled-over burr)
        h = np.minimum(v / 0.1, ((1.0 - v) / 0.9) ** 2)
    return np.where(inside, h, 0.0)


BURR_SHAPES = ("cosine", "triangle", "plateau", "spike")


def _burr_offsets(
    s: np.ndarray, coverage: float, heights: tuple[float, float], sides: int, rng
) -> np.ndarray:
    """Normal offset of one profile from its burrs: they cover ``coverage`` of its length."""
    length = s[-1]
    covered = np.zeros(len(s), dtype=bool)
    offset = np.zeros(len(s))
    for _ in range(200):
        if covered.mean() >= coverage:
            break
        width = rng.uniform(0.01, 0.06) * length
        start = rng.uniform(-0.5 * width, length - 0.5 * width)
        u = (s - start) / width
        sign = 1.0 if sides == 1 or rng.random() < 0.5 else -1.0
        offset += sign * rng.uniform(*heights) * _bump(u, rng.choice(BURR_SHAPES))
        covered |= (u > 0.0) & (u < 1.0)
    return offset


def burr_profiles(
    profile: str,
    sides: int,
    n_profiles: int,
    coverage: float,
    height: float,
    seed: int,
    *,
    noise: float = 0.01,
    n_points: int = 400,
) -> tuple[list[np.ndarray], np.ndarray]:
    """Measured profiles with burrs: ``(demos, nominal)`` in mm.

    ``profile``: "line" (120 mm) or "arc" (radius 35 mm over 200°). Each profile
    is sampled at ``n_points`` points equally spaced along it, with white normal
    noise of sd ``noise``; burrs (4 shapes, widths 1-6 % of the length) cover
    ``coverage`` of it, each of height uniform in ``[0.5, 1] * height * noise``
    (so the set's tallest are ``height`` times the noise), outwards only
    (``sides=1``) or to a random side (``sides=2``).
    """
    rng = np.random.default_rng(seed)
    fine = _fine_line(120.0) if profile == "line" else _fine_arc(35.0, np.radians(200.0))
    s = arc_length(fine)
    normals = left_normals(fine)
    sample = np.linspace(0.0, s[-1], n_points)
    heights = (0.5 * height * noise, height * noise)
    demos = []
    for _ in range(n_profiles):
        offset = _burr_offsets(s, coverage, heights, sides, rng) if coverage > 0 else 0.0
        shifted = fine + np.asarray(offset)[..., None] * normals
        points = np.column_stack([np.interp(sample, s, shifted[:, k]) for k in range(2)])
        on_normals = np.column_stack([np.interp(sample, s, normals[:, k]) for k in range(2)])
        demos.append(points + rng.normal(0.0, noise, n_points)[:, None] * on_normals)
    return demos, fine


def detour_band(
    n_demos: int,
    n_detours: int,
    height: float,
    seed: int,
    *,
    sigma: float = 0.015,
    n_points: int = 150,
    dropped: bool = False,
) -> tuple[list[np.ndarray], np.ndarray]:
    """A smooth band about an arch, ``n_detours`` demonstrations taking one detour: metres.

    Each demonstration's normal offset is a random smooth curve of sd ``sigma``
    (a sum of four sines of random phase), plus white noise of sd ``sigma / 20``.
    A detour is a raised-cosine bump of height ``height * sigma`` (to a random
    side) and width 10-20 % of the length, centred in the middle 60 %.

    ``dropped=True`` (an oracle, the same draws): over each detour's stretch the
    detouring demonstration's offset is the mean of the others' (those without a
    detour there), so that the plain mean there is theirs alone: the
    demonstrations' mean with every detour stretch left out, which a centre that
    told the detours perfectly and ignored them could reach.
    """
    rng = np.random.default_rng(seed)
    fine = _fine_arch()
    s = arc_length(fine)
    u = s / s[-1]
    normals = left_normals(fine)
    detouring = set(rng.choice(n_demos, size=n_detours, replace=False).tolist())
    offsets, stretches, sizes, noises = [], [], [], []
    for j in range(n_demos):
        amp = rng.normal(0.0, 1.0, 4) / np.sqrt(np.arange(1, 5))
        phase = rng.uniform(0.0, 2.0 * np.pi, 4)
        offset = sum(
            a * np.sin((k + 0.5) * np.pi * u + p)
            for k, (a, p) in enumerate(zip(amp, phase, strict=True))
        )
        offset = sigma * offset / np.sqrt(np.sum(1.0 / np.arange(1, 5)) / 2.0)
        stretch = np.zeros(len(u), dtype=bool)
        if j in detouring:
            width = rng.uniform(0.1, 0.2)
            centre = rng.uniform(0.2, 0.8)
            sign = 1.0 if rng.random() < 0.5 else -1.0
            bump = _bump((u - centre) / width + 0.5, "cosine")
            stretch = bump > 0.0
            if not dropped:
                offset = offset + sign * height * sigma * bump
        offsets.append(offset)
        stretches.append(stretch)
        sizes.append(n_points + int(rng.integers(-20, 21)))
        noises.append(rng.normal(0.0, sigma / 20.0, (sizes[-1], 2)))
    if dropped:
        plain = np.array(offsets)
        inside = np.array(stretches)
        others = np.where(inside, 0.0, plain).sum(axis=0) / np.maximum((~inside).sum(axis=0), 1)
        offsets = [np.where(inside[j], others, plain[j]) for j in range(n_demos)]
    demos = []
    for offset, size, noise in zip(offsets, sizes, noises, strict=True):
        path = fine + offset[:, None] * normals
        demos.append(resample(path, size) + noise)
    return demos, fine


# ------------------------------------------------------------------ cases
def cases(quick: bool = False) -> list[dict]:
    """Every case: its kind, label and generator (a function of the seed)."""
    out = []
    box = [(0.05, 2, 6), (0.05, 20, 20), (0.3, 2, 20), (0.3, 20, 6), (0.15, 6, 12)]
    if not quick:
        box += [(0.05, 2, 20), (0.3, 20, 20), (0.05, 20, 6), (0.3, 2, 6)]
    for profile in ("line", "arc"):
        for sides in (1, 2):
            kind = f"burrs {profile} {sides}-sided"
            for coverage, height, n in box:
                out.append(
                    {
                        "kind": kind,
                        "case": f"{kind} cov {coverage:.2f} h {height}x n {n}",
                        "make": (
                            lambda seed, p=profile, sd=sides, c=coverage, h=height, n=n: (
                                burr_profiles(p, sd, n, c, h, seed)
                            )
                        ),
                    }
                )
        out.append(
            {
                "kind": "clean",
                "case": f"clean {profile} (white noise), n 10",
                "make": lambda seed, p=profile: burr_profiles(p, 1, 10, 0.0, 0.0, seed),
            }
        )
    # The sweep (``--kinds sweep``, not in the default run): burr coverages, heights and
    # profile counts between the box's, so that a rule fitted to the box's corners is
    # checked where it was not looked at.
    for profile in ("line", "arc"):
        for sides in (1, 2):
            kind = f"sweep {profile} {sides}-sided"
            for coverage in (0.1, 0.2):
                for height in (3, 10):
                    for n in (8, 16):
                        out.append(
                            {
                                "kind": kind,
                                "case": f"{kind} cov {coverage:.2f} h {height}x n {n}",
                                "make": (
                                    lambda seed, p=profile, sd=sides, c=coverage, h=height, n=n: (
                                        burr_profiles(p, sd, n, c, h, seed)
                                    )
                                ),
                            }
                        )
    for n_demos, n_detours, height in ((10, 3, 3.0), (8, 2, 4.0), (14, 4, 2.0), (10, 3, 4.0)):
        out.append(
            {
                "kind": "detours",
                "case": f"detours {n_detours}/{n_demos} h {height:g} sd",
                "make": lambda seed, n=n_demos, k=n_detours, h=height: detour_band(n, k, h, seed),
                "peer": True,
                # The same demonstrations with their detours erased: no centre can do
                # better than their mean, which the band's own spread limits.
                "floor": lambda seed, n=n_demos, k=n_detours: detour_band(n, k, 0.0, seed),
                # ... and with every detour's stretch left out of its demonstration.
                "dropped": lambda seed, n=n_demos, k=n_detours, h=height: detour_band(
                    n, k, h, seed, dropped=True
                ),
            }
        )
    # Detours that dominate the error (12 and 20 band sds high): the only kind where the
    # issue's 0.5 x best peer goal is within reach of a centre at all (from about 15 sds); a
    # separate kind, so that the band sets above keep their "size of the band" meaning.
    for height in (12.0, 20.0):
        out.append(
            {
                "kind": "detours-dominant",
                "case": f"detours dominant 3/10 h {height:g} sd",
                "make": lambda seed, h=height: detour_band(10, 3, h, seed),
                "peer": True,
                "floor": lambda seed: detour_band(10, 3, 0.0, seed),
                "dropped": lambda seed, h=height: detour_band(10, 3, h, seed, dropped=True),
            }
        )
    for n_demos in (6, 15):
        out.append(
            {
                "kind": "clean",
                "case": f"clean band (smooth), n {n_demos}",
                "make": lambda seed, n=n_demos: detour_band(n, 0, 1.0, seed),
            }
        )
    return out


# ------------------------------------------------------------------ runs
def _soft_dtw(demos: list[np.ndarray]) -> np.ndarray:
    from tslearn.barycenters import softdtw_barycenter

    stacked = np.vstack(demos)
    centre, scale = stacked.mean(axis=0), stacked.std()
    scaled = np.array([resample((d - centre) / scale, 100) for d in demos])
    init = scaled.mean(axis=0)
    return softdtw_barycenter(scaled, gamma=0.01, max_iter=50, init=init) * scale + centre


def _dba(demos: list[np.ndarray]) -> np.ndarray:
    from tslearn.barycenters import dtw_barycenter_averaging
    from tslearn.utils import to_time_series_dataset

    dataset = to_time_series_dataset(demos)
    return dtw_barycenter_averaging(dataset, barycenter_size=100, max_iter=30)


def _gmr(demos: list[np.ndarray], seed: int) -> np.ndarray:
    from gmr import GMM

    from lfdkit.app.evaluation import GMR_CANDIDATES
    from lfdkit.mimic import select_n_components

    k = select_n_components(demos, GMR_CANDIDATES, random_state=seed)[0]
    samples = np.vstack([np.column_stack((np.linspace(0, 1, len(d)), d)) for d in demos])
    gmm = GMM(n_components=k, random_state=seed).from_samples(samples, init_params="kmeans++")
    return gmm.predict(np.array([0]), np.linspace(0, 1, 100)[:, None])


def _e2(path: np.ndarray, nominal: np.ndarray) -> float:
    return metrics.e2(resample(path, 100), nominal, n_points=100)


def run_case(case: dict, seed: int, peer: Callable | None, all_peers: bool = False) -> dict:
    demos, nominal = case["make"](seed)
    row: dict = {"case": case["case"], "kind": case["kind"], "seed": seed, "e2": {}}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for centre in ("adaptive", *FIXED):
            start = time.perf_counter()
            mp = MeanPath(n_points=100, center=centre).fit(demos)
            row.setdefault("time_s", {})[centre] = time.perf_counter() - start
            row["e2"][centre] = _e2(mp.path_, nominal)
            if centre == "adaptive":
                row["choice"] = list(getattr(mp, "center_tuning_", (4.0, 4.0, 8.0)))
                row["reason"] = getattr(mp, "center_reason_", "")
        if case.get("peer"):
            row["e2"]["average"] = _e2(pointwise_average(demos, 100), nominal)
            if peer is not None:
                row["e2"]["soft-DTW"] = _e2(peer(demos), nominal)
            if all_peers:
                row["e2"]["DBA"] = _e2(_dba(demos), nominal)
                row["e2"]["GMR"] = _e2(_gmr(demos, seed), nominal)
        if "floor" in case:
            erased, _ = case["floor"](seed)
            row["e2"]["floor"] = _e2(
                MeanPath(n_points=100, center="mean").fit(erased).path_, nominal
            )
        if "dropped" in case:
            dropped, _ = case["dropped"](seed)
            row["e2"]["dropped"] = _e2(
                MeanPath(n_points=100, center="mean").fit(dropped).path_, nominal
            )
    return row


def _ratio_interval(mine: list[dict], draws: int = 2000) -> tuple[float, float]:
    """90 % interval of default / best fixed centre (means over seeds), seeds resampled.

    The best fixed centre is re-picked in every resampling, as in the table.
    """
    e2 = np.array([[r["e2"][c] for c in ("adaptive", *FIXED)] for r in mine])
    rng = np.random.default_rng(0)
    picks = rng.integers(0, len(mine), (draws, len(mine)))
    means = e2[picks].mean(axis=1)  # (draws, 1 + centres)
    ratios = means[:, 0] / means[:, 1:].min(axis=1)
    low, high = np.quantile(ratios, [0.05, 0.95])
    return float(low), float(high)


def _run_job(job: tuple[bool, str, int, bool, bool]) -> dict:
    """One case x seed in a worker: ``(quick, case name, seed, with peer, all peers)``."""
    quick, name, seed, with_peer, all_peers = job
    case = next(c for c in cases(quick) if c["case"] == name)
    return run_case(case, seed, _soft_dtw if with_peer else None, all_peers)


def summarise(rows: list[dict]) -> list[dict]:
    """Per case: mean e2 over seeds of each centre, the default's ratios, the targets."""
    out = []
    for name in dict.fromkeys(r["case"] for r in rows):
        mine = [r for r in rows if r["case"] == name]
        e2 = {k: float(np.mean([r["e2"][k] for r in mine])) for k in mine[0]["e2"]}
        best_fixed = min(e2[c] for c in FIXED)
        best_lfdkit = min(e2[c] for c in ("adaptive", *FIXED))
        per_seed = [r["e2"]["adaptive"] / min(r["e2"][c] for c in FIXED) for r in mine]
        low, high = _ratio_interval(mine)
        item = {
            "case": name,
            "kind": mine[0]["kind"],
            "e2": e2,
            "ratio_best": e2["adaptive"] / best_fixed,
            "ratio_mean": e2["adaptive"] / e2["mean"],
            "worst_seed_ratio_best": float(max(per_seed)),
            "ratio_best_90": [low, high],
            "choices": [r["choice"] for r in mine],
        }
        item["pass"] = item["ratio_best"] <= TARGET_BEST and (
            item["kind"] != "clean" or item["ratio_mean"] <= TARGET_CLEAN
        )
        peers = [p for p in PEERS if p in e2]
        if peers:
            best_peer = min(peers, key=lambda p: e2[p])
            item["best_peer"] = best_peer
            item["ratio_peer"] = best_lfdkit / e2[best_peer]
            item["default_ratio_peer"] = e2["adaptive"] / e2[best_peer]
            for oracle in ("floor", "dropped"):
                if oracle in e2:
                    item[f"{oracle}_ratio_peer"] = e2[oracle] / e2[best_peer]
        out.append(item)
    return out


def print_table(summary: list[dict], n_seeds: int) -> None:
    print(
        f"\nMean-Path centres on held-out-style sets: e2 (units of the set), mean of {n_seeds} "
        "seeds; default/best fixed centre (target <= 1.05), default/mean (clean: <= 1.02)"
    )
    head = f"{'case':<38}{'default':>10}{'mean':>10}{'median':>10}{'biweight':>10}"
    print(head + f"{'def/best':>9}{'90% (seeds)':>14}{'def/mean':>9}  chosen")
    for r in summary:
        e = r["e2"]
        counts = Counter("/".join(f"{x:g}" for x in c) for c in r["choices"])
        chosen = ", ".join(f"{k} x{v}" for k, v in counts.most_common())
        peer = ""
        if "ratio_peer" in r:
            peer = f"  / best peer ({r['best_peer']}): lfdkit {r['ratio_peer']:.2f}"
            peer += f", default {r['default_ratio_peer']:.2f}"
        if "dropped_ratio_peer" in r:
            peer += f", detours dropped {r['dropped_ratio_peer']:.2f}"
        if "floor_ratio_peer" in r:
            peer += f", erased {r['floor_ratio_peer']:.2f}"
        print(
            f"{r['case']:<38}{e['adaptive']:>10.4g}{e['mean']:>10.4g}{e['median']:>10.4g}"
            f"{e['biweight']:>10.4g}{r['ratio_best']:>9.3f}"
            f"{r['ratio_best_90'][0]:>8.2f}-{r['ratio_best_90'][1]:<5.2f}"
            f"{r['ratio_mean']:>9.3f}  {chosen}{'' if r['pass'] else '  FAIL'}{peer}"
        )
    print("\nworst per kind (mean over seeds):")
    for kind in dict.fromkeys(r["kind"] for r in summary):
        mine = [r for r in summary if r["kind"] == kind]
        worst = max(mine, key=lambda r: r["ratio_best"])
        line = f"  {kind:<22} default/best fixed {worst['ratio_best']:.3f} ({worst['case']})"
        if kind == "clean":
            line += f"; default/mean at most {max(r['ratio_mean'] for r in mine):.3f}"
        if "ratio_peer" in worst:
            line += (
                f"; / best peer: best lfdkit at most {max(r['ratio_peer'] for r in mine):.2f}, "
                f"default at most {max(r['default_ratio_peer'] for r in mine):.2f}"
                f" (goal <= {TARGET_PEER}); the mean with the detour stretches dropped at "
                f"best {min(r['dropped_ratio_peer'] for r in mine):.2f}, with the detours "
                f"erased at best {min(r['floor_ratio_peer'] for r in mine):.2f}"
            )
        print(line)
    failed = [r["case"] for r in summary if not r["pass"]]
    print(
        f"{len(summary) - len(failed)} of {len(summary)} cases pass"
        + (f"; fail: {failed}" if failed else "")
    )


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--first-seed", type=int, default=0)
    parser.add_argument("--quick", action="store_true", help="5 burr cases per kind, 2 seeds")
    parser.add_argument("--kinds", nargs="*", help="only these kinds (e.g. detours clean)")
    parser.add_argument("--no-peer", action="store_true", help="skip the soft-DTW barycentre")
    parser.add_argument(
        "--all-peers", action="store_true", help="DBA (tslearn) and GMR (gmr) too: slower"
    )
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (one thread each)")
    parser.add_argument(
        "--output", type=Path, default=Path(__file__).parent / "results" / "mimic_centres"
    )
    args = parser.parse_args(argv)
    n_seeds = 2 if args.quick else args.seeds
    seeds = range(args.first_seed, args.first_seed + n_seeds)
    peer = None
    if not args.no_peer:
        try:
            import tslearn  # noqa: F401

            peer = _soft_dtw
        except ImportError:
            print("tslearn not installed: no soft-DTW peer", file=sys.stderr)
    todo = [
        c
        for c in cases(args.quick)
        if (c["kind"].split()[0] in args.kinds if args.kinds else c["kind"].split()[0] != "sweep")
    ]
    start = time.perf_counter()
    jobs = [
        (args.quick, case["case"], seed, peer is not None, args.all_peers)
        for case in todo
        for seed in seeds
    ]
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(_run_job, jobs, chunksize=1))
    else:
        rows = []
        for i, job in enumerate(jobs):
            rows.append(_run_job(job))
            if (i + 1) % n_seeds == 0:
                print(f"[{(i + 1) // n_seeds}/{len(todo)}] {job[1]}", file=sys.stderr, flush=True)
    wall = time.perf_counter() - start
    summary = summarise(rows)
    print_table(summary, n_seeds)
    print(f"{len(jobs)} case x seed runs in {wall:.0f} s ({args.jobs} processes)")
    args.output.mkdir(parents=True, exist_ok=True)
    out = args.output / "mimic_centres.json"
    result = {
        "benchmark": "mimic_centres",
        "created": time.strftime("%Y-%m-%dT%H:%M:%S"),
        "machine": machine_info(),
        "git": git_state(),
        "seeds": list(seeds),
        "wall_s": wall,
        "jobs": args.jobs,
        "targets": {"best": TARGET_BEST, "clean_vs_mean": TARGET_CLEAN, "peer": TARGET_PEER},
        "summary": summary,
        "rows": rows,
    }
    write_json(out, result)
    print(f"wrote {out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
