"""Arm descriptions: one immutable object holds everything lfdkit knows about a robot arm.

A robot is described once, by an :class:`Arm`, and every part of
:mod:`lfdkit.execute` reads it from there: the kinematics (:mod:`.ur5`) its
Denavit–Hartenberg table, the timing (:mod:`.timing`) and the URScript checks
(:mod:`.urscript`) its joint limits, the MuJoCo model (:mod:`.mujoco`, and the
sweeping task's scene, :mod:`lfdkit.tasks.sweeping.sim`) its joint count,
masses, link radii and servo gains. A new arm is one new :class:`Arm`; no
module holds a copy of these numbers.

Contents of a description
-------------------------
* *Kinematics*: the standard DH table ``d``, ``a``, ``alpha`` (one entry per
  joint; link transform ``T_{i-1}^i = Rot_z(θ_i) Trans_z(d_i) Trans_x(a_i)
  Rot_x(α_i)``, metres and radians). The number of joints is the length of
  the table. The flange is the last DH frame; a tool is not part of the arm
  but passed where it is used (``tool=`` of :func:`lfdkit.execute.ur5.forward`).
* *Limits*: joint position limits ``(lower, upper)`` (rad), speed limits
  (rad/s) and acceleration limits (rad/s²), one per joint.
* *Simulation*: link masses (kg), the radius of each link's capsule (m, the
  collision and inertia shape in MuJoCo) and the gains of the joint position
  servos (``kp`` in N·m/rad, ``kv`` in N·m·s/rad).

Validation
----------
:class:`Arm` checks itself when it is made (shapes, finite values, positive
limits and masses, ``lower < upper``); an error names the field, e.g.
``Arm.max_joint_speed: must be finite and > 0, got -1.0 for joint 2``. Arrays
are stored as read-only float64 copies, so a description cannot change after
the checks. Functions that take an ``arm`` therefore only check, where it
enters, that it is an :class:`Arm` (:func:`check_arm`) and, for the analytic
inverse kinematics, that it is :attr:`~Arm.ur_type`.

UR structure
------------
The closed-form inverse kinematics of :mod:`.ur5` holds for every arm with the
joint structure of the Universal Robots family: 6 joints, ``a1 = a4 = a5 =
a6 = 0``, ``d2 = d3 = 0``, ``alpha = (π/2, 0, 0, π/2, −π/2, 0)``, ``a2``,
``a3`` non-zero and a shoulder offset ``d4 > 0`` (to 1e-12). :attr:`Arm.ur_type`
says whether an arm has it; forward kinematics and the Jacobian need only the
DH table.

Arms
----
:data:`UR5` is the arm of the thesis (Tables 6.2 and 6.3). :data:`UR10` has
Universal Robots' published DH parameters and link masses, speed limits of
120°/s on base and shoulder and 180°/s on the other joints, position limits of
±360°; UR publishes no joint acceleration limit, so it gets the UR5's
15 rad/s². Its link radii and servo gains are choices of this module, sized to
its longer and heavier links (a straight sweep of the sweeping task,
:mod:`lfdkit.tasks.sweeping.sim`, at 20 % speed tracks within 0.5 mm, as the
UR5's does).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from types import MappingProxyType
from typing import Any

import numpy as np

__all__ = ["ARMS", "UR5", "UR10", "Arm", "check_arm", "per_joint"]

_UR_ALPHA = (math.pi / 2, 0.0, 0.0, math.pi / 2, -math.pi / 2, 0.0)
_UR_TOL = 1e-12  # slack on the zero and twist entries of a UR-type DH table
_SNAP = 1e-12  # |cos α|, |sin α| below this are exactly 0 (np.cos(π/2) is 6e-17)


def check_arm(arm: Any) -> Arm:
    """Return ``arm`` if it is an :class:`Arm`, else raise ``TypeError`` naming ``arm``.

    The check a function taking ``arm=`` makes where the arm enters: the numbers were
    checked when the description was made, so only its kind is left to check.
    """
    if not isinstance(arm, Arm):
        raise TypeError(f"arm: expected an Arm (e.g. lfdkit.execute.arm.UR5), got {arm!r}")
    return arm


def _array(value: Any, name: str) -> np.ndarray:
    try:
        return np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"Arm.{name}: expected numbers, got {value!r}") from exc


def per_joint(
    value: Any, name: str, n: int, *, positive: bool, scalar_ok: bool = False
) -> np.ndarray:
    """One finite value per joint (a scalar is repeated if ``scalar_ok``), read-only.

    The one check of a per-joint quantity: the arm's own fields and the
    limits a timing is given, so each refuses bad input in the same line,
    naming ``name`` and the joint (counted from 1).

    Parameters
    ----------
    value : float or array_like, shape (n,)
    name : str
        What the errors call it (``"Arm.max_joint_speed"``, ``"max_jerk"``).
    n : int
        Number of joints.
    positive : bool
        Values must also be > 0 (limits, masses).
    scalar_ok : bool
        A single number stands for every joint.

    Returns
    -------
    ndarray, shape (n,)
        A read-only float64 copy.

    Raises
    ------
    TypeError
        If ``value`` is not numbers.
    ValueError
        For another shape, or a value that is not finite (not > 0).
    """
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name}: expected numbers, got {value!r}") from exc
    if scalar_ok and arr.ndim == 0:
        arr = np.full(n, float(arr))
    if arr.shape != (n,):
        what = "a number or one per joint" if scalar_ok else "one value per joint"
        raise ValueError(f"{name}: expected {what} ({n} joints), got shape {arr.shape}")
    bad = ~np.isfinite(arr) | ((arr <= 0) if positive else False)
    if np.any(bad):
        j = int(np.argmax(bad))
        rule = "finite and > 0" if positive else "finite"
        raise ValueError(f"{name}: must be {rule}, got {float(arr[j])!r} for joint {j + 1}")
    arr.setflags(write=False)
    return arr


def _snapped(values: np.ndarray) -> np.ndarray:
    out = np.where(np.abs(values) < _SNAP, 0.0, values)
    out.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False, repr=False)
class Arm:
    """A serial arm of revolute joints: DH table, joint limits and simulation data.

    Every array argument takes anything NumPy reads as numbers and is kept as a
    read-only float64 array; ``n`` is the number of joints, the length of ``d``.
    Arms compare by identity. :func:`dataclasses.replace` makes a checked
    variant, e.g. ``replace(UR5, name="UR5 slow", max_joint_speed=1.0)``.

    Parameters
    ----------
    name : str
        Shown in messages, e.g. ``"UR5"``.
    d : array_like, shape (n,)
        DH link offsets along the previous ``z`` axis (m).
    a : array_like, shape (n,)
        DH link lengths along the new ``x`` axis (m).
    alpha : array_like, shape (n,)
        DH link twists about the new ``x`` axis (rad).
    joint_limits : array_like, shape (n, 2)
        ``(lower, upper)`` joint position per joint (rad), ``lower < upper``.
    max_joint_speed : float or array_like, shape (n,)
        Joint speed limits (rad/s), > 0; a number applies to every joint.
    max_joint_acceleration : float or array_like, shape (n,)
        Joint acceleration limits (rad/s²), > 0; a number applies to every joint.
    link_masses : array_like, shape (n,)
        Mass of the link each joint moves (kg), > 0.
    link_radii : array_like, shape (n,)
        Radius of each link's capsule in the MuJoCo model (m), > 0.
    kp : array_like, shape (n,)
        Stiffness of each joint's position servo in MuJoCo (N·m/rad), > 0.
    kv : array_like, shape (n,)
        Damping of each joint's position servo in MuJoCo (N·m·s/rad), > 0.

    Attributes
    ----------
    cos_alpha, sin_alpha : ndarray, shape (n,)
        ``cos α`` and ``sin α``, exactly 0 where below 1e-12 (``np.cos(π/2)`` is
        6e-17), so that link transforms of UR-type arms have exact zeros.
    ur_type : bool
        Whether the arm has the UR joint structure (see the module notes), so
        that the analytic inverse kinematics of :mod:`lfdkit.execute.ur5` applies.

    Raises
    ------
    TypeError
        If ``name`` is not a string or a field cannot be read as numbers.
    ValueError
        If ``name`` is empty, a field has the wrong shape, a value is NaN/inf, a limit, mass,
        radius or gain is not positive, or a lower joint limit is not below
        the upper one; the message names the field (``Arm.<field>: ...``).
    """

    name: str
    d: np.ndarray
    a: np.ndarray
    alpha: np.ndarray
    joint_limits: np.ndarray
    max_joint_speed: np.ndarray
    max_joint_acceleration: np.ndarray
    link_masses: np.ndarray
    link_radii: np.ndarray
    kp: np.ndarray
    kv: np.ndarray
    cos_alpha: np.ndarray = field(init=False)
    sin_alpha: np.ndarray = field(init=False)
    ur_type: bool = field(init=False)

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise TypeError(f"Arm.name: expected a str, got {self.name!r}")
        if not self.name.strip():
            raise ValueError("Arm.name: must not be empty")
        d = _array(self.d, "d")
        if d.ndim != 1 or len(d) == 0:
            raise ValueError(f"Arm.d: expected one value per joint, shape (n,), got {d.shape}")
        n = len(d)

        def put(name: str, value: Any) -> None:
            object.__setattr__(self, name, value)

        for name in ("d", "a", "alpha"):
            put(name, per_joint(getattr(self, name), f"Arm.{name}", n, positive=False))
        limits = _array(self.joint_limits, "joint_limits")
        if limits.shape != (n, 2):
            raise ValueError(
                f"Arm.joint_limits: expected (lower, upper) per joint, shape ({n}, 2), "
                f"got {limits.shape}"
            )
        if not np.isfinite(limits).all():
            raise ValueError("Arm.joint_limits: contains NaN or an infinite value")
        if (limits[:, 0] >= limits[:, 1]).any():
            j = int(np.argmax(limits[:, 0] >= limits[:, 1]))
            raise ValueError(
                f"Arm.joint_limits: joint {j + 1} has lower {float(limits[j, 0])!r} >= "
                f"upper {float(limits[j, 1])!r}"
            )
        limits.setflags(write=False)
        put("joint_limits", limits)
        for name in ("max_joint_speed", "max_joint_acceleration"):
            put(
                name,
                per_joint(getattr(self, name), f"Arm.{name}", n, positive=True, scalar_ok=True),
            )
        for name in ("link_masses", "link_radii", "kp", "kv"):
            put(name, per_joint(getattr(self, name), f"Arm.{name}", n, positive=True))
        put("cos_alpha", _snapped(np.cos(self.alpha)))
        put("sin_alpha", _snapped(np.sin(self.alpha)))
        put("ur_type", self._has_ur_structure())

    def _has_ur_structure(self) -> bool:
        if self.n_joints != 6:
            return False
        zeros = np.abs(np.r_[self.a[[0, 3, 4, 5]], self.d[[1, 2]]]).max()
        twists = np.abs(self.alpha - _UR_ALPHA).max()
        return bool(
            zeros <= _UR_TOL
            and twists <= _UR_TOL
            and min(abs(self.a[1]), abs(self.a[2])) > _UR_TOL
            and self.d[3] > _UR_TOL
        )

    @property
    def n_joints(self) -> int:
        """Number of joints, the length of the DH table."""
        return len(self.d)

    def __repr__(self) -> str:
        return f"Arm({self.name!r}, {self.n_joints} joints)"

    def __reduce__(self) -> tuple[type[Arm], tuple[Any, ...]]:
        # Pickle and copy through __init__, so that the copy is checked and read-only too.
        return (type(self), tuple(getattr(self, f.name) for f in fields(self) if f.init))


#: The UR5 of the thesis: DH table (Table 6.3), limits (Table 6.2); masses from
#: Universal Robots' published dynamics parameters.
UR5 = Arm(
    name="UR5",
    d=(0.08916, 0.0, 0.0, 0.10915, 0.09465, 0.0823),
    a=(0.0, -0.425, -0.39225, 0.0, 0.0, 0.0),
    alpha=_UR_ALPHA,
    joint_limits=[[-2 * math.pi, 2 * math.pi]] * 6,
    max_joint_speed=3.2,
    max_joint_acceleration=15.0,
    link_masses=(3.7, 8.393, 2.275, 1.219, 1.219, 0.1879),
    link_radii=(0.06, 0.054, 0.045, 0.04, 0.04, 0.035),
    kp=(3000.0, 3000.0, 2000.0, 800.0, 800.0, 500.0),
    kv=(120.0, 120.0, 80.0, 25.0, 25.0, 12.0),
)

#: The UR10: Universal Robots' published DH parameters, link masses and joint
#: speed limits (120°/s base and shoulder, 180°/s the others); the UR family's
#: twists and ±360° position limits and, as UR publishes none, the UR5's
#: acceleration limit come with the UR5; link radii and servo gains chosen here.
UR10 = replace(
    UR5,
    name="UR10",
    d=(0.1273, 0.0, 0.0, 0.163941, 0.1157, 0.0922),
    a=(0.0, -0.612, -0.5723, 0.0, 0.0, 0.0),
    max_joint_speed=np.radians([120.0, 120.0, 180.0, 180.0, 180.0, 180.0]),
    link_masses=(7.1, 12.7, 4.27, 2.0, 2.0, 0.365),
    link_radii=(0.075, 0.07, 0.055, 0.045, 0.045, 0.035),
    kp=(9000.0, 9000.0, 4000.0, 1200.0, 1200.0, 600.0),
    kv=(360.0, 360.0, 160.0, 40.0, 40.0, 15.0),
)

#: The arms described here, by lower-case name (the ``--arm`` of ``lfdkit execute``).
ARMS: Mapping[str, Arm] = MappingProxyType({"ur5": UR5, "ur10": UR10})
