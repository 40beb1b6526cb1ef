"""Tests for lfdkit.datasets.synthetic: seeded demonstration sets with known ground truth."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.core.geometry import (
    arc_length,
    intersect_normals,
    left_normals,
    path_length,
    point_tangents,
    project_onto_polyline,
    segment_lengths,
)
from lfdkit.datasets import (
    CLOSED_DATASETS,
    MIMIC_DATASETS,
    RESIDUAL_SHAPES,
    DemoSet,
    closed_circle,
    da_vinci_walls,
    deburring_circular,
    deburring_linear,
    different_extents,
    draw_residuals,
    figure_eight,
    letter_a,
    load_dataset,
    local_detours,
    loops,
    nearly_closed_o,
    noisy_band,
    quasi_circular_band,
    residual_profile,
    uneven_sampling,
    walking_corridor,
)


# ----------------------------------------------------------------- helpers
def _orient(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Sign of the turn a -> b -> c (broadcast over leading axes)."""
    return np.sign(
        (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1])
        - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])
    )


def crossing_pairs(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Boolean matrix: segment i of polyline p properly crosses segment k of polyline q."""
    a, b = p[:-1, None], p[1:, None]
    c, d = q[None, :-1], q[None, 1:]
    return (_orient(a, b, c) * _orient(a, b, d) < 0) & (_orient(c, d, a) * _orient(c, d, b) < 0)


def self_intersects(p: np.ndarray) -> bool:
    """Whether two non-adjacent segments of a 2-D polyline cross."""
    cross = crossing_pairs(p, p)
    return bool(np.triu(cross, k=2).any())


def signed_normal_offsets(nominal: np.ndarray, demo: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Signed distance along the nominal's left normals to the demo, and the hit mask."""
    hits = intersect_normals(nominal, point_tangents(nominal), demo)
    d = np.einsum("ij,ij->i", hits.points - nominal, left_normals(nominal))
    return d, hits.found


def signed_side(points: np.ndarray, polyline: np.ndarray) -> np.ndarray:
    """Signed distance of points to a 2-D polyline, positive on its left."""
    s, closest, _ = project_onto_polyline(points, polyline)
    seg = np.clip(np.searchsorted(arc_length(polyline), s, side="right") - 1, 0, len(polyline) - 2)
    t = polyline[seg + 1] - polyline[seg]
    n = np.column_stack((-t[:, 1], t[:, 0])) / np.linalg.norm(t, axis=1, keepdims=True)
    return np.einsum("ij,ij->i", points - closest, n)


# ----------------------------------------------------------------- all generators
@pytest.mark.parametrize("name", sorted(MIMIC_DATASETS))
def test_seeded_reproducible_and_well_formed(name):
    a = load_dataset(name, seed=7)
    b = MIMIC_DATASETS[name](seed=7)
    c = load_dataset(name, seed=np.random.default_rng(7))
    other = load_dataset(name, seed=8)
    assert isinstance(a, DemoSet)
    assert a.name == name
    assert a.units in ("m", "mm")
    assert len(a.demos) == len(b.demos) == len(c.demos)
    for x, y, z in zip(a.demos, b.demos, c.demos, strict=True):
        np.testing.assert_array_equal(x, y)
        np.testing.assert_array_equal(x, z)
    np.testing.assert_array_equal(a.nominal, b.nominal)
    assert any(
        x.shape != y.shape or not np.array_equal(x, y)
        for x, y in zip(a.demos, other.demos, strict=False)
    )
    q = a.nominal.shape[1]
    assert a.nominal.shape[0] >= 400
    for demo in a.demos:
        assert demo.dtype == np.float64 and demo.ndim == 2 and demo.shape[1] == q
        assert np.isfinite(demo).all()
    for wall in a.walls:
        assert wall.shape[1] == q
    # The nominal runs in the demonstrations' direction.
    for demo in a.demos:
        assert np.linalg.norm(demo[0] - a.nominal[0]) < np.linalg.norm(demo[0] - a.nominal[-1])
    assert (a.material_side is not None) == name.startswith("deburring")
    assert a.description


def test_load_dataset_unknown_name():
    with pytest.raises(ValueError, match=r"valid names:.*noisy_band"):
        load_dataset("no_such_set")


def test_demoset_validation():
    line = np.c_[np.linspace(0, 1, 5), np.zeros(5)]
    with pytest.raises(ValueError, match="units: expected one of 'm', 'cm', 'mm'"):
        DemoSet("x", [line], line, units="inch")
    with pytest.raises(ValueError, match="material_side"):
        DemoSet("x", [line], line, units="m", material_side=0)
    with pytest.raises(ValueError, match="columns"):
        DemoSet("x", [line], np.c_[line, line[:, :1]], units="m")


# ----------------------------------------------------------------- chapter 4
def test_quasi_circular_band_offsets():
    offset = 0.6
    jitter = 0.01 * offset
    ds = quasi_circular_band(n_points=100, offset=offset, seed=3)
    assert len(ds.demos) == 2 and all(d.shape == (100, 2) for d in ds.demos)
    # Open curve: endpoints far apart; about 300 degrees of a radius ~5 m curve.
    assert np.linalg.norm(ds.nominal[0] - ds.nominal[-1]) > 4.0
    for demo, sign in zip(ds.demos, (1.0, -1.0), strict=True):
        # Interior nominal points only: at the very ends the demo may stop just short of
        # the nominal's end normal, which then meets the far side of the open curve.
        d, found = signed_normal_offsets(ds.nominal, demo)
        assert found[2:-2].all()
        err = d[2:-2] - sign * offset
        # Chord error of a 100-point polyline on this curve is ~2 mm at most; jitter is
        # Gaussian with sd 0.006 m: every deviation within 4.5 sd, RMS close to one sd.
        assert np.abs(err).max() < 4.5 * jitter + 0.003
        assert 0.5 * jitter < np.sqrt(np.mean(err**2)) < 1.5 * jitter


def test_noisy_band_spread_matches_noise():
    noise = 0.15
    ds = noisy_band(n_demos=10, n_points=100, noise=noise, seed=0)
    d = np.array([signed_normal_offsets(ds.nominal, demo)[0][5:-5] for demo in ds.demos])
    assert np.isfinite(d).all()
    assert 0.5 * noise < d.std() < 1.5 * noise
    # Smooth offsets are bounded by sqrt(6) sd, plus a little white noise.
    assert np.abs(d).max() < np.sqrt(6) * noise + 0.05
    assert not any(self_intersects(demo) for demo in ds.demos)


def test_walking_corridor_inside_walls():
    ds = walking_corridor(seed=11)
    assert len(ds.demos) == 30 and len(ds.walls) >= 2
    lengths = [len(d) for d in ds.demos]
    assert min(lengths) >= 90 and max(lengths) <= 110 and len(set(lengths)) > 1
    assert 9.0 < path_length(ds.nominal) < 11.0
    start, goal = ds.nominal[0], ds.nominal[-1]
    for demo in ds.demos:
        assert np.linalg.norm(demo[0] - start) < 0.3 + 0.05
        assert np.linalg.norm(demo[-1] - goal) < 0.3 + 0.05
        for wall in ds.walls:
            assert not crossing_pairs(demo, wall).any()
            assert project_onto_polyline(demo, wall)[2].min() > 0.1
        # Inside the corridor (y in [-0.9, 0.9]) or the room (x in [4.5, 8.5], y <= 5).
        x, y = demo[:, 0], demo[:, 1]
        in_corridor = (np.abs(y) < 0.9) & (x > -1.0) & (x < 8.5)
        in_room = (y >= 0.9) & (y < 5.0) & (x > 4.5) & (x < 8.5)
        assert (in_corridor | in_room).all()


def test_da_vinci_between_walls():
    ds = da_vinci_walls(n_demos=4, seed=2)
    assert ds.nominal.shape[1] == 3 and all(d.shape[1] == 3 for d in ds.demos)
    assert all(w.shape[1] == 3 for w in ds.walls)
    wall_y = sorted(float(w[0, 1]) for w in ds.walls)
    for demo in ds.demos:
        assert (demo[:, 1] > wall_y[0]).all() and (demo[:, 1] < wall_y[1]).all()
        # Deviations are a few mm around the nominal.
        dist = project_onto_polyline(demo, ds.nominal)[2]
        assert dist.max() < 0.012 and dist.mean() > 0.0005
    assert 0.05 < np.ptp(ds.nominal[:, 0]) < 0.2


# ----------------------------------------------------------------- deburring
def test_residual_profile_bounds():
    u = np.linspace(-0.2, 1.2, 1401)
    assert len(RESIDUAL_SHAPES) == 7
    for shape in RESIDUAL_SHAPES:
        h = residual_profile(shape, u)
        assert h.shape == u.shape
        assert (h >= 0).all() and (h <= 1).all()
        assert residual_profile(shape, 0.0) == 0.0 and residual_profile(shape, 1.0) == 0.0
        assert (h[(u < 0) | (u > 1)] == 0).all()
        assert h.max() > 0.95
    with pytest.raises(ValueError, match="valid"):
        residual_profile("blob", u)


def test_draw_residuals_frequency_and_shapes():
    draws = [draw_residuals(10, 10, 200.0, 0.3, seed=s) for s in range(10)]
    count = sum(len(row) for res in draws for row in res)
    assert 0.25 < count / (10 * 10 * 10) < 0.35
    assert {r.shape for res in draws[:4] for row in res for r in row} == set(RESIDUAL_SHAPES)
    for res in draws:
        for j, row in enumerate(res):
            for r in row:
                assert r.demo == j and 0.5 <= r.height <= 2.0
                assert r.segment * 20.0 <= r.start and r.start + r.width <= (r.segment + 1) * 20.0


@pytest.mark.parametrize("gen", [deburring_linear, deburring_circular])
def test_deburring_never_inside_material(gen):
    for seed in range(3):
        ds = gen(seed=seed)
        assert ds.units == "mm" and ds.material_side in (1, -1)
        for demo in ds.demos:
            outward = -ds.material_side * signed_side(demo, ds.nominal)
            assert outward.min() >= -1e-9
            # The 500-point nominal's chords lie up to 2.5e-4 mm inside the true arc.
            assert outward.max() <= 2.0 + 1e-3


def test_deburring_circular_radius():
    ds = deburring_circular(seed=4)
    assert ds.material_side == 1  # the disc is on the left of the counter-clockwise arc
    np.testing.assert_allclose(np.linalg.norm(ds.nominal, axis=1), 50.0)
    for demo in ds.demos:
        r = np.linalg.norm(demo, axis=1)
        assert r.min() >= 50.0 - 1e-9 and r.max() <= 52.0 + 1e-9


def test_deburring_linear_matches_drawn_residuals():
    n_demos, n_segments = 10, 10
    ds = deburring_linear(n_demos=n_demos, n_points=200, seed=5)
    res = draw_residuals(n_demos, n_segments, 200.0, 0.3, seed=5)
    assert ds.material_side == -1
    for demo, row in zip(ds.demos, res, strict=True):
        x, y = demo[:, 0], demo[:, 1]
        expected = sum(
            (r.height * residual_profile(r.shape, (x - r.start) / r.width) for r in row),
            np.zeros_like(x),
        )
        np.testing.assert_allclose(y, expected, atol=1e-12)
        segment = np.minimum((x // 20.0).astype(int), n_segments - 1)
        with_residual = {int(i) for i in np.unique(segment[y > 0])}
        assert with_residual == {r.segment for r in row}


def test_deburring_optional_noise():
    clean = deburring_linear(seed=1)
    noisy = deburring_linear(seed=1, noise=0.05)
    diff = np.concatenate([a - b for a, b in zip(noisy.demos, clean.demos, strict=True)])
    assert 0.03 < diff.std() < 0.07


# ----------------------------------------------------------------- hard cases
def test_different_extents():
    for n_demos in (10, 11):
        ds = different_extents(n_demos=n_demos, seed=6)
        t0, t1 = point_tangents(ds.nominal)[[0, -1]]
        # Tangential position of each demo's start (end) relative to the nominal's start (end).
        start = np.array([(d[0] - ds.nominal[0]) @ t0 for d in ds.demos])
        end = np.array([(d[-1] - ds.nominal[-1]) @ t1 for d in ds.demos])
        # Starts (ends) spread over up to 15 % of the ~12 m curve: they really differ, and
        # some demos overhang the nominal while others fall short of it.
        assert np.ptp(start) > 0.5 and np.ptp(end) > 0.5
        assert start.min() < 0 < start.max() and end.min() < 0 < end.max()
        assert abs(np.median(start)) < 0.05 and abs(np.median(end)) < 0.05
        full = noisy_band(seed=0).nominal
        assert path_length(ds.nominal) < path_length(full)


def test_local_detours_are_local_and_counted():
    noise = 0.15
    base = noisy_band(n_demos=10, n_points=100, noise=noise, seed=9)
    ds = local_detours(n_demos=10, n_detours=3, seed=9, n_points=100, noise=noise)
    changed = [
        j
        for j, (a, b) in enumerate(zip(ds.demos, base.demos, strict=True))
        if not np.array_equal(a, b)
    ]
    assert len(changed) == 3
    for j in changed:
        dist = project_onto_polyline(ds.demos[j], base.demos[j])[2]
        assert dist.max() > 3.0 * noise
        far = dist > 0.5 * noise
        assert segment_lengths(ds.demos[j])[far[:-1]].sum() < 0.15 * path_length(ds.demos[j])


def test_uneven_sampling_spacing():
    ds = uneven_sampling(n_demos=10, seed=12)
    counts = {len(d) for d in ds.demos}
    assert len(counts) > 1
    for demo in ds.demos:
        seg = segment_lengths(demo)
        assert seg.max() / seg.min() >= 20.0
        assert project_onto_polyline(demo, ds.nominal)[2].max() < np.sqrt(6) * 0.15 + 1e-6


def test_loops_self_intersect():
    base = noisy_band(n_demos=10, seed=13)
    ds = loops(n_demos=10, n_loops=2, seed=13)
    looped = [self_intersects(d) for d in ds.demos]
    assert sum(looped) == 2
    for j, has_loop in enumerate(looped):
        if not has_loop:
            np.testing.assert_array_equal(ds.demos[j], base.demos[j])


# ----------------------------------------------------------------- closed shapes
@pytest.mark.parametrize("name", sorted(CLOSED_DATASETS))
def test_closed_sets_seeded_and_well_formed(name):
    a = load_dataset(name, seed=7)
    b = CLOSED_DATASETS[name](seed=7)
    c = load_dataset(name, seed=np.random.default_rng(7))
    other = load_dataset(name, seed=8)
    assert isinstance(a, DemoSet) and a.name == name
    assert a.units == "mm" and a.material_side is None and a.description
    assert len(a.demos) == 7 and a.nominal.shape == (500, 2)
    for x, y, z, w in zip(a.demos, b.demos, c.demos, other.demos, strict=True):
        assert x.shape == (200, 2) and x.dtype == np.float64 and np.isfinite(x).all()
        np.testing.assert_array_equal(x, y)
        np.testing.assert_array_equal(x, z)
        assert not np.array_equal(x, w)
    np.testing.assert_array_equal(a.nominal, b.nominal)
    # The nominal is fixed: only the demonstrations depend on the seed.
    np.testing.assert_array_equal(a.nominal, other.nominal)
    # Not part of MIMIC_DATASETS (benchmarks/mimic.py and `lfdkit demo` run those).
    assert name not in MIMIC_DATASETS


@pytest.mark.parametrize(
    ("gen", "noise"),
    [(closed_circle, 1.0), (closed_circle, 0.4), (nearly_closed_o, 1.0), (figure_eight, 1.0)],
)
def test_closed_sets_noise_level(gen, noise):
    """Points lie at RMS distance ≈ noise from the nominal (the normal offsets' sd)."""
    rms = []
    for seed in range(5):
        ds = gen(seed=seed, noise=noise)
        dist = np.concatenate([project_onto_polyline(d, ds.nominal)[2] for d in ds.demos])
        rms.append(np.sqrt(np.mean(dist**2)))
        # Smooth offsets are bounded by sqrt(6) sd, plus a little white noise.
        assert dist.max() < np.sqrt(6) * noise + 0.3 * noise
    assert 0.7 * noise < np.mean(rms) < 1.3 * noise


def test_closed_circle_is_closed():
    ds = closed_circle(seed=1, radius=20.0, noise=1.0)
    np.testing.assert_array_equal(ds.nominal[0], ds.nominal[-1])
    # Points of the fine 4001-point polygon resampled: chord error below 1e-5 mm.
    np.testing.assert_allclose(np.linalg.norm(ds.nominal, axis=1), 20.0, atol=1e-5)
    np.testing.assert_allclose(ds.nominal[0], [0.0, 20.0], atol=1e-12)
    assert path_length(ds.nominal) == pytest.approx(2 * np.pi * 20.0, rel=1e-4)
    for demo in ds.demos:
        np.testing.assert_array_equal(demo[0], demo[-1])  # start = end exactly
        # Starts on the top of the circle (the radial offset moves it up or down).
        assert abs(demo[0, 0]) < 0.3 and abs(demo[0, 1] - 20.0) < np.sqrt(6) + 0.3
        # Once round, counter-clockwise: the unwrapped angle gains 2 pi.
        angle = np.unwrap(np.arctan2(demo[:, 1], demo[:, 0]))
        assert angle[-1] - angle[0] == pytest.approx(2 * np.pi, abs=1e-9)
        assert not self_intersects(demo[:-1])


def test_nearly_closed_o_gap():
    coverage, radius, noise = 0.96, 20.0, 1.0
    ds = nearly_closed_o(seed=2, coverage=coverage, radius=radius, noise=noise)
    gap_arc = (1.0 - coverage) * 2 * np.pi * radius
    chord = 2 * radius * np.sin(np.pi * (1.0 - coverage))
    assert np.linalg.norm(ds.nominal[0] - ds.nominal[-1]) == pytest.approx(chord, rel=1e-6)
    assert path_length(ds.nominal) == pytest.approx(coverage * 2 * np.pi * radius, rel=1e-4)
    assert 4.5 < gap_arc < 5.5
    for demo in ds.demos:
        gap = np.linalg.norm(demo[0] - demo[-1])
        # Nearly closed: a gap of a few mm, never closed, never wide open.
        assert chord - 2 * np.sqrt(6) * noise - 0.5 < gap < chord + 2 * np.sqrt(6) * noise + 0.5
        assert gap > 0.5
        angle = np.unwrap(np.arctan2(demo[:, 1], demo[:, 0]))
        assert 0.9 * coverage * 2 * np.pi < angle[-1] - angle[0] < 2 * np.pi
    with pytest.raises(ValueError, match="coverage"):
        nearly_closed_o(coverage=1.0)


def test_figure_eight_closed_and_crossing():
    ds = figure_eight(seed=3, size=20.0)
    np.testing.assert_array_equal(ds.nominal[0], ds.nominal[-1])
    np.testing.assert_allclose(ds.nominal[0], [0.0, 20.0], atol=1e-9)
    assert np.ptp(ds.nominal[:, 1]) == pytest.approx(40.0, rel=1e-3)
    assert np.ptp(ds.nominal[:, 0]) == pytest.approx(20.0, rel=1e-3)
    # The nominal passes through the origin twice (its crossing), half a length apart.
    s = arc_length(ds.nominal)
    near = np.linalg.norm(ds.nominal, axis=1) < 0.5
    passes = s[near]
    assert passes.min() < 0.5 * s[-1] < passes.max()
    for demo in ds.demos:
        np.testing.assert_array_equal(demo[0], demo[-1])
        assert self_intersects(demo[:-1])  # the figure-eight crosses itself


def test_letter_a_returns_near_start_and_common_end():
    radius, spread = 15.0, 0.015
    height = 2.2 * radius
    for seed in range(3):
        ds = letter_a(seed=seed, radius=radius, start_spread=spread)
        nominal = ds.nominal
        np.testing.assert_array_equal(nominal[-1], [0.0, 0.0])
        assert np.ptp(nominal[:, 1]) == pytest.approx(height, rel=1e-3)
        # The nominal passes back through its own start at about 71 % of its length.
        s = arc_length(nominal)
        late = s > 0.5 * s[-1]
        s_back, _, dist = project_onto_polyline(nominal[:1], nominal[late])
        assert dist[0] < 0.01
        assert (s_back[0] + s[late][0]) / s[-1] == pytest.approx(0.71, abs=0.02)
        starts = np.array([d[0] for d in ds.demos])
        for demo in ds.demos:
            np.testing.assert_array_equal(demo[-1], [0.0, 0.0])  # one common end
            # Start within the start disc of the nominal's start (plus white noise).
            assert np.linalg.norm(demo[0] - nominal[0]) < spread * height + 0.2
            # The demonstration later passes close to its own start.
            sd = arc_length(demo)
            later = sd > 0.5 * sd[-1]
            gap = project_onto_polyline(demo[:1], demo[later])[2][0]
            assert gap < 3.0 * 0.75
        # Starts spread by about 1-2 % of the height.
        spread_seen = np.linalg.norm(starts - starts.mean(axis=0), axis=1).max()
        assert 0.2 * spread * height < spread_seen < 1.2 * spread * height


def test_letter_a_noise_level():
    noise = 0.75
    rms = []
    for seed in range(5):
        ds = letter_a(seed=seed, noise=noise, start_spread=0.0)
        s = arc_length(ds.nominal)
        u = s / s[-1]
        for demo in ds.demos:
            # Away from the tapered ends, along the nominal's normals.
            d, found = signed_normal_offsets(ds.nominal, demo)
            keep = found & (u > 0.2) & (u < 0.6)
            rms.append(np.sqrt(np.mean(d[keep] ** 2)))
            assert np.abs(d[keep]).max() < np.sqrt(6) * noise + 0.3
    assert 0.7 * noise < np.mean(rms) < 1.3 * noise
    with pytest.raises(ValueError, match="noise"):
        letter_a(noise=1.0)  # would fold the tight turn (radius 15 mm: noise < 0.88 mm)


def test_load_dataset_finds_closed_sets():
    for name in CLOSED_DATASETS:
        assert load_dataset(name, seed=0).name == name
    with pytest.raises(ValueError, match=r"valid names:.*closed_circle.*noisy_band"):
        load_dataset("no_such_set")
