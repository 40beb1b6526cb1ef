"""Obstacles of a class a skill never learned: refused, or a hard radius plus a margin.

With ``unknown_class=MARGIN`` such an obstacle is kept out of by its radius
plus the margin, with no learned response, or with the response of a learned
class (``unknown_response``: by name, or the nearest in size).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence

import numpy as np

from lfdkit.core.validation import (
    check_positive,
)
from lfdkit.emulate import Reward
from lfdkit.model.scene import Scene

#: How a plan around an obstacle class never learned is asked for (in refusals).
UNKNOWN_HOW = (
    "to plan around it as a hard radius plus a margin with no learned response, pass "
    "unknown_class=MARGIN (lfdkit plan/execute: --unknown-class margin=M)"
)
#: Width of the stand-in response of an unlearned class, as a fraction of its hard
#: radius: ``exp(-(1/0.01)^2)`` = 0 at the constraint's edge, so it shapes nothing.
_UNKNOWN_RESPONSE_WIDTH = 0.01


class UnknownClasses:
    """How a :class:`~lfdkit.skill.Skill` answers obstacles of a class it never learned."""

    def _stand_in_classes(
        self, reward: Reward, scene: Scene, unknown: np.ndarray, response: str | None
    ) -> dict[str, str | None]:
        """For each unlearned class in ``scene``, the learned class whose response it takes.

        ``response`` is :meth:`plan_details`' ``unknown_response``: None (no
        response), ``"nearest"`` (the learned class whose obstacles'
        median radius :attr:`class_radii_` is nearest the class's own median
        radius in ``scene``; ties go to the first learned) or a learned class.
        """
        learned = tuple(reward.classes)
        if response is not None and (not isinstance(response, str) or response == ""):
            raise ValueError(
                f"unknown_response: expected 'nearest', a learned class or None, got {response!r}"
            )
        if response not in (None, "nearest") and response not in learned:
            known = ", ".join(repr(c) for c in learned) or "none"
            raise ValueError(
                f"unknown_response: {response!r} is not a learned class (learned: {known}); "
                "name one of them, 'nearest' or none"
            )
        labels = np.array(scene.labels, dtype=object)
        classes = list(dict.fromkeys(labels[unknown]))
        if response != "nearest":
            return {label: response for label in classes}
        sizes = getattr(self, "class_radii_", {})
        candidates = [c for c in learned if c in sizes]
        if classes and not candidates:
            raise ValueError(
                "unknown_response: 'nearest' needs the sizes of the learned classes' "
                "obstacles, which this skill lacks (a reward adopted, or a file from before "
                f"them); name the class whose response to use ({', '.join(learned) or 'none'})"
            )
        out = {}
        for label in classes:
            radius = float(np.median(scene.radii[labels == label]))
            out[label] = min(candidates, key=lambda c: abs(sizes[c] - radius))
        return out


def unknown_margins(
    reward: Reward, scene: Scene, margin: float | None, clearance: float
) -> tuple[np.ndarray, float]:
    """Which obstacles are of a class ``reward`` never learned (mask), and their margin.

    Without ``margin`` a scene with such a class is refused, the error naming
    the opt-in; with it, each such obstacle must have something to keep out
    of (radius plus clearance plus margin above 0).
    """
    unknown = np.array([label not in reward.precisions for label in scene.labels], dtype=bool)
    if margin is not None:
        margin = check_positive(margin, "unknown_class", allow_zero=True)
    if not unknown.any():
        return unknown, 0.0
    if margin is None:
        label = scene.labels[int(np.argmax(unknown))]
        known = ", ".join(repr(c) for c in reward.classes) or "none"
        raise ValueError(
            f"scene: obstacle class {label!r} was never learned (learned classes: {known}); "
            f"{UNKNOWN_HOW}, or demonstrate around it"
        )
    reach = scene.radii + check_positive(clearance, "clearance", allow_zero=True) + margin
    point = np.flatnonzero(unknown & (reach <= 0.0))
    if point.size:
        o = int(point[0])
        raise ValueError(
            f"unknown_class: obstacle {o} ({scene.labels[o]!r}) has radius 0 and no "
            f"clearance, so margin {margin:g} leaves nothing to keep out of; give a "
            "positive margin"
        )
    return unknown, margin


def median_radii(scenes: Sequence[Scene], classes: Sequence[str]) -> dict[str, float]:
    """Per class, the median radius (units) of its obstacles over ``scenes``."""
    radii: dict[str, list[float]] = {c: [] for c in classes}
    for scene in scenes:
        for label, radius in zip(scene.labels, scene.radii, strict=True):
            if label in radii:
                radii[label].append(float(radius))
    return {c: float(np.median(values)) for c, values in radii.items() if values}


def with_stand_ins(
    reward: Reward,
    scene: Scene,
    unknown: np.ndarray,
    reach: np.ndarray,
    responses: dict[str, str | None],
) -> Reward:
    """``reward`` with a stand-in for every unlearned class.

    The planner needs a precision for every class. Where ``responses`` names
    a learned class, the unlearned one takes its precision; where it names
    none, the stand-in is so narrow (:data:`_UNKNOWN_RESPONSE_WIDTH` of the
    class's smallest hard radius ``reach``, units) that it is nil wherever
    the plan may go.
    """
    labels = np.array(scene.labels, dtype=object)
    stand_ins = {}
    for label in dict.fromkeys(labels[unknown]):
        like = responses.get(label)
        if like is not None:
            stand_ins[label] = reward.precisions[like]
            continue
        width = _UNKNOWN_RESPONSE_WIDTH * float(reach[labels == label].min())
        stand_ins[label] = np.full(scene.positions.shape[1], 1.0 / width**2)
    return Reward(
        reward.nominal_weight,
        {**reward.precisions, **stand_ins},
        reward.swerve,
        along_path=reward.along_path,
    )


def warn_unknown(
    scene: Scene,
    unknown: np.ndarray,
    margin: float,
    units: str,
    responses: dict[str, str | None],
    sizes: dict[str, float],
) -> None:
    """Says which obstacles are planned around as hard radii, with which response (one line)."""
    labels = np.array(scene.labels, dtype=object)
    classes = list(dict.fromkeys(labels[unknown]))
    count = int(np.count_nonzero(unknown))
    borrowed = []
    for label in classes:
        like = responses.get(label)
        if like is None:
            continue
        said = f"{label!r} takes the learned response of {like!r}"
        if like in sizes:
            radius = float(np.median(scene.radii[labels == label]))
            said += f" (radius {radius:.3g} {units} against {sizes[like]:.3g} {units})"
        borrowed.append(said)
    if not borrowed:
        how = (
            " with no learned response: the plan keeps out but does not swerve as a "
            "demonstrator would; demonstrate around the class to learn its response"
        )
    else:
        bare = [repr(c) for c in classes if responses.get(c) is None]
        how = "; " + "; ".join(borrowed) + (f"; {', '.join(bare)} no response" if bare else "")
        how += "; demonstrate around the class to learn its own response"
    warnings.warn(
        f"plan: obstacle class{'es' * (len(classes) != 1)} "
        f"{', '.join(repr(c) for c in classes)} never learned: planned around "
        f"{'it' if count == 1 else 'them'} ({count} obstacle{'s' * (count != 1)}) as a hard "
        f"radius plus margin {margin:g} {units} (plus the clearance){how}",
        UserWarning,
        stacklevel=5,
    )
