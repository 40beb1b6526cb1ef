"""Imitation: carry a generalized path to new starts and goals (Dynamic Movement Primitives)."""

from lfdkit.imitate.dmp import BASIS_LADDER, DMP, Trajectory, minimum_jerk_times
from lfdkit.imitate.warp import warp_path

__all__ = ["BASIS_LADDER", "DMP", "Trajectory", "minimum_jerk_times", "warp_path"]
