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

from lfdkit.core.lazy import lazy_names

# Loaded on first use (PEP 562): planning a skill needs the DMP and the timing,
# not the ProMP, the rhythmic DMPs or TP-GMM (which imports the mimic methods).
__getattr__, __dir__ = lazy_names(
    __name__,
    {
        "BASIS_LADDER": "dmp",
        "DMP": "dmp",
        "minimum_jerk_times": "dmp",
        "QuaternionDMP": "orientation_dmp",
        "ProMP": "promp",
        "QuaternionRhythmicDMP": "rhythmic",
        "RhythmicDMP": "rhythmic",
        "RhythmicPoseDMP": "rhythmic",
        "estimate_period": "rhythmic",
        "SpeedProfile": "timing",
        "learn_timing": "timing",
        "path_progress": "timing",
        "TPGMM": "tpgmm",
        "TaskFrame": "tpgmm",
        "gaussian_product": "tpgmm",
        "warp_path": "warp",
    },
    globals(),
)

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
