"""The learned obstacle behaviour in words: what ``lfdkit learn`` prints and reports show.

One wording for what a skill keeps besides its reward (issue 26), so the
command's lines and the demo's report say the same: the slow return (each
step back toward the nominal bounded by a learned fraction of the step
bound, :attr:`lfdkit.skill.Skill.return_fraction_`) and the classes kept on
one side with the clearance kept from them
(:attr:`lfdkit.skill.Skill.side_preferences_`). Files from before either
say nothing of it.
"""

from __future__ import annotations

__all__ = ["side_words", "slow_return_words"]


def slow_return_words(
    fraction: float, demonstrated: dict | None, max_slope: float, units: str
) -> str | None:
    """The slow-return model's bound in words, or None where steps are symmetric.

    Parameters
    ----------
    fraction : float
        ``Skill.return_fraction_``: the bound on each step back toward the
        nominal, a fraction of the step bound (1: symmetric, the thesis's, and
        every file from before the model).
    demonstrated : dict or None
        ``ioc_info_["demonstrated_return"]``: its ``"ratio"`` is how steeply
        the demonstrations return over how steeply they swerve (unit-free).
    max_slope : float
        The skill's step bound as a slope (lateral per unit along the path).
    units : str
        The skill's length unit, named in the slope.

    Returns
    -------
    str or None
        E.g. "slow return: back at most 0.13 of the step bound (a slope of
        0.13 m across per m along; the demonstrations return 0.11 times as steeply
        as they swerve)".
    """
    if not fraction < 1.0:
        return None
    said = f"a slope of {fraction * max_slope:.2g} {units} across per {units} along"
    ratio = (demonstrated or {}).get("ratio")
    if ratio is not None and ratio == ratio:  # NaN: not measured
        said += f"; the demonstrations return {ratio:.2g} times as steeply as they swerve"
    return f"slow return: back at most {fraction:.2g} of the step bound ({said})"


def side_words(sides: dict, units: str) -> str:
    """The classes kept on one side, in words: where, and how far (files with it).

    Parameters
    ----------
    sides : dict
        ``Skill.side_preferences_``: ``{class: {"side", "within"[, "clearance"]}}``,
        lengths in ``units`` (``clearance``: absent in files from before it).
    units : str
        The lengths' unit.

    Returns
    -------
    str
        E.g. "every 'cup' on the left (within 0.09 m of the path, at least
        0.024 m from it)".
    """
    words = []
    for c, p in sides.items():
        kept = f"within {p['within']:.3g} {units} of the path"
        if p.get("clearance") is not None:
            kept += f", at least {p['clearance']:.3g} {units} from it"
        words.append(f"every {c!r} on the {p['side']} ({kept})")
    return ", ".join(words)
