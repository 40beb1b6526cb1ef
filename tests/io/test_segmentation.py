"""Splitting a recording at pauses and trimming its rest: every sample accounted for."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.io.segmentation import segment_recording


def _strokes(rest: list[float], moves: list[float], dt: float = 0.01, noise: float = 0.0):
    """Rest, move 1 unit/s along x, rest, ...: times, positions, and the motion intervals."""
    t, x, intervals, now, pos = [], [], [], 0.0, 0.0
    for k, r in enumerate(rest):
        for _ in range(round(r / dt)):
            t.append(now), x.append(pos)
            now += dt
        if k < len(moves):
            start = now
            for _ in range(round(moves[k] / dt)):
                t.append(now), x.append(pos)
                now += dt
                pos += dt
            intervals.append((start, now))
    t = np.array(t)
    rng = np.random.default_rng(0)
    p = np.c_[np.array(x), np.zeros(len(t))] + rng.normal(0, noise, (len(t), 2))
    return t, p, intervals


def test_a_recording_is_split_at_its_pauses_and_trimmed() -> None:
    t, p, intervals = _strokes([1.0, 0.8, 1.5, 2.0], [2.0, 1.0, 1.5], noise=1e-5)
    seg = segment_recording(t, p, speed=0.05, pause=0.5, window=0.02)
    assert len(seg.segments) == 3 and len(seg.pauses) == 2
    for (a, b), (start, stop) in zip(seg.segments, intervals, strict=True):
        assert abs(t[a] - start) <= 0.011 and abs(t[b - 1] - stop) <= 0.011
    assert [round(pa.duration, 2) for pa in seg.pauses] == [0.78, 1.48]
    assert seg.accounted() == seg.n_samples == len(t)
    head, tail = seg.trimmed
    assert head == 99 and tail == 198  # one rest sample kept at each end
    table = seg.table("r.bag")
    assert "split at a pause of 0.780 s" in table and "trimmed rest: 99 samples" in table


def test_a_short_rest_does_not_split_and_split_false_keeps_one() -> None:
    t, p, _ = _strokes([0.5, 0.3, 0.5], [1.0, 1.0])
    assert len(segment_recording(t, p, speed=0.05, pause=0.5).segments) == 1
    t, p, _ = _strokes([0.5, 1.0, 0.5], [1.0, 1.0])
    assert len(segment_recording(t, p, speed=0.05, pause=0.5).segments) == 2
    one = segment_recording(t, p, speed=0.05, pause=0.5, split=False)
    assert len(one.segments) == 1 and one.pauses == ()
    whole = segment_recording(t, p, speed=0.05, split=False, trim=False)
    assert whole.segments == ((0, len(t)),) and whole.trimmed == (0, 0)
    assert whole.accounted() == len(t)


def test_no_motion_is_an_error_with_the_top_speed() -> None:
    t = np.linspace(0, 1, 50)
    with pytest.raises(ValueError, match=r"never move faster than speed=0\.01.*top speed 0"):
        segment_recording(t, np.zeros((50, 3)))
    with pytest.raises(ValueError, match="speed"):
        segment_recording(t, np.zeros((50, 3)), speed=-1.0)


def test_sensor_noise_at_rest_is_not_motion() -> None:
    """0.2 mm of noise at 100 Hz reads as 2.5 cm/s between samples, 1.4 mm/s over 0.2 s."""
    t, p, intervals = _strokes([1.0, 1.0, 1.0], [0.5, 0.5])
    p = 0.2 * p + np.random.default_rng(1).normal(0, 2e-4, p.shape)  # strokes at 0.2 m/s
    seg = segment_recording(t, p)  # defaults: 1 cm/s, 0.5 s, over 0.2 s
    assert len(seg.segments) == 2
    for (a, b), (start, stop) in zip(seg.segments, intervals, strict=True):
        assert abs(t[a] - start) < 0.12 and abs(t[b - 1] - stop) < 0.12  # window/2 + a sample
    jittery = segment_recording(t, p, window=0.01)  # neighbouring samples only
    assert len(jittery.pauses) == 0 and jittery.trimmed == (0, 0)


def test_moves_back_to_the_start_are_left_out_and_listed() -> None:
    t = np.arange(0.0, 12.0, 0.01)
    x = np.zeros_like(t)
    for a, sign in ((1.0, 1), (3.5, -1), (6.0, 1), (8.5, -1)):  # out, back, out, back
        x += sign * np.clip(t - a, 0.0, 1.0)
    p = np.c_[x, 0 * x]
    seg = segment_recording(t, p, returns="drop", window=0.02)
    assert len(seg.segments) == 2 and len(seg.returns) == 2
    for a, b in seg.segments:
        assert p[b - 1, 0] - p[a, 0] > 0.99
    assert seg.accounted() == len(t)
    assert seg.table().count("left out a move back to the start") == 2
    with pytest.raises(ValueError, match="returns: expected 'keep' or 'drop'"):
        segment_recording(t, p, returns="skip")
