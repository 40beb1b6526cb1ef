"""The timed 3-D reach demonstrations ``data/reach3d.json`` was learned from
(tests/app/test_execute_batch.py). Other tests' reaches are the library's
:func:`lfdkit.datasets.reach_demos`: this one is shorter and unwobbled, and the
stored skill is checked against it."""

from __future__ import annotations

import numpy as np


def reach_demos(
    n_demos: int,
    duration: float,
    n_samples: int,
    y_span: float,
    height: float,
    wobble: float = 0.0,
    seed: int = 3,
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """Timed 3-D demonstrations of a reach over a box, and their times.

    Each goes ``y_span`` (m) along y, centred on 0, at x = 0.45 m, rising
    ``height`` (m) above z = 0.15 m on a half sine, in ``duration`` s (±5 %,
    drawn) with a minimum-jerk-like cosine speed, sampled ``n_samples`` times.
    ``wobble`` (m, standard deviation) varies each one's height and x; at 0 they
    are not drawn (the generator's stream is the durations only).

    Returns
    -------
    demos : list of ndarray, shape (n_samples, 3)
        Positions, m.
    times : list of ndarray, shape (n_samples,)
        Seconds from 0.
    """
    rng = np.random.default_rng(seed)
    demos, times = [], []
    for _ in range(n_demos):
        length = duration * (1 + 0.05 * rng.standard_normal())
        t = np.linspace(0.0, length, n_samples)
        s = 0.5 - 0.5 * np.cos(np.pi * t / length)
        rise, x = height, np.full_like(t, 0.45)
        if wobble:
            rise = height + wobble * rng.standard_normal()
            x = np.full_like(t, 0.45 + wobble * rng.standard_normal())
        y = -0.5 * y_span + y_span * s
        demos.append(np.column_stack([x, y, 0.15 + rise * np.sin(np.pi * s)]))
        times.append(t)
    return demos, times
