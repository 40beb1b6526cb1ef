"""Mimicking: one clean generalized path from several noisy demonstrations.

Every method follows one contract and is listed in one registry
(:mod:`lfdkit.mimic.base`): a new method is its module, one ``register`` call
there and its import below.
"""

from lfdkit.mimic.base import MIMIC_METHODS, Mimic, MimicMethod, MimicSettings, register

# isort: off
# In the order the methods are listed (MIMIC_METHODS, tables, --mimic).
from lfdkit.mimic.mean_path import MeanPath
from lfdkit.mimic.gmr import GMR, ComponentLimitWarning, select_n_components
from lfdkit.mimic.nlpca import NLPCA
from lfdkit.mimic.baselines import ArcLengthAverage, pointwise_average

# isort: on
from lfdkit.mimic.orientation import (
    DemoOrientationWarning,
    PathLengthWarning,
    SeveralMotionsError,
    check_one_motion,
    orient_demos,
)
from lfdkit.mimic.rotation_mean import PathOrientations, mean_orientations

__all__ = [
    "GMR",
    "MIMIC_METHODS",
    "NLPCA",
    "ArcLengthAverage",
    "ComponentLimitWarning",
    "DemoOrientationWarning",
    "MeanPath",
    "Mimic",
    "MimicMethod",
    "MimicSettings",
    "PathLengthWarning",
    "PathOrientations",
    "SeveralMotionsError",
    "check_one_motion",
    "mean_orientations",
    "orient_demos",
    "pointwise_average",
    "register",
    "select_n_components",
]
