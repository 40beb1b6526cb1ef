"""The layered skill: mimic → imitate → emulate, in one object (thesis Fig 1.4 and 5.2).

A :class:`Skill` learns, in order,

1. **mimic**: the generalized path of clean demonstrations (no obstacle),
   :class:`lfdkit.mimic.MeanPath` (default) or any method of
   :data:`lfdkit.mimic.MIMIC_METHODS`;
2. **imitate**: a :class:`lfdkit.imitate.DMP` trained on that path, which
   carries it to a new start and goal;
3. **emulate**: from demonstrations recorded around obstacles, one
   :class:`lfdkit.emulate.Reward` term per obstacle class, by inverse optimal
   control (:class:`lfdkit.emulate.IOC`).

After the reward, the skill chooses its behaviour model (route planner and
clearance floor) by cross-validated replanning error: each obstacle
demonstration left out of a refit and replanned in its own scene with every
candidate (:attr:`Skill.model_selection_`; the thesis's model unless
another is closer by more than 2 %). It then replans every training scene
with the model chosen and keeps the result per demonstration
(:attr:`Skill.training_fidelity_`: Pr over the nominal, passing sides,
clearance against the demonstrated one), with the clearance floor learned
per obstacle class (:attr:`Skill.clearances_`): the model's own, or for a
model without one (except ``model="thesis"``) the demonstrated floor as a
safety floor that gives way between two obstacles its plan passes between
(:attr:`Skill.gaps_`, :mod:`lfdkit.emulate.gaps`; issue 26). A held-out
median Pr below 50 % is warned about, and so is a plan where the floors
decide a gap no demonstration showed.

:meth:`Skill.plan` then does what the thesis's robot does in a new scene: the
DMP retargets the generalized path to the new start and goal (the *nominal*),
and the planner (receding-horizon MPC by default, or the full-horizon
optimum) moves along it around the scene's obstacles. The plan comes timed
(:class:`~lfdkit.model.timed_path.TimedPlan`: times, points, velocities): by
its own arc length with the duration and speed profile the skill learned from the demonstrations'
times (:attr:`Skill.timing_`, :mod:`lfdkit.imitate.timing`), or with the
``timing`` law over ``duration`` when they had none.

Demonstrations with the tool's orientation (``orientations=``, unit
quaternions) also give the mean orientation along the path and an
orientation DMP (:class:`lfdkit.imitate.QuaternionDMP`): plans then carry
the orientation from a start to a goal orientation, reached exactly
(:attr:`~lfdkit.model.timed_path.TimedPlan.orientations`).

Each layer can be learned on its own (:meth:`Skill.fit_path`,
:meth:`Skill.fit_reward`) or taken from elsewhere (:meth:`Skill.use_path`,
:meth:`Skill.adopt`, e.g. an obstacle class learned in another skill).

Files
-----
:meth:`Skill.save` writes one JSON document, ``{"format": "lfdkit-skill",
"version": 1, ...}``, with every number written exactly (floats round-trip
bit for bit) and no pickle; the format, its limits and its strict reader are
:mod:`lfdkit.io.skill_file`.

The same fitted skill always writes the same bytes: the file holds no date
and no run times (those stay on the object, in :attr:`Skill.mimic_info_` and
:attr:`Skill.ioc_info_`, for reports), so skill files can be compared and
cached.

:meth:`Skill.load` restores the DMPs as fitted (weights, training times,
timing and the forced response the rollouts evaluate, stored with a
checksum): loading is reading, never refitting, and a loaded skill plans to
the bit as the saved one (issue 30: 2.9 s to load the sweeping skill before,
most of it SciPy imports the refit needed). Files written before that are
refitted from the stored path and parameters (a deterministic closed-form
fit). A file from a newer format version, or one with a missing or broken
field, is refused with a message naming the file and the field.

Modules
-------
The estimator is one class, :class:`Skill`, put together from the parts below
(each a mixin of its methods, with its constants and helpers):

- :mod:`.estimator`: :class:`Skill` (parameters, ``fit``, ``fit_path``,
  ``fit_reward``, ``adopt``, ``evaluate``, ``to_units``) and :func:`learn`;
- :mod:`.planning`: the nominal, :meth:`Skill.plan`, :meth:`Skill.plan_details`
  and :meth:`Skill.point_times`;
- :mod:`.selection`: the behaviour model chosen by leave-one-out replanning;
- :mod:`.orientation`: orientation data checked, the orientation DMP, the
  orientations along a plan;
- :mod:`.via`: via-points (:meth:`Skill.via_path`, the plan's passing checks);
- :mod:`.unknown`: plans around obstacle classes never learned;
- :mod:`.files`: :meth:`Skill.save`, :meth:`Skill.load` and the dict they
  write and read.

:mod:`.periodic` holds :class:`PeriodicSkill`, the periodic counterpart
(wiping, polishing: a rhythm learned from several cycles, with its own file);
:mod:`.task_frames` :class:`TaskFrameSkill`, the task-frame one (a movement
learned in the frames of the objects it acts on, TP-GMM, planned for new
poses of them, with its own file).
"""

from lfdkit.core.lazy import lazy_names
from lfdkit.io.skill_file import (
    MAX_SKILL_FILE_BYTES,
    SKILL_FILE_LIMITS,
    SKILL_FORMAT,
    SKILL_VERSION,
)
from lfdkit.skill.estimator import Skill, learn
from lfdkit.skill.planning import RETIME_ROUNDS as RETIME_ROUNDS
from lfdkit.skill.planning import PlannerKind as PlannerKind
from lfdkit.skill.selection import CLEARANCE_FLOORS as CLEARANCE_FLOORS
from lfdkit.skill.selection import CONSISTENT_CLEARANCE as CONSISTENT_CLEARANCE
from lfdkit.skill.selection import CROSS_VALIDATION_MAX_ITER as CROSS_VALIDATION_MAX_ITER
from lfdkit.skill.selection import MAX_FOLDS as MAX_FOLDS
from lfdkit.skill.selection import MIN_CROSS_VALIDATION_DEMOS as MIN_CROSS_VALIDATION_DEMOS
from lfdkit.skill.selection import SELECTION_MARGIN as SELECTION_MARGIN
from lfdkit.skill.via import VIA_TOLERANCE as VIA_TOLERANCE

# Loaded on first use (PEP 562): a periodic skill's rhythmic DMPs are not needed
# to load or plan a discrete skill (issue 30).
__getattr__, __dir__ = lazy_names(
    __name__, {"PeriodicSkill": "periodic", "TaskFrameSkill": "task_frames"}, globals()
)

# The skill-file constants live with the format (lfdkit.io.skill_file); re-exported here.
__all__ = [
    "MAX_SKILL_FILE_BYTES",
    "SKILL_FILE_LIMITS",
    "SKILL_FORMAT",
    "SKILL_VERSION",
    "PeriodicSkill",
    "Skill",
    "TaskFrameSkill",
    "learn",
]
