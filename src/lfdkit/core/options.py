"""Defaults and choices of the parameters users set by name, in one light module.

:class:`lfdkit.skill.Skill` takes its constructor defaults and its choices from
here, :mod:`lfdkit.emulate.planner` its horizon bounds, and the command line
(:mod:`lfdkit.app.cli`) the defaults, choices and ranges it shows and applies, so
that none of them repeats another's numbers. The module imports nothing, so
``lfdkit --help`` shows them without loading the library (seconds).
"""

from __future__ import annotations

from types import MappingProxyType

__all__ = [
    "DEMONSTRATION_SPEED",
    "LONGEST_DEMONSTRATION",
    "MAX_HORIZON",
    "MIN_HORIZON",
    "MODELS",
    "PLANNERS",
    "POOR_FIDELITY",
    "SCALINGS",
    "SKILL_DEFAULTS",
    "THESIS_DMP",
    "TIMINGS",
]

#: Horizons of the receding-horizon planner, inclusive (the thesis found 4 to 12 to work, §5.4).
MIN_HORIZON, MAX_HORIZON = 4, 12

#: :class:`~lfdkit.skill.Skill`'s ``planner`` choices: receding horizon or full-horizon optimum.
PLANNERS = ("mpc", "full")
#: :class:`~lfdkit.skill.Skill`'s ``model`` choices: from the demonstrations, the thesis's,
#: or "auto" with each obstacle's response in the nominal's frame (2-D).
MODELS = ("auto", "thesis", "path")
#: Cross-validated median Pr (%) of the chosen behaviour model below which a skill is said
#: to emulate its demonstrations poorly (issue 26: ``Skill.fit`` warns, ``lfdkit learn`` says).
POOR_FIDELITY = 50.0
#: :class:`~lfdkit.skill.Skill`'s ``timing`` choices (:meth:`lfdkit.imitate.DMP.fit`).
TIMINGS = ("minimum_jerk", "uniform")
#: :class:`~lfdkit.skill.Skill`'s ``scaling`` choices (:class:`lfdkit.imitate.DMP`).
SCALINGS = ("translate", "spatial", "per_dimension")

#: Mean speed (m/s) along the path of an untimed demonstration, which gives the skill's
#: duration when ``duration="auto"`` (issue 31: a fixed 1 s made an 80 cm sweep peak at
#: 1.5 m/s). A hand guiding a tool at a task: the shipped sweeps, timed at minimum jerk,
#: move at 0.15-0.2 m/s on average. At minimum jerk the peak is 1.875 times the mean.
DEMONSTRATION_SPEED = 0.2

#: Longest plausible demonstration (s): a person shows a task in seconds to a minute or two;
#: a median over 10 minutes is a file whose times are in milliseconds (1000 times too long).
LONGEST_DEMONSTRATION = 600.0

#: :class:`~lfdkit.skill.Skill`'s constructor defaults, by parameter (read-only).
SKILL_DEFAULTS = MappingProxyType(
    {
        "mimic": "mean_path",
        "n_points": 100,
        "n_components": 10,
        "n_basis": "auto",
        "timing": "minimum_jerk",
        "duration": "auto",
        "scaling": "translate",
        "planner": "mpc",
        "horizon": 8,
        "model": "auto",
        "max_slope": 1.0,
        "classes": None,
        "random_state": None,
        "units": "m",
    }
)

#: The thesis's DMP settings (10 basis functions per dimension, each dimension's forcing
#: scaled by its own start-to-goal change), one named option away from the defaults:
#: ``DMP(**THESIS_DMP)``. The defaults are the Skill's (``SKILL_DEFAULTS``): on held-out
#: starts and goals per-dimension factors blow up where a dimension barely moved.
THESIS_DMP = MappingProxyType({"n_basis": 10, "scaling": "per_dimension"})
