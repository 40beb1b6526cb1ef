"""Settings of the emulation benchmark: data sets, planners, targets and the thesis's values."""

from __future__ import annotations

import numpy as np

DATASETS = ("artificial", "da_vinci_marker", "sweeping")
VARIANTS = ("train", "free", "true")
LEARNED_VARIANTS = ("train", "free")
HORIZON = 8
SPEED_HORIZON = 12
RECOVERY_TARGET = 0.10
PR_TARGET = 90.0
RATIO_TARGET = 1.5
DMP_FACTOR_TARGET = 3.0
FIT_FULL_TARGET_S = 2.0
FIT_STAGED_TARGET_S = 15.0
MPC_STEP_TARGET_S = 1e-3
PLAN_TARGET_S = 0.1
DMP_GAMMAS = (0.0, 10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0)
DMP_BETAS = (0.5, 1.0, 2.0, 4.0, 20.0 / np.pi, 10.0, 20.0)
QUICK_GAMMAS = (0.0, 100.0, 1000.0)
QUICK_BETAS = (2.0, 20.0 / np.pi, 20.0)
DMP_WEIGHTS = 30
DMP_DT = 0.01
SCIPY_FD_STEP = 1e-4
#: Held-out scene names in the order of ``EmulationSet.held_out_scenes``.
HELD_OUT_NAMES = {
    "artificial": ("cluttered", "concave"),
    "da_vinci_marker": (
        "marker (0.035, 0.009)",
        "marker (0.05, -0.004)",
        "marker close",
        "2 markers",
    ),
    "sweeping": ("mixed cup+marker 1", "mixed marker+cup 2", "mixed cup+marker 3", "cluttered"),
}
#: Held-out scenes where the learned reward must not collide.
NO_COLLISION_SCENES = {"artificial": ("cluttered", "concave"), "sweeping": ("cluttered",)}
THESIS = {
    "artificial": "Q=10, R=[2500, 215], MSE_R 1.08e-3",
    "da_vinci_marker": "train/test MSE 0.175/0.091 (thesis units)",
    "sweeping": "Pr 96.5 % (cup), 92.7 % (marker)",
}
PLAN_NAMES = {
    "learned_full": "learned full horizon",
    "learned_mpc": f"learned MPC H={HORIZON}",
    "true_full": "true parameters (full)",
    "true_mpc": f"true parameters MPC H={HORIZON}",
}
