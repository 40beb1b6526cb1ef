"""Reward learning around boxes in 3-D: leave one demonstration out, against the DMP alone.

Run ``python benchmarks/boxes3d.py`` (``--quick`` for a smoke run). Prints a
table and writes ``boxes3d.json`` to ``--output`` (``benchmarks/results/boxes3d``).

The data (issue 34): synthetic 3-D people reaching from spread starts to a
common goal around boxes (:class:`lfdkit.model.box.Box`), generated here with a
known reward, so that the learned one can be judged:

* ``one_box`` — one carton (0.12 × 0.20 × 0.25 m, turned 25° about z) in the
  middle of the reach, jittered by up to 2 cm per demonstration;
* ``three_boxes`` — a carton, a tall tin and a flat tray, turned, in the way.

Each person plans with the true reward (``Q = 6``, box precision ``400 /m²``:
a response about 5 cm wide; clearance 1 cm) along the straight line from
its start to the goal (what a DMP generalises to), then adds smooth noise
(σ 3 mm, 15-point smoothing; a person is not an optimiser). A second
``--noise`` and a ``--units mm`` run check that nothing is tuned to one
generator.

Per fold (one demonstration held out, the reward learned from the others
with the Skill's staged fit, IOC with MPC H=8 refinement, 100 points): the
plan from the held-out start to the goal in its scene, with the
person's clearance of 1 cm. Reported: the mean distance (cm) from the plan
to the held-out person along the nominal's normals, the same for the DMP
alone (the straight nominal), the side of each box the plan passes on against
the person's, collisions, the plan's clearance against the person's, fit
seconds and whether the fit converged (with its reason).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.spatial.transform import Rotation

sys.path.insert(0, str(Path(__file__).resolve().parent))

from _common import git_state, json_ready, machine_info

from lfdkit.emulate import IOC, Box, Reward, Scene, metrics, plan_path

TRUE_REWARD = Reward(6.0, {"box": [400.0, 400.0, 400.0]})
GOAL = np.array([0.65, 0.0, 0.12])
CLEARANCE = 0.01
N_POINTS = 100


def _box(centre, size, yaw_deg) -> Box:
    return Box("box", centre, 0.0, size, Rotation.from_euler("z", yaw_deg, True).as_quat())


def layout(kind: str) -> list[Box]:
    """The boxes of a set (metres)."""
    if kind == "one_box":
        return [_box([0.33, 0.0, 0.125], [0.12, 0.20, 0.25], 25.0)]
    return [
        _box([0.25, 0.10, 0.10], [0.10, 0.14, 0.20], 20.0),
        _box([0.42, -0.10, 0.15], [0.08, 0.08, 0.30], -10.0),
        _box([0.50, 0.12, 0.03], [0.16, 0.12, 0.06], 40.0),
    ]


def _smooth_noise(rng: np.random.Generator, sigma: float) -> np.ndarray:
    """Smooth noise (N_POINTS, 3) of standard deviation ``sigma``, zero at both ends."""
    kernel = np.exp(-0.5 * (np.arange(-30, 31) / 5.0) ** 2)
    raw = rng.normal(size=(N_POINTS + 60, 3))
    smooth = np.column_stack([np.convolve(raw[:, i], kernel, "valid") for i in range(3)])
    smooth *= sigma / smooth.std()
    return smooth[:N_POINTS] * np.sin(np.linspace(0.0, np.pi, N_POINTS))[:, None]


def make_set(kind: str, n_demos: int, seed: int, noise: float = 0.003) -> dict:
    """Demonstrations, scenes, nominals (straight start → goal) and the person's clearance."""
    rng = np.random.default_rng(seed)
    demos, scenes, nominals = [], [], []
    for j in range(n_demos):
        angle = np.pi * (j + 0.5) / n_demos - 0.5 * np.pi + rng.uniform(-0.1, 0.1)
        start = np.array([0.0, 0.3 * np.sin(angle), 0.15 + 0.1 * rng.uniform(-1, 1)])
        scene = Scene(tuple(b.translated(rng.uniform(-0.02, 0.02, 3) * [1, 1, 0]) for b in layout(kind)))
        nominal = start + np.linspace(0.0, 1.0, N_POINTS)[:, None] * (GOAL - start)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            plan = plan_path(TRUE_REWARD, nominal, scene, clearance=CLEARANCE)
        demos.append(plan.points + _smooth_noise(rng, noise))
        scenes.append(scene)
        nominals.append(nominal)
    return {"demos": demos, "scenes": scenes, "nominals": nominals}
