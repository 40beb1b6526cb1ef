"""What a fitted skill plans: the nominal (the DMP's rollout), timed plans and their details.

:meth:`Skill.plan <lfdkit.skill.Skill.plan>` retargets the generalized path
(the *nominal*) and moves along it around a scene's obstacles with the
behaviour model the skill chose (route planner, clearance floor, frame); a
plan around moving obstacles is re-planned at its own times up to
:data:`RETIME_ROUNDS` times before it is refused.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import warnings
from collections.abc import Mapping, Sequence
from typing import Any, Literal

import numpy as np

from lfdkit.core.constraints import OneOf
from lfdkit.core.options import (
    PLANNERS,
)
from lfdkit.core.progress import ProgressLike
from lfdkit.core.units import UnitsWarning, conversion_factor, misplaced_units
from lfdkit.core.validation import (
    check_horizon,
    check_point,
    check_positive,
)
from lfdkit.emulate import Corridor, Plan, Reward, UnsafePlanError, plan_path
from lfdkit.emulate.fidelity import same_sides
from lfdkit.emulate.gaps import (
    GAP_STANDARD_ERRORS,
    SIDE_BLOCKER,
    abreast_pairs,
    bridge_blockers,
    close_declined_gaps,
    close_narrow_gaps,
    closes_a_threaded_gap,
    gaps_closed_by,
    held_pairs,
    open_gap_margins,
    passable_pairs,
    passes_a_new_gap,
    preferred_side_blockers,
    preferred_side_margins,
    side_blockers,
    threaded_pairs,
)
from lfdkit.emulate.problem import UNCERTAINTY_MARGIN
from lfdkit.emulate.reward import in_path_frame, unshown_widths
from lfdkit.emulate.taut import taut_plan
from lfdkit.imitate.timing import DURATION_RANGE
from lfdkit.model.half_space import HalfSpace
from lfdkit.model.scene import Obstacle, Scene
from lfdkit.model.timed_path import TimedPlan
from lfdkit.skill.unknown import UNKNOWN_HOW, unknown_margins, warn_unknown, with_stand_ins
from lfdkit.skill.via import passing_phases, path_extent, warn_via_missed

PlannerKind = Literal["mpc", "full"]
# Samples of a DMP rollout handed to the planner, which resamples it at
# constant speed: dense enough that the resampled nominal follows the curve.
_NOMINAL_OVERSAMPLING = 4
#: Re-plans of a moving-obstacle plan at its own (arc-length) times before it is refused.
RETIME_ROUNDS = 3


class Planning:
    """What a fitted :class:`~lfdkit.skill.Skill` plans: the nominal, timed plans, their details."""

    def _rollouts(self, starts: np.ndarray, goals: np.ndarray) -> np.ndarray:
        n_steps = _NOMINAL_OVERSAMPLING * int(self.n_points)
        # Starts and goals come checked (_ends, _goals, check_demos): not again in the DMP.
        return self.dmp_.rollout(starts, goals, n_steps=n_steps, check_input=False).positions

    def nominal(self, start: Any = None, goal: Any = None) -> np.ndarray:
        """The generalized path carried to a new start and goal by the DMP.

        Parameters
        ----------
        start, goal : array_like, shape (q,), optional
            Default: the generalized path's own.

        Returns
        -------
        ndarray, shape (4 n_points, q)
            DMP rollout positions at equal time steps (denser where the
            skill's speed profile is slow, e.g. at the ends).
        """
        return self._nominal(*self._ends(start, goal))

    def _ends(self, start: Any, goal: Any) -> tuple[np.ndarray, np.ndarray]:
        """The start and goal a caller gave, checked (default: the generalized path's)."""
        self._check_fitted()
        q = self.n_dims_
        start = self.path_[0] if start is None else check_point(start, "start", q, style="point")
        goal = self.path_[-1] if goal is None else check_point(goal, "goal", q, style="point")
        return start, goal

    def _nominal(self, start: np.ndarray, goal: np.ndarray) -> np.ndarray:
        """:meth:`nominal` from a checked start and goal."""
        tol = 1e-12 * path_extent(self.path_)
        # A closed skill (an "o") goes from a point back to it; an open one cannot.
        closed = np.allclose(self.path_[0], self.path_[-1], rtol=0.0, atol=tol)
        if not closed and np.allclose(start, goal, rtol=0.0, atol=tol):
            raise ValueError("goal: coincides with start; a path needs distinct ends")
        return self._rollouts(start[None], goal[None])[0]

    def plan(
        self,
        start: Any = None,
        goal: Any = None,
        scene: Scene | None = None,
        *,
        duration: float | None = None,
        speed: float | None = None,
        start_orientation: Any = None,
        goal_orientation: Any = None,
        **options: Any,
    ) -> TimedPlan:
        """The timed plan for a new start, goal and scene: positions, times and velocities.

        The path is :meth:`plan_details`' (its keyword ``options``:
        ``planner``, ``horizon``, ``goal_approach``, ``clearance``,
        ``unknown_class``; its errors
        and safety guarantees), timed by its own arc length with the skill's
        speed profile :attr:`timing_` (learned from the demonstrations' times,
        or the ``timing`` law): it starts and ends at rest (unless the timing
        is ``"uniform"``) and lasts the skill's duration, so a plan that
        swerves (and is longer) runs uniformly faster, never in a burst where
        it swerves. With moving obstacles the timed plan is checked again at
        its own times (the planner used the nominal's) and re-planned at them
        where it is not clear (:meth:`_checked_at_own_times`); its
        ``details.clearance`` is then the clearance at its own times.

        Parameters
        ----------
        start, goal : array_like, shape (q,), optional
            Default: the generalized path's own.
        scene : Scene, optional
            Obstacles (default none).
        duration : float, optional
            Seconds the plan lasts (default ``timing_.duration``).
        speed : float, optional
            Or a speed factor: the plan lasts ``timing_.duration / speed``
            (2 runs twice as fast). Not with ``duration``.
        start_orientation, goal_orientation : array_like, shape (4,), optional
            Only for a skill with orientation (:attr:`orientation_dmp_`): the
            tool's orientation at the start and at the goal, unit quaternions
            ``[x, y, z, w]``; default the first and last of
            :attr:`orientations_`.
        **options
            :meth:`plan_details`' keywords, ``via`` among them: ``[(phase,
            point), ...]``, points the plan passes at those fractions of its
            duration (:meth:`via_path`). The nominal passes each exactly; the
            plan, resampled at constant speed, within a small fraction of the
            path's extent, and around obstacles as the planner must (a
            :class:`UserWarning` says when a plan misses a via-point by more
            than :data:`VIA_TOLERANCE` of the path's extent). A skill with
            orientation takes ``(phase, point, [x, y, z, w])``: the
            orientations are turned to that one at the time the plan passes
            ``point`` (:meth:`orientations_at`), start and goal kept.

        Returns
        -------
        TimedPlan
            ``times`` (n_points,) s, ``points`` (n_points, q), ``velocities``
            (n_points, q) units/s, ``details`` (:meth:`plan_details`' Plan),
            and for a skill with orientation ``orientations`` (n_points, 4):
            the orientation DMP's movement from ``start_orientation`` to
            ``goal_orientation``, sampled at each point's normalised time
            ``t / duration`` (the phase the position DMP and the speed
            profile share), so it ends *exactly* at the goal orientation.
            It stands for its points in NumPy expressions (``np.asarray(plan)``
            is ``plan.points``), as the ndarray this method used to return.

        Raises
        ------
        ValueError
            For a ``duration`` or ``speed`` that is not a positive, finite
            number, both given, or a duration outside 1e-6 to 1e9 s; an
            orientation that is not a unit quaternion, or one given to a
            skill without orientation; and :meth:`plan_details`' errors.
        """
        total = self._plan_duration(duration, speed)
        if scene is not None and isinstance(scene, Scene) and scene.moving:
            options.setdefault("duration", total)  # where the tool is when: this plan's timing
        ends = self._orientation_ends(start_orientation, goal_orientation)
        turns = self._via_orientations(options.get("via"), ends is not None)
        details = self.plan_details(start, goal, scene, **options)
        times, velocities = self.timing_.time_path(details.points, total)
        if scene is not None and isinstance(scene, Scene) and scene.moving:
            details, times, velocities = self._checked_at_own_times(
                details, times, velocities, total, start, goal, scene, options
            )
        orientations = None
        if ends is not None:
            if turns is not None:
                turns = (passing_phases(details.points, times, options["via"], turns[0]), turns[1])
            orientations = self._orientations_at(times / total, *ends, via=turns)
        if options.get("via") is not None:
            warn_via_missed(details.points, options["via"], self.units)
        return TimedPlan(
            times, details.points, velocities, details=details, orientations=orientations
        )

    def _checked_at_own_times(
        self,
        details: Plan,
        times: np.ndarray,
        velocities: np.ndarray,
        total: float,
        start: Any,
        goal: Any,
        scene: Scene,
        options: dict[str, Any],
    ) -> tuple[Plan, np.ndarray, np.ndarray]:
        """A moving-obstacle plan checked at the times it is run; re-planned at them if needed.

        The planner avoids each obstacle where it is when the tool reaches a
        point on the *nominal's* timing (:meth:`point_times`); the plan is then
        timed by its own arc length, a little different where it swerves (the
        issue-27 battery: 1.58 mm inside a marker crossing at 4 m/s, 14 ms
        later than planned). So the timed plan is checked at its own times
        (:func:`lfdkit.emulate.planner.moving_clearance`); where it fails, it
        is re-planned with those times and re-timed, up to
        :data:`RETIME_ROUNDS` rounds, and refused if it still fails.
        """
        from lfdkit.emulate.planner import UnsafePlanError, moving_clearance

        clearance = float(options.get("clearance", 0.0))
        margin = options.get("unknown_class")
        reward = self.reward_ if self.reward_ is not None else Reward(1.0, {})
        unknown, margin = unknown_margins(reward, scene, margin, clearance)
        clearance = clearance + np.where(unknown, margin, 0.0)  # each obstacle's
        hard = scene.has_extent | (clearance > 0.0)
        start_point, goal_point = self._ends(start, goal)
        for round_ in range(RETIME_ROUNDS + 1):
            gaps = moving_clearance(details.points, times, scene, clearance, UNCERTAINTY_MARGIN)
            tolerance = 1e-9 * max(path_extent(details.points), 1e-300)
            if not np.any((gaps < -tolerance) & hard):
                details.clearance = gaps
                return details, times, velocities
            if round_ == RETIME_ROUNDS:
                break
            details = self._plan(
                start_point,
                goal_point,
                scene,
                options.get("planner"),
                options.get("horizon"),
                options.get("goal_approach", "auto"),
                clearance,
                options.get("progress"),
                times,
                unknown_class=options.get("unknown_class"),
                via=options.get("via"),
                unknown_response=options.get("unknown_response"),
            )
            times, velocities = self.timing_.time_path(details.points, total)
        o = int(np.argmin(np.where(hard, gaps, np.inf)))
        raise UnsafePlanError(
            f"no collision-free timed plan: timed by its own length, the plan passes "
            f"{-gaps[o]:.3g} inside obstacle {o} ({scene.obstacles[o].label!r}, radius plus "
            f"clearance {clearance[o]:g}) even after {RETIME_ROUNDS} re-plans at its own times; "
            "a longer duration or a larger clearance may help"
        )

    def _plan_duration(self, duration: float | None, speed: float | None) -> float:
        """Seconds a plan lasts: ``duration``, or the skill's divided by ``speed``."""
        self._check_fitted()
        if duration is not None and speed is not None:
            raise ValueError("speed: give duration or speed, not both")
        if duration is not None:
            total = check_positive(duration, "duration")
        else:
            factor = 1.0 if speed is None else check_positive(speed, "speed")
            total = self.timing_.duration / factor
        low, high = DURATION_RANGE
        if not low <= total <= high:
            what = "duration" if duration is not None else "speed"
            raise ValueError(
                f"{what}: the plan would last {total:g} s; expected {low:g} to {high:g} s"
            )
        return total

    def plan_details(
        self,
        start: Any = None,
        goal: Any = None,
        scene: Scene | None = None,
        *,
        planner: PlannerKind | None = None,
        horizon: int | None = None,
        goal_approach: float | str | None = "auto",
        clearance: float = 0.0,
        progress: ProgressLike = None,
        duration: float | None = None,
        unknown_class: float | None = None,
        via: Sequence[tuple[float, Any]] | None = None,
        unknown_response: str | None = None,
    ) -> Plan:
        """The path for a new start, goal and scene: DMP-retargeted nominal, then MPC.

        Parameters
        ----------
        start, goal : array_like, shape (q,), optional
            Default: the generalized path's own.
        scene : Scene, optional
            Obstacles (default none); each class must have been learned.
        planner : {"mpc", "full"}, optional
            Override the skill's planner.
        horizon : int, optional
            Override the MPC horizon (4 to 12).
        goal_approach : float, "auto" or None
            Length (units of the path) before the goal over which the plan is
            drawn back onto the nominal so that it ends at the goal; "auto"
            (the default) is a tenth of the path. None: the thesis's reward,
            which has no goal term; a swerve can leave the plan's end beside
            the goal. See :func:`lfdkit.emulate.planner.goal_weights`.
        clearance : float
            Tool clearance (units) added to every obstacle's radius; the plan
            keeps out of radius plus clearance (a hard constraint). With
            ``model="auto"`` the clearance the demonstrations kept from the
            obstacle's class (:attr:`clearances_`) comes on top (halved for
            an obstacle nearer the start or goal than that; where no plan
            keeps it, or where keeping it moves the route from the plan
            without it (:attr:`gaps_`), half of it and then none, with a
            warning), and the plan's ``clearance`` is measured beyond both.
        progress : Progress, callable, bool or None
            Reports the planner's global search and its MPC steps over the
            plan's points (:func:`lfdkit.core.progress.as_progress`); default silent.
        duration : float, optional
            Seconds the plan lasts (default ``timing_.duration``): with moving
            obstacles in ``scene``, the tool reaches plan point ``k`` at
            ``point_times()[k]`` and each obstacle is avoided where it
            is predicted then (:func:`lfdkit.emulate.plan_path`'s ``times``).
            Not used for a static scene.
        unknown_class : float, optional
            Opt-in for obstacles of a class this skill never learned: a margin
            (units, >= 0). Each such obstacle becomes a hard constraint, its
            radius plus this margin (plus ``clearance``), with *no* learned
            response (the plan keeps out but does not swerve as a demonstrator
            would); a ``UserWarning`` names the classes. Default None: such a
            scene is refused (the error names this option).
        via : sequence of (float, array_like (q,)), optional
            Via-points ``(phase, point)``: the nominal is bent through each
            ``point`` at ``phase``, the fraction of the movement's duration
            (strictly between 0 and 1), the way the demonstrations varied
            (:meth:`via_path`); the planner then follows it.
        unknown_response : str, optional
            With ``unknown_class``, the response such an obstacle gets besides
            its hard radius: None (default) none; ``"nearest"`` the response of
            the learned class nearest in size (:attr:`class_radii_` against
            the median radius of the class's obstacles in ``scene``); or the
            name of a learned class. The warning says which class was used.

        Returns
        -------
        Plan
            ``points`` (n_points, q), the planned path from ``start`` (with no
            obstacle, the nominal resampled at constant speed), with its
            ``clearance``, ``goal_error`` and ``cost``.

        Raises
        ------
        lfdkit.emulate.UnsafePlanError
            When no plan within the action bounds keeps out of the obstacles
            and reaches the goal.
        ValueError
            For a start or goal of the wrong dimension or not finite, a scene
            with an obstacle class this skill has not learned (or with
            obstacles when no reward is learned) unless ``unknown_class`` is
            given, a negative ``unknown_class``, an ``unknown_response`` that
            is neither ``"nearest"`` nor a learned class (or ``"nearest"`` for
            a skill without :attr:`class_radii_`), a start or goal inside an
            obstacle, a horizon outside 4-12, a negative or non-finite
            ``clearance``, or a via-point that is not a
            ``(phase, point)`` pair with a phase in (0, 1) and a point of the
            skill's dimension.
        """
        given = {"start": start, "goal": goal}
        start, goal = self._ends(start, goal)
        if horizon is not None:  # checked even where the route plans without one
            check_horizon(horizon)
        # Checked even without obstacles: a negative margin is a mistake whatever the scene.
        clearance = check_positive(clearance, "clearance", allow_zero=True)
        if isinstance(scene, Scene) and len(scene):
            q = self.n_dims_
            wrong = next((i for i, o in enumerate(scene) if np.size(o.position) != q), None)
            if wrong is not None:
                raise ValueError(
                    f"scene: obstacle {wrong} ({scene.labels[wrong]!r}) has "
                    f"{np.size(scene.obstacles[wrong].position)} coordinates for a {q}-D skill; "
                    f"give every obstacle {q}"
                )
        self._warn_misplaced(
            {name: point for name, point in given.items() if point is not None}, scene
        )
        times = None
        if isinstance(scene, Scene) and scene.moving:
            times = self.point_times(duration)
        return self._plan(
            start,
            goal,
            scene,
            planner,
            horizon,
            goal_approach,
            clearance,
            progress,
            times,
            unknown_class=unknown_class,
            via=via,
            unknown_response=unknown_response,
        )

    def _warn_misplaced(self, points: Mapping[str, Any], scene: Scene | None) -> None:
        """Warn (:class:`UnitsWarning`) for a start, goal or obstacle given in another unit.

        A goal typed in metres for a skill in millimetres is a valid point near
        the origin: the plan would run to it without a word. Each point given
        far outside the generalized path's box that another unit brings inside
        it (:func:`lfdkit.core.units.misplaced_units`) is named, with its unit.
        """
        low, high = self.path_.min(axis=0).tolist(), self.path_.max(axis=0).tolist()
        named = [(name, np.asarray(point, float).ravel(), 0.0) for name, point in points.items()]
        if isinstance(scene, Scene):
            named += [
                (
                    f"scene: obstacle {i} ({o.label!r})",
                    np.asarray(o.position, float).ravel(),
                    obstacle_extent(o),
                )
                for i, o in enumerate(scene)
                if not isinstance(o, HalfSpace) and np.size(o.position) == len(low)
            ]
        for name, point, size in named:
            likely = misplaced_units(point.tolist(), low, high, self.units, size=size)
            if likely is None:
                continue
            shown = ", ".join(f"{v:.4g}" for v in point)
            factor = conversion_factor(likely, self.units)
            detail = f"{name}: ({shown}) {self.units} lies far from the skill's workspace"
            why = (
                f"{detail} (its path spans {path_extent(self.path_):.4g} {self.units}); "
                f"in {likely} it would lie within it"
            )
            if misplaced_units(point.tolist(), low, high, self.units) is None:  # by its size
                detail = f"{name}: {size:.3g} {self.units} across is smaller than any obstacle"
                why = (
                    f"{detail}; in {likely} it would be {size * factor:.4g} {self.units} across "
                    "and lie among the demonstrations"
                )
            warnings.warn(
                UnitsWarning(
                    f"{why}: if it is in {likely}, multiply it by {factor:g} or plan with "
                    f"skill.to_units({likely!r})",
                    likely=likely,
                    detail=detail,
                ),
                stacklevel=4,
            )

    def point_times(self, duration: float | None = None) -> np.ndarray:
        """When the tool reaches each of the plan's ``n_points`` points (s), on the nominal.

        The skill's speed profile (:attr:`timing_`) along a path sampled at
        constant arc length: point ``k`` is reached at
        ``duration · phase(k / (n_points − 1))``
        (:meth:`lfdkit.imitate.SpeedProfile.phase`). A plan that swerves is a
        little longer; timed by its own length it runs uniformly faster, so
        point ``k`` is reached at nearly the same time (the assumption with
        which moving obstacles are predicted).

        Parameters
        ----------
        duration : float, optional
            Seconds (default ``timing_.duration``).

        Returns
        -------
        ndarray, shape (n_points,)
        """
        total = self._plan_duration(duration, None)
        return total * self.timing_.phase(np.linspace(0.0, 1.0, int(self.n_points)))

    def _plan(
        self,
        start: np.ndarray,
        goal: np.ndarray,
        scene: Scene | None,
        planner: PlannerKind | None,
        horizon: int | None,
        goal_approach: float | str | None,
        clearance: float,
        progress: ProgressLike = None,
        times: np.ndarray | None = None,
        *,
        route: str | None = None,
        unknown_class: float | None = None,
        via: Sequence[tuple[float, Any]] | None = None,
        reward: Reward | None = None,
        clearances: Mapping[str, float] | None = None,
        gaps: str | None = None,
        frame: str | None = None,
        unknown_response: str | None = None,
        gap_clearances: Mapping[str, float] | None = None,
        sided: Sequence[Obstacle] | None = None,
        sided_margins: np.ndarray | None = None,
        return_fraction: float | None = None,
    ) -> Plan:
        """:meth:`plan_details` from a checked start and goal.

        ``route``, ``reward``, ``clearances`` and ``frame`` default to the
        skill's (:attr:`route_`, :attr:`reward_`, :attr:`clearances_`,
        :attr:`frame_`); the model choice plans with others. ``via`` bends the
        nominal through via-points (:meth:`via_path`). ``gap_clearances``
        (``{class: units}``, the clearance the demonstrations typically kept):
        with gaps closed, every gap narrower than the two obstacles' together
        is closed (:func:`lfdkit.emulate.gaps.close_narrow_gaps`); default the
        skill's own (``model_selection_["gap_clearances"]``, each widened by
        its ``model_selection_["gap_allowance"]``, warned where that closes a
        gap) for its own plans, none for a candidate's. ``sided``: the balls that keep each
        obstacle of a class passed by preference on its side
        (:meth:`_sided_blockers`; default: found here, and where no plan keeps
        them, none, warned); ``sided_margins`` (n_obstacles,), the clearance
        each obstacle kept on its side keeps (units, at least; found with them).
        ``return_fraction``: the receding horizon's bound on the step back
        toward the nominal (``plan_path``'s; default the skill's
        :attr:`return_fraction_`; a full-horizon plan has none).
        """
        if via is None:
            nominal = self._nominal(start, goal)
        else:
            nominal = self.via_path(via, start, goal).points
        scene = Scene() if scene is None else scene
        if not isinstance(scene, Scene):
            raise TypeError(f"scene: expected a Scene, got {type(scene).__name__}")
        if reward is None and sided is None and route is None and frame is None:
            self._warn_unshown_directions(nominal, scene)  # the skill's own plan, said once
        # Planning again with what this call was given: with the side blockers found here,
        # or with a fitted swerve's reward (issue 26).
        again = functools.partial(
            self._plan,
            start,
            goal,
            scene,
            planner,
            horizon,
            goal_approach,
            clearance,
            progress,
            times,
            route=route,
            unknown_class=unknown_class,
            via=via,
            clearances=clearances,
            gaps=gaps,
            frame=frame,
            unknown_response=unknown_response,
            return_fraction=return_fraction,
        )
        if sided is None:
            sided, sided_margins = self._sided_blockers(nominal, scene, start, goal)
            bridges = self._held_bridges(nominal, scene, start, goal, clearance, clearances)
            if bridges:
                try:
                    return again(
                        reward=reward,
                        gap_clearances=gap_clearances,
                        sided=[*sided, *bridges],
                        sided_margins=sided_margins,
                    )
                except UnsafePlanError:
                    warnings.warn(
                        "plan: no plan goes round both obstacles of each pair one behind the "
                        "other that the demonstrated swerve holds past; planned without that",
                        UserWarning,
                        stacklevel=4,
                    )
            if sided:
                try:
                    return again(
                        reward=reward,
                        gap_clearances=gap_clearances,
                        sided=sided,
                        sided_margins=sided_margins,
                    )
                except UnsafePlanError:
                    classes = sorted({o.label for o in scene if o.label in self.side_preferences_})
                    warnings.warn(
                        f"plan: no plan passes every {', '.join(map(repr, classes))} on the side "
                        "the demonstrations kept it on; planned the way the learned response "
                        "passes it",
                        UserWarning,
                        stacklevel=4,
                    )
                    return again(reward=reward, gap_clearances=gap_clearances, sided=())
        if reward is None and len(scene) > 1 and not scene.moving:
            route_reward = self._swerve_route_reward()
            if route_reward is not None:  # a swerve's widths, the route among several: issue 26
                return self._swerve_routed(
                    lambda fitted: again(reward=fitted, sided=sided, sided_margins=sided_margins),
                    route_reward,
                    nominal,
                    scene,
                )
        kind = self.planner if planner is None else planner
        OneOf(PLANNERS)(kind, "planner")
        # No route learned (a reward adopted, an older file): the MPC with lookahead, as before.
        route = route or getattr(self, "route_", None) or self._unfitted_route()
        # The taut route (a person who keeps a margin and otherwise takes the shortest
        # way): where it finds no path, the full-horizon plan with the same floor.
        taut, route = route == "taut", "full" if route == "taut" else route
        if kind == "mpc" and (route != "full" or planner == "mpc"):
            h = int(self.horizon) if horizon is None else horizon
        else:
            h = None
        reward = self.reward_ if reward is None else reward
        if reward is None:
            if len(scene) and unknown_class is None:
                raise ValueError(
                    "scene: has obstacles, but this skill has no obstacle reward; learn one "
                    "with fit_reward() (demonstrations around obstacles) or adopt() it; "
                    f"{UNKNOWN_HOW}"
                )
            reward = Reward(1.0, {})
        unknown, margin = unknown_margins(reward, scene, unknown_class, clearance)
        responses = self._stand_in_classes(reward, scene, unknown, unknown_response)
        unknown_margin = np.where(unknown, margin, 0.0)
        if unknown.any():
            reach = scene.radii + clearance + unknown_margin
            reward = with_stand_ins(reward, scene, unknown, reach, responses)
            warn_unknown(
                scene, unknown, margin, self.units, responses, getattr(self, "class_radii_", {})
            )
        options = dict(
            horizon=h,
            max_slope=float(self.max_slope),
            goal_approach=goal_approach,
            progress=progress,
            times=times,
            lookahead=route != "window",
            # As steep a way back to the goal as the demonstrations swerved, where the
            # route's sides need it (older skill files: none steeper than max_slope).
            return_slope=(getattr(self, "ioc_info_", None) or {}).get("demonstrated_slope") or None,
        )
        if return_fraction is None:  # the skill's own (older files: 1, symmetric)
            return_fraction = getattr(self, "return_fraction_", 1.0)
        if h is not None and return_fraction < 1.0:  # the receding horizon's alone
            options["return_fraction"] = return_fraction
        if gaps is None:
            gaps = getattr(self, "gaps_", "closed") if clearances is None else "closed"
        margins = self._margins(scene, start, goal, clearance, clearances)
        if margins is not None and gaps == "closed" and len(scene) > 1:
            allowance: Mapping[str, float] = {}
            if clearances is None:  # the skill's own plan: its own (older files: none)
                selection = getattr(self, "model_selection_", None) or {}
                gap_clearances = selection.get("gap_clearances")
                allowance = selection.get("gap_allowance") or {}
            kept = dict(gap_clearances or {})
            wide = {c: m + allowance.get(c, 0.0) for c, m in kept.items()}
            typical = self._margins(scene, start, goal, clearance, kept)
            if typical is not None:
                narrow = margins
                within = self._margins(scene, start, goal, clearance, wide)
                margins = close_narrow_gaps(margins, typical, scene, wide=within, path=nominal)
                if allowance and np.any(margins > narrow):
                    self._warn_allowance(scene, narrow, nominal, typical, within)
        # Gaps no wider than one the demonstrations went round stay closed, whatever the model
        # (gaps open or closed): the skill's own plans, where the training scenes showed one.
        declined = self._declined_clearances(scene, start, goal, clearance, clearances)
        declined_pairs: set[tuple[int, int]] = set()
        if margins is not None and declined is not None:
            margins, closed = close_declined_gaps(margins, *declined, scene, nominal)
            declined_pairs = set(closed)
            # Never more than the room the task's own start and goal leave (as _margins).
            room = self._margins(scene, start, goal, clearance, dict.fromkeys(scene.labels, np.inf))
            margins = np.minimum(margins, room)
        # The skill's own plan, not a candidate's; said once a plan is made (a refusal says
        # enough on its own line).
        gap_margins = margins if clearances is None else None
        # Past an obstacle kept on its side the learned response pushes the plan towards it (the
        # shorter way round): it keeps its class's clearance there, whatever the model's floor
        # and the gaps (lfdkit.emulate.gaps.preferred_side_margins), within the ends' room.
        side = None
        if sided_margins is not None and len(scene) and np.any(sided_margins > 0.0):
            ends_room = self._margins(
                scene, start, goal, clearance, dict.fromkeys(scene.labels, np.inf)
            )
            side = sided_margins if ends_room is None else np.minimum(sided_margins, ends_room)
        if taut and not scene.moving and self.n_dims_ == 2 and len(scene):
            kept = 0.0 if margins is None else margins
            kept = kept if side is None else np.maximum(kept, side)
            where, extra = scene, clearance + unknown_margin + kept
            if sided:  # kept out of as hard radii, as the planner's (below)
                where = Scene(scene.obstacles + tuple(sided))
                extra = np.concatenate([np.broadcast_to(extra, len(scene)), np.zeros(len(sided))])
            shortest = taut_plan(
                nominal,
                where,
                extra,
                n_points=int(self.n_points),
                max_slope=float(self.max_slope),
            )
            if shortest is not None and sided:
                shortest = dataclasses.replace(shortest, clearance=shortest.clearance[: len(scene)])
            if shortest is not None:
                if gap_margins is not None:
                    self._warn_gaps(scene, gap_margins, gaps)
                return shortest
        frame = frame or getattr(self, "frame_", "world")
        if (self.model == "path" or frame == "path") and len(scene) and not scene.moving:
            reward, scene = self._in_path_frame(reward, scene, nominal)
        # The thesis's MPC can walk into a dead end the lookahead sees: then that.
        routes = [route] + (["lookahead"] if route == "window" and h is not None else [])

        # The model choice plans each scene without a floor several times (its reference,
        # each safety floor's route check): planned once per reward while it runs.
        memo = getattr(self, "_free_plans", None)
        ends = start.tobytes() + goal.tobytes() + np.asarray(clearance, dtype=float).tobytes()
        key = (
            tuple(routes),
            id(scene),
            ends,
            h,
            b"".join(b.position.tobytes() for b in sided),
            options.get("return_fraction", 1.0),
        )
        # Every attempt moves along the same nominal: resampled and framed once.
        corridor = Corridor.from_path(nominal, int(self.n_points))

        def attempt(
            kept: np.ndarray | None, last: bool, blockers: Sequence[Obstacle] = ()
        ) -> Plan | None:
            """The plan keeping ``kept`` beyond radius + clearance, by the first route.

            ``blockers`` (:func:`~lfdkit.emulate.gaps.side_blockers`) are kept out of
            as well; the plan's clearances are then the scene's obstacles' alone.
            """
            if kept is None and memo is not None and key in memo and memo[key][0] is reward:
                return memo[key][1]
            blockers = [*sided, *blockers]
            extra = clearance + unknown_margin + (0.0 if kept is None else kept)
            where, response = scene, reward
            if blockers:
                where = Scene(scene.obstacles + tuple(blockers))
                extra = np.concatenate(
                    [np.broadcast_to(extra, len(scene)), np.zeros(len(blockers))]
                )
                # A response so narrow it is nil outside the blocker (as an unlearned class's).
                narrow = 1.0 / (0.01 * min(b.radius for b in blockers)) ** 2
                response = Reward(
                    reward.nominal_weight,
                    {**reward.precisions, SIDE_BLOCKER: np.full(scene.positions.shape[1], narrow)},
                    reward.swerve,
                    along_path=reward.along_path,
                )
            for way in routes:
                options["lookahead"] = way != "window"
                try:
                    plan = plan_path(response, corridor, where, clearance=extra, **options)
                except UnsafePlanError:
                    if last and way == routes[-1]:
                        raise
                    continue
                if blockers:
                    plan = dataclasses.replace(plan, clearance=plan.clearance[: len(scene)])
                    if len(blockers) > len(sided):  # a gap's: not the plan without a floor
                        return plan
                if kept is None and memo is not None and not unknown.any() and via is None:
                    memo[key] = (reward, plan)
                return plan
            return None

        free: Plan | None = None
        if margins is not None and gaps == "open":
            capped = open_gap_margins(margins, scene)
            if np.any(capped < margins):
                # The learned response decides which gaps to take: the plan with no floor
                # shows it; the floor gives way only between the obstacles it passes
                # between, where the gap is not narrower than the floor of either alone.
                free = attempt(None, last=False)
                pairs = None
                if free is not None:
                    pairs = threaded_pairs(free.points, scene)
                    # The skill's own plans only: the model choice's are what decides it.
                    if not (clearances is None and self._threads_gaps()):
                        pairs = passable_pairs(pairs, margins, scene)
                if declined_pairs:  # not those the person went round
                    n = len(scene)
                    every = [(i, j) for i in range(n) for j in range(i + 1, n)]
                    pairs = [
                        p for p in (every if pairs is None else pairs) if p not in declined_pairs
                    ]
                margins = open_gap_margins(margins, scene, pairs=pairs)
                if declined is not None:  # an obstacle's cap from a gap opened elsewhere
                    margins = np.minimum(
                        close_declined_gaps(margins, *declined, scene, nominal)[0], room
                    )
        if side is not None:
            margins = side if margins is None else np.maximum(margins, side)
        shares = (1.0, 0.5, 0.0) if margins is not None else (0.0,)
        # At least the clearance the demonstrations kept; where no plan keeps it
        # all (a narrow passage every way round), half of it, then none, said.
        # A floor must not move the route either: where the plan passes an
        # obstacle on another side than the plan without it (gaps open), or
        # between two it went round (closed), less of it (the plan without it
        # is planned too: a floor costs a second plan).
        moved = False
        for share in shares:
            kept = None if margins is None else share * margins
            if free is not None and share == 0.0:
                # None of the floor: the same clearances as the plan without it, planned above.
                plan = free
            else:
                plan = attempt(kept, last=share == 0.0)
            if plan is None:
                continue
            if kept is not None and share > 0.0 and (gaps == "closed" or declined_pairs):
                # A closed gap the learned response threads: round both on the side it
                # passes the first of the two (the floor alone may take either way round).
                if gaps_closed_by(kept, scene):
                    free = attempt(None, last=False) if free is None else free
                blocked = (
                    []
                    if free is None
                    else side_blockers(free.points, nominal, scene, kept, np.stack([start, goal]))
                )
                firsts = Scene(tuple(scene.obstacles[o] for o, _ in blocked))
                if blocked and not same_sides(plan.points, free.points, nominal, firsts):
                    blockers = [ball for _, ball in blocked]
                    plan = attempt(kept, last=False, blockers=blockers) or plan
            if kept is not None and share > 0.0:
                # Compared whether or not the floor touches the final plan: a receding
                # horizon it blocked part-way may have turned for good. Open gaps: to
                # another side of an obstacle (unless round a gap the floor keeps closed,
                # narrower than PASSABLE floors). Closed: through a gap the plan without it
                # went round (thesis person, 2x noise, seed 0: between two boxes, Pr 99 ->
                # 2 %); a floor closes gaps, it never opens one. Else the floor is kept
                # (the late person, seed 0: without it a new task's plan goes wild).
                check = gaps == "open" or bool(threaded_pairs(plan.points, scene))
                free = attempt(None, last=False) if free is None and check else free
                if free is not None and (
                    not same_sides(plan.points, free.points, nominal, scene)
                    and not closes_a_threaded_gap(kept, scene, free.points)
                    if gaps == "open"
                    else passes_a_new_gap(plan.points, free.points, scene)
                ):
                    moved = True
                    continue
            if margins is not None and share < 1.0:
                why = (
                    "keeping all of it takes another route round the obstacles than the "
                    "learned response"
                    if moved
                    else "no plan keeps all of it"
                )
                warnings.warn(
                    "plan: the clearance the demonstrations kept from the obstacles (up to "
                    f"{margins.max():.3g} {self.units}) is kept at {share:.0%}: {why}",
                    UserWarning,
                    stacklevel=4,
                )
            if gap_margins is not None:
                self._warn_gaps(scene, gap_margins, gaps)
            return plan
        raise AssertionError("unreachable")  # pragma: no cover

    def _sided_blockers(
        self, nominal: np.ndarray, scene: Scene, start: np.ndarray, goal: np.ndarray
    ) -> tuple[list[Obstacle], np.ndarray | None]:
        """Balls that keep each obstacle of a class passed by preference on its side, and margins.

        The skill's :attr:`side_preferences_` (``{class: {"side", "within",
        "clearance"}}``), for :func:`lfdkit.emulate.gaps.preferred_side_blockers`:
        in a static scene (2-D or 3-D), balls beside each such obstacle the
        nominal passes nearer than ``within``, on the side the person never
        passed it; and the clearance each obstacle keeps
        (:func:`lfdkit.emulate.gaps.preferred_side_margins`, shape
        (n_obstacles,); None where no obstacle is blocked or the file has no
        clearance). Empty without a preference (older skill files, a reward
        adopted).
        """
        preferences = getattr(self, "side_preferences_", None)
        if not preferences or not len(scene) or scene.moving or self.n_dims_ not in (2, 3):
            return [], None
        # The model choice replans each training scene with every candidate: found once.
        memo = getattr(self, "_sided_memo", None)
        key = (id(scene), nominal.tobytes(), start.tobytes(), goal.tobytes())
        if memo is not None and key in memo:
            balls, margins = memo[key][1:]
            return list(balls), None if margins is None else margins.copy()
        wanted = {c: (p["side"], float(p["within"])) for c, p in preferences.items()}
        ends = np.stack([start, goal])
        pairs = preferred_side_blockers(nominal, scene, wanted, ends, int(self.n_points))
        kept = {c: float(p["clearance"]) for c, p in preferences.items() if "clearance" in p}
        margins = preferred_side_margins(scene, (o for o, _ in pairs), kept) if pairs else None
        balls = [ball for _, ball in pairs]
        if memo is not None:  # the scene kept with them: its id is not another's meanwhile
            memo[key] = (scene, tuple(balls), None if margins is None else margins.copy())
        return balls, margins

    def _held_bridges(
        self,
        nominal: np.ndarray,
        scene: Scene,
        start: np.ndarray,
        goal: np.ndarray,
        clearance: float,
        clearances: Mapping[str, float] | None,
    ) -> list[Obstacle]:
        """Balls that keep the skill's own plan round both of each held pair, on one side.

        :func:`lfdkit.emulate.gaps.held_pairs` with the clearances the
        demonstrations typically kept (``model_selection_["gap_clearances"]``,
        less their ``model_selection_["gap_allowance"]`` for the overlap of
        the bands) and how long their swerve lasted (``model_selection_["swerve_reach"]``),
        closed by :func:`lfdkit.emulate.gaps.bridge_blockers`. Only for the
        skill's own plans (``clearances`` None) of a static 2-D scene with two
        obstacles or more, with a floor the skill keeps whole (gaps closed: a
        person shown to keep a clearance; a person answering a smooth reward
        threads what its response threads), and not for the taut route (a
        person who keeps a margin and otherwise takes the shortest way passes
        between any two obstacles that leave room for both margins).
        """
        selection = getattr(self, "model_selection_", None) or {}
        reach, typical = selection.get("swerve_reach"), selection.get("gap_clearances")
        if (
            clearances is not None
            or not reach
            or not typical
            or len(scene) < 2
            or scene.moving
            or self.n_dims_ != 2
            or getattr(self, "route_", None) == "taut"
            or getattr(self, "gaps_", "open") != "closed"
            or not getattr(self, "clearances_", None)
        ):
            return []
        kept = self._margins(scene, start, goal, clearance, typical)
        if kept is None:
            return []
        # Held only where the bands overlap beyond what few noisy demonstrations leave
        # uncertain in the clearances they kept.
        allowance = selection.get("gap_allowance") or {}
        sure = np.array([float(allowance.get(label, 0.0)) for label in scene.labels])
        pairs = held_pairs(scene, nominal, kept, (float(reach[0]), float(reach[1])), allowance=sure)
        return bridge_blockers(scene, pairs, nominal, kept, np.stack([start, goal]))

    def _declined_clearances(
        self,
        scene: Scene,
        start: np.ndarray,
        goal: np.ndarray,
        clearance: float,
        clearances: Mapping[str, float] | None,
    ) -> tuple[np.ndarray, float] | None:
        """What closes the gaps the demonstrations would go round; None for none.

        The clearances typically kept from each obstacle
        (``model_selection_["gap_clearances"]``, units) and the widest gap
        the training scenes showed the person declining, in those
        (``model_selection_["declined_gap"]``,
        :func:`lfdkit.emulate.gaps.declined_gap_width`), for
        :func:`lfdkit.emulate.gaps.close_declined_gaps`. Only for the skill's
        own plans (``clearances`` None) of a scene with two obstacles or more.
        """
        selection = getattr(self, "model_selection_", None) or {}
        width, typical = selection.get("declined_gap"), selection.get("gap_clearances")
        if clearances is not None or not width or not typical or len(scene) < 2:
            return None
        kept = self._margins(scene, start, goal, clearance, typical)
        return None if kept is None else (kept, float(width))

    def _warn_allowance(
        self,
        scene: Scene,
        margins: np.ndarray,
        nominal: np.ndarray,
        typical: np.ndarray,
        within: np.ndarray,
    ) -> None:
        """Warn where a gap across the path is closed only by the allowance for a clearance's error.

        ``typical``: the clearances typically kept (n_obstacles,), ``within``:
        with ``model_selection_["gap_allowance"]`` added (units); ``margins``
        the floors before either closed a gap.
        """
        closed = {(i, j) for i, j, _ in gaps_closed_by(typical, scene)}
        widened = {(i, j): gap for i, j, gap in gaps_closed_by(within, scene)}
        only = [
            (i, j, widened[i, j])
            for i, j in abreast_pairs(list(widened), scene, nominal)
            if (i, j) not in closed and margins[i] + margins[j] <= widened[i, j]
        ]
        if not only:
            return
        i, j, gap = min(only, key=lambda pair: pair[2])
        labels = scene.labels
        warnings.warn(
            f"plan: obstacles {i} ({labels[i]!r}) and {j} ({labels[j]!r}) leave a gap of "
            f"{gap:.3g} {self.units}, wider than the clearances the demonstrations kept from "
            f"them ({typical[i] + typical[j]:.3g} {self.units} together) but within "
            f"{GAP_STANDARD_ERRORS:g} standard errors of them ({within[i] + within[j]:.3g} "
            f"{self.units}: few demonstrations, with noise, learned them); this plan goes "
            f"around both ({len(only)} such gap(s) in this scene); show more demonstrations "
            f"near a {labels[i]!r} and a {labels[j]!r} to learn their clearances closer",
            UserWarning,
            stacklevel=4,
        )

    def _threads_gaps(self) -> bool:
        """Whether the demonstrations show a person who threads the gaps its response does.

        They do where planning the held-out ones with the closest any other
        came costs more than :data:`~lfdkit.skill.selection.CONSISTENT_CLEARANCE`
        times the error with no floor (``model_selection_["threads_gaps"]``):
        the person answers a smooth reward, not a margin, and where two
        responses sum to a minimum between two obstacles it passes there,
        closer to each than it came to a lone one (the thesis's person: 2.0-2.3
        cm from each of two boxes 4.5 cm apart, 4.1-5.0 cm from a lone one,
        seeds 1 and 2 of the fidelity benchmark). Then the safety floor gives
        way in every gap the learned response threads, not only in those
        :data:`~lfdkit.emulate.gaps.PASSABLE` floors wide.
        """
        return bool((getattr(self, "model_selection_", None) or {}).get("threads_gaps", False))

    def _warn_gaps(self, scene: Scene, margins: np.ndarray, gaps: str) -> None:
        """Warn where the learned clearances would close a gap the demonstrations never showed.

        Single-obstacle demonstrations cannot tell a person who threads a
        gap narrower than the clearance kept from one obstacle (the thesis's)
        from one who goes around both; the plan then follows :attr:`gaps_`,
        a guess, and says so.
        """
        closed = gaps_closed_by(margins, scene)
        if not closed or (getattr(self, "model_selection_", None) or {}).get("gaps_shown", 0) > 0:
            return
        i, j, gap = min(closed, key=lambda pair: pair[2])
        labels = scene.labels
        way = (
            "may pass between them (the clearances give way there, as for the thesis's person)"
            if gaps == "open"
            else "goes around both (it keeps the clearance from each)"
        )
        warnings.warn(
            f"plan: obstacles {i} ({labels[i]!r}) and {j} ({labels[j]!r}) leave a gap of "
            f"{gap:.3g} {self.units}, narrower than the clearances the demonstrations kept "
            f"from them ({margins[i] + margins[j]:.3g} {self.units} together; "
            f"{len(closed)} such gap(s) in this scene); no demonstration passed two obstacles "
            f"that close, so whether the person would pass between them is not known: this "
            f"plan {way}; show a demonstration next to two close obstacles to decide",
            UserWarning,
            stacklevel=5,
        )

    def _warn_unshown_directions(self, nominal: np.ndarray, scene: Scene) -> None:
        """Warn where the plan meets an obstacle running a way its class was never shown in,
        and the learned response's width there depends on which frame the person reacts in.

        Demonstrations passing a class's obstacles in one direction cannot tell a
        person who reacts in room axes (the thesis's model, what ``"auto"``
        plans) from one who reacts relative to the motion (``model="path"``);
        on a task that passes it another way the two differ
        (:func:`lfdkit.emulate.reward.unshown_widths`). Fidelity benchmark, seed
        11, in mm, the late swerver's new task (a diagonal): planned in room
        axes, Pr −2662 %, the box's response 1.4× as wide across the path as
        shown; relative to the motion, 94 %. Only ``model="auto"`` in 2-D with a
        learned response that is planned with (not the taut route).
        """
        if (
            self.model != "auto"
            or self.n_dims_ != 2
            or not len(scene)
            or scene.moving
            or self.reward_ is None
            or getattr(self, "frame_", "world") != "world"
            or getattr(self, "route_", None) == "taut"
        ):
            return
        info = self.ioc_info_ or {}
        shown = info.get("shown_directions")
        if shown is None:  # older files, an adopted reward: the direction it was learned along
            axis = np.asarray(info.get("frame_axis") or self.path_[-1] - self.path_[0], float)
            angle = math.atan2(axis[1], axis[0]) % math.pi
            shown = {label: [angle] for label in self.reward_.classes}
        found = unshown_widths(self.reward_, scene, nominal, shown)
        if not found:
            return
        i, degrees, across, along = max(found, key=lambda f: abs(math.log(f[2])))
        label = scene.labels[i]
        others = len(found) - 1
        more = f" (and {others} more obstacle{'s' * (others > 1)})" if others else ""
        warnings.warn(
            f"plan: obstacle {i} ({label!r}) is passed {degrees:.0f}° from every direction "
            f"the demonstrations passed a {label!r} in{more}; its learned response, kept in "
            f"room axes, is {across:.2g} times as wide across the path and {along:.2g} times "
            "along it as they showed, and whether the person reacts in room axes or relative "
            f"to the motion is not known from them: show a demonstration passing a {label!r} "
            "running this way, or, for a person who reacts relative to the motion, learn the "
            "skill with model='path' (lfdkit learn --model path)",
            UserWarning,
            stacklevel=4,
        )

    def _in_path_frame(
        self, reward: Reward, scene: Scene, nominal: np.ndarray
    ) -> tuple[Reward, Scene]:
        """The reward in the path frame: each response as shown, bent with ``nominal``."""
        if self.n_dims_ != 2:
            raise ValueError(
                f"model: 'path' turns responses in the plane only, this skill is "
                f"{self.n_dims_}-D; use model='auto'"
            )
        axis = (self.ioc_info_ or {}).get("frame_axis")
        if axis is None:  # a reward adopted: learned along this path, as far as is known
            axis = self.path_[-1] - self.path_[0]
        shown = (self.ioc_info_ or {}).get("shown_directions")
        return in_path_frame(reward, scene, nominal, np.asarray(axis, dtype=np.float64), shown)

    def _margins(
        self,
        scene: Scene,
        start: np.ndarray,
        goal: np.ndarray,
        clearance: float,
        clearances: Mapping[str, float] | None = None,
    ) -> np.ndarray | None:
        """The learned clearance of each obstacle of ``scene`` (units), or None for none.

        Where the task's own start or goal is nearer an obstacle than its
        class's learned clearance, that obstacle keeps half the distance (the
        plan must start and end there). Whole: where gaps stay open
        (:attr:`gaps_`), :meth:`_plan` lowers them between the obstacles its
        plan passes between.
        """
        learned = getattr(self, "clearances_", None) if clearances is None else clearances
        if not learned or not len(scene) or scene.moving:
            return None
        margins = np.array([learned.get(label, 0.0) for label in scene.labels])
        if not margins.any():
            return None
        ends = np.minimum(scene.distances(start[None]), scene.distances(goal[None]))
        room = 0.5 * np.maximum(ends - check_positive(clearance, "clearance", allow_zero=True), 0.0)
        return np.minimum(margins, room)


def obstacle_extent(obstacle: Any) -> float:
    """An obstacle's largest extent (units): a box's longest edge, else its covering balls'."""
    edges = getattr(obstacle, "size", None)
    if edges is not None and np.size(edges) == np.size(obstacle.position):
        return float(np.max(edges)) + 2.0 * float(obstacle.radius)
    centres, radii = obstacle.balls()
    centres = np.atleast_2d(np.asarray(centres, float))
    radii = np.asarray(radii, float).reshape(-1, 1)
    return float(np.max((centres + radii).max(axis=0) - (centres - radii).min(axis=0)))
