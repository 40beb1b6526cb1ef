"""Imitation: carry a generalized path to new starts and goals (Dynamic Movement Primitives)."""

from lfdkit.imitate.dmp import DMP, Trajectory, minimum_jerk_times

__all__ = ["DMP", "Trajectory", "minimum_jerk_times"]
