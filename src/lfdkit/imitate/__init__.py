"""Imitation: carry a generalized path to new starts and goals (Dynamic Movement Primitives).

:mod:`.primitive` is the base the position and orientation DMPs share (their
parameters, checks and phase); :mod:`.dmp` is the DMP estimator, its
numerics (exact transitions, quadrature, bases, quintic pieces) in
``_dmp_numerics`` and its compiled loops in ``_dmp_kernels``
(:mod:`.orientation_dmp` the same for unit quaternions);
:mod:`.timing` the duration and speed profile of a movement along its path
(learned from timed demonstrations, or a law), with which the DMP is trained
and any path (a plan) is timed;
:mod:`.promp` the probabilistic movement primitive (a Gaussian over paths,
conditioned on via-points); :mod:`.rhythmic` periodic movements (rhythmic
DMPs for position and orientation); :mod:`.tpgmm` the task-parameterised
GMM/GMR (a skill carried to new poses of the task's frames).
"""

from lfdkit.imitate.dmp import BASIS_LADDER, DMP, minimum_jerk_times
from lfdkit.imitate.orientation_dmp import QuaternionDMP
from lfdkit.imitate.promp import ProMP
from lfdkit.imitate.rhythmic import (
    QuaternionRhythmicDMP,
    RhythmicDMP,
    RhythmicPoseDMP,
    estimate_period,
)
from lfdkit.imitate.timing import SpeedProfile, learn_timing, path_progress
from lfdkit.imitate.tpgmm import TPGMM, TaskFrame, gaussian_product
from lfdkit.imitate.warp import warp_path

__all__ = [
    "BASIS_LADDER",
    "DMP",
    "TPGMM",
    "ProMP",
    "QuaternionDMP",
    "QuaternionRhythmicDMP",
    "RhythmicDMP",
    "RhythmicPoseDMP",
    "SpeedProfile",
    "TaskFrame",
    "estimate_period",
    "gaussian_product",
    "learn_timing",
    "minimum_jerk_times",
    "path_progress",
    "warp_path",
]
