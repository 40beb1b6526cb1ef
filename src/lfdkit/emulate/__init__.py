"""Emulation: learn how the demonstrator reacts to obstacles (a reward) and plan in new scenes."""

from lfdkit.emulate.ioc import IOC
from lfdkit.emulate.planner import Corridor, Plan, UnsafePlanError, plan_clearance, plan_path
from lfdkit.emulate.reward import Reward
from lfdkit.emulate.scene import Obstacle, Scene

__all__ = [
    "IOC",
    "Corridor",
    "Obstacle",
    "Plan",
    "Reward",
    "Scene",
    "UnsafePlanError",
    "plan_clearance",
    "plan_path",
]
