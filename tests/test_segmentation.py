"""Splitting a recording at pauses and trimming its rest: every sample accounted for."""

from __future__ import annotations

import numpy as np
import pytest

from lfdkit.segmentation import segment_recording


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
    seg = segment_recording(t, p, speed=0.05, pause=0.5)
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
