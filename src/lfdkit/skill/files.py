"""A skill to and from its file: ``Skill.save``, ``Skill.load`` and the dict between them.

The format, its limits and its strict reader are :mod:`lfdkit.io.skill_file`;
this module turns a :class:`~lfdkit.skill.Skill` into its document and back,
restoring the DMPs as fitted (reading, never refitting) and refitting only
files written before the fitted state was stored.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

from lfdkit.core.options import (
    SKILL_DEFAULTS,
)
from lfdkit.emulate import Reward
from lfdkit.imitate import DMP, ProMP, QuaternionDMP, SpeedProfile
from lfdkit.io import skill_file

if TYPE_CHECKING:  # annotations only: the estimator imports this module
    from lfdkit.skill.estimator import Skill

#: Most training samples of an orientation DMP a skill file stores (3 doubles each, 0.6 MB).
_MAX_STORED_ORIENTATION_SAMPLES = 20_000


class SkillFiles(skill_file.SavedToSkillFile):
    """A :class:`~lfdkit.skill.Skill` to and from its file (:mod:`lfdkit.io.skill_file`)."""

    # ------------------------------------------------------------------ files
    def to_dict(self) -> dict[str, Any]:
        """The skill as a JSON-ready dict (:func:`lfdkit.io.skill_file.to_document`).

        The same fitted skill always gives the same dict: no date, and the
        run times (``"seconds"``) of :attr:`mimic_info_` and :attr:`ioc_info_`
        are left out (they stay on the object for reports).
        """
        self._check_fitted()
        reward = None
        if self.reward_ is not None:
            reward = (self.reward_.nominal_weight, self.reward_.precisions)
        timing = self.timing_
        # Stored unless it is the law the parameters give (as in files before timings).
        learned = timing != SpeedProfile.from_law(self.timing, self._law_duration(self.path_))
        params = self.get_params()
        if params["model"] == SKILL_DEFAULTS["model"]:
            del params["model"]  # as in files before models: they read back the same
        emulation = None
        route = getattr(self, "route_", None)
        radii = dict(getattr(self, "class_radii_", {}))
        swerve = self.reward_ is not None and self.reward_.swerve
        sides = getattr(self, "side_preferences_", {})
        if self.reward_ is not None and (
            route is not None or self.clearances_ or radii or swerve or sides
        ):
            route = route or self._unfitted_route()
            emulation = {"route": route, "clearances": dict(self.clearances_)}
            if getattr(self, "frame_", "world") != "world":  # as in files before frames
                emulation["frame"] = self.frame_
            if getattr(self, "gaps_", "closed") != "closed":  # as in files before gaps
                emulation["gaps"] = self.gaps_
            if radii:
                emulation["radii"] = radii
            if sides:  # classes kept on one side (issue 26); older files have none
                emulation["sides"] = {c: dict(p) for c, p in sides.items()}
            if self.reward_.swerve:  # the swerve model (issue 26); older files have none
                emulation["swerve"] = {c: w.tolist() for c, w in self.reward_.swerve.items()}
            if getattr(self, "return_fraction_", 1.0) < 1.0:  # older files: 1, symmetric
                emulation["return_fraction"] = float(self.return_fraction_)
        return skill_file.to_document(
            params,
            n_dims=self.n_dims_,
            units=self.units,
            path=self.path_,
            mimic_info=self.mimic_info_,
            reward=reward,
            ioc_info=self.ioc_info_,
            timing=timing.to_dict() if learned else None,
            orientations=self.orientations_,
            emulation=emulation,
            # The fitted DMPs as they plan: loading restores them, never refits (issue 30).
            dmp={k: v for k, v in self.dmp_.to_state().items() if k != "path"},
            orientation_dmp=self._stored_orientation_dmp(),
            promp=None if getattr(self, "promp_", None) is None else self.promp_.to_state(),
        )

    def _stored_orientation_dmp(self) -> dict[str, Any] | None:
        """The orientation DMP's state for the file; None (refit on load) when too long.

        It holds its own training samples (``max(1000, 10 n)`` for a path of
        ``n`` points): beyond :data:`_MAX_STORED_ORIENTATION_SAMPLES` the file
        would outgrow :data:`MAX_SKILL_FILE_BYTES`, so that rare skill refits it.
        """
        dmp = self.orientation_dmp_
        if dmp is None or len(dmp.dmp_.path_) > _MAX_STORED_ORIENTATION_SAMPLES:
            return None
        return dmp.to_state()

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, source: str = "skill") -> Skill:
        """Rebuild a skill from :meth:`to_dict`'s output.

        The fields are read by :class:`lfdkit.io.skill_file.SkillDocument`;
        the skill checks its parameters, restores the DMP as fitted (refits
        it on the path for a file without ``dmp``) and rebuilds the reward
        from them, in that order.

        Raises
        ------
        ValueError
            For another format, a newer version, or a missing or broken field;
            the message starts with ``source`` and names the field.
        """
        document = skill_file.SkillDocument(data, source)
        params = document.params(cls().get_params())
        units = document.units()
        if units is not None:  # a file without it (or without params.units) is in metres
            stated = params.setdefault("units", units)
            if stated != units:
                raise ValueError(
                    f"{source}: units: {units!r} does not match params.units {stated!r}"
                )
        try:
            skill = cls(**params)
            skill._validate_params()
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{source}: params: {exc}") from None
        n_dims = document.n_dims()
        path = document.path(n_dims)
        raw_timing = document.timing()
        timing = None
        if raw_timing is not None:
            timing = SpeedProfile.from_dict(raw_timing, f"{source}: timing")
        orientations = document.orientations(len(path))
        try:
            fitted = _stored_dmps(skill, document, path, timing, orientations)
            skill._use_path(path, "given", timing, orientations, fitted)
            skill.mimic_info_ = document.mimic()
            skill.promp_ = _stored_promp(document, n_dims)
            reward = document.reward(n_dims)
            if reward is not None:
                weight, matrices = reward
                skill.adopt(Reward(weight, matrices, document.swerve()))
            skill.ioc_info_ = document.ioc()
            emulation = document.emulation()
            if emulation is not None and skill.reward_ is not None:
                skill.route_, skill.clearances_, skill.frame_, skill.gaps_ = emulation
                skill.class_radii_ = document.class_radii()
                skill.side_preferences_ = document.side_preferences()
                skill.return_fraction_ = document.return_fraction()
                fit = skill.ioc_info_ or {}
                skill.training_fidelity_ = fit.get("training_fidelity")
                skill.model_selection_ = fit.get("model_selection")
            _check_learned_classes(skill)
        except ValueError as exc:
            if str(exc).startswith(source):
                raise
            raise ValueError(f"{source}: {exc}") from None
        return skill


def _check_learned_classes(skill: Skill) -> None:
    """Refuse a skill whose ``params.classes`` contradicts the classes its reward learned.

    The reward fit (``ioc`` summary) learned its classes with ``params.classes``:
    each of them is one of those and is in the reward. Classes adopted from
    another skill are in the reward but not in the summary, so they pass.
    """
    learned = (skill.ioc_info_ or {}).get("classes")
    if skill.classes is None or not isinstance(learned, list):
        return
    reward = tuple(skill.reward_.classes) if getattr(skill, "reward_", None) is not None else ()
    stray = [c for c in learned if c not in skill.classes or c not in reward]
    if stray:
        raise ValueError(
            f"params.classes: {list(skill.classes)} contradicts the classes the reward learned "
            f"({learned}; reward: {list(reward)}): class {stray[0]!r}; the file was edited or "
            "damaged: learn the skill again"
        )


# ------------------------------------------------------------------ helpers
def _stored_dmps(
    skill: Skill,
    document: skill_file.SkillDocument,
    path: np.ndarray,
    timing: SpeedProfile | None,
    orientations: np.ndarray | None,
) -> tuple[DMP, QuaternionDMP | None] | None:
    """The DMPs a skill file stores, restored and checked against the skill; None to refit.

    None for a file without them (before issue 30). A state that does not
    belong to this skill (another path, timing, basis count or scaling) is
    refused: planning with it would not be what the file says.
    """
    state = document.dmp()
    if state is None:
        if not isinstance(skill.n_basis, str) and skill.n_basis > skill_file.MAX_REFIT_BASIS:
            raise ValueError(
                f"params.n_basis: {skill.n_basis} basis functions, but no fitted DMP (dmp) to "
                f"restore; a file without it holds at most {skill_file.MAX_REFIT_BASIS} "
                "(refitting more takes tens of seconds): save the skill again with this lfdkit"
            )
        return None
    dmp = DMP.from_state({**state, "path": path}, "dmp")
    law = timing or SpeedProfile.from_law(skill.timing, skill._law_duration(path))
    wanted = {
        "duration": (dmp.duration_, law.duration),
        "params.scaling": (dmp.scaling, skill.scaling),
        "params.n_basis": (dmp.n_basis, skill.n_basis),
        "timing": (
            dmp.timing_ is not None and tuple(dmp.timing_.coefficients),
            tuple(law.coefficients),
        ),
    }
    for name, (stored, expected) in wanted.items():
        if stored != expected:
            said = "another speed profile" if name == "timing" else f"{stored!r}"
            raise ValueError(
                f"dmp.{name}: the stored DMP was fitted with {said}, not the skill's; "
                "remove the dmp field to refit"
            )
    orientation_state = document.orientation_dmp()
    if orientations is None or orientation_state is None:
        return dmp, None  # a skill with orientations but none stored: fitted again
    return dmp, QuaternionDMP.from_state(orientation_state, "orientation.dmp")


def _stored_promp(document: skill_file.SkillDocument, n_dims: int) -> ProMP | None:
    """The file's ProMP (:attr:`Skill.promp_`), of the skill's dimension; None without."""
    state = document.promp()
    if state is None:
        return None
    promp = ProMP.from_state(state, f"{document.source}: promp")
    if promp.n_dims_ != n_dims:
        raise ValueError(
            f"{document.source}: promp.n_dims: {promp.n_dims_}, but the path is {n_dims}-D"
        )
    return promp
